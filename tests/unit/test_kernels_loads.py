"""Gravity, sea loads, seabed and point loads against reference_impl (eqs. 8.19, 8.93-8.95)."""
from __future__ import annotations

import numpy as np
import pytest

import reference_impl as ref
from rfesim.loads.gravity import gravity_energy, gravity_forces
from rfesim.loads.hydro import buoyancy_forces, morison_forces, submergence
from rfesim.loads.point import point_loads
from rfesim.loads.seabed import seabed_forces

SEEDS = [0, 1, 2, 3, 4]
ROUNDOFF = 1e-12
WATER_DENSITY = 1025.0
GRAVITY = 9.81


def random_rotations(rng, n):
    return np.array([ref.random_rotation(rng) for _ in range(n)])


# ------------------------------------------------------------------ gravity

@pytest.mark.parametrize("seed", SEEDS)
def test_gravity(seed):
    rng = np.random.default_rng(seed)
    n = 7
    mass = rng.uniform(1.0, 100.0, size=n)
    kind = rng.integers(0, 3, size=n).astype(np.int64)
    scale = rng.uniform(0.1, 1.0)
    F0 = rng.normal(size=(n, 3))
    F = F0.copy()
    gravity_forces(mass, kind, GRAVITY, scale, F)
    expected = F0 + np.array([ref.gravity_force(m, GRAVITY, scale) for m in mass])
    np.testing.assert_allclose(F, expected, rtol=ROUNDOFF, atol=0)
    r = rng.normal(size=(n, 3))
    assert gravity_energy(mass, r, GRAVITY) == pytest.approx(GRAVITY * float(mass @ r[:, 2]), rel=ROUNDOFF)


# ------------------------------------------------------------------ submergence and buoyancy

def element_crossing_surface(rng, case):
    """(length, rotation, centre, surface_z) for the named case."""
    length = rng.uniform(0.5, 5.0)
    R = ref.random_rotation(rng)
    surface_z = rng.uniform(-2.0, 2.0)
    half_rise = 0.5 * length * abs(R[2, 0])
    if case == "submerged":
        centre_z = surface_z - half_rise - rng.uniform(0.01, 3.0)
    elif case == "dry":
        centre_z = surface_z + half_rise + rng.uniform(0.01, 3.0)
    else:
        if case == "partial_left_low" and R[2, 0] < 0:
            R = R @ np.diag([-1.0, -1.0, 1.0])      # make the left end (local -x) the low end
        if case == "partial_right_low" and R[2, 0] > 0:
            R = R @ np.diag([-1.0, -1.0, 1.0])
        centre_z = surface_z + rng.uniform(-0.9, 0.9) * half_rise
    centre = np.array([rng.uniform(-10, 10), rng.uniform(-10, 10), centre_z])
    return length, R, centre, surface_z


CASES = ["submerged", "dry", "partial_left_low", "partial_right_low"]


def by_hand(length, R, centre, surface_z):
    """Fraction and centroid of a vertical element written out (the axis alone is wet below
    the surface; its section has no height): the low end is submerged."""
    t = R[:, 0]
    left, right = centre - 0.5 * length * t, centre + 0.5 * length * t
    if left[2] <= surface_z and right[2] <= surface_z:
        return 1.0, centre
    if left[2] > surface_z and right[2] > surface_z:
        return 0.0, centre
    low, high = (left, right) if left[2] < right[2] else (right, left)
    fraction = (surface_z - low[2]) / (high[2] - low[2])
    waterline = low + fraction * (high - low)
    return fraction, 0.5 * (low + waterline)


@pytest.mark.parametrize("seed", SEEDS)
def test_submergence(seed):
    """Against the quadrature of reference_impl.submerged_part: random elements clear of the
    surface, through it, and lying across it within their radius."""
    rng = np.random.default_rng(seed)
    rows = [element_crossing_surface(rng, case) for case in CASES for _ in range(3)]
    n = len(rows)
    length = np.array([row[0] for row in rows])
    R = np.array([row[1] for row in rows])
    r = np.array([row[2] for row in rows])
    surface = np.array([row[3] for row in rows])
    area = rng.uniform(0.01, 0.1, size=n)
    area[-1] = 0.0                                   # no sea loads on this one
    fraction = np.full(n, -1.0)
    point = np.full((n, 3), np.nan)
    submergence(length, area, R, r, surface, fraction, point)
    for i in range(n):
        expected_fraction, expected_point = ref.submerged_part(length[i], area[i], R[i], r[i], surface[i])
        assert fraction[i] == pytest.approx(expected_fraction, rel=1e-9, abs=1e-11)
        np.testing.assert_allclose(point[i], expected_point, rtol=0, atol=1e-9 * length[i])
    cases = [case for case in CASES for _ in range(3)]
    radius = np.sqrt(area / np.pi)
    for i, case in enumerate(cases[:-1]):
        rise = 0.5 * length[i] * abs(R[i, 2, 0])
        if case == "submerged" and r[i, 2] + rise + radius[i] <= surface[i]:
            assert fraction[i] == 1.0
        elif case == "dry" and r[i, 2] - rise - radius[i] >= surface[i]:
            assert fraction[i] == 0.0
        elif case.startswith("partial"):
            assert 0.0 < fraction[i] < 1.0


def test_submergence_of_a_vertical_element_is_its_wet_axis():
    rng = np.random.default_rng(7)
    for z in (-3.0, -0.4, 0.0, 0.3, 2.0):
        R = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]) @ np.diag([1.0, 1.0, 1.0])
        R = R.T if rng.random() < 0.5 else R            # the axis up or down
        r = np.array([[0.5, -1.0, z]])
        fraction, point = np.zeros(1), np.zeros((1, 3))
        submergence(np.array([2.0]), np.array([0.05]), R[None], r, np.zeros(1), fraction, point)
        f, p = by_hand(2.0, R, r[0], 0.0)
        assert fraction[0] == pytest.approx(f, abs=1e-14)
        np.testing.assert_allclose(point[0], p, atol=1e-14)


def test_submergence_of_a_horizontal_element_is_its_immersed_section():
    """A horizontal element at axis height h: the circular segment's share of the disc,
    (acos u - u sqrt(1 - u^2)) / pi with u = h / a: half at the surface, 1 and 0 a radius
    below and above it, continuous between (the axis alone made it jump from 1 to 0)."""
    a = 0.126157                                  # the radius of area 0.05
    area = np.pi * a * a
    R = np.eye(3)[None]
    for h, expected in ((-0.2, 1.0), (-a, 1.0), (-0.5 * a, None), (0.0, 0.5), (0.5 * a, None), (a, 0.0),
                        (0.2, 0.0)):
        fraction = np.zeros(1)
        point = np.zeros((1, 3))
        submergence(np.array([2.0]), np.array([area]), R, np.array([[1.0, 2.0, h]]), np.zeros(1), fraction, point)
        u = h / a
        closed = 1.0 if u <= -1 else 0.0 if u >= 1 else (np.arccos(u) - u * np.sqrt(1 - u * u)) / np.pi
        assert fraction[0] == pytest.approx(closed, abs=1e-14)
        if expected is not None:
            assert fraction[0] == pytest.approx(expected, abs=1e-14)
        np.testing.assert_array_equal(point[0], [1.0, 2.0, h])
    # the segment of u = -1/2: 1 - (pi/3 - sqrt(3)/4) / pi
    fraction = np.zeros(1)
    submergence(np.array([2.0]), np.array([area]), R, np.array([[1.0, 2.0, 0.5 * a]]), np.zeros(1), fraction,
                np.zeros((1, 3)))
    assert fraction[0] == pytest.approx((np.pi / 3 - np.sqrt(3) / 4) / np.pi, rel=1e-12)


@pytest.mark.parametrize("h", [-0.15, -0.08, 0.0, 0.05, 0.11])
def test_submergence_of_nearly_level_elements(h):
    """Tilts from 1e-9 rad to 0.1 rad about level, across the switch from Gauss-Legendre to
    the antiderivatives (|u_r - u_l| = SMALL_RISE): the reference's quadrature to 1e-9, and no
    jump at the switch (the antiderivatives alone put the centroid of a level element at
    random along it)."""
    from rfesim.loads.hydro import SMALL_RISE
    length, area = 2.0, 0.05
    a = np.sqrt(area / np.pi)
    switch = np.arcsin(SMALL_RISE * a / length)          # |u_r - u_l| = 2 hl sin(tilt) / (a cos(tilt))
    for tilt in (1e-9, 1e-6, 0.999 * switch, 1.001 * switch, 1e-3, 1e-2, 0.1):
        c, s_ = np.cos(tilt), np.sin(tilt)
        R = np.array([[c, 0.0, -s_], [0.0, 1.0, 0.0], [s_, 0.0, c]])
        centre = np.array([1.0, 2.0, h])
        fraction, point = np.zeros(1), np.zeros((1, 3))
        submergence(np.array([length]), np.array([area]), R[None], centre[None], np.zeros(1), fraction, point)
        f_ref, p_ref = ref.submerged_part(length, area, R, centre, 0.0)
        assert fraction[0] == pytest.approx(f_ref, abs=1e-9)
        np.testing.assert_allclose(point[0], p_ref, atol=1e-9)


@pytest.mark.parametrize("seed", SEEDS)
def test_buoyancy(seed):
    rng = np.random.default_rng(seed)
    rows = [element_crossing_surface(rng, case) for case in CASES for _ in range(3)]
    n = len(rows)
    length = np.array([row[0] for row in rows])
    R = np.array([row[1] for row in rows])
    r = np.array([row[2] for row in rows])
    surface = np.array([row[3] for row in rows])
    area = rng.uniform(0.01, 0.1, size=n)
    kind = np.zeros(n, np.int64)
    fraction = np.zeros(n)
    point = np.zeros((n, 3))
    submergence(length, area, R, r, surface, fraction, point)
    scale = rng.uniform(0.2, 1.0)
    F0 = rng.normal(size=(n, 3))
    M0 = rng.normal(size=(n, 3))
    F, M = F0.copy(), M0.copy()
    buoyancy_forces(length, area, kind, WATER_DENSITY, GRAVITY, scale, r, fraction, point, F, M)
    for i in range(n):
        force, moment = ref.buoyancy_force_and_moment(length[i], area[i], WATER_DENSITY, GRAVITY, scale, r[i],
                                                      fraction[i], point[i])
        typical = WATER_DENSITY * GRAVITY * area[i] * length[i]
        np.testing.assert_allclose(F[i] - F0[i], force, rtol=0, atol=ROUNDOFF * typical)
        np.testing.assert_allclose(M[i] - M0[i], moment, rtol=0, atol=ROUNDOFF * typical * length[i])


# ------------------------------------------------------------------ Morison

@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("water_motion", ["still", "current", "current_and_acceleration"])
def test_morison(seed, water_motion):
    rng = np.random.default_rng(seed)
    rows = [element_crossing_surface(rng, case) for case in CASES for _ in range(3)]
    n = len(rows)
    length = np.array([row[0] for row in rows])
    R = np.array([row[1] for row in rows])
    r = np.array([row[2] for row in rows])
    surface = np.array([row[3] for row in rows])
    diameter = rng.uniform(0.1, 0.5, size=n)
    diameter[0] = 0.0                                    # no sea loads on this one
    area = np.pi * diameter ** 2 / 4
    cdn, cdt = rng.uniform(0.5, 1.5, size=n), rng.uniform(0.0, 0.1, size=n)
    can, cat = rng.uniform(0.5, 1.5, size=n), rng.uniform(0.0, 0.3, size=n)
    v = rng.normal(size=(n, 3))
    w = rng.normal(size=(n, 3))
    water_velocity = np.zeros((n, 3)) if water_motion == "still" else rng.normal(size=(n, 3))
    water_acceleration = rng.normal(size=(n, 3)) if water_motion == "current_and_acceleration" else np.zeros((n, 3))
    fraction = np.zeros(n)
    point = np.zeros((n, 3))
    submergence(length, area, R, r, surface, fraction, point)
    F0 = rng.normal(size=(n, 3))
    M0 = rng.normal(size=(n, 3))
    F, M = F0.copy(), M0.copy()
    Ma = np.full((n, 3, 3), np.nan)
    Ja = np.full((n, 3), np.nan)
    morison_forces(length, diameter, area, cdn, cdt, can, cat, WATER_DENSITY, R, r, v, w, fraction, point,
                   water_velocity, water_acceleration, F, M, Ma, Ja)
    for i in range(n):
        force, moment, added_mass, added_inertia = ref.morison_force_and_moment(
            length[i], diameter[i], area[i], cdn[i], cdt[i], can[i], cat[i], WATER_DENSITY, R[i], r[i], v[i],
            w[i], fraction[i], point[i], water_velocity[i], water_acceleration[i])
        typical_force = max(np.linalg.norm(force), WATER_DENSITY * diameter[i] * length[i] + 1.0)
        np.testing.assert_allclose(F[i] - F0[i], force, rtol=0, atol=ROUNDOFF * typical_force)
        np.testing.assert_allclose(M[i] - M0[i], moment, rtol=0, atol=ROUNDOFF * typical_force * length[i])
        typical_mass = WATER_DENSITY * area[i] * length[i] + 1.0
        np.testing.assert_allclose(Ma[i], added_mass, rtol=0, atol=ROUNDOFF * typical_mass)
        np.testing.assert_allclose(Ja[i], added_inertia, rtol=0, atol=ROUNDOFF * typical_mass * length[i] ** 2)
        if fraction[i] == 0.0 or diameter[i] == 0.0:
            np.testing.assert_array_equal(F[i], F0[i])
            np.testing.assert_array_equal(Ma[i], 0.0)


def test_morison_drag_directions():
    """A horizontal element along x in a current along x and along y: pure axial and pure
    normal drag, with the magnitudes of the formulas."""
    R = np.eye(3)[None]
    r = np.array([[0.0, 0.0, -5.0]])
    args = dict(length=np.array([2.0]), diameter=np.array([0.3]), area=np.array([0.07]),
                cdn=np.array([1.2]), cdt=np.array([0.05]), can=np.array([1.0]), cat=np.array([0.1]))
    for current, expected in (([1.5, 0.0, 0.0], [0.5 * WATER_DENSITY * 0.05 * np.pi * 0.3 * 2.0 * 1.5 ** 2, 0, 0]),
                              ([0.0, 1.5, 0.0], [0, 0.5 * WATER_DENSITY * 1.2 * 0.3 * 2.0 * 1.5 ** 2, 0])):
        F = np.zeros((1, 3))
        M = np.zeros((1, 3))
        morison_forces(args["length"], args["diameter"], args["area"], args["cdn"], args["cdt"], args["can"],
                       args["cat"], WATER_DENSITY, R, r, np.zeros((1, 3)), np.zeros((1, 3)), np.ones(1), r.copy(),
                       np.array([current]), np.zeros((1, 3)), F, M, np.zeros((1, 3, 3)), np.zeros((1, 3)))
        np.testing.assert_allclose(F[0], expected, rtol=ROUNDOFF, atol=ROUNDOFF)
        np.testing.assert_array_equal(M[0], 0.0)


# ------------------------------------------------------------------ seabed

def call_seabed(length, radius, damping, seabed_z, seabed_k, R, r, v, w, F, M, contact_force, contact_length,
                mu=(0.0, 0.0), kt=0.0, bed=None, anchor=None, anchored=None, mode=2):
    """The seabed kernel on a flat seabed at seabed_z (or the profile ``bed`` = (s, z, dir))
    with friction off unless given; returns the trial anchors and the friction forces."""
    n = length.shape[0]
    bed_s, bed_z, bed_dir = bed if bed is not None else (np.array([-1.0, 1.0]), np.array([seabed_z, seabed_z]),
                                                          np.array([1.0, 0.0]))
    anchor = np.zeros((n, 3)) if anchor is None else anchor
    anchored = np.zeros(n, np.int64) if anchored is None else anchored
    anchor_trial = np.full((n, 3), np.nan)
    anchored_trial = np.full(n, -1, np.int64)
    friction = np.full((n, 3), np.nan)
    seabed_forces(length, radius, damping, np.zeros(n), bed_s, bed_z, bed_dir, seabed_k, np.asarray(mu, float), kt,
                  R, r, v, w,
                  F, M, contact_force, contact_length, anchor, anchored, anchor_trial, anchored_trial,
                  np.array([mode], np.int64), friction, np.zeros(3))
    return anchor_trial, anchored_trial, friction


def element_near_seabed(rng, case, seabed_z, contact_radius):
    length = rng.uniform(0.5, 5.0)
    R = ref.random_rotation(rng)
    half_rise = 0.5 * length * abs(R[2, 0])
    bottom = seabed_z + contact_radius           # axis height at which the underside touches
    if case == "fully":
        centre_z = bottom - half_rise - rng.uniform(0.001, 0.05)
    elif case == "none":
        centre_z = bottom + half_rise + rng.uniform(0.001, 0.5)
    else:
        centre_z = bottom + rng.uniform(-0.9, 0.9) * half_rise
    centre = np.array([rng.uniform(-10, 10), rng.uniform(-10, 10), centre_z])
    return length, R, centre


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("damped", [False, True])
def test_seabed_against_quadrature(seed, damped):
    rng = np.random.default_rng(seed)
    seabed_z = -100.0
    seabed_k = 2e5
    cases = ["fully", "partly", "none"] * 3
    n = len(cases)
    radius = rng.uniform(0.05, 0.3, size=n)
    rows = [element_near_seabed(rng, case, seabed_z, radius[i]) for i, case in enumerate(cases)]
    length = np.array([row[0] for row in rows])
    R = np.array([row[1] for row in rows])
    r = np.array([row[2] for row in rows])
    v = 0.1 * rng.normal(size=(n, 3))
    w = 0.1 * rng.normal(size=(n, 3))
    damping = rng.uniform(1e2, 1e3, size=n) if damped else np.zeros(n)
    F0 = rng.normal(size=(n, 3))
    M0 = rng.normal(size=(n, 3))
    F, M = F0.copy(), M0.copy()
    contact_force = np.full(n, np.nan)
    contact_length = np.full(n, np.nan)
    call_seabed(length, radius, damping, seabed_z, seabed_k, R, r, v, w, F, M, contact_force, contact_length)
    for i, case in enumerate(cases):
        force, moment, normal, contact = ref.seabed_contact_by_quadrature(
            length[i], radius[i], damping[i], seabed_z, seabed_k, R[i], r[i], v[i], w[i])
        if case == "none":
            assert normal == 0.0
            np.testing.assert_array_equal(F[i], F0[i])
            np.testing.assert_array_equal(M[i], M0[i])
            assert contact_force[i] == 0.0 and contact_length[i] == 0.0
            continue
        assert normal > 0.0
        if case == "fully":
            assert contact_length[i] == length[i]
        else:
            assert 0.0 < contact_length[i] < length[i]
        np.testing.assert_allclose(F[i] - F0[i], force, rtol=1e-5, atol=0)
        np.testing.assert_allclose(M[i] - M0[i], moment, rtol=0, atol=1e-5 * normal * length[i])
        assert contact_force[i] == pytest.approx(normal, rel=1e-5)
        assert contact_length[i] == pytest.approx(contact, rel=ROUNDOFF)


def test_seabed_force_is_never_tensile():
    """An element lifting off fast: the damper would pull, the force is clipped to zero, and
    the element is out of contact: no contact length (the touchdown output places the
    touchdown point on RFEs with a contact length; audit 7 found it on RFEs the seabed no
    longer pushed, which kept the full 2 m here) and no friction, its anchor released."""
    R = np.eye(3)[None]
    r = np.array([[0.0, 0.0, -100.0 + 0.2 - 0.01]])           # 1 cm penetration, radius 0.2
    F = np.zeros((1, 3))
    M = np.zeros((1, 3))
    contact_force = np.full(1, np.nan)
    contact_length = np.full(1, np.nan)
    # spring 1e3 * 2 m * 0.01 m = 20 N; damper 1e4 * 2 m * 10 m/s = 2e5 N pulling
    anchor_trial, anchored_trial, friction = call_seabed(
        np.array([2.0]), np.array([0.2]), np.array([1e4]), -100.0, 1e3, R, r, np.array([[0.0, 0.0, 10.0]]),
        np.zeros((1, 3)), F, M, contact_force, contact_length, mu=(0.5, 0.5), kt=1e3,
        anchor=r + 0.3, anchored=np.ones(1, np.int64), mode=0)
    np.testing.assert_array_equal(F, 0.0)
    np.testing.assert_array_equal(M, 0.0)
    assert contact_force[0] == 0.0
    assert contact_length[0] == 0.0
    np.testing.assert_array_equal(friction, 0.0)
    assert anchored_trial[0] == 0
    np.testing.assert_array_equal(anchor_trial, r)
    # lifting off slowly the spring still pushes: in contact over the whole element
    call_seabed(np.array([2.0]), np.array([0.2]), np.array([1e4]), -100.0, 1e3, R, r, np.array([[0.0, 0.0, 1e-4]]),
                np.zeros((1, 3)), F, M, contact_force, contact_length)
    assert contact_force[0] == pytest.approx(20.0 - 1e4 * 2.0 * 1e-4, rel=1e-12)
    assert contact_length[0] == 2.0


# ------------------------------------------------------------------ point loads (eq. 8.93)

@pytest.mark.parametrize("seed", SEEDS)
def test_point_loads(seed):
    rng = np.random.default_rng(seed)
    n = 5
    nload = 8
    R = random_rotations(rng, n)
    load_rfe = rng.integers(0, n, size=nload).astype(np.int64)
    load_rfe[:2] = 3                                  # two loads on the same RFE add up
    arm = rng.normal(size=(nload, 3))
    force = rng.normal(scale=100.0, size=(nload, 3))
    moment = rng.normal(scale=10.0, size=(nload, 3))
    local = (np.arange(nload) % 2).astype(np.int64)
    scale = rng.uniform(0.1, 1.0)
    F0 = rng.normal(size=(n, 3))
    M0 = rng.normal(size=(n, 3))
    F, M = F0.copy(), M0.copy()
    point_loads(load_rfe, arm, force, moment, local, scale, R, F, M, np.zeros((8, 3)))
    F_expected, M_expected = F0.copy(), M0.copy()
    for j in range(nload):
        f, m = ref.point_load(R[load_rfe[j]], arm[j], force[j], moment[j], bool(local[j]), scale)
        F_expected[load_rfe[j]] += f
        M_expected[load_rfe[j]] += m
    np.testing.assert_allclose(F, F_expected, rtol=0, atol=ROUNDOFF * 1e3)
    np.testing.assert_allclose(M, M_expected, rtol=0, atol=ROUNDOFF * 1e3)
