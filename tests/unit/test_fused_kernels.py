"""The scalar ("fused") forms of the hot kernels equal their readable references to the bit:
``rfesim.loads.sde_fused.sde_forces_rest_fused`` against ``rfesim.loads.sde.sde_forces_rest_into``,
``poses`` (``poses_fused``) against ``poses_reference``, ``project`` (``_project_free``)
against ``project_reference``. Random states of the every-kind scene of
test_kernels_assemble (free, pinned, clamped RFEs on a moving vessel) and random SDE sets
with every kind of rest rotation (none, static, driven)."""
from __future__ import annotations

import numpy as np
import pytest

import reference_impl as ref
from rfesim.loads.sde import sde_forces_rest_into
from rfesim.loads.sde_fused import sde_forces_rest_fused
from rfesim.model.assemble import (accumulate_forces, poses, poses_reference, project, project_reference,
                                   sde_forces_all)
from rfesim.model.compile import compile_scenario
from rfesim.scenario import load_scenario
from rfesim.solvers.system import System
from rfesim.vessel_kernel import attachment_kinematics
from test_kernels_assemble import SCENARIO, random_state

SEEDS = [0, 1, 2, 3]
POSE_ARRAYS = ("R", "E", "Edot", "wb", "w", "r", "rbase", "roff", "v")


@pytest.fixture(scope="module")
def system():
    return System(compile_scenario(load_scenario(SCENARIO)))


@pytest.mark.parametrize("seed", SEEDS)
def test_poses_fused_equal_the_reference(seed, system):
    rng = np.random.default_rng(seed)
    state = random_state(system, rng)
    km, att, ws = system.km, system.att, system.ws
    attachment_kinematics(system.vs, state.t, att)
    poses_reference(km, att, state.q, state.qd, state.ref, ws)
    expected = {k: getattr(ws, k).copy() for k in POSE_ARRAYS}
    for k in POSE_ARRAYS:
        getattr(ws, k)[:] = np.nan
    poses(km, att, state.q, state.qd, state.ref, ws)
    assert set(km.rfe_kind) == {0, 1, 2}
    for k in POSE_ARRAYS:
        np.testing.assert_array_equal(getattr(ws, k), expected[k], err_msg=k)


@pytest.mark.parametrize("seed", SEEDS)
def test_project_equals_the_reference(seed, system):
    rng = np.random.default_rng(seed)
    state = random_state(system, rng)
    km, att, ws = system.km, system.att, system.ws
    attachment_kinematics(system.vs, state.t, att)
    poses(km, att, state.q, state.qd, state.ref, ws)
    accumulate_forces(km, att, ws, 1.0)
    # added mass and inertia of every kind, random (they are inputs of the projection)
    ws.Ma[:] = rng.normal(size=ws.Ma.shape) * 50.0
    ws.Ja[:] = rng.uniform(0.0, 30.0, ws.Ja.shape)
    project_reference(km, att, ws)
    Mgen, fgen = ws.Mgen.copy(), ws.fgen.copy()
    ws.Mgen[:] = np.nan
    ws.fgen[:] = np.nan
    project(km, att, ws)
    np.testing.assert_array_equal(ws.Mgen, Mgen)
    np.testing.assert_array_equal(ws.fgen, fgen)


def random_sdes(rng, n, with_rest):
    """A chain of n RFEs with random poses and velocities, n - 1 SDEs between neighbours
    with random arms, stiffness, damping and (with_rest) rest rotations of every kind."""
    R = np.array([ref.exp_so3(ref.random_rotation_vector(rng, 1.0)) for _ in range(n)])
    rbase = rng.normal(size=(n, 3)) * 5.0
    roff = rng.normal(size=(n, 3)) * 0.1
    v = rng.normal(size=(n, 3))
    w = rng.normal(size=(n, 3))
    ns = n - 1
    left = np.arange(ns, dtype=np.int64)
    right = left + 1
    arm_l = rng.normal(size=(ns, 3))
    arm_r = rng.normal(size=(ns, 3))
    stiff = rng.uniform(1e3, 1e9, (ns, 6))
    damp = rng.uniform(0.0, 1e5, (ns, 6))
    if with_rest:
        flag = rng.integers(0, 3, ns).astype(np.int64)
        flag[:3] = (0, 1, 2)
        rest_static = np.array([ref.exp_so3(ref.random_rotation_vector(rng, 0.5)) for _ in range(ns)])
        rest_eff = np.array([ref.exp_so3(ref.random_rotation_vector(rng, 0.5)) for _ in range(ns)])
        rest_rate = rng.normal(size=(ns, 3))
    else:
        flag = np.zeros(0, np.int64)
        rest_static = np.zeros((0, 3, 3))
        rest_eff = np.zeros((0, 3, 3))
        rest_rate = np.zeros((0, 3))
    # neighbours turned by less than pi relative to each other (the SDE's range)
    for i in range(1, n):
        R[i] = R[i - 1] @ ref.exp_so3(ref.random_rotation_vector(rng, 1.2))
    return (left, right, arm_l, arm_r, stiff, damp, flag, rest_static, rest_eff, rest_rate, R, rbase, roff, v, w)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("with_rest", [False, True])
def test_sde_fused_equals_the_readable_kernel(seed, with_rest):
    rng = np.random.default_rng(100 + seed)
    n = 12
    args = random_sdes(rng, n, with_rest)
    ns = n - 1
    out = []
    for kernel in ("readable", "fused"):
        F = rng.normal(size=(n, 3))
        M = rng.normal(size=(n, 3))
        if out:                        # the same accumulators to start from
            F[:] = out[0][5]
            M[:] = out[0][6]
        F0, M0 = F.copy(), M.copy()
        eps = np.full((ns, 6), np.nan)
        sigma = np.full((ns, 6), np.nan)
        point = np.full((ns, 3), np.nan)
        if kernel == "readable":
            sde_forces_rest_into(*args, F, M, eps, sigma, point, np.zeros((32, 3)), np.zeros((16, 3, 3)))
        else:
            sde_forces_rest_fused(*args, F, M, eps, sigma, point)
        out.append((F, M, eps, sigma, point, F0, M0))
    for k, name in enumerate(("F", "M", "eps", "sigma", "point")):
        np.testing.assert_array_equal(out[1][k], out[0][k], err_msg=name)
    assert np.abs(out[0][0] - out[0][5]).max() > 1.0        # the SDEs did add forces


def test_scene_sde_forces_equal_the_readable_kernel(system):
    """The evaluation's SDE pass (sde_forces_all, with the scene's rest rotations and
    drives) equals the readable kernel on the evaluated workspace."""
    rng = np.random.default_rng(7)
    state = random_state(system, rng)
    km, att, ws = system.km, system.att, system.ws
    system.evaluate(state)
    n, ns = system.n, km.sde_left.shape[0]
    F1, M1 = np.zeros((n, 3)), np.zeros((n, 3))
    sde_forces_all(km, att, ws, F1, M1)
    eps1, sig1 = ws.eps.copy(), ws.sigma.copy()
    F2, M2 = np.zeros((n, 3)), np.zeros((n, 3))
    eps2, sig2, pt2 = np.zeros((ns, 6)), np.zeros((ns, 6)), np.zeros((ns, 3))
    sde_forces_rest_into(km.sde_left, km.sde_right, km.sde_arm_left, km.sde_arm_right, km.sde_stiffness,
                         km.sde_damping, km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.sde_rest_rate, ws.R,
                         ws.rbase, ws.roff, ws.v, ws.w, F2, M2, eps2, sig2, pt2, np.zeros((32, 3)),
                         np.zeros((16, 3, 3)))
    np.testing.assert_array_equal(F1, F2)
    np.testing.assert_array_equal(M1, M2)
    np.testing.assert_array_equal(eps1, eps2)
    np.testing.assert_array_equal(sig1, sig2)
    assert np.abs(F1).max() > 0.0
