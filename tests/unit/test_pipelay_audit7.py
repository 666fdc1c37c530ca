"""Regression tests for the pipelay audit 7 (reel-lay, J-lay, tensioner and payout):

1. a constant-tension tensioner pays out stably at the usual steps (implicit payout);
2. a reel-lay template with a constant-tension tensioner starts without a transient (the
   reel holds the back tension statics settled);
3. a two-row payout table is a straight line (the schema's constant speed);
4. a track's capacity holds up to its stated value, and a template refuses a capacity below
   its static load naming the field;
5. the reel-lay straightener bends the pipe against the reeling sense;
6. the reel-lay template stores enough pipe to bring reeled pipe past the straightener;
7. a payout table that pays out more than the pipe held upstream is refused.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.errors import ScenarioError

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = ROOT / "scenarios"

MASS_PER_LENGTH = 100.0
LENGTH = 150.0
PULL = 5.0e4


# --------------------------------------------------------------------------- 1. implicit payout

def pulled_line(payout, time_step=0.05, duration=2.0, capacity=1.0e6):
    """A 150 m line without gravity, pulled at end B by PULL, held by a 10 m tensioner
    (grip stiffness 1e7 N/m/m: k = 1e8 N/m)."""
    return rfesim.Scenario.model_validate({
        "environment": {"gravity": 0.0},
        "line_types": {"pipe": {"EA": 2e9, "EIy": 1e6, "GJ": 1e6, "mass_per_length": MASS_PER_LENGTH,
                                "outer_diameter": 0.3, "damping": {"axial_ratio": 0.05, "bending_ratio": 0.05}}},
        "lines": {"pipe": {"type": "pipe", "length": LENGTH, "elements": 75,
                           "end_a": {"attach": "free", "position": [-70.0, 0.0, 0.0], "direction": [1, 0, 0]},
                           "end_b": {"attach": "free"},
                           "loads": [{"at": "end_b", "force": [PULL, 0.0, 0.0]}]}},
        "supports": {"tensioner": {"kind": "tensioner", "line": "pipe", "entry": [0.0, 0.0, 0.0],
                                   "axis": [1.0, 0.0, 0.0], "length": 10.0, "capacity": capacity,
                                   "payout": payout}},
        "analysis": {"dynamics": {"duration": duration, "output_interval": 0.05,
                                  "integrator": {"kind": "generalized-alpha", "time_step": time_step}}},
    })


def test_constant_tension_payout_settles_at_the_usual_step():
    """Set 30 kN, band 5 kN, gain 1e5 N s/m against a 50 kN pull: the rigid closed form is
    m dv/dt = PULL - (set + band + gain v), v -> (PULL - set - band) / gain = 0.15 m/s with
    tau = m / gain = 0.15 s, D(t) = v_inf (t - tau (1 - exp(-t / tau))). The explicit
    update used before needed h < 2 gain / k = 2 ms; at h = 0.05 s it chattered (D flipping
    by +-v_max h, the grip force changing sign)."""
    T_set, band, gain, vmax = 3.0e4, 0.5e4, 1.0e5, 0.5
    res = rfesim.simulate(pulled_line({"kind": "constant-tension", "tension": T_set, "dead_band": band,
                                       "gain": gain, "max_speed": vmax}))
    tens = res.tensioners["tensioner"]
    t, D, F = np.asarray(res.time), np.asarray(tens.payout), np.asarray(tens.grip_force)
    v_inf = (PULL - T_set - band) / gain
    tau = MASS_PER_LENGTH * LENGTH / gain
    closed = v_inf * (t - tau * (1.0 - np.exp(-t / tau)))
    assert v_inf == pytest.approx(0.15)
    np.testing.assert_allclose(D, closed, atol=0.01)       # backward Euler at h = tau / 3
    assert D[-1] == pytest.approx(v_inf * (2.0 - tau), rel=0.02)      # 0.2775 m
    assert np.all(np.diff(D) >= -1e-12)                    # no chatter: the pads never go back
    assert np.all(F > 0.0)                                 # no sign flips
    late = t >= 1.0
    speed = np.gradient(D, t)[late]
    np.testing.assert_allclose(speed, v_inf, rtol=0.02)
    np.testing.assert_allclose(F[late], PULL, rtol=0.02)   # steady: set + band + gain v = PULL
    # the characteristic holds between the recorded force and the payout speed
    np.testing.assert_allclose(T_set + band + gain * speed, F[late], rtol=0.02)


# --------------------------------------------------------------------------- 2. reel set point

def test_reel_lay_with_a_constant_tension_tensioner_starts_without_a_transient():
    """Tensioner set to its own static force with a 30 kN band: nothing should move. The reel
    holds the back tension statics settled (its law acts on its grip force less the offset
    statics fixed, grip - back tension; its set point is that back tension), so the
    tensioner's load stays at its static value.
    Before: the reel's law acted on its grip force (69 kN, which carries the moment of the
    pipe leaving the drum) with a set point of half the back tension (8.7 kN): it paid out at
    once, compressed the pipe on the ramp and raised the tensioner's load from 174 to 214 kN."""
    base = {"environment.water.waves": None, "vessels.reeler.motion": {"kind": "fixed"},
            "analysis.dynamics.duration": 0.05, "analysis.dynamics.output_interval": 0.05}
    r0 = rfesim.simulate(rfesim.load_scenario(SCENARIOS / "reel_lay.json", overrides=base))
    F0 = float(r0.tensioners["lay_tensioner"].grip_force[0])
    over = dict(base)
    over.update({"analysis.dynamics.duration": 1.0, "analysis.dynamics.output_interval": 0.1,
                 "pipelay.lay.tensioner.payout": {"kind": "constant-tension", "tension": F0, "dead_band": 3.0e4,
                                                  "gain": 1.0e5, "max_speed": 0.5}})
    res = rfesim.simulate(rfesim.load_scenario(SCENARIOS / "reel_lay.json", overrides=over))
    reel = json.loads(res.scenario_json)["supports"]["lay_reel"]
    assert reel["payout"]["tension"] == reel["back_tension"]
    tens, rl = res.tensioners["lay_tensioner"], res.reels["lay_reel"]
    F = np.asarray(tens.grip_force)
    assert np.abs(F - F0).max() < 0.03 * F0
    assert np.abs(np.asarray(tens.payout)).max() < 1e-3
    D = np.asarray(rl.payout)
    assert np.abs(D - D[0]).max() < 0.01
    # the pipe on the ramp (between the aligner and the tensioner) stays in tension
    line = res.line("lay")
    s = np.asarray(line.sde_arc_length)
    stored = reel["stored_length"]
    ramp = (s > stored + 4.0) & (s < stored + 20.0)
    assert np.asarray(line.tension)[:, ramp].min() > 0.0


# --------------------------------------------------------------------------- 3. two-row tables

def test_two_row_payout_table_is_a_straight_line():
    """Rows [[0, 0], [20, 2]]: 0.1 m/s, D = 0.1 t (before: zero end slopes, D(1 s) = 0.0145 m
    and a peak speed of 0.15 m/s)."""
    from rfesim.loads.tensioner import tensioner_payout
    from rfesim.model.supports import fill_payout
    from rfesim.scenario.schema import PayoutTable
    out = {k: np.zeros((1, 4)) for k in ("tens_table_t", "tens_table_d", "tens_table_v")}
    out.update(tens_mode=np.zeros(1, np.int64), tens_count=np.zeros(1, np.int64))
    fill_payout(out, "tens", 0, PayoutTable(kind="table", rows=[[0.0, 0.0], [20.0, 2.0]]))
    D = [tensioner_payout(out["tens_mode"], out["tens_table_t"], out["tens_table_d"], out["tens_table_v"],
                          out["tens_count"], 0, t, np.zeros(1)) for t in (1.0, 2.0, 3.0, 4.0, 10.0, 20.0, 30.0)]
    np.testing.assert_allclose(D, [0.1, 0.2, 0.3, 0.4, 1.0, 2.0, 2.0], rtol=0, atol=1e-12)
    # three rows and more keep the monotone cubic (continuous speed), passing every row
    fill_payout(out, "tens", 0, PayoutTable(kind="table", rows=[[0.0, 0.0], [10.0, 0.0], [20.0, 10.0]]))
    out["tens_count"][0] = 3
    D = [tensioner_payout(out["tens_mode"], out["tens_table_t"], out["tens_table_d"], out["tens_table_v"],
                          out["tens_count"], 0, t, np.zeros(1)) for t in (10.0, 20.0)]
    np.testing.assert_allclose(D, [0.0, 10.0], atol=1e-12)
    assert "PCHIP" in PayoutTable.__doc__ and "Two rows: a straight line" in PayoutTable.__doc__


# --------------------------------------------------------------------------- 4. capacity

def test_track_capacity_is_the_whole_tracks_holding_force():
    """Every RFE in the track pulled far beyond its grip: the grip forces add up to the stated
    capacity exactly, whatever the taper and the element lengths (before: F_max l w / L per
    RFE, about 0.75 F_max in all)."""
    from rfesim.loads.tensioner import MODE_TABLE, tensioner_forces
    n, L, cap = 12, 10.0, 6.0e5
    lengths = np.full(n, 1.25)
    xi = -0.6 + 1.25 * np.arange(n)                    # one half-length element at the entry
    r = np.zeros((n, 3))
    r[:, 0] = xi
    F = np.zeros((n, 3))
    force = np.zeros(1)
    tensioner_forces(np.array([0]), np.zeros((1, 3)), np.array([[1.0, 0.0, 0.0]]), np.array([L]),
                     np.array([1e6]), np.array([1e7]), np.array([cap]), np.array([0]), np.array([n]),
                     np.array([MODE_TABLE]), np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2)), np.array([2]),
                     0.0, np.zeros((1, 3)), np.eye(3)[None], lengths, r, F, xi - 5.0, np.ones(n, np.int64),
                     np.zeros(n), np.zeros(n, np.int64), np.zeros(1), force, np.zeros(1), np.zeros(1), np.ones(1),
                     np.zeros(1), 0.0, np.zeros(1))
    assert force[0] == pytest.approx(cap, rel=1e-12)
    assert -F[:, 0].sum() == pytest.approx(cap, rel=1e-12)


def test_j_lay_collar_holds_up_to_its_capacity_and_a_short_one_is_refused():
    """The J-lay collar carries the catenary's top tension (468.3 kN by hand) and 10 m of pipe
    in the tower (11.8 kN; 30 m before the J-lay default elements became 1.5 m): 480.1 kN. Rated 600 kN it holds (before: statics failed at an
    RFE 900 m away below about 671 kN); rated 400 kN the template refuses it, naming the field."""
    over = {"analysis.dynamics.duration": 0.5, "analysis.dynamics.output_interval": 0.5,
            "pipelay.lay.vessel.motion": {"kind": "fixed"}, "pipelay.lay.tensioner.capacity": 6.0e5}
    res = rfesim.simulate(rfesim.load_scenario(SCENARIOS / "j_lay.json", overrides=over))
    collar = res.tensioners["lay_collar"]
    assert np.asarray(collar.grip_force) == pytest.approx(480.1e3, rel=0.01)
    assert np.abs(np.asarray(collar.payout)).max() == 0.0
    over["pipelay.lay.tensioner.capacity"] = 4.0e5
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(SCENARIOS / "j_lay.json", overrides=over)
    text = str(err.value)
    assert "pipelay.lay.tensioner.capacity" in text and "400000 N" in text and "collar" in text


# --------------------------------------------------------------------------- 5. straightener sense

def _reel_lay_statics(offset: float):
    over = {"environment.water.waves": None, "vessels.reeler.motion": {"kind": "fixed"},
            "analysis.dynamics.duration": 0.05, "analysis.dynamics.output_interval": 0.05,
            "pipelay.lay.element_length": 1.0, "pipelay.lay.straightener_offset": offset,
            "pipelay.lay.tensioner.payout": None, "pipelay.lay.reel.stored_length": 12.0}
    res = rfesim.simulate(rfesim.load_scenario(SCENARIOS / "reel_lay.json", overrides=over))
    st = json.loads(res.scenario_json)["supports"]["lay_straightener"]
    e, entry = np.array(st["axis"]), np.array(st["entry"])
    P = np.asarray(res.line("lay").position)[0]
    seg = np.diff(P, axis=0)
    turn = np.diff(np.arctan2(-seg[:, 2], seg[:, 0]))       # + : the reel's and the aligner's sense
    mid = entry + 0.5 * st["span"] * e
    im = int(np.linalg.norm(P[1:-1] - mid, axis=1).argmin())
    return turn[im] / 1.0, st                                # per metre (1 m elements)


def test_straightener_reverse_bends():
    """Raising straightener_offset bends the pipe at the middle roller against the reeling
    and aligner sense (positive turning, +0.107 1/m on the drum): before, the middle roller
    pushed the other way and 0.30 m gave +0.086 1/m."""
    k0, st = _reel_lay_statics(0.0)
    k3, _ = _reel_lay_statics(0.3)
    al = math.radians(70.0)
    np.testing.assert_allclose(st["side"], [-math.sin(al), 0.0, -math.cos(al)], atol=1e-12)
    assert k3 < k0 - 0.05
    assert k3 < 0.0


# --------------------------------------------------------------------------- 6. stored length

def _expanded(overrides: dict) -> dict:
    sc = rfesim.load_scenario(SCENARIOS / "reel_lay.json", overrides=overrides)
    return json.loads(sc.model_dump_json())


def test_reel_lay_template_stores_enough_pipe():
    """Default stored length: path from the take-off point to the straightener exit (2 + Rp
    alpha + 2 + 6 m, Rp the aligner's pipe-axis radius) + the table's 7.5 m + two 2 m
    elements, at most half a turn less one element (23.6 m); before a fixed quarter turn
    (12.8 m), shorter than that path (21.4 m): no reeled pipe could reach the straightener."""
    sup = _expanded({})["supports"]
    reel, aligner = sup["lay_reel"], sup["lay_aligner"]
    Rp = aligner["radius"] + 0.5 * 0.3239 + aligner["roller_radius"]
    path = 2.0 + Rp * math.radians(70.0) + 2.0 + 6.0
    assert path == pytest.approx(21.38, abs=0.01)
    half_turn = math.pi * reel["radius"] - 2.0               # half a turn less one element
    assert reel["stored_length"] == pytest.approx(min(half_turn, path + 7.5 + 4.0), rel=1e-9)
    assert reel["stored_length"] > path                       # reeled pipe can reach past the straightener
    assert reel["radius"] * math.radians(reel["wrap_deg"]) >= reel["stored_length"]
    # an explicit stored length, and one the drum cannot hold
    assert _expanded({"pipelay.lay.reel.stored_length": 20.0})["supports"]["lay_reel"]["stored_length"] == 20.0
    with pytest.raises(ScenarioError, match="pipelay.lay.reel.stored_length"):
        _expanded({"pipelay.lay.reel.stored_length": 30.0})


# --------------------------------------------------------------------------- 7. payout beyond the pipe held

def test_payout_beyond_the_pipe_held_is_refused():
    """J-lay: 40 m through a 10 m collar (end A at its entry; 30 m before the default elements
    became 1.5 m: three elements long) dropped the pipe silently;
    reel-lay: the bundled table once reached 88.5 m at 600 s against 12.8 m stored. Both are
    refused at check time, naming the field and the numbers."""
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(SCENARIOS / "j_lay.json", overrides={
            "pipelay.lay.tensioner.payout": {"kind": "table", "rows": [[0.0, 0.0], [10.0, 40.0]]}})
    text = str(err.value)
    assert "pipelay.lay.tensioner.payout" in text and "40 m" in text and "holds only 10 m" in text
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(SCENARIOS / "reel_lay.json", overrides={
            "pipelay.lay.tensioner.payout": {"kind": "table", "rows": [[0.0, 0.0], [600.0, 88.5]]}})
    assert "pipelay.lay.tensioner.payout" in str(err.value) and "88.5 m" in str(err.value)
    with pytest.raises(ScenarioError, match="88.5 m"):
        rfesim.load_scenario(SCENARIOS / "reel_lay.json", overrides={
            "pipelay.lay.reel.stored_length": 20.0,
            "pipelay.lay.tensioner.payout": {"kind": "table", "rows": [[0.0, 0.0], [600.0, 88.5]]}})
    # a reel support of its own: the table against stored_length
    from rfesim.scenario.schema import ReelSupport
    with pytest.raises(Exception, match="stored_length"):
        ReelSupport.model_validate({"kind": "reel", "line": "l", "centre": [0, 0, 0], "axis": [0, -1, 0],
                                    "direction": [1, 0, 0], "radius": 8.0, "stored_length": 10.0, "capacity": 1e6,
                                    "payout": {"kind": "table", "rows": [[0.0, 0.0], [10.0, 11.0]]}})
    # the bundled scenarios stay valid
    for name in ("reel_lay.json", "j_lay.json", "s_lay_template.json"):
        rfesim.load_scenario(SCENARIOS / name)
