"""The analytic block-tridiagonal Jacobian (rfesim.solvers.jacobian) against the coloured
central-difference Jacobian, in statics and in an implicit step, for lines with pinned,
clamped and free ends, in water, on the seabed, on a moving vessel."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.model.compile import compile_scenario
from rfesim.solvers.banded import bt_to_dense
from rfesim.solvers.jacobian import jacobian_analytic
from rfesim.solvers.kernels import jacobian_fd_general
from rfesim.solvers.statics import solve_statics
from rfesim.solvers.system import System

ROOT = Path(__file__).resolve().parents[2]


def cantilever_on_vessel():
    return {
        "environment": {"gravity": 9.81, "water": {"density": 1025.0, "depth": 50.0}},
        "vessels": {"ship": {"motion": {"kind": "harmonic", "heave": {"amplitude": 1.0, "period": 7.0},
                                        "pitch": {"amplitude": 2.0, "period": 9.0}}}},
        "line_types": {"pipe": {"outer_diameter": 0.3, "wall_thickness": 0.02, "youngs_modulus": 2.1e11,
                                "density": 7850.0, "drag_normal": 1.2, "drag_axial": 0.01, "added_mass_normal": 1.0,
                                "damping": {"axial_ratio": 0.05, "bending_ratio": 0.05}}},
        "lines": {"pipe": {"type": "pipe", "length": 30.0, "elements": 12,
                           "end_a": {"attach": "ship", "position": [0, 0, -1.0], "direction": [0.6, 0, -0.8],
                                     "connection": "clamped"},
                           "end_b": {"attach": "free"}}},
    }


def scenarios():
    h1 = json.loads((ROOT / "scenarios" / "h1_riser_heave.json").read_text())
    h1["lines"]["riser"]["elements"] = 30
    return {"h1_riser": h1, "cantilever_on_vessel": cantilever_on_vessel()}


def dense(system, J):
    mask = system.mask.ravel()
    return bt_to_dense(J)[np.ix_(mask, mask)]


def _off_equilibrium(name, seed, t):
    """The scene at its static state moved by 1e-3 (m or rad) at random, at time t, with the
    predictor terms Q0, V0 and coefficients cq, cv of a 0.05 s implicit step."""
    sc = rfesim.load_scenario(scenarios()[name])
    system = System(compile_scenario(sc))
    state, _ = solve_statics(system)
    rng = np.random.default_rng(seed)
    q = state.q.copy()
    q[system.mask] += (rng.normal(size=q.shape) * 1e-3)[system.mask]
    system.set_time(t)
    h = 0.05
    cq, cv = h * h * 0.3, h * 0.6
    Q0 = q - cq * rng.normal(size=q.shape)
    V0 = rng.normal(scale=0.1, size=q.shape)
    Q0[~system.mask] = q[~system.mask]
    V0[~system.mask] = 0.0
    return system, state, q, Q0, V0, cq, cv


@pytest.mark.parametrize("name", ["h1_riser", "cantilever_on_vessel"])
@pytest.mark.parametrize("mode", [0, 1])
def test_analytic_jacobian_matches_central_differences(name, mode):
    sc = rfesim.load_scenario(scenarios()[name])
    system = System(compile_scenario(sc))
    state, _ = solve_statics(system)
    rng = np.random.default_rng(7)
    q = state.q.copy()
    # off equilibrium by displacements of 1e-5 of an element and rotations of 1e-5 rad: SDE
    # gaps stay of the order of real strains (the geometric terms neglect O(gap/length))
    scale = np.where(np.arange(6) < 3, 1e-5 * system.length_scale[:, None], 1e-5)
    q[system.mask] += (rng.normal(size=q.shape) * scale)[system.mask]
    system.set_time(0.0)
    h = 0.02
    cq, cv = h * h * 0.3, h * 0.6
    Q0 = q - cq * rng.normal(scale=1.0, size=q.shape)
    V0 = rng.normal(scale=0.1, size=q.shape)
    Q0[~system.mask] = q[~system.mask]
    V0[~system.mask] = 0.0
    args = (system.km, system.att, q, state.ref, system.ws, 1.0, mode, Q0, V0, cq, cv, system.mask,
            system.qd_buf, system.A_buf)
    r0 = np.zeros_like(q)
    jacobian_fd_general(*args, np.zeros_like(q), system.qp, system.rp, system.hs, system.length_scale, system.J,
                        True, 1e-6)
    reference = dense(system, system.J.copy())
    jacobian_analytic(*args, r0, system.qp, system.rp, system.hs, system.length_scale, system.J, system.Ks,
                      system.Kds, system.T, system.Fsde, system.Msde)
    analytic = dense(system, system.J.copy())
    # compare block rows scaled by their largest entry: stiff axial and soft bending entries
    # differ by 1e10, a global norm would hide errors in the soft ones
    rows = np.abs(reference).max(axis=1, keepdims=True)
    err = np.abs(analytic - reference) / rows
    # the geometric SDE terms take J_r(theta) = I: an error of the order of the relative
    # rotation of neighbouring RFEs (~1e-2) times the geometric part of a row
    assert err.max() < 5e-3, err.max()
    # and the Newton step from the analytic Jacobian solves the reference linear system to
    # within 1 % of the residual (comparing the steps themselves would amplify the
    # differences in near-singular directions such as cable torsion)
    rhs = r0[system.mask]
    dq_a = np.linalg.solve(analytic, rhs)
    assert np.linalg.norm(reference @ dq_a - rhs) < 1e-2 * np.linalg.norm(rhs)


@pytest.mark.parametrize("name", ["h1_riser", "cantilever_on_vessel"])
def test_jacobian_from_the_newton_iterate_equals_the_full_one(name):
    """ga_advance forms the Jacobian from the evaluation of its Newton iterate
    (residual_general(..., 2, Fsde, Msde) keeps the SDE forces, jacobian_analytic_at with
    ``evaluated`` evaluates neither again): the same matrix and residual as
    jacobian_analytic, which evaluates both itself."""
    from rfesim.solvers.jacobian import jacobian_analytic_at
    from rfesim.solvers.residual import residual_general
    system, state, q, Q0, V0, cq, cv = _off_equilibrium(name, seed=3, t=1.3)
    args = (system.km, system.att, q, state.ref, system.ws, 1.0, 1, Q0, V0, cq, cv, system.mask,
            system.qd_buf, system.A_buf)
    r_full = np.zeros_like(q)
    jacobian_analytic(*args, r_full, system.qp, system.rp, system.hs, system.length_scale, system.J, system.Ks,
                      system.Kds, system.T, system.Fsde, system.Msde)
    J_full = system.J.copy()
    system.J[:] = np.nan
    system.Fsde[:] = np.nan
    r_it = np.zeros_like(q)
    residual_general(*args, r_it, 2, system.Fsde, system.Msde)
    jacobian_analytic_at(*args, r_it, system.qp, system.rp, system.hs, system.length_scale, system.J, system.Ks,
                         system.Kds, system.T, system.Fsde, system.Msde, True)
    np.testing.assert_array_equal(r_it, r_full)
    np.testing.assert_array_equal(system.J, J_full)


def _reference_jacobian(system, q, ref, Q0, V0, cq, cv, r0, mode):
    """The analytic Jacobian written out with numpy, from the tangents that jacobian_analytic
    left in system.Ks, Kds (SDEs, spatial) and T (the RFEs' coordinate maps): the SDE blocks
    T_i^T (cK K + cD Kd) T_j, plus the local part by forward differences with every RFE
    perturbed at once and the SDE forces frozen (residual_general mode 1)."""
    from rfesim.solvers.residual import residual_general
    km, n = system.km, q.shape[0]
    cK, cD = (1.0, 0.0) if mode == 0 else (cq, cv)
    J = np.zeros((n, 3, 6, 6))
    for s in range(km.sde_left.shape[0]):
        for bi, i in enumerate((km.sde_left[s], km.sde_right[s])):
            for bj, j in enumerate((km.sde_left[s], km.sde_right[s])):
                K = cK * system.Ks[s, 6 * bi:6 * bi + 6, 6 * bj:6 * bj + 6] + cD * system.Kds[s, 6 * bi:6 * bi + 6,
                                                                                              6 * bj:6 * bj + 6]
                J[i, j - i + 1] += system.T[i].T @ K @ system.T[j]
    typical = np.where(np.arange(6) < 3, system.length_scale[:, None], 1.0)
    for k in range(6):
        qp = q.copy()
        qp[:, k] = q[:, k] + 1.5e-8 * np.maximum(np.abs(q[:, k]), typical[:, k])
        hs = qp[:, k] - q[:, k]
        rp = np.zeros_like(q)
        residual_general(system.km, system.att, qp, ref, system.ws, 1.0, mode, Q0, V0, cq, cv, system.mask,
                         system.qd_buf, system.A_buf, rp, 1, system.Fsde, system.Msde)
        J[:, 1, :, k] += (rp - r0) / hs[:, None]
    return J


@pytest.mark.parametrize("name", ["h1_riser", "cantilever_on_vessel"])
@pytest.mark.parametrize("mode", [0, 1])
def test_analytic_jacobian_assembly_against_its_numpy_form(name, mode):
    """jacobian_analytic's assembly (the products with T specialised for free RFEs, whose T
    is diag(I, R E); the general product for pinned and clamped ones) against the same
    Jacobian formed with numpy from its own tangents: equal to rounding, block by block."""
    system, state, q, Q0, V0, cq, cv = _off_equilibrium(name, seed=11, t=0.7)
    r0 = np.zeros_like(q)
    jacobian_analytic(system.km, system.att, q, state.ref, system.ws, 1.0, mode, Q0, V0, cq, cv, system.mask,
                      system.qd_buf, system.A_buf, r0, system.qp, system.rp, system.hs, system.length_scale, system.J,
                      system.Ks, system.Kds, system.T, system.Fsde, system.Msde)
    J = system.J.copy()
    assert (system.km.rfe_kind == 0).sum() > 2 and (system.km.rfe_kind != 0).any()   # both paths taken
    J_ref = _reference_jacobian(system, q, state.ref, Q0, V0, cq, cv, r0, mode)
    scale = np.abs(J_ref).max(axis=(1, 3), keepdims=True) + 1e-300       # per block row
    assert (np.abs(J - J_ref) / scale).max() < 1e-12
