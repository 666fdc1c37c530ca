"""Sea kinematics at depth (docs/theory.md 'Sea kinematics at depth'): the kernel skips a
wave component at a point where it has decayed below SKIP_DEPTH of the sea's velocity
bound, and forms exp(-k (z + 2h)) from exp(k z) and exp(-2 k h). Checked against the
readable formulas (those of test_sea_kernel, with the finite-depth profiles written free
of overflow: cosh(k(z+h))/sinh(kh) = (e^{kz} + e^{-k(z+2h)}) / (1 - e^{-2kh})) on a broad random sea (short waves that vanish a few
metres down, long ones that reach the seabed) at points from the surface to the seabed of
deep and 1000 m water: equal to round-off, while most component-point pairs are skipped."""
from __future__ import annotations

import math

import numpy as np
import pytest

from rfesim.sea.current import no_current
from rfesim.sea.kernel import SKIP_DEPTH, pack_sea
from rfesim.sea.waves import WaveComponents, wave_number
from test_sea_kernel import GRAVITY, ROUNDOFF, run_kernel


def reference_sea(waves: WaveComponents, t: float, points):
    """(eta, velocity, acceleration) by the Airy formulas, numpy arrays, still-water level 0,
    no current, every stretching of rfesim.sea.kernel."""
    x, y, z = points[:, 0:1], points[:, 1:2], points[:, 2]
    a, w, k, phi = waves.amplitude, waves.omega, waves.wavenumber, waves.phase
    cb, sb = np.cos(waves.direction), np.sin(waves.direction)
    V = waves.velocity_coefficients()
    T = waves.ramp_duration
    if T > 0.0 and t < T:
        ramp = 0.0 if t <= 0.0 else 0.5 * (1.0 - math.cos(math.pi * t / T))
        ramp_rate = 0.0 if t <= 0.0 else 0.5 * math.pi / T * math.sin(math.pi * t / T)
    else:
        ramp, ramp_rate = 1.0, 0.0
    theta = w * t - k * (x * cb + y * sb) + phi
    eta = ramp * np.sum(a * np.cos(theta), axis=1)
    h = waves.depth
    deep = math.isinf(h)
    zc = np.minimum(z, eta)
    above = np.zeros_like(zc)
    if waves.stretching == "wheeler":
        ze = zc - eta if deep else h * (zc - eta) / (h + eta)
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
        den = 1.0 - np.exp(-2.0 * k * h)
        C = (np.exp(k * ze) + np.exp(-k * (ze + 2.0 * h))) / den
        S = (np.exp(k * ze) - np.exp(-k * (ze + 2.0 * h))) / den
    C, S = C + above[:, None] * k * S, S + above[:, None] * k * C
    u = np.stack([np.sum(V * C * np.cos(theta) * cb, axis=1), np.sum(V * C * np.cos(theta) * sb, axis=1),
                  np.sum(-V * S * np.sin(theta), axis=1)], axis=1)
    du = np.stack([np.sum(-V * w * C * np.sin(theta) * cb, axis=1), np.sum(-V * w * C * np.sin(theta) * sb, axis=1),
                   np.sum(-V * w * S * np.cos(theta), axis=1)], axis=1)
    return eta, ramp * u, ramp * du + ramp_rate * u


def broad_sea(rng, depth, stretching, nc=120):
    omega = np.geomspace(0.35, 8.0, nc) * rng.uniform(0.97, 1.03, nc)
    amplitude = 0.6 * (0.8 / omega) ** 2.5 * rng.uniform(0.5, 1.0, nc)     # a falling spectrum
    return WaveComponents(amplitude=amplitude, omega=omega,
                          wavenumber=np.asarray(wave_number(omega, depth, GRAVITY)),
                          phase=rng.uniform(0.0, 2.0 * np.pi, nc), direction=rng.uniform(-0.3, 0.3, nc),
                          depth=math.inf if depth is None else depth, stretching=stretching, ramp_duration=10.0)


def skipped_fraction(waves, points):
    """Fraction of (point, component) pairs below the kernel's skip height (Wheeler/none
    stretching bound z_s <= z: a pair counted here is skipped by the kernel too)."""
    V = np.abs(waves.velocity_coefficients()) * (1.0 + waves.omega)
    den = 1.0 if math.isinf(waves.depth) else -np.expm1(-2.0 * waves.wavenumber * waves.depth)
    lim = np.log(SKIP_DEPTH * V.sum() / (2.0 * V / den)) / waves.wavenumber
    eta_max = np.abs(waves.amplitude).sum()
    return float(np.mean(points[:, 2:3] + eta_max < lim[None, :]))


@pytest.mark.parametrize("depth", [1000.0, None])
@pytest.mark.parametrize("stretching", ["wheeler", "none", "linear"])
def test_deep_points_equal_the_formulas_while_components_are_skipped(depth, stretching):
    rng = np.random.default_rng(11)
    waves = broad_sea(rng, depth, stretching)
    spec = pack_sea(waves, no_current(), 0.0)
    bottom = -1000.0 if depth else -1500.0
    points = np.column_stack([rng.uniform(-300, 300, 80), rng.uniform(-50, 50, 80),
                              np.concatenate([rng.uniform(-30.0, 3.0, 20), rng.uniform(bottom, -30.0, 60)])])
    assert skipped_fraction(waves, points) > 0.4        # the skip is exercised
    for t in (0.0, 4.2, 37.9):
        got = run_kernel(spec, t, points)
        want = reference_sea(waves, t, points)
        for g, w in zip(got, want):
            scale = max(1.0, float(np.max(np.abs(w))))
            assert np.max(np.abs(g - w)) <= ROUNDOFF * scale
        # below 200 m the velocity is tiny but still resolved to round-off of the surface values
        deep = points[:, 2] < -200.0
        assert np.max(np.abs(got[1][deep] - want[1][deep])) <= 1e-13 * np.max(np.abs(want[1]))


def test_a_component_with_no_velocity_contributes_only_to_the_elevation():
    rng = np.random.default_rng(3)
    waves = broad_sea(rng, 200.0, "wheeler", nc=9)
    velocity = waves.velocity_coefficients().copy()
    velocity[4] = 0.0
    waves = WaveComponents(amplitude=waves.amplitude, omega=waves.omega, wavenumber=waves.wavenumber,
                           phase=waves.phase, direction=waves.direction, depth=waves.depth, stretching="wheeler",
                           ramp_duration=0.0, velocity=velocity)
    spec = pack_sea(waves, no_current(), 0.0)
    points = np.column_stack([rng.uniform(-100, 100, 30), np.zeros(30), rng.uniform(-200.0, 0.0, 30)])
    got = run_kernel(spec, 3.0, points)
    want = reference_sea(waves, 3.0, points)
    for g, w in zip(got, want):
        assert np.max(np.abs(g - w)) <= ROUNDOFF * max(1.0, float(np.max(np.abs(w))))


@pytest.mark.parametrize("depth", [1000.0, None])
@pytest.mark.parametrize("stretching", ["wheeler", "none"])
def test_kinematics_cutoff_at_depth(depth, stretching):
    """waves.kinematics_cutoff (docs/theory.md 'Wave kinematics cut-off at depth'): below
    deep_z, where the summed bound of all components is the cut-off fraction of the sea's
    bound, a point gets no wave kinematics and the still-water level; its true kinematics
    are below the cut-off; every other point is unchanged to round-off."""
    rng = np.random.default_rng(5)
    waves = broad_sea(rng, depth, stretching)
    cutoff = 1e-4          # this sea's long waves are high (sum |a| = 56 m): deep_z about -590 m
    spec = pack_sea(waves, no_current(), 0.0, cutoff)
    assert pack_sea(waves, no_current(), 0.0).deep_z == -np.inf          # off by default
    k = waves.wavenumber
    V = np.abs(waves.velocity_coefficients()) * (1.0 + waves.omega)
    vref = V.sum()
    den = 1.0 if depth is None else -np.expm1(-2.0 * k * depth)
    summed_bound = float(np.sum(2.0 * V / den * np.exp(k * spec.deep_z)))
    assert summed_bound == pytest.approx(cutoff * vref, rel=1e-9)
    assert -1000.0 < spec.deep_z < -20.0
    bottom = -1000.0 if depth else -1500.0
    points = np.column_stack([rng.uniform(-300, 300, 300), rng.uniform(-50, 50, 300),
                              np.concatenate([rng.uniform(-30.0, 3.0, 20), rng.uniform(bottom, -30.0, 280)])])
    # the kernel's rule, after the ramp (r = 1): under the lowest surface, highest stretched height below deep_z
    E = np.abs(waves.amplitude).sum()
    zr = points[:, 2]
    if stretching == "wheeler":
        ze_hi = zr + E if depth is None else depth * (zr + E) / (depth - E)
    else:
        ze_hi = zr
    skipped = (zr < -E) & (ze_hi < spec.deep_z)
    assert skipped.sum() > 20 and (~skipped).sum() > 20            # both kinds of points are exercised
    for t in (12.0, 37.9):
        got = run_kernel(spec, t, points)
        want = reference_sea(waves, t, points)
        assert np.all(got[0][skipped] == 0.0)
        assert np.all(got[1][skipped] == 0.0) and np.all(got[2][skipped] == 0.0)
        assert np.max(np.abs(want[1][skipped])) <= cutoff * vref
        assert np.max(np.abs(want[2][skipped])) <= cutoff * vref
        for g, w in zip(got, want):
            scale = max(1.0, float(np.max(np.abs(w))))
            assert np.max(np.abs(g[~skipped] - w[~skipped])) <= ROUNDOFF * scale


def test_component_constants_packed_once_match_their_formulas():
    """pack_sea packs each component's profile denominator, exp(-2 k h) and skip height
    (sea_component_constants) once; they are the closed forms, in finite and deep water."""
    rng = np.random.default_rng(5)
    for depth in (60.0, None):
        waves = broad_sea(rng, depth, "wheeler")
        spec = pack_sea(waves, no_current(), 0.0)
        k = waves.wavenumber
        V = np.abs(waves.velocity_coefficients()) * (1.0 + waves.omega)
        if depth is None:
            den, e2 = np.ones_like(k), np.zeros_like(k)
        else:
            den, e2 = 1.0 - np.exp(-2.0 * k * depth), np.exp(-2.0 * k * depth)
        lim = np.log(SKIP_DEPTH * V.sum() / (2.0 * V / den)) / k
        np.testing.assert_allclose(spec.profile_den, den, rtol=1e-13)
        np.testing.assert_allclose(spec.profile_e2, e2, rtol=1e-13, atol=0.0)
        np.testing.assert_allclose(spec.skip_below, lim, rtol=1e-12)
