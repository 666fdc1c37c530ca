"""Fibre model of the pipe wall (rfesim.materials.section): quadrature, monotonic
moment-curvature, and the cyclic fibre model with kinematic hardening (elastic
unloading, reverse yielding, dissipation = loop area)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from rfesim.materials.section import (FibreSection, PipeWall, bending_tangent, moment_curvature, ring_quadrature,
                                      yield_curvature, yield_moment)
from rfesim.materials.stress_strain import Bilinear, RambergOsgood, elastic_perfectly_plastic

WALL = PipeWall(0.3239, 0.0159, 207e9)
EPP = elastic_perfectly_plastic(207e9, 448e6)
HARD = Bilinear(207e9, 448e6, 0.02)


def test_quadrature_exact_for_area_and_inertia():
    for n_radial, n_angular in ((2, 4), (3, 12), (6, 720)):
        y, z, w = ring_quadrature(WALL, n_radial, n_angular)
        assert w.sum() == pytest.approx(WALL.area, rel=1e-13)
        assert np.sum(w * z * z) == pytest.approx(WALL.inertia, rel=1e-13)
        assert np.sum(w * y * y) == pytest.approx(WALL.inertia, rel=1e-13)
        assert abs(np.sum(w * y * z)) < 1e-13 * WALL.inertia


def test_elastic_range_is_ei_kappa():
    ky = yield_curvature(EPP, WALL)
    kappa = np.array([-ky, 0.3 * ky, ky])
    np.testing.assert_allclose(moment_curvature(EPP, WALL, kappa), WALL.bending_stiffness * kappa, rtol=1e-12)
    assert yield_moment(EPP, WALL) == pytest.approx(WALL.bending_stiffness * ky, rel=1e-14)


def test_angular_quadrature_converges_at_second_order():
    """The elastic-plastic kink limits the midpoint rule to O(h^2); the error at one
    curvature depends on where the kink falls between points, so the RMS error over
    curvatures from 1.1 to 10 kappa_y is measured."""
    ky = yield_curvature(EPP, WALL)
    kappa = ky * np.linspace(1.1, 10.0, 37)
    reference = moment_curvature(EPP, WALL, kappa, n_angular=46080)
    ns = np.array([60, 120, 240, 480])
    errors = np.array([np.sqrt(np.mean((moment_curvature(EPP, WALL, kappa, n_angular=n) / reference - 1) ** 2))
                       for n in ns])
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all(orders > 1.8), orders
    default = moment_curvature(EPP, WALL, kappa)          # 720 sectors
    assert np.max(np.abs(default / reference - 1)) < 1e-5


def test_tangent_is_derivative_of_moment():
    ky = yield_curvature(HARD, WALL)
    kappa = np.array([0.5, 1.7, 4.0, 20.0]) * ky
    h = 1e-6 * ky
    fd = (moment_curvature(HARD, WALL, kappa + h) - moment_curvature(HARD, WALL, kappa - h)) / (2 * h)
    np.testing.assert_allclose(bending_tangent(HARD, WALL, kappa), fd, rtol=2e-3)


def test_fibre_section_monotonic_matches_moment_curvature():
    fib = FibreSection(HARD, WALL, 6, 720)
    ky = yield_curvature(HARD, WALL)
    for ratio in (0.5, 2.0, 5.0):
        assert fib.trial(ratio * ky)[0] == pytest.approx(float(moment_curvature(HARD, WALL, ratio * ky)), rel=1e-12)


@pytest.mark.parametrize("law", [EPP, HARD], ids=["epp", "hardening"])
def test_unloading_elastic_then_reverse_yield_at_twice_yield(law):
    """Unloading from kappa_r is linear with slope EI until the moment has dropped by
    2 M_y (kinematic hardening: Bauschinger effect), then the section yields in reverse."""
    fib = FibreSection(law, WALL, 12, 360)
    ky = yield_curvature(law, WALL)
    ei = WALL.bending_stiffness
    kr = 3.0 * ky
    mr = fib.update(kr)[0]
    # fibres sit inside the outer radius, so the section's first fibre yields a little after kappa_y
    _, z, _ = ring_quadrature(WALL, 12, 360)
    first = ky * WALL.outer_radius / z.max()
    for dk in np.linspace(0.0, 2.0 * first * (1 - 1e-9), 9)[1:]:
        assert fib.trial(kr - dk)[0] == pytest.approx(mr - ei * dk, rel=1e-12)
    dk = 2.0 * first * 1.05
    assert fib.trial(kr - dk)[0] > mr - ei * dk + 1e-4 * yield_moment(law, WALL)
    # reverse yield moment: smaller than M_y in magnitude (an isotropic model would give -M_r)
    m_rev = mr - 2.0 * ei * first
    assert m_rev == pytest.approx(mr - 2.0 * yield_moment(law, WALL), rel=5e-3)
    assert abs(m_rev) < yield_moment(law, WALL) < mr


@pytest.mark.parametrize("law", [EPP, HARD, RambergOsgood(207e9, 448e6, 15.0)], ids=["epp", "hardening", "ro"])
def test_cycle_dissipation_equals_loop_area(law):
    """Energy balance along a path: int M dkappa = delta(free energy) + dissipation;
    over a stabilised symmetric cycle the state returns, so dissipation = loop area."""
    fib = FibreSection(law, WALL, 2, 60)
    ky = yield_curvature(law, WALL)
    amp = 4.0 * ky
    fib.update(amp)                                  # first loading (exact in one step)
    psi0, d0 = fib.free_energy(), fib.dissipation
    kappa = amp * np.cos(np.linspace(0.0, 2.0 * math.pi, 2001))
    moments = np.array([fib.update(k)[0] for k in kappa])
    area = np.sum(0.5 * (moments[1:] + moments[:-1]) * np.diff(kappa))
    assert fib.free_energy() == pytest.approx(psi0, rel=1e-9)
    assert fib.dissipation - d0 == pytest.approx(area, rel=2e-4)
    assert area > 0.5 * yield_moment(law, WALL) * ky     # a real loop, not a line
