"""DOP853's stiffness test alike in the rigid and the linear (flexible) time models, by scipy's
public ``ode`` only (issue 27 §1.3, simfix27s "Left").

Hairer's DOP853 stops with code -4 ("the problem seems to become stiff") once its steps stay at
the edge of their stability region for 15 checks in a row, the first after 1,000 accepted steps
of a call: a heuristic, not a failure (``solve_ivp``'s DOP853 has no such test). The rigid model's
compiled path switched it off through scipy's private ``ode._integrator.iwork``; the linear
model's own DOP853 (pedestals, gear meshes, flexible rotors) kept it and failed with a
RuntimeError. Both now go on from where it stopped (``simulation._system.integrate_to``), and
both keep it with journal bearings, where it means a journal at its wall.

Truth from outside the integrator's route: the same equations integrated with output times close
enough that no call reaches 1,000 steps (the test cannot fire), and ``solve_ivp``'s DOP853.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import ode, solve_ivp

import rotordyn_modal as rdm

WN = 1e5                       # the fast relaxation [1/s]: DOP853's steps held near 6 / WN


def _stiff_rhs(t, y):
    """A slow forced oscillator (1 rad/s) beside a fast first-order lag (``WN``) that follows it:
    DOP853's steps sit at the edge of their stability region on the real axis."""
    return [y[1], np.cos(t) - y[0] - 0.02 * y[1], -WN * (y[2] - y[0])]


def _solver():
    solver = ode(_stiff_rhs).set_integrator("dop853", rtol=1e-9, atol=1e-12, nsteps=10 ** 9)
    return solver.set_initial_value([0.0, 0.0, 0.0], 0.0)


def test_integrate_to_goes_on_past_the_stiffness_test_and_keeps_it_when_asked():
    """scipy's DOP853 alone stops with code -4 well before t = 1 s; ``integrate_to`` reaches it,
    equal to ``solve_ivp``'s DOP853 (no stiffness test) to 1e-7 of the slow motion; with
    ``stiffness_test=True`` it stops as scipy does."""
    import warnings

    from rotordyn_modal.simulation._system import STIFF_STOP, integrate_to

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        kept = _solver()
        integrate_to(kept, 1.0, stiffness_test=True)
        assert kept.get_return_code() == STIFF_STOP and kept.t < 1.0
        solver = _solver()
        y = integrate_to(solver, 1.0)
    assert solver.successful() and solver.t == 1.0
    exact = solve_ivp(_stiff_rhs, (0.0, 1.0), [0.0] * 3, method="DOP853", rtol=1e-11, atol=1e-14).y[:, -1]
    assert np.abs(y[:2] - exact[:2]).max() < 1e-7 * np.abs(exact[:2]).max()


def _pedestal_machine() -> dict:
    """A rigid rotor on bearings A and B, A on a pedestal of 1e-6 kg on 1e8 N/m: a 1.6 MHz mode
    the linear time model must carry (pedestals are not in the nonlinear model)."""
    return {"name": "stiff pedestal", "reference_rotor": "r", "spin_axis": [1.0, 0.0, 0.0],
            "rotors": [{"name": "r", "mass": 10.0, "center_of_mass": [0.2, 0.0, 0.0], "polar_inertia": 0.05,
                        "diametral_inertia": 0.2}],
            "bearings": [{"name": "A", "rotor": "r", "position": [0.0, 0.0, 0.0], "stiffness": 1e6, "damping": 100.0,
                          "pedestal_mass": 1e-6, "pedestal_stiffness": 1e8},
                         {"name": "B", "rotor": "r", "position": [0.4, 0.0, 0.0], "stiffness": 1.2e6,
                          "damping": 100.0}],
            "unbalances": [{"rotor": "r", "amount": 1e-4, "axial_offset": 0.1}],
            "sensors": [{"name": "s", "rotor": "r", "position": [0.2, 0.0, 0.0], "direction": [0, 1, 0]}]}


def test_the_linear_time_model_runs_past_the_stiffness_test_as_the_rigid_one_does():
    """The pedestal machine at 300 rad/s for 0.8 ms, every mode kept, output at its end only
    (about 1,300 steps in one call): main failed with 'integration failed at t = 6.67e-05 s
    (DOP853 code -4)' (RuntimeError). Now its displacements at the end equal those of the same
    run with 9 output times (under 1,000 steps a call: the test never fires) to 1e-9 of the
    largest."""
    model = rdm.Model.from_dict(_pedestal_machine(), source="stiff.toml")
    runs = []
    for samples in (2, 9):
        with rdm.long_work_allowed():
            runs.append(rdm.simulate(model, 8e-4, 300.0, modes_below=np.inf, samples=samples, backend="numpy"))
    n = model.dofs.n
    one, many = runs[0].states[-1, :n], runs[1].states[-1, :n]
    assert np.isfinite(one).all()
    assert np.abs(one - many).max() < 1e-9 * np.abs(many).max()
