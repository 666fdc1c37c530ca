"""Lines sunk into the seabed deeper than their diameter are named (rfesim.seabed_check): in
the results' message after statics and dynamics, and as a statics hint when the seabed is
too soft for a line's own weight."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.seabed_check import _seabed_z

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def riser(**changes) -> dict:
    """The H1 riser (290 m of 12-inch pipe, 0.644 kN/m submerged, seabed 9e5 N/m/m), statics only."""
    d = json.loads((SCENARIOS / "h1_riser_heave.json").read_text())
    d["analysis"] = {"statics": {"enabled": True}, "dynamics": {"enabled": False}}
    for path, value in changes.items():
        node = d
        keys = path.split(".")
        for k in keys[:-1]:
            node = node[k]
        node[keys[-1]] = value
    return d


def test_one_element_riser_pushed_into_the_seabed_is_named():
    """One element: two rigid 145 m halves whose hinge would hang 58 m under the chord, below
    the seabed; statics puts it 3.24 m deep with 5e7 N on the seabed (and 7e7 N of compression
    in the SDE): named, with the weight's own 0.7 mm sinkage and the elements field."""
    res = rfesim.statics(riser(**{"lines.riser.elements": 1}))
    assert "line 'riser' sinks 3.24 m into the seabed (its underside, 145 m from end A at t = 0 s)" in res.message
    assert "alone sinks it only 0.000716 m, so the line is pushed in" in res.message
    assert "its elements (1 of 290 m) are too long to follow the seabed (lines.riser.elements)" in res.message


@pytest.mark.parametrize("elements", [4, 100])
def test_a_riser_resting_on_the_seabed_is_not_named(elements):
    res = rfesim.statics(riser(**{"lines.riser.elements": elements}))
    assert "sinks" not in res.message


def test_a_soft_seabed_is_named_in_the_results():
    """At 2000 N/m/m the 0.644 kN/m riser's weight alone sinks it 0.32 m, more than its 0.3 m
    diameter; at the touchdown, where the sagbend presses it down, 0.497 m."""
    res = rfesim.statics(riser(**{"environment.seabed.normal_stiffness": 2000.0}))
    assert "line 'riser' sinks 0.497 m into the seabed (its underside, 120.3 m from end A" in res.message
    assert "alone sinks it 0.322 m into the seabed's normal_stiffness (2000 N/m/m): the seabed is too soft for the " \
           "line (give environment.seabed.normal_stiffness for the soil" in res.message


def test_a_seabed_too_soft_for_statics_is_the_hint():
    """At 1.5 N/m/m (a unit slip) the riser would sink 429 m: statics fails, and the error
    says why instead of only asking for more iterations."""
    d = riser(**{"environment.seabed.normal_stiffness": 1.5})
    d["analysis"]["statics"]["max_iterations"] = 30
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.statics(d)
    text = str(info.value)
    assert "the seabed's normal_stiffness (1.5 N/m/m) lets line 'riser' sink 429 m under its own submerged " \
           "weight, more than its diameter (0.3 m)" in text
    assert "soft clays give 1e4 to 1e6 N/m/m" in text


def test_seabed_height_matches_the_contact_kernel():
    """The vectorised height and slope of a profile against the kernel's (inside the profile
    and beyond its ends, where it goes on with the end slopes)."""
    from rfesim.loads.seabed import seabed_height

    class Km:
        bed_s = np.array([-50.0, 0.0, 40.0, 100.0])
        bed_z = np.array([-80.0, -100.0, -95.0, -120.0])
        bed_dir = np.array([np.cos(0.3), np.sin(0.3)])

    rng = np.random.default_rng(3)
    x, y = rng.uniform(-200.0, 250.0, 40), rng.uniform(-50.0, 50.0, 40)
    z, g = _seabed_z(Km, x, y)
    out = np.zeros(3)
    for i in range(x.size):
        seabed_height(Km.bed_s, Km.bed_z, Km.bed_dir, x[i], y[i], out)
        assert z[i] == pytest.approx(out[0], rel=1e-12, abs=1e-9)
        assert g[i] * Km.bed_dir[0] == pytest.approx(out[1], rel=1e-12, abs=1e-12)


# ---------------------------------------------------------------- below the floor of a scene without seabed
def crane(rope_length: float, seabed: bool = False, duration: float = 0.0) -> dict:
    """The column crane (tip about 35 m above the water, 100 m deep, no seabed) with its
    payload on a rope of the given length."""
    d = json.loads((SCENARIOS / "column_crane.json").read_text())
    d["cranes"]["crane"]["rope"]["length"] = rope_length
    if seabed:
        d["environment"]["seabed"] = {"normal_stiffness": 1e6, "friction": 0.5}
    if duration:
        d["analysis"]["dynamics"].update(duration=duration, output_interval=0.5)
    else:
        d["analysis"] = {"statics": {"enabled": True}, "dynamics": {"enabled": False}}
    return rfesim.load_scenario(d, base_dir=SCENARIOS)


def test_a_payload_hung_below_the_sea_floor_is_named():
    """A 200 m rope from the tip: the module hangs about 64 m below the 100 m floor, which a
    scene without seabed did not mention."""
    from rfesim.seabed_check import below_bottom_warnings
    sc = crane(200.0)
    st = rfesim.statics(sc)
    z = float(np.asarray(st.bodies["crane_payload"].position)[0, 2])
    assert z < -150.0
    message = st.message
    assert (f"body 'crane_payload' goes {-100.0 - z:.4g} m below the sea floor (environment.water.depth 100 m, the "
            f"floor at z = -100 m; the scene has no seabed") in message, message
    assert "line 'crane_rope' goes " in message
    assert below_bottom_warnings(crane(32.0), rfesim.statics(crane(32.0))) == []


def test_a_scene_with_a_seabed_is_left_to_the_contact():
    from rfesim.seabed_check import below_bottom_warnings
    sc = crane(200.0, seabed=True)
    assert below_bottom_warnings(sc, rfesim.statics(crane(200.0))) == []


def test_the_dynamics_name_the_time():
    res = rfesim.simulate(crane(200.0, duration=1.0))
    assert "body 'crane_payload' goes " in res.message and " below the sea floor at t = " in res.message


def test_a_line_anchored_with_its_axis_on_the_floor_is_not_below_it():
    """Results of a 0.3 m line whose lowest point is its anchor at the floor (z = -100 m), and
    the same 0.5 m lower: only the second is named, 0.35 m below the floor (0.5 less the
    radius 0.15)."""
    from types import SimpleNamespace

    from rfesim.seabed_check import below_bottom_warnings
    sc = rfesim.load_scenario(json.loads((SCENARIOS / "catenary_riser.json").read_text()), base_dir=SCENARIOS)
    sc.environment.seabed = None
    sc.environment.water.depth = 100.0
    name = next(iter(sc.lines))
    sc.line_types[sc.lines[name].type].outer_diameter = 0.3

    def results(z0):
        pos = np.zeros((2, 3, 3))
        pos[:, :, 2] = [z0, z0 + 10.0, z0 + 20.0]
        line = SimpleNamespace(position=pos, arc_length=np.array([0.0, 10.0, 20.0]))
        return SimpleNamespace(time=np.array([0.0, 1.0]), lines={name: line}, line=lambda n: line, bodies={})

    assert below_bottom_warnings(sc, results(-100.0)) == []
    (w,) = below_bottom_warnings(sc, results(-100.5))
    assert w.startswith(f"line '{name}' goes 0.35 m below the sea floor at arc length 0 m at t = 0 s"), w
