"""A static equilibrium with a rope pushed through itself is named (rfesim.solvers.buckling.
through_rope_warnings), and a dynamic run that stops on it at once says where it came from.

The column crane lift-off with a 21 m boom (30 m shipped): the boom tip is 4.7 m short of the
payload on the supply's deck, and the 35.35 m rope between them, 6.6 m slack, converged in
statics with two 1.18 m elements overlapping by 1.66 m at the bottom of its bight (a slack rope
SDE carries no force, so Newton left it so). Its dynamics stopped in their first substep with
the hint for a rope whipped through itself by a drive."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

import rfesim

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def liftoff(boom: float = 21.0, rope: float | None = None, dynamics: bool = False) -> rfesim.Scenario:
    d = json.loads((SCENARIOS / "column_crane_liftoff.json").read_text())
    d["cranes"]["crane"]["boom"]["length"] = boom
    if rope is not None:
        d["cranes"]["crane"]["rope"]["length"] = rope
    if dynamics:
        d["analysis"]["dynamics"]["duration"] = 2.0
    else:
        d["analysis"].pop("dynamics", None)
    return rfesim.load_scenario(d, base_dir=SCENARIOS)


def test_statics_names_a_rope_left_pushed_through_itself():
    res = rfesim.simulate(liftoff())
    msg = res.message
    assert "statics warning: rope 'crane_rope' lies with elements pushed through one another at arc length " in msg
    overlap = float(msg.split("(overlapping by ")[1].split(" m")[0])
    element = float(msg.split("its elements being ")[1].split(" m")[0])
    assert element == pytest.approx(35.35 / 30, rel=1e-3) and overlap > element
    assert "give cranes.crane.rope.length nearer that" in msg


def test_the_dynamic_run_that_stops_on_it_says_so():
    with pytest.raises(rfesim.SolverError) as err:
        rfesim.simulate(liftoff(dynamics=True))
    msg = str(err.value)
    assert "(rope elements pushed through one another" in msg
    assert "the static equilibrium it started from had them: rope 'crane_rope' lies with elements" in msg
    assert "whipped by a drive" not in msg          # not the hint for a run that drives a rope through itself


def test_the_advice_runs_and_a_taut_start_is_not_named():
    """A rope within 0.7 m of the distance between its ends: no warning, and the run goes on."""
    res = rfesim.simulate(liftoff(rope=29.5, dynamics=True))
    assert res.message.startswith("finished")
    assert "pushed through" not in res.message
    assert "pushed through" not in rfesim.simulate(liftoff(boom=30.0)).message
