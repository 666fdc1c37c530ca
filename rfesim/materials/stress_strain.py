"""Uniaxial stress-strain laws of pipe steel (section 8.4.2, f_mat of Fig. 8.15).

Every law is an odd function sigma(eps) (tension and compression alike) with an initial
slope equal to Young's modulus:

* ``Bilinear``: elastic to the yield stress, then linear hardening with the tangent
  modulus ``E_t = hardening_ratio * E``; ``hardening_ratio = 0`` is elastic-perfectly
  plastic (``elastic_perfectly_plastic``);
* ``RambergOsgood``: ``eps = sigma/E + offset * (sigma/yield_stress)**n`` (the yield
  stress is the stress at the plastic ``offset`` strain, 0.2 % proof stress by default);
* ``TabulatedLaw``: a concave polyline through the origin and measured (strain, stress)
  points, continued beyond the last point with the last slope.

For cyclic loading every law is represented by its **overlay (Iwan / Mroz) model**: the
monotonic curve approximated by a polyline (exact for the bilinear and tabulated laws),
realised as elastic-perfectly-plastic sub-elements in parallel. Under reversed loading
this is kinematic hardening with the Masing rule: the unloading branch from a reversal
point is the monotonic curve scaled by two (Bauschinger effect). ``overlay_elements``
turns any concave polyline (stress-strain or moment-curvature) into those sub-elements.

Units: strain [-], stress [Pa]; or, for ``overlay_elements`` on a section, curvature
[1/m] and moment [N*m].
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def overlay_elements(x_break, y_break, final_slope):
    """Sub-elements of the overlay model of a concave polyline through the origin.

    The polyline passes through (0, 0) and (x_break[j], y_break[j]) and continues with
    ``final_slope`` after the last point. Element j (stiffness k_j, strength r_j) yields
    at x_break[j]; an unbreakable spring of stiffness ``k_inf = final_slope`` remains:

        y(x) = k_inf x + sum_j k_j min(x, x_break[j]),  k_j = s_j - s_{j+1},  r_j = k_j x_break[j],

    with s_j the slope of segment j. Returns (k, r, k_inf). Raises ValueError when the
    breaks do not increase or the slopes increase (a convex or softening curve has no
    overlay model with positive sub-elements).
    """
    x = np.asarray(x_break, dtype=float)
    y = np.asarray(y_break, dtype=float)
    if x.ndim != 1 or x.shape != y.shape or x.size == 0:
        raise ValueError("the break points must be two 1-D arrays of equal, non-zero length")
    xs = np.concatenate(([0.0], x))
    ys = np.concatenate(([0.0], y))
    dx = np.diff(xs)
    if np.any(dx <= 0.0):
        j = int(np.argmax(dx <= 0.0))
        raise ValueError(f"break point {j}: abscissa {xs[j + 1]:.6g} does not increase (previous {xs[j]:.6g})")
    slopes = np.concatenate((np.diff(ys) / dx, [float(final_slope)]))
    if slopes[-1] < 0.0:
        raise ValueError(f"the final slope {slopes[-1]:.6g} is negative (softening is not supported)")
    scale = max(abs(slopes[0]), 1e-300)
    k = slopes[:-1] - slopes[1:]
    if np.any(k < -1e-9 * scale):
        j = int(np.argmax(k < -1e-9 * scale))
        raise ValueError(f"segment {j + 1} is steeper than segment {j} (slope {slopes[j + 1]:.6g} > "
                         f"{slopes[j]:.6g}): the curve must be concave (slopes must not increase)")
    k = np.maximum(k, 0.0)
    r = k * x
    return k, r, float(slopes[-1])


def overlay_response(k, r, k_inf, x):
    """Monotonic response y(x) of an overlay model (odd in x); vectorised in x."""
    x = np.asarray(x, dtype=float)
    ax = np.abs(x)[..., None]
    y = k_inf * np.abs(x) + np.sum(np.minimum(k * ax, r), axis=-1)
    return np.sign(x) * y


class StressStrainLaw:
    """Base of the uniaxial laws: ``stress``, ``tangent``, ``yield_strain`` and the
    polyline ``backbone`` of the overlay model."""

    youngs_modulus: float
    yield_stress: float

    @property
    def yield_strain(self) -> float:
        """Strain at the end of the linear range (nominal sigma_y/E for Ramberg-Osgood)."""
        return self.yield_stress / self.youngs_modulus

    @property
    def has_linear_range(self) -> bool:
        return True

    def stress(self, strain):
        raise NotImplementedError

    def tangent(self, strain):
        raise NotImplementedError

    def backbone(self):
        """(strains, stresses, final_slope) of the polyline used by the overlay model."""
        raise NotImplementedError

    def overlay(self):
        """(k, r, k_inf) of the uniaxial overlay model (Pa, Pa, Pa)."""
        return overlay_elements(*self.backbone())


@dataclass(frozen=True)
class Bilinear(StressStrainLaw):
    """Elastic, then linear hardening E_t = hardening_ratio * E (0: perfectly plastic)."""

    youngs_modulus: float       # Pa
    yield_stress: float         # Pa
    hardening_ratio: float = 0.0   # E_t / E, in [0, 1)

    def __post_init__(self):
        if not self.youngs_modulus > 0.0:
            raise ValueError(f"youngs_modulus must be positive, got {self.youngs_modulus}")
        if not self.yield_stress > 0.0:
            raise ValueError(f"yield_stress must be positive, got {self.yield_stress}")
        if not 0.0 <= self.hardening_ratio < 1.0:
            raise ValueError(f"hardening_ratio must be in [0, 1), got {self.hardening_ratio}")

    def stress(self, strain):
        e = np.asarray(strain, dtype=float)
        ey = self.yield_strain
        E = self.youngs_modulus
        plastic = np.sign(e) * (self.yield_stress + self.hardening_ratio * E * (np.abs(e) - ey))
        return np.where(np.abs(e) <= ey, E * e, plastic)

    def tangent(self, strain):
        e = np.asarray(strain, dtype=float)
        E = self.youngs_modulus
        return np.where(np.abs(e) <= self.yield_strain, E, self.hardening_ratio * E)

    def backbone(self):
        return (np.array([self.yield_strain]), np.array([self.yield_stress]),
                self.hardening_ratio * self.youngs_modulus)


def elastic_perfectly_plastic(youngs_modulus: float, yield_stress: float) -> Bilinear:
    """The elastic-perfectly-plastic law (bilinear with zero hardening)."""
    return Bilinear(youngs_modulus, yield_stress, 0.0)


@dataclass(frozen=True)
class RambergOsgood(StressStrainLaw):
    """eps = sigma/E + offset*(|sigma|/yield_stress)**n * sign(sigma)."""

    youngs_modulus: float       # Pa
    yield_stress: float         # Pa, stress at the plastic strain `offset`
    exponent: float             # n > 1
    offset: float = 0.002       # plastic strain at the yield stress [-]
    backbone_points: int = 48   # polyline points of the overlay model
    backbone_span: tuple = (0.2, 200.0)   # first and last polyline strain / nominal yield strain

    def __post_init__(self):
        if not self.youngs_modulus > 0.0:
            raise ValueError(f"youngs_modulus must be positive, got {self.youngs_modulus}")
        if not self.yield_stress > 0.0:
            raise ValueError(f"yield_stress must be positive, got {self.yield_stress}")
        if not self.exponent > 1.0:
            raise ValueError(f"the Ramberg-Osgood exponent must be > 1, got {self.exponent}")
        if not self.offset > 0.0:
            raise ValueError(f"the Ramberg-Osgood offset must be positive, got {self.offset}")

    @property
    def has_linear_range(self) -> bool:
        return False

    def strain(self, stress):
        s = np.asarray(stress, dtype=float)
        return s / self.youngs_modulus + np.sign(s) * self.offset * (np.abs(s) / self.yield_stress) ** self.exponent

    def stress(self, strain):
        """Inverse of ``strain`` by Newton's method from an upper bound (g convex: monotone)."""
        e = np.abs(np.asarray(strain, dtype=float))
        E, sy, n, a = self.youngs_modulus, self.yield_stress, self.exponent, self.offset
        s = np.minimum(E * e, sy * (e / a) ** (1.0 / n))
        for _ in range(200):
            g = s / E + a * (s / sy) ** n - e
            # (s / sy)^(n-1) / sy, not s^(n-1) / sy^n: sy^n overflows for n > 35 (steels near
            # perfectly plastic), the ratio stays below (e / a)^((n-1)/n)
            dg = 1.0 / E + a * n * (s / sy) ** (n - 1.0) / sy
            step = g / dg
            s = s - step
            if np.all(np.abs(step) <= 1e-15 * np.maximum(s, sy)):
                break
        return np.sign(np.asarray(strain, dtype=float)) * s

    def tangent(self, strain):
        s = np.abs(self.stress(strain))
        E, sy, n, a = self.youngs_modulus, self.yield_stress, self.exponent, self.offset
        return 1.0 / (1.0 / E + a * n * (s / sy) ** (n - 1.0) / sy)

    def backbone(self):
        lo, hi = self.backbone_span
        e = self.yield_strain * np.geomspace(lo, hi, self.backbone_points)
        return e, self.stress(e), float(self.tangent(e[-1]))


@dataclass(frozen=True)
class TabulatedLaw(StressStrainLaw):
    """A concave polyline through the origin and (strain, stress) points; the first point
    is the yield point (on the elastic line), slopes must not increase; beyond the last
    point the last slope continues."""

    youngs_modulus: float       # Pa, must equal the slope of the first segment (1 %)
    strains: tuple              # [-], increasing, > 0
    stresses: tuple             # Pa, non-decreasing

    def __post_init__(self):
        e = np.asarray(self.strains, dtype=float)
        s = np.asarray(self.stresses, dtype=float)
        if e.ndim != 1 or e.shape != s.shape or e.size < 1:
            raise ValueError("the table needs at least one (strain, stress) point")
        check_table(self.youngs_modulus, e, s)

    @property
    def yield_stress(self) -> float:
        return float(self.stresses[0])

    @property
    def yield_strain(self) -> float:
        return float(self.strains[0])

    def _polyline(self):
        e = np.concatenate(([0.0], np.asarray(self.strains, dtype=float)))
        s = np.concatenate(([0.0], np.asarray(self.stresses, dtype=float)))
        return e, s

    def _final_slope(self):
        e, s = self._polyline()
        return (s[-1] - s[-2]) / (e[-1] - e[-2]) if e.size > 2 else 0.0

    def stress(self, strain):
        x = np.asarray(strain, dtype=float)
        e, s = self._polyline()
        ax = np.abs(x)
        inside = np.interp(ax, e, s)
        beyond = s[-1] + self._final_slope() * (ax - e[-1])
        return np.sign(x) * np.where(ax <= e[-1], inside, beyond)

    def tangent(self, strain):
        ax = np.abs(np.asarray(strain, dtype=float))
        e, s = self._polyline()
        slopes = np.concatenate((np.diff(s) / np.diff(e), [self._final_slope()]))
        idx = np.searchsorted(e[1:], ax, side="left")
        return slopes[np.minimum(idx, slopes.size - 1)]

    def backbone(self):
        return (np.asarray(self.strains, dtype=float), np.asarray(self.stresses, dtype=float),
                float(self._final_slope()))


def check_table(youngs_modulus, strains, stresses):
    """Check a stress-strain table; raises ValueError naming the row (0-based)."""
    e = np.asarray(strains, dtype=float)
    s = np.asarray(stresses, dtype=float)
    if not (np.all(np.isfinite(e)) and np.all(np.isfinite(s))):
        raise ValueError("the table must contain finite numbers")
    if e[0] <= 0.0 or s[0] <= 0.0:
        raise ValueError("row 0: the first point (the yield point) needs strain > 0 and stress > 0")
    first = s[0] / e[0]
    if abs(first - youngs_modulus) > 0.01 * youngs_modulus:
        raise ValueError(f"row 0: the first point is the yield point and must lie on the elastic line: "
                         f"stress/strain = {first:.6g} Pa, youngs_modulus = {youngs_modulus:.6g} Pa "
                         f"(differ by more than 1 %)")
    for j in range(1, e.size):
        if not e[j] > e[j - 1]:
            raise ValueError(f"row {j}: strain {e[j]:.6g} does not increase (previous {e[j - 1]:.6g})")
        if s[j] < s[j - 1]:
            raise ValueError(f"row {j}: stress {s[j]:.6g} Pa decreases (previous {s[j - 1]:.6g} Pa); "
                             f"softening is not supported")
    slopes = np.diff(np.concatenate(([0.0], s))) / np.diff(np.concatenate(([0.0], e)))
    for j in range(1, slopes.size):
        if slopes[j] > slopes[j - 1] * (1.0 + 1e-9):
            raise ValueError(f"row {j}: the slope {slopes[j]:.6g} Pa is steeper than the previous segment's "
                             f"{slopes[j - 1]:.6g} Pa: the curve must be concave")


def law_from_material(material, youngs_modulus: float) -> StressStrainLaw:
    """The stress-strain law of a scenario ``ElastoplasticMaterial`` (rfesim.scenario.schema)."""
    law = material.law
    if law == "bilinear":
        return Bilinear(youngs_modulus, material.yield_stress, material.hardening_ratio or 0.0)
    if law == "ramberg-osgood":
        return RambergOsgood(youngs_modulus, material.yield_stress, material.ro_n, material.ro_offset)
    if law == "table":
        rows = material.table
        return TabulatedLaw(youngs_modulus, tuple(r[0] for r in rows), tuple(r[1] for r in rows))
    raise ValueError(f"unknown stress-strain law {law!r}")
