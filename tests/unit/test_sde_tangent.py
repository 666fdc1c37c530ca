"""The SDE tangent (rfesim.loads.sde_tangent) against finite differences of sde_forces."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from rfesim.loads.sde import sde_forces
from rfesim.loads.sde_tangent import sde_tangent


def random_pair(rng, bend=0.05, gap=1e-3):
    """Two neighbouring RFEs of a line, bent by ~bend rad, with a small gap."""
    Ra = Rotation.random(random_state=rng.integers(1 << 30)).as_matrix()
    rel = Rotation.from_rotvec(rng.normal(scale=bend, size=3)).as_matrix()
    Rb = Ra @ rel
    la, lb = 1.0, 0.8
    arm_a = np.array([0.5 * la, 0.0, 0.0])
    arm_b = np.array([-0.5 * lb, 0.0, 0.0])
    ra = rng.normal(size=3)
    joint = ra + Ra @ arm_a
    rb = joint - Rb @ arm_b + rng.normal(scale=gap, size=3)
    return Ra, Rb, ra, rb, arm_a, arm_b


def spatial_forces(Ra, Rb, ra, rb, arm_a, arm_b, stiffness):
    R = np.stack([Ra, Rb])
    rbase = np.stack([ra, rb])
    roff = np.zeros((2, 3))
    F = np.zeros((2, 3))
    M = np.zeros((2, 3))
    eps, sigma, point = np.zeros((1, 6)), np.zeros((1, 6)), np.zeros((1, 3))
    sde_forces(np.array([0]), np.array([1]), arm_a[None], arm_b[None], stiffness[None], np.zeros((1, 6)),
               R, rbase, roff, np.zeros((2, 3)), np.zeros((2, 3)), F, M, eps, sigma, point)
    return np.concatenate([F[0], M[0], F[1], M[1]]), sigma


def finite_difference_tangent(Ra, Rb, ra, rb, arm_a, arm_b, stiffness, h=1e-7):
    """-df/dx by central differences in spatial virtual displacements and rotations."""
    K = np.zeros((12, 12))
    for j in range(12):
        cols = []
        for sign in (1.0, -1.0):
            d = np.zeros(12)
            d[j] = sign * h
            Ra2 = Rotation.from_rotvec(d[3:6]).as_matrix() @ Ra
            Rb2 = Rotation.from_rotvec(d[9:12]).as_matrix() @ Rb
            f, _ = spatial_forces(Ra2, Rb2, ra + d[0:3], rb + d[6:9], arm_a, arm_b, stiffness)
            cols.append(f)
        K[:, j] = -(cols[0] - cols[1]) / (2 * h)
    return K


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("bend", [1e-3, 0.03])
def test_tangent_matches_finite_differences(seed, bend):
    rng = np.random.default_rng(seed)
    Ra, Rb, ra, rb, arm_a, arm_b = random_pair(rng, bend=bend)
    stiffness = np.array([1e6, 3e5, 2e5, 1e4, 2e4, 3e4])
    f, sigma = spatial_forces(Ra, Rb, ra, rb, arm_a, arm_b, stiffness)
    K = np.zeros((1, 12, 12))
    Kd = np.zeros((1, 12, 12))
    sde_tangent(np.array([0]), np.array([1]), arm_a[None], arm_b[None], stiffness[None], np.zeros((1, 6)),
                np.stack([Ra, Rb]), np.stack([ra, rb]), np.zeros((2, 3)), sigma, K, Kd)
    Kfd = finite_difference_tangent(Ra, Rb, ra, rb, arm_a, arm_b, stiffness)
    scale = np.abs(Kfd).max()
    # the geometric part uses J_r = I: its error is of the order of theta times the forces
    assert np.abs(K[0] - Kfd).max() <= max(1e-6, 2.0 * bend) * scale


def test_damping_tangent_is_BT_D_B():
    """B^T D B is symmetric positive semi-definite and zero for zero damping."""
    rng = np.random.default_rng(3)
    Ra, Rb, ra, rb, arm_a, arm_b = random_pair(rng)
    damping = np.array([10.0, 5.0, 5.0, 1.0, 2.0, 3.0])
    K = np.zeros((1, 12, 12))
    Kd = np.zeros((1, 12, 12))
    sde_tangent(np.array([0]), np.array([1]), arm_a[None], arm_b[None], np.zeros((1, 6)), damping[None],
                np.stack([Ra, Rb]), np.stack([ra, rb]), np.zeros((2, 3)), np.zeros((1, 6)), K, Kd)
    assert np.allclose(Kd[0], Kd[0].T, atol=1e-12 * np.abs(Kd).max())
    assert np.linalg.eigvalsh(Kd[0]).min() > -1e-9 * np.abs(Kd).max()
    assert np.abs(K).max() == 0.0


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("bend", [1e-3, 0.03])
def test_geometric_stiffness_matches_finite_differences(seed, bend):
    """The geometric part (tangent at the state minus the material part B^T C B) against
    finite differences, with forces large enough for it to matter (gap 1 % of the element)."""
    rng = np.random.default_rng(seed)
    Ra, Rb, ra, rb, arm_a, arm_b = random_pair(rng, bend=bend, gap=0.01)
    stiffness = np.array([1e6, 3e5, 2e5, 1e4, 2e4, 3e4])
    f, sigma = spatial_forces(Ra, Rb, ra, rb, arm_a, arm_b, stiffness)
    args = (np.array([0]), np.array([1]), arm_a[None], arm_b[None], stiffness[None], np.zeros((1, 6)),
            np.stack([Ra, Rb]), np.stack([ra, rb]), np.zeros((2, 3)))
    K, K0, Kd = np.zeros((1, 12, 12)), np.zeros((1, 12, 12)), np.zeros((1, 12, 12))
    sde_tangent(*args, sigma, K, Kd)
    sde_tangent(*args, np.zeros((1, 6)), K0, Kd)          # material part only
    geometric_fd = finite_difference_tangent(Ra, Rb, ra, rb, arm_a, arm_b, stiffness, h=1e-6) - K0[0]
    geometric = K[0] - K0[0]
    assert np.abs(geometric - geometric_fd).max() <= (0.01 + bend) * np.abs(geometric_fd).max()
