"""VALIDATION.md section "Beams": R1, B1, B2, B4, B5, B9 for the absolute (section 8.4)
formulation. The cases themselves live in rfesim.bench.cases (shared with the report)."""
from __future__ import annotations

import numpy as np
import pytest

from rfesim.bench.cases import (B4_RATIOS, CHAIN_C, MATTIASSON, PENDULUM, b4_frequencies, chain_frequencies,
                                end_moment, mattiasson, pendulum_period_ratio, r1_tip_force, r1_tip_moment)


# --------------------------------------------------------------------------- R1
@pytest.mark.parametrize("shear", ["fem", "kruszewski"])
@pytest.mark.parametrize("n", [3, 10, 20])
def test_R1_linear_cantilever_tip_force(n, shear):
    """Tip force P: rotation PL^2/(2EI) and deflection (PL^3/3EI)(1 - 1/(4n^2)) exactly, plus
    the shear part: PL/GA (eq. 8.88) or PL^3/(12 EI n^2) (eq. 8.89, which makes it exact)."""
    (w, rot), (w_ref, rot_ref) = r1_tip_force(n, shear)
    assert w == pytest.approx(w_ref, rel=1e-8)
    assert rot == pytest.approx(rot_ref, rel=1e-8)


@pytest.mark.parametrize("n", [4, 12])
def test_R1_linear_cantilever_tip_moment(n):
    """Tip moment M: rotation ML/EI and deflection ML^2/(2EI) exactly (for any n)."""
    (w, rot), (w_ref, rot_ref) = r1_tip_moment(n)
    assert w == pytest.approx(w_ref, rel=1e-8)
    assert rot == pytest.approx(rot_ref, rel=1e-8)


# --------------------------------------------------------------------------- B1
@pytest.mark.parametrize("alpha", [1.0, 10.0])
def test_B1_mattiasson_large_deflection(alpha):
    """Inextensible cantilever, dead tip load, alpha = PL^2/EI: 0.3 % at 20 elements."""
    w, u, rot = mattiasson(20, alpha)
    ref = MATTIASSON[alpha]
    assert w == pytest.approx(ref[0], rel=3e-3)
    assert u == pytest.approx(ref[1], rel=3e-3)
    assert rot == pytest.approx(ref[2], rel=3e-3)


@pytest.mark.parametrize("alpha", [1.0, 10.0])
def test_B1_convergence_order_is_two(alpha):
    """The error of the tip deflection falls as 1/n^2 (observed order within 0.15 of 2)."""
    err = [abs(mattiasson(n, alpha)[0] / MATTIASSON[alpha][0] - 1.0) for n in (10, 20, 40)]
    orders = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.15), (err, orders)


# --------------------------------------------------------------------------- B2
@pytest.mark.parametrize("fraction", [0.25, 0.5, 1.0])
def test_B2_pure_end_moment(fraction):
    """Uniform curvature M/EI and tip rotation ML/EI exactly, even when the line rolls up."""
    L, EI = 1.0, 1.0
    line, M, _ = end_moment(20, fraction, L, EI)
    assert line.curvature[0] == pytest.approx(np.full(20, M / EI), rel=1e-8)
    total = (line.curvature[0] * (L / 20)).sum()               # sum of the SDE rotations
    assert total == pytest.approx(M * L / EI, rel=1e-8)
    d = line.end_b_direction[0]                                # tip rotation about -y
    expected = np.array([np.cos(M * L / EI), 0.0, -np.sin(M * L / EI)])
    assert d == pytest.approx(expected, abs=1e-8)


def test_B2_closes_into_a_circle():
    """At M = 2 pi EI/L the tip returns to the clamp: within 1e-3 L at n = 20."""
    _, _, err = end_moment(20, 1.0)
    assert err < 1e-3


def test_B2_tip_position_converges_as_n_squared():
    """Half circle: the tip error is the O(1/n^2) error of the RFE polygon."""
    err = [end_moment(n, 0.5)[2] for n in (10, 20, 40)]
    orders = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.1), (err, orders)
    assert err[1] < 2e-3


# --------------------------------------------------------------------------- B4
@pytest.mark.parametrize("n", [10, 20])
def test_B4_cantilever_frequencies_rigid_shear(n):
    """Bending springs only (shear and axial springs stiff), RFE inertia m l^2/12: the
    over-prediction ratios of VALIDATION.md B4."""
    assert b4_frequencies(n) == pytest.approx(B4_RATIOS[n], abs=1.5e-5)


def test_B4_fem_shear_converges_from_above():
    """With eq. 8.89 shear springs the first frequency converges to the continuum value as 1/n^2."""
    err = [abs(b4_frequencies(n, shear="fem")[0] - 1.0) for n in (10, 20, 40)]
    orders = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.2), (err, orders)
    assert err[-1] < 1e-3


# --------------------------------------------------------------------------- B5
@pytest.mark.parametrize("n", [10, 20, 40])
def test_B5_hanging_chain_first_mode(n):
    """Inextensible chain pinned at the top: omega_1 = 1.20241 sqrt(g/L) within 0.1 % at n >= 10."""
    assert chain_frequencies(n, modes=6)[0] == pytest.approx(CHAIN_C[0], rel=1e-3)


def test_B5_hanging_chain_higher_modes():
    """Modes 2 and 3 converge to c_n from above; at n = 40 within 0.1 % and 0.5 %."""
    errs = np.array([chain_frequencies(n)[1:3] / CHAIN_C[1:3] - 1.0 for n in (10, 20, 40)])
    assert np.all(errs > 0) and np.all(np.diff(errs, axis=0) < 0)
    assert errs[-1, 0] < 1e-3 and errs[-1, 1] < 5e-3


# --------------------------------------------------------------------------- B9
@pytest.mark.parametrize("theta0", [30.0, 90.0, 150.0])
def test_B9_large_amplitude_pendulum(theta0):
    ratio = pendulum_period_ratio(
        theta0, lambda T0: {"kind": "generalized-alpha", "time_step": T0 / 400, "rho_inf": 1.0})
    assert ratio == pytest.approx(PENDULUM[theta0], rel=5e-4)
