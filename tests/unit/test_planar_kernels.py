"""rfesim.formulations.planar (section 8.3) against the readable dense formulation of
planar_reference (eqs. 8.52-8.70) on random links with random (curved, offset) RFE
geometry, random states, every end condition: mass matrix, kinetic energy, forward
dynamics with base and end-B reactions, inverse-dynamics residual, and the banded Newton
(KKT) correction."""
from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import planar_reference as ref
from rfesim.formulations import planar as pl
from rfesim.formulations import planar_kernels as pk
from rfesim.formulations.planar import BaseMotion, PlanarModel

ROUNDOFF = 1e-11
ENDS = list(itertools.product([pk.FREE, pk.PINNED, pk.CLAMPED], repeat=2))


def random_link(rng, nr, end_a=pk.FREE, end_b=pk.FREE):
    """A link of nr RFEs whose joints are off the RFE axes (b != 0), so every alpha, phi_ij of
    eqs. 8.53/8.57 is non-zero, with random SDEs (curved rest shape) and point loads."""
    start = np.column_stack([-rng.uniform(0.2, 1.0, nr), rng.normal(scale=0.2, size=nr)])
    end = np.column_stack([rng.uniform(0.2, 1.0, nr), rng.normal(scale=0.2, size=nr)])
    nl = 3
    return PlanarModel(
        mass=rng.uniform(0.5, 2.0, nr), inertia=rng.uniform(0.05, 0.3, nr), joint_start=start, joint_end=end,
        sde_stiffness=rng.uniform(1.0, 10.0, nr - 1), sde_damping=rng.uniform(0.0, 1.0, nr - 1),
        sde_rest_angle=rng.normal(scale=0.2, size=nr - 1), gravity=9.81, end_a=end_a, end_b=end_b,
        end_b_position=rng.normal(size=2), end_b_angle=0.3, load_rfe=rng.integers(0, nr, nl),
        load_offset=rng.normal(size=(nl, 2)), load_force=rng.normal(size=(nl, 2)), load_moment=rng.normal(size=nl),
        q_initial=np.zeros(nr + 2))


def random_state(rng, model):
    m = model.ncoord
    return rng.normal(size=m), rng.normal(size=m)


@pytest.mark.parametrize("seed", range(4))
def test_mass_matrix_and_kinetic_energy(seed):
    rng = np.random.default_rng(seed)
    model = random_link(rng, 7)
    q, qd = random_state(rng, model)
    A_ref = ref.mass_matrix(model, q)
    A = pl.mass_matrix(model, q)
    assert np.abs(A - A_ref).max() <= ROUNDOFF * np.abs(A_ref).max()
    assert np.abs(A - A.T).max() <= 1e-14 * np.abs(A).max()
    assert np.linalg.eigvalsh(A).min() > 0.0                       # positive definite
    kinetic = ref.kinetic_energy(model, q, qd)                      # eqs. 8.54-8.55
    assert abs(0.5 * qd @ A_ref @ qd - kinetic) <= ROUNDOFF * kinetic   # eq. 8.57
    assert abs(pl.kinetic_energy(model, q, qd) - kinetic) <= ROUNDOFF * kinetic


@pytest.mark.parametrize("seed", range(3))
def test_velocity_terms_are_the_lagrange_terms(seed):
    """B_bar qd of eq. 8.59 equals dA/dt qd - dT/dq (central differences of the reference)."""
    rng = np.random.default_rng(seed)
    model = random_link(rng, 5)
    q, qd = random_state(rng, model)
    eps = 1e-6
    dA_dt = (ref.mass_matrix(model, q + eps * qd) - ref.mass_matrix(model, q - eps * qd)) / (2 * eps)
    dT_dq = np.array([(ref.kinetic_energy(model, q + eps * e, qd) - ref.kinetic_energy(model, q - eps * e, qd)) / (2 * eps)
                      for e in np.eye(q.size)])
    expected = dA_dt @ qd - dT_dq
    got = ref.velocity_matrix(model, q, qd) @ qd
    assert np.abs(got - expected).max() <= 1e-7 * np.abs(expected).max()


@pytest.mark.parametrize("end_a,end_b", ENDS)
def test_forward_dynamics_matches_reference(end_a, end_b):
    rng = np.random.default_rng(10 + 3 * end_a + end_b)
    model = random_link(rng, 6, end_a, end_b)
    q, qd = random_state(rng, model)
    base_acc = rng.normal(size=3)
    qdd_ref, base_ref, end_ref = ref.accelerations(model, q, qd, base_acc)
    work = pl.PlanarWork(model)
    qdd = np.zeros(model.ncoord)
    pk.accelerations(q, qd, base_acc, model.mass, model.inertia, model.z_in, model.z_out, model.sde_stiffness,
                     model.sde_damping, model.sde_rest_angle, model.gravity, model.end_a, model.end_b,
                     model.load_rfe, model.load_offset, model.load_force, model.load_moment, 1.0, qdd,
                     work.reaction, *work.schur())
    scale = np.abs(qdd_ref).max()
    assert np.abs(qdd - qdd_ref).max() <= ROUNDOFF * scale
    fscale = max(np.abs(base_ref).max(), np.abs(end_ref).max(), 1.0)
    assert np.abs(work.reaction[0] - base_ref).max() <= ROUNDOFF * fscale        # eq. 8.70
    assert np.abs(work.reaction[-1] - end_ref).max() <= ROUNDOFF * fscale        # eq. 8.67
    # inverse dynamics (eq. 8.66/8.68): zero on free coordinates, the base reaction on the others
    r = pl.residual(model, q, qd, qdd_ref, end_ref, work)
    free = model.free_mask()
    assert np.abs(r[free]).max() <= ROUNDOFF * fscale * 10
    assert np.abs(r[:3][~free[:3]] - base_ref[~free[:3]]).max(initial=0.0) <= ROUNDOFF * fscale * 10
    # prescribed base accelerations are reproduced
    assert np.abs(qdd[:3][~free[:3]] - base_acc[~free[:3]]).max(initial=0.0) <= ROUNDOFF * scale


@pytest.mark.parametrize("seed", range(3))
def test_residual_matches_reference_equations_of_motion(seed):
    rng = np.random.default_rng(20 + seed)
    model = random_link(rng, 8)
    q, qd = random_state(rng, model)
    qdd = rng.normal(size=model.ncoord)
    expected = ref.mass_matrix(model, q) @ qdd - ref.right_hand_side(model, q, qd)   # eq. 8.66
    got = pl.residual(model, q, qd, qdd)
    assert np.abs(got - expected).max() <= ROUNDOFF * np.abs(expected).max()


@pytest.mark.parametrize("end_a", [pk.FREE, pk.PINNED, pk.CLAMPED])
def test_banded_newton_correction_solves_the_dense_system(end_a):
    """The KKT correction dq solves (c_m A + c_d D + c_k K) dq = -r on the free coordinates,
    K = central-difference Jacobian of the static residual (zero on prescribed dq)."""
    rng = np.random.default_rng(30 + end_a)
    model = random_link(rng, 6, end_a, pk.FREE)
    q, qd = random_state(rng, model)
    qdd = rng.normal(size=model.ncoord)
    zero = np.zeros_like(q)
    work = pl.PlanarWork(model)
    pk.body_kinematics(q, qd, zero, model.z_in, model.z_out, work.rot, work.pc, work.vc, work.ac)
    r = pl.residual(model, q, qd, qdd)
    c_m, c_d, c_k = 1.0, 0.3, 0.05
    dq, _ = pl._newton_correction(model, work, q, qd, r, np.zeros(3), c_m, c_d, c_k, 1.0)
    eps = 1e-6
    K = np.column_stack([(pl.residual(model, q + eps * e, zero, zero) - pl.residual(model, q - eps * e, zero, zero))
                         / (2 * eps) for e in np.eye(q.size)])
    _, D, _ = ref.stiffness_and_damping(model)
    S = c_m * ref.mass_matrix(model, q) + c_d * D + c_k * K
    free = model.free_mask()
    assert np.all(dq[~free] == 0.0)
    lhs = (S @ dq)[free]
    assert np.abs(lhs + r[free]).max() <= 1e-7 * np.abs(r).max()


def test_spin_up_profile_derivatives():
    prof = pl.smooth_spin_up(6.0, 15.0)
    motion = BaseMotion(phi=lambda t: prof(t)[0])          # plain function: derivatives by differences
    for t in (0.5, 7.0, 14.9, 18.0):
        pos, vel, acc = motion.evaluate(t)
        exact = prof(t)
        assert pos[2] == pytest.approx(exact[0], abs=1e-12)
        assert vel[2] == pytest.approx(exact[1], abs=1e-8)
        assert acc[2] == pytest.approx(exact[2], abs=1e-5)
    assert prof(15.0)[1] == pytest.approx(6.0) and prof(15.0)[2] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("kwargs,field", [
    ({"axial_stiffness": 1e9}, "axial_stiffness"),
    ({"shear_stiffness": 1e9}, "shear_stiffness"),
    ({"end_a": "welded"}, "end_a"),
    ({"end_b": "hinged"}, "end_b"),
    ({"elements": -1}, "elements"),
    ({"length": 0.0}, "length"),
    ({"point_loads": [(2.0, 1.0, 0.0, 0.0)]}, "point_loads"),
])
def test_builder_errors_name_the_field(kwargs, field):
    args = dict(length=1.0, bending_stiffness=1.0, mass_per_length=1.0, elements=4)
    args.update(kwargs)
    with pytest.raises(ValueError, match=field):
        pl.planar_beam(**args)


def test_beam_discretisation():
    model = pl.planar_beam(2.0, 3.0, 1.5, 4, angle=0.3)
    d = 0.5
    assert model.mass.sum() == pytest.approx(3.0)
    assert np.allclose(model.mass, 1.5 * np.array([d / 2, d, d, d, d / 2]))
    assert np.allclose(model.sde_stiffness, 3.0 / d)
    assert np.allclose(pl.tip_position(model, model.q_initial), 2.0 * np.array([math.cos(0.3), math.sin(0.3)]))
    joints = pl.joint_positions(model, model.q_initial)
    assert np.allclose(np.hypot(*joints[1:-1].T), [0.25, 0.75, 1.25, 1.75])   # SDEs at segment middles
