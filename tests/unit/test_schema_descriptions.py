"""Schema points found by the scenario reference's review (2026-11-28): the section's rotary
inertia had no upper bound (1e300 was accepted), and the settings an engineer switches most
had no description."""
from __future__ import annotations

import pytest

import rfesim
from rfesim import ScenarioError


def _scene(**line_type):
    return {"line_types": {"pipe": {"EA": 1e9, "EIy": 1e6, "mass_per_length": 100.0, "outer_diameter": 0.3,
                                    **line_type}},
            "lines": {"l": {"type": "pipe", "length": 10.0, "elements": 4,
                            "end_a": {"attach": "fixed", "position": [0, 0, 0]},
                            "end_b": {"attach": "free", "position": [10, 0, 0]}}},
            "analysis": {"statics": {"enabled": False}}}


def test_rotary_inertia_is_bounded_with_its_reason():
    rfesim.load_scenario(_scene(rotary_inertia=5.0))
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(_scene(rotary_inertia=1e300))
    text = str(err.value)
    assert "line_types.pipe.rotary_inertia" in text and "radius of gyration of 10 m" in text


def test_the_switches_and_tolerances_are_described():
    schema = rfesim.Scenario.model_json_schema()
    defs = schema["$defs"]
    assert "rest" in defs["StaticsSettings"]["properties"]["enabled"]["description"]
    assert "Dormand-Prince" in defs["AdaptiveSettings"]["properties"]["rtol"]["description"]
    assert "rad/s" in defs["AdaptiveSettings"]["properties"]["atol"]["description"]
    assert "halved" in defs["GeneralizedAlphaSettings"]["properties"]["max_iterations"]["description"]
    for key in ("name", "environment", "vessels", "line_types", "lines", "analysis"):
        assert schema["properties"][key].get("description"), key
