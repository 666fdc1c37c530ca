"""Seabed on a slope or a profile and Coulomb friction (spring-slider stick/slip), kernel
against the readable references of reference_impl, and the stick/slip law's behaviour."""
from __future__ import annotations

import numpy as np
import pytest

import reference_impl as ref
from rfesim.loads.seabed import commit_friction, seabed_forces, seabed_height

SEEDS = [1, 2, 3]


def run_kernel(length, radius, damping, bed, k, R, r, v, w, mu=(0.0, 0.0), kt=1.0, anchor=None, anchored=None,
               mode=2, stick_damping=None):
    n = length.shape[0]
    F = np.zeros((n, 3))
    M = np.zeros((n, 3))
    cf = np.zeros(n)
    cl = np.zeros(n)
    anchor = np.zeros((n, 3)) if anchor is None else anchor
    anchored = np.zeros(n, np.int64) if anchored is None else anchored
    at = np.zeros((n, 3))
    adt = np.zeros(n, np.int64)
    ff = np.zeros((n, 3))
    ct = np.zeros(n) if stick_damping is None else stick_damping
    seabed_forces(length, radius, damping, ct, bed[0], bed[1], bed[2], k, np.asarray(mu, float), kt, R, r, v, w, F, M,
                  cf, cl, anchor, anchored, at, adt, np.array([mode], np.int64), ff, np.zeros(3))
    return F, M, cf, cl, at, adt, ff


def random_bed(rng):
    s = np.sort(rng.uniform(-50, 50, size=5))
    z = -100.0 + rng.uniform(-3, 3, size=5)
    ang = rng.uniform(0, 2 * np.pi)
    return s, z, np.array([np.cos(ang), np.sin(ang)])


@pytest.mark.parametrize("seed", SEEDS)
def test_profile_height_matches_interpolation(seed):
    rng = np.random.default_rng(seed)
    s, z, d = random_bed(rng)
    out = np.zeros(3)
    for _ in range(50):
        x, y = rng.uniform(-80, 80, size=2)
        seabed_height(s, z, d, x, y, out)
        zr, nr = ref.seabed_plane_under(s, z, d, x, y)
        assert out[0] == pytest.approx(zr, abs=1e-12)
        n = np.array([-out[1], -out[2], 1.0]) / np.hypot(np.hypot(out[1], out[2]), 1.0)
        np.testing.assert_allclose(n, nr, atol=1e-14)


@pytest.mark.parametrize("seed", SEEDS)
def test_normal_contact_on_a_profile_against_quadrature(seed):
    rng = np.random.default_rng(seed)
    bed = random_bed(rng)
    n = 12
    length = rng.uniform(0.5, 3.0, size=n)
    radius = rng.uniform(0.05, 0.3, size=n)
    damping = rng.uniform(0.0, 1e3, size=n)
    R = np.array([ref.random_rotation(rng) for _ in range(n)])
    r = np.zeros((n, 3))
    for i in range(n):
        x, y = rng.uniform(-40, 40, size=2)
        zb, nrm = ref.seabed_plane_under(bed[0], bed[1], bed[2], x, y)
        # centre placed so the element is partly or fully in contact, or just clear
        r[i] = np.array([x, y, zb]) + nrm * (radius[i] + rng.uniform(-0.6, 0.6) * 0.5 * length[i])
    v = 0.1 * rng.normal(size=(n, 3))
    w = 0.1 * rng.normal(size=(n, 3))
    k = 3e5
    F, M, cf, cl, *_ = run_kernel(length, radius, damping, bed, k, R, r, v, w)
    touched = 0
    for i in range(n):
        zb, nrm = ref.seabed_plane_under(bed[0], bed[1], bed[2], r[i, 0], r[i, 1])
        P0 = np.array([r[i, 0], r[i, 1], zb])
        force, moment, normal, contact = ref.seabed_on_plane_by_quadrature(
            length[i], radius[i], damping[i], P0, nrm, k, R[i], r[i], v[i], w[i])
        if normal == 0.0:
            assert np.all(F[i] == 0.0) and cf[i] == 0.0 and cl[i] == 0.0 == contact
            continue
        touched += 1
        np.testing.assert_allclose(F[i], force, rtol=1e-5, atol=1e-6 * normal)
        np.testing.assert_allclose(M[i], moment, rtol=0, atol=1e-5 * normal * length[i])
        assert cl[i] == pytest.approx(contact, rel=1e-9)
    assert touched >= 3


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("damped", [False, True])
def test_friction_against_spring_slider_reference(seed, damped):
    """Stick (inside the ellipse) and slip (outside) cases with anisotropic coefficients,
    without and with the stick damper (sliding velocities of 0.1 m/s)."""
    rng = np.random.default_rng(seed)
    bed = random_bed(rng)
    n = 16
    length = rng.uniform(0.5, 3.0, size=n)
    radius = rng.uniform(0.05, 0.3, size=n)
    R = np.array([ref.random_rotation(rng) for _ in range(n)])
    r = np.zeros((n, 3))
    for i in range(n):
        x, y = rng.uniform(-40, 40, size=2)
        zb, nrm = ref.seabed_plane_under(bed[0], bed[1], bed[2], x, y)
        # fully in contact: the centre below the touching height by more than the half rise
        r[i] = np.array([x, y, zb]) + nrm * (radius[i] - 0.5 * length[i] * abs(R[i][:, 0] @ nrm) - 0.01)
    anchor = r + rng.normal(scale=1e-5, size=(n, 3))                               # these stick
    anchor[n // 2:] = r[n // 2:] + rng.normal(scale=10.0, size=(n - n // 2, 3))    # these slip
    mu = (rng.uniform(0.2, 1.0), rng.uniform(0.2, 1.0))
    kt = 2e4
    v = 0.1 * rng.normal(size=(n, 3)) if damped else np.zeros((n, 3))
    ct = rng.uniform(1e3, 3e4, size=n) if damped else np.zeros(n)
    F, M, cf, cl, at, adt, ff = run_kernel(length, radius, np.zeros(n), bed, 1e5, R, r, v,
                                           np.zeros((n, 3)), mu=mu, kt=kt, anchor=anchor,
                                           anchored=np.ones(n, np.int64), mode=0, stick_damping=ct)
    slipped = 0
    for i in range(n):
        zb, nrm = ref.seabed_plane_under(bed[0], bed[1], bed[2], r[i, 0], r[i, 1])
        assert cl[i] == pytest.approx(length[i])
        force, new_anchor = ref.seabed_friction_spring_slider(nrm, R[i][:, 0], r[i], anchor[i], kt, cl[i], cf[i],
                                                              mu[0], mu[1], v[i], ct[i])
        np.testing.assert_allclose(ff[i], force, rtol=1e-10, atol=1e-10 * cf[i])
        np.testing.assert_allclose(at[i], new_anchor, rtol=0, atol=1e-12 * 100)
        assert adt[i] == 1
        assert abs(ff[i] @ nrm) < 1e-9 * cf[i]              # friction lies in the seabed plane
        np.testing.assert_allclose(F[i], cf[i] * nrm + ff[i], rtol=1e-12, atol=1e-9 * cf[i])
        a_dir = R[i][:, 0] - (R[i][:, 0] @ nrm) * nrm
        a_dir /= np.linalg.norm(a_dir)
        fa, fl = ff[i] @ a_dir, ff[i] @ np.cross(nrm, a_dir)
        ratio = np.hypot(fa / mu[0], fl / mu[1]) / cf[i]
        assert ratio <= 1.0 + 1e-12
        slipped += ratio > 1.0 - 1e-12
    assert slipped >= n // 4
    assert slipped <= n - n // 4


def test_first_touch_sets_the_anchor_and_commit_accepts_it():
    R = np.eye(3)[None]
    r = np.array([[1.0, 2.0, -100.0 + 0.2 - 0.01]])
    bed = (np.array([-1.0, 1.0]), np.array([-100.0, -100.0]), np.array([1.0, 0.0]))
    F, M, cf, cl, at, adt, ff = run_kernel(np.array([2.0]), np.array([0.2]), np.zeros(1), bed, 1e5, R, r,
                                           np.zeros((1, 3)), np.zeros((1, 3)), mu=(0.5, 0.5), kt=1e5, mode=0)
    assert cf[0] == pytest.approx(1e5 * 2.0 * 0.01)
    np.testing.assert_array_equal(ff, 0.0)
    np.testing.assert_array_equal(at, r)
    assert adt[0] == 1
    anchor = np.zeros((1, 3))
    anchored = np.zeros(1, np.int64)
    commit_friction(anchor, anchored, at, adt)
    np.testing.assert_array_equal(anchor, r)
    assert anchored[0] == 1
    # a lift-off releases the anchor
    r_up = r + [[0.0, 0.0, 1.0]]
    *_, at2, adt2, ff2 = run_kernel(np.array([2.0]), np.array([0.2]), np.zeros(1), bed, 1e5, R, r_up,
                                     np.zeros((1, 3)), np.zeros((1, 3)), mu=(0.5, 0.5), kt=1e5, anchor=anchor,
                                     anchored=anchored, mode=0)
    assert adt2[0] == 0
    np.testing.assert_array_equal(ff2, 0.0)


def test_mobilised_mode_points_towards_end_a():
    """Statics mode 1: axial friction mu N along -axis, anchors placed to give the same force."""
    R = np.eye(3)[None]                 # axis along +x: end A at -x
    r = np.array([[0.0, 0.0, -100.0 + 0.2 - 0.01]])
    bed = (np.array([-1.0, 1.0]), np.array([-100.0, -100.0]), np.array([1.0, 0.0]))
    F, M, cf, cl, at, adt, ff = run_kernel(np.array([2.0]), np.array([0.2]), np.zeros(1), bed, 1e5, R, r,
                                           np.zeros((1, 3)), np.zeros((1, 3)), mu=(0.3, 0.7), kt=1e5, mode=1)
    np.testing.assert_allclose(ff[0], [-0.3 * cf[0], 0.0, 0.0], atol=1e-12)
    # the committed anchor reproduces the force in stick/slip mode
    *_, ff0 = run_kernel(np.array([2.0]), np.array([0.2]), np.zeros(1), bed, 1e5, R, r, np.zeros((1, 3)),
                         np.zeros((1, 3)), mu=(0.3, 0.7), kt=1e5, anchor=at, anchored=adt, mode=0)
    np.testing.assert_allclose(ff0, ff, rtol=1e-9)
