"""Uniaxial stress-strain laws, their overlay (kinematic hardening) models, and the
scenario schema of the elasto-plastic material (rfesim.materials.stress_strain,
rfesim.scenario.schema.ElastoplasticMaterial)."""
from __future__ import annotations

import copy

import numpy as np
import pytest

import rfesim
from rfesim import ScenarioError
from rfesim.materials.stress_strain import (Bilinear, RambergOsgood, TabulatedLaw, elastic_perfectly_plastic,
                                            overlay_elements, overlay_response)

E = 207e9
SY = 448e6


# ----------------------------------------------------------------------------- laws

def test_bilinear_closed_form():
    law = Bilinear(E, SY, 0.02)
    ey = SY / E
    eps = np.array([-5 * ey, -ey, 0.3 * ey, ey, 3 * ey])
    expected = np.array([-(SY + 0.02 * E * 4 * ey), -SY, 0.3 * SY, SY, SY + 0.02 * E * 2 * ey])
    np.testing.assert_allclose(law.stress(eps), expected, rtol=1e-14)
    np.testing.assert_allclose(law.tangent(eps), [0.02 * E, E, E, E, 0.02 * E])
    assert np.all(elastic_perfectly_plastic(E, SY).stress([2 * ey, 50 * ey]) == SY)


def test_ramberg_osgood_inverse_and_tangent():
    law = RambergOsgood(E, SY, 12.0, 0.002)
    sigma = np.linspace(-1.3 * SY, 1.3 * SY, 101)
    np.testing.assert_allclose(law.stress(law.strain(sigma)), sigma, rtol=1e-12, atol=1e-3)
    # the yield stress is the 0.2 % proof stress
    assert law.strain(SY) == pytest.approx(SY / E + 0.002, rel=1e-14)
    eps = np.array([0.5, 1.0, 2.0, 8.0]) * SY / E
    h = 1e-7 * SY / E
    fd = (law.stress(eps + h) - law.stress(eps - h)) / (2 * h)
    np.testing.assert_allclose(law.tangent(eps), fd, rtol=1e-5)


def test_table_interpolates_and_extrapolates_with_last_slope():
    ey = SY / E
    law = TabulatedLaw(E, (ey, 0.01, 0.03), (SY, 480e6, 500e6))
    assert law.stress(0.02) == pytest.approx(490e6, rel=1e-14)
    assert law.stress(0.05) == pytest.approx(520e6, rel=1e-14)       # last slope 1e9 Pa continues
    assert law.stress(-0.5 * ey) == pytest.approx(-0.5 * SY, rel=1e-14)
    assert law.tangent(0.02) == pytest.approx(1e9, rel=1e-12)


@pytest.mark.parametrize("strains, stresses, word", [
    ((SY / E, 0.01), (SY, 440e6), "decreases"),
    ((SY / E, 0.01, 0.009), (SY, 460e6, 470e6), "does not increase"),
    ((SY / E, 0.01, 0.02), (SY, 450e6, 500e6), "concave"),
    ((0.003,), (SY,), "elastic line"),
])
def test_table_errors(strains, stresses, word):
    with pytest.raises(ValueError, match=word):
        TabulatedLaw(E, strains, stresses)


def test_law_parameter_errors():
    with pytest.raises(ValueError, match="yield_stress"):
        Bilinear(E, -1.0)
    with pytest.raises(ValueError, match="hardening_ratio"):
        Bilinear(E, SY, 1.0)
    with pytest.raises(ValueError, match="exponent"):
        RambergOsgood(E, SY, 1.0)


# ----------------------------------------------------------------------------- overlay model

def test_overlay_reproduces_the_polyline_exactly():
    rng = np.random.default_rng(1)
    x = np.cumsum(rng.uniform(0.1, 1.0, 8))
    slopes = np.sort(rng.uniform(0.05, 3.0, 9))[::-1]         # concave
    y = np.cumsum(slopes[:-1] * np.diff(np.concatenate(([0.0], x))))
    k, r, k_inf = overlay_elements(x, y, slopes[-1])
    assert k_inf + k.sum() == pytest.approx(slopes[0], rel=1e-14)
    probe = np.linspace(-12.0, 12.0, 301)
    expected = np.sign(probe) * np.interp(np.abs(probe), np.concatenate(([0.0], x)), np.concatenate(([0.0], y)),
                                          right=np.nan)
    beyond = np.abs(probe) > x[-1]
    expected[beyond] = np.sign(probe[beyond]) * (y[-1] + slopes[-1] * (np.abs(probe[beyond]) - x[-1]))
    np.testing.assert_allclose(overlay_response(k, r, k_inf, probe), expected, rtol=1e-12, atol=1e-12)


def test_overlay_rejects_convex_curves():
    with pytest.raises(ValueError, match="concave"):
        overlay_elements([1.0, 2.0], [1.0, 3.0], 0.0)


def _uniaxial_cycle(law, strains):
    """Readable strain-driven overlay model: stresses along a strain path."""
    k, r, k_inf = law.overlay()
    plastic = np.zeros_like(k)
    out = []
    for e in strains:
        trial = k * (e - plastic)
        s = np.clip(trial, -r, r)
        plastic = np.where(np.abs(trial) > r, e - s / np.where(k > 0, k, 1.0), plastic)
        out.append(k_inf * e + s.sum())
    return np.array(out)


@pytest.mark.parametrize("law", [Bilinear(E, SY, 0.05),
                                 TabulatedLaw(E, (SY / E, 0.005, 0.02), (SY, 480e6, 510e6))],
                         ids=["bilinear", "table"])
def test_masing_rule_unloading_branch(law):
    """Kinematic hardening: from a reversal at eps_r the unloading stress is
    sigma_r - 2 f((eps_r - eps)/2) (twice-scaled backbone, Bauschinger effect)."""
    er = 8 * SY / E
    down = np.linspace(er, -er, 401)
    path = np.concatenate((np.linspace(0, er, 50), down))
    s = _uniaxial_cycle(law, path)[50:]
    sr = float(law.stress(er))
    np.testing.assert_allclose(s, sr - 2 * law.stress((er - down) / 2), rtol=1e-12, atol=1e-6 * SY)
    assert s[-1] == pytest.approx(-sr, rel=1e-12)


# ----------------------------------------------------------------------------- schema

BASE = {
    "line_types": {"pipe12": {"outer_diameter": 0.3239, "wall_thickness": 0.0159, "youngs_modulus": E,
                              "density": 7850.0,
                              "material": {"kind": "elastoplastic", "yield_stress": SY, "hardening_ratio": 0.02}}},
}
DIRECT = {"EA": 1e9, "EIy": 1e7, "mass_per_length": 100.0}


def _with(material=None, line_type=None):
    data = copy.deepcopy(BASE)
    if material is not None:
        data["line_types"]["pipe12"]["material"] = material
    if line_type is not None:
        data["line_types"]["pipe12"] = line_type
    return data


def test_schema_accepts_the_three_laws():
    sc = rfesim.Scenario.model_validate(BASE)
    m = sc.line_types["pipe12"].material
    assert (m.kind, m.law, m.yield_stress, m.hardening_ratio) == ("elastoplastic", "bilinear", SY, 0.02)
    ro = rfesim.Scenario.model_validate(_with({"kind": "elastoplastic", "law": "ramberg-osgood",
                                               "yield_stress": SY, "ro_n": 15})).line_types["pipe12"].material
    assert (ro.ro_n, ro.ro_offset) == (15.0, 0.002)
    tab = rfesim.Scenario.model_validate(_with({"kind": "elastoplastic", "law": "table",
                                                "table": [[SY / E, SY], [0.02, 500e6]]})).line_types["pipe12"].material
    assert tab.yield_stress == SY
    epp = rfesim.Scenario.model_validate(_with({"kind": "elastoplastic", "yield_stress": SY})).line_types["pipe12"]
    assert epp.material.hardening_ratio == 0.0


EP = {"kind": "elastoplastic"}
SCHEMA_CASES = [
    ("yield-negative", _with({**EP, "yield_stress": -448e6}), "material.yield_stress", "greater than 0"),
    ("yield-zero", _with({**EP, "yield_stress": 0.0}), "material.yield_stress", "greater than 0"),
    ("yield-missing", _with({**EP}), "material.yield_stress", "needs a yield stress"),
    ("yield-in-MPa-units", _with({**EP, "yield_stress": 448e9}), "material.yield_stress", "not a metal"),
    ("hardening-one", _with({**EP, "yield_stress": SY, "hardening_ratio": 1.0}), "material.hardening_ratio",
     "[0, 1)"),
    ("hardening-negative", _with({**EP, "yield_stress": SY, "hardening_ratio": -0.1}),
     "material.hardening_ratio", "[0, 1)"),
    ("ro-missing-n", _with({**EP, "law": "ramberg-osgood", "yield_stress": SY}), "material.ro_n", "needs"),
    ("ro-n-one", _with({**EP, "law": "ramberg-osgood", "yield_stress": SY, "ro_n": 1.0}), "material.ro_n",
     "greater than 1"),
    ("ro-with-hardening", _with({**EP, "law": "ramberg-osgood", "yield_stress": SY, "ro_n": 9,
                                 "hardening_ratio": 0.1}), "material.hardening_ratio", "not used"),
    ("table-missing", _with({**EP, "law": "table"}), "material.table", "at least one row"),
    ("table-strain-not-increasing", _with({**EP, "law": "table", "table": [[SY / E, SY], [0.01, 460e6],
                                                                            [0.01, 470e6]]}),
     "material.table.2", "does not increase"),
    ("table-stress-decreasing", _with({**EP, "law": "table", "table": [[SY / E, SY], [0.01, 400e6]]}),
     "material.table.1", "decreases"),
    ("table-convex", _with({**EP, "law": "table", "table": [[SY / E, SY], [0.01, 450e6], [0.02, 500e6]]}),
     "material.table.2", "concave"),
    ("table-off-elastic-line", _with({**EP, "law": "table", "table": [[0.003, SY]]}), "material.table.0",
     "elastic line"),
    ("table-row-length", _with({**EP, "law": "table", "table": [[SY / E, SY, 1.0]]}), "material.table.0",
     "exactly 2"),
    ("table-yield-mismatch", _with({**EP, "law": "table", "yield_stress": 400e6, "table": [[SY / E, SY]]}),
     "material.yield_stress", "differs"),
    ("unknown-law", _with({**EP, "law": "johnson-cook", "yield_stress": SY}), "material.law", "bilinear"),
    ("direct-properties", _with(line_type={**DIRECT, "material": {**EP, "yield_stress": SY}}), "material",
     "pipe geometry"),
]


@pytest.mark.parametrize("data, path, word", [c[1:] for c in SCHEMA_CASES], ids=[c[0] for c in SCHEMA_CASES])
def test_schema_errors_name_the_field(data, path, word):
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate(data)
    full = f"line_types.pipe12.{path}"
    reasons = [r for p, r in info.value.errors if p == full]
    assert reasons, info.value.errors
    assert any(word in r for r in reasons), reasons


def test_json_schema_has_units():
    schema = rfesim.Scenario.model_json_schema()
    props = schema["$defs"]["ElastoplasticMaterial"]["properties"]
    assert props["yield_stress"]["units"] == "Pa"
    assert props["hardening_ratio"]["units"] == "1"
