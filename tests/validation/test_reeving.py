"""Reeving (rfesim.loads.reeving): the sheave is also pulled toward the rope's lead (its
winch) by the tension at the sheave.

* kernel against a readable reference (the join's force from the readable SDE kernel);
* the pull's tangent (also on the lead's RFE, a boom's foot) against central differences
  of the readable pull law; the analytic Jacobian with the pull, and its off-band blocks,
  against finite differences;
* statics of cranes with the rope along the boom converges (the column_crane scenario, the
  crane of the tests at 8 and 20 boom elements) and the pull runs through the hinge; its
  dynamics and modes are those without reeving; the finite-difference Jacobian is refused;
* statics of an A-frame whose rope leads to a deck winch: the cylinders carry the weights'
  moment and the pull's moment about the hinge; the tension at the sheave is the weight
  hanging under it;
* a column crane whose rope runs along the boom to its foot: the pull is internal (the
  pedestal base loads are still exactly the weights' resultant and moment) and the boom is
  compressed by the rope tension;
* an A-frame overboarding run with the rope along the legs completes; with a deck winch
  lead the rope slips over the sheave (the slip kernel against numpy; the winch hands the
  slip to the hanging rope; the payload rides up by the slip) until the rope two-blocks,
  where the run stops saying so; without a winch it stops once the slip passes the rope's
  first element;
* errors name the field."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import rfesim
from rfesim.crane_results import crane_summary
from rfesim.errors import ScenarioError
from rfesim.loads.reeving import reeving_forces
from rfesim.loads.sde import sde_forces_rest_into
from rfesim.model.compile import compile_scenario
from rfesim.scenario.cranes import CylinderSpec, cylinder_lever
from rfesim.solvers.banded import bt_to_dense
from rfesim.solvers.jacobian import jacobian_analytic
from test_cranes import static_system

G = 9.81
DECK_WINCH = [6.0, 0.0, 3.0]         # forward of the hinge (outboard is -x), vessel frame


def a_frame(reeving=None, tilt=20.0, dynamics=False):
    tpl = {"type": "a-frame", "position": [0.0, 0.0, 2.0], "outboard_deg": 180.0,
           "legs": {"length": 8.0, "outer_diameter": 0.6, "wall_thickness": 0.025},
           "tilt_deg": [[0.0, tilt], [1.0, tilt]], "crossbeam_mass": 2000.0,
           "cylinder": {"base": [-3.0, 0.0], "eye": 5.0, "count": 2},
           "rope": {"length": 6.0, "elements": 6},
           "payload": {"mass": 10000.0, "radius_of_gyration": 1.0}}
    if reeving is not None:
        tpl["reeving"] = reeving
    dyn = {"duration": 0.2, "output_interval": 0.1,
           "integrator": {"kind": "generalized-alpha", "time_step": 0.05}}
    return {"environment": {"gravity": G}, "cranes": {"af": tpl},
            "analysis": {"statics": {"enabled": True}, "dynamics": dyn if dynamics else {"enabled": False}}}


def column(reeving=None, elements=10):
    tpl = {"type": "column", "position": [0.0, 0.0, 2.0],
           "pedestal": {"length": 8.0, "outer_diameter": 2.0, "wall_thickness": 0.04, "elements": 4},
           "boom": {"length": 20.0, "outer_diameter": 0.8, "wall_thickness": 0.02, "elements": elements},
           "slewing_deg": 0.0, "luffing_deg": 40.0, "rope": {"length": 10.0, "elements": 10},
           "payload": {"mass": 5000.0, "radius_of_gyration": 1.0}}
    if reeving is not None:
        tpl["reeving"] = reeving
    return {"environment": {"gravity": G}, "cranes": {"c": tpl},
            "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}}}


def reference_pull(system, j):
    """(tension, force on the parent, moment about its centre, lead point) of reeving j from
    the readable SDE kernel: the join SDE alone gives its force on the parent."""
    km, ws, att = system.km, system.ws, system.att
    s = int(km.rv_sde[j])
    a = int(km.sde_left[s])
    n = ws.R.shape[0]
    F = np.zeros((n, 3))
    M = np.zeros((n, 3))
    one = slice(s, s + 1)
    sde_forces_rest_into(km.sde_left[one], km.sde_right[one], km.sde_arm_left[one], km.sde_arm_right[one],
                         km.sde_stiffness[one], km.sde_damping[one], km.sde_has_rest[one], km.sde_rest[one],
                         ws.sde_rest_eff[one], ws.sde_rest_rate[one], ws.R, ws.rbase, ws.roff, ws.v, ws.w, F, M,
                         np.zeros((1, 6)), np.zeros((1, 6)), np.zeros((1, 3)), np.zeros((40, 3)),
                         np.zeros((16, 3, 3)))
    f = F[a]                     # (the join's arm on the rope carries the slip: slip_arms)
    T = np.linalg.norm(f)
    b = int(km.sde_right[s])
    P = 0.5 * (ws.r[a] + ws.R[a] @ km.sde_arm_left[s] + ws.r[b] + ws.R[b] @ km.sde_arm_right[s])   # the sheave
    if km.rv_kind[j] == 0:
        L = att.p[km.rv_att[j]] + att.R[km.rv_att[j]] @ km.rv_point[j]
    else:
        k = km.rv_rfe[j]
        L = ws.r[k] + ws.R[k] @ km.rv_point[j]
    e = (L - P) / np.linalg.norm(L - P)
    return T, T * e, np.cross(P - ws.r[a], T * e), L


def reference_slip(system, j):
    """(slip delta m, its rate m/s) of reeving j, numpy (rfesim.loads.reeving): delta =
    |L - P| - rv_len with P the sheave on the parent's side of the join, rate e . (v_L - v_P)."""
    km, ws, att = system.km, system.ws, system.att
    s = int(km.rv_sde[j])
    a = int(km.sde_left[s])
    arm = ws.R[a] @ km.sde_arm_left[s]
    P = ws.r[a] + arm
    at = int(km.rv_att[j])
    lead_arm = att.R[at] @ km.rv_point[j]
    L = att.p[at] + lead_arm
    e = (L - P) / np.linalg.norm(L - P)
    delta = float(np.linalg.norm(L - P) - km.rv_len[j])
    rate = float(e @ ((att.v[at] + np.cross(att.w[at], lead_arm)) - (ws.v[a] + np.cross(ws.w[a], arm))))
    return delta, rate


@pytest.mark.parametrize("lead", [DECK_WINCH, "boom"])
def test_reeving_kernel_against_its_readable_reference(lead):
    sc, system, state = static_system(a_frame(reeving=lead))
    km, ws, att = system.km, system.ws, system.att
    n = ws.R.shape[0]
    F = np.zeros((n, 3))
    M = np.zeros((n, 3))
    T_out, e_out, f_out = np.zeros(1), np.zeros((1, 3)), np.zeros((1, 3))
    reeving_forces(km.rv_sde, km.rv_kind, km.rv_att, km.rv_rfe, km.rv_point, km.sde_left, km.sde_right,
                   km.sde_arm_left, km.sde_arm_right, km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.R,
                   ws.rbase, ws.roff, ws.sigma, ws.sde_point, att.p, att.R, F, M, T_out, e_out, f_out,
                   np.zeros((32, 3)), np.zeros((16, 3, 3)))
    T, force, moment, L = reference_pull(system, 0)
    a = int(km.sde_left[km.rv_sde[0]])
    assert T > 5e4                                           # the payload and rope hang on the sheave
    assert T_out[0] == pytest.approx(T, rel=1e-9)
    assert np.allclose(F[a], force, rtol=0, atol=1e-9 * T)
    assert np.allclose(M[a], moment, rtol=0, atol=1e-8 * T)
    if km.rv_kind[0] == 1:                                   # along the legs: the equal pull at the foot
        k = int(km.rv_rfe[0])
        assert np.allclose(F[k], -force, rtol=0, atol=1e-9 * T)
        assert np.allclose(F.sum(axis=0), 0.0, atol=1e-9 * T)
    else:
        assert np.count_nonzero(np.abs(F).sum(axis=1)) == 1  # the reaction goes to the vessel


def test_slip_kernel_against_its_readable_reference():
    """The rope's slip over a sheave led to a deck winch (rfesim.loads.reeving.slip_arms):
    delta against numpy, the join's arm on the rope (-l/2 + delta + c/k rate), the same arm
    when set again (its base kept), and a base rewritten in between (a winch's payout) taken
    as the new base; with the frame moved 5 cm and everything moving."""
    from rfesim.loads.reeving import slip_arms
    sc, system, state = static_system(a_frame(reeving=DECK_WINCH))
    km = system.km
    rng = np.random.default_rng(11)
    moved = state.copy()
    step = rng.normal(size=moved.q.shape) * np.where(np.arange(6) < 3, 0.05, 5e-4)
    moved.q[system.mask] += step[system.mask]
    moved.qd[system.mask] = rng.normal(scale=0.3, size=moved.q.shape)[system.mask]
    system.accelerations(moved)
    ws, att = system.ws, system.att
    s = int(km.rv_sde[0])
    b = int(km.sde_right[s])
    half = 0.5 * float(km.rfe_length[b])
    delta, rate = reference_slip(system, 0)
    k, c = float(km.sde_stiffness[s, 0]), float(km.sde_damping[s, 0])
    assert abs(delta) > 1e-3 and abs(rate) > 1e-3                     # a real slip, moving
    assert ws.rv_slip_out[0] == pytest.approx(delta, rel=1e-12)        # as the evaluation set it
    want = -half + delta + c / k * rate
    assert km.sde_arm_right[s, 0] == pytest.approx(want, rel=1e-12)
    out = np.zeros(1)

    def again():
        slip_arms(km.rv_sde, km.rv_slip, km.rv_att, km.rv_point, km.rv_len, km.rv_arm_written, km.rv_arm_offset,
                  km.sde_left, km.sde_arm_left, km.sde_arm_right, km.sde_stiffness, km.sde_damping, ws.R, ws.rbase,
                  ws.roff, ws.v, ws.w, att.p, att.R, att.v, att.w, out)

    again()
    assert out[0] == pytest.approx(delta, rel=1e-12)
    assert km.sde_arm_right[s, 0] == pytest.approx(want, rel=1e-12)   # not offset twice
    km.sde_arm_right[s, 0] = -1.1 * half                                 # a winch paid out: a new base
    again()
    assert km.sde_arm_right[s, 0] == pytest.approx(-1.1 * half + delta + c / k * rate, rel=1e-12)
    np.testing.assert_array_equal(km.sde_arm_right[s, 1:], 0.0)


def readable_pulls(system, j, R, r, v, w):
    """The pulls of reeving j from the RFE poses R (n, 3, 3), centres r (n, 3) and spatial
    velocities v, w (n, 3), in numpy (rfesim.loads.reeving's law; the join's force from the
    readable SDE kernel): (12,) the force T e on the sheave's RFE a and its moment about a's
    centre, then for a line-end lead -T e on the lead's RFE f and its moment about f's
    centre (zeros for a vessel lead). A rope without slip (its join's arms as compiled)."""
    km, ws, att = system.km, system.ws, system.att
    s = int(km.rv_sde[j])
    a, b = int(km.sde_left[s]), int(km.sde_right[s])
    F = np.zeros_like(r)
    M = np.zeros_like(r)
    one = slice(s, s + 1)
    sde_forces_rest_into(km.sde_left[one], km.sde_right[one], km.sde_arm_left[one], km.sde_arm_right[one],
                         km.sde_stiffness[one], km.sde_damping[one], km.sde_has_rest[one], km.sde_rest[one],
                         ws.sde_rest_eff[one], ws.sde_rest_rate[one], R, r, np.zeros_like(r), v, w, F, M,
                         np.zeros((1, 6)), np.zeros((1, 6)), np.zeros((1, 3)), np.zeros((40, 3)),
                         np.zeros((16, 3, 3)))
    T = np.linalg.norm(F[a])
    P = 0.5 * (r[a] + R[a] @ km.sde_arm_left[s] + r[b] + R[b] @ km.sde_arm_right[s])    # the sheave
    out = np.zeros(12)
    if km.rv_kind[j] == 1:
        f = int(km.rv_rfe[j])
        L = r[f] + R[f] @ km.rv_point[j]
    else:
        L = att.p[km.rv_att[j]] + att.R[km.rv_att[j]] @ km.rv_point[j]
    pull = T * (L - P) / np.linalg.norm(L - P)
    out[0:3] = pull
    out[3:6] = np.cross(P - r[a], pull)
    if km.rv_kind[j] == 1:
        out[6:9] = -pull
        out[9:12] = np.cross(L - r[f], -pull)
    return out


def readable_pull_tangent(system, j, step=1e-7):
    """-d(pulls)/dx and -d(pulls)/dv of ``readable_pulls`` by central differences in the spatial
    displacements (dr, da; R -> exp(da) R) and velocities (v, w) of RFEs a, b and f (the
    columns of rfesim.loads.reeving.reeving_tangent's rv_K, rv_Kd), at the workspace's state;
    Richardson-extrapolated from the steps ``step`` and ``step``/2 (T = |f| of a join as stiff
    as 1e10 N/m bends sharply: the plain differences are off by 8.5e3 N/m at 1e-7 m, 266 at
    1e-8)."""
    from scipy.spatial.transform import Rotation
    km, ws = system.km, system.ws
    s = int(km.rv_sde[j])
    nodes = (int(km.sde_left[s]), int(km.sde_right[s]), int(km.rv_rfe[j]))

    def differences(h):
        K = np.zeros((12, 18))
        Kd = np.zeros((12, 18))
        for col in range(18):
            i, k = nodes[col // 6], col % 6
            if km.rv_kind[j] != 1 and col >= 12:
                continue
            diff = []
            diff_v = []
            for sign in (1.0, -1.0):
                R, r, v, w = ws.R.copy(), ws.r.copy(), ws.v.copy(), ws.w.copy()
                if k < 3:
                    r[i, k] += sign * h
                else:
                    R[i] = Rotation.from_rotvec(sign * h * np.eye(3)[k - 3]).as_matrix() @ R[i]
                diff.append(readable_pulls(system, j, R, r, ws.v, ws.w))
                R, r = ws.R.copy(), ws.r.copy()
                (v if k < 3 else w)[i, k % 3] += sign * h
                diff_v.append(readable_pulls(system, j, R, r, v, w))
            K[:, col] = -(diff[0] - diff[1]) / (2.0 * h)
            Kd[:, col] = -(diff_v[0] - diff_v[1]) / (2.0 * h)
        return K, Kd

    K1, Kd1 = differences(step)
    K2, Kd2 = differences(0.5 * step)
    return (4.0 * K2 - K1) / 3.0, (4.0 * Kd2 - Kd1) / 3.0


@pytest.mark.parametrize("elements", [8, 20])
def test_reeving_tangent_against_its_readable_reference(elements):
    """rfesim.loads.reeving.reeving_tangent (rope along the boom to its foot: rows the sheave's
    RFE a and the foot's f, columns a, the rope's first b and f) against central differences
    of the readable pull law, at a moved state (10 um, 10 urad off the equilibrium, at rest:
    like the SDE tangent, the pull's leaves out how the join's damping force changes with the
    positions at given rates, 3e-6 of the join's stiffness at 0.3 m/s): the tension's
    dependence on the join (of the join's stiffness), the run's turning (T/|L - P|) and the
    arms' turning (T |arm|), each to 1e-6 of its scale. Before, the foot's rows were left out
    (the coupling 2.7e9 N/m of a boom foot with its tip)."""
    from rfesim.loads.reeving import reeving_tangent
    from rfesim.loads.sde_tangent import sde_tangent_rest
    sc, system, state = static_system(column(reeving="boom", elements=elements))
    km = system.km
    rng = np.random.default_rng(5)
    moved = state.copy()
    step = rng.normal(size=moved.q.shape) * 1e-5
    moved.q[system.mask] += step[system.mask]
    system.evaluate(moved)
    ws, att = system.ws, system.att
    nsde = km.sde_left.shape[0]
    Ks, Kds = np.zeros((nsde, 12, 12)), np.zeros((nsde, 12, 12))
    sde_tangent_rest(km.sde_left, km.sde_right, km.sde_arm_left, km.sde_arm_right, km.sde_stiffness,
                     km.sde_damping, km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.R, ws.rbase, ws.roff,
                     ws.sigma, Ks, Kds)
    rv_K, rv_Kd = np.zeros((1, 12, 18)), np.zeros((1, 12, 18))
    reeving_tangent(km.rv_sde, km.rv_kind, km.rv_att, km.rv_rfe, km.rv_point, km.rv_slip, km.sde_left,
                    km.sde_right, km.sde_arm_left, km.sde_arm_right, ws.R, ws.rbase, ws.roff, ws.sde_point, att.p,
                    att.R, ws.rv_tension, ws.rv_dir, ws.rv_fdir, Ks, Kds, rv_K, rv_Kd)
    K, Kd = readable_pull_tangent(system, 0)
    T = float(ws.rv_tension[0])
    assert T > 4e4
    s = int(km.rv_sde[0])
    a, f = int(km.sde_left[s]), int(km.rv_rfe[0])
    assert a - f == elements                                     # the boom's tip and foot: not neighbours
    scale = np.abs(K).max()
    assert scale > 1e9                                           # the join's stiffness
    # the blocks of f's columns in a's rows (and a's in f's) are the run's and arms' turning only
    turning = np.abs(K[0:6, 12:18]).max()
    run = np.linalg.norm(ws.r[f] + ws.R[f] @ km.rv_point[0] - ws.sde_point[s])
    assert (1.0 - 1e-6) * T / run < turning < 10.0 * T
    for rows in (slice(0, 6), slice(6, 12)):
        for cols in (slice(0, 6), slice(6, 12), slice(12, 18)):
            ref = K[rows, cols]
            err = np.abs(rv_K[0][rows, cols] - ref).max()
            assert err < 1e-6 * max(np.abs(ref).max(), T), (rows, cols, err, np.abs(ref).max())
    np.testing.assert_allclose(rv_Kd[0], Kd, rtol=0, atol=1e-6 * np.abs(Kd).max())
    assert np.abs(Kd[0:3, 6:12]).max() > 1e4                     # the join's damping (N s/m), through T


def _dense_central_differences(system, args, q, step=1e-6):
    """The Jacobian of residual_q (args: its arguments but q and out) by central differences,
    one coordinate at a time (no colouring: every off-band block too)."""
    from rfesim.solvers.kernels import residual_q
    n = q.shape[0]
    D = np.zeros((6 * n, 6 * n))
    rp, rm = np.zeros((n, 6)), np.zeros((n, 6))
    for i in range(n):
        for k in range(6):
            h = step * (system.length_scale[i] if k < 3 else 1.0)
            qp = q.copy()
            qp[i, k] += h
            residual_q(*args[:2], qp, *args[2:], rp)
            qp[i, k] -= 2.0 * h
            residual_q(*args[:2], qp, *args[2:], rm)
            D[:, 6 * i + k] = ((rp - rm) / (2.0 * h)).ravel()
    return D


@pytest.mark.parametrize("lead", [DECK_WINCH, "boom"])
@pytest.mark.parametrize("mode", [0, 1])
def test_analytic_jacobian_with_reeving_against_finite_differences(mode, lead):
    """The pull's tension depends on the join's stretch: the analytic Jacobian carries it
    (rfesim.loads.reeving.reeving_tangent); without it the parent's rows are off by the
    rope's join stiffness. With the rope along the boom the pull's reaction on the boom's
    foot couples the foot with the tip and the rope's first RFE, off the band: those blocks
    (ws.ob_J) too, against central differences one coordinate at a time."""
    data = a_frame(reeving=lead) if lead != "boom" else column(reeving="boom", elements=8)
    sc, system, state = static_system(data)
    km = system.km
    rng = np.random.default_rng(3)
    q = state.q.copy()
    scale = np.where(np.arange(6) < 3, 1e-6 * system.length_scale[:, None], 1e-6)
    q[system.mask] += (rng.normal(size=q.shape) * scale)[system.mask]
    h = 0.02
    cq, cv = h * h * 0.3, h * 0.6
    Q0 = q - cq * rng.normal(size=q.shape)
    V0 = rng.normal(scale=0.01, size=q.shape)
    args = (km, system.att, state.ref, system.ws, 1.0, mode, Q0, V0, cq, cv, system.mask, system.qd_buf,
            system.A_buf)
    reference = _dense_central_differences(system, args, q)
    jacobian_analytic(*args[:2], q, *args[2:], np.zeros_like(q), system.qp, system.rp, system.hs,
                      system.length_scale, system.J, system.Ks, system.Kds, system.T, system.Fsde, system.Msde)
    analytic = bt_to_dense(system.J.copy())
    for c, (i, j) in enumerate(zip(km.ob_row, km.ob_col)):
        analytic[6 * i:6 * i + 6, 6 * j:6 * j + 6] += system.ws.ob_J[c]
    # the rows of the sheave's two RFEs (the parent's last, the rope's first), their neighbours and
    # the lead's RFE with its neighbours (the boom's foot)
    s = int(km.rv_sde[0])
    a, b = int(km.sde_left[s]), int(km.sde_right[s])
    near = {a - 1, a, b, b + 1}
    if km.rv_kind[0] == 1:
        f = int(km.rv_rfe[0])
        near |= {f - 1, f, f + 1}
        assert km.has_offband and {(f, a), (f, b), (a, f)} <= set(zip(km.ob_row, km.ob_col))
        stiff = 1e9 * (cq if mode == 1 else 1.0)                                     # (the step's cq K)
        assert np.abs(reference[6 * f:6 * f + 6, 6 * b:6 * b + 6]).max() > stiff     # the foot against the rope
    rows = np.concatenate([np.arange(6 * i, 6 * i + 6) for i in sorted(near)])
    rows = rows[system.mask.ravel()[rows]]
    ref_rows, ana_rows = reference[rows], analytic[rows]
    size = np.abs(ref_rows).max(axis=1, keepdims=True)
    err = np.abs(ana_rows - ref_rows) / size
    assert err.max() < 5e-3, err.max()     # the tolerance of tests/unit/test_jacobian.py
    if km.rv_kind[0] == 1:
        return
    # and the pull's coupling matters: without reeving the parent's force rows against the rope's
    # first RFE differ by e (f/T)^T times the join's, of the order of the join stiffness
    plain = (km._replace(has_reeving=False),) + args[1:]
    without = _dense_central_differences(system, plain, q)
    block, block0 = reference[6 * a:6 * a + 3, 6 * b:6 * b + 3], without[6 * a:6 * a + 3, 6 * b:6 * b + 3]
    assert np.abs(block - block0).max() > 0.3 * np.abs(block0).max()


def test_a_frame_deck_winch_pull_adds_its_moment_about_the_hinge():
    """A-frame at rest 20 deg outboard, 10 t on the hook, rope led to a deck winch forward:
    2 F l (cylinders) = the weights' tipping moment + the pull's moment about the hinge,
    within 1 %; the tension at the sheave is the weight hanging under it (payload + rope,
    in air) within 1 %; the pull cuts the cylinder force by more than a third."""
    data = a_frame(reeving=DECK_WINCH)
    res = rfesim.simulate(data)
    out = crane_summary(res, "af", cylinder=data["cranes"]["af"]["cylinder"])
    base = crane_summary(rfesim.simulate(a_frame()), "af", cylinder=data["cranes"]["af"]["cylinder"])
    sc, system, state = static_system(data)
    km, ws = system.km, system.ws
    stub = system.model.line("af_stub")
    lifted = np.arange(km.rfe_mass.shape[0]) >= stub.rfe_stop
    tipping = np.sum(km.rfe_mass[lifted] * G * -(ws.r[lifted, 0]))          # outboard is -x, hinge x = 0
    T, force, moment, L = reference_pull(system, 0)
    s = int(km.rv_sde[0])
    P = ws.sde_point[s]
    hinge = np.array([0.0, 0.0, 2.0])
    pull_tipping = -np.cross(P - hinge, force)[1]                           # turning the frame outboard
    assert pull_tipping < 0.0                                               # the winch forward pulls it in
    rope = system.model.line("af_rope")
    hanging = 10000.0 + km.rfe_mass[rope.rfe_start:rope.rfe_stop].sum()
    assert ws.rv_tension[0] == pytest.approx(hanging * G, rel=0.01)
    _, lever = cylinder_lever(CylinderSpec(base=[-3.0, 0.0], eye=5.0), math.radians(90.0 - 20.0))
    F = out["cylinder_force"][0]
    assert 2.0 * F * lever == pytest.approx(tipping + pull_tipping, rel=0.01)
    assert abs(F) < (1.0 - 1.0 / 3.0) * abs(base["cylinder_force"][0])


def test_rope_along_the_boom_is_internal_and_compresses_the_boom():
    """Column crane, rope led along the boom to its foot: the pull and its reaction are
    internal, so the pedestal base still carries exactly the weights' resultant and moment
    (deformed positions); the boom's axial force grows in compression by the tension."""
    res = rfesim.statics(column(reeving="boom"))
    sc, system, state = static_system(column(reeving="boom"))
    km, ws = system.km, system.ws
    base = np.array([0.0, 0.0, 2.0])
    W = km.rfe_mass * G
    moment = np.cross(ws.r - base, np.outer(W, [0.0, 0.0, -1.0])).sum(axis=0)
    ped = res.line("c_pedestal")
    assert np.allclose(ped.end_a_force[0], [0.0, 0.0, -W.sum()], rtol=0, atol=1e-6 * W.sum())
    assert np.allclose(ped.end_a_moment[0], moment, rtol=0, atol=1e-6 * np.abs(moment).max())
    plain = rfesim.statics(column())
    T = float(ws.rv_tension[0])
    mid = 5                                                  # an SDE half way along the boom
    axial = res.line("c_boom").tension[0, mid]
    axial0 = plain.line("c_boom").tension[0, mid]
    assert axial - axial0 == pytest.approx(-T, rel=0.01)


def _column_crane_scenario(reeving="boom"):
    """scenarios/column_crane.json (statics: the crane slewed to 80 deg, the module 3 m above
    the water) with the hoist rope led along the boom (``reeving``)."""
    import json
    from pathlib import Path
    path = Path(__file__).resolve().parents[2] / "scenarios" / "column_crane.json"
    data = json.loads(path.read_text())
    motion = data["vessels"]["barge"]["motion"]
    motion["file"] = str(path.parent / motion["file"])
    data["analysis"]["dynamics"]["enabled"] = False
    if reeving is not None:
        data["cranes"]["crane"]["reeving"] = reeving
    return data


def _iterations(res):
    return int(res.counters["newton_iterations"])


@pytest.mark.parametrize("case", ["column_crane.json", "8 boom elements", "20 boom elements"])
def test_statics_with_the_rope_along_the_boom_converges_and_pulls_through_the_hinge(case):
    """Statics of cranes with the rope led along the boom to its foot (the hinge). Before, the
    coloured finite differences mixed the foot's coupling with the tip into the band:
    scenarios/column_crane.json with reeving "boom" did not converge ("load factor 0.5469
    reached, residual 1.37e-07"), nor the test crane at 8 or 20 boom elements; they converged
    only at some element counts (the crane of the tests at 10). Now each converges within
    twice the iterations without reeving plus 10. The physics: the pull runs from the sheave
    to the hinge, so it has no moment about the hinge and the luffing cylinders (or the
    luffing drive) carry what they carry without it (to 1e-4; the boom's extra compression
    moves the tip by micrometres); the tension at the sheave is the weight hanging under it
    (1 %), as without reeving (1e-6); the boom's axial force changes by -T along it (1 %)
    and the deck still takes the weights' resultant."""
    if case == "column_crane.json":
        data, plain_data = _column_crane_scenario(), _column_crane_scenario(None)
        crane, payload = "crane", 10000.0
    else:
        elements = int(case.split()[0])
        data, plain_data = column(reeving="boom", elements=elements), column(elements=elements)
        crane, payload = "c", 5000.0
    cyl = data["cranes"][crane].get("cylinder")
    res = rfesim.statics(data)
    plain = rfesim.statics(plain_data)
    assert "converged" in res.message
    assert _iterations(res) <= 2 * _iterations(plain) + 10, (_iterations(res), _iterations(plain))
    out, out0 = crane_summary(res, crane, cylinder=cyl), crane_summary(plain, crane, cylinder=cyl)
    if cyl is not None:
        assert out["cylinder_force"][0] == pytest.approx(out0["cylinder_force"][0], rel=1e-4)
    else:
        assert out["drive_torque"]["luffing"][0] == pytest.approx(out0["drive_torque"]["luffing"][0], rel=1e-4)
    sc, system, state = static_system(data)
    km, ws = system.km, system.ws
    rope = system.model.line(f"{crane}_rope")
    hanging = (payload + km.rfe_mass[rope.rfe_start:rope.rfe_stop].sum()) * G
    T = float(ws.rv_tension[0])
    assert T == pytest.approx(hanging, rel=0.01)
    assert out["rope_tension"][0] == pytest.approx(out0["rope_tension"][0], rel=1e-6)
    boom, boom0 = res.line(f"{crane}_boom").tension[0], plain.line(f"{crane}_boom").tension[0]
    mid = len(boom) // 2
    assert boom[mid] - boom0[mid] == pytest.approx(-T, rel=0.01)
    base, base0 = res.line(f"{crane}_pedestal").end_a_force[0], plain.line(f"{crane}_pedestal").end_a_force[0]
    np.testing.assert_allclose(base, base0, rtol=0, atol=1e-6 * np.abs(base0).max())


def test_dynamics_with_the_rope_along_the_boom_slews_like_without_it():
    """The crane of the tests at 8 boom elements (whose statics failed before) slewing 10 deg
    in 2 s with the rope along the boom: it runs with no more Newton iterations than 1.3x
    those without reeving, and the pull through the hinge leaves the luffing drive's torque
    as it is without it (1 %)."""
    def slewing(reeving):
        data = column(reeving=reeving, elements=8)
        data["cranes"]["c"]["slewing_deg"] = [[0.0, 0.0], [2.0, 10.0]]
        data["analysis"]["dynamics"] = {"duration": 2.0, "output_interval": 0.1,
                                        "integrator": {"kind": "generalized-alpha", "time_step": 0.02}}
        return rfesim.simulate(data)

    res, plain = slewing("boom"), slewing(None)
    assert res.time[-1] == pytest.approx(2.0)
    assert res.counters["newton_iterations"] <= 1.3 * plain.counters["newton_iterations"]
    out, out0 = crane_summary(res, "c"), crane_summary(plain, "c")
    np.testing.assert_allclose(out["drive_torque"]["luffing"], out0["drive_torque"]["luffing"],
                               rtol=0.01, atol=0.01 * np.abs(out0["drive_torque"]["luffing"]).max())


@pytest.mark.parametrize("elements", [10, 12])
def test_modes_with_the_rope_along_the_boom_are_those_without_it(elements):
    """Modal analysis of the crane of the tests with the rope along the boom: the pull toward
    the foot turns with the boom like a tendon inside it, so the modes are nearly those
    without reeving (the boom's first bending mode 1.179 Hz without, 1.187 with, at 10 and 12
    elements; within 2 %). Before, its stiffness came from the coloured differences, which
    mixed the foot's coupling with the tip into the band: 1.450 Hz at 10 elements, 1.905 at 12."""
    plain = rfesim.modes(column(elements=elements), 8)
    res = rfesim.modes(column(reeving="boom", elements=elements), 8)
    np.testing.assert_allclose(res.frequencies_hz[2:6], plain.frequencies_hz[2:6], rtol=0.005)   # the pendulum
    assert plain.frequencies_hz[6] == pytest.approx(1.18, rel=0.01)                              # the boom
    assert res.frequencies_hz[6] == pytest.approx(plain.frequencies_hz[6], rel=0.02)


def test_rope_along_a_line_with_finite_difference_jacobian_is_refused():
    """The coloured finite-difference Jacobian mixes the pull on the boom's foot into the band
    (82 of 100 steps of the crane of the tests halved); dynamics with a rope led along a line
    asks for the analytic Jacobian, naming the field."""
    data = column(reeving="boom")
    data["analysis"]["dynamics"] = {"duration": 1.0, "integrator": {"kind": "generalized-alpha", "time_step": 0.02,
                                                                    "jacobian": "finite-difference"}}
    with pytest.raises(ScenarioError) as exc:
        rfesim.Scenario.model_validate(data)
    text = str(exc.value)
    assert "analysis.dynamics.integrator.jacobian" in text and "c_boom:end_a" in text and "analytic" in text
    data["cranes"]["c"]["reeving"] = DECK_WINCH                  # a deck lead couples neighbours only
    rfesim.Scenario.model_validate(data)


def _a_frame_scenario(duration, name="a_frame.json"):
    import json
    from pathlib import Path
    path = Path(__file__).resolve().parents[2] / "scenarios" / name
    data = json.loads(path.read_text())
    motion = data["vessels"]["barge"]["motion"]
    motion["file"] = str(path.parent / motion["file"])
    data["analysis"]["dynamics"]["duration"] = duration
    return data


def test_a_frame_overboarding_with_the_rope_along_the_legs_runs():
    """The a_frame scenario's first 45 s (lift, swing out over the stern, start lowering)
    with the rope led along the legs to the hinge: it completes; the pull passes through the
    hinge, so the cylinder force at the start is that without reeving (to 1e-3), and the
    tension at the sheave stays near the hanging weight."""
    data = _a_frame_scenario(45.0)
    plain = rfesim.simulate(copy.deepcopy(data))
    data["cranes"]["aframe"]["reeving"] = "boom"
    res = rfesim.simulate(data)
    cyl = data["cranes"]["aframe"]["cylinder"]
    out, out0 = crane_summary(res, "aframe", cylinder=cyl), crane_summary(plain, "aframe", cylinder=cyl)
    assert res.time[-1] == pytest.approx(45.0)
    assert out["cylinder_force"][0] == pytest.approx(out0["cylinder_force"][0], rel=1e-3)
    assert np.all(np.isfinite(out["cylinder_force"]))
    assert 0.8 * 20000.0 * G < np.median(out["rope_tension"]) < 1.3 * 20000.0 * G


def test_a_frame_swinging_out_with_a_deck_winch_lead_draws_rope_over_the_sheave(tmp_path):
    """The a_frame scenario (rope of 5 elements, braked winch) with its rope led to a deck
    winch 10 m forward of the hinge. Before the slip (rfesim.loads.reeving.slip_arms) the
    hanging rope kept its length, the pull was circulatory, the swing-out fluttered until
    Newton failed at 29 s, and a dynamic run was refused. Now, over 26 s (the legs from -25
    to +17 deg): the run draws 4 m of rope over the sheave; the winch hands the slip to the
    hanging rope's length (rfesim.model.winches) so the part left on the sheave's join stays
    under half the rope's first element, and the rope's end A sits that part up past the
    sheave; the payload rides higher than without the lead by the whole slip (to the offset
    of their statics, within 2.5 cm over the 4 m). Run on, the rope two-blocks and the run
    stops saying so, keeping its results. Without a winch the slip stays on the join and the
    run stops once it passes the rope's first element."""
    data = _a_frame_scenario(26.0)
    data["cranes"]["aframe"]["rope"]["elements"] = 5
    data["cranes"]["aframe"]["tilt_deg"] = [[0.0, -25.0], [5.0, -25.0], [35.0, 35.0]]   # from 5 s, 3.71 deg/s at the stop
    plain = rfesim.simulate(copy.deepcopy(data))
    data["cranes"]["aframe"]["reeving"] = [-38.0, 0.0, 4.0]
    res = rfesim.simulate(copy.deepcopy(data))
    assert res.time[-1] == pytest.approx(26.0)
    rope, winch = res.line("aframe_rope"), res.winches["aframe_winch"]
    slip = rope.reeving_slip
    # the hanging rope is shorter by it; from its length at t = 0, which holds the slip statics
    # left (audit 7 D4: handed over at the start, so reeving_slip starts at 0; 5.0 before)
    handed = winch.suspended_length[0] + winch.payout - winch.suspended_length
    on_join = slip - handed
    assert slip[-1] > 4.0 and handed[-1] > 3.5
    assert np.abs(on_join).max() < 0.5 * 0.5                         # half the first RFE (dx / 2)
    sheave = res.line("aframe_crossbeam").position[:, -1]
    np.testing.assert_allclose(rope.position[:, 0], sheave - on_join[:, None] * rope.end_a_direction, atol=1e-4)
    rise = res.body("aframe_payload").position[:, 2] - plain.body("aframe_payload").position[:, 2]
    offset = rise - slip
    assert np.abs(offset - offset[0]).max() < 0.025
    tension = rope.tension[:, 0]
    assert 0.7 * 20000.0 * G < tension.min() and tension.max() < 1.3 * 20000.0 * G
    res.to_netcdf(tmp_path / "slip.nc")
    np.testing.assert_array_equal(rfesim.open_results(tmp_path / "slip.nc").line("aframe_rope").reeving_slip, slip)
    longer = copy.deepcopy(data)
    longer["analysis"]["dynamics"]["duration"] = 45.0
    with pytest.raises(rfesim.SolverError) as exc:
        rfesim.simulate(longer)
    assert "drew" in str(exc.value) and "left hanging" in str(exc.value)
    assert 26.0 < exc.value.results.time[-1] < 45.0
    del data["cranes"]["aframe"]["winch"]
    with pytest.raises(rfesim.SolverError) as exc:
        rfesim.simulate(data)
    assert "slipped" in str(exc.value) and "first element" in str(exc.value)
    kept = exc.value.results
    assert 5.0 < kept.time[-1] < 26.0 and abs(kept.line("aframe_rope").reeving_slip[-1]) > 0.5


def test_deck_winch_scenario_swings_out_with_the_winch_paying_out_the_slip():
    """scenarios/a_frame_deck_winch.json (the portal), first 45 s: the run to the deck winch
    grows by about 7 m as the legs swing out; the rope slips over the sheave by that much while
    the winch pays out as the legs turn (7.0 m over 5-35 s), so the module's hanging length
    under the sheave stays within 0.6 m of the start through the swing (the sheave itself
    heaves by 1-2 m with the barge's pitch at the stern) and the module hangs plumb under it."""
    res = rfesim.simulate(_a_frame_scenario(45.0, "a_frame_deck_winch.json"))
    assert res.time[-1] == pytest.approx(45.0)
    t = res.time
    slip = res.line("aframe_rope").reeving_slip
    swung = int(np.searchsorted(t, 36.0))
    assert 6.5 < slip[swung] < 7.8
    hanging = res.body("aframe_payload").position - res.line("aframe_rope").position[:, 0]
    length = np.linalg.norm(hanging, axis=1)
    assert np.abs(length[:swung] - length[0]).max() < 0.6
    assert np.abs(hanging[:swung, :2]).max() < 0.3
    assert res.winches["aframe_winch"].payout[swung] == pytest.approx(7.0, rel=0.02)


@pytest.mark.parametrize("edit, field, words", [
    (lambda d: d["cranes"]["af"].update(reeving=[0.0, 1.0]), "cranes.af.reeving", ""),
    (lambda d: d["cranes"]["af"].update(reeving="legs"), "cranes.af.reeving", ""),
])
def test_template_reeving_errors_name_the_field(edit, field, words):
    data = a_frame()
    edit(data)
    with pytest.raises(ScenarioError) as exc:
        rfesim.Scenario.model_validate(data)
    assert field in str(exc.value)


def _line_scene(reeving, connection="pinned"):
    return {"environment": {"gravity": G},
            "vessels": {"ship": {}},
            "line_types": {"bar": {"outer_diameter": 0.3, "wall_thickness": 0.02, "youngs_modulus": 2.1e11,
                                   "density": 7850.0},
                           "rope": {"outer_diameter": 0.04, "EA": 1e8, "EIy": 10.0, "EIz": 10.0, "GJ": 10.0,
                                    "mass_per_length": 8.0}},
            "lines": {"boom": {"type": "bar", "length": 5.0, "elements": 2,
                               "end_a": {"attach": "ship", "position": [0, 0, 10], "direction": [1, 0, 0],
                                         "connection": "clamped"}, "end_b": {"attach": "free"}},
                      "rope": {"type": "rope", "length": 5.0, "elements": 2,
                               "end_a": {"attach": "boom:end_b", "connection": connection,
                                         "direction": [0, 0, -1], "reeving": reeving},
                               "end_b": {"attach": "free"}}}}


@pytest.mark.parametrize("reeving, connection, field, words", [
    ({"lead": "ship", "point": [0, 0, 0]}, "clamped", "lines.rope.end_a.reeving", "pinned join"),
    ({"lead": "ship"}, "pinned", "lines.rope.end_a.reeving.point", "give the lead point"),
    ({"lead": "boom:end_a", "point": [0, 0, 0]}, "pinned", "lines.rope.end_a.reeving.point", "leave out point"),
    ({"lead": "boom:middle"}, "pinned", "lines.rope.end_a.reeving.lead", "'<line>:end_a'"),
    ({"lead": "barge", "point": [0, 0, 0]}, "pinned", "lines.rope.end_a.reeving.lead", "unknown vessel 'barge'"),
    ({"lead": "mast:end_a"}, "pinned", "lines.rope.end_a.reeving.lead", "unknown line 'mast'"),
    ({"lead": "boom:end_b"}, "pinned", "lines.rope.end_a.reeving.lead", "the sheave itself"),
])
def test_reeving_errors_name_the_field(reeving, connection, field, words):
    data = _line_scene(reeving, connection)
    with pytest.raises(ScenarioError) as exc:
        compile_scenario(rfesim.Scenario.model_validate(data))
    text = str(exc.value)
    assert field in text and words in text, text


def test_reeving_on_a_line_scene_pulls_the_boom_tip_toward_the_lead():
    """A 5 m cantilever with a 5 m rope hanging from its tip, the rope led back to the
    cantilever's root: the tip's vertical deflection is that of the hanging weight alone
    (the pull is along the chord, nearly axial), and the root's axial force grows by T."""
    data = copy.deepcopy(_line_scene({"lead": "boom:end_a"}))
    data["analysis"] = {"statics": {"enabled": True}, "dynamics": {"enabled": False}}
    data["lines"]["rope"]["end_b"] = {"attach": "free"}
    res = rfesim.statics(data)
    plain = copy.deepcopy(data)
    del plain["lines"]["rope"]["end_a"]["reeving"]
    res0 = rfesim.statics(plain)
    T = 8.0 * 5.0 * G
    dN = res.line("boom").tension[0, 0] - res0.line("boom").tension[0, 0]
    assert dN == pytest.approx(-T, rel=0.02)
