"""A statics that cannot succeed says why, where the scene shows it (rfesim.api._statics_hint):
a line with no support, slack lying on the seabed; and the start shape of such slack has no
NaN in it (rfesim.model.compile._Curve with repeated points)."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.model.compile import _Curve, compile_scenario


def cantilever(end_a: dict) -> dict:
    return {
        "name": "hint cantilever",
        "environment": {"gravity": 9.81},
        "line_types": {"beam": {"EA": 1.0e8, "EIy": 1.0e5, "mass_per_length": 50.0}},
        "lines": {"pipe": {"type": "beam", "length": 10.0, "elements": 10, "end_a": end_a,
                           "end_b": {"attach": "free"}}},
        "analysis": {"statics": {"enabled": True}},
    }


def rope_on_seabed(length: float, z_end: float = -99.97) -> dict:
    """A rope between two points 5 m apart lying on a seabed at z = -100 m."""
    return {
        "name": "rope on the seabed",
        "environment": {"gravity": 9.81, "water": {"depth": 100.0},
                        "seabed": {"normal_stiffness": 1e5, "friction": 0.0}},
        "line_types": {"rope": {"EA": 1e8, "EIy": 10.0, "mass_per_length": 10.0, "outer_diameter": 0.05,
                                "tension_only": True}},
        "lines": {"r": {"type": "rope", "length": length, "elements": 20,
                        "end_a": {"attach": "fixed", "position": [0.0, 0.0, z_end]},
                        "end_b": {"attach": "fixed", "position": [5.0, 0.0, z_end]}}},
        "analysis": {"statics": {"enabled": True}},
    }


def test_line_without_support_is_named_when_statics_fails():
    data = cantilever({"attach": "free", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0]})
    with pytest.raises(rfesim.SolverError) as err:
        rfesim.statics(rfesim.load_scenario(data))
    assert "line 'pipe' has no support (both ends free)" in str(err.value)
    assert err.value.message.startswith("static equilibrium not found")
    assert "analysis.statics.enabled" in err.value.hint


def test_slack_on_the_seabed_is_named_when_statics_fails():
    with pytest.raises(rfesim.SolverError) as err:
        rfesim.statics(rfesim.load_scenario(rope_on_seabed(20.0)))
    text = str(err.value)
    assert "line 'r' has both ends on the seabed and 15 m of slack (20 m between points 5 m apart)" in text
    assert "nan" not in err.value.message.lower()          # the start shape is finite


def test_start_of_slack_on_the_seabed_is_finite():
    model = compile_scenario(rfesim.load_scenario(rope_on_seabed(20.0)))
    assert np.isfinite(model.initial.q).all()
    # a curve whose slack is bunched up at its end (repeated points): the chain marches past
    # them along the last real direction, each joint at its straight distance
    curve = _Curve(np.array([0.0, 1.0, 2.0, 3.0]),
                   np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]))
    pts = curve._march(np.zeros(3), np.full(3, 0.75))
    assert np.isfinite(pts).all()
    assert np.allclose(np.linalg.norm(np.diff(pts, axis=0), axis=1), 0.75)
    assert np.allclose(pts[:, 1:], 0.0) and np.all(np.diff(pts[:, 0]) > 0)


def test_no_hint_for_a_line_as_long_as_its_span():
    """A taut rope on the seabed has a static shape: no slack hint, and statics converges."""
    res = rfesim.statics(rfesim.load_scenario(rope_on_seabed(5.0)))
    assert res.status == 0
    assert np.isfinite(res.line("r").tension[0]).all()


def riser_from_seabed(length: float) -> dict:
    """A 20 kg/m line from an anchor on the seabed at 50 m depth to a point 120 m away at the surface."""
    return {"environment": {"gravity": 9.81, "water": {"depth": 50.0},
                            "seabed": {"normal_stiffness": 1e5, "friction": 0.0}},
            "line_types": {"p": {"EA": 1e8, "EIy": 1e6, "mass_per_length": 20.0, "outer_diameter": 0.1}},
            "lines": {"l": {"type": "p", "length": length, "elements": 20,
                            "end_a": {"attach": "fixed", "position": [0.0, 0.0, -50.0]},
                            "end_b": {"attach": "fixed", "position": [120.0, 0.0, 0.0]}}},
            "analysis": {"statics": {"enabled": True}}}


def test_a_line_too_long_to_hang_and_lie_straight_is_named():
    """200 m from the seabed to a point 50 m up and 120 m away: 30 m more than can hang
    vertically and lie straight. Statics settled with the last 50 m standing 4 m deep in the
    seabed under 1.6 MN of compression, with only a buckling warning; now a warning says why
    first, or the failure says why (whether Newton settles on such a shape is a matter of
    round-off). 160 m (10 m less than span + height) gets none."""
    try:
        text = rfesim.statics(rfesim.load_scenario(riser_from_seabed(200.0))).message
    except rfesim.SolverError as exc:
        text = str(exc)
    assert ("line 'l' runs from the seabed to a point 50 m up and 120 m away, and is 30 m "
            "longer (200 m) than can hang vertically and lie straight on the seabed (170 m)") in text
    res = rfesim.statics(rfesim.load_scenario(riser_from_seabed(160.0)))
    assert "warning" not in res.message
    assert compile_scenario(rfesim.load_scenario(riser_from_seabed(160.0))).lines[0].seabed_fold is None
