"""A static equilibrium with a line folded back on itself is named (rfesim.solvers.buckling.
fold_warnings): slack bunched up by its start shape, whose tensions are not the line's."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import rfesim
from rfesim.solvers.buckling import FOLD
from tests.validation.test_u_shaped_line import scene

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def test_slack_folded_on_the_seabed_is_named():
    """160 m of chain from the seabed to a point 50 m up and 100 m away is 10 m longer than can
    hang and lie straight: statics converges with the rest folded on the seabed."""
    d = scene(160.0)
    d["lines"]["l"]["end_a"]["position"] = [0.0, 0.0, -99.95]
    d["lines"]["l"]["end_b"]["position"] = [100.0, 0.0, -50.0]
    res = rfesim.simulate(rfesim.load_scenario(d))
    msg = res.message
    assert "statics warning: line 'l' lies folded back on itself at " in msg
    assert "this equilibrium has slack bunched up, and its tensions are not the line's" in msg
    # the angle it names is past the right angle
    angle = float(msg.split("its elements meet at up to ")[1].split(" deg")[0])
    assert math.degrees(FOLD) < angle <= 180.0


def test_a_u_shaped_line_is_not_folded():
    res = rfesim.simulate(rfesim.load_scenario(scene(300.0)))
    assert "folded" not in res.message


@pytest.mark.parametrize("name", ["catenary_riser.json", "s_lay.json", "column_crane.json"])
def test_bundled_scenarios_are_not_folded(name):
    d = json.loads((SCENARIOS / name).read_text())
    d["analysis"].pop("dynamics", None)
    d["analysis"].pop("modal", None)
    res = rfesim.simulate(rfesim.load_scenario(d, base_dir=SCENARIOS))
    assert res.message.startswith("statics only")
    assert "folded" not in res.message
