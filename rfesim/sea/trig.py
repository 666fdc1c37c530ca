"""Sine and cosine of a wave phase together, compiled inline (docs/theory.md, 'Sine and cosine
of the wave phases').

The sea sum evaluates, at every wet point and every residual evaluation, the cosine and the
sine of each wave component's phase omega t - k.x + phi: 2 x 200 calls of the C library per
point in the crane bench, where the library's sin and cos each save and restore the
floating-point rounding mode and reduce the argument on their own. ``sincos(theta)`` reduces
the argument once, theta = n pi/2 + r with |r| <= pi/4 (pi/2 in three parts, Cody and Waite,
so that n * part 1 is exact for |n| < 2**20), and sums the Taylor series of sin r and cos r to
r**15 and r**16 (the first terms left out are below 5e-17 at |r| = pi/4). The error against
the library is a few units in the last place of the result; for |theta| beyond LARGE the
library's own functions are used.
"""
from __future__ import annotations

import math
from decimal import Decimal, getcontext

from numba import njit

# pi / 2 to 60 digits (pi = 3.14159265358979323846264338327950288419716939937510582097494...)
getcontext().prec = 80
_HALF_PI = Decimal("3.141592653589793238462643383279502884197169399375105820974944592") / 2


def _split(value: Decimal, bits: int) -> float:
    """``value`` rounded toward zero to a float of at most ``bits`` significant bits."""
    m, e = math.frexp(float(value))
    scale = 2.0 ** bits
    return math.ldexp(math.trunc(m * scale) / scale, e)


PIO2_1 = _split(_HALF_PI, 33)                        # n * PIO2_1 exact for |n| < 2**20
PIO2_2 = _split(_HALF_PI - Decimal(PIO2_1), 33)
PIO2_3 = float(_HALF_PI - Decimal(PIO2_1) - Decimal(PIO2_2))
TWO_OVER_PI = float(1 / _HALF_PI)
LARGE = 1.0e6                                        # |theta| beyond: the library's sin and cos

# Taylor coefficients (-1)^m / (2m+1)! and (-1)^m / (2m)!
S1, S2, S3, S4 = -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0
S5, S6, S7 = -1.0 / 39916800.0, 1.0 / 6227020800.0, -1.0 / 1307674368000.0
C1, C2, C3, C4 = -0.5, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0
C5, C6, C7, C8 = -1.0 / 3628800.0, 1.0 / 479001600.0, -1.0 / 87178291200.0, 1.0 / 20922789888000.0


@njit(cache=True, fastmath={'contract'}, inline='always')
def sincos_reduced(theta):
    """(sin theta, cos theta) for |theta| < LARGE (not checked): no branch and no call, so
    that a loop over wave components compiles to vector instructions."""
    n = math.floor(theta * TWO_OVER_PI + 0.5)
    r = ((theta - n * PIO2_1) - n * PIO2_2) - n * PIO2_3
    z = r * r
    s = r + r * z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * (S6 + z * S7))))))
    c = 1.0 + z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * (C6 + z * (C7 + z * C8)))))))
    q = int(n) & 3
    # the quadrant by selects, not branches (its value is random from one component to the next)
    sn = c if q & 1 else s
    cs = s if q & 1 else c
    if q & 2:
        sn = -sn
    if (q + 1) & 2:
        cs = -cs
    return sn, cs


@njit(cache=True, inline='always')
def sincos(theta):
    """(sin theta, cos theta) for any theta."""
    if not abs(theta) < LARGE:                       # also NaN and inf
        return math.sin(theta), math.cos(theta)
    return sincos_reduced(theta)


@njit(cache=True, fastmath={'contract'})
def phase_sincos_into(omega, wavenumber, cos_direction, sin_direction, phase, t, x, y, bound, sth, cth):
    """sth[j], cth[j] = sin, cos of the phase omega_j t - k_j (x cos b_j + y sin b_j) + phi_j of
    every wave component at the point (x, y) at time t. ``bound`` is an upper bound of every
    |phase| (the caller's |t| max|omega| + (|x| + |y|) max k + max|phi|): below LARGE the loop
    runs on vector instructions, else through the library's functions."""
    nc = omega.shape[0]
    if bound < LARGE:
        for j in range(nc):
            th = omega[j] * t - wavenumber[j] * (x * cos_direction[j] + y * sin_direction[j]) + phase[j]
            sth[j], cth[j] = sincos_reduced(th)
    else:
        for j in range(nc):
            th = omega[j] * t - wavenumber[j] * (x * cos_direction[j] + y * sin_direction[j]) + phase[j]
            sth[j], cth[j] = sincos(th)
