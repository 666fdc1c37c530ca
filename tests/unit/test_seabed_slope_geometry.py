"""Lines on a sloped seabed (audit of 2026-11-27): the touchdown output, the seabed-fold
warning of statics and the seabed fields that apply to one geometry only.

* The touchdown point took the contact side of its RFE from the sign of the RFE axis's z,
  right on a flat seabed only: on a 10 deg slope rising towards the grounded end it reported
  47.50 m of arc (a point 0.26 m above the seabed) where the pipe touches down at 52.1 m.
* The fold warning took "hang vertically and lie straight" as the horizontal span plus the
  height of the ends: a 125 m line onto a +10 deg slope was told it folds (up to 138.6 m
  fits), a 160 m line onto a -20 deg slope was not (143.7 m fits).
"""
import math

import numpy as np
import pytest

import rfesim
from rfesim.errors import ScenarioError
from rfesim.model.compile import compile_scenario

PIPE = {"outer_diameter": 0.3, "wall_thickness": 0.02, "youngs_modulus": 2.07e11, "poisson_ratio": 0.3,
        "density": 7850.0}


def onto_slope(phi, length=125.0, dynamics=False):
    """A pipe pinned 30 m up (over the seabed under it at x = -40) down to a point resting on
    a plane seabed through the origin rising at phi degrees along +x."""
    g = math.tan(math.radians(phi))
    sc = {"environment": {"gravity": 9.81,
                          "seabed": {"z": 0.0, "slope_deg": phi, "normal_stiffness": 1e6, "friction": 0.0}},
          "line_types": {"p": PIPE},
          "lines": {"L": {"type": "p", "length": length, "elements": 25,
                          "end_a": {"attach": "fixed", "position": [-40.0, 0.0, 30.0 + max(0.0, -60.0 * g)],
                                    "connection": "pinned"},
                          "end_b": {"attach": "fixed", "position": [60.0, 0.0, 60.0 * g + 0.149],
                                    "connection": "pinned"}}},
          "analysis": {"statics": {"enabled": True}}}
    if dynamics:
        sc["analysis"]["dynamics"] = {"duration": 0.2, "output_interval": 0.1,
                                      "integrator": {"kind": "generalized-alpha", "time_step": 0.01}}
    return sc


def geometric_touchdown(pos, phi, radius=0.15):
    """Arc length along the output polyline where the pipe's underside first meets the plane."""
    n = np.array([-math.sin(math.radians(phi)), 0.0, math.cos(math.radians(phi))])
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pos, axis=0), axis=1))])
    s = np.linspace(0.0, arc[-1], 100001)
    P = np.column_stack([np.interp(s, arc, pos[:, k]) for k in range(3)])
    return s[np.argmax(P @ n - radius <= 0.0)], n


@pytest.mark.parametrize("phi", [10.0, -10.0])
def test_touchdown_on_a_slope_is_where_the_pipe_meets_the_seabed(phi):
    res = rfesim.simulate(onto_slope(phi, dynamics=True))
    line = res.lines["L"]
    for row in (0, -1):     # statics (Python) and the compiled recording of the run
        pos = np.asarray(line.position)[row]
        s_geo, n = geometric_touchdown(pos, phi)
        s_td = float(np.asarray(line.touchdown_arc_length)[row])
        # within the resolution of the output polyline (5 m RFEs; 0.2 m on a flat seabed)
        assert abs(s_td - s_geo) < 0.5, (row, s_td, s_geo)
        p = np.asarray(line.touchdown_position)[row]
        assert abs(float(p @ n) - 0.15) < 0.05


def test_the_fold_warning_measures_along_the_slope():
    up = compile_scenario(rfesim.load_scenario(onto_slope(10.0))).lines[0]
    assert up.seabed_fold is None           # 125 m < 138.6 m: hangs and lies straight
    res = rfesim.statics(rfesim.load_scenario(onto_slope(10.0)))
    assert "folds on the seabed" not in res.message
    down = compile_scenario(rfesim.load_scenario(onto_slope(-20.0, length=160.0))).lines[0]
    length, span, height, limit, drop = down.seabed_fold
    assert drop == 0.0
    # end A at 30 m + 60 tan 20 over z = 0, the seabed under it at 40 tan 20, end B 0.149 m over
    # it: a 37.13 m hang, then 100 m / cos 20 deg along the slope (143.55 m; the flat formula
    # gave the span plus the height of the ends, 173.5 m)
    g = math.tan(math.radians(20.0))
    assert length == 160.0 and span == pytest.approx(100.0)
    assert height == pytest.approx(30.0 + 20.0 * g - 0.149, rel=1e-9)
    assert limit == pytest.approx(height + 100.0 / math.cos(math.radians(20.0)), rel=1e-9)


def scene_with_seabed(seabed, water=None):
    sc = {"environment": {"water": water or {"density": 1025.0}, "seabed": seabed},
          "line_types": {"p": PIPE},
          "lines": {"L": {"type": "p", "length": 10.0, "elements": 2,
                          "end_a": {"attach": "fixed", "position": [0.0, 0.0, -10.0]},
                          "end_b": {"attach": "free", "position": [10.0, 0.0, -10.0]}}}}
    return sc


@pytest.mark.parametrize("seabed, field", [
    ({"z": -50.0, "slope_deg": 5.0, "profile_direction_deg": 90.0}, "profile_direction_deg"),
    ({"profile": [[-100.0, -60.0], [100.0, -40.0]], "slope_direction_deg": 90.0}, "slope_direction_deg"),
])
def test_a_direction_of_the_other_seabed_geometry_is_refused(seabed, field):
    with pytest.raises(ScenarioError, match=field):
        rfesim.load_scenario(scene_with_seabed(seabed))


def test_water_depth_must_match_a_seabed_profile():
    prof = {"profile": [[-100.0, -60.0], [100.0, -40.0]]}       # 50 m deep at the origin
    with pytest.raises(ScenarioError, match=r"water.depth.*100 m does not match the seabed profile, 50 m deep"):
        rfesim.load_scenario(scene_with_seabed(prof, {"depth": 100.0}))
    sc = rfesim.load_scenario(scene_with_seabed(prof, {"depth": 50.0}))
    assert sc.environment.seabed_z_at(0.0, 0.0) == pytest.approx(-50.0)
