"""Small numba helpers for interpolation in sorted tables."""
from __future__ import annotations

from numba import njit


@njit(cache=True)
def bracket(xs, x):
    """Index ``lo`` with ``xs[lo] <= x < xs[lo + 1]`` by bisection in ascending ``xs``
    (n >= 2); the caller handles ``x`` at or beyond the ends."""
    lo = 0
    hi = xs.shape[0] - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if xs[mid] <= x:
            lo = mid
        else:
            hi = mid
    return lo
