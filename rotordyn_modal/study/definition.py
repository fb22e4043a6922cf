"""The study file (``docs/study-file.md``): read, validate, and hold it as plain data.

A study is a base model, parameters addressed by dotted keys (each a grid or a
distribution), a sampling design, the analyses run on every variant and a seed.
Every rule refuses a bad file with :class:`StudyError`, whose message names the
file, the table and key, the value found and what was expected, like a bad model.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field

import numpy as np

from .._limits import count_problem
from ..model._table import non_number, unknown_key, visible
from ..errors import InputError
from ._rules import StudyError, grid_values, is_number
from .analyses import parse_analyses

__all__ = ["StudyError", "Parameter", "StudyDefinition", "read_study", "parse_study",
           "DESIGNS", "DISTRIBUTIONS"]

#: sampling designs of the distributions' parameters
DESIGNS = ("monte-carlo", "latin-hypercube", "sobol", "saltelli")
#: distribution name -> keys it needs (one of the alternatives)
DISTRIBUTIONS = {
    "normal": (("mean", "std"),),
    "lognormal": (("median", "log_std"), ("mean", "std")),
    "uniform": (("low", "high"),),
}
#: top-level keys of a model file (docs/model-file.md) that no study file has
_MODEL_KEYS = ("spin_axis", "stator", "rotors", "suspensions", "bearings", "transmissions", "materials")
_TOP_KEYS = ("seed", "samples", "design", "chunk_size", "parameters", "correlation", "analyses",
             "operating_band_rpm", "name")
#: largest seed or chunk size: the results file (netCDF 3) stores them as 32-bit integers
_LARGEST_INT = 2**31 - 1
_PARAMETER_KEYS = ("name", "key", "keys", "values", "scale", "distribution", "apply", "mean", "std",
                   "median", "log_std", "low", "high", "truncate")


@dataclass(frozen=True)
class Parameter:
    """One varied quantity of a study.

    Attributes
    ----------
    name : str
        Label in results (default: the first key).
    keys : tuple of str
        Dotted keys that all receive the same sampled number.
    apply : {'value', 'scale'}
        Set the keys to the number, or multiply them (whole arrays too) by it.
    grid : ndarray or None, shape (G,)
        Grid points (a grid parameter); None for a distribution.
    distribution : str or None
        'normal', 'lognormal' or 'uniform'.
    arguments : dict
        scipy.stats arguments of the distribution (``loc``, ``scale``, ``s``).
    truncate : tuple of float or None
        (low, high) bounds of a truncated distribution.
    """

    name: str
    keys: tuple
    apply: str
    grid: np.ndarray | None = None
    distribution: str | None = None
    arguments: dict = field(default_factory=dict)
    truncate: tuple | None = None

    @property
    def is_grid(self) -> bool:
        return self.grid is not None

    def frozen(self):
        """The scipy.stats frozen distribution."""
        from scipy import stats

        return {"normal": stats.norm, "lognormal": stats.lognorm,
                "uniform": stats.uniform}[self.distribution](**self.arguments)


@dataclass(frozen=True)
class StudyDefinition:
    """A validated study.

    Attributes
    ----------
    parameters : tuple of Parameter
    design : str
        One of :data:`DESIGNS` (used only when some parameter is a distribution).
    samples : int
        Samples of the distributions (per grid point); for 'saltelli' the base
        sample N, giving N (d + 2) variants.
    seed : int or None
    correlation : ndarray, shape (n_random, n_random)
        Correlation of the distributions' parameters (Gaussian copula), in the
        order of the distribution parameters.
    analyses : dict
        Analysis name -> validated options (see :mod:`rotordyn_modal.study.analyses`).
    chunk_size : int or None
        Variants per chunk sent to a worker (None: chosen by the executor).
    operating_band_rpm : tuple or None
        (low, high) operating speed band [rpm] for reports.
    source : str
    raw : dict
        The study description as given.
    """

    parameters: tuple
    design: str
    samples: int
    seed: int | None
    correlation: np.ndarray
    analyses: dict
    chunk_size: int | None
    operating_band_rpm: tuple | None
    source: str
    raw: dict

    @property
    def grid_parameters(self) -> tuple:
        return tuple(p for p in self.parameters if p.is_grid)

    @property
    def random_parameters(self) -> tuple:
        return tuple(p for p in self.parameters if not p.is_grid)


# ----------------------------------------------------------------------------------------
def read_study(path, model=None) -> StudyDefinition:
    """Read and validate a study file.

    Parameters
    ----------
    path : str or path-like
        TOML study file (``docs/study-file.md``).
    model : Model, optional
        Base model; its dotted keys are checked when given.

    Returns
    -------
    StudyDefinition
    """
    from ..io.model_file import read_toml

    data = read_toml(path, "study file", StudyError)
    return parse_study(data, str(path), model)


def parse_study(data: dict, source: str = "<study>", model=None) -> StudyDefinition:
    """Validate a study description (the structure of the TOML file).

    Parameters
    ----------
    data : dict
    source : str
        Named in messages.
    model : Model, optional
        Base model whose dotted keys are checked.

    Returns
    -------
    StudyDefinition
    """
    if not isinstance(data, dict):
        raise StudyError(source, "<study>", data, "a table")
    model_keys = [key for key in _MODEL_KEYS if key in data]
    if model_keys and "parameters" not in data:     # 'study m.toml --spec m.toml': was "spin_axis ... unknown key"
        raise StudyError(source, "<file>", f"a model file (its {', '.join(model_keys)})",
                         "a study file ([[parameters]], [analyses.*]; docs/study-file.md): the model is the "
                         "command's first argument, the study file --spec")
    _unknown(data, _TOP_KEYS, source, "<top level>")
    seed, design, chunk = _run_options(data, source)
    items = data.get("parameters")
    if not isinstance(items, list) or not items:
        raise StudyError(source, "[[parameters]]", items, "at least one [[parameters]] table")
    description = model.to_dict() if model is not None else None      # the base model's, read only
    parsed = [_parameter(item, i, source, model, description) for i, item in enumerate(items)]
    parameters = tuple(parameter for parameter, _ in parsed)
    _unique_names(parameters, source)
    _one_parameter_per_value(parameters, [places for _, places in parsed], source)
    random = [p for p in parameters if not p.is_grid]
    samples = _samples(data, random, source)
    _check_variant_count(parameters, samples, design, source)
    correlation = _correlation(data.get("correlation"), random, source)
    _check_design(design, correlation, random, parameters, source)
    analyses = parse_analyses(data.get("analyses"), source, model)
    band = _band(data.get("operating_band_rpm"), source)
    return StudyDefinition(parameters=parameters, design=design, samples=int(samples or 0),
                           seed=seed, correlation=correlation, analyses=analyses,
                           chunk_size=chunk, operating_band_rpm=band, source=source, raw=data)


def _run_options(data, source):
    """``seed`` (None or a whole number >= 0), ``design`` and ``chunk_size`` (None or >= 1)."""
    seed = data.get("seed")
    if seed is not None and (not _is_int(seed) or not 0 <= seed <= _LARGEST_INT):
        raise StudyError(source, "seed", seed, f"a whole number from 0 to {_LARGEST_INT}")
    design = data.get("design", "monte-carlo")
    if design not in DESIGNS:
        raise StudyError(source, "design", design, "one of " + ", ".join(DESIGNS))
    chunk = data.get("chunk_size")
    if chunk is not None and (not _is_int(chunk) or not 1 <= chunk <= _LARGEST_INT):
        raise StudyError(source, "chunk_size", chunk, f"a whole number from 1 to {_LARGEST_INT}")
    return seed, design, chunk


def _samples(data, random, source):
    """``samples``: >= 2 when some parameter is a distribution, none when all are grids."""
    samples = data.get("samples", 0 if not random else None)
    if random and (not _is_int(samples) or samples < 2):
        raise StudyError(source, "samples", samples, "a whole number >= 2 (samples of the distributions)")
    if not random and samples not in (0, None):
        raise StudyError(source, "samples", samples, "no samples: every parameter is a grid "
                         "(give a distribution to sample)")
    return samples


def _check_design(design, correlation, random, parameters, source):
    """A Saltelli design (Sobol indices) takes independent distributions only."""
    if design == "saltelli" and not np.allclose(correlation, np.eye(len(random))):
        raise StudyError(source, "design", design, "independent parameters (Sobol indices assume "
                         "no correlation); remove [correlation] or use another design")
    if design == "saltelli" and len(random) != len(parameters):
        raise StudyError(source, "design", design, "distributions only (a Saltelli design takes no grid "
                         "parameters)")


def _check_variant_count(parameters, samples, design, source):
    """Refuse, before sampling, a study of more variants than the limit (:mod:`rotordyn_modal._limits`)."""
    count = math.prod(len(p.grid) for p in parameters if p.is_grid)
    random = sum(1 for p in parameters if not p.is_grid)
    if random:
        count *= samples * (random + 2 if design == "saltelli" else 1)
    if problem := count_problem(count, "variants"):
        raise StudyError(source, *count_key(parameters, samples), "a study of " + problem)


def count_key(parameters, samples) -> tuple:
    """The key of a study file that sets its number of variants, and its value, for a message:
    ``('samples', N)`` where some parameter is a distribution, else ``('[[parameters]] grids',
    '3 x 4 points')``."""
    if any(not p.is_grid for p in parameters):
        return "samples", samples
    grids = " x ".join(str(len(p.grid)) for p in parameters if p.is_grid)
    return "[[parameters]] grids", f"{grids} points"


def _is_int(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _unknown(table, allowed, source, where):
    for key in table:
        if key not in allowed:
            raise StudyError(source, f"{where} {visible(key)}", table[key], "one of the keys " + ", ".join(allowed)
                             + unknown_key(key, allowed))


def _unique_names(parameters, source):
    seen = set()
    for i, p in enumerate(parameters):
        if p.name in seen:
            raise StudyError(source, f"[[parameters]] {i + 1} name", p.name, "a name used once")
        seen.add(p.name)


def _one_parameter_per_value(parameters, places, source):
    """Refuse two parameters that address one value of the base model (the same key, a key and
    an element of it, a name and an index of one table) where either sets it (``apply =
    "value"``): the later one overwrote the other in every variant, whose column then showed
    numbers no variant had. Two factors (``"scale"``) multiply, as given; one factor's ``keys``
    addressing one value twice is refused (it was applied twice: the factor squared).
    ``places``: per parameter, the place each of its keys addresses in one description of the
    base model, as :func:`_check_keys` parsed them (empty without a base model)."""
    seen = []
    for i, (parameter, located) in enumerate(zip(parameters, places)):
        for key, (container, name, indices) in zip(parameter.keys, located):
            place = (id(container), name, _positive_indices(container[name], indices) if indices else ())
            for j, other, other_key, (c, n, idx) in seen:
                shorter = min(len(idx), len(place[2]))
                if (c, n) != place[:2] or idx[:shorter] != place[2][:shorter]:
                    continue
                if j == i and parameter.apply == "scale":
                    raise StudyError(source, f"[[parameters]] {i + 1} keys", list(parameter.keys),
                                     f"keys of different values: {other_key} and {key} address one value, which "
                                     "every variant multiplied twice (the factor squared)")
                if j != i and "value" in (parameter.apply, other.apply):
                    raise StudyError(source, f"[[parameters]] {i + 1} key", key,
                                     f"a value no other parameter changes: [[parameters]] {j + 1} "
                                     f"({other.name!r}, apply = {other.apply!r}) changes {other_key}, the same value, "
                                     f"and this one (apply = {parameter.apply!r}) changed it after in every variant: "
                                     "the first one's column would show numbers no variant had (give one parameter "
                                     "per value; two factors, apply = 'scale', multiply)")
            seen.append((i, parameter, key, place))


def _positive_indices(value, indices) -> tuple:
    """``indices`` into the nested list ``value`` with negative ones counted from the end."""
    out = []
    for index in indices:
        out.append(index + len(value) if index < 0 else index)
        value = value[out[-1]]
    return tuple(out)


def _parameter(item, i, source, model, data) -> tuple:
    """The parameter of ``[[parameters]]`` table ``item`` (number ``i``, from 0) and the places its
    keys address in ``data``, the base model's description (:func:`_check_keys`)."""
    where = f"[[parameters]] {i + 1}"
    if not isinstance(item, dict):
        raise StudyError(source, where, item, "a table")
    _unknown(item, _PARAMETER_KEYS, source, where)
    keys = _keys(item, where, source)
    name = item.get("name", keys[0])
    if not isinstance(name, str) or not name:
        raise StudyError(source, f"{where} name", name, "a non-empty string")
    grid_keys = [k for k in ("values", "scale") if k in item]
    if len(grid_keys) > 1 or (grid_keys and "distribution" in item):
        raise StudyError(source, where, sorted(item), "exactly one of values, scale or distribution")
    if grid_keys:
        grid = grid_values(item[grid_keys[0]], f"{where} {grid_keys[0]}", source)
        apply = "value" if grid_keys[0] == "values" else "scale"
        parameter = Parameter(name=name, keys=keys, apply=apply, grid=grid)
        places = _check_keys(parameter, grid[0], model, data, where, source)
        _check_range(parameter, model, _grid_ends(grid, item, grid_keys[0]), where, source)
        return parameter, places
    if "distribution" not in item:
        raise StudyError(source, where, sorted(item), "one of values, scale (a grid) or distribution")
    parameter = _distribution(item, name, keys, where, source)
    places = _check_keys(parameter, parameter.frozen().median(), model, data, where, source)
    _check_range(parameter, model, _distribution_ends(parameter, item), where, source)
    return parameter, places


def _keys(item, where, source) -> tuple:
    if ("key" in item) == ("keys" in item):
        raise StudyError(source, where, sorted(item), "exactly one of key (a dotted key) or keys (a list)")
    keys = [item["key"]] if "key" in item else item["keys"]
    if not isinstance(keys, list) or not keys or not all(isinstance(k, str) and k for k in keys):
        raise StudyError(source, f"{where} key", keys, "dotted keys such as 'suspensions.mount-FL.stiffness'")
    return tuple(keys)


def _positive(item, key, where, source) -> float:
    value = item.get(key)
    if not is_number(value) or value <= 0:
        raise StudyError(source, f"{where} {key}", value, "a finite number > 0")
    return float(value)


def _number(item, key, where, source) -> float:
    value = item.get(key)
    if not is_number(value):
        raise StudyError(source, f"{where} {key}", value, "a finite number")
    return float(value)


def _distribution(item, name, keys, where, source) -> Parameter:
    kind = item["distribution"]
    if not isinstance(kind, str) or kind not in DISTRIBUTIONS:
        raise StudyError(source, f"{where} distribution", kind, "one of " + ", ".join(DISTRIBUTIONS))
    apply = item.get("apply", "value")
    if apply not in ("value", "scale"):
        raise StudyError(source, f"{where} apply", apply, "'value' (set the key) or 'scale' (multiply it)")
    arguments = _distribution_arguments(kind, item, where, source)
    truncate = _truncation(item.get("truncate"), where, source)
    parameter = Parameter(name=name, keys=keys, apply=apply, distribution=kind, arguments=arguments,
                          truncate=truncate)
    if truncate is not None:
        dist = parameter.frozen()
        if not dist.cdf(truncate[1]) - dist.cdf(truncate[0]) > 1e-12:
            raise StudyError(source, f"{where} truncate", list(truncate),
                             "bounds that keep some probability of the distribution")
    return parameter


def _distribution_arguments(kind, item, where, source) -> dict:
    alternatives = DISTRIBUTIONS[kind]
    given = [alt for alt in alternatives if any(k in item for k in alt)]
    if len(given) != 1 or not all(k in item for k in given[0]):
        expected = " or ".join(" and ".join(alt) for alt in alternatives)
        present = {k: item[k] for k in ("mean", "std", "median", "log_std", "low", "high") if k in item}
        raise StudyError(source, f"{where} ({kind})", present, expected)
    if kind == "normal":
        return {"loc": _number(item, "mean", where, source), "scale": _positive(item, "std", where, source)}
    if kind == "uniform":
        low, high = _number(item, "low", where, source), _number(item, "high", where, source)
        if not high > low:
            raise StudyError(source, f"{where} high", high, f"a number > low = {low}")
        return {"loc": low, "scale": high - low}
    if "median" in item:
        median, log_std = _positive(item, "median", where, source), _positive(item, "log_std", where, source)
    else:
        mean, std = _positive(item, "mean", where, source), _positive(item, "std", where, source)
        log_std = math.sqrt(math.log1p((std / mean) ** 2))
        median = mean / math.sqrt(1 + (std / mean) ** 2)
    return {"s": log_std, "scale": median}


def _truncation(value, where, source):
    if value is None:
        return None
    if not isinstance(value, list) or len(value) != 2 or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in value) \
            or not value[1] > value[0]:
        raise StudyError(source, f"{where} truncate", value, "[low, high] with low < high "
                         "(use -inf or inf for one side)")
    return float(value[0]), float(value[1])


def _check_keys(parameter, number, model, data, where, source) -> list:
    """Apply a representative number at the base model's keys (refuses unknown keys), each key
    parsed once: the places ``(container, field, indices)`` they address in ``data`` (the base
    model's description, left unchanged: the number is applied to a copy of each value), for
    :func:`_one_parameter_per_value`; empty without a base model."""
    if model is None:
        return []
    from ..model.parameters import change_at, parse_key

    places = []
    for key in parameter.keys:
        try:
            located = parse_key(key, data, model.source, missing_ok=True)   # scale: refused by change_at
        except InputError as error:
            raise StudyError(source, f"{where} key", key, f"a dotted key of the model ({error})") from None
        if parameter.apply == "value" and _holds_array(located, key, model.source):
            raise StudyError(source, f"{where} key", key, "a key holding one number to set (it holds an "
                             "array: multiply it with scale / apply = 'scale', or pick an element with [i])")
        container, name, indices = located
        try:
            here = {name: copy.deepcopy(container[name])} if name in container else {}
            change_at((here, name, indices), parameter.apply, float(number), key, model.source)
        except InputError as error:
            raise StudyError(source, f"{where} key", key, f"a dotted key of the model ({error})") from None
        if name not in container:
            _refuse_unknown_key(model, key, name, float(number), f"{where} key", source)
        places.append(located)
    return places


def _refuse_unknown_key(model, key: str, name: str, number: float, where: str, source) -> None:
    """A key the model file leaves out may be set only where its table takes it: the model's
    refusal of the key itself at ``number`` (a misspelt ``inner_diamter``, with its suggestion;
    a material's ``shear_modulus`` beside its ``poisson_ratio``) is said now, not by every
    variant failing."""
    error = _variant_refusal(model, [(key, "value", number)])
    if error is not None and f"] {name} = " in str(error):
        raise StudyError(source, where, key, f"a dotted key of the model (the file leaves {name!r} out and "
                         f"the model does not take it at {number:.6g}: {error})")


def _grid_ends(grid, item, grid_key) -> list:
    """The smallest and largest point of a grid, each as ``(number, study key, its value)``."""
    return [(float(number), grid_key, item[grid_key]) for number in sorted({float(grid.min()), float(grid.max())})]


def _distribution_ends(parameter, item) -> list:
    """The finite ends of the numbers a distribution can draw, each as ``(number, study key, its
    value)``: a number just inside the end (the end itself is drawn with probability 0, so
    ``low = 0`` or ``truncate = [0, inf]`` keep a mass positive). An unbounded side (a normal
    distribution without ``truncate``) has no end to check."""
    low, high = (float(v) for v in parameter.frozen().support())
    if parameter.distribution == "uniform":
        keys = {side: (side, item.get(side)) for side in ("low", "high")}
    else:   # a lognormal's 0
        keys = dict.fromkeys(("low", "high"), ("distribution", item.get("distribution")))
    if parameter.truncate is not None and parameter.truncate[0] > low:
        low, keys["low"] = parameter.truncate[0], ("truncate", item.get("truncate"))
    if parameter.truncate is not None and parameter.truncate[1] < high:
        high, keys["high"] = parameter.truncate[1], ("truncate", item.get("truncate"))
    ends = []
    for end, other, side in ((low, high, "low"), (high, low, "high")):
        if math.isfinite(end):
            ends.append((float(np.nextafter(end, other)), *keys[side]))
    return ends


def _check_range(parameter, model, ends, where, source):
    """Refuse, as the study file is read, a range (grid points, a distribution's bounds) that turns
    a number of the base model at the parameter's keys to zero or below (a value set to it, a
    positive number multiplied by a factor <= 0) where the model refuses that (a mass, a
    stiffness): every variant drawn there would fail. Keys whose numbers may be negative (a
    position, a cross-coupled stiffness) pass, as the model takes them; so does a number the
    model refuses whatever its sign (left to the variants, where other parameters may change
    what it depends on).

    Parameters
    ----------
    parameter : Parameter
    model : Model or None
        The base model (None: nothing is checked).
    ends : list of (float, str, object)
        Numbers the parameter takes at the ends of its range, with the study file's key and its
        value that set them (:func:`_grid_ends`, :func:`_distribution_ends`).
    where : str
        ``[[parameters]] N``.
    source : str
    """
    if model is None:
        return
    for number, study_key, shown in ends:
        turned = [key for key in parameter.keys   # a set key may be one the file leaves out: not read
                  if _turns_non_positive(None if parameter.apply == "value" else model.get(key), parameter.apply,
                                         number)]
        error = _refusal(model, parameter, number) if turned else None
        if error is None or (number != 0 and _refusal(model, parameter, abs(number)) is not None):
            continue
        what = "factor" if parameter.apply == "scale" else "value"
        raise StudyError(source, f"{where} {study_key}", shown,
                         f"a range of parameter {parameter.name!r} over which the model takes {', '.join(turned)} "
                         f"(no variant was run): at the {what} {number:.6g}, {error}")


def _refusal(model, parameter, number):
    """The model's error for the base model with the parameter at ``number``, or None."""
    return _variant_refusal(model, [(key, parameter.apply, number) for key in parameter.keys])


def _variant_refusal(model, changes):
    """The model's error for its variant with ``changes`` (:meth:`Model.variant`), or None."""
    import warnings

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model.variant(changes)
    except InputError as error:
        return error
    return None


def _turns_non_positive(current, apply: str, number: float) -> bool:
    """Whether setting (``apply="value"``) or multiplying (``"scale"``) ``current`` (a number or a
    nested list of numbers) by ``number`` gives zero or below where it was above zero (a set value
    <= 0 at all)."""
    if apply == "value":
        return number <= 0
    values = np.asarray(current, dtype=float).ravel()
    return number <= 0 and bool(np.any(values > 0))


def _holds_array(located, key, model_source) -> bool:
    """Whether the place :func:`~rotordyn_modal.model.parameters.parse_key` found holds an array."""
    from ..model.parameters import value_at

    try:
        return isinstance(value_at(located, key, model_source), list)
    except InputError:
        return False  # an index out of range: refused with the model's message below


def _correlation(table, random, source) -> np.ndarray:
    d = len(random)
    if table is None:
        return np.eye(d)
    where = "[correlation]"
    if not isinstance(table, dict):
        raise StudyError(source, where, table, "a table with parameters and matrix")
    _unknown(table, ("parameters", "matrix"), source, where)
    names = table.get("parameters")
    known = [p.name for p in random]
    if not isinstance(names, list) or not names or not all(isinstance(n, str) and n in known for n in names) \
            or len(set(names)) != len(names):
        raise StudyError(source, f"{where} parameters", names,
                         "distinct names of distribution parameters: " + ", ".join(known))
    try:   # strings and booleans are not numbers ("0.5", true), as everywhere in the file
        matrix = np.empty(0) if non_number(table.get("matrix")) else np.array(table.get("matrix"), dtype=float)
    except (TypeError, ValueError):
        matrix = np.empty(0)
    k = len(names)
    if matrix.shape != (k, k) or not np.all(np.isfinite(matrix)) or not np.allclose(matrix, matrix.T) \
            or not np.allclose(np.diag(matrix), 1.0) or np.any(np.abs(matrix) > 1):
        raise StudyError(source, f"{where} matrix", table.get("matrix"),
                         f"a symmetric {k}x{k} matrix with ones on the diagonal and entries in [-1, 1]")
    if np.linalg.eigvalsh(matrix).min() <= 1e-12:
        raise StudyError(source, f"{where} matrix", table.get("matrix"), "a positive definite matrix")
    full = np.eye(d)
    index = [known.index(n) for n in names]
    full[np.ix_(index, index)] = matrix
    return full


def _band(value, source):
    if value is None:
        return None
    if not isinstance(value, list) or len(value) != 2 or not all(is_number(v) for v in value) \
            or not value[1] > value[0]:
        raise StudyError(source, "operating_band_rpm", value, "[low, high] in rpm with low < high")
    return float(value[0]), float(value[1])
