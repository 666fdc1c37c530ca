"""rfesim.sea.trig.sincos (the wave phases' sine and cosine with one argument reduction)
against the C library's math.sin and math.cos, the slow readable reference: a few units in
the last place over the phases a long run reaches, the quadrant boundaries, the reduction's
constants, and the library's fallback beyond LARGE."""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from numba import njit

from rfesim.sea import trig
from rfesim.sea.trig import LARGE, PIO2_1, PIO2_2, PIO2_3, sincos

# pi / 2 to 40 digits, independent of the module's own string
HALF_PI = Fraction("1.5707963267948966192313216916397514420985")


@njit(cache=True)
def _many(theta, s, c):
    for i in range(theta.shape[0]):
        s[i], c[i] = sincos(theta[i])


def _compare(theta):
    s = np.empty_like(theta)
    c = np.empty_like(theta)
    _many(theta, s, c)
    ref_s = np.array([math.sin(v) for v in theta])
    ref_c = np.array([math.cos(v) for v in theta])
    return np.abs(s - ref_s).max(), np.abs(c - ref_c).max()


@pytest.mark.parametrize("scale", [1.0, 10.0, 1.0e3, 3.0e4, 9.0e5])
def test_sincos_matches_the_library(scale):
    theta = np.random.default_rng(int(scale)).uniform(-scale, scale, 20000)
    es, ec = _compare(theta)
    assert es <= 3e-16 and ec <= 3e-16, (es, ec)


def test_sincos_at_the_quadrant_boundaries_and_exact_values():
    n = np.arange(-2000, 2001, dtype=np.float64)
    edges = np.concatenate([n * (math.pi / 4), n * (math.pi / 2), np.nextafter(n * (math.pi / 4), np.inf),
                            np.nextafter(n * (math.pi / 4), -np.inf)])
    es, ec = _compare(edges)
    assert es <= 3e-16 and ec <= 3e-16, (es, ec)
    assert sincos(0.0) == (0.0, 1.0)
    s, c = sincos(-1e-300)
    assert s == -1e-300 and c == 1.0


def test_the_split_of_half_pi():
    # the three parts sum to pi/2 far below a double's resolution; the first two carry at most
    # 33 significant bits, so n * part for |n| < 2**20 is exact
    total = Fraction(PIO2_1) + Fraction(PIO2_2) + Fraction(PIO2_3)
    assert abs(total - HALF_PI) < Fraction(1, 10 ** 36)
    for part in (PIO2_1, PIO2_2):
        m, _ = math.frexp(part)
        assert (m * 2.0 ** 33).is_integer()
    assert trig.TWO_OVER_PI == float(1 / HALF_PI)


def test_beyond_large_and_not_finite_use_the_library():
    for v in (LARGE * 1.5, -LARGE * 7.3, 1e300):
        assert sincos(v) == (math.sin(v), math.cos(v))
    s, c = sincos(float("nan"))
    assert math.isnan(s) and math.isnan(c)
    s, c = sincos(float("inf"))
    assert math.isnan(s) and math.isnan(c)


@pytest.mark.parametrize("t, x, y", [(1234.5, 310.0, -42.0), (5.0e5, 1.0e3, 2.0e3)])
def test_phase_sincos_into_on_both_paths(t, x, y):
    """The component loop (rfesim.sea.trig.phase_sincos_into) against numpy's sin and cos of
    the same phases: on the vector path (bound below LARGE) and on the library's path (a
    bound above it, as the caller gives for late times or far points)."""
    from rfesim.sea.trig import phase_sincos_into
    rng = np.random.default_rng(5)
    nc = 200
    omega = rng.uniform(0.3, 3.0, nc)
    k = omega ** 2 / 9.81
    b = rng.uniform(-math.pi, math.pi, nc)
    cb, sb = np.cos(b), np.sin(b)
    phase = rng.uniform(0.0, 2.0 * math.pi, nc)
    theta = omega * t - k * (x * cb + y * sb) + phase
    bound = abs(t) * omega.max() + (abs(x) + abs(y)) * k.max() + phase.max()
    assert np.all(np.abs(theta) <= bound)
    s = np.empty(nc)
    c = np.empty(nc)
    phase_sincos_into(omega, k, cb, sb, phase, t, x, y, bound, s, c)
    # the kernel's phase may differ from numpy's by a rounding of theta (fused multiply-adds)
    tol = 3e-16 + 4.0 * np.spacing(np.abs(theta))
    assert np.all(np.abs(s - np.sin(theta)) <= tol)
    assert np.all(np.abs(c - np.cos(theta)) <= tol)
    assert (bound < LARGE) == (t < 1.0e5)
