"""lay_summary takes the strains of a coated template pipe at the steel's outer fibre: the
template's line type carries steel_outer_diameter beside the coated outer_diameter (before,
a 50 mm coating made the default overbend and sagbend strains 31 % high, the ratio of the
coated to the steel diameter, 0.4239 / 0.3239)."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

import rfesim
from rfesim.lay_results import lay_summary

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def _coated():
    d = json.loads((SCENARIOS / "s_lay_template.json").read_text())
    d["vessels"]["barge"]["motion"] = {"kind": "fixed"}
    del d["environment"]["water"]["waves"]
    d["pipelay"]["lay"]["pipe"].update(coating_thickness=0.05, coating_density=2400.0)
    d["analysis"].pop("dynamics", None)
    return d


def test_coated_template_strains_are_at_the_steel():
    sc = rfesim.load_scenario(_coated())
    lt = sc.line_types[sc.lines["lay"].type]
    assert lt.outer_diameter == pytest.approx(0.4239) and lt.steel_outer_diameter == pytest.approx(0.3239)
    res = rfesim.statics(sc)
    default, steel = lay_summary(res), lay_summary(res, outer_diameter=0.3239)
    for key in ("overbend_strain", "sagbend_strain", "overbend_total_strain", "sagbend_total_strain"):
        assert default[key] == pytest.approx(steel[key], rel=1e-12), key
    assert default["overbend_strain"] == pytest.approx(0.5 * 0.3239 * default["overbend_curvature"], rel=1e-12)


def test_steel_inside_the_coating():
    d = _coated()
    d.pop("pipelay")
    d["line_types"] = {"p": {"outer_diameter": 0.4, "steel_outer_diameter": 0.5, "EA": 1e9, "EIy": 1e7,
                             "mass_per_length": 100.0}}
    with pytest.raises(rfesim.ScenarioError) as info:
        rfesim.load_scenario(d)
    assert "line_types.p.steel_outer_diameter" in str(info.value) and "inside the coating" in str(info.value)
