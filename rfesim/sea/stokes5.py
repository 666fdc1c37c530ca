"""Stokes fifth-order regular waves (Fenton 1985, "A fifth-order Stokes theory for steady
waves", J. Waterway Port Coastal Ocean Eng. 111, 216-234; coefficients as corrected in
Fenton 1990, "Nonlinear wave theories", The Sea 9).

With k the wave number, d the depth, S = sech(2kd), eps = kH/2 and the phase
theta = omega t - k x (x along the direction of travel) + phase, and zero Eulerian mean
current (the waves do not carry a mean current at a fixed point):

* elevation above the mean level (Fenton's eq. 14)::

    k eta = eps cos(th) + eps^2 B22 cos(2 th) + eps^3 B31 (cos th - cos 3 th)
            + eps^4 (B42 cos 2 th + B44 cos 4 th)
            + eps^5 (-(B53 + B55) cos th + B53 cos 3 th + B55 cos 5 th)

  so that crest minus trough is 2 eps / k = H exactly (the odd harmonics cancel in pairs);
* horizontal particle velocity (the x-derivative of Fenton's potential, eq. 13)::

    u = C0 sqrt(g/k^3) sum_i eps^i sum_j A_ij j k cosh(j k (z + d)) cos(j th)

  with w the matching vertical velocity (sinh, sin);
* dispersion (eq. 19 with zero Eulerian current): c sqrt(k/g) = C0 + eps^2 C2 + eps^4 C4,
  omega = k c, solved for k given the period.

Harmonic j is then a component of the linear kernel (rfesim.sea.kernel) with wave number
j k, frequency j omega, phase j phase, elevation amplitude E_j / k and velocity coefficient
V_j = C0 sqrt(g/k) j sum_i eps^i A_ij sinh(j k d): its u = V_j cosh(jk(z+d))/sinh(jkd) cos.
The products A_ij sinh(j k d) are written in S and tanh(2kd) alone (the sinh factors cancel
exactly), so deep water is the limit S -> 0 without overflow.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def _S(kd: float) -> float:
    """sech(2 kd) without overflow."""
    e = math.exp(-2.0 * kd) if kd < 350.0 else 0.0
    return 2.0 * e / (1.0 + e * e)


@dataclass(frozen=True)
class FentonCoefficients:
    """Fenton's (1985) dimensionless coefficients at kd (Table 1)."""
    kd: float
    S: float
    C0: float
    C2: float
    C4: float
    B22: float
    B31: float
    B42: float
    B44: float
    B53: float
    B55: float
    # A_ij sinh(j k d), keyed (i, j)
    Ah: dict


def coefficients(kd: float) -> FentonCoefficients:
    if not kd > 0.0:
        raise ValueError(f"kd must be > 0, got {kd}")
    S = _S(kd)
    th = math.tanh(kd)
    th2 = math.tanh(2.0 * kd)
    coth = 1.0 / th
    m = 1.0 - S
    C0 = math.sqrt(th)
    C2 = C0 * (2.0 + 7.0 * S ** 2) / (4.0 * m ** 2)
    C4 = C0 * (4.0 + 32.0 * S - 116.0 * S ** 2 - 400.0 * S ** 3 - 71.0 * S ** 4 + 146.0 * S ** 5) / (32.0 * m ** 5)
    B22 = coth * (1.0 + 2.0 * S) / (2.0 * m)
    B31 = -3.0 * (1.0 + 3.0 * S + 3.0 * S ** 2 + 2.0 * S ** 3) / (8.0 * m ** 3)
    B42 = coth * (6.0 - 26.0 * S - 182.0 * S ** 2 - 204.0 * S ** 3 - 25.0 * S ** 4 + 26.0 * S ** 5) \
        / (6.0 * (3.0 + 2.0 * S) * m ** 4)
    B44 = coth * (24.0 + 92.0 * S + 122.0 * S ** 2 + 66.0 * S ** 3 + 67.0 * S ** 4 + 34.0 * S ** 5) \
        / (24.0 * (3.0 + 2.0 * S) * m ** 4)
    d5 = (3.0 + 2.0 * S) * (4.0 + S) * m ** 6
    B53 = 9.0 * (132.0 + 17.0 * S - 2216.0 * S ** 2 - 5897.0 * S ** 3 - 6292.0 * S ** 4 - 2687.0 * S ** 5
                 + 194.0 * S ** 6 + 467.0 * S ** 7 + 82.0 * S ** 8) / (128.0 * d5)
    B55 = 5.0 * (300.0 + 1579.0 * S + 3176.0 * S ** 2 + 2949.0 * S ** 3 + 1188.0 * S ** 4 + 675.0 * S ** 5
                 + 1326.0 * S ** 6 + 827.0 * S ** 7 + 130.0 * S ** 8) / (384.0 * d5)
    # A_ij sinh(jkd): sinh(2kd) = tanh(2kd)/S, sinh(3kd)/sinh(kd) = 1 + 2/S,
    # sinh(4kd) = 2 tanh(2kd)/S^2, sinh(5kd)/sinh(kd) = (4 + 2S - S^2)/S^2
    Ah = {
        (1, 1): 1.0,
        (3, 1): (-4.0 - 20.0 * S + 10.0 * S ** 2 - 13.0 * S ** 3) / (8.0 * m ** 3),
        (5, 1): (-1184.0 + 32.0 * S + 13232.0 * S ** 2 + 21712.0 * S ** 3 + 20940.0 * S ** 4 + 12554.0 * S ** 5
                 - 500.0 * S ** 6 - 3341.0 * S ** 7 - 670.0 * S ** 8) / (64.0 * d5),
        (2, 2): 3.0 * S * th2 / (2.0 * m ** 2),
        (4, 2): (12.0 - 14.0 * S - 264.0 * S ** 2 - 45.0 * S ** 3 - 13.0 * S ** 4) * th2 / (24.0 * m ** 5),
        (3, 3): (-2.0 * S + 11.0 * S ** 2) * (S + 2.0) / (8.0 * m ** 3),
        (5, 3): (4.0 + 105.0 * S + 198.0 * S ** 2 - 1376.0 * S ** 3 - 1302.0 * S ** 4 - 117.0 * S ** 5
                 + 58.0 * S ** 6) * (S + 2.0) / (32.0 * (3.0 + 2.0 * S) * m ** 6),
        (4, 4): (10.0 * S - 174.0 * S ** 2 + 291.0 * S ** 3 + 278.0 * S ** 4) * 2.0 * th2
                / (48.0 * (3.0 + 2.0 * S) * m ** 5),
        (5, 5): (-6.0 * S + 272.0 * S ** 2 - 1552.0 * S ** 3 + 852.0 * S ** 4 + 2029.0 * S ** 5 + 430.0 * S ** 6)
                * (4.0 + 2.0 * S - S ** 2) / (64.0 * d5),
    }
    return FentonCoefficients(kd, S, C0, C2, C4, B22, B31, B42, B44, B53, B55, Ah)


@dataclass(frozen=True)
class StokesWave:
    """A solved Stokes 5th-order wave: k, omega and the five harmonics."""
    height: float
    period: float
    depth: float                # inf: deep water
    wavenumber: float           # k of the fundamental, 1/m
    omega: float                # 2 pi / period
    celerity: float             # omega / k, m/s
    eps: float                  # k H / 2
    elevation: np.ndarray       # (5,) m, amplitude of cos(j theta) in eta
    velocity: np.ndarray        # (5,) m/s, V_j (u_j = V_j cosh(jk(z+d))/sinh(jkd) cos(j theta))

    @property
    def wavelength(self) -> float:
        return 2.0 * math.pi / self.wavenumber


def _harmonics(k: float, H: float, depth: float, g: float):
    kd = k * depth if math.isfinite(depth) else math.inf
    c = coefficients(min(kd, 400.0))
    e = 0.5 * k * H
    E = np.array([e + e ** 3 * c.B31 - e ** 5 * (c.B53 + c.B55),
                  e ** 2 * c.B22 + e ** 4 * c.B42,
                  -e ** 3 * c.B31 + e ** 5 * c.B53,
                  e ** 4 * c.B44,
                  e ** 5 * c.B55])
    A = c.Ah
    s = [e * A[1, 1] + e ** 3 * A[3, 1] + e ** 5 * A[5, 1],
         e ** 2 * A[2, 2] + e ** 4 * A[4, 2],
         e ** 3 * A[3, 3] + e ** 5 * A[5, 3],
         e ** 4 * A[4, 4],
         e ** 5 * A[5, 5]]
    V = c.C0 * math.sqrt(g / k) * np.array([(j + 1) * s[j] for j in range(5)])
    speed = (c.C0 + e ** 2 * c.C2 + e ** 4 * c.C4) * math.sqrt(g / k)
    return E / k, V, speed, e


def stokes5(height: float, period: float, depth: float | None, gravity: float = 9.81) -> StokesWave:
    """Solve the Stokes 5th-order wave of ``height`` (crest to trough) and ``period`` in water
    of ``depth`` (None/inf: deep). Raises ValueError where the theory does not apply: a wave
    steeper than the breaking limit (H/L > 0.142 tanh(kd)) or in too shallow water
    (Ursell number H L^2 / d^3 > 40, where cnoidal theory is the right one)."""
    if not (height > 0.0 and period > 0.0):
        raise ValueError("height and period must be > 0")
    h = math.inf if depth is None or not math.isfinite(depth) else float(depth)
    omega = 2.0 * math.pi / period

    def f(k):
        _, _, speed, _ = _harmonics(k, height, h, gravity)
        return k * speed - omega

    # the linear wave number, then a bracketed root of the nonlinear dispersion
    from .waves import wave_number
    k0 = float(wave_number(omega, None if math.isinf(h) else h, gravity))
    lo, hi = 0.5 * k0, 1.2 * k0
    flo, fhi = f(lo), f(hi)
    if not (flo < 0.0 < fhi):
        raise ValueError(f"no Stokes 5th-order solution for H = {height} m, T = {period} s, depth = {h} m "
                         f"(too steep or too shallow)")
    for _ in range(200):                      # bisection + secant (Illinois): robust and fast
        k = hi - fhi * (hi - lo) / (fhi - flo)
        fk = f(k)
        if abs(fk) <= 1e-14 * omega or hi - lo <= 1e-15 * k:
            break
        if fk > 0.0:
            hi, fhi = k, fk
            flo *= 0.5
        else:
            lo, flo = k, fk
            fhi *= 0.5
    L = 2.0 * math.pi / k
    kd = k * h
    if height / L > 0.142 * math.tanh(min(kd, 50.0)):
        raise ValueError(f"H/L = {height / L:.4f} is beyond the breaking limit 0.142 tanh(kd) = "
                         f"{0.142 * math.tanh(min(kd, 50.0)):.4f}")
    if math.isfinite(h) and height * L * L / h ** 3 > 40.0:
        raise ValueError(f"Ursell number H L^2/d^3 = {height * L * L / h ** 3:.1f} > 40: shallow-water waves "
                         f"are outside Stokes theory (use cnoidal or stream-function waves)")
    E, V, speed, eps = _harmonics(k, height, h, gravity)
    return StokesWave(height, period, h, k, omega, speed, eps, E, V)


def elevation(w: StokesWave, theta):
    """eta (m above the mean level) at phase(s) theta."""
    theta = np.asarray(theta, float)
    return sum(w.elevation[j] * np.cos((j + 1) * theta) for j in range(5))


def velocity(w: StokesWave, theta, z):
    """(u, w) at phase theta = omega t - k x + phase and height z above the mean level (below
    the surface), from the harmonics (readable form, used by the tests)."""
    theta = np.asarray(theta, float)
    z = np.asarray(z, float)
    u = np.zeros(np.broadcast(theta, z).shape)
    v = np.zeros_like(u)
    for j in range(5):
        kj = (j + 1) * w.wavenumber
        if math.isinf(w.depth):
            C = S = np.exp(kj * z)
        else:
            C = np.cosh(kj * (z + w.depth)) / np.sinh(kj * w.depth)
            S = np.sinh(kj * (z + w.depth)) / np.sinh(kj * w.depth)
        u = u + w.velocity[j] * C * np.cos((j + 1) * theta)
        v = v - w.velocity[j] * S * np.sin((j + 1) * theta)
    return u, v
