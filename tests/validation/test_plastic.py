"""VALIDATION.md P4: elasto-plastic bending of a 12.75 in x 0.625 in X65 pipe.

D = 0.3239 m, t = 0.0159 m, E = 207 GPa, yield 448 MPa. Reference numbers:
M_y = 506.01 kN*m, M_p = 676.34 kN*m, kappa_y = 0.01336 1/m; elastic-perfectly plastic
fibre model M/M_p = 0.74817 (kappa/kappa_y = 1), 0.95183 (2), 0.99258 (5); linear
hardening E_t = 0.02 E: 0.96272 (2), 1.04755 (5), 1.12783 (10); reeling on an 8 m hub
(pipe axis radius 8.162 m): strain 1.984 %, residual curvature after elastic unloading
0.10470 1/m. Tolerance 0.5 %. Checked for the fibre model (rfesim.materials.section) and
for the SDE kernel built from a scenario material (rfesim.materials.sde_plastic).
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import rfesim
from rfesim.materials.sde_plastic import N_OUT, pack_params, plastic_bending_into, plastic_params
from rfesim.materials.section import (PipeWall, moment_curvature, plastic_moment, reeling, yield_curvature,
                                      yield_moment)
from rfesim.materials.stress_strain import Bilinear, elastic_perfectly_plastic
from rfesim.model.sections import section_from_type

TOL = 5e-3
WALL = PipeWall(0.3239, 0.0159, 207e9)
EPP = elastic_perfectly_plastic(207e9, 448e6)
HARD = Bilinear(207e9, 448e6, 0.02)

EPP_RATIOS = [(1.0, 0.74817), (2.0, 0.95183), (5.0, 0.99258)]
HARD_RATIOS = [(2.0, 0.96272), (5.0, 1.04755), (10.0, 1.12783)]


def _kernel(hardening_ratio):
    """The SDE kernel's parameters from a scenario line type (schema -> Section -> params)."""
    data = {"line_types": {"x65": {"outer_diameter": 0.3239, "wall_thickness": 0.0159, "youngs_modulus": 207e9,
                                   "density": 7850.0,
                                   "material": {"kind": "elastoplastic", "law": "bilinear", "yield_stress": 448e6,
                                                "hardening_ratio": hardening_ratio}}}}
    lt = rfesim.Scenario.model_validate(data).line_types["x65"]
    ps = plastic_params(lt.material, section_from_type(lt))
    params, hist = pack_params([ps.params])
    return ps, params, hist


def _kernel_moment(params, hist, kappa_y, kappa_z=0.0):
    out = np.zeros(N_OUT)
    trial = hist.copy()
    plastic_bending_into(params, hist, 0, kappa_y, kappa_z, out, trial)
    return out, trial


def test_p4_section_constants():
    assert yield_moment(EPP, WALL) / 1e3 == pytest.approx(506.01, rel=TOL)
    assert plastic_moment(EPP, WALL) / 1e3 == pytest.approx(676.34, rel=TOL)
    assert yield_curvature(EPP, WALL) == pytest.approx(0.01336, rel=TOL)
    # the fibre model's moment tends to M_p at large curvature
    assert float(moment_curvature(EPP, WALL, 1000 * yield_curvature(EPP, WALL))) == pytest.approx(
        plastic_moment(EPP, WALL), rel=1e-4)


@pytest.mark.parametrize("law, ratios", [(EPP, EPP_RATIOS), (HARD, HARD_RATIOS)], ids=["epp", "hardening"])
def test_p4_fibre_moment_curvature(law, ratios):
    ky = yield_curvature(law, WALL)
    mp = plastic_moment(EPP, WALL)
    for ratio, expected in ratios:
        assert float(moment_curvature(law, WALL, ratio * ky)) / mp == pytest.approx(expected, rel=TOL)


@pytest.mark.parametrize("hardening_ratio, ratios", [(0.0, EPP_RATIOS), (0.02, HARD_RATIOS)],
                         ids=["epp", "hardening"])
def test_p4_kernel_moment_curvature(hardening_ratio, ratios):
    ps, params, hist = _kernel(hardening_ratio)
    assert ps.yield_moment / 1e3 == pytest.approx(506.01, rel=TOL)
    assert ps.plastic_moment / 1e3 == pytest.approx(676.34, rel=TOL)
    for ratio, expected in ratios:
        m = _kernel_moment(params, hist, ratio * ps.yield_curvature)[0][0]
        assert m / ps.plastic_moment == pytest.approx(expected, rel=TOL)
        # the same in any bending direction (isotropic pipe)
        out = _kernel_moment(params, hist, 0.6 * ratio * ps.yield_curvature, -0.8 * ratio * ps.yield_curvature)[0]
        assert np.hypot(out[0], out[1]) == pytest.approx(m, rel=1e-12)


def test_p4_reeling_fibre_model():
    r = reeling(EPP, WALL, 8.0)
    assert r.axis_radius == pytest.approx(8.162, rel=TOL)
    assert r.outer_fibre_strain == pytest.approx(0.01984, rel=TOL)
    assert r.unloading_elastic
    assert r.residual_curvature == pytest.approx(0.10470, rel=TOL)
    assert r.residual_curvature_elastic == pytest.approx(r.residual_curvature, rel=1e-9)


def test_p4_reeling_kernel():
    """Spool the SDE onto the reel, commit, release to zero moment: residual curvature."""
    ps, params, hist = _kernel(0.0)
    kappa = 1.0 / (8.0 + 0.5 * 0.3239)
    out, hist = _kernel_moment(params, hist, kappa)
    assert out[0] > 1.3 * ps.yield_moment                     # well into the plastic range
    residual = brentq(lambda k: _kernel_moment(params, hist, k)[0][0], 0.0, kappa, xtol=1e-14)
    assert residual == pytest.approx(0.10470, rel=TOL)
    # unloading was elastic: residual = kappa - M/EI
    assert residual == pytest.approx(kappa - out[0] / ps.bending_stiffness, rel=1e-10)
