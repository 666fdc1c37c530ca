"""A crane payload placed by the user off the vertical under its sheave is warned
(rfesim.scenario.cranes._off_lead): the lift starts with a side pull."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import rfesim
from rfesim.scenario.cranes import OFF_LEAD_DEG

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def liftoff(**crane) -> dict:
    d = json.loads((SCENARIOS / "column_crane_liftoff.json").read_text())
    d["cranes"]["crane"].update(crane)
    return d


def warnings_of(d: dict) -> list[str]:
    return [w for w in rfesim.load_scenario(d, base_dir=SCENARIOS)._template_warnings if "off lead" in w]


def test_a_payload_left_behind_by_a_luffing_change_is_off_lead():
    """Luffed to 38.5 deg, the 30 m boom's tip reaches 6.27 m past the payload the scenario
    placed under it at 55 deg: atan(6.27 / 29.68) = 11.9 deg."""
    found = warnings_of(liftoff(luffing_deg=38.5))
    assert len(found) == 1
    w = found[0]
    assert w.startswith("cranes.crane.payload.position: the rope's end on the payload starts ")
    aside = float(w.split("starts ")[1].split(" m aside")[0])
    angle = float(w.split(", ")[1].split(" deg off lead")[0])
    drop = float(w.split("over its ")[1].split(" m drop")[0])
    reach = 30.0 * (math.cos(math.radians(38.5)) - math.cos(math.radians(55.0)))
    assert aside == pytest.approx(reach, abs=0.02)
    assert angle == pytest.approx(math.degrees(math.atan2(aside, drop)), abs=0.05)


def test_under_the_sheave_or_placed_by_the_template_is_not_warned():
    assert warnings_of(liftoff()) == []                      # the shipped lift-off: under the tip
    d = liftoff(luffing_deg=38.5)
    d["cranes"]["crane"]["payload"].pop("deck")
    d["cranes"]["crane"]["payload"].pop("position")          # hung straight under the sheave
    assert warnings_of(d) == []
    # a little aside, within OFF_LEAD_DEG, is not warned either
    step = math.degrees(math.atan2(30.0 * (math.cos(math.radians(54.0)) - math.cos(math.radians(55.0))), 29.7))
    assert step < OFF_LEAD_DEG
    assert warnings_of(liftoff(luffing_deg=54.0)) == []


def test_the_off_lead_lift_runs_its_bight_resting_on_the_rope_contact():
    """The lift luffed to 38.5 deg stopped at 13.79 s, its slack bight telescoped through
    itself as the winch hauled (rope elements pushed through one another). With the rope's
    axial contact (rfesim.loads.tension_only) it runs its 30 s: the bight bunches onto the
    contact with under 0.1 kN, far below the rope's 1.8 kN weight, so no 'driven into itself'
    warning; the payload lifts off and the rope takes it."""
    res = rfesim.simulate(rfesim.load_scenario(liftoff(luffing_deg=38.5), base_dir=SCENARIOS))
    assert res.status == 0 and res.time[-1] == pytest.approx(45.0)
    tension = res.line("crane_rope").tension
    assert -1000.0 < tension.min() < 0.0                        # the contact held, gently
    assert tension.max() > 98.1e3                                # the rope took the 10 t module
    assert "driven into itself" not in res.message and "pushed through" not in res.message
