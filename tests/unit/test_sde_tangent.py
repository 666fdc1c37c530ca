"""The SDE tangent (rfesim.loads.sde_tangent) against finite differences of sde_forces."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from reference_impl import spatial_central_differences

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
    return -spatial_central_differences(
        lambda Ra2, Rb2, ra2, rb2: spatial_forces(Ra2, Rb2, ra2, rb2, arm_a, arm_b, stiffness)[0], Ra, Rb, ra, rb, h)


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
    # exact but for the change of W in W^T h, h = F x g: O(|F| |g|), tiny against the material part
    assert np.abs(K[0] - Kfd).max() <= 1e-5 * scale


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


def geometric_parts(Ra, Rb, ra, rb, arm_a, arm_b, stiffness, h=1e-6):
    """(analytic, finite-difference) geometric parts: tangent minus the material B^T C B."""
    f, sigma = spatial_forces(Ra, Rb, ra, rb, arm_a, arm_b, stiffness)
    args = (np.array([0]), np.array([1]), arm_a[None], arm_b[None], stiffness[None], np.zeros((1, 6)),
            np.stack([Ra, Rb]), np.stack([ra, rb]), np.zeros((2, 3)))
    K, K0, Kd = np.zeros((1, 12, 12)), np.zeros((1, 12, 12)), np.zeros((1, 12, 12))
    sde_tangent(*args, sigma, K, Kd)
    sde_tangent(*args, np.zeros((1, 6)), K0, Kd)
    return K[0] - K0[0], finite_difference_tangent(Ra, Rb, ra, rb, arm_a, arm_b, stiffness, h=h) - K0[0]


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("bend", [0.5, 1.57, 2.5])
def test_pin_tangent_is_exact_at_any_relative_rotation(seed, bend):
    """A pin (isotropic translational stiffness, no rotational stiffness: a rope's end
    pinned to a payload) between RFEs turned far apart: the geometric part against finite
    differences to 1e-6. With the mean frame's rotation taken as (da_a + da_b)/2 (W = I) it
    was 7-50 % off at 0.5-1.57 rad, which gave the payload's free yaw a false stiffness
    coupling of 5e4 N*m/rad and left the A-frame deck-winch statics cycling for 183
    iterations (docs/theory.md, 'The SDE tangent')."""
    rng = np.random.default_rng(seed)
    pair = random_pair(rng, bend=bend, gap=0.01)
    geometric, geometric_fd = geometric_parts(*pair, np.array([1e6, 1e6, 1e6, 0.0, 0.0, 0.0]))
    assert np.abs(geometric - geometric_fd).max() <= 1e-6 * np.abs(geometric_fd).max()


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("bend", [0.03, 0.5, 1.57])
def test_tangent_with_section_moments_is_exact_but_for_the_gap_moment(seed, bend):
    """With rotational stiffness the section moment m = R_b J_r^-T M' changes with theta
    through J_r^-T (jr_inv_t_derivative). The one term left out is the change of W in
    W^T h, h = F x g the gap moment: O(|F| |g|), so with a gap of 1e-4 of the element the
    geometric part matches finite differences to 1e-4 at any bend (with W = J_r = I it was
    11-93 % off at 0.5-1.57 rad and 0.4-2 % at 0.03 rad)."""
    rng = np.random.default_rng(seed)
    pair = random_pair(rng, bend=bend, gap=1e-4)
    geometric, geometric_fd = geometric_parts(*pair, np.array([1e8, 3e7, 2e7, 1e4, 2e4, 3e4]))
    assert np.abs(geometric - geometric_fd).max() <= 1e-4 * np.abs(geometric_fd).max()


@pytest.mark.parametrize("angle", [0.0, 1e-3, 0.05, 0.0999, 0.1, 0.1001, 1.0, 2.0, 3.0])
def test_jr_inverse_transpose_derivative_against_its_readable_reference(angle):
    """d(J_r(theta)^-T M')/d(theta) against central differences of the quadrature J_r of
    reference_impl, on both sides of the switch from the series to the closed form."""
    from reference_impl import right_jacobian_inverse
    from rfesim.loads.sde_tangent import jr_inv_t_derivative
    rng = np.random.default_rng(7)
    axis = rng.normal(size=3)
    th = angle * axis / np.linalg.norm(axis)
    Mp = rng.normal(size=3) * 1e3
    D = np.zeros((3, 3))
    jr_inv_t_derivative(th, Mp, D)
    h = 1e-6
    D_fd = np.zeros((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        D_fd[:, j] = (right_jacobian_inverse(th + e).T @ Mp - right_jacobian_inverse(th - e).T @ Mp) / (2 * h)
    assert np.abs(D - D_fd).max() <= 1e-7 * np.abs(Mp).max()


def deformation(Ra, Rb, ra, rb, arm_a, arm_b):
    """eps = [R'^T g, theta] of the pair (sde_forces' eps output)."""
    F, M = np.zeros((2, 3)), np.zeros((2, 3))
    eps, sigma, point = np.zeros((1, 6)), np.zeros((1, 6)), np.zeros((1, 3))
    sde_forces(np.array([0]), np.array([1]), arm_a[None], arm_b[None], np.ones((1, 6)), np.zeros((1, 6)),
               np.stack([Ra, Rb]), np.stack([ra, rb]), np.zeros((2, 3)), np.zeros((2, 3)), np.zeros((2, 3)),
               F, M, eps, sigma, point)
    return eps[0]


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("bend", [1e-3, 0.5])
def test_material_parts_are_BT_C_B_and_BT_D_B_of_the_deformation_map(seed, bend):
    """The material parts against B^T C B and B^T D B with B = d(eps)/dx by central
    differences of the deformation, at a small and a large bend."""
    rng = np.random.default_rng(seed)
    Ra, Rb, ra, rb, arm_a, arm_b = random_pair(rng, bend=bend, gap=1e-3)
    stiffness = np.array([1e6, 3e5, 2e5, 1e4, 2e4, 3e4])
    damping = np.array([10.0, 5.0, 4.0, 1.0, 2.0, 3.0])
    B = spatial_central_differences(
        lambda Ra2, Rb2, ra2, rb2: deformation(Ra2, Rb2, ra2, rb2, arm_a, arm_b), Ra, Rb, ra, rb, 1e-6)
    K, Kd = np.zeros((1, 12, 12)), np.zeros((1, 12, 12))
    sde_tangent(np.array([0]), np.array([1]), arm_a[None], arm_b[None], stiffness[None], damping[None],
                np.stack([Ra, Rb]), np.stack([ra, rb]), np.zeros((2, 3)), np.zeros((1, 6)), K, Kd)
    for got, c in ((K[0], stiffness), (Kd[0], damping)):
        want = B.T @ np.diag(c) @ B
        assert np.abs(got - want).max() <= 1e-8 * np.abs(want).max()
