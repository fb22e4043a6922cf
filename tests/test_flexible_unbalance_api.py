"""API 684 amplification factor and separation margin of a flexible rotor's bending critical speed,
against an independent computation (issue 28: "unbalance at any station of any rotor, several
unbalance planes along a shaft, API 684 amplification factors and separation margins").

The independent route shares only the assembled ``M, C, G, K`` with the package: the unbalance
forces are written from the physics of a rotating point mass (docs/model-file.md, "Unbalance
phase reference": phase 0 along ``a = z``, 90 degrees along ``b = e x a = -y`` for a spin about
x), the response is a plain ``numpy.linalg.solve`` at each speed, and the peak and the
half-power points are found on the continuous response by root finding (no grid)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.optimize

import rotordyn_modal as rdm

LENGTH = 1.2                                      # [m]
PLANES = ((0.3, 2.0e-4, 0.0), (0.6, 1.5e-4, 0.0), (0.9, 1.0e-4, 180.0))   # (z [m], amount [kg m], phase [deg])
PROBE_Z = 0.6


def _rotor(planes=PLANES):
    """A steel shaft (1.2 m, 40 mm, 8 elements) with a 20 kg disk at mid-span on two damped
    bearings (1e6 N/m, 1 kN s/m: the shaft's 48 EI / L^3 is 7.4e5 N/m, so its first mode bends
    the shaft more than it moves the bearings) at its ends, grounded; unbalances in ``planes``; a
    probe along y at mid-span."""
    return rdm.Model.from_dict({
        "name": "jeffcott-like", "spin_axis": [1.0, 0.0, 0.0],
        "materials": [{"name": "steel", "density": 7810.0, "young_modulus": 2.11e11, "poisson_ratio": 0.3}],
        "rotors": [{"name": "r", "speed_ratio": 1.0, "start": [0.0, 0.0, 0.0],
                    "shaft": [{"length": LENGTH, "outer_diameter": 0.04, "material": "steel", "elements": 8}],
                    "disks": [{"name": "d", "axial_position": 0.6, "mass": 20.0, "polar_inertia": 0.2,
                               "diametral_inertia": 0.1}]}],
        "bearings": [{"name": n, "rotor": "r", "axial_position": z, "stiffness": 1e6, "damping": 1e3}
                     for n, z in (("A", 0.0), ("B", LENGTH))],
        "unbalances": [{"rotor": "r", "axial_position": z, "amount": u, "phase_deg": p} for z, u, p in planes],
        "sensors": [{"name": "probe-y", "rotor": "r", "measure": "relative", "axial_position": PROBE_Z,
                     "direction": [0.0, 1.0, 0.0]}],
    })


class Independent:
    """The unbalance response at the probe from the assembled matrices and a rotating-mass force."""

    def __init__(self, model, planes=PLANES):
        self.M, self.C, self.G, self.K = rdm.matrices(model)
        names = list(model.dofs.names)
        mesh = model.rotors[0].flexible.mesh
        self.probe = names.index(f"r.n{mesh.node(PROBE_Z)}.uy")
        self.unit = np.zeros(len(names), dtype=complex)       # force per Omega^2
        for z, amount, phase in planes:
            k = mesh.node(z)
            # force along cos(Wt + p) a + sin(Wt + p) b = Re(e^{i(Wt + p)} (a - i b)), a = z, b = -y
            self.unit[names.index(f"r.n{k}.uz")] += amount * np.exp(1j * np.radians(phase))
            self.unit[names.index(f"r.n{k}.uy")] += amount * np.exp(1j * np.radians(phase)) * 1j

    def response(self, speed):
        """Complex amplitude at the probe [m] at ``speed`` [rad/s]."""
        w = float(speed)
        dynamic = self.K - w ** 2 * self.M + 1j * w * (self.C + w * self.G)
        return np.linalg.solve(dynamic, w ** 2 * self.unit)[self.probe]

    def amplitude(self, speed):
        return abs(self.response(speed))


def _peak_and_half_power(independent, low, high):
    """The peak speed of the probe's amplitude in (low, high) and its half-power points, by
    bounded maximisation and Brent's root finding on the continuous response."""
    peak = scipy.optimize.minimize_scalar(lambda w: -independent.amplitude(w), bounds=(low, high),
                                          method="bounded", options={"xatol": 1e-9 * high}).x
    level = independent.amplitude(peak) / np.sqrt(2)
    below = scipy.optimize.brentq(lambda w: independent.amplitude(w) - level, low, peak, xtol=1e-12)
    above = scipy.optimize.brentq(lambda w: independent.amplitude(w) - level, peak, high, xtol=1e-12)
    return peak, below, above


@pytest.fixture(scope="module")
def sweep():
    """The package's unbalance response through the first bending critical speed (fine grid)."""
    model = _rotor()
    modal = rdm.modal(model, 0.0)
    first = modal.eigenvalues[modal.oscillatory][0].imag                 # ~ the bending critical [rad/s]
    assert modal.kinds[modal.oscillatory][0] == "bending"                # most strain energy in the shaft
    speeds = np.linspace(0.8 * first, 1.2 * first, 801)
    return model, speeds, rdm.unbalance_response(model, speeds, outputs="probe-y")


def test_several_planes_superpose_and_equal_the_independent_solve(sweep):
    """The response to three planes along the shaft equals the sum of the responses to each plane
    alone (linearity) and the independent solve at every speed."""
    model, speeds, result = sweep
    few = speeds[::100]
    together = rdm.unbalance_response(model, few, outputs="probe-y").response[0, 0]
    alone = sum(rdm.unbalance_response(_rotor([plane]), few, outputs="probe-y").response[0, 0] for plane in PLANES)
    assert np.allclose(together, alone, rtol=1e-10, atol=1e-12 * np.abs(together).max())
    independent = Independent(model)
    expected = np.array([independent.response(w) for w in few])
    assert np.allclose(together, expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())
    assert np.allclose(result.response[0, 0, ::100], expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())


def test_amplification_factor_and_separation_margin_of_the_bending_critical(sweep):
    """API 684: AF = N_c / (N_2 - N_1) from the half-power points; the separation margin
    100 |N_op - N_c| / N_op and the required margin of a critical below the operating speed,
    min(16, 17 (1 - 1 / (AF - 1.5))) (API 617; docs/standards.md). The
    package's figures from its 801-speed sweep equal the independent ones from the continuous
    response within the grid's interpolation (1e-3); AF is close to 1 / (2 zeta) of the mode
    (first order in zeta, the unbalance force growing as Omega^2 across the band)."""
    model, speeds, result = sweep
    independent = Independent(model)
    peak, below, above = _peak_and_half_power(independent, speeds[0], speeds[-1])
    af = peak / (above - below)
    operating = 1.3 * peak
    table = result.peaks(operating_speed=operating)
    assert len(table) == 1                                   # one peak: the first bending critical
    row = table.iloc[0]
    assert row["speed_rpm"] * np.pi / 30 == pytest.approx(peak, rel=(speeds[1] - speeds[0]) / peak)
    assert row["amplification_factor"] == pytest.approx(af, rel=1e-3)
    assert row["separation_margin_pct"] == pytest.approx(100 * abs(operating - peak) / operating, abs=0.1)
    assert af > 2.5 and row["required_margin_pct"] == pytest.approx(
        min(16.0, 17 * (1 - 1 / (row["amplification_factor"] - 1.5))), rel=1e-12)
    # the mode at the critical speed, from the independent matrices: lambda of the quadratic pencil
    n = len(independent.K)
    zero, eye = np.zeros((n, n)), np.eye(n)
    state = np.block([[zero, eye], [-np.linalg.solve(independent.M, independent.K),
                                    -np.linalg.solve(independent.M, independent.C + peak * independent.G)]])
    lam = np.linalg.eigvals(state)
    lam = lam[np.argmin(np.abs(lam.imag - peak))]           # the forward mode whirling at the critical
    zeta = -lam.real / abs(lam)
    assert 0.005 < zeta < 0.05                              # lightly damped, where AF ~ 1 / (2 zeta) holds
    assert af == pytest.approx(1 / (2 * zeta), rel=3 * zeta)
