"""Compiled sea kinematics: the waves and current of a scene packed for numba kernels.

``sea_spec(environment)`` packs the wave components (:mod:`rfesim.sea.waves`) and the
current profile (:mod:`rfesim.sea.current`) into a :class:`SeaSpec` of arrays and floats;
``sea_kinematics_into(ss, t, points, eta, vel, acc)`` fills, at each point,

* ``eta``: the absolute z of the free surface above the point's (x, y):
  surface_level + r(t) sum a cos(theta);
* ``vel``: the water particle velocity, waves plus current;
* ``acc``: the local wave particle acceleration du/dt (the current is steady in space;
  its time factor is slow and not differentiated), including the ramp-rate term r'(t) u.

Stretching of the wave kinematics (z' = height above still water of the point, eta the
local elevation; above the instantaneous surface every method uses the value AT the
surface, z' -> eta):

* ``wheeler`` (code 1, default): the Airy expressions at z_s = h (z' - eta) / (h + eta)
  (deep water: z' - eta), which maps the wetted column [-h, eta] onto [-h, 0];
* ``none`` (0): the Airy expressions at the actual z' (exponential growth above z' = 0);
* ``vertical`` (2): held at their still-water-level value above z' = 0;
* ``linear`` (3): linear (Taylor) extrapolation above z' = 0, u(z') = u(0) + z' du/dz(0).

Under every method the acceleration is the Airy local acceleration at the same
(stretched) height: the term of d z_s/dt in the Wheeler mapping is left out, as usual.
Points below the seabed take the seabed value. The current is evaluated at min(z, surface).

Cut-off at depth (``kinematics_cutoff`` of the waves, default 0: off): a point below the
lowest possible surface (still water minus r(t) sum |a_w|) whose highest possible stretched
height is below ``deep_z`` gets zero wave velocity and acceleration and ``eta`` = the
still-water level (the elevation is not summed there: the point is under water whatever it
is, and nothing else uses it). ``deep_z`` bounds all components together below the cut-off
fraction of the sea's velocity bound (:func:`deep_cutoff_height`).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..interp import bracket
from .current import current_profile
from .trig import phase_sincos_into
from .waves import STRETCHING_CODES, wave_components, water_depth


class SeaSpec(NamedTuple):
    has_waves: bool
    amplitude: np.ndarray       # (nc,) m, wave component amplitudes (elevation)
    velocity: np.ndarray        # (nc,) m/s, velocity coefficient: u = velocity C cos, w = -velocity S sin
                                #   (a omega for a linear component; the harmonic's own for Stokes 5th)
    omega: np.ndarray           # (nc,) rad/s
    wavenumber: np.ndarray      # (nc,) 1/m
    phase: np.ndarray           # (nc,) rad
    cos_direction: np.ndarray   # (nc,) cos of the direction of travel (toward) from global x
    sin_direction: np.ndarray   # (nc,)
    depth: float                # m, still water depth (inf: deep water)
    surface_level: float        # m, z of the still water surface
    stretching: int             # 0 none, 1 wheeler, 2 vertical, 3 linear
    ramp: float                 # s, cosine ramp-in of the waves (0: none)
    has_current: bool
    current_z: np.ndarray       # (m,) m, absolute z of the profile points, ascending
    current_speed: np.ndarray   # (m,) m/s
    current_cos: float          # cos of the current direction (toward) from global x
    current_sin: float
    current_time: np.ndarray    # (p,) s, time-factor table (empty: factor 1)
    current_factor: np.ndarray  # (p,) -
    elevation_bound: float      # m, sum |a_w|: no surface elevation exceeds it
    deep_z: float               # m, stretched height (from still water) below which every component together
                                #   is below the kinematics cut-off (-inf: no cut-off)
    profile_den: np.ndarray     # (nc,) 1 - exp(-2 k h) (1 in deep water): the finite-depth profiles' denominator
    profile_e2: np.ndarray      # (nc,) exp(-2 k h) (0 in deep water)
    skip_below: np.ndarray      # (nc,) m, stretched height below which the component is below SKIP_DEPTH of the
                                #   sea's velocity bound (not evaluated; inf: never evaluated)


def deep_cutoff_height(waves, cutoff: float) -> float:
    """Stretched height z (from still water) below which the bound of all wave components
    together, sum_j 2 |u_j| (1 + omega_j) exp(k_j z) / (1 - exp(-2 k_j h)), is below
    ``cutoff`` times the sea's bound sum |u_j| (1 + omega_j) (the bound of the per-component
    skip of ``sea_kinematics_into`` summed over the components); -inf for no cut-off."""
    nc = waves.amplitude.size
    if cutoff <= 0.0 or nc == 0:
        return -math.inf
    k = np.asarray(waves.wavenumber, float)
    V = np.abs(waves.velocity_coefficients()) * (1.0 + np.asarray(waves.omega, float))
    vref = float(V.sum())
    if vref <= 0.0 or np.any(k <= 0.0):
        return -math.inf
    h = float(waves.depth)
    den = np.ones(nc) if math.isinf(h) else -np.expm1(-2.0 * k * h)
    coef = 2.0 * V / den

    def bound(z):
        return float(np.sum(coef * np.exp(k * z)))

    target = cutoff * vref
    lo = -h if not math.isinf(h) else -1e6
    if bound(lo) >= target:
        return -math.inf             # not even at the seabed
    hi = 0.0
    if bound(hi) <= target:
        return 0.0
    for _ in range(200):              # bisection: the bound rises with z
        mid = 0.5 * (lo + hi)
        if bound(mid) < target:
            lo = mid
        else:
            hi = mid
    return lo


def pack_sea(waves, current, surface_level: float, kinematics_cutoff: float = 0.0) -> SeaSpec:
    """A SeaSpec from :class:`WaveComponents` and :class:`CurrentProfile` objects;
    ``kinematics_cutoff`` as in :func:`deep_cutoff_height` (0: none)."""
    nc = waves.amplitude.size
    has_current = current.z.size > 0
    velocity = np.ascontiguousarray(waves.velocity_coefficients(), dtype=np.float64)
    omega = np.ascontiguousarray(waves.omega, dtype=np.float64)
    wavenumber = np.ascontiguousarray(waves.wavenumber, dtype=np.float64)
    return SeaSpec(
        has_waves=bool(nc > 0),
        amplitude=np.ascontiguousarray(waves.amplitude, dtype=np.float64),
        velocity=velocity,
        omega=omega,
        wavenumber=wavenumber,
        phase=np.ascontiguousarray(waves.phase, dtype=np.float64),
        cos_direction=np.ascontiguousarray(np.cos(waves.direction), dtype=np.float64),
        sin_direction=np.ascontiguousarray(np.sin(waves.direction), dtype=np.float64),
        depth=float(waves.depth),
        surface_level=float(surface_level),
        stretching=int(STRETCHING_CODES[waves.stretching]),
        ramp=float(waves.ramp_duration),
        has_current=bool(has_current),
        current_z=np.ascontiguousarray(current.z, dtype=np.float64),
        current_speed=np.ascontiguousarray(current.speed, dtype=np.float64),
        current_cos=math.cos(current.direction) if has_current else 1.0,
        current_sin=math.sin(current.direction) if has_current else 0.0,
        current_time=np.ascontiguousarray(current.time, dtype=np.float64),
        current_factor=np.ascontiguousarray(current.factor, dtype=np.float64),
        elevation_bound=float(np.abs(waves.amplitude).sum()) if nc > 0 else 0.0,
        deep_z=float(deep_cutoff_height(waves, kinematics_cutoff)),
        **_component_constants(velocity, omega, wavenumber, float(waves.depth)),
    )


def _component_constants(velocity, omega, wavenumber, depth: float) -> dict:
    """The per-component constants of the kinematics (``sea_component_constants``), once per sea."""
    nc = velocity.shape[0]
    den, e2, lim = np.empty(nc), np.empty(nc), np.empty(nc)
    if nc > 0:
        sea_component_constants(velocity, omega, wavenumber, depth, den, e2, lim)
    return dict(profile_den=den, profile_e2=e2, skip_below=lim)


def sea_spec(environment) -> SeaSpec:
    """Pack the waves and current of a scenario ``Environment`` (an empty spec without
    water, waves or current: still water at ``surface_level``)."""
    from .current import no_current
    from .waves import no_waves
    water = getattr(environment, "water", None)
    if water is None:
        return pack_sea(no_waves(), no_current(), 0.0)
    waves = wave_components(water.waves, water_depth(environment), environment.gravity) \
        if water.waves is not None else no_waves()
    cutoff = float(getattr(water.waves, "kinematics_cutoff", 0.0) or 0.0) if water.waves is not None else 0.0
    return pack_sea(waves, current_profile(water.current), water.surface_level, cutoff)


@njit(cache=True)
def interp_clamped(xs, ys, x):
    """Linear interpolation in ascending ``xs``, held constant beyond the ends."""
    n = xs.shape[0]
    if x <= xs[0]:
        return ys[0]
    if x >= xs[n - 1]:
        return ys[n - 1]
    lo = bracket(xs, x)
    hi = lo + 1
    f = (x - xs[lo]) / (xs[hi] - xs[lo])
    return ys[lo] + f * (ys[hi] - ys[lo])


SKIP_DEPTH = 1e-17      # a component below this fraction of the sea's velocity bound is skipped


@njit(cache=True)
def sea_component_constants(velocity, omega, wavenumber, h, den, e2, lim):
    """Per wave component (docs/theory.md 'Sea kinematics at depth'): the denominator of the
    finite-depth profiles 1 - exp(-2 k h), exp(-2 k h), and the stretched height ``lim``
    below which the component's velocity and acceleration are below SKIP_DEPTH of the whole
    sea's bound sum |a_w| (1 + omega) (negligible at round-off: it is not evaluated).
    Independent of time and place: packed once with the sea (pack_sea)."""
    nc = velocity.shape[0]
    deep = math.isinf(h)
    vref = 0.0
    for j in range(nc):
        vref += abs(velocity[j]) * (1.0 + omega[j])
    for j in range(nc):
        k = wavenumber[j]
        if deep:
            den[j] = 1.0
            e2[j] = 0.0
        else:
            den[j] = -math.expm1(-2.0 * k * h)
            e2[j] = math.exp(-2.0 * k * h)
        # |C|, |S| <= 2 exp(k z_s) / den for z_s >= -h
        bound = 2.0 * abs(velocity[j]) * (1.0 + omega[j]) / den[j]
        if bound <= 0.0 or k <= 0.0:
            lim[j] = np.inf
        else:
            lim[j] = math.log(SKIP_DEPTH * vref / bound) / k


@njit(cache=True)
def sea_kinematics_into(ss, t, points, eta, vel, acc):
    """Free-surface z, water velocity and wave acceleration at ``points`` (n, 3) at time t."""
    sea_kinematics_reach(ss, t, points, eta, False, eta, vel, acc)


@njit(cache=True)
def crest_bound(ss, t):
    """Height above the still water level that no crest of the sea exceeds at time t: the
    ramp factor times the sum of the component amplitudes."""
    if not ss.has_waves:
        return 0.0
    s = ss.elevation_bound
    if ss.ramp > 0.0 and t < ss.ramp:
        if t <= 0.0:
            return 0.0
        s *= 0.5 * (1.0 - math.cos(math.pi / ss.ramp * t))
    return s


@njit(cache=True, _nrt=True)
def sea_kinematics_reach(ss, t, points, reach, use_reach, eta, vel, acc):
    """sea_kinematics_into; with ``use_reach`` a point whose lowest wettable level,
    z - reach[i], is above the surface is dry: its velocity and acceleration are not
    evaluated (zero) -- above every possible crest (``crest_bound``) not even the
    elevation (eta is then the still water level). The loads of a dry RFE or body do not
    read them (docs/theory.md, 'Sea kinematics of dry RFEs')."""
    n = points.shape[0]
    nc = ss.amplitude.shape[0]
    waves = ss.has_waves and nc > 0
    h = ss.depth
    deep = math.isinf(h)
    code = ss.stretching
    # cosine ramp-in r(t) and its rate
    r = 1.0
    rd = 0.0
    if ss.ramp > 0.0 and t < ss.ramp:
        if t <= 0.0:
            r = 0.0
        else:
            a = math.pi / ss.ramp
            r = 0.5 * (1.0 - math.cos(a * t))
            rd = 0.5 * a * math.sin(a * t)
    factor = 1.0
    if ss.has_current and ss.current_time.shape[0] > 0:
        factor = interp_clamped(ss.current_time, ss.current_factor, t)
    cth = np.empty(nc)
    sth = np.empty(nc)
    # per component, packed once with the sea (sea_component_constants)
    den = ss.profile_den
    e2 = ss.profile_e2
    lim = ss.skip_below
    # kinematics cut-off at depth (docs/theory.md 'Wave kinematics cut-off at depth'): below
    # the surface whatever its elevation (|eta| <= r sum |a_w|), a point whose highest possible
    # stretched height is below ss.deep_z gets no wave kinematics and no elevation sum
    ebound = r * ss.elevation_bound
    cut = waves and ss.deep_z > -np.inf and (deep or h > ebound)
    top = ebound if use_reach else np.inf     # above every crest: dry whatever the waves
    # |phase| <= tbound + (|x| + |y|) kmax at every point (phase_sincos_into)
    tbound = 0.0
    kmax = 0.0
    if waves:
        wmax = 0.0
        pmax = 0.0
        for j in range(nc):
            wmax = max(wmax, abs(ss.omega[j]))
            pmax = max(pmax, abs(ss.phase[j]))
            kmax = max(kmax, abs(ss.wavenumber[j]))
        tbound = abs(t) * wmax + pmax
    for i in range(n):
        x = points[i, 0]
        y = points[i, 1]
        zr = points[i, 2] - ss.surface_level
        if use_reach and zr - reach[i] > top:
            eta[i] = ss.surface_level
            for k in range(3):
                vel[i, k] = 0.0
                acc[i, k] = 0.0
            continue
        e = 0.0
        vx = 0.0
        vy = 0.0
        vz = 0.0
        ax = 0.0
        ay = 0.0
        az = 0.0
        below = False
        if cut and zr < -ebound:
            if code == 1:
                ze_hi = zr + ebound if deep else h * (zr + ebound) / (h - ebound)
            else:
                ze_hi = zr
            below = ze_hi < ss.deep_z
        if waves and not below:
            # sine and cosine of every phase (rfesim.sea.trig, on vector instructions)
            phase_sincos_into(ss.omega, ss.wavenumber, ss.cos_direction, ss.sin_direction, ss.phase, t, x, y,
                              tbound + (abs(x) + abs(y)) * kmax, sth, cth)
            for j in range(nc):
                e += ss.amplitude[j] * cth[j]
            e *= r
            if use_reach and zr - reach[i] > e:
                eta[i] = ss.surface_level + e
                for k in range(3):
                    vel[i, k] = 0.0
                    acc[i, k] = 0.0
                continue
            zc = min(zr, e)                 # above the surface: the value at the surface
            above = 0.0                     # height above still water for linear extrapolation
            if code == 1:
                if deep:
                    ze = zc - e
                else:
                    ze = h * (zc - e) / max(h + e, 1e-9 * h)
            elif code == 2:
                ze = min(zc, 0.0)
            elif code == 3:
                if zc > 0.0:
                    ze = 0.0
                    above = zc
                else:
                    ze = zc
            else:
                ze = zc
            if not deep and ze < -h:
                ze = -h
            for j in range(nc):
                if ze < lim[j]:
                    continue                # decayed below round-off at this depth
                k = ss.wavenumber[j]
                # C = cosh(k(z+h))/sinh(kh), S = sinh(k(z+h))/sinh(kh), free of overflow
                if deep:
                    C = math.exp(k * ze)
                    S = C
                else:
                    ep = math.exp(k * ze)
                    em = e2[j] / ep       # exp(-k (z + 2 h))
                    C = (ep + em) / den[j]
                    S = (ep - em) / den[j]
                if above > 0.0:
                    C, S = C + above * k * S, S + above * k * C
                aw = ss.velocity[j]
                aww = aw * ss.omega[j]
                c = cth[j]
                s = sth[j]
                uh = aw * C * c
                duh = -aww * C * s
                vx += uh * ss.cos_direction[j]
                vy += uh * ss.sin_direction[j]
                vz -= aw * S * s
                ax += duh * ss.cos_direction[j]
                ay += duh * ss.sin_direction[j]
                az -= aww * S * c
            ax = r * ax + rd * vx
            ay = r * ay + rd * vy
            az = r * az + rd * vz
            vx *= r
            vy *= r
            vz *= r
        surface = ss.surface_level + e
        eta[i] = surface
        if ss.has_current:
            zcur = min(points[i, 2], surface)
            u = factor * interp_clamped(ss.current_z, ss.current_speed, zcur)
            vx += u * ss.current_cos
            vy += u * ss.current_sin
        vel[i, 0] = vx
        vel[i, 1] = vy
        vel[i, 2] = vz
        acc[i, 0] = ax
        acc[i, 1] = ay
        acc[i, 2] = az
