"""rfesim.sea.kernel.sea_kinematics_into against a slow, readable numpy version written
straight from the Airy formulas (rfesim.sea.waves docstring), on random points and times,
for every stretching, finite and deep water, with current, time factor and ramp."""
from __future__ import annotations

import math

import numpy as np
import pytest

from rfesim.sea.current import CurrentProfile, no_current
from rfesim.sea.kernel import pack_sea, sea_kinematics_into, sea_spec
from rfesim.sea.waves import WaveComponents, no_waves, wave_number
from rfesim.scenario.schema import Environment

GRAVITY = 9.81
ROUNDOFF = 1e-12


def reference_sea(waves: WaveComponents, current: CurrentProfile, surface_level: float, t: float, points):
    """(eta (n,), velocity (n, 3), acceleration (n, 3)): the formulas, one array at a time."""
    x, y, z = points[:, 0:1], points[:, 1:2], points[:, 2]
    a, w, k, phi = waves.amplitude, waves.omega, waves.wavenumber, waves.phase
    cb, sb = np.cos(waves.direction), np.sin(waves.direction)
    V = waves.velocity_coefficients()           # a omega for linear components
    T = waves.ramp_duration
    if T > 0.0 and t < T:
        ramp = 0.0 if t <= 0.0 else 0.5 * (1.0 - math.cos(math.pi * t / T))
        ramp_rate = 0.0 if t <= 0.0 else 0.5 * math.pi / T * math.sin(math.pi * t / T)
    else:
        ramp, ramp_rate = 1.0, 0.0
    theta = w * t - k * (x * cb + y * sb) + phi                       # (n, nc)
    eta = ramp * np.sum(a * np.cos(theta), axis=1)
    h = waves.depth
    deep = math.isinf(h)
    zc = np.minimum(z - surface_level, eta)                           # above the surface: at the surface
    above = np.zeros_like(zc)
    if waves.stretching == "wheeler":
        ze = zc - eta if deep else h * (zc - eta) / (h + eta)
    elif waves.stretching == "vertical":
        ze = np.minimum(zc, 0.0)
    elif waves.stretching == "linear":
        above = np.maximum(zc, 0.0)
        ze = np.minimum(zc, 0.0)
    else:
        ze = zc
    if not deep:
        ze = np.maximum(ze, -h)
    ze = ze[:, None]
    if deep:
        C = S = np.exp(k * ze)
    else:
        C = np.cosh(k * (ze + h)) / np.sinh(k * h)
        S = np.sinh(k * (ze + h)) / np.sinh(k * h)
    C, S = C + above[:, None] * k * S, S + above[:, None] * k * C
    u_x = np.sum(V * C * np.cos(theta) * cb, axis=1)
    u_y = np.sum(V * C * np.cos(theta) * sb, axis=1)
    u_z = np.sum(-V * S * np.sin(theta), axis=1)
    du_x = np.sum(-V * w * C * np.sin(theta) * cb, axis=1)
    du_y = np.sum(-V * w * C * np.sin(theta) * sb, axis=1)
    du_z = np.sum(-V * w * S * np.cos(theta), axis=1)
    vel = ramp * np.stack([u_x, u_y, u_z], axis=1)
    acc = ramp * np.stack([du_x, du_y, du_z], axis=1) + ramp_rate * np.stack([u_x, u_y, u_z], axis=1)
    surface = surface_level + eta
    if current.z.size:
        vel += current.velocity(t, np.minimum(points[:, 2], surface))
    return surface, vel, acc


def random_sea(rng, depth, stretching, ramp, nc=7, own_velocity=False):
    """Random linear components; with ``own_velocity`` each has its own velocity coefficient
    (as the harmonics of a Stokes 5th-order wave do) instead of a omega."""
    omega = rng.uniform(0.3, 2.0, nc)
    return WaveComponents(amplitude=rng.uniform(0.1, 1.2, nc), omega=omega,
                          wavenumber=np.asarray(wave_number(omega, depth, GRAVITY)),
                          phase=rng.uniform(0.0, 2.0 * np.pi, nc), direction=rng.uniform(-np.pi, np.pi, nc),
                          depth=math.inf if depth is None else depth, stretching=stretching, ramp_duration=ramp,
                          velocity=rng.uniform(-2.0, 2.0, nc) if own_velocity else None)


def random_current(rng):
    z = np.sort(rng.uniform(-60.0, 3.0, 4))
    time = np.array([0.0, 20.0, 50.0])
    return CurrentProfile(z=z, speed=rng.uniform(-0.5, 1.5, 4), direction=rng.uniform(0, 2 * np.pi),
                          time=time, factor=np.array([0.2, 1.0, 0.7]))


def run_kernel(spec, t, points):
    n = points.shape[0]
    eta, vel, acc = np.zeros(n), np.zeros((n, 3)), np.zeros((n, 3))
    sea_kinematics_into(spec, float(t), points, eta, vel, acc)
    return eta, vel, acc


@pytest.mark.parametrize("stretching", ["wheeler", "none", "vertical", "linear"])
@pytest.mark.parametrize("depth", [40.0, None])
@pytest.mark.parametrize("seed", [0, 1])
def test_kernel_equals_the_readable_formulas(stretching, depth, seed):
    rng = np.random.default_rng(seed)
    surface_level = rng.uniform(-2.0, 2.0)
    waves = random_sea(rng, depth, stretching, ramp=15.0, own_velocity=seed == 1)
    current = random_current(rng)
    spec = pack_sea(waves, current, surface_level)
    # points below, near, at and above the surface, and under the seabed
    points = np.column_stack([rng.uniform(-200, 200, 60), rng.uniform(-200, 200, 60),
                              surface_level + rng.uniform(-45.0, 4.0, 60)])
    for t in (-1.0, 0.0, 3.7, 14.99, 15.0, 41.3, 123.0):
        got = run_kernel(spec, t, points)
        want = reference_sea(waves, current, surface_level, t, points)
        for g, w in zip(got, want):
            scale = max(1.0, float(np.max(np.abs(w))))
            assert np.max(np.abs(g - w)) <= ROUNDOFF * scale


def test_points_above_the_surface_take_the_surface_value():
    rng = np.random.default_rng(3)
    for stretching in ("wheeler", "none", "vertical", "linear"):
        spec = pack_sea(random_sea(rng, 50.0, stretching, 0.0), no_current(), 0.0)
        base = np.array([[12.0, -7.0, 0.0]])
        eta, _, _ = run_kernel(spec, 2.5, base)
        at = np.array([[12.0, -7.0, eta[0]]])
        high = np.array([[12.0, -7.0, eta[0] + 30.0]])
        _, v_at, a_at = run_kernel(spec, 2.5, at)
        _, v_hi, a_hi = run_kernel(spec, 2.5, high)
        assert np.array_equal(v_at, v_hi) and np.array_equal(a_at, a_hi)


def test_acceleration_is_the_time_derivative_of_the_velocity_at_a_fixed_point():
    # with no stretching the Airy velocity at a fixed submerged point is u(t); du/dt
    # (ramp included) must match a central difference of it
    rng = np.random.default_rng(5)
    for depth in (30.0, None):
        spec = pack_sea(random_sea(rng, depth, "none", ramp=10.0), no_current(), 0.0)
        points = np.column_stack([rng.uniform(-50, 50, 10), rng.uniform(-50, 50, 10), rng.uniform(-25, -4, 10)])
        for t in (2.0, 7.5, 30.0):
            dt = 1e-5
            _, vp, _ = run_kernel(spec, t + dt, points)
            _, vm, _ = run_kernel(spec, t - dt, points)
            _, _, acc = run_kernel(spec, t, points)
            assert np.max(np.abs((vp - vm) / (2 * dt) - acc)) < 1e-7 * max(1.0, np.max(np.abs(acc)))


def test_velocity_satisfies_continuity_and_surface_kinematics():
    # linear theory: du/dx + dw/dz = 0 in the water; at z = 0 (no stretching) w = d(eta)/dt
    rng = np.random.default_rng(8)
    spec = pack_sea(random_sea(rng, 60.0, "none", 0.0), no_current(), 0.0)
    p = np.array([[3.0, 4.0, -7.0]])
    d = 1e-4
    div = 0.0
    for axis in range(3):
        e = np.zeros((1, 3))
        e[0, axis] = d
        _, vp, _ = run_kernel(spec, 1.3, p + e)
        _, vm, _ = run_kernel(spec, 1.3, p - e)
        div += (vp[0, axis] - vm[0, axis]) / (2 * d)
    assert abs(div) < 1e-7
    surface = np.array([[3.0, 4.0, 0.0]])
    etap, _, _ = run_kernel(spec, 1.3 + 1e-5, surface)
    etam, _, _ = run_kernel(spec, 1.3 - 1e-5, surface)
    _, v0, _ = run_kernel(spec, 1.3, np.array([[3.0, 4.0, -1e-12]]))
    assert abs((etap[0] - etam[0]) / 2e-5 - v0[0, 2]) < 1e-6


def test_still_water_spec_gives_the_surface_level_and_no_motion():
    env = Environment.model_validate({"water": {"depth": 50.0, "surface_level": 1.5}})
    spec = sea_spec(env)
    assert not spec.has_waves and not spec.has_current
    points = np.array([[0.0, 0.0, -10.0], [5.0, 1.0, 3.0]])
    eta, vel, acc = run_kernel(spec, 3.0, points)
    assert np.array_equal(eta, [1.5, 1.5]) and not vel.any() and not acc.any()
    air = sea_spec(Environment.model_validate({}))
    assert not air.has_waves and air.surface_level == 0.0
    empty = pack_sea(no_waves(), no_current(), 0.0)
    assert empty.amplitude.shape == (0,)


def test_current_profile_interpolates_and_holds_beyond_the_ends():
    env = Environment.model_validate({"water": {"depth": 100.0, "current": {
        "profile": [[0.0, 1.0], [-100.0, 0.2], [-50.0, 0.5]], "direction_deg": 90.0,
        "time_factor": [[0.0, 0.0], [10.0, 1.0]]}}})
    spec = sea_spec(env)
    points = np.array([[0, 0, -25.0], [0, 0, -75.0], [0, 0, -150.0], [0, 0, 5.0]])
    _, vel, acc = run_kernel(spec, 5.0, points)
    assert vel[:, 1] == pytest.approx(0.5 * np.array([0.75, 0.35, 0.2, 1.0]), rel=1e-14)
    assert np.max(np.abs(vel[:, 0])) < 1e-15 and not acc.any()
    _, vel, _ = run_kernel(spec, 60.0, points)
    assert vel[:, 1] == pytest.approx([0.75, 0.35, 0.2, 1.0], rel=1e-14)
