"""The compiled joint march (rfesim.model.march.march_joints, run by
rfesim.model.compile._Curve._march) against the numpy code it replaced, kept here as the
slow readable reference: the joints are bit-identical on random polylines (repeated
points, starts off the curve, marching past its end, overflow, NaN) and a bundled riser
scenario's model (reference positions and rotations) is the same to the last bit.

The reference's 3-vector dots are ``_dot3`` (the fused chain, checked exactly in rational
arithmetic below), not numpy's ``@``: numpy's dot is OpenBLAS's, whose kernel depends on the
CPU and rounds the last bit differently on some (the march kernel keeps one arithmetic on
every machine, rfesim.model.march)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.model import compile as compile_module
from rfesim.model.compile import _Curve, compile_scenario
from rfesim.model.march import _dot3, march_joints

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


# ----------------------------------------------------------------------------- reference
# rfesim.model.compile._Curve._march and _last_direction before the kernel, verbatim but for
# the 3-vector dots (numpy's @ and the 1-D np.linalg.norm, sqrt(x @ x)), which are dot() and
# norm() below: the fused chain of the machine the kernel was written on

def dot(a, b) -> float:
    return _dot3(a[0], a[1], a[2], b[0], b[1], b[2])


def norm(a) -> float:
    return float(np.sqrt(dot(a, a)))


def reference_last_direction(X: np.ndarray) -> np.ndarray:
    """Unit direction of the curve's last segment of nonzero length."""
    d = np.diff(X, axis=0)
    n = np.linalg.norm(d, axis=1)
    k = np.nonzero(n > 0.0)[0]
    return d[k[-1]] / n[k[-1]] if k.size else np.array([1.0, 0.0, 0.0])


def reference_march(X: np.ndarray, start: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Joint points from ``start`` along the polyline, each at the given straight
    distance from the previous one (sphere-polyline intersections, moving forward)."""
    pts = np.empty((lengths.size + 1, 3))
    pts[0] = start
    seg = 0
    for i, ell in enumerate(lengths):
        c = pts[i]
        found = None
        while seg < X.shape[0] - 1:
            p0, p1 = X[seg], X[seg + 1]
            d = p1 - p0
            if not dot(d, d) > 0.0:
                seg += 1              # a repeated point (a curve with its slack bunched up)
                continue
            if norm(p1 - c) >= ell:
                # solve |p0 + u d - c| = ell for the largest u in [0, 1]
                f = p0 - c
                a = dot(d, d)
                b = dot(2.0 * f, d)
                cc = dot(f, f) - ell * ell
                disc = max(b * b - 4 * a * cc, 0.0)
                u = (-b + np.sqrt(disc)) / (2 * a)
                found = p0 + min(max(u, 0.0), 1.0) * d
                break
            seg += 1
        if found is None:          # past the end of the curve: continue straight
            found = c + ell * reference_last_direction(X)
        pts[i + 1] = found
    return pts


def _kernel(X, start, lengths):
    return _Curve(np.arange(X.shape[0], dtype=float), X)._march(start, lengths)


def _random_polyline(rng):
    m = int(rng.integers(2, 60))
    X = np.cumsum(rng.standard_normal((m, 3)) * rng.uniform(0.01, 100.0), axis=0)
    if rng.random() < 0.5:                     # repeated points (slack bunched up)
        rep = rng.integers(0, m, size=int(rng.integers(1, 6)))
        X = np.insert(X, rep, X[rep], axis=0)
    if rng.random() < 0.3:                     # far from the origin
        X = X + rng.uniform(-1e4, 1e4, 3)
    return X


# ----------------------------------------------------------------------------- tests

def test_dot3_is_numpys_dot_to_rounding():
    """numpy's x @ y of 3-vectors is OpenBLAS's ddot, whose rounding depends on the CPU's
    kernel: _dot3 is the same number to within the rounding of a 3-term sum."""
    rng = np.random.default_rng(11)
    x = rng.standard_normal((20000, 3)) * rng.uniform(1e-3, 1e3, (20000, 1))
    y = rng.standard_normal((20000, 3))
    got = np.array([_dot3(*a, *b) for a, b in zip(x, y)])
    want = np.array([a @ b for a, b in zip(x, y)])
    bound = 4.0 * np.finfo(float).eps * np.sum(np.abs(x * y), axis=1)
    assert np.all(np.abs(got - want) <= bound)
    # a wrong pairing of the components is far outside that bound
    swapped = np.array([_dot3(a[0], a[2], a[1], *b) for a, b in zip(x[:200], y[:200])])
    assert np.count_nonzero(np.abs(swapped - want[:200]) > bound[:200]) > 190


def test_dot3_is_the_fused_chain_exactly():
    """Machine-independent: _dot3 is fma(y2, x2, fma(y1, x1, y0 x0)), each step rounded once
    (exact rational arithmetic, correctly rounded by float(Fraction))."""
    from fractions import Fraction

    def fma(a, b, c):
        return float(Fraction(a) * Fraction(b) + Fraction(c))

    rng = np.random.default_rng(5)
    for a, b in zip(rng.standard_normal((2000, 3)) * 1e3, rng.standard_normal((2000, 3))):
        a, b = [float(v) for v in a], [float(v) for v in b]
        want = fma(b[2], a[2], fma(b[1], a[1], fma(b[0], a[0], 0.0)))
        assert _dot3(*a, *b) == want


def test_kernel_is_the_reference_on_random_polylines():
    rng = np.random.default_rng(2026)
    past_end = 0
    for _ in range(1500):
        X = _random_polyline(rng)
        n = int(rng.integers(1, 100))
        lengths = rng.uniform(0.01, 3.0, size=n) * rng.uniform(0.1, 10.0)
        start = X[0] if rng.random() < 0.7 else X[0] + rng.standard_normal(3)
        want = reference_march(X, start, lengths)
        got = _kernel(X, start, lengths)
        assert got.shape == want.shape
        assert np.array_equal(got, want)
        past_end += lengths.sum() > np.linalg.norm(np.diff(X, axis=0), axis=1).sum()
    assert past_end > 100         # many of them march past the end of the curve


@pytest.mark.parametrize("X, start, lengths", [
    # slack bunched up at the end (tests/unit/test_statics_hints.py)
    ([[0.0, 0, 0], [1, 0, 0], [1, 0, 0], [1, 0, 0]], [0.0, 0, 0], [0.75, 0.75, 0.75]),
    # repeated points at the start and in the middle
    ([[0.0, 0, 0], [0, 0, 0], [0, 1, 0], [0, 1, 0], [0, 1, 0], [2, 1, 1]], [0.0, 0, 0], [0.3] * 12),
    # every point the same: straight on along x
    ([[1.0, 2, 3]] * 4, [1.0, 2, 3], [0.5, 0.25]),
    # a two-point curve, a zero step, a start off the curve, steps longer than the curve
    ([[0.0, 0, 0], [3, 4, 0]], [0.1, -0.2, 0.3], [0.0, 1.0, 7.0, 0.0, 2.5]),
    # squares that overflow (NaN joints, as before)
    ([[0.0, 0, 0], [1e160, 1e160, 0], [2e160, 0, 0]], [0.0, 0, 0], [1e159, 1e160]),
    # a NaN point in the curve
    ([[0.0, 0, 0], [1, 0, 0], [np.nan, 0, 0], [3, 0, 0], [4, 1, 0]], [0.0, 0, 0], [0.4] * 12),
    # no steps
    ([[0.0, 0, 0], [1, 0, 0]], [0.0, 0, 0], []),
])
def test_kernel_is_the_reference_on_edge_cases(X, start, lengths):
    X, start, lengths = np.array(X, float), np.array(start, float), np.array(lengths, float)
    with np.errstate(all="ignore"):
        want = reference_march(X, start, lengths)
        got = _kernel(X, start, lengths)
    assert got.shape == want.shape == (lengths.size + 1, 3)
    assert np.array_equal(got, want, equal_nan=True)


@pytest.mark.parametrize("name", ["catenary_riser.json", "s_lay.json"])
def test_bundled_model_is_the_same_as_with_the_reference(name, monkeypatch):
    sc = rfesim.load_scenario(SCENARIOS / name)
    model = compile_scenario(sc)
    calls = []

    def march(self, start, lengths, direction=None):
        calls.append(lengths.size)
        return reference_march(self.X, start, lengths)

    monkeypatch.setattr(compile_module._Curve, "_march", march)
    slow = compile_scenario(sc)
    assert len(calls) > 3                      # the secant on the closing strain ran
    assert np.array_equal(model.initial.ref.X, slow.initial.ref.X)
    assert np.array_equal(model.initial.ref.R, slow.initial.ref.R)
    assert np.array_equal(model.initial.q, slow.initial.q)


def test_march_joints_takes_float_arrays_directly():
    X = np.array([[0.0, 0.0, 0.0], [4.0, 3.0, 0.0], [4.0, 3.0, 5.0]])
    pts = march_joints(X, X[0], np.array([2.5, 2.5, 5.0, 1.0]), np.array([0.0, 0.0, 1.0]))
    # a 3-4-5 triangle: exactly on the polyline at 2.5, 5 and 10 m, then 1 m past its end
    assert np.array_equal(pts, [[0.0, 0.0, 0.0], [2.0, 1.5, 0.0], [4.0, 3.0, 0.0], [4.0, 3.0, 5.0],
                                [4.0, 3.0, 6.0]])
