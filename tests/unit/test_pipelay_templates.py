"""Pipelay templates (rfesim.scenario.pipelay): expansion into ordinary scenario sections,
its determinism and geometry (the natural catenary from the lift-off point), errors that
name the template field, name clashes, and `rfesim check --expand`."""
from __future__ import annotations

import copy
import json
import math
import subprocess
import sys

import numpy as np
import pytest

import rfesim
from rfesim.catenary import natural_catenary
from rfesim.scenario import expand
from rfesim.scenario.pipelay import GRADE_YIELD

G, RHO_W = 9.81, 1025.0
D, T_WALL, E, RHO = 0.3239, 0.0159, 2.07e11, 7850.0
AREA = math.pi / 4 * (D ** 2 - (D - 2 * T_WALL) ** 2)
W_SUB = (RHO * AREA - RHO_W * math.pi / 4 * D ** 2) * G          # 356.2532 N/m (VALIDATION.md P2)
PIPE = {"outer_diameter": D, "wall_thickness": T_WALL}


def s_lay(**over):
    tpl = {"method": "s-lay", "vessel": "barge", "tension": 150e3, "pipe": dict(PIPE)}
    tpl.update(over)
    return {"environment": {"water": {"depth": 130.0}},
            "vessels": {"barge": {"position": [10.0, -5.0, 0.0], "heading_deg": 30.0}},
            "pipelay": {"lay1": tpl}, "analysis": {"dynamics": {"enabled": False}}}


def j_lay(**over):
    tpl = {"method": "j-lay", "tower_angle_deg": 85.0, "pipe": dict(PIPE),
           "vessel": {"motion": {"kind": "harmonic", "heave": {"amplitude": 1.0, "period": 9.0}}}}
    tpl.update(over)
    return {"environment": {"water": {"depth": 1200.0}}, "pipelay": {"jl": tpl}}


def errors_of(data):
    with pytest.raises(rfesim.ScenarioError) as info:
        rfesim.Scenario.model_validate(data)
    return dict(info.value.errors)


def test_expansion_is_deterministic_and_validates():
    data = s_lay()
    before = copy.deepcopy(data)
    a, b = expand(data), expand(copy.deepcopy(data))
    assert data == before                                   # the input is not modified
    assert json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)
    assert "pipelay" not in a
    assert set(a["supports"]) == {"lay1_tensioner", "lay1_stinger"}
    assert a["lines"]["lay1"]["type"] == "lay1_pipe"
    assert a["environment"]["seabed"]["normal_stiffness"] == 1e6     # added: the scene had none
    sc = rfesim.Scenario.model_validate(data)
    assert list(sc.lines) == ["lay1"] and sc.pipelay == {}
    # the expanded dict is an ordinary scenario: it validates to the same model
    assert rfesim.Scenario.model_validate(a).model_dump() == sc.model_dump()


def test_s_lay_geometry_follows_the_natural_catenary_from_the_stinger_tip():
    """The stinger's tip angle equals the catenary's departure angle from the tip, and end B
    lies the catenary's span plus the laid length beyond the tip, along the vessel's x axis."""
    data = expand(s_lay())
    st = data["supports"]["lay1_stinger"]
    lift = (D / 2 + st["roller_radius"]) / math.cos(math.radians(st["v_angle_deg"]))
    Rp, theta = st["radius"] + lift, st["length"] / st["radius"]
    # a station exactly at the tip
    assert st["length"] / st["spacing"] == pytest.approx(round(st["length"] / st["spacing"]), abs=1e-9)
    tip_local = np.array([st["start"][0] + Rp * math.sin(theta), 0.0, st["start"][2] + lift - Rp * (1 - math.cos(theta))])
    h30 = math.radians(30.0)
    rot = np.array([[math.cos(h30), -math.sin(h30), 0], [math.sin(h30), math.cos(h30), 0], [0, 0, 1]])
    tip = np.array([10.0, -5.0, 0.0]) + rot @ tip_local
    z_bed = -130.0 + D / 2 - W_SUB / 1e6
    nat = natural_catenary(W_SUB, tip[2] - z_bed, 150e3)
    assert math.degrees(theta) == pytest.approx(nat["top_angle_deg"], abs=1e-6)
    end_b = np.asarray(data["lines"]["lay1"]["end_b"]["position"])
    along = nat["horizontal_span"] + 50.0
    np.testing.assert_allclose(end_b, tip + along * rot @ [1.0, 0, 0] + [0, 0, z_bed - tip[2]], atol=1e-6)
    line = data["lines"]["lay1"]
    tens = data["supports"]["lay1_tensioner"]
    # the pipe: 10 m in the tensioner, 2 m free to station 0, the arc, the catenary, the laid
    # length; the support's track reaches half an element past the tensioner's exit (its pads
    # let go over the last element: tests/validation/test_slay_first_station.py)
    track = tens["length"] - 0.5 * line["length"] / line["elements"]
    assert track == pytest.approx(10.0, rel=1e-12)
    expected = track + 2.0 + Rp * theta + nat["suspended_length"] + 50.0
    assert line["length"] == pytest.approx(expected, rel=1e-12)
    # elements of a third of the station spacing (at most 4 m): the roller reactions converge
    assert line["elements"] == math.ceil(line["length"] / min(4.0, st["spacing"] / 3.0))
    np.testing.assert_allclose(line["end_a"]["position"], np.array([10.0, -5.0, 0.0]) + rot @ tens["entry"],
                               atol=1e-12)
    assert line["end_a"]["attach"] == "free" and tens["attach"] == "barge"


def test_j_lay_tension_follows_from_the_tower_angle():
    """H = w h cos(a) / (1 - cos(a)): the catenary leaves the exit at the tower angle."""
    data = expand(j_lay())
    collar = data["supports"]["jl_collar"]
    axis = np.asarray(collar["axis"])
    assert math.degrees(math.atan2(-axis[2], axis[0])) == pytest.approx(85.0, abs=1e-12)
    h = 0.0 - (-1200.0 + D / 2 - W_SUB / 1e6)
    c = math.cos(math.radians(85.0))
    H = W_SUB * h * c / (1 - c)
    nat = natural_catenary(W_SUB, h, H)
    assert nat["top_angle_deg"] == pytest.approx(85.0, abs=1e-9)
    end_b = data["lines"]["jl"]["end_b"]["position"]
    assert end_b[0] == pytest.approx(nat["horizontal_span"] + 50.0, rel=1e-12)
    assert data["lines"]["jl"]["length"] == pytest.approx(collar["length"] + nat["suspended_length"] + 50.0)
    assert "jl_vessel" in data["vessels"] and collar["attach"] == "jl_vessel"
    # the same lay given by its tension leaves at 85 deg too
    by_tension = expand(j_lay(tower_angle_deg=None, tension=H))
    assert by_tension["supports"]["jl_collar"]["axis"] == pytest.approx(collar["axis"], abs=1e-9)


def test_pipe_grade_coating_and_contents():
    lt = expand(s_lay(pipe=dict(PIPE, grade="X70", material="elastoplastic")))["line_types"]["lay1_pipe"]
    assert lt["material"]["yield_stress"] == GRADE_YIELD["X70"] == 483e6
    coated = dict(PIPE, coating_thickness=0.05, coating_density=2400.0, contents_density=1025.0)
    lt = expand(s_lay(pipe=coated))["line_types"]["lay1_pipe"]
    Dc, d = D + 0.1, D - 2 * T_WALL
    assert lt["outer_diameter"] == pytest.approx(Dc)
    assert lt["mass_per_length"] == pytest.approx(RHO * AREA + 2400 * math.pi / 4 * (Dc ** 2 - D ** 2)
                                                  + 1025 * math.pi / 4 * d ** 2, rel=1e-12)
    assert lt["EIy"] == pytest.approx(E * math.pi / 64 * (D ** 4 - d ** 4), rel=1e-12)


@pytest.mark.parametrize("over, field, words", [
    ({"tension": 0.0}, "pipelay.lay1.tension", "must be > 0"),
    ({"tension": -5.0}, "pipelay.lay1.tension", "must be > 0"),
    ({"tension": None}, "pipelay.lay1.tension", "required for s-lay"),
    ({"pipe": {"outer_diameter": 0.3, "wall_thickness": 0.2}}, "pipelay.lay1.pipe.wall_thickness", "outer radius"),
    ({"pipe": {"wall_thickness": 0.02}}, "pipelay.lay1.pipe.outer_diameter", "missing"),
    ({"pipe": dict(PIPE, coating_thickness=0.05)}, "pipelay.lay1.pipe.coating_density", "needs its density"),
    ({"pipe": dict(PIPE, grade="X99")}, "pipelay.lay1.pipe.grade", "X65"),
    ({"stinger": {"radius": -1.0}}, "pipelay.lay1.stinger.radius", "greater than 0"),
    ({"stinger": {"spacing": 500.0}}, "pipelay.lay1.stinger.spacing", "longer than the stinger"),
    ({"vessel": "tug"}, "pipelay.lay1.vessel", "unknown vessel 'tug'"),
    ({"method": "x-lay"}, "pipelay.lay1.method", "s-lay"),
    ({"elements": 10, "element_length": 3.0}, "pipelay.lay1.elements", "not both"),
    ({"element_length": 40.0}, "pipelay.lay1.element_length", "boundary layer"),
    ({"pipe": dict(PIPE, wall_thickness=0.001)}, "pipelay.lay1.pipe", "floats"),
    ({"stiner": {}}, "pipelay.lay1.stiner", "did you mean 'stinger'"),
])
def test_errors_name_the_template_field(over, field, words):
    errors = errors_of(s_lay(**over))
    assert field in errors, errors
    assert words in errors[field]


@pytest.mark.parametrize("over, field, words", [
    ({"tower_angle_deg": 60.0}, "pipelay.jl.tower_angle_deg", "[70, 90)"),
    ({"tower_angle_deg": 90.0}, "pipelay.jl.tower_angle_deg", "zero horizontal tension"),
    ({"tension": 1e5}, "pipelay.jl.tension", "not both"),
    ({"tower_angle_deg": None}, "pipelay.jl.tower_angle_deg", "or the lay tension"),
    ({"tower_angle_deg": None, "tension": 2e6}, "pipelay.jl.tension", "70 to 90 deg"),
    ({"exit": [0.0, 0.0, -1300.0]}, "pipelay.jl.exit", "below the seabed"),
])
def test_j_lay_errors(over, field, words):
    errors = errors_of(j_lay(**over))
    assert field in errors, errors
    assert words in errors[field]


def test_names_that_clash_are_refused():
    data = s_lay()
    data["line_types"] = {"p": {"EA": 1e9, "EIy": 1e6, "mass_per_length": 100.0}}
    data["lines"] = {"lay1": {"type": "p", "length": 10.0, "elements": 5,
                              "end_a": {"attach": "fixed", "position": [0, 0, 0]}}}
    assert "already defined in lines" in errors_of(data)["pipelay.lay1.line"]
    data["pipelay"]["lay1"]["line"] = "pipe2"
    sc = rfesim.Scenario.model_validate(data)                 # another name: both lines exist
    assert set(sc.lines) == {"lay1", "pipe2"}
    data["supports"] = {"pipe2_stinger": {"kind": "rollers", "line": "lay1", "stiffness": 1e6,
                                          "rollers": [{"position": [0, 0, 0], "axis": [0, 1, 0], "width": 1.0}]}}
    assert "already used in supports" in errors_of(data)["pipelay.lay1.line"]
    two = s_lay()
    two["pipelay"]["lay2"] = dict(two["pipelay"]["lay1"], line="lay1")
    assert "already defined" in errors_of(two)["pipelay.lay2.line"]


def test_needs_water_and_a_flat_seabed():
    dry = s_lay()
    dry["environment"] = {}
    assert "sea water" in errors_of(dry)["pipelay.lay1"]
    sloped = s_lay()
    sloped["environment"]["seabed"] = {"normal_stiffness": 1e6, "slope_deg": 2.0}
    assert "flat seabed" in errors_of(sloped)["pipelay.lay1"]


def test_template_scenarios_expand_and_validate():
    for path, line, supports in (("scenarios/s_lay_template.json", "lay", {"lay_tensioner", "lay_stinger"}),
                                 ("scenarios/j_lay.json", "lay", {"lay_collar"}),
                                 ("scenarios/reel_lay.json", "lay", {"lay_reel", "lay_aligner", "lay_straightener",
                                                                     "lay_tensioner"})):
        sc = rfesim.load_scenario(path)
        assert set(sc.supports) == supports and line in sc.lines
        assert sc.analysis.dynamics.duration > 0


def test_cli_check_expand_prints_the_expanded_scenario():
    run = subprocess.run([sys.executable, "-m", "rfesim.cli", "check", "--expand", "scenarios/j_lay.json"],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    data = json.loads(run.stdout)
    assert "pipelay" not in data and data["supports"]["lay_collar"]["kind"] == "tensioner"
    assert data == expand(json.load(open("scenarios/j_lay.json")))


def test_reel_lay_chain_of_supports_meets_the_ramp_exit():
    """Reel top -> 2 m -> aligner arc to the ramp angle -> 2 m -> straightener -> 2 m ->
    tensioner -> exit: consecutive pieces join on the pipe axis; the line's length adds up."""
    data = expand(json.load(open("scenarios/reel_lay.json")))
    sup = data["supports"]
    e = np.asarray(sup["lay_tensioner"]["axis"])
    assert math.degrees(math.atan2(-e[2], e[0])) == pytest.approx(70.0, abs=1e-12)
    exit_ = np.asarray(sup["lay_tensioner"]["entry"]) + sup["lay_tensioner"]["length"] * e
    np.testing.assert_allclose(exit_, [0.0, 0.0, 2.0], atol=1e-12)
    np.testing.assert_allclose(np.asarray(sup["lay_straightener"]["entry"]) + (6.0 + 2.0) * e,
                               sup["lay_tensioner"]["entry"], atol=1e-12)
    al = sup["lay_aligner"]
    lift = D / 2 + al["roller_radius"]
    Rp, theta = al["radius"] + lift, al["length"] / al["radius"]
    arc_end = np.asarray(al["start"]) + [Rp * math.sin(theta), 0.0, lift - Rp * (1 - math.cos(theta))]
    np.testing.assert_allclose(arc_end + 2.0 * e, sup["lay_straightener"]["entry"], atol=1e-9)
    reel = sup["lay_reel"]
    take_off = np.asarray(reel["centre"]) + [0.0, 0.0, reel["radius"]]
    np.testing.assert_allclose(take_off + [2.0, 0.0, 0.0], np.asarray(al["start"]) + [0, 0, lift], atol=1e-12)
    assert data["line_types"]["lay_pipe"]["material"]["kind"] == "elastoplastic"
    assert data["lines"]["lay"]["end_a"] == {"attach": "free"}
