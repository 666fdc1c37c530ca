"""Moment-curvature of a pipe wall by fibre integration (section 8.4.2, VALIDATION.md P4).

Plane sections stay plane and the pipe is bent without axial force: the strain of a
fibre at (y, z) of the section is

    eps = z * kappa_y - y * kappa_z,        M_y = int sigma z dA,   M_z = -int sigma y dA,

so that ``M = EI kappa`` in both directions while elastic.

**Quadrature.** The thick ring r_i <= r <= r_o is integrated with Gauss-Legendre points
through the wall (``n_radial``, weight r dr) times the periodic midpoint rule around the
circumference (``n_angular`` equal sectors). It is exact for the area and the second
moment (polynomial in r, trigonometric of degree 2 in the angle) with n_radial >= 2,
n_angular >= 3; the elastic-plastic kink of sigma(eps) makes the angular error O(h^2)
(relative 1e-5 for the default 720 sectors, see tests/unit/test_materials_section.py).

* ``moment_curvature``: monotonic M(kappa) with the law's exact stress-strain curve.
* ``FibreSection``: the cyclic fibre model. Every fibre carries the plastic strains of
  the sub-elements of its law's overlay model (rfesim.materials.stress_strain), which
  is **kinematic hardening** (Mroz multi-surface, Masing rule): unloading is elastic
  until the stress has changed by twice the yield stress, then the fibre yields in
  reverse (Bauschinger effect). Plastic dissipation is accumulated exactly.
* ``reeling``: bending onto a hub and elastic unloading to zero moment (residual
  curvature).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .stress_strain import StressStrainLaw


@dataclass(frozen=True)
class PipeWall:
    """Steel wall of a circular pipe."""

    outer_diameter: float       # m
    wall_thickness: float       # m
    youngs_modulus: float       # Pa

    def __post_init__(self):
        if not (self.outer_diameter > 0.0 and 0.0 < self.wall_thickness <= 0.5 * self.outer_diameter):
            raise ValueError(f"not a pipe wall: outer_diameter {self.outer_diameter} m, "
                             f"wall_thickness {self.wall_thickness} m")

    @property
    def outer_radius(self) -> float:
        return 0.5 * self.outer_diameter

    @property
    def inner_diameter(self) -> float:
        return self.outer_diameter - 2.0 * self.wall_thickness

    @property
    def area(self) -> float:
        """Steel area (m^2)."""
        return math.pi / 4.0 * (self.outer_diameter ** 2 - self.inner_diameter ** 2)

    @property
    def inertia(self) -> float:
        """Second moment of area about a diameter (m^4)."""
        return math.pi / 64.0 * (self.outer_diameter ** 4 - self.inner_diameter ** 4)

    @property
    def plastic_modulus(self) -> float:
        """Plastic section modulus (D^3 - d^3)/6 (m^3)."""
        return (self.outer_diameter ** 3 - self.inner_diameter ** 3) / 6.0

    @property
    def bending_stiffness(self) -> float:
        """EI (N*m^2)."""
        return self.youngs_modulus * self.inertia


def ring_quadrature(wall: PipeWall, n_radial: int = 6, n_angular: int = 720):
    """Fibres (y, z, area) of the ring: Gauss-Legendre in r times midpoint in the angle."""
    xg, wg = np.polynomial.legendre.leggauss(n_radial)
    ro = wall.outer_radius
    ri = ro - wall.wall_thickness
    r = 0.5 * (ro + ri) + 0.5 * (ro - ri) * xg
    wr = 0.5 * (ro - ri) * wg * r
    theta = (np.arange(n_angular) + 0.5) * (2.0 * math.pi / n_angular)
    y = np.outer(r, np.cos(theta)).ravel()
    z = np.outer(r, np.sin(theta)).ravel()
    w = np.outer(wr, np.full(n_angular, 2.0 * math.pi / n_angular)).ravel()
    return y, z, w


def yield_curvature(law: StressStrainLaw, wall: PipeWall) -> float:
    """Curvature at which the outer fibre reaches the end of the linear range (1/m)."""
    return law.yield_strain / wall.outer_radius


def yield_moment(law: StressStrainLaw, wall: PipeWall) -> float:
    """First-yield moment sigma_y I / r_o (N*m)."""
    return law.yield_stress * wall.inertia / wall.outer_radius


def plastic_moment(law: StressStrainLaw, wall: PipeWall) -> float:
    """Fully plastic moment sigma_y (D^3 - d^3)/6 of a perfectly plastic wall (N*m)."""
    return law.yield_stress * wall.plastic_modulus


def moment_curvature(law: StressStrainLaw, wall: PipeWall, kappa, n_radial: int = 6, n_angular: int = 720):
    """Monotonic M(kappa) (N*m) by fibre integration; vectorised in kappa (1/m), odd."""
    kappa = np.asarray(kappa, dtype=float)
    _, z, w = ring_quadrature(wall, n_radial, n_angular)
    eps = kappa[..., None] * z
    return np.sum(law.stress(eps) * z * w, axis=-1)


def bending_tangent(law: StressStrainLaw, wall: PipeWall, kappa, n_radial: int = 6, n_angular: int = 720):
    """dM/dkappa (N*m^2) of the monotonic curve: the integral of E_t(eps) z^2."""
    kappa = np.asarray(kappa, dtype=float)
    _, z, w = ring_quadrature(wall, n_radial, n_angular)
    return np.sum(law.tangent(kappa[..., None] * z) * z * z * w, axis=-1)


class FibreSection:
    """Cyclic fibre model of a pipe wall under biaxial bending, kinematic hardening.

    State: the plastic strain of every sub-element of every fibre (``plastic``,
    (n_fibres, n_elements)), the curvature and moment vectors of the last committed
    state, and the plastic dissipation per unit length (J/m).
    ``trial`` evaluates a curvature from the committed state without changing it;
    ``update`` evaluates and commits (an overlay element's return map is exact for any
    strain increment along a straight path, so large steps are fine on monotonic legs).
    """

    def __init__(self, law: StressStrainLaw, wall: PipeWall, n_radial: int = 4, n_angular: int = 180):
        self.law = law
        self.wall = wall
        self.y, self.z, self.w = ring_quadrature(wall, n_radial, n_angular)
        self.k, self.r, self.k_inf = law.overlay()
        self.plastic = np.zeros((self.y.size, self.k.size))
        self.kappa = np.zeros(2)
        self.moment = np.zeros(2)
        self.dissipation = 0.0

    def _response(self, kappa_y: float, kappa_z: float):
        eps = self.z * kappa_y - self.y * kappa_z
        trial = self.k * (eps[:, None] - self.plastic)
        over = np.abs(trial) > self.r
        stress_el = np.where(over, np.sign(trial) * self.r, trial)
        safe_k = np.where(self.k > 0.0, self.k, 1.0)
        plastic = np.where(over, eps[:, None] - stress_el / safe_k, self.plastic)
        d_diss = np.sum(self.w[:, None] * self.r * np.abs(plastic - self.plastic))
        sigma = self.k_inf * eps + stress_el.sum(axis=1)
        moment = np.array([np.sum(sigma * self.z * self.w), -np.sum(sigma * self.y * self.w)])
        return moment, plastic, d_diss

    def trial(self, kappa_y: float, kappa_z: float = 0.0) -> np.ndarray:
        """[M_y, M_z] (N*m) at this curvature, from the committed state (not changed)."""
        return self._response(kappa_y, kappa_z)[0]

    def update(self, kappa_y: float, kappa_z: float = 0.0) -> np.ndarray:
        """[M_y, M_z] at this curvature, committing the new state."""
        moment, plastic, d_diss = self._response(kappa_y, kappa_z)
        self.plastic = plastic
        self.dissipation += d_diss
        self.kappa = np.array([kappa_y, kappa_z])
        self.moment = moment
        return moment

    def free_energy(self) -> float:
        """Stored energy per unit length (J/m) in the committed state."""
        eps = self.z * self.kappa[0] - self.y * self.kappa[1]
        e = 0.5 * self.k_inf * eps ** 2 + 0.5 * np.sum(self.k * (eps[:, None] - self.plastic) ** 2, axis=1)
        return float(np.sum(e * self.w))

    def unload(self) -> np.ndarray:
        """Unload along the direction of the committed moment to zero moment; commits
        and returns the residual curvature vector (1/m)."""
        m = np.hypot(*self.moment)
        if m == 0.0:
            return self.kappa.copy()
        n = self.moment / m
        k0 = self.kappa.copy()

        def moment_along(s):
            kap = k0 - s * n
            return float(self.trial(kap[0], kap[1]) @ n)

        ei = self.wall.bending_stiffness
        hi = m / ei
        while moment_along(hi) > 0.0:
            hi *= 2.0
        from scipy.optimize import brentq     # here: scipy.optimize costs 1 s of start-up
        s = brentq(moment_along, 0.0, hi, xtol=1e-16, rtol=1e-14)
        kap = k0 - s * n
        self.update(kap[0], kap[1])
        return self.kappa.copy()


@dataclass(frozen=True)
class ReelingResult:
    hub_radius: float            # m
    axis_radius: float           # m, hub radius + outer radius
    curvature: float             # 1/m, 1/axis_radius
    outer_fibre_strain: float    # -, r_o / axis_radius
    moment: float                # N*m, on the reel
    residual_curvature: float    # 1/m, after unloading to zero moment (cyclic fibre model)
    residual_curvature_elastic: float   # 1/m, kappa - M/EI (assumes elastic unloading)
    unloading_elastic: bool      # True when |M| <= 2 M_y (Masing: no reverse yielding)


def reeling(law: StressStrainLaw, wall: PipeWall, hub_radius: float, n_radial: int = 4,
            n_angular: int = 360) -> ReelingResult:
    """Pipe spooled onto a hub (its axis on radius hub + r_o) and released to zero moment."""
    axis = hub_radius + wall.outer_radius
    kappa = 1.0 / axis
    fibres = FibreSection(law, wall, n_radial, n_angular)
    moment = float(fibres.update(kappa)[0])
    residual = float(fibres.unload()[0])
    elastic = kappa - moment / wall.bending_stiffness
    return ReelingResult(hub_radius=hub_radius, axis_radius=axis, curvature=kappa,
                         outer_fibre_strain=wall.outer_radius / axis, moment=moment,
                         residual_curvature=residual, residual_curvature_elastic=elastic,
                         unloading_elastic=law.has_linear_range
                         and abs(moment) <= 2.0 * yield_moment(law, wall) * (1.0 + 1e-12))
