"""A line with a kinked, driven joint SDE (rest rotation and drives, rfesim.loads.drives)
through the whole model: residual, energy, outputs, analytic Jacobian and a
generalised-alpha run. The models are compiled from a straight line and then given a
rest rotation / drives on one SDE (rfesim.model.arrays.joint_arrays)."""
from __future__ import annotations

import numpy as np
import pytest

import reference_impl as ref
import rfesim
from rfesim.loads.drives import rest_at
from rfesim.model.arrays import check_joint_arrays, joint_arrays
from rfesim.model.compile import compile_scenario
from rfesim.model.energy import mechanical_energy
from rfesim.solvers.banded import bt_to_dense
from rfesim.solvers.jacobian import jacobian_analytic
from rfesim.solvers.kernels import ga_advance, genalpha_parameters, jacobian_fd_general
from rfesim.solvers.system import System

JOINT = 2                                    # the kinked SDE: between RFEs 2 and 3
ROT_Y90 = ref.rotation_about_y(np.pi / 2)
DRIVES = [{"sde": JOINT, "axis": [0.0, 0.0, 1.0], "table": [[0.0, 0.0], [1.0, 0.2], [3.0, 1.2], [4.0, 1.5]]},
          {"sde": JOINT, "axis": [0.0, 1.0, 0.0], "table": [[0.5, 0.0], [2.5, -0.4], [4.0, -0.5]]}]


def line_scenario(gravity=0.0, end_a=None):
    return {
        "environment": {"gravity": gravity},
        "line_types": {"pipe": {"outer_diameter": 0.3, "wall_thickness": 0.02, "youngs_modulus": 2.1e11,
                                "density": 7850.0, "damping": {"axial_ratio": 0.05, "bending_ratio": 0.05}}},
        "lines": {"pipe": {"type": "pipe", "length": 6.0, "elements": 6,
                           "end_a": end_a or {"attach": "free", "position": [0, 0, 0], "direction": [1, 0, 0]},
                           "end_b": {"attach": "free"}}}}


def system_with_joint(rest, drives=(), **kw):
    model = compile_scenario(rfesim.load_scenario(line_scenario(**kw)))
    model.km = model.km._replace(**joint_arrays(model.nsde, {JOINT: rest}, list(drives)))
    return System(model)


def kinked_state(system, rest_joint, t=0.0, Q=np.eye(3), c=np.zeros(3)):
    """RFEs laid out stress-free for the joint's rest rotation: frames I up to RFE JOINT,
    rest_joint after it, centres chained with zero gaps; then the rigid motion (Q, c)."""
    km = system.km
    n = system.n
    frames = np.array([np.eye(3) if i <= JOINT else rest_joint for i in range(n)])
    centres = np.zeros((n, 3))
    for s in range(system.model.nsde):
        a, b = km.sde_left[s], km.sde_right[s]
        centres[b] = centres[a] + frames[a] @ km.sde_arm_left[s] - frames[b] @ km.sde_arm_right[s]
    st = system.model.initial.copy()
    st.t = t
    st.q[:] = 0.0
    st.ref.R[:] = Q[None] @ frames
    st.ref.X[:] = centres @ Q.T + c
    return st


def static_residual(system, st):
    system.set_time(st.t)
    out = np.zeros_like(st.q)
    system.static_residual(st.q, st.ref, 1.0, out)
    return out


def test_kinked_line_is_stress_free_and_stays_so_under_rigid_rotation():
    system = system_with_joint(ROT_Y90)
    plain = System(compile_scenario(rfesim.load_scenario(line_scenario())))
    st = kinked_state(system, ROT_Y90)
    r_plain = static_residual(plain, kinked_state(plain, ROT_Y90))
    big = np.abs(r_plain).max()
    assert big > 1e6                         # the L shape bends a straight line hard
    assert np.abs(static_residual(system, st)).max() < 1e-11 * big
    rng = np.random.default_rng(4)
    for _ in range(3):
        Q = ref.random_rotation(rng)
        moved = kinked_state(system, ROT_Y90, Q=Q, c=rng.uniform(-100, 100, 3))
        assert np.abs(static_residual(system, moved)).max() < 1e-11 * big
    # elastic energy and the output channels see no deformation either
    bent = mechanical_energy(plain, kinked_state(plain, ROT_Y90)).elastic
    assert bent > 1e6
    assert mechanical_energy(system, moved).elastic < 1e-20 * bent
    assert np.abs(system.ws.eps).max() < 1e-14
    # a kink the other way is not the rest state
    assert np.abs(static_residual(system, kinked_state(system, ROT_Y90.T))).max() > 0.5 * big


def test_drives_are_evaluated_at_the_state_time():
    rest = ref.exp_so3(np.array([0.1, 0.3, -0.2]))
    system = system_with_joint(rest, DRIVES)
    check_joint_arrays(system.km)
    for t in (0.0, 0.7, 2.2, 3.9, 5.0):
        R0, _ = rest_at(system.km, t)
        st = kinked_state(system, R0[JOINT], t=t)
        system.evaluate(st)
        assert np.abs(system.ws.sde_rest_eff[JOINT] - R0[JOINT]).max() < 1e-15
        # the layout of the driven rest state is undeformed at that time ...
        assert np.abs(system.ws.eps).max() < 1e-14
        # ... and not at another time (the drives moved)
        if 0.0 < t < 4.0:
            later = st.copy()
            later.t = t + 0.3
            system.evaluate(later)
            assert np.abs(system.ws.eps[JOINT, 3:]).max() > 1e-3


def test_damped_joint_following_its_drive_feels_no_drag():
    """The outer part turning rigidly about the joint point with the drive's angular velocity:
    no SDE force although the joint is damped; without subtracting the drive rate the
    damping would give a moment D omega."""
    rest = np.eye(3)
    system = system_with_joint(rest, DRIVES)
    km = system.km
    assert km.sde_damping[JOINT, 3:].min() > 0.0
    t = 2.2
    R0, omega0 = rest_at(km, t)
    st = kinked_state(system, R0[JOINT], t=t)
    w = omega0[JOINT]                        # RFE JOINT has frame I: body = global
    assert np.linalg.norm(w) > 0.1
    joint_point = st.ref.X[JOINT] + km.sde_arm_left[JOINT]
    for i in range(JOINT + 1, system.n):
        R = st.ref.R[i]
        st.qd[i, :3] = np.cross(w, st.ref.X[i] - joint_point)
        wb = R.T @ w                         # ZYX rates at zero angles: (wz, wy, wx) of the body rate
        st.qd[i, 3:] = [wb[2], wb[1], wb[0]]
    system.evaluate(st)
    drag = np.abs(km.sde_damping[JOINT, 3:] * np.linalg.norm(w)).max()
    assert drag > 1.0
    assert np.abs(system.ws.sigma[:, 3:]).max() < 1e-9 * drag
    # translations: the round-off of the gaps (~1e-16 m) times the axial stiffness
    roundoff = 1e-15 * km.sde_stiffness[:, :3].max() * 6.0
    assert np.abs(system.ws.sigma[:, :3]).max() < roundoff
    assert np.abs(system.ws.F).max() < roundoff and np.abs(system.ws.M).max() < 6.0 * roundoff


@pytest.mark.parametrize("mode", [0, 1])
def test_analytic_jacobian_with_rest_rotation_and_drives(mode):
    rest = ROT_Y90
    system = system_with_joint(rest, DRIVES, gravity=9.81)
    t = 2.2
    R0, _ = rest_at(system.km, t)
    st = kinked_state(system, R0[JOINT], t=t)
    rng = np.random.default_rng(11)
    q = st.q.copy()
    scale = np.where(np.arange(6) < 3, 1e-5 * system.length_scale[:, None], 1e-5)
    q[system.mask] += (rng.normal(size=q.shape) * scale)[system.mask]
    system.set_time(t)
    h = 0.02
    cq, cv = h * h * 0.3, h * 0.6
    Q0 = q - cq * rng.normal(size=q.shape)
    V0 = rng.normal(scale=0.1, size=q.shape)
    args = (system.km, system.att, q, st.ref, system.ws, 1.0, mode, Q0, V0, cq, cv, system.mask, system.qd_buf,
            system.A_buf)
    jacobian_fd_general(*args, np.zeros_like(q), system.qp, system.rp, system.hs, system.length_scale, system.J,
                        True, 1e-6)
    mask = system.mask.ravel()
    reference = bt_to_dense(system.J.copy())[np.ix_(mask, mask)]
    jacobian_analytic(*args, np.zeros_like(q), system.qp, system.rp, system.hs, system.length_scale, system.J,
                      system.Ks, system.Kds, system.T, system.Fsde, system.Msde)
    analytic = bt_to_dense(system.J.copy())[np.ix_(mask, mask)]
    rows = np.abs(reference).max(axis=1, keepdims=True)
    err = np.abs(analytic - reference) / rows
    assert err.max() < 5e-3, err.max()     # the tolerance of tests/unit/test_jacobian.py


def test_slewing_drive_turns_the_outer_part_in_a_generalised_alpha_run():
    """End A clamped, no gravity; the joint slews 90 deg about z by an S-shaped table over
    2 s (zero rate at both ends). After 3 s the outer part has turned rigidly about the
    joint point by 90 deg (up to its small elastic lag and vibration)."""
    end_a = {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0], "connection": "clamped"}
    drives = [{"sde": JOINT, "axis": [0.0, 0.0, 1.0], "table": [[0.0, 0.0], [2.0, np.pi / 2]]}]
    system = system_with_joint(np.eye(3), drives, end_a=end_a)
    km = system.km
    st = system.model.initial.copy()
    system.evaluate(st)
    tip0 = system.ws.r[-1] + system.ws.R[-1] @ np.array([0.5 * km.rfe_length[-1], 0, 0])
    joint_point = system.ws.r[JOINT] + system.ws.R[JOINT] @ km.sde_arm_left[JOINT]
    st.qdd[:] = system.accelerations(st)
    am, af, beta, gamma = genalpha_parameters(0.8)
    flags = np.zeros(3, np.int64)
    stats = np.zeros(4, np.int64)
    fail = np.zeros(3)
    h = 0.01
    status = ga_advance(km, system.vs, system.att, system.ws, st.q, st.qd, st.qdd, st.aux, st.ref, 0.0, h, 300,
                        am, af, beta, gamma, 1e-6, 20, True, system.mask, system.length_scale, 1e3, system.J,
                        system.Fac, system.Q0, system.V0, system.r, system.dq, system.qd_buf, system.A_buf,
                        system.qp, system.rp, system.hs, flags, stats, fail, True, system.Ks, system.Kds, system.T,
                        system.Fsde, system.Msde, st.qdd.copy())
    assert status == 0, fail
    st.t = 3.0
    system.evaluate(st)
    tip = system.ws.r[-1] + system.ws.R[-1] @ np.array([0.5 * km.rfe_length[-1], 0, 0])
    expected = joint_point + ref.rotation_about_z(np.pi / 2) @ (tip0 - joint_point)
    assert np.linalg.norm(tip - expected) < 1e-3 * np.linalg.norm(tip0 - joint_point)
    # the outer RFEs' frames turned by the drive
    assert np.abs(system.ws.R[-1] - ref.rotation_about_z(np.pi / 2)).max() < 1e-3
