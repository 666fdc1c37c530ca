"""rfesim.model.assemble (poses, project, solve_accelerations, residual_into, rebase)
against Newton-Euler written independently in reference_impl (eqs. 8.72-8.74, 8.92).

A small scene is compiled from a scenario: one line pinned and one clamped to a vessel
moving harmonically in all six degrees of freedom, both ends B free, in water with drag
and added mass; the state is then randomised."""
from __future__ import annotations

import numpy as np
import pytest

import reference_impl as ref
from rfesim.model.arrays import KIND_CLAMPED, KIND_FREE, KIND_PINNED, Reference
from rfesim.model.assemble import poses, rebase, residual_into, solve_accelerations
from rfesim.model.compile import State, compile_scenario
from rfesim.scenario import load_scenario
from rfesim.solvers.system import System
from rfesim.vessel_kernel import attachment_kinematics

SEEDS = [0, 1, 2, 3, 4, 5]
ROUNDOFF = 1e-12

SCENARIO = {
    "environment": {"gravity": 9.81, "water": {"density": 1025.0, "depth": 60.0}},
    "vessels": {"ship": {"position": [3.0, -2.0, 0.5], "heading_deg": 30.0,
                         "motion": {"kind": "harmonic",
                                    "surge": {"amplitude": 0.8, "period": 9.0, "phase_deg": 10.0},
                                    "sway": {"amplitude": 0.5, "period": 11.0, "phase_deg": 40.0},
                                    "heave": {"amplitude": 1.2, "period": 7.0, "phase_deg": 70.0},
                                    "roll": {"amplitude": 6.0, "period": 8.0, "phase_deg": 100.0},
                                    "pitch": {"amplitude": 4.0, "period": 6.5, "phase_deg": 130.0},
                                    "yaw": {"amplitude": 3.0, "period": 12.0, "phase_deg": 160.0},
                                    "ramp_duration": 2.0}}},
    "line_types": {"hose": {"EA": 2.0e6, "EIy": 4.0e3, "EIz": 6.0e3, "GJ": 3.0e3, "GA": 1.0e6,
                            "mass_per_length": 60.0, "outer_diameter": 0.3, "drag_normal": 1.1,
                            "drag_axial": 0.05, "added_mass_normal": 1.0, "added_mass_axial": 0.2,
                            "damping": {"axial_ratio": 0.05, "bending_ratio": 0.1}}},
    "lines": {
        "pinned": {"type": "hose", "length": 9.0, "elements": 3,
                   "end_a": {"attach": "ship", "position": [2.0, 1.0, 0.5], "connection": "pinned"},
                   "loads": [{"at": "end_b", "force": [10.0, -20.0, 30.0], "moment": [1.0, 2.0, -3.0]}]},
        "clamped": {"type": "hose", "length": 9.0, "elements": 3,
                    "end_a": {"attach": "ship", "position": [-1.0, 2.0, 0.0], "direction": [0.3, 0.1, -1.0],
                              "connection": "clamped"},
                    "loads": [{"at": 4.0, "force": [5.0, 5.0, 5.0], "frame": "local"}]},
    },
    "analysis": {"statics": {"enabled": False}},
}


@pytest.fixture(scope="module")
def system():
    return System(compile_scenario(load_scenario(SCENARIO)))


def random_state(system, rng):
    """Random time, coordinates, rates and reference rotations (moderate angles)."""
    model = system.model
    n = model.n
    mask = model.dof_mask
    q = np.where(mask, np.concatenate([rng.uniform(-0.3, 0.3, (n, 3)), rng.uniform(-0.6, 0.6, (n, 3))], 1), 0.0)
    qd = np.where(mask, rng.normal(size=(n, 6)), 0.0)
    R0 = np.array([R @ ref.exp_so3(ref.random_rotation_vector(rng, 0.2)) for R in model.initial.ref.R])
    reference = Reference(R=R0, X=model.initial.ref.X.copy())
    return State(t=float(rng.uniform(0.0, 20.0)), q=q, qd=qd, qdd=np.zeros((n, 6)), ref=reference,
                 aux=np.zeros((n, 6)))


def accelerations(system, state):
    """Evaluate the equations of motion and solve them RFE by RFE (solve_accelerations)."""
    system.evaluate(state)
    qdd = np.full((system.n, 6), np.nan)
    solve_accelerations(system.ws, qdd)
    return qdd


def indices(system, kind):
    return [i for i in range(system.n) if system.km.rfe_kind[i] == kind]


def test_scene_has_every_kind(system):
    assert len(indices(system, KIND_FREE)) == 6
    assert len(indices(system, KIND_PINNED)) == 1
    assert len(indices(system, KIND_CLAMPED)) == 1


# ------------------------------------------------------------------ poses (eqs. 8.73-8.74)

@pytest.mark.parametrize("seed", SEEDS)
def test_poses(seed, system):
    rng = np.random.default_rng(seed)
    state = random_state(system, rng)
    system.evaluate(state)
    ws, km, att = system.ws, system.km, system.att
    for i in range(system.n):
        angles, rates = state.q[i, 3:], state.qd[i, 3:]
        kind = km.rfe_kind[i]
        if kind == KIND_CLAMPED:
            a = km.rfe_attach[i]
            R = att.R[a] @ km.rfe_clamp_R[i]
            w = att.w[a]
        else:
            R = state.ref.R[i] @ ref.rotation_zyx(*angles)
            E = ref.euler_rate_matrix(*angles)
            np.testing.assert_allclose(ws.E[i], E, rtol=0, atol=ROUNDOFF)
            np.testing.assert_allclose(ws.wb[i], E @ rates, rtol=0, atol=ROUNDOFF * np.linalg.norm(rates))
            np.testing.assert_allclose(ws.Edot[i], ref.euler_rate_matrix_time_derivative(angles, rates) @ rates,
                                       rtol=0, atol=ROUNDOFF * np.linalg.norm(rates) ** 2)
            w = R @ E @ rates
        np.testing.assert_allclose(ws.R[i], R, rtol=0, atol=ROUNDOFF)
        np.testing.assert_allclose(ws.w[i], w, rtol=0, atol=ROUNDOFF * np.linalg.norm(w))
        if kind == KIND_FREE:
            centre = state.ref.X[i] + state.q[i, :3]
            velocity = state.qd[i, :3]
        else:
            pin, pin_velocity, _ = ref.attachment_point_kinematics(att, km.rfe_attach[i], km.rfe_attach_offset[i])
            centre = pin - R @ km.rfe_pin_arm[i]
            velocity = pin_velocity + np.cross(w, centre - pin)
        np.testing.assert_allclose(ws.r[i], centre, rtol=0, atol=ROUNDOFF * np.abs(centre).max())
        np.testing.assert_allclose(ws.rbase[i] + ws.roff[i], centre, rtol=0, atol=ROUNDOFF * np.abs(centre).max())
        np.testing.assert_allclose(ws.v[i], velocity, rtol=0, atol=ROUNDOFF * np.linalg.norm(velocity))


def evaluate_poses_at(system, state, time_shift, qdd=None):
    """Poses along the trajectory q + qd s + qdd s^2 / 2 at time t + s (copies)."""
    qdd = np.zeros_like(state.q) if qdd is None else qdd
    q = state.q + state.qd * time_shift + 0.5 * qdd * time_shift ** 2
    qd = state.qd + qdd * time_shift
    attachment_kinematics(system.vs, state.t + time_shift, system.att)
    poses(system.km, system.att, q, qd, state.ref, system.ws)
    return system.ws.r.copy(), system.ws.R.copy(), system.ws.v.copy(), system.ws.w.copy()


@pytest.mark.parametrize("seed", SEEDS)
def test_pose_velocities_are_time_derivatives_of_poses(seed, system):
    """v = dr/dt and [w]x = dR/dt R^T along the motion (central differences), every kind."""
    rng = np.random.default_rng(seed)
    state = random_state(system, rng)
    step = 1e-6
    r_plus, R_plus, _, _ = evaluate_poses_at(system, state, step)
    r_minus, R_minus, _, _ = evaluate_poses_at(system, state, -step)
    r, R, v, w = evaluate_poses_at(system, state, 0.0)
    for i in range(system.n):
        np.testing.assert_allclose(v[i], (r_plus[i] - r_minus[i]) / (2 * step), rtol=0, atol=1e-7)
        w_fd = ref.unskew((R_plus[i] - R_minus[i]) / (2 * step) @ R[i].T)
        np.testing.assert_allclose(w[i], w_fd, rtol=0, atol=1e-8)


# ------------------------------------------------------------------ project, free RFEs (eq. 8.92)

@pytest.mark.parametrize("seed", SEEDS)
def test_free_rfe_mass_blocks_and_newton_euler(seed, system):
    rng = np.random.default_rng(seed)
    state = random_state(system, rng)
    qdd = accelerations(system, state)
    ws, km = system.ws, system.km
    for i in indices(system, KIND_FREE):
        angles, rates = state.q[i, 3:], state.qd[i, 3:]
        E = ref.euler_rate_matrix(*angles)
        body_inertia = km.rfe_inertia[i] + ws.Ja[i]
        expected_mass = ref.free_rfe_generalised_mass(km.rfe_mass[i], ws.Ma[i], body_inertia, E)
        np.testing.assert_allclose(ws.Mgen[i], expected_mass, rtol=0, atol=ROUNDOFF * np.abs(expected_mass).max())
        np.testing.assert_array_equal(ws.fgen[i, :3], ws.F[i])
        translational, rotational = ref.free_rfe_newton_euler_residuals(
            km.rfe_mass[i], ws.Ma[i], body_inertia, ws.R[i], ws.F[i], ws.M[i], angles, rates, qdd[i, :3],
            qdd[i, 3:])
        force_scale = np.abs(ws.F[i]).max() + km.rfe_mass[i] * np.abs(qdd[i, :3]).max()
        omega = E @ rates
        moment_scale = (np.abs(ws.M[i]).max() + body_inertia.max() * np.linalg.norm(omega) ** 2
                        + body_inertia.max() * np.abs(E @ qdd[i, 3:]).max())
        np.testing.assert_allclose(translational, 0.0, rtol=0, atol=ROUNDOFF * force_scale)
        np.testing.assert_allclose(rotational, 0.0, rtol=0, atol=1e-11 * moment_scale)


# ------------------------------------------------------------------ project, pinned and clamped RFEs

@pytest.mark.parametrize("seed", SEEDS)
def test_pinned_rfe_newton_euler_with_the_pin_reaction(seed, system):
    """The angular acceleration of the pinned RFE equals that of a free rigid body plus an
    unknown pin reaction whose end point accelerates with the attachment point."""
    rng = np.random.default_rng(seed)
    state = random_state(system, rng)
    qdd = accelerations(system, state)
    ws, km, att = system.ws, system.km, system.att
    for i in indices(system, KIND_PINNED):
        np.testing.assert_array_equal(qdd[i, :3], 0.0)
        np.testing.assert_array_equal(ws.Mgen[i, :3, :3], np.eye(3))
        np.testing.assert_array_equal(ws.Mgen[i, :3, 3:], 0.0)
        angles, rates = state.q[i, 3:], state.qd[i, 3:]
        alpha_kernel = ws.R[i] @ ref.body_angular_acceleration(angles, rates, qdd[i, 3:])
        pin, _, pin_acceleration = ref.attachment_point_kinematics(att, km.rfe_attach[i], km.rfe_attach_offset[i])
        centre_acceleration, alpha, reaction = ref.pinned_rfe_newton_euler(
            km.rfe_mass[i], ws.Ma[i], km.rfe_inertia[i] + ws.Ja[i], ws.R[i], ws.w[i], ws.r[i], pin,
            pin_acceleration, ws.F[i], ws.M[i])
        np.testing.assert_allclose(alpha_kernel, alpha, rtol=0, atol=1e-10 * np.abs(alpha).max())
        # the end point's acceleration from the kernel's motion is the attachment point's
        to_pin = pin - ws.r[i]
        end_acceleration = ref.point_acceleration(centre_acceleration, alpha_kernel, ws.w[i], to_pin)
        np.testing.assert_allclose(end_acceleration, pin_acceleration, rtol=0,
                                   atol=1e-10 * np.abs(centre_acceleration).max())


@pytest.mark.parametrize("seed", SEEDS)
def test_pinned_rfe_centre_acceleration_from_poses(seed, system):
    """Second differences of the pinned RFE's centre along the kernel's motion
    (q + qd s + qdd s^2/2, attachment at t + s) equal Newton's a_c = (m I + M_a)^-1 (F + F_r)
    with the pin reaction of the independent Newton-Euler solution; and the end point stays
    on the attachment point."""
    rng = np.random.default_rng(seed)
    state = random_state(system, rng)
    qdd = accelerations(system, state)
    ws, km, att = system.ws, system.km, system.att
    pinned = indices(system, KIND_PINNED)
    expected = {}
    for i in pinned:
        pin, _, pin_acceleration = ref.attachment_point_kinematics(att, km.rfe_attach[i], km.rfe_attach_offset[i])
        expected[i] = ref.pinned_rfe_newton_euler(km.rfe_mass[i], ws.Ma[i], km.rfe_inertia[i] + ws.Ja[i], ws.R[i],
                                                  ws.w[i], ws.r[i], pin, pin_acceleration, ws.F[i], ws.M[i])
    step = 2e-5          # the random states have large accelerations: keep the truncation error small
    samples = {}
    for shift in (-step, 0.0, step):
        r, R, _, _ = evaluate_poses_at(system, state, shift, qdd)
        pins = {i: ref.attachment_point_kinematics(system.att, km.rfe_attach[i], km.rfe_attach_offset[i])[0]
                for i in pinned}
        samples[shift] = (r, R, pins)
    for i in pinned:
        for shift in samples:
            r, R, pins = samples[shift]
            np.testing.assert_allclose(r[i] + R[i] @ km.rfe_pin_arm[i], pins[i], rtol=0,
                                       atol=ROUNDOFF * np.abs(pins[i]).max())
        centre_fd = (samples[step][0][i] - 2 * samples[0.0][0][i] + samples[-step][0][i]) / step ** 2
        centre_acceleration = expected[i][0]
        np.testing.assert_allclose(centre_fd, centre_acceleration, rtol=0,
                                   atol=1e-5 * np.abs(centre_acceleration).max())


@pytest.mark.parametrize("seed", SEEDS)
def test_clamped_rfe_has_no_coordinates(seed, system):
    rng = np.random.default_rng(seed)
    state = random_state(system, rng)
    qdd = accelerations(system, state)
    for i in indices(system, KIND_CLAMPED):
        np.testing.assert_array_equal(system.ws.Mgen[i], np.eye(6))
        np.testing.assert_array_equal(system.ws.fgen[i], 0.0)
        np.testing.assert_array_equal(qdd[i], 0.0)


@pytest.mark.parametrize("seed", SEEDS)
def test_solve_accelerations_and_residual(seed, system):
    """qdd solves Mgen qdd = fgen block by block (numpy), and residual_into is Mgen qdd - fgen."""
    rng = np.random.default_rng(seed)
    state = random_state(system, rng)
    qdd = accelerations(system, state)
    ws = system.ws
    for i in range(system.n):
        expected = np.linalg.solve(ws.Mgen[i], ws.fgen[i])
        np.testing.assert_allclose(qdd[i], expected, rtol=0,
                                   atol=1e-11 * np.linalg.cond(ws.Mgen[i]) * max(np.abs(expected).max(), 1e-30))
    trial = rng.normal(size=qdd.shape)
    out = np.empty_like(trial)
    residual_into(ws, trial, out)
    expected = np.einsum("iab,ib->ia", ws.Mgen, trial) - ws.fgen
    np.testing.assert_allclose(out, expected, rtol=0, atol=ROUNDOFF * np.abs(expected).max())
    residual_into(ws, qdd, out)
    scale = np.abs(ws.fgen).max()
    np.testing.assert_allclose(out, 0.0, rtol=0, atol=1e-10 * scale)


# ------------------------------------------------------------------ rebase

def motion_summary(q, qd, qdd, reference, kind, i):
    """Orientation, body angular velocity and acceleration, and centre of RFE i."""
    angles, rates, angle_accelerations = q[i, 3:], qd[i, 3:], qdd[i, 3:]
    R = reference.R[i] @ ref.rotation_zyx(*angles)
    omega = ref.euler_rate_matrix(*angles) @ rates
    omega_dot = ref.body_angular_acceleration(angles, rates, angle_accelerations)
    centre = reference.X[i] + q[i, :3] if kind[i] == KIND_FREE else None
    return R, omega, omega_dot, centre


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("threshold", [0.0, 0.4])
@pytest.mark.parametrize("map_aux", [False, True])
def test_rebase_keeps_the_motion(seed, threshold, map_aux):
    rng = np.random.default_rng(seed)
    n = 9
    kind = np.array([KIND_FREE, KIND_PINNED, KIND_CLAMPED] * 3, np.int64)
    q = np.concatenate([rng.uniform(-2.0, 2.0, (n, 3)), rng.uniform(-1.0, 1.0, (n, 3))], 1)
    q[0, 3:] = [0.1, -0.2, 0.3]                  # below the threshold 0.4
    q[kind == KIND_CLAMPED] = 0.0
    q[kind == KIND_PINNED, :3] = 0.0
    qd = rng.normal(size=(n, 6))
    qdd = rng.normal(size=(n, 6))
    aux = rng.normal(size=(n, 6))
    reference = Reference(R=np.array([ref.random_rotation(rng) for _ in range(n)]),
                          X=rng.uniform(-100.0, 100.0, (n, 3)))
    before = [motion_summary(q, qd, qdd, reference, kind, i) for i in range(n)]
    before_aux = [motion_summary(q, qd, aux, reference, kind, i) for i in range(n)]
    q1, qd1, qdd1, aux1 = q.copy(), qd.copy(), qdd.copy(), aux.copy()
    reference1 = Reference(R=reference.R.copy(), X=reference.X.copy())
    count = rebase(q1, qd1, reference1, kind, threshold, qdd1, aux1, map_aux)
    expected_count = sum(1 for i in range(n) if kind[i] != KIND_CLAMPED and np.abs(q[i, 3:]).max() > threshold)
    assert count == expected_count
    for i in range(n):
        if kind[i] == KIND_CLAMPED:
            np.testing.assert_array_equal(q1[i], q[i])
            np.testing.assert_array_equal(reference1.R[i], reference.R[i])
            continue
        if np.abs(q[i, 3:]).max() <= threshold:
            np.testing.assert_array_equal(q1[i, 3:], q[i, 3:])
            np.testing.assert_array_equal(qd1[i, 3:], qd[i, 3:])
            np.testing.assert_array_equal(reference1.R[i], reference.R[i])
        else:
            np.testing.assert_array_equal(q1[i, 3:], 0.0)
        if kind[i] == KIND_FREE:
            np.testing.assert_array_equal(q1[i, :3], 0.0)
        np.testing.assert_array_equal(qd1[i, :3], qd[i, :3])
        np.testing.assert_array_equal(qdd1[i, :3], qdd[i, :3])
        R, omega, omega_dot, centre = motion_summary(q1, qd1, qdd1, reference1, kind, i)
        R0, omega0, omega_dot0, centre0 = before[i]
        np.testing.assert_allclose(R, R0, rtol=0, atol=ROUNDOFF)
        np.testing.assert_allclose(omega, omega0, rtol=0, atol=ROUNDOFF * np.abs(omega0).max())
        np.testing.assert_allclose(omega_dot, omega_dot0, rtol=0, atol=ROUNDOFF * np.abs(omega_dot0).max())
        if centre is not None:
            np.testing.assert_allclose(centre, centre0, rtol=0, atol=ROUNDOFF * np.abs(centre0).max())
        _, _, omega_dot_aux, _ = motion_summary(q1, qd1, aux1, reference1, kind, i)
        if map_aux:
            np.testing.assert_allclose(omega_dot_aux, before_aux[i][2], rtol=0,
                                       atol=ROUNDOFF * np.abs(before_aux[i][2]).max())
        else:
            np.testing.assert_array_equal(aux1[i], aux[i])
