"""A pipelay template whose laid_length puts thousands of elements on the seabed, far beyond
what the lay feels, is named (rfesim.scenario.pipelay.LAID_ELEMENTS): a reel-lay given
100 km of laid pipe sat in its statics for minutes with no word on why."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

import rfesim
from rfesim.scenario.pipelay import LAID_DEPTHS, LAID_ELEMENTS

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def warnings(name: str, laid: float | None = None) -> list[str]:
    d = json.loads((SCENARIOS / name).read_text())
    if laid is not None:
        d["pipelay"]["lay"]["laid_length"] = laid
    return [w for w in rfesim.load_scenario(d, base_dir=SCENARIOS)._template_warnings
            if w.startswith("pipelay.lay.laid_length")]


@pytest.mark.parametrize("name", ["reel_lay.json", "s_lay_template.json", "j_lay.json"])
def test_the_shipped_pipelay_scenarios_lay_a_short_tail(name):
    assert warnings(name) == []


def test_a_long_laid_tail_is_named_with_its_elements():
    (w,) = warnings("reel_lay.json", 100000.0)
    sc = rfesim.load_scenario(json.loads((SCENARIOS / "reel_lay.json").read_text()), base_dir=SCENARIOS)
    depth = sc.environment.water.depth
    assert w.startswith(f"pipelay.lay.laid_length: 100000 m of pipe on the seabed ({100000.0 / depth:.3g} times the "
                        f"water depth) makes about 50000 of the line's "), w
    assert "give a laid_length of a few water depths" in w


def test_the_limits_are_elements_and_water_depths():
    """Reel-lay in 300 m with 2 m elements: 3500 m is past 10 depths but makes only 1750
    elements, 4500 m makes 2250. J-lay in 1200 m with 1.5 m elements: 11 km makes 7300
    elements but is under 10 depths, 20 km is past both."""
    assert LAID_DEPTHS == 10.0 and LAID_ELEMENTS == 2000
    assert warnings("reel_lay.json", 3500.0) == []
    assert len(warnings("reel_lay.json", 4500.0)) == 1
    assert warnings("j_lay.json", 11000.0) == []
    assert len(warnings("j_lay.json", 20000.0)) == 1
