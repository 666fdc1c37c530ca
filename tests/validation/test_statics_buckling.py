"""Statics says when its equilibrium buckles, and a straight start with slack goes on from the
catenary (rfesim.solvers.buckling, rfesim.api._static_state; docs/theory.md, section 6).

Without gravity the catenary riser starts straight, every element shortened to span the
chord, and that straight column is in equilibrium at once (0 Newton iterations) at a
compression EA (1 - d / L) far beyond its Euler load pi^2 EI / L^2: true, and unstable. A
straight start (analysis.statics.start) of a line longer than the distance between its ends
is the same column with gravity on, and Newton fails there.
"""
from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim import api
from rfesim.errors import SolverError
from rfesim.model.compile import compile_scenario
from rfesim.model.joins import JOINT_STIFFNESS
from rfesim.solvers.buckling import GREENHILL, cantilever_load, compressed_stretches
from rfesim.solvers.system import System

from test_tension_only_statics import EA, LENGTH, rope

RISER = Path(__file__).resolve().parents[2] / "scenarios" / "catenary_riser.json"


def statics_with_stretches(sc):
    """(state, info, compressed stretches) of a scenario's statics, as rfesim.statics runs it."""
    system = System(compile_scenario(sc))
    state, info = api._static_state(system, sc)
    return state, info, compressed_stretches(system, state)


def pipe_section(sc, name: str) -> tuple[float, float]:
    """(EA, EI) of a pipe line type from its diameter, wall and Young's modulus."""
    lt = sc.line_types[name]
    d_out, d_in = lt.outer_diameter, lt.outer_diameter - 2.0 * lt.wall_thickness
    E = lt.youngs_modulus
    return E * math.pi / 4.0 * (d_out ** 2 - d_in ** 2), E * math.pi / 64.0 * (d_out ** 4 - d_in ** 4)


def test_weightless_riser_is_a_buckled_column_and_says_so(caplog):
    sc = rfesim.load_scenario(RISER, overrides={"environment.gravity": 0.0})
    line = sc.lines["riser"]
    EA_pipe, EI = pipe_section(sc, line.type)
    # end B on the vessel at the origin, heading 180 deg: the point (0, 0, -15) stays where it is
    span = math.dist(line.end_a.position, line.end_b.position)
    compression = EA_pipe * (1.0 - span / line.length)          # every element shortened to span the chord
    euler = math.pi ** 2 * EI / line.length ** 2
    with caplog.at_level(logging.WARNING, logger="rfesim"):
        res = rfesim.statics(sc)
    assert res.counters["newton_iterations"] == 0
    assert np.asarray(res.line("riser").tension[0]) == pytest.approx(-compression, rel=1e-9)
    _, info, stretches = statics_with_stretches(sc)
    assert len(stretches) == 1
    c = stretches[0]
    assert (c.line, c.start, c.length) == ("riser", 0.0, pytest.approx(line.length, rel=1e-12))
    assert c.compression == pytest.approx(compression, rel=1e-9)
    assert c.euler_load == pytest.approx(euler, rel=1e-12)
    assert compression > 1e5 * euler                            # 180 MN against 1.04 kN
    for text in (res.message, caplog.text):
        assert "line 'riser'" in text and "free stretch of 600 m" in text
        assert f"{compression / 1e3:.4g} kN of compression" in text
        assert f"Euler load pi^2 EI / L^2 = {euler / 1e3:.4g} kN" in text
        assert "unstable (buckling)" in text and "give the line tension" in text
    assert info.warnings and info.warnings[0] in res.message


def test_riser_with_gravity_does_not_warn(caplog):
    sc = rfesim.load_scenario(RISER)
    with caplog.at_level(logging.WARNING, logger="rfesim"):
        res = rfesim.statics(sc)
    assert "warning" not in res.message
    assert not [r for r in caplog.records if r.levelno >= logging.WARNING]
    _, info, stretches = statics_with_stretches(sc)
    assert info.warnings == [] and not any(c.buckles for c in stretches)


def test_ropes_carry_no_compression():
    """Without gravity, the rope of 20 m between points 5 m apart is no column for the buckling
    check: its only warning is the one for a rope crammed into its elements' axial contact
    (rfesim.solvers.buckling.crammed_rope_warnings; before the contact it lay slack, its
    elements passed through one another, with no warning); the same line elastic in
    compression is a column at EA (1 - 5/20) and warns."""
    res = rfesim.statics(rope(5.0, gravity=0.0, EI=10.0))
    assert res.message.count("warning") == 1 and "statics warning: rope 'r' is crammed into itself" in res.message
    sc = rfesim.load_scenario(rope(5.0, gravity=0.0, EI=10.0, tension_only=False))
    _, info, stretches = statics_with_stretches(sc)
    assert len(info.warnings) == 1 and "line 'r'" in info.warnings[0]
    assert stretches[0].compression == pytest.approx(EA * (1.0 - 5.0 / LENGTH), rel=1e-9)
    assert stretches[0].euler_load == pytest.approx(math.pi ** 2 * 10.0 / LENGTH ** 2, rel=1e-12)


PUSHED_EULER = math.pi ** 2 * 1e4 / 20.0 ** 2      # N, pinned Euler load of the pushed beam


def pushed_beam(gravity: float, seabed: bool) -> dict:
    """A beam of 20 m clamped at end A, horizontal, pushed at its free end B by ten times its
    (pinned) Euler load; with gravity it lies on a seabed 0.1 m below its axis."""
    env = {"gravity": gravity}
    if seabed:
        env["seabed"] = {"z": -10.0, "normal_stiffness": 1e6}
    return {"name": "pushed beam", "environment": env,
            "line_types": {"beam": {"EA": 1e8, "EIy": 1e4, "mass_per_length": 50.0, "outer_diameter": 0.2}},
            "lines": {"b": {"type": "beam", "length": 20.0, "elements": 20,
                            "end_a": {"attach": "fixed", "position": [0.0, 0.0, -9.9], "connection": "clamped",
                                      "direction": [1.0, 0.0, 0.0]},
                            "end_b": {"attach": "free"},
                            "loads": [{"at": "end_b", "force": [-10.0 * PUSHED_EULER, 0.0, 0.0]}]}},
            "analysis": {"statics": {"enabled": True}}}


def test_compressed_line_on_the_seabed_is_supported():
    """Lying on the seabed the pushed beam is held along its length: no free stretch, no
    warning. Weightless and off the seabed it is a free column of 20 m and warns."""
    _, info, stretches = statics_with_stretches(rfesim.load_scenario(pushed_beam(9.81, seabed=True)))
    assert info.warnings == [] and stretches == []
    _, info, stretches = statics_with_stretches(rfesim.load_scenario(pushed_beam(0.0, seabed=False)))
    assert len(info.warnings) == 1 and len(stretches) == 1
    assert stretches[0].length == pytest.approx(20.0, rel=1e-12)
    assert stretches[0].compression == pytest.approx(10.0 * PUSHED_EULER, rel=1e-6)
    assert stretches[0].euler_load == pytest.approx(PUSHED_EULER / 4.0, rel=1e-9)      # end B free: a cantilever (to round-off)


@pytest.mark.parametrize("factor", [0.5, 0.2])
def test_a_cantilever_with_a_free_end_is_judged_on_twice_its_length(factor, caplog):
    """The pushed beam (end A clamped, end B free) at half its pinned Euler load is past its
    cantilever load pi^2 EI / (2 L)^2 = N_E / 4 and warns, saying so; at a fifth of it, below
    N_E / 4, it does not. Judged pinned (as before), neither warned."""
    data = pushed_beam(0.0, seabed=False)
    data["lines"]["b"]["loads"][0]["force"] = [-factor * PUSHED_EULER, 0.0, 0.0]
    sc = rfesim.load_scenario(data)
    with caplog.at_level(logging.WARNING, logger="rfesim"):
        res = rfesim.statics(sc)
    _, info, stretches = statics_with_stretches(sc)
    c, = stretches
    assert (c.line, c.lines, c.start, c.stop) == ("b", ("b",), 0.0, pytest.approx(20.0, rel=1e-12))
    assert c.compression == pytest.approx(factor * PUSHED_EULER, rel=1e-6)
    assert c.free_ends == 1 and c.effective_length == pytest.approx(40.0, rel=1e-8)
    assert c.euler_load == pytest.approx(PUSHED_EULER / 4.0, rel=1e-8)      # its compression even to round-off
    assert c.deviation <= 1e-9 * c.length
    if factor * 4.0 > 1.0:
        assert c.buckles and len(info.warnings) == 1
        for text in (res.message, caplog.text):
            assert "line 'b' carries" in text and "free stretch of 20 m" in text
            assert f"above its Euler load {PUSHED_EULER / 4e3:.4g} kN (one end free, a cantilever of 20 m" in text
            assert f"whose load alone buckles it at pi^2 EI / (2 L)^2 = {PUSHED_EULER / 4e3:.4g} kN" in text
    else:
        assert not c.buckles and info.warnings == [] and "warning" not in res.message


def standing_pipe(length: float) -> dict:
    """A 12-inch X65 pipe standing clamped upright in air, its top free: a column under its
    own weight (Greenhill)."""
    return {"name": "standing pipe", "environment": {"gravity": 9.81},
            "line_types": {"pipe": {"outer_diameter": 0.3239, "wall_thickness": 0.0159, "youngs_modulus": 2.07e11,
                                    "density": 7850.0}},
            "lines": {"p": {"type": "pipe", "length": length, "elements": 20,
                            "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0], "connection": "clamped",
                                      "direction": [0.0, 0.0, 1.0]},
                            "end_b": {"attach": "free"}}},
            "analysis": {"statics": {"enabled": True}}}


@pytest.mark.parametrize("share", [0.9, 1.1])
def test_a_column_under_its_own_weight_buckles_at_greenhills_length(share):
    """A cantilever standing under its own weight q buckles when q L^3 = 7.837 EI (Greenhill),
    at 63 m for this pipe: at 0.9 of that length it does not warn, at 1.1 it does. The
    tip-load rule pi^2 EI / (2 L)^2 alone warned from 43 m."""
    sc = rfesim.load_scenario(standing_pipe(60.0))
    _, EI = pipe_section(sc, "pipe")
    q = 7850.0 * math.pi / 4.0 * (0.3239 ** 2 - (0.3239 - 2 * 0.0159) ** 2) * 9.81
    critical = (GREENHILL * EI / q) ** (1.0 / 3.0)
    assert critical == pytest.approx(63.1, abs=0.1)
    length = share * critical
    _, info, stretches = statics_with_stretches(rfesim.load_scenario(standing_pipe(length)))
    c, = stretches
    assert c.free_ends == 1 and c.length == pytest.approx(length, rel=1e-9)
    assert c.compression == pytest.approx(q * length * (1 - 0.5 / 20), rel=1e-6)   # at the first SDE, dx/2 up
    assert c.free_end_compression == pytest.approx(q * length / 40, rel=1e-6)    # the top RFE: dx / 2 of pipe
    # Dunkerley's sum is 5.6 % low for a uniform weight, 8 % on these 20 elements
    assert 0.9 * GREENHILL * EI / length ** 2 < c.euler_load < GREENHILL * EI / length ** 2
    assert c.buckles is (share > 1.0)
    assert len(info.warnings) == int(share > 1.0)
    if share > 1.0:
        assert "combined by Dunkerley's sum" in info.warnings[0]


def test_cantilever_load_is_exact_for_one_load_and_safe_for_a_weight():
    EI = 1.0e4
    # one load at 9 m of a 10 m cantilever (the SDEs above it unloaded): pi^2 EI / (2 * 9)^2
    assert cantilever_load(EI, [0.5] * 20, [0.0] * 2 + [300.0] * 18) == pytest.approx(
        math.pi ** 2 * EI / 18.0 ** 2, rel=1e-12)
    # a uniform weight on 2000 SDEs: 5.6 % below Greenhill's q L^3 = 7.837 EI, never above
    n, L = 2000, 10.0
    q = 1.0
    load = cantilever_load(EI, [L / n] * n, [q * L * (k + 1) / n for k in range(n)])
    assert load == pytest.approx(0.75 * math.pi ** 2 * EI / L ** 2, rel=2e-3)
    assert load < GREENHILL * EI / L ** 2


@pytest.mark.parametrize("force, warns", [(600.0, True), (250.0, False)])
def test_a_load_near_the_free_end_is_judged_where_it_acts(force, warns):
    """A weightless 10 m cantilever standing clamped, pushed down at 9 m: it buckles at
    pi^2 EI / (2 * 9 m)^2 = 305 N (the metre above the load stays straight). Before, the load
    was taken for a weight along it (7.837 EI / L^2 = 784 N) and 600 N passed."""
    data = standing_pipe(10.0)
    data["environment"]["gravity"] = 0.0
    data["line_types"] = {"pipe": {"EA": 1e8, "EIy": 1e4, "mass_per_length": 1.0}}
    data["lines"]["p"]["loads"] = [{"at": 9.0, "force": [0.0, 0.0, -force]}]
    _, info, stretches = statics_with_stretches(rfesim.load_scenario(data))
    c, = stretches
    assert c.free_ends == 1 and c.compression == pytest.approx(force, rel=1e-6)
    assert c.euler_load == pytest.approx(math.pi ** 2 * 1e4 / 18.0 ** 2, rel=0.06)
    assert c.buckles is warns and len(info.warnings) == int(warns)


def test_a_follower_load_at_the_free_end_keeps_the_pinned_check():
    """A load given in the end's own frame follows it (Beck's column, not Euler's): the end
    is not taken as free, and the pushed beam at half its pinned Euler load does not warn."""
    data = pushed_beam(0.0, seabed=False)
    data["lines"]["b"]["loads"][0].update(force=[-0.5 * PUSHED_EULER, 0.0, 0.0], frame="local")
    _, info, stretches = statics_with_stretches(rfesim.load_scenario(data))
    c, = stretches
    assert c.compression == pytest.approx(0.5 * PUSHED_EULER, rel=1e-6)
    assert c.free_ends == 0 and c.euler_load == pytest.approx(PUSHED_EULER, rel=1e-12)
    assert info.warnings == []


COLUMN_EI = 1e4                                  # N m^2, the softest of the column's sections
COLUMN_EULER = math.pi ** 2 * COLUMN_EI / 20.0 ** 2   # N, pinned Euler load of the four lines together


def joined_column(compression: float, corner: bool = False) -> dict:
    """Four lines of 5 m joined end to end (clamped joins) into a weightless column of 20 m,
    pinned at both ends to fixed points a little closer than 20 m so that it carries
    ``compression``; line 'c' twice as stiff in bending as the others. ``corner``: line 'c'
    starts at 30 deg to 'b' (the column turns at that join) and end B of 'd' is free."""
    EA = 1e6
    span = 20.0 * (1.0 - compression / EA)
    types = {"soft": {"EA": EA, "EIy": COLUMN_EI, "mass_per_length": 10.0},
             "stiff": {"EA": EA, "EIy": 2.0 * COLUMN_EI, "mass_per_length": 10.0}}
    lines = {"a": {"type": "soft", "length": 5.0, "elements": 5,
                   "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0]},
                   "end_b": {"attach": "free"}}}
    for name, parent, kind in (("b", "a", "soft"), ("c", "b", "stiff"), ("d", "c", "soft")):
        lines[name] = {"type": kind, "length": 5.0, "elements": 5,
                       "end_a": {"attach": f"{parent}:end_b", "connection": "clamped"}, "end_b": {"attach": "free"}}
    lines["d"]["end_b"] = {"attach": "fixed", "position": [span, 0.0, 0.0]}
    for name in "bc":
        lines[name]["end_a"]["direction"] = [1.0, 0.0, 0.0]
    if corner:
        lines["c"]["end_a"]["direction"] = [math.cos(math.radians(30.0)), math.sin(math.radians(30.0)), 0.0]
        lines["d"]["end_b"] = {"attach": "free"}
    return {"name": "joined column", "environment": {"gravity": 0.0}, "line_types": types, "lines": lines,
            "analysis": {"statics": {"enabled": True}}}


@pytest.mark.parametrize("factor", [4.0, 0.5])
def test_a_column_of_joined_lines_is_checked_as_one(factor, caplog):
    """Four 5 m lines joined end to end into a 20 m column: at four times the column's Euler
    load each line alone is at a quarter of its own (pi^2 EI / (5 m)^2) and passed; the
    stretch now runs across the joins over all four lines, with the smallest EI of them,
    and warns naming them. At half the column's load it does not warn."""
    sc = rfesim.load_scenario(joined_column(factor * COLUMN_EULER))
    with caplog.at_level(logging.WARNING, logger="rfesim"):
        res = rfesim.statics(sc)
    _, info, stretches = statics_with_stretches(sc)
    c, = stretches
    assert (c.line, c.lines, c.start, c.stop) == ("a", ("a", "b", "c", "d"), 0.0, pytest.approx(5.0, rel=1e-12))
    assert c.length == pytest.approx(20.0, rel=1e-12) and c.free_ends == 0
    # the three joints add the axial compliance of 1 / JOINT_STIFFNESS element (1 m) each
    assert c.compression == pytest.approx(factor * COLUMN_EULER * 20.0 / (20.0 + 3.0 / JOINT_STIFFNESS), rel=1e-6)
    assert c.bending_stiffness == COLUMN_EI
    assert c.euler_load == pytest.approx(COLUMN_EULER, rel=1e-12)
    assert c.compression < math.pi ** 2 * COLUMN_EI / 5.0 ** 2          # each line alone passes
    if factor > 1.0:
        assert c.buckles and len(info.warnings) == 1
        for text in (res.message, caplog.text):
            assert "lines 'a', 'b', 'c', 'd', joined end to end, carry" in text
            assert "free stretch of 20 m (from arc length 0 m of 'a' to arc length 5 m of 'd')" in text
            assert f"pi^2 EI / L^2 = {COLUMN_EULER / 1e3:.4g} kN (pinned ends" in text
            assert "the smallest along the stretch" in text
    else:
        assert not c.buckles and info.warnings == [] and "warning" not in res.message


def test_a_corner_join_ends_the_stretch():
    """Where line 'c' turns 30 deg from 'b' the lines do not continue each other: the joined
    frame is checked as two stretches, 'a'-'b' and 'c'-'d', not as one bent column."""
    sc = rfesim.load_scenario(joined_column(0.0, corner=True))
    system = System(compile_scenario(sc))
    state = system.model.initial
    system.evaluate(state)
    from rfesim.solvers.buckling import _walks
    walks = _walks(system, [0.0] * 4)
    assert [[system.model.lines[k].name for k in dict.fromkeys(st.line for st in steps if not st.joint)]
            for steps, _, _ in walks] == [["a", "b"], ["c", "d"]]
    sc = rfesim.load_scenario(joined_column(1.0))
    system = System(compile_scenario(sc))
    system.evaluate(system.model.initial)
    walks = _walks(system, [0.0] * 4)
    assert len(walks) == 1 and sum(st.joint for st in walks[0][0]) == 3


def with_start(data, start: str):
    return rfesim.load_scenario(data, overrides={"analysis.statics.start": start})


STRAIGHT_CASES = {
    "rope": lambda: rope(5.0),
    "line elastic in compression": lambda: rope(5.0, tension_only=False),
    "catenary riser": lambda: RISER,
}


@pytest.mark.parametrize("case", list(STRAIGHT_CASES))
def test_straight_start_with_slack_goes_on_from_the_catenary(case, caplog):
    """The straight start of a line much longer than the distance between its ends is a
    column that buckles, and Newton failed from it; statics now goes on from the catenary
    start, says so, and finds the equilibrium of the default (catenary) start."""
    data = STRAIGHT_CASES[case]()
    name = "riser" if case == "catenary riser" else "r"
    with caplog.at_level(logging.WARNING, logger="rfesim"):
        res = rfesim.statics(with_start(data, "straight"))
    assert "so statics started from the catenary" in res.message and f"line '{name}'" in res.message
    assert "straight start failed" in caplog.text
    ref = rfesim.statics(with_start(data, "auto"))
    for attr in ("end_a_force", "end_b_force"):
        got, want = np.asarray(getattr(res.line(name), attr)[0]), np.asarray(getattr(ref.line(name), attr)[0])
        assert np.abs(got - want).max() <= 1e-6 * np.abs(want).max()


def test_straight_start_that_cannot_be_rescued_says_why(monkeypatch):
    """When the catenary start fails too, the error says why the straight start could not
    work and what to do; a start other than straight is not retried."""
    calls = []

    def failing(system, state=None, **kw):
        calls.append(state)
        raise SolverError("static equilibrium not found: Newton did not converge")

    monkeypatch.setattr(api, "solve_statics", failing)
    with pytest.raises(SolverError) as err:
        rfesim.statics(with_start(rope(5.0), "straight"))
    assert len(calls) == 2 and calls[0] is None and calls[1] is not None
    assert err.value.message.startswith("static equilibrium not found")
    assert "line 'r' is 20 m long between ends 5 m apart" in err.value.hint
    assert "statics from the catenary start failed too" in err.value.hint
    calls.clear()
    with pytest.raises(SolverError) as err:
        rfesim.statics(with_start(rope(5.0), "catenary"))
    assert len(calls) == 1 and not err.value.hint


def test_straight_start_is_not_replaced_where_the_start_shape_sets_the_model():
    """A clamped end given without a direction takes its orientation from the start shape:
    a catenary start would be another model (another clamp), so the failed straight start
    is not silently replaced; the hint says what differs and what to do."""
    data = rope(5.0, tension_only=False, EI=1e3)
    data["lines"]["r"]["end_a"]["connection"] = "clamped"
    sc = with_start(data, "straight")
    straight, catenary = compile_scenario(sc), compile_scenario(sc, start="catenary")
    assert not np.array_equal(straight.km.rfe_clamp_R, catenary.km.rfe_clamp_R)
    with pytest.raises(SolverError) as err:
        rfesim.statics(sc)
    assert "line 'r' is 20 m long between ends 5 m apart" in err.value.hint
    assert "rfe_clamp_R" in err.value.hint and "give those ends a direction" in err.value.hint
    data["lines"]["r"]["end_a"]["direction"] = [0.0, 0.0, -1.0]     # given: the same model from either start
    res = rfesim.statics(with_start(data, "straight"))
    assert "so statics started from the catenary" in res.message


NEUTRAL_D = 0.1


def neutral_tether(span: float) -> dict:
    """A neutrally buoyant tether of 100 m (EI 2000 N m^2) between fixed points ``span``
    apart at 50 m depth: nothing pulls it straight, so statics bends it sideways."""
    return {"name": "neutrally buoyant tether",
            "environment": {"gravity": 9.81, "water": {"density": 1025.0, "depth": 200.0}},
            "line_types": {"u": {"EA": 1e7, "EIy": 2000.0, "outer_diameter": NEUTRAL_D,
                                 "mass_per_length": 1025.0 * math.pi / 4.0 * NEUTRAL_D ** 2}},
            "lines": {"l": {"type": "u", "length": 100.0, "elements": 50,
                            "end_a": {"attach": "fixed", "position": [0.0, 0.0, -50.0]},
                            "end_b": {"attach": "fixed", "position": [span, 0.0, -50.0]}}},
            "analysis": {"statics": {"enabled": True}}}


def test_a_bent_compressed_line_is_the_stable_elastica_and_does_not_warn():
    """The slack neutrally buoyant tether settles bent (the elastica): its compression is a
    few per cent above pi^2 EI / L^2, as the post-buckled pinned column's is, and the bent
    shape is stable (its lowest modes about the equilibrium have positive frequencies). Only
    a straight stretch beyond its Euler load is reported."""
    sc = rfesim.load_scenario(neutral_tether(90.0))
    _, info, stretches = statics_with_stretches(sc)
    c, = stretches
    assert c.euler_load < c.compression < 1.1 * c.euler_load
    assert c.deviation > 0.1 * c.length                   # bent by about a fifth of its length
    assert not c.buckles and info.warnings == []


def test_a_heavy_load_elsewhere_does_not_hide_a_buckled_line():
    """The noise floor of the compression is each line's own force scale: a second line pulled
    by 3 MN does not hide the pushed beam at ten times its Euler load."""
    data = pushed_beam(0.0, seabed=False)
    data["lines"]["tie"] = {"type": "beam", "length": 10.0, "elements": 5,
                            "end_a": {"attach": "fixed", "position": [0.0, 10.0, 0.0]}, "end_b": {"attach": "free"},
                            "loads": [{"at": "end_b", "force": [3e6, 0.0, 0.0]}]}
    _, info, stretches = statics_with_stretches(rfesim.load_scenario(data))
    assert len(info.warnings) == 1 and "line 'b'" in info.warnings[0]
    assert [c.line for c in stretches if c.buckles] == ["b"]


def test_a_closing_join_is_crossed_too():
    """Two 10 m lines (EI 10 N m^2) pinned to fixed points 20 m apart less the compression's
    shortening, end B of 'b' closing onto end B of 'a' (a portal's crossbeam halves): at
    twice the Euler load of the 20 m column each half is at half its own and passed; the
    stretch runs from 'a' through the closing join back along 'b' (from its end B) and warns.
    (A closing end B must start within 1e-6 m of its target, which the straight start of a
    shortened 'b' misses by a quarter element times its strain: hence the soft section.)"""
    EI = 10.0
    euler = math.pi ** 2 * EI / 20.0 ** 2
    EA, compression = 1e6, 2.0 * euler
    span = 20.0 - compression * (20.0 + 1.0 / JOINT_STIFFNESS) / EA
    data = {"name": "closed column", "environment": {"gravity": 0.0},
            "line_types": {"soft": {"EA": EA, "EIy": EI, "mass_per_length": 10.0}},
            "lines": {"a": {"type": "soft", "length": 10.0, "elements": 10,
                            "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0]},
                            "end_b": {"attach": "free"}},
                      "b": {"type": "soft", "length": 10.0, "elements": 10,
                            "end_a": {"attach": "fixed", "position": [span, 0.0, 0.0],
                                      "direction": [-1.0, 0.0, 0.0]},
                            "end_b": {"attach": "a:end_b", "connection": "clamped"}}},
            "analysis": {"statics": {"enabled": True}}}
    _, info, stretches = statics_with_stretches(rfesim.load_scenario(data))
    c, = stretches
    assert (c.lines, c.start, c.stop, c.free_ends) == (("a", "b"), 0.0, 0.0, 0)
    assert c.length == pytest.approx(20.0, rel=1e-12)
    assert c.compression == pytest.approx(compression, rel=1e-6)
    assert c.euler_load == pytest.approx(euler, rel=1e-12) and c.buckles
    assert len(info.warnings) == 1 and "lines 'a', 'b', joined end to end" in info.warnings[0]
