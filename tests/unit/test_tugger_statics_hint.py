"""A statics that fails because constant-tension tuggers pull a body sideways harder than
its weight lets it hold (rfesim.api._tugged_off) says so. The lift-off's module given 1 kg
(its two 3 kN tuggers pull it 4.94 kN towards the barge) failed with only 'raise
analysis.statics.max_iterations'."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

import rfesim
from rfesim.api import _tugged_off
from rfesim.model.compile import compile_scenario

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
G = 9.81


def lift_off(mass: float, deck: bool = True) -> rfesim.Scenario:
    d = json.loads((SCENARIOS / "column_crane_liftoff.json").read_text())
    d["analysis"].pop("dynamics", None)
    payload = d["cranes"]["crane"]["payload"]
    payload["mass"] = mass
    if not deck:
        payload.pop("deck")
    return rfesim.load_scenario(d, base_dir=SCENARIOS)


def side_pull() -> float:
    """The two tuggers' horizontal resultant at the start: 3 kN each from deck points
    (+-12, 14, 4) of the barge to points 1.5 m fore and aft of the module's centre
    (0, 29.2073, 4), level with them."""
    dy = 29.2073 - 14.0
    return 2 * 3000.0 * dy / (dy ** 2 + 10.5 ** 2) ** 0.5


def test_a_statics_failure_names_tuggers_the_deck_friction_cannot_hold():
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.statics(lift_off(1.0))
    message = str(info.value)
    assert "the tuggers 'crane_fore', 'crane_aft' on body 'crane_payload' pull it sideways with " \
           f"{side_pull() / 1e3:.4g} kN at the start, more than the deck's friction holds: 0.5 times the " in message
    # its 9.81 N of weight less the tuggers' slight lift (the module's centre starts 6 mm below
    # their deck points)
    pressed = float(message.split("0.5 times the ")[1].split(" kN")[0]) * 1e3
    assert 0.5 * G < pressed <= G, pressed
    assert "give the tuggers less tension (cranes.crane.tuggers.fore.mode.tension)" in message


@pytest.mark.parametrize("mass, deck, named", [
    (1000.0, True, True),      # 0.5 x 9.81 kN = 4.9 kN < 4.94 kN
    (1100.0, True, False),     # 5.4 kN of friction
    (10000.0, True, False),    # the shipped module
    (400.0, False, True),      # hanging: 3.9 kN of weight against 4.94 kN sideways, past 45 deg
    (600.0, False, False),
])
def test_which_bodies_are_named(mass, deck, named):
    sc = lift_off(mass, deck)
    hints = _tugged_off(sc, compile_scenario(sc))
    assert bool(hints) == named, hints
    if named:
        assert f"{side_pull() / 1e3:.4g} kN" in hints[0]
        assert ("deck's friction" in hints[0]) == deck
        assert ("lean past 45 deg" in hints[0]) == (not deck)
