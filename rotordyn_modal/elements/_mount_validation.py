"""Validation rules of the suspensions (rubber mounts) table, beside their element (:mod:`.mounts`).

:func:`suspension` takes one raw ``[[suspensions]]`` table (plain Python values, as TOML gives
them) and returns the validated :class:`~rotordyn_modal.model.components.Suspension` with its
6x6 matrices in model axes, or raises :class:`~rotordyn_modal.errors.ModelError` naming source,
table, key, value and what was expected. The rules across tables stay in
:mod:`rotordyn_modal.model._validation`.
"""

from __future__ import annotations

import numpy as np

from ..model._table import Table as _Table, magnitude_problem, semidefinite_problem
from ..model.components import Suspension, input_keys, is_finite_number

__all__ = ["suspension"]

_AXES_TOLERANCE = 1e-6


def _orthonormal_axes(table: _Table, key: str) -> np.ndarray:
    axes = table.array(key, [(3, 3)], default=np.eye(3))
    if key not in table.data:
        return axes
    norms = np.linalg.norm(axes, axis=1)
    if np.any(norms == 0):
        raise table.error(key, table.data[key], "three non-zero rows (the suspension's axes)")
    axes = axes / norms[:, None]
    if np.abs(axes @ axes.T - np.eye(3)).max() > _AXES_TOLERANCE:
        raise table.error(key, table.data[key], "mutually orthogonal rows (the suspension's axes)")
    # nearest orthogonal matrix, so that rounding in the file does not leak into the model
    u, _, vt = np.linalg.svd(axes)
    return u @ vt


def _suspension_matrix(table: _Table, key: str, axes: np.ndarray, required: bool) -> np.ndarray:
    """The 6x6 matrix acting on [u_P, theta] in model axes from a 3-, 6-list, 3x3 or 6x6 value."""
    value = table.array(key, [(3,), (6,), (3, 3), (6, 6)], required=required)
    if value is None:
        return np.zeros((6, 6))
    if value.ndim == 1:
        if np.any(value < 0):
            raise table.error(key, table.data[key], "non-negative diagonal values")
        value = np.diag(value)
    elif problem := semidefinite_problem(value):
        raise table.error(key, table.data[key], problem)
    local = np.zeros((6, 6))
    local[: value.shape[0], : value.shape[1]] = value
    rotation = np.zeros((6, 6))
    rotation[:3, :3] = axes  # local = axes @ model
    # rotations and moments are axial vectors: in a left-handed set of axes their
    # components change sign (det = -1), so a 6x6 coupling keeps its physical meaning
    rotation[3:, 3:] = np.linalg.det(axes) * axes
    return rotation.T @ local @ rotation


def suspension(table: _Table, earlier=None) -> Suspension:
    """The validated suspension; ``earlier`` (raw table, Suspension) of the description this one
    was made from lends the parts whose keys hold the same objects (see
    :func:`rotordyn_modal.model._validation.validate`)."""
    if earlier is not None and earlier[0] is table.data:
        return earlier[1]
    table.check_keys(input_keys("suspensions"))
    lent = _lent_axes(table, earlier)
    axes = _orthonormal_axes(table, "axes") if lent is None else lent.axes
    same_damping = lent is not None and _same_keys(table, earlier[0], ("damping",))
    same_branches = lent is not None and _same_keys(table, earlier[0], ("maxwell_stiffness", "maxwell_time"))
    return Suspension(   # the keyword arguments run in the order of the checks' messages
        name=table.data["name"],
        position=table.vector3("position", required=True),
        stiffness=table.data["stiffness"] if "stiffness" in table.data else table.require("stiffness"),
        damping=table.data.get("damping"),
        loss_factor=table.number("loss_factor", default=0.0, nonnegative=True),
        axes=axes,
        stiffness_matrix=_suspension_matrix(table, "stiffness", axes, required=True),
        damping_matrix=lent.damping_matrix if same_damping else _suspension_matrix(table, "damping", axes,
                                                                                   required=False),
        maxwell_stiffness=table.data.get("maxwell_stiffness"),
        maxwell_time=table.data.get("maxwell_time"),
        maxwell_stiffness_matrix=lent.maxwell_stiffness_matrix if same_branches else _maxwell_branches(table, axes),
    )


def _same_keys(table: _Table, raw, keys) -> bool:
    """Each key is absent from both tables or holds the same object in both."""
    return all((key in table.data) == (key in raw) and table.data.get(key) is raw.get(key) for key in keys)


def _lent_axes(table: _Table, earlier):
    """The earlier suspension when its ``axes`` are this table's (the same object, or absent
    from both), else None."""
    if earlier is None or not _same_keys(table, earlier[0], ("axes",)):
        return None
    return earlier[1]


def _maxwell_branches(table: _Table, axes: np.ndarray):
    """(n_branches, 6, 6) branch stiffnesses in model axes, or None without branches."""
    if "maxwell_stiffness" not in table.data and "maxwell_time" not in table.data:
        return None
    stiffness, times = table.require("maxwell_stiffness"), table.require("maxwell_time")
    if not isinstance(stiffness, (list, tuple)) or not isinstance(times, (list, tuple)) \
            or len(stiffness) != len(times) or not stiffness:
        raise table.error("maxwell_time", times, "a list of relaxation times [s], one per branch of "
                          f"maxwell_stiffness ({len(stiffness) if isinstance(stiffness, list) else 0} branches)")
    for i, tau in enumerate(times):
        if not is_finite_number(tau) or not tau > 0:
            raise table.error(f"maxwell_time[{i}]", tau, "a finite relaxation time > 0 [s]")
        if problem := magnitude_problem(tau, positive=True):
            raise table.error(f"maxwell_time[{i}]", tau, "a relaxation time [s] that is " + problem)
    branches = []
    for i, branch in enumerate(stiffness):
        sub = _Table(table.source, table.label, {f"maxwell_stiffness[{i}]": branch})
        branches.append(_suspension_matrix(sub, f"maxwell_stiffness[{i}]", axes, required=True))
    return np.array(branches)
