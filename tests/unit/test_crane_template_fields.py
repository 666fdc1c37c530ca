"""Crane template fields as the user wrote them: a winch that runs out of rope names
``cranes.<c>.winch.stored`` (not the made ``winches.<c>_winch``); ``crossbeam_mass`` says
what it holds with and without a ``crossbeam`` member."""
from __future__ import annotations

import pytest

import rfesim
from rfesim.scenario.cranes import AFrame

G = 9.81


def test_crane_winch_out_of_rope_names_the_template_field():
    data = {"environment": {"gravity": G},
            "cranes": {"c": {"type": "column", "position": [0.0, 0.0, 2.0],
                             "pedestal": {"length": 8.0, "outer_diameter": 2.0, "wall_thickness": 0.04,
                                          "elements": 4},
                             "boom": {"length": 20.0, "outer_diameter": 0.8, "wall_thickness": 0.02, "elements": 4},
                             "luffing_deg": 40.0, "rope": {"length": 10.0, "elements": 5},
                             "payload": {"mass": 5000.0, "radius_of_gyration": 1.0},
                             # a free drum (no motor torque) runs away under the payload
                             "winch": {"stored": 1.0, "mode": {"kind": "drum", "radius": 0.5, "inertia": 100.0}}}},
            "analysis": {"statics": {"enabled": False},
                         "dynamics": {"duration": 3.0, "output_interval": 0.1,
                                      "integrator": {"kind": "generalized-alpha", "time_step": 0.01}}}}
    with pytest.raises(rfesim.SolverError) as err:
        rfesim.simulate(data)
    msg = str(err.value)
    assert "ran out of rope" in msg and "1 m stored on the drum (cranes.c.winch.stored)" in msg
    assert "winches.c_winch.stored" not in msg


def test_crossbeam_mass_says_what_it_holds_in_each_frame():
    text = AFrame.model_fields["crossbeam_mass"].description
    assert "Without `crossbeam`: the mass of the whole crossbeam with its sheave block" in text
    assert "with a `crossbeam` member: only what its tube leaves out, the sheave block" in text


def test_a_crossbeam_not_as_long_as_the_leg_spacing_says_they_must_be_equal():
    """The A-frame with a deck winch given leg_spacing 9.5 m (its crossbeam 6 m): the error
    names the crossbeam and the rule, not only the two numbers."""
    import json
    from pathlib import Path
    scenarios = Path(__file__).resolve().parents[2] / "scenarios"
    d = json.loads((scenarios / "a_frame_deck_winch.json").read_text())
    frame = next(c for c in d["cranes"].values() if c.get("crossbeam"))
    frame["leg_spacing"] = frame["crossbeam"]["length"] + 3.5
    with pytest.raises(rfesim.ScenarioError) as err:
        rfesim.load_scenario(d, base_dir=scenarios)
    msg = str(err.value)
    assert "crossbeam.length: 6.0 m: the crossbeam spans the legs, so its length must equal leg_spacing (9.5 m)" in msg
