"""Crane templates (rfesim.scenario.cranes): expansion into a serial string of joined lines,
geometry of the boom / legs and the payload under the sheave, drive axes that turn the
boom the right way, the luffing-cylinder triangle, errors that name the template field,
and the slack-event detection of rfesim.crane_results."""
from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest

import rfesim
from rfesim.crane_results import slack_events
from rfesim.scenario import expand
from rfesim.scenario.cranes import CylinderSpec, cylinder_angle, cylinder_lever

PAYLOAD = {"mass": 5000.0, "radius_of_gyration": 1.0, "volume": 1.0, "height": 1.0}


def column(**over):
    tpl = {"type": "column", "vessel": "ship", "position": [2.0, 5.0, 3.0],
           "pedestal": {"length": 10.0, "outer_diameter": 2.0, "wall_thickness": 0.04},
           "boom": {"length": 20.0, "outer_diameter": 1.0, "wall_thickness": 0.02},
           "slewing_deg": 30.0, "luffing_deg": 40.0, "rope": {"length": 12.0}, "payload": dict(PAYLOAD)}
    tpl.update(over)
    return {"vessels": {"ship": {"position": [100.0, 50.0, 0.0], "heading_deg": 20.0}},
            "cranes": {"c": tpl}, "analysis": {"dynamics": {"enabled": False}}}


def a_frame(**over):
    tpl = {"type": "a-frame", "position": [-40.0, 0.0, 4.0], "legs": {"length": 8.0, "EA": 1e10, "EI": 1e9,
                                                                       "mass_per_length": 300.0},
           "tilt_deg": 20.0, "rope": {"length": 4.0}, "payload": dict(PAYLOAD)}
    tpl.update(over)
    return {"cranes": {"af": tpl}, "analysis": {"dynamics": {"enabled": False}}}


def errors_of(data):
    with pytest.raises(rfesim.ScenarioError) as info:
        expand(data)
    return dict(info.value.errors)


def rotate(v, axis, angle):
    """Rodrigues: v turned by angle (rad) about the unit axis."""
    v, k = np.asarray(v, float), np.asarray(axis, float) / np.linalg.norm(axis)
    return v * math.cos(angle) + np.cross(k, v) * math.sin(angle) + k * (k @ v) * (1 - math.cos(angle))


def test_column_expands_into_a_joined_string_deterministically():
    data = column()
    before = copy.deepcopy(data)
    a, b = expand(data), expand(copy.deepcopy(data))
    assert data == before and json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)
    assert "cranes" not in a
    lines = a["lines"]
    assert list(lines) == ["c_pedestal", "c_boom", "c_rope"]
    assert lines["c_pedestal"]["end_a"] == {"attach": "ship", "position": [2.0, 5.0, 3.0],
                                            "direction": [0.0, 0.0, 1.0], "connection": "clamped"}
    assert lines["c_boom"]["end_a"]["attach"] == "c_pedestal:end_b"
    assert lines["c_boom"]["end_a"]["connection"] == "clamped"
    assert lines["c_rope"]["end_a"] == {"attach": "c_boom:end_b", "connection": "pinned",
                                        "direction": [0.0, 0.0, -1.0]}
    assert lines["c_rope"]["end_b"]["attach"] == "c_payload"
    assert a["line_types"]["c_rope_section"]["tension_only"] is True
    # constant angles: drives that hold still (their torques are outputs)
    assert [(d["name"], d["angle"]) for d in lines["c_boom"]["end_a"]["drives"]] == [
        ("slewing", [[0.0, 30.0], [1.0, 30.0]]), ("luffing", [[0.0, 40.0], [1.0, 40.0]])]


def test_column_geometry_tip_and_payload():
    """Boom direction: luffing above the horizontal, slewing from the vessel's x axis, turned
    by the heading; the payload's attachment point hangs a rope length under the tip."""
    a = expand(column())
    slew, luff, head = math.radians(30 + 20), math.radians(40), math.radians(20)
    d = np.array(a["lines"]["c_boom"]["end_a"]["direction"])
    assert np.allclose(d, [math.cos(luff) * math.cos(slew), math.cos(luff) * math.sin(slew), math.sin(luff)],
                       atol=1e-12)
    c, s = math.cos(head), math.sin(head)
    base = np.array([100 + c * 2 - s * 5, 50 + s * 2 + c * 5, 3.0])
    tip = base + [0, 0, 10.0] + 20.0 * d
    body = a["bodies"]["c_payload"]
    attach = np.array(a["lines"]["c_rope"]["end_b"]["position"])
    assert np.allclose(attach, [0, 0, 0.5])                   # top of a 1 m high body
    assert np.allclose(np.array(body["position"]) + attach, tip - [0, 0, 12.0], atol=1e-9)


def test_column_drive_axes_turn_the_boom_the_right_way():
    """Turning the boom direction about the slewing axis by +da gives the direction at
    slewing + da; about the luffing axis by +da, luffing + da."""
    tables = column(slewing_deg=[[0, 30], [10, 60]], luffing_deg=[[0, 40], [10, 55]])
    drives = {d["name"]: d for d in expand(tables)["lines"]["c_boom"]["end_a"]["drives"]}
    assert drives["slewing"]["angle"] == [[0.0, 30.0], [10.0, 60.0]]
    assert drives["luffing"]["angle"] == [[0.0, 40.0], [10.0, 55.0]]
    head = math.radians(20)

    def direction(slew, luff):
        s, l = math.radians(slew) + head, math.radians(luff)
        return np.array([math.cos(l) * math.cos(s), math.cos(l) * math.sin(s), math.sin(l)])

    d0 = direction(30, 40)
    assert np.allclose(rotate(d0, drives["slewing"]["axis"], math.radians(7)), direction(37, 40), atol=1e-12)
    assert np.allclose(rotate(d0, drives["luffing"]["axis"], math.radians(7)), direction(30, 47), atol=1e-12)
    # slewing first, then luffing about the slewed axis: Rot(a1, ds) Rot(a2, dl) d0
    both = rotate(rotate(d0, drives["luffing"]["axis"], math.radians(5)), drives["slewing"]["axis"],
                  math.radians(25))
    assert np.allclose(both, direction(55, 45), atol=1e-12)


def test_a_frame_string_and_tilt_axis():
    a = expand(a_frame(tilt_deg=[[0, -20], [10, 30]]))
    assert list(a["lines"]) == ["af_stub", "af_legs", "af_crossbeam", "af_rope"]
    legs = a["lines"]["af_legs"]
    assert legs["end_a"]["attach"] == "af_stub:end_b"
    assert a["lines"]["af_stub"]["end_a"]["position"] == [-40.0, 0.0, 3.0]   # 1 m under the hinge
    # two legs as one line: twice the axial and in-plane stiffness and mass
    lt = a["line_types"]["af_legs_section"]
    assert lt["EA"] == 2e10 and lt["EIy"] == 2e9 and lt["mass_per_length"] == 600.0
    assert lt["EIz"] == pytest.approx(2e9 + 2e10 * 3.0 ** 2)
    d0 = np.array(legs["end_a"]["direction"])                 # 20 deg inboard of the vertical, stern at -x
    assert np.allclose(d0, [math.sin(math.radians(20)), 0.0, math.cos(math.radians(20))], atol=1e-12)
    axis = legs["end_a"]["drives"][0]["axis"]
    # +50 deg about the luffing axis: 30 deg outboard (toward -x)
    assert np.allclose(rotate(d0, axis, math.radians(50)),
                       [-math.sin(math.radians(30)), 0.0, math.cos(math.radians(30))], atol=1e-12)



def heeled(data: dict, vessel: str, roll: float = 0.0, pitch: float = 0.0, heave: float = 0.0) -> dict:
    """The scene with its vessel held at a roll, pitch and heave from t = 0 (a motion table)."""
    data.setdefault("vessels", {}).setdefault(vessel, {})["motion"] = {
        "kind": "table", "interpolation": "linear",
        "rows": [[0, 0, 0, heave, roll, pitch, 0], [100, 0, 0, heave, roll, pitch, 0]]}
    return data


def rx(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def test_a_crane_on_a_heeled_vessel_starts_as_built_on_its_deck():
    """A vessel at 5 deg roll and 0.5 m heave at t = 0: the boom's direction, the drive axes
    and the tip (the payload under it) turn and move with the deck, as the pedestal clamped
    to it does. Before, they were placed as on a level deck, and the joint's rest rotation
    took the heel into the luffing angle for the whole run."""
    level, heel = expand(column()), expand(heeled(column(), "ship", roll=5.0, heave=0.5))
    h = math.radians(20.0)
    R = np.array([[math.cos(h), -math.sin(h), 0.0], [math.sin(h), math.cos(h), 0.0], [0.0, 0.0, 1.0]])
    turn = R @ rx(5.0) @ R.T               # the level scene's global directions, heeled about the vessel's x
    boom_l, boom_h = level["lines"]["c_boom"]["end_a"], heel["lines"]["c_boom"]["end_a"]
    assert np.allclose(boom_h["direction"], turn @ boom_l["direction"], atol=1e-12)
    for dl, dh in zip(boom_l["drives"], boom_h["drives"]):
        assert np.allclose(dh["axis"], turn @ np.asarray(dl["axis"]), atol=1e-12)
    base = np.array([100.0, 50.0, 0.0])
    tip_l = np.array(level["bodies"]["c_payload"]["position"]) + [0.0, 0.0, 12.5]
    tip_h = np.array(heel["bodies"]["c_payload"]["position"]) + [0.0, 0.0, 12.5]
    assert np.allclose(tip_h, base + [0.0, 0.0, 0.5] + turn @ (tip_l - base), atol=1e-9)
    # an A-frame pitched 5 deg: its legs' direction and tilt axis turn with the deck
    ry = np.array([[math.cos(math.radians(5)), 0.0, math.sin(math.radians(5))], [0.0, 1.0, 0.0],
                   [-math.sin(math.radians(5)), 0.0, math.cos(math.radians(5))]])
    al = expand(a_frame())["lines"]["af_legs"]["end_a"]
    ah = expand(heeled(a_frame(vessel="v"), "v", pitch=5.0))["lines"]["af_legs"]["end_a"]
    assert np.allclose(ah["direction"], ry @ np.asarray(al["direction"]), atol=1e-12)
    assert np.allclose(ah["drives"][0]["axis"], ry @ np.asarray(al["drives"][0]["axis"]), atol=1e-12)


def test_a_heeled_crane_in_statics_keeps_its_luffing_angle_to_the_deck():
    """Statics of the column crane at 5 deg roll: the angle between pedestal and boom is the
    level crane's (50.35 deg: 40 deg luffing and the boom's sag) within the change of its
    elastic sag under the heeled gravity (50.32 deg); before, 55.06 deg."""
    def angle(data):
        st = rfesim.statics(rfesim.load_scenario(data))
        p, b = (np.asarray(st.line(n).position[0]) for n in ("c_pedestal", "c_boom"))
        a, d = p[-1] - p[0], b[-1] - b[0]
        return math.degrees(math.acos(a @ d / np.linalg.norm(a) / np.linalg.norm(d)))

    data = column(slewing_deg=70.0)
    data["analysis"] = {"statics": {"enabled": True}}
    level = angle(copy.deepcopy(data))
    assert 50.0 < level < 51.0
    assert angle(heeled(data, "ship", roll=5.0)) == pytest.approx(level, abs=0.15)


def test_a_drive_table_from_before_t0_starts_where_its_drive_does():
    """slewing_deg [[-10, 0], [1, 90], [20, 90]]: the boom starts at the value of the monotone
    cubic the drive follows (88.83 deg at t = 0), not at the straight line between the rows
    (81.82 deg), which left it 7 deg short of the table for the whole run."""
    from scipy.interpolate import PchipInterpolator
    table = [[-10.0, 0.0], [1.0, 90.0], [20.0, 90.0]]
    start = float(PchipInterpolator([r[0] for r in table], [r[1] for r in table])(0.0))
    assert start == pytest.approx(88.828, abs=1e-3)
    d = expand(column(slewing_deg=table))["lines"]["c_boom"]["end_a"]["direction"]
    assert math.degrees(math.atan2(d[1], d[0])) == pytest.approx(start + 20.0, abs=1e-9)   # + the heading


def test_cylinder_triangle_round_trip_and_lever():
    cyl = CylinderSpec(base=[2.5, -4.0], eye=10.0)
    for deg in (0.0, 20.0, 45.0, 70.0):
        a = math.radians(deg)
        length, lever = cylinder_lever(cyl, a)
        assert cylinder_angle(cyl, length) == pytest.approx(a, abs=1e-12)
        # lever = d(length)/d(angle) * eye-independent identity: virtual work F dL = M da
        h = 1e-6
        dL = (cylinder_lever(cyl, a + h)[0] - cylinder_lever(cyl, a - h)[0]) / (2 * h)
        assert lever == pytest.approx(dL, rel=1e-6)
    with pytest.raises(rfesim.ScenarioError, match="cannot reach"):
        expand(column(luffing_deg=None, cylinder={"base": [2.5, -4.0], "eye": 10.0, "stroke": [[0, 30.0]]}))


def test_stroke_table_becomes_the_luffing_table():
    cyl = {"base": [2.5, -4.0], "eye": 10.0}
    L40 = cylinder_lever(CylinderSpec(**cyl), math.radians(40))[0]
    L60 = cylinder_lever(CylinderSpec(**cyl), math.radians(60))[0]
    a = expand(column(luffing_deg=None, cylinder=dict(cyl, stroke=[[0, L40], [20, L60]])))
    slewing, drive = a["lines"]["c_boom"]["end_a"]["drives"]
    assert slewing["name"] == "slewing" and drive["name"] == "luffing"
    assert np.allclose(np.array(drive["angle"]), [[0, 40.0], [20, 60.0]], atol=1e-9)


def test_a_frame_stroke_table_takes_the_branch_of_the_legs():
    """An A-frame's cylinder from an inboard deck base lengthens as the legs tilt outboard
    (toward smaller plane angles): the stroke table gives the tilt on that branch, not the
    mirror image below the deck (which the column crane's branch rule gave: -200 deg)."""
    cyl = {"base": [-3.0, 0.0], "eye": 5.0}
    L = [cylinder_lever(CylinderSpec(**cyl), math.radians(90.0 - tilt))[0] for tilt in (-20.0, 20.0, 35.0)]
    assert L[0] < L[1] < L[2]
    a = expand(a_frame(tilt_deg=None, cylinder=dict(cyl, stroke=[[0, L[0]], [10, L[1]], [20, L[2]]])))
    (drive,) = a["lines"]["af_legs"]["end_a"]["drives"]
    assert np.allclose(np.array(drive["angle"]), [[0, -20.0], [10, 20.0], [20, 35.0]], atol=1e-9)
    # a stroke that would put the legs below the deck is refused, naming the row
    errors = errors_of(a_frame(tilt_deg=None, cylinder=dict(cyl, stroke=[[0, L[1]], [10, 2.05]])))
    assert "outside their range" in errors["cranes.af.cylinder.stroke.1.1"]


def test_a_frame_stroke_table_keeps_the_legs_branch_with_a_raised_base():
    """A cylinder base above the hinge line puts both triangle branches inside the legs'
    range: from the inboard base (-3, 3) the dead point (the legs pointing at the base) is
    45 deg inboard, and a stroke for a 15 deg inboard tilt also fits 75 deg inboard, past the
    base. The legs work through upright, so the table keeps the branch that holds it (it gave
    -60 and -75 deg for -30 and -15 deg, a jump of 60 deg to the next row); from the outboard
    base (3, 3) likewise."""
    tilts = (-30.0, -15.0, 0.0, 15.0, 35.0)
    for base in ([-3.0, 3.0], [3.0, 3.0]):
        cyl = {"base": base, "eye": 6.0}
        L = [cylinder_lever(CylinderSpec(**cyl), math.radians(90.0 - tilt))[0] for tilt in tilts]
        a = expand(a_frame(tilt_deg=None, cylinder=dict(cyl, stroke=[[10.0 * k, x] for k, x in enumerate(L)])))
        (drive,) = a["lines"]["af_legs"]["end_a"]["drives"]
        assert np.allclose(np.array(drive["angle"]), [[10.0 * k, t] for k, t in enumerate(tilts)], atol=1e-9), base


@pytest.mark.parametrize("tpl, over, field, words", [
    ("column", {"vessel": "tug"}, "cranes.c.vessel", "unknown vessel 'tug'"),
    ("column", {"luffing_deg": None}, "cranes.c.luffing_deg", "or cylinder.stroke"),
    ("column", {"luffing_deg": 95.0}, "cranes.c.luffing_deg", "outside"),
    ("column", {"slewing_deg": [[0, 10], [0, 20]]}, "cranes.c.slewing_deg.1.0", "times must increase"),
    ("column", {"cylinder": {"base": [1, -2], "eye": 5, "stroke": [[0, 6.0]]}}, "cranes.c.cylinder.stroke",
     "not both"),
    ("column", {"boom": {"length": 20.0, "outer_diameter": 1.0}}, "cranes.c.boom.wall_thickness", "tube"),
    ("column", {"boom": {"length": 20.0, "EA": 1e9}}, "cranes.c.boom.EI", "EA, EI and mass_per_length"),
    ("column", {"payload": "box"}, "cranes.c.payload", "unknown body 'box'"),
    ("column", {"winch": {"line": "x", "mode": {"kind": "speed", "rows": [[0, 0]]}}}, "cranes.c.winch.line",
     "leave out line"),
    ("column", {"type": "tower"}, "cranes.c.type", "column"),
    ("a-frame", {"tilt_deg": 85.0}, "cranes.af.tilt_deg", "outside"),
])
def test_errors_name_the_template_field(tpl, over, field, words):
    errors = errors_of(column(**over) if tpl == "column" else a_frame(**over))
    assert field in errors, errors
    assert words in errors[field]


def test_names_that_clash_are_refused():
    data = column()
    data["lines"] = {"c_boom": {"type": "x", "length": 1.0, "elements": 1}}
    assert "already used in lines" in errors_of(data)["cranes.c.boom"]


def test_template_scenarios_expand():
    for path, lines in (("scenarios/column_crane.json", {"crane_pedestal", "crane_boom", "crane_rope"}),
                        ("scenarios/a_frame.json", {"aframe_stub", "aframe_legs", "aframe_crossbeam",
                                                    "aframe_stub_2", "aframe_legs_2", "aframe_crossbeam_2",
                                                    "aframe_rope"}),
                        ("scenarios/a_frame_deck_winch.json", {"aframe_stub", "aframe_legs", "aframe_crossbeam",
                                                               "aframe_stub_2", "aframe_legs_2", "aframe_crossbeam_2",
                                                               "aframe_rope"})):
        data = json.load(open(path))
        out = expand(data)
        assert set(out["lines"]) == lines
        assert len(out["winches"]) == 1 and len(out["bodies"]) == 1


def test_slack_events_and_snap_loads():
    t = np.arange(0.0, 10.0, 0.5)
    T = np.full_like(t, 100.0)
    T[4:7] = 0.0           # slack 2.0 .. 3.0 s
    T[7] = 500.0           # snap at 3.5 s
    T[15:] = 0.0           # slack from 7.5 s to the end
    ev = slack_events(t, T, 1.0)
    assert len(ev) == 2
    assert ev[0] == {"start": 2.0, "end": 3.5, "snap_load": 500.0, "snap_time": 3.5, "blips": 0}
    assert ev[1]["start"] == 7.5 and math.isnan(ev[1]["end"]) and math.isnan(ev[1]["snap_load"])
    assert slack_events(t, np.full_like(t, 100.0), 1.0) == []


def test_slack_event_merges_taut_blips_and_its_snap_window_stops_at_the_next_event():
    """Audit: a chattering slack rope (one-sample taut blips of a few kN) counted 37 events in
    6 s, and each event's snap load was the largest tension of a 2 s window running over the
    next events. Now a short, low taut interval (one sample, or under min_taut; below
    blip_level) does not end an event, a high one (a snap) does, and the snap window stops
    at the next event's start."""
    t = np.round(np.arange(0.0, 3.0, 0.01), 10)
    T = np.full_like(t, 1000.0)
    T[100:150] = 0.0                 # slack 1.00 .. 1.50 s
    T[120] = 80.0                    # a one-sample blip in it, below blip_level 500 N
    T[135:137] = 90.0                # a two-sample one (0.02 s < min_taut)
    T[150:160] = 2000.0              # taut again at 1.50 s: snap 2000 N
    T[160:170] = 0.0                 # slack 1.60 .. 1.70 s
    T[170] = 600.0                   # a one-sample blip above blip_level: a snap, it ends the event
    T[171:180] = 0.0                 # slack 1.71 .. 1.80 s
    T[180:] = 3000.0                 # taut from 1.80 s on: its snap 3000 N
    ev = slack_events(t, T, 10.0, blip_level=500.0)
    assert [(e["start"], e["end"], e["snap_load"], e["snap_time"], e["blips"]) for e in ev] == [
        (1.0, 1.5, 2000.0, 1.5, 2), (1.6, 1.7, 600.0, 1.7, 0), (1.71, 1.8, 3000.0, 1.8, 0)]
    # the first event's window (2 s) covers the later 3000 N; it stops at the next event's start
    assert ev[0]["snap_time"] < ev[1]["start"]
    # without the height limit the short snap merges too; the 0.1 s taut interval does not
    assert [(e["start"], e["end"], e["blips"]) for e in slack_events(t, T, 10.0, blip_level=1e9)] == [
        (1.0, 1.5, 2), (1.6, 1.8, 1)]
