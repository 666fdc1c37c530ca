"""rfesim.loads.sde against the readable SDE of reference_impl (eqs. 8.75-8.91).

The elastic forces must be minus the gradient of V = 1/2 eps^T C eps (finite differences
over positions and global virtual rotations), the damping forces minus the velocity
gradient of the dissipation function 1/2 eps_dot^T D eps_dot, with eps_dot by finite
differences along the rigid motions of the two RFEs."""
from __future__ import annotations

import numpy as np
import pytest

import reference_impl as ref
from rfesim.loads.sde import sde_elastic_energy, sde_forces

SEEDS = [0, 1, 2, 3, 4, 5]
ROUNDOFF = 1e-12


def random_chain(rng, pairs, relative_angle=0.3, gap_size=0.05):
    """RFEs with random poses and velocities, and SDEs joining the given (a, b) pairs.
    Each b is placed roughly where a's chain continues (gap ~ gap_size, relative rotation
    ~ relative_angle) so the deformation is that of a bent, stretched, sheared line."""
    n = 1 + max(max(a, b) for a, b in pairs)
    rotations = np.empty((n, 3, 3))
    rbase = np.empty((n, 3))
    roff = np.empty((n, 3))
    rotations[0] = ref.random_rotation(rng)
    rbase[0] = rng.uniform(-50.0, 50.0, size=3)
    roff[0] = rng.uniform(-1.0, 1.0, size=3)
    arm_left = np.empty((len(pairs), 3))
    arm_right = np.empty((len(pairs), 3))
    placed = {0}
    for s, (a, b) in enumerate(pairs):
        half_a = rng.uniform(0.3, 2.0)
        half_b = rng.uniform(0.3, 2.0)
        arm_left[s] = [half_a, 0.0, 0.0] + rng.normal(scale=0.05, size=3)
        arm_right[s] = [-half_b, 0.0, 0.0] + rng.normal(scale=0.05, size=3)
        if a not in placed:
            rotations[a] = ref.random_rotation(rng)
            rbase[a] = rng.uniform(-50.0, 50.0, size=3)
            roff[a] = rng.uniform(-1.0, 1.0, size=3)
            placed.add(a)
        if b not in placed:
            rotations[b] = rotations[a] @ ref.exp_so3(ref.random_rotation_vector(rng, relative_angle * rng.uniform(0.1, 1)))
            end_a = rbase[a] + roff[a] + rotations[a] @ arm_left[s]
            centre_b = end_a - rotations[b] @ arm_right[s] + rng.normal(scale=gap_size, size=3)
            roff[b] = rng.uniform(-1.0, 1.0, size=3)
            rbase[b] = centre_b - roff[b]
            placed.add(b)
    velocities = rng.normal(size=(n, 3))
    angular_velocities = rng.normal(size=(n, 3))
    stiffness = rng.uniform(0.5, 2.0, size=(len(pairs), 6)) * np.array([1e5, 3e4, 3e4, 2e3, 5e3, 5e3])
    damping = rng.uniform(0.5, 2.0, size=(len(pairs), 6)) * np.array([1e3, 3e2, 3e2, 20.0, 50.0, 50.0])
    return dict(left=np.array([a for a, _ in pairs], np.int64), right=np.array([b for _, b in pairs], np.int64),
                arm_left=arm_left, arm_right=arm_right, stiffness=stiffness, damping=damping, R=rotations,
                rbase=rbase, roff=roff, v=velocities, w=angular_velocities)


def run_kernel(chain, stiffness=None, damping=None):
    n = chain["R"].shape[0]
    nsde = chain["left"].shape[0]
    F = np.zeros((n, 3))
    M = np.zeros((n, 3))
    eps = np.zeros((nsde, 6))
    sigma = np.zeros((nsde, 6))
    point = np.zeros((nsde, 3))
    sde_forces(chain["left"], chain["right"], chain["arm_left"], chain["arm_right"],
               chain["stiffness"] if stiffness is None else stiffness,
               chain["damping"] if damping is None else damping,
               chain["R"], chain["rbase"], chain["roff"], chain["v"], chain["w"], F, M, eps, sigma, point)
    return F, M, eps, sigma, point


def pair_of(chain, s):
    a, b = chain["left"][s], chain["right"][s]
    return dict(position_a=chain["rbase"][a] + chain["roff"][a], rotation_a=chain["R"][a],
                velocity_a=chain["v"][a], angular_velocity_a=chain["w"][a], arm_a=chain["arm_left"][s],
                position_b=chain["rbase"][b] + chain["roff"][b], rotation_b=chain["R"][b],
                velocity_b=chain["v"][b], angular_velocity_b=chain["w"][b], arm_b=chain["arm_right"][s])


CHAINS = {
    "single": [(0, 1)],
    "line": [(0, 1), (1, 2), (2, 3)],
    "scattered": [(0, 1), (1, 2), (2, 3), (3, 4), (0, 5), (4, 6)],
}


# ------------------------------------------------------------------ deformation (eq. 8.85)

@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("chain_name", list(CHAINS))
def test_deformation_section_forces_and_points(seed, chain_name):
    rng = np.random.default_rng(seed)
    chain = random_chain(rng, CHAINS[chain_name])
    _, _, eps, sigma, point = run_kernel(chain)
    position_scale = np.abs(chain["rbase"]).max()
    for s in range(len(CHAINS[chain_name])):
        pair = pair_of(chain, s)
        expected_eps = ref.sde_deformation(pair["position_a"], pair["rotation_a"], pair["arm_a"],
                                           pair["position_b"], pair["rotation_b"], pair["arm_b"])
        # the gap is a difference of positions of size position_scale
        np.testing.assert_allclose(eps[s, :3], expected_eps[:3], rtol=0, atol=ROUNDOFF * position_scale)
        np.testing.assert_allclose(eps[s, 3:], expected_eps[3:], rtol=0, atol=ROUNDOFF)
        expected_rate = ref.sde_deformation_rate(pair)
        expected_sigma = ref.sde_section_forces(chain["stiffness"][s], chain["damping"][s], expected_eps,
                                                expected_rate)
        sigma_scale = np.abs(chain["stiffness"][s] * expected_eps).max() + np.abs(chain["damping"][s]).max()
        np.testing.assert_allclose(sigma[s], expected_sigma, rtol=0, atol=1e-8 * sigma_scale)
        expected_point = ref.sde_point(pair["position_a"], pair["rotation_a"], pair["arm_a"],
                                       pair["position_b"], pair["rotation_b"], pair["arm_b"])
        np.testing.assert_allclose(point[s], expected_point, rtol=0, atol=ROUNDOFF * position_scale)


@pytest.mark.parametrize("seed", SEEDS)
def test_deformation_rate_matches_differences_along_rigid_motions(seed):
    """With C = 0 and D = 1 the kernel's sigma is d(eps)/dt."""
    rng = np.random.default_rng(seed)
    chain = random_chain(rng, CHAINS["scattered"])
    nsde = chain["left"].shape[0]
    _, _, _, sigma, _ = run_kernel(chain, stiffness=np.zeros((nsde, 6)), damping=np.ones((nsde, 6)))
    for s in range(nsde):
        expected = ref.sde_deformation_rate(pair_of(chain, s))
        np.testing.assert_allclose(sigma[s], expected, rtol=0, atol=1e-8 * np.abs(expected).max())


# ------------------------------------------------------------------ forces (eqs. 8.90-8.91, 8.96)

def accumulate_reference(chain, per_sde):
    n = chain["R"].shape[0]
    F = np.zeros((n, 3))
    M = np.zeros((n, 3))
    for s in range(chain["left"].shape[0]):
        a, b = chain["left"][s], chain["right"][s]
        Fa, Ma, Fb, Mb = per_sde(s)
        F[a] += Fa
        M[a] += Ma
        F[b] += Fb
        M[b] += Mb
    return F, M


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("chain_name", list(CHAINS))
@pytest.mark.parametrize("relative_angle", [1e-3, 0.3, 1.5])
def test_elastic_forces_are_minus_the_gradient_of_the_potential(seed, chain_name, relative_angle):
    rng = np.random.default_rng(seed)
    chain = random_chain(rng, CHAINS[chain_name], relative_angle=relative_angle)
    nsde = chain["left"].shape[0]
    F, M, _, _, _ = run_kernel(chain, damping=np.zeros((nsde, 6)))
    F_ref, M_ref = accumulate_reference(
        chain, lambda s: ref.sde_elastic_forces_by_gradient(pair_of(chain, s), chain["stiffness"][s]))
    scale = max(np.abs(F_ref).max(), np.abs(M_ref).max())
    np.testing.assert_allclose(F, F_ref, rtol=0, atol=1e-6 * scale)
    np.testing.assert_allclose(M, M_ref, rtol=0, atol=1e-6 * scale)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("chain_name", list(CHAINS))
@pytest.mark.parametrize("relative_angle", [1e-3, 0.3, 1.5])
def test_damping_forces_are_minus_the_gradient_of_the_dissipation_function(seed, chain_name, relative_angle):
    rng = np.random.default_rng(seed)
    chain = random_chain(rng, CHAINS[chain_name], relative_angle=relative_angle)
    nsde = chain["left"].shape[0]
    F, M, _, _, _ = run_kernel(chain, stiffness=np.zeros((nsde, 6)))
    F_ref, M_ref = accumulate_reference(
        chain, lambda s: ref.sde_damping_forces_by_dissipation(pair_of(chain, s), chain["damping"][s]))
    scale = max(np.abs(F_ref).max(), np.abs(M_ref).max())
    np.testing.assert_allclose(F, F_ref, rtol=0, atol=1e-7 * scale)
    np.testing.assert_allclose(M, M_ref, rtol=0, atol=1e-7 * scale)


@pytest.mark.parametrize("seed", SEEDS)
def test_elastic_and_damping_forces_add(seed):
    rng = np.random.default_rng(seed)
    chain = random_chain(rng, CHAINS["scattered"])
    nsde = chain["left"].shape[0]
    F, M, _, _, _ = run_kernel(chain)
    F_elastic, M_elastic, _, _, _ = run_kernel(chain, damping=np.zeros((nsde, 6)))
    F_damping, M_damping, _, _, _ = run_kernel(chain, stiffness=np.zeros((nsde, 6)))
    scale = np.abs(np.concatenate([F, M])).max()
    np.testing.assert_allclose(F, F_elastic + F_damping, rtol=0, atol=ROUNDOFF * scale)
    np.testing.assert_allclose(M, M_elastic + M_damping, rtol=0, atol=ROUNDOFF * scale)


def test_forces_are_added_to_what_is_there():
    rng = np.random.default_rng(11)
    chain = random_chain(rng, CHAINS["line"])
    F, M, _, _, _ = run_kernel(chain)
    n = chain["R"].shape[0]
    F0 = rng.normal(size=(n, 3))
    M0 = rng.normal(size=(n, 3))
    F1, M1 = F0.copy(), M0.copy()
    sde_forces(chain["left"], chain["right"], chain["arm_left"], chain["arm_right"], chain["stiffness"],
               chain["damping"], chain["R"], chain["rbase"], chain["roff"], chain["v"], chain["w"], F1, M1,
               np.zeros((3, 6)), np.zeros((3, 6)), np.zeros((3, 3)))
    scale = np.abs(np.concatenate([F, M])).max()
    np.testing.assert_allclose(F1, F0 + F, rtol=0, atol=ROUNDOFF * scale)
    np.testing.assert_allclose(M1, M0 + M, rtol=0, atol=ROUNDOFF * scale)


# ------------------------------------------------------------------ exact properties

@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("chain_name", list(CHAINS))
def test_momentum_balance(seed, chain_name):
    """Sum of forces is zero and the total moment about the origin is zero (round-off)."""
    rng = np.random.default_rng(seed)
    chain = random_chain(rng, CHAINS[chain_name], relative_angle=0.8, gap_size=0.3)
    F, M, _, _, _ = run_kernel(chain)
    centres = chain["rbase"] + chain["roff"]
    force_scale = np.abs(F).max()
    np.testing.assert_allclose(F.sum(axis=0), 0.0, rtol=0, atol=ROUNDOFF * force_scale)
    total_moment = M.sum(axis=0) + np.cross(centres, F).sum(axis=0)
    np.testing.assert_allclose(total_moment, 0.0, rtol=0,
                               atol=ROUNDOFF * force_scale * np.abs(centres).max())
    for s in range(chain["left"].shape[0]):        # and SDE by SDE
        Fs, Ms, _, _, _ = run_kernel({**chain, "left": chain["left"][s:s + 1], "right": chain["right"][s:s + 1],
                                      "arm_left": chain["arm_left"][s:s + 1],
                                      "arm_right": chain["arm_right"][s:s + 1],
                                      "stiffness": chain["stiffness"][s:s + 1],
                                      "damping": chain["damping"][s:s + 1]})
        np.testing.assert_array_equal(Fs.sum(axis=0), 0.0)
        moment = Ms.sum(axis=0) + np.cross(centres, Fs).sum(axis=0)
        np.testing.assert_allclose(moment, 0.0, rtol=0, atol=ROUNDOFF * np.abs(Fs).max() * np.abs(centres).max())


@pytest.mark.parametrize("seed", SEEDS)
def test_undeformed_pair_in_rigid_motion_has_no_forces(seed):
    """b placed exactly where the chain continues (same orientation, ends touching) and
    both moving as one rigid body: eps = 0, eps_dot = 0, no forces."""
    rng = np.random.default_rng(seed)
    chain = random_chain(rng, CHAINS["single"])
    Ra = chain["R"][0]
    chain["R"][1] = Ra
    end_a = chain["rbase"][0] + chain["roff"][0] + Ra @ chain["arm_left"][0]
    chain["rbase"][1] = end_a - Ra @ chain["arm_right"][0] - chain["roff"][1]
    w = chain["w"][0]
    chain["w"][1] = w
    centre_a = chain["rbase"][0] + chain["roff"][0]
    centre_b = chain["rbase"][1] + chain["roff"][1]
    chain["v"][1] = chain["v"][0] + np.cross(w, centre_b - centre_a)
    F, M, eps, sigma, _ = run_kernel(chain)
    position_scale = np.abs(chain["rbase"]).max()
    stiffness = chain["stiffness"].max()
    np.testing.assert_allclose(eps, 0.0, rtol=0, atol=ROUNDOFF * position_scale)
    typical = stiffness * position_scale + chain["damping"].max() * np.linalg.norm(chain["v"])
    np.testing.assert_allclose(sigma, 0.0, rtol=0, atol=ROUNDOFF * typical)
    np.testing.assert_allclose(F, 0.0, rtol=0, atol=ROUNDOFF * typical)
    np.testing.assert_allclose(M, 0.0, rtol=0, atol=ROUNDOFF * typical * position_scale)


@pytest.mark.parametrize("seed", SEEDS)
def test_elastic_energy(seed):
    rng = np.random.default_rng(seed)
    chain = random_chain(rng, CHAINS["scattered"])
    _, _, eps, _, _ = run_kernel(chain)
    expected = sum(ref.sde_elastic_potential(chain["stiffness"][s], eps[s]) for s in range(eps.shape[0]))
    assert sde_elastic_energy(chain["stiffness"], eps) == pytest.approx(expected, rel=ROUNDOFF)
    pair_energy = sum(ref.sde_elastic_potential(
        chain["stiffness"][s], ref.sde_deformation(**{k: v for k, v in pair_of(chain, s).items()
                                                     if k.startswith(("position", "rotation", "arm"))}))
        for s in range(eps.shape[0]))
    assert sde_elastic_energy(chain["stiffness"], eps) == pytest.approx(pair_energy, rel=1e-10)
