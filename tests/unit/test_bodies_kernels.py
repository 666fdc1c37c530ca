"""Rigid bodies and ropes: the kernels against readable numpy references, and the schema's errors.

* rfesim.loads.bodies.body_hydro_forces against ``body_hydro_reference`` below, written
  from the formulas of the module text, on random poses, velocities and sea kinematics,
  with and without box dimensions (the box's submerged part from a Delaunay tetrahedralisation
  of its clipped corners, not the kernel's face clipping);
* a tilted half-submerged box: buoyancy and moment against the hand-computed wedge (the
  metacentric formula BM - BG), restoring for a flat box and capsizing for a tall one;
* rfesim.loads.tension_only: after the correction, forces equal those of the SDE kernel
  with the axial stiffness and damping removed on the SDEs whose axial force was
  compressive (the force is linear in the section forces), and the elastic forces of a
  slack pair are minus the gradient of the potential without its axial term; a pair pushed
  past its axial contact gets minus the gradient of the contact energy too (ramp and linear
  parts), the axial tangent is the derivative of its force, and its damping is scaled as
  its stiffness;
* bad body input raises ScenarioError naming the field.
"""
from __future__ import annotations

import copy
import itertools
import math

import numpy as np
import pytest

import rfesim
import reference_impl as ref
from rfesim import ScenarioError
from rfesim.loads.bodies import body_hydro_forces
from rfesim.loads.sde import sde_forces
from rfesim.loads.tension_only import tension_only_correction

RHO, G = 1025.0, 9.81


# ----------------------------------------------------------------------------- body hydrodynamics

def box_below(half, n, d):
    """(fraction, centroid) of the box |x_k| <= half_k below the plane n . x = d: the convex
    hull of the corners below and the edges' crossings, cut into tetrahedra by Delaunay."""
    from scipy.spatial import Delaunay
    corners = [np.array(c) * half for c in itertools.product((-1.0, 1.0), repeat=3)]
    pts = [c for c in corners if n @ c <= d]
    for a, b in itertools.combinations(corners, 2):
        if np.count_nonzero(a != b) == 1 and (n @ a <= d) != (n @ b <= d):
            pts.append(a + (n @ a - d) / (n @ a - n @ b) * (b - a))
    if len(pts) < 4:
        return 0.0, np.zeros(3)
    pts = np.array(pts)
    vol, moment = 0.0, np.zeros(3)
    for simplex in Delaunay(pts).simplices:
        q = pts[simplex]
        tv = abs(np.linalg.det(q[1:] - q[0])) / 6.0
        vol += tv
        moment += tv * q.mean(axis=0)
    return vol / (8.0 * np.prod(half)), moment / vol


def body_hydro_reference(R, r, v, w, surface_z, water_vel, water_acc, volume, height, cob, cd_area, added_mass,
                         added_inertia, slam, scale, box=(0.0, 0.0, 0.0)):
    """Force, moment (about the centre), Ma, Ja, fraction and point of application of one
    body (module text); ``box`` half-sizes > 0: the box's submerged part at its centroid."""
    d = R @ cob
    if box[0] > 0.0:
        f, xs = box_below(np.asarray(box), R[2], surface_z - (r[2] + d[2]))
        d = d + R @ xs
        P = r + d
    else:
        P = r + d
        f = float(np.clip((surface_z - (P[2] - 0.5 * height)) / height, 0.0, 1.0))
    Ma = f * R @ np.diag(added_mass) @ R.T
    Ja = f * np.asarray(added_inertia)
    force = np.zeros(3)
    if f > 0.0:
        u = water_vel - (v + np.cross(w, d))
        ub = R.T @ u
        force += scale * RHO * G * volume * f * np.array([0.0, 0.0, 1.0])
        force += R @ (0.5 * RHO * np.asarray(cd_area) * np.abs(ub) * ub * f)
        force += RHO * volume * f * water_acc + Ma @ water_acc
        if f < 1.0 and u[2] > 0.0:
            force[2] += 0.5 * RHO * slam * u[2] ** 2
    return force, np.cross(d, force), Ma, Ja, f, P


def random_bodies(rng, nb, n):
    rfe = rng.choice(n, size=nb, replace=False).astype(np.int64)
    R = np.array([ref.random_rotation(rng) for _ in range(n)])
    r = rng.uniform(-3.0, 3.0, size=(n, 3))
    b = dict(body_rfe=rfe, body_volume=rng.uniform(0.5, 5.0, nb), body_height=rng.uniform(0.5, 3.0, nb),
             body_cob=rng.normal(scale=0.5, size=(nb, 3)), body_drag=rng.uniform(0.0, 5.0, (nb, 3)),
             body_added_mass=rng.uniform(0.0, 5e3, (nb, 3)), body_added_inertia=rng.uniform(0.0, 1e3, (nb, 3)),
             body_slam=rng.uniform(0.0, 10.0, nb), R=R, r=r, v=rng.normal(size=(n, 3)), w=rng.normal(size=(n, 3)),
             surface_z=rng.uniform(-1.0, 1.0, n), water_vel=rng.normal(size=(n, 3)),
             water_acc=rng.normal(size=(n, 3)))
    # every other body a box (half-sizes), its centre of buoyancy near the surface: cut by it
    box = rng.uniform(0.3, 1.5, (nb, 3))
    box[::2] = 0.0
    for j in range(1, nb, 2):
        i = rfe[j]
        r[i, 2] = b["surface_z"][i] - (R[i] @ b["body_cob"][j])[2] + rng.uniform(-0.5, 0.5)
    b["body_box"] = box
    return b


@pytest.mark.parametrize("seed", range(6))
def test_body_hydro_kernel_matches_reference(seed):
    rng = np.random.default_rng(seed)
    n, nb = 7, 4
    b = random_bodies(rng, nb, n)
    F0 = rng.normal(size=(n, 3))
    M0 = rng.normal(size=(n, 3))
    F, M = F0.copy(), M0.copy()
    Ma, Ja = np.full((n, 3, 3), 7.0), np.full((n, 3), 7.0)
    sub_frac, sub_point = np.full(n, -1.0), np.zeros((n, 3))
    scale = 0.7
    body_hydro_forces(b["body_rfe"], b["body_volume"], b["body_height"], b["body_box"], b["body_cob"],
                      b["body_drag"], b["body_added_mass"], b["body_added_inertia"], b["body_slam"], RHO, G, scale,
                      b["R"], b["r"], b["v"], b["w"], b["surface_z"], b["water_vel"], b["water_acc"], F, M, Ma, Ja,
                      sub_frac, sub_point)
    fractions = []
    for j, i in enumerate(b["body_rfe"]):
        force, moment, ma, ja, f, P = body_hydro_reference(
            b["R"][i], b["r"][i], b["v"][i], b["w"][i], b["surface_z"][i], b["water_vel"][i], b["water_acc"][i],
            b["body_volume"][j], b["body_height"][j], b["body_cob"][j], b["body_drag"][j], b["body_added_mass"][j],
            b["body_added_inertia"][j], b["body_slam"][j], scale, b["body_box"][j])
        fractions.append(f)
        size = np.abs(force).max() + 1.0
        # a box's part under water: two different exact constructions, round-off apart
        tol = 1e-12 if b["body_box"][j, 0] == 0.0 else 1e-10
        np.testing.assert_allclose(F[i] - F0[i], force, rtol=0, atol=tol * size)
        np.testing.assert_allclose(M[i] - M0[i], moment, rtol=0, atol=tol * size * 10)
        np.testing.assert_allclose(Ma[i], ma, rtol=0, atol=tol * 5e3)
        np.testing.assert_allclose(Ja[i], ja, rtol=0, atol=tol * 1e3)
        assert sub_frac[i] == pytest.approx(f, abs=1e-15 if tol == 1e-12 else 1e-11)
        np.testing.assert_allclose(sub_point[i], P, rtol=0, atol=1e-14 * 10 if tol == 1e-12 else 1e-10)
        if b["body_box"][j, 0] > 0.0:
            assert 0.0 < f < 1.0                                   # the box is cut by the surface
    others = np.setdiff1d(np.arange(n), b["body_rfe"])
    np.testing.assert_array_equal(F[others], F0[others])           # other RFEs untouched
    assert np.all(sub_frac[others] == -1.0)


def test_body_submergence_fraction_and_slamming_limits():
    """Buoyancy rho g V f with f linear over the height; slamming only entering, only while crossing."""
    R = np.eye(3)[None]
    base = dict(body_rfe=np.array([0]), body_volume=np.array([2.0]), body_height=np.array([2.0]),
                body_box=np.zeros((1, 3)), body_cob=np.zeros((1, 3)), body_drag=np.zeros((1, 3)),
                body_added_mass=np.zeros((1, 3)), body_added_inertia=np.zeros((1, 3)),
                body_slam=np.array([math.pi * 3.0]))

    def fz(z, vz):
        F, M = np.zeros((1, 3)), np.zeros((1, 3))
        body_hydro_forces(*base.values(), RHO, G, 1.0, R, np.array([[0.0, 0.0, z]]), np.array([[0.0, 0.0, vz]]),
                          np.zeros((1, 3)), np.zeros(1), np.zeros((1, 3)), np.zeros((1, 3)), F, M, np.zeros((1, 3, 3)),
                          np.zeros((1, 3)), np.zeros(1), np.zeros((1, 3)))
        return F[0, 2]

    for z, frac in ((1.5, 0.0), (1.0, 0.0), (0.5, 0.25), (0.0, 0.5), (-0.5, 0.75), (-1.0, 1.0), (-3.0, 1.0)):
        assert fz(z, 0.0) == pytest.approx(RHO * G * 2.0 * frac, rel=1e-14, abs=1e-9)
    slam = 0.5 * RHO * math.pi * 3.0 * 2.0 ** 2
    assert fz(0.0, -2.0) - fz(0.0, 0.0) == pytest.approx(slam, rel=1e-14)      # entering: slams
    assert fz(0.0, 2.0) == pytest.approx(fz(0.0, 0.0), rel=1e-14)              # leaving: no slam
    assert fz(-1.5, -2.0) == pytest.approx(fz(-1.5, 0.0), rel=1e-14)           # submerged: no slam
    assert fz(2.0, -2.0) == 0.0                                                # in air: nothing


def still_box(half, R, z, volume, cob=(0.0, 0.0, 0.0), height=None):
    """Force, moment about the centre of mass, fraction and point of application of one body
    at rest in still water (surface z = 0), its centre of mass at height z: with box
    half-sizes ``half``, or without (``half`` zeros, vertical extent ``height``)."""
    F, M = np.zeros((1, 3)), np.zeros((1, 3))
    frac, point = np.zeros(1), np.zeros((1, 3))
    body_hydro_forces(np.array([0]), np.array([volume]), np.array([height or 2.0 * half[2]]),
                      np.array([half], float), np.array([cob], float), np.zeros((1, 3)), np.zeros((1, 3)),
                      np.zeros((1, 3)), np.zeros(1), RHO, G, 1.0, np.asarray(R, float)[None],
                      np.array([[0.0, 0.0, z]]), np.zeros((1, 3)), np.zeros((1, 3)), np.zeros(1), np.zeros((1, 3)),
                      np.zeros((1, 3)), F, M, np.zeros((1, 3, 3)), np.zeros((1, 3)), frac, point)
    return F[0], M[0], frac[0], point[0]


def pitch(theta):
    """Rotation by theta about the global y axis (body z tilts toward +x)."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


@pytest.mark.parametrize("half, theta_deg, cob_z, restoring", [
    ((2.0, 1.0, 0.5), 10.0, 0.0, True),        # flat box: BM = a^2/(3c) = 2.67 m > BG = c/2 = 0.25 m
    ((2.0, 1.0, 0.5), 10.0, 0.3, True),        # centre of buoyancy 0.3 m above the centre of mass
    ((0.3, 0.5, 1.0), 5.0, 0.0, False),        # tall box: BM = 0.03 m < BG = 0.5 m, it capsizes
])
def test_tilted_half_submerged_box_buoyancy_and_moment(half, theta_deg, cob_z, restoring):
    """A box (half-sizes a, b, c) pitched by theta, its centre on the surface: the plane
    z' = x' tan(theta) through the centre leaves the lower half under water (volume fraction
    1/2 by symmetry, buoyancy rho g V / 2) with its centroid at x' = a^2 t / (3c),
    z' = a^2 t^2 / (6c) - c/2 (t = tan theta, body axes; the wedge integrals over
    -c <= z' <= x' t). The moment about the centre of mass is -X rho g V / 2 about y, X the
    global horizontal arm of that centroid (plus the centre of buoyancy's offset): negative
    (restoring) when BM = a^2 / (3c) exceeds BG = c/2 - cob."""
    a, b, c = half
    th = math.radians(theta_deg)
    t = math.tan(th)
    assert a * t < c                        # the plane cuts the two x faces (the wedge formula)
    R = pitch(th)
    volume = 0.75 * 8.0 * a * b * c         # an open box: 3/4 of its envelope displaces water
    cob = np.array([0.0, 0.0, cob_z])
    z = -(R @ cob)[2]                       # the box centre (centre of buoyancy) on the surface
    F, M, f, point = still_box(half, R, z, volume, cob)
    B = RHO * G * volume / 2.0
    xs = np.array([a * a * t / (3.0 * c), 0.0, a * a * t * t / (6.0 * c) - c / 2.0])
    arm = R @ (cob + xs)
    assert f == pytest.approx(0.5, abs=1e-14)
    np.testing.assert_allclose(F, [0.0, 0.0, B], rtol=0, atol=1e-12 * B)
    np.testing.assert_allclose(M, [0.0, -arm[0] * B, 0.0], rtol=0, atol=1e-12 * B)
    np.testing.assert_allclose(point, [0.0, 0.0, z] + arm, rtol=0, atol=1e-14)
    # the metacentric form of the same moment, to first order in theta
    gm = a * a / (3.0 * c) - (c / 2.0 - cob_z)
    assert M[1] == pytest.approx(-B * gm * th, rel=0.02)
    assert (M[1] < 0.0) == restoring


def test_upright_box_is_the_height_model():
    """Upright, a box with height c gives the height model's buoyancy (fraction linear over
    c) and no moment; fully submerged it acts at the centre of buoyancy exactly; tilted and
    clear of the surface it is the same as upright (the attitude matters only in the
    splash zone)."""
    half, volume = (2.0, 1.0, 0.5), 6.0
    for z, frac in ((0.6, 0.0), (0.25, 0.25), (0.0, 0.5), (-0.4, 0.9), (-0.5, 1.0), (-2.0, 1.0)):
        F, M, f, point = still_box(half, np.eye(3), z, volume)
        F0, M0, f0, point0 = still_box((0.0, 0.0, 0.0), np.eye(3), z, volume, height=1.0)
        assert f == pytest.approx(frac, abs=1e-14) and f0 == pytest.approx(frac, abs=1e-15)
        np.testing.assert_allclose(F, F0, rtol=1e-13, atol=1e-9)
        np.testing.assert_allclose(M, 0.0, atol=1e-9)
    cob = (0.2, -0.1, 0.3)
    R = pitch(0.4)
    F, M, f, point = still_box(half, R, -5.0, volume, cob)
    F0, M0, f0, point0 = still_box((0.0, 0.0, 0.0), R, -5.0, volume, cob, height=1.0)
    assert f == 1.0
    np.testing.assert_array_equal(F, F0)
    np.testing.assert_array_equal(M, M0)
    np.testing.assert_array_equal(point, point0)
    # tilted, the box reaches higher than c/2: at z = -0.6 the height model is under, the box is not
    F, M, f, point = still_box(half, R, -0.6, volume)
    assert f < 1.0 and still_box((0.0, 0.0, 0.0), R, -0.6, volume, height=1.0)[2] == 1.0


# ----------------------------------------------------------------------------- tension-only SDEs

def random_pairs(rng, nsde, gap=0.3):
    """A chain of RFEs with axial gaps of both signs (some SDEs stretched, some compressed)."""
    n = nsde + 1
    R = np.empty((n, 3, 3))
    rbase = np.empty((n, 3))
    R[0] = ref.random_rotation(rng)
    rbase[0] = rng.uniform(-5.0, 5.0, 3)
    arm_l = np.tile([0.5, 0.0, 0.0], (nsde, 1))
    arm_r = np.tile([-0.5, 0.0, 0.0], (nsde, 1))
    for s in range(nsde):
        R[s + 1] = R[s] @ ref.exp_so3(ref.random_rotation_vector(rng, 0.2))
        end = rbase[s] + R[s] @ arm_l[s]
        rbase[s + 1] = end - R[s + 1] @ arm_r[s] + gap * rng.uniform(-1.0, 1.0) * R[s][:, 0] \
            + rng.normal(scale=0.02, size=3)
    roff = rng.normal(scale=1e-3, size=(n, 3))
    stiffness = rng.uniform(0.5, 2.0, (nsde, 6)) * np.array([1e5, 3e4, 3e4, 2e3, 5e3, 5e3])
    damping = rng.uniform(0.5, 2.0, (nsde, 6)) * np.array([1e3, 3e2, 3e2, 20.0, 50.0, 50.0])
    return dict(left=np.arange(nsde, dtype=np.int64), right=np.arange(1, n, dtype=np.int64), arm_left=arm_l,
                arm_right=arm_r, stiffness=stiffness, damping=damping, R=R, rbase=rbase, roff=roff,
                v=rng.normal(size=(n, 3)), w=rng.normal(size=(n, 3)))


def kernel(c, stiffness, damping):
    n, nsde = c["R"].shape[0], c["left"].shape[0]
    F, M = np.zeros((n, 3)), np.zeros((n, 3))
    eps, sigma, point = np.zeros((nsde, 6)), np.zeros((nsde, 6)), np.zeros((nsde, 3))
    sde_forces(c["left"], c["right"], c["arm_left"], c["arm_right"], stiffness, damping, c["R"], c["rbase"],
               c["roff"], c["v"], c["w"], F, M, eps, sigma, point)
    return F, M, eps, sigma


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("with_damping", [False, True])
def test_tension_only_equals_sde_without_axial_spring_where_compressed(seed, with_damping):
    rng = np.random.default_rng(seed)
    c = random_pairs(rng, 8)
    nsde = c["left"].shape[0]
    damping = c["damping"] if with_damping else np.zeros((nsde, 6))
    flags = (rng.uniform(size=nsde) < 0.7).astype(np.int64)
    F, M, eps, sigma = kernel(c, c["stiffness"], damping)
    compressed = (sigma[:, 0] < 0.0) & (flags == 1)
    assert compressed.any() and (sigma[:, 0] > 0.0).any()
    k_tangent = np.zeros((nsde, 6))
    tension_only_correction(c["left"], c["right"], c["arm_left"], c["arm_right"], c["stiffness"], flags, c["R"],
                            c["rbase"], c["roff"], sigma, F, M, k_tangent, True, np.zeros((32, 3)),
                            np.zeros((16, 3, 3)))
    k_ref, d_ref = c["stiffness"].copy(), damping.copy()
    k_ref[compressed, 0] = 0.0
    d_ref[compressed, 0] = 0.0
    F_ref, M_ref, _, sigma_ref = kernel(c, k_ref, d_ref)
    size = np.abs(F_ref).max()
    np.testing.assert_allclose(F, F_ref, rtol=0, atol=1e-10 * size)
    np.testing.assert_allclose(M, M_ref, rtol=0, atol=1e-10 * size)
    np.testing.assert_allclose(sigma, sigma_ref, rtol=0, atol=1e-10 * size)
    assert np.all(sigma[flags == 1, 0] >= 0.0)
    np.testing.assert_array_equal(k_tangent, k_ref)       # the Jacobian sees no axial stiffness when slack


def test_slack_pair_forces_are_minus_the_gradient_without_axial_energy():
    """A compressed tension-only pair: V = 1/2 eps^T C eps without the axial term."""
    rng = np.random.default_rng(11)
    for _ in range(20):
        c = random_pairs(rng, 1, gap=0.3)
        F, M, eps, sigma = kernel(c, c["stiffness"], np.zeros((1, 6)))
        if sigma[0, 0] < -1.0:
            break
    k_tangent = np.zeros((1, 6))
    tension_only_correction(c["left"], c["right"], c["arm_left"], c["arm_right"], c["stiffness"],
                            np.ones(1, np.int64), c["R"], c["rbase"], c["roff"], sigma, F, M, k_tangent, True,
                            np.zeros((32, 3)), np.zeros((16, 3, 3)))
    pair = dict(position_a=c["rbase"][0] + c["roff"][0], rotation_a=c["R"][0], arm_a=c["arm_left"][0],
                position_b=c["rbase"][1] + c["roff"][1], rotation_b=c["R"][1], arm_b=c["arm_right"][0],
                velocity_a=c["v"][0], angular_velocity_a=c["w"][0], velocity_b=c["v"][1],
                angular_velocity_b=c["w"][1])
    stiffness = c["stiffness"][0].copy()
    stiffness[0] = 0.0
    Fa, Ma, Fb, Mb = ref.sde_elastic_forces_by_gradient(pair, stiffness)
    size = np.abs(F).max()
    np.testing.assert_allclose(F[0], Fa, rtol=0, atol=1e-5 * size)
    np.testing.assert_allclose(F[1], Fb, rtol=0, atol=1e-5 * size)
    np.testing.assert_allclose(M[0], Ma, rtol=0, atol=1e-5 * size)
    np.testing.assert_allclose(M[1], Mb, rtol=0, atol=1e-5 * size)


def contact_pair(rng, gap):
    """One rope SDE (arms 0.5 m each: reach 1 m, contact from a gap of -0.5 m) with the
    axial gap ``gap`` along the left element's axis and a small random offset and bend."""
    c = random_pairs(rng, 1, gap=0.0)
    c["rbase"][1] += gap * c["R"][0][:, 0]
    return c


def corrected(c, damping):
    F, M, eps, sigma = kernel(c, c["stiffness"], damping)
    k_tangent = np.zeros((1, 6))
    tension_only_correction(c["left"], c["right"], c["arm_left"], c["arm_right"], c["stiffness"],
                            np.ones(1, np.int64), c["R"], c["rbase"], c["roff"], sigma, F, M, k_tangent, True,
                            np.zeros((32, 3)), np.zeros((16, 3, 3)))
    return F, M, eps, sigma, k_tangent


@pytest.mark.parametrize("gap, part", [(-0.45, "slack"), (-0.53, "ramp"), (-0.56, "ramp"), (-0.75, "linear")])
def test_rope_contact_forces_are_minus_the_gradient_of_its_energy(gap, part):
    """Past its axial contact a rope pair pushes back: forces and moments are minus the
    gradient of the bending and shear energy plus the contact energy of the axial gap
    (reference_impl.rope_contact_potential, finite differences in positions and rotations)."""
    rng = np.random.default_rng(5)
    c = contact_pair(rng, gap)
    F, M, eps, sigma, k_tangent = corrected(c, np.zeros((1, 6)))
    depth = -0.5 - eps[0, 0]
    assert {"slack": depth < 0.0, "ramp": 0.0 < depth < 0.1, "linear": depth > 0.1}[part]
    C = c["stiffness"][0, 0]
    pair = dict(position_a=c["rbase"][0] + c["roff"][0], rotation_a=c["R"][0], arm_a=c["arm_left"][0],
                position_b=c["rbase"][1] + c["roff"][1], rotation_b=c["R"][1], arm_b=c["arm_right"][0])
    stiffness = c["stiffness"][0].copy()
    stiffness[0] = 0.0
    Fa, Ma, Fb, Mb = ref.sde_elastic_forces_by_gradient(pair, stiffness, axial_contact=(C, 1.0))
    size = np.abs(F).max()
    np.testing.assert_allclose(F[0], Fa, rtol=0, atol=1e-5 * size)
    np.testing.assert_allclose(F[1], Fb, rtol=0, atol=1e-5 * size)
    np.testing.assert_allclose(M[0], Ma, rtol=0, atol=1e-5 * size)
    np.testing.assert_allclose(M[1], Mb, rtol=0, atol=1e-5 * size)
    if part == "slack":
        assert sigma[0, 0] == 0.0 and k_tangent[0, 0] == 0.0
    else:
        assert sigma[0, 0] < 0.0
        # the axial tangent is the derivative of the axial force in the gap
        h = 1e-7
        moved = contact_pair(np.random.default_rng(5), gap - h)
        slope = (corrected(moved, np.zeros((1, 6)))[3][0, 0] - sigma[0, 0]) / \
            (corrected(moved, np.zeros((1, 6)))[2][0, 0] - eps[0, 0])
        assert k_tangent[0, 0] == pytest.approx(slope, rel=1e-4)
        assert k_tangent[0, 0] == pytest.approx(C * min(depth / 0.1, 1.0), rel=1e-12)


def test_rope_axial_energy_against_its_reference():
    """rfesim.loads.tension_only.rope_axial_energy (the energy check's axial term of a rope)
    is 1/2 C eps^2 stretched, 0 slack and the reference contact energy past the closing."""
    from rfesim.loads.tension_only import rope_axial_energy
    rng = np.random.default_rng(3)
    C = rng.uniform(1e4, 1e8, 400)
    reach = rng.uniform(0.2, 4.0, 400)
    gap = reach * rng.uniform(-0.9, 0.2, 400)
    got = rope_axial_energy(C, gap, reach)
    want = [0.5 * c * e * e if e > 0.0 else ref.rope_contact_potential(c, r, e) for c, e, r in zip(C, gap, reach)]
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=0.0)
    assert (got[(gap < 0.0) & (gap > -0.5 * reach)] == 0.0).all() and (got[gap < -0.6 * reach] > 0.0).all()


@pytest.mark.parametrize("gap", [-0.55, -0.75])
def test_rope_contact_damping_is_scaled_as_its_stiffness(gap):
    """With damping the contact force is the elastic contact force plus the Kelvin-Voigt
    axial damping times k_contact / C_x, and never a pull: a pair closing keeps it, a pair
    opening fast enough carries nothing."""
    rng = np.random.default_rng(7)
    c = contact_pair(rng, gap)
    damping = c["damping"]
    _, _, eps, sigma0, k_tangent = corrected(c, np.zeros((1, 6)))
    _, _, _, elastic = kernel(c, c["stiffness"], np.zeros((1, 6)))
    scale = k_tangent[0, 0] / c["stiffness"][0, 0]
    assert 0.0 < scale <= 1.0
    for sign in (1.0, -1.0):                                          # opening, closing
        c["v"][1] = c["v"][0] + sign * 5.0 * c["R"][0][:, 0]
        _, _, _, with_rate = kernel(c, c["stiffness"], damping)
        rate_force = with_rate[0, 0] - elastic[0, 0]                  # D_x d(eps_x)/dt
        assert np.sign(rate_force) == sign
        sigma = corrected(c, damping)[3][0, 0]
        assert sigma == pytest.approx(min(0.0, sigma0[0, 0] + scale * rate_force), rel=1e-9, abs=1e-9)
        assert (sigma == 0.0) == (sign > 0.0 and sigma0[0, 0] + scale * rate_force > 0.0)


# ----------------------------------------------------------------------------- schema errors

BASE = {
    "environment": {"gravity": 9.81, "water": {"density": 1025.0, "depth": 100.0}},
    "line_types": {"rope": {"EA": 1e8, "EIy": 1.0, "mass_per_length": 1.0, "tension_only": True}},
    "bodies": {"payload": {"mass": 1e4, "inertia": [1e4, 1e4, 1e4], "volume": 2.0, "height": 2.0}},
    "lines": {"hoist": {"type": "rope", "length": 20.0, "elements": 4,
                        "end_a": {"attach": "fixed", "position": [0, 0, 10]},
                        "end_b": {"attach": "payload", "position": [0, 0, 1.0]}}},
    "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}},
}


def errors_of(mutate):
    data = copy.deepcopy(BASE)
    mutate(data)
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate(data)
    return dict(info.value.errors)


def test_base_scenario_is_valid():
    sc = rfesim.Scenario.model_validate(copy.deepcopy(BASE))
    assert sc.bodies["payload"].principal_inertia() == [1e4, 1e4, 1e4]
    assert sc.line_types["rope"].tension_only is True


@pytest.mark.parametrize("mutate, field, words", [
    (lambda d: d["bodies"]["payload"].update(mass=-5.0), "bodies.payload.mass", "greater than or equal to 0.001 kg"),
    (lambda d: d["bodies"]["payload"].update(inertia=[1.0, 1.0, 3.0]), "bodies.payload.inertia", "sum of the other"),
    (lambda d: d["bodies"]["payload"].update(inertia=None), "bodies.payload.inertia", "radius_of_gyration"),
    (lambda d: d["bodies"]["payload"].update(radius_of_gyration=1.0), "bodies.payload.radius_of_gyration",
     "not both"),
    (lambda d: d["bodies"]["payload"].update(volume=-1.0), "bodies.payload.volume", "greater than or equal"),
    (lambda d: d["bodies"]["payload"].update(drag={"cd": [1, -1, 1], "area": 2.0}), "bodies.payload.drag.cd.1",
     "negative"),
    (lambda d: d["bodies"]["payload"].update(added_mass={"ca": 1.0, "mass": 100.0}),
     "bodies.payload.added_mass.mass", "not both"),
    (lambda d: d["bodies"]["payload"].update(colour="red"), "bodies.payload.colour", ""),
    (lambda d: d["lines"]["hoist"]["end_b"].update(attach="crate"), "lines.hoist.end_b.attach", "crate"),
    (lambda d: (d["lines"]["hoist"].update(end_a={"attach": "payload", "position": [0, 0, 0]},
                                           end_b={"attach": "fixed", "position": [0, 0, 10]})),
     "lines.hoist.end_a.attach", "end_b"),
    (lambda d: d["lines"].update(second=copy.deepcopy(d["lines"]["hoist"])), "lines.second.end_b.attach",
     "one line per body"),
    (lambda d: d["bodies"].update(buoy={"mass": 10.0, "radius_of_gyration": 0.2}), "bodies.buoy",
     "not attached"),
    (lambda d: d["bodies"]["payload"].update(dimensions=[2.0, -1.0, 2.0]), "bodies.payload.dimensions.1",
     "greater than 0 m"),
    (lambda d: d["bodies"]["payload"].update(dimensions=[1.0, 1.0, 1.5]), "bodies.payload.height",
     "differs from the box's height dimensions.2 = 1.5 m"),
    (lambda d: d["bodies"]["payload"].update(dimensions=[1.0, 0.5, 2.0], volume=1.2), "bodies.payload.volume",
     "more than the box"),
])
def test_bad_bodies_name_the_field(mutate, field, words):
    errors = errors_of(mutate)
    assert field in errors, errors
    assert words in errors[field]


def test_box_dimensions_reach_the_model():
    """``dimensions`` [a, b, c]: the kernel's half-sizes, the height c, the deck footprint
    [a, b]; without them the body has no box (zeros: the height model)."""
    from rfesim.model.compile import compile_scenario
    data = copy.deepcopy(BASE)
    body = data["bodies"]["payload"]
    del body["height"]
    body.update(dimensions=[3.0, 2.0, 1.5], volume=8.0)
    sc = rfesim.Scenario.model_validate(data)
    assert sc.bodies["payload"].vertical_extent() == 1.5
    assert sc.bodies["payload"].deck_footprint() == [3.0, 2.0]
    np.testing.assert_array_equal(compile_scenario(sc).km.body_box, [[1.5, 1.0, 0.75]])
    np.testing.assert_array_equal(compile_scenario(rfesim.Scenario.model_validate(copy.deepcopy(BASE))).km.body_box,
                                  [[0.0, 0.0, 0.0]])


# ----------------------------------------------------------------------------- Jacobian with a body and a slack rope

def test_analytic_jacobian_with_body_and_slack_rope():
    """The analytic Jacobian of an implicit step (rope with a slack SDE, connection SDE, body
    hydrodynamics) against central differences, as in tests/unit/test_jacobian.py. The rows
    of the rope's torsion (GJ ~ 1 N*m^2: rows below 1e-4 of the largest) are left out of the
    entry-wise check: the tangent's small-rotation terms of the connection (its two frames
    are 90 deg apart) put O(T * 1e-4) into them; the Newton step is checked whole. (Statics
    uses the central-difference Jacobian.)"""
    mode = 1
    from rfesim.model.compile import compile_scenario
    from rfesim.solvers.banded import bt_to_dense
    from rfesim.solvers.jacobian import jacobian_analytic
    from rfesim.solvers.kernels import jacobian_fd_general
    from rfesim.solvers.statics import solve_statics
    from rfesim.solvers.system import System

    data = copy.deepcopy(BASE)
    data["bodies"]["payload"].update(drag={"cd": 1.0, "area": [3.0, 3.0, 4.0]}, added_mass={"ca": 0.8},
                                     centre_of_buoyancy=[0.1, 0.0, 0.2], inertia=[1e4, 1.2e4, 1.4e4])
    system = System(compile_scenario(rfesim.Scenario.model_validate(data)))
    state, _ = solve_statics(system)
    q = state.q.copy()
    q[3:, 2] += 0.01            # lift the lower rope and the body: SDE 2 goes slack
    rng = np.random.default_rng(3)
    scale = np.where(np.arange(6) < 3, 1e-5 * system.length_scale[:, None], 1e-5)
    q[system.mask] += (rng.normal(size=q.shape) * scale)[system.mask]
    system.set_time(0.0)
    h = 0.02
    cq, cv = h * h * 0.3, h * 0.6
    Q0 = q - cq * rng.normal(size=q.shape)
    V0 = rng.normal(scale=0.1, size=q.shape)
    Q0[~system.mask] = q[~system.mask]
    V0[~system.mask] = 0.0
    args = (system.km, system.att, q, state.ref, system.ws, 1.0, mode, Q0, V0, cq, cv, system.mask,
            system.qd_buf, system.A_buf)
    r0 = np.zeros_like(q)
    jacobian_fd_general(*args, np.zeros_like(q), system.qp, system.rp, system.hs, system.length_scale, system.J,
                        True, 1e-6)
    mask = system.mask.ravel()
    reference = bt_to_dense(system.J.copy())[np.ix_(mask, mask)]
    jacobian_analytic(*args, r0, system.qp, system.rp, system.hs, system.length_scale, system.J, system.Ks,
                      system.Kds, system.T, system.Fsde, system.Msde)
    analytic = bt_to_dense(system.J.copy())[np.ix_(mask, mask)]
    assert system.ws.sigma[2, 0] == 0.0 and system.ws.sigma[0, 0] > 0.0       # one slack, others taut
    rows = np.abs(reference).max(axis=1, keepdims=True)
    err = np.abs(analytic - reference) / rows
    full = np.flatnonzero(mask)
    rope = full // 6 < system.model.bodies[0].rfe
    soft = rope & (full % 6 == 5)                            # torsion (phi about the RFE axis) of the rope
    assert rows.ravel()[soft].max() < 1e-4 * rows.max()
    assert err[~soft].max() < 5e-3, err[~soft].max()
    rhs = r0.ravel()[mask]
    step = np.linalg.solve(analytic, rhs)
    assert np.linalg.norm(reference @ step - rhs) < 1e-2 * np.linalg.norm(rhs)
