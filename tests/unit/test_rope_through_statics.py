"""A slack rope bight in statics rests on its axial contact (rfesim.loads.tension_only), and
a static state with a rope pushed through itself is still named (rfesim.solvers.buckling.
through_rope_warnings).

The column crane lift-off with a 21 m boom (30 m shipped): the boom tip is 4.7 m short of the
payload on the supply's deck, and the 35.35 m rope between them is 6.6 m slack. Before the
contact its statics converged with two 1.18 m elements overlapping by 1.66 m at the bottom of
the bight (a slack rope SDE carried no force at all, so Newton left it so), and its dynamics
stopped in their first substep. Now the contact holds the bight and the run goes on."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
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


def _statics(sc):
    from rfesim.model.compile import compile_scenario
    from rfesim.solvers.statics import solve_statics
    from rfesim.solvers.system import System
    system = System(compile_scenario(sc))
    state, _ = solve_statics(system)
    return system, state


def test_the_slack_bight_rests_on_its_contact_in_statics():
    system, state = _statics(liftoff())
    rope = [li for li in system.model.lines if li.name == "crane_rope"][0]
    st = state.copy()
    st.qd[:] = 0.0
    system.evaluate(st)
    gaps = system.ws.eps[rope.sde_start:rope.sde_stop, 0]
    # no pair past the contact's ramp (half an element, plus a tenth), none pushed through
    assert gaps.min() > -0.6 * rope.dx and gaps.min() < -0.5 * rope.dx     # the contact is what holds it
    res = rfesim.simulate(liftoff())
    assert "pushed through" not in res.message and "crammed" not in res.message


def test_the_run_that_stopped_at_once_now_goes_on():
    res = rfesim.simulate(liftoff(dynamics=True))
    assert res.status == 0 and res.time[-1] == pytest.approx(2.0)
    tension = np.asarray(res.line("crane_rope").tension)
    assert tension.max() > 1000.0                  # the rope's upper part hangs taut
    assert tension.min() > -1000.0                 # the bight rests: small contact forces, no shock
    assert "driven into itself" not in res.message


def test_a_static_state_pushed_through_is_named():
    """Through_rope_warnings on a state with one element moved back 1.5 element lengths
    along its axis: its gap to the previous element is past minus their arms' sum."""
    sc = liftoff(boom=30.0)
    system, state = _statics(sc)
    rope = [li for li in system.model.lines if li.name == "crane_rope"][0]
    from rfesim.solvers.buckling import through_rope_warnings
    assert through_rope_warnings(system, state, sc) == []
    k = rope.rfe_start + 15
    st = state.copy()
    system.evaluate(st)
    st.q[k, :3] -= 1.5 * rope.dx * system.ws.R[k, :, 0]
    msg = through_rope_warnings(system, st, sc)
    assert len(msg) == 1 and msg[0].startswith("rope 'crane_rope' lies with elements pushed through one another")
    overlap = float(msg[0].split("(overlapping by ")[1].split(" m")[0])
    assert overlap == pytest.approx(1.5 * rope.dx, rel=0.05)
    assert f"its elements being {rope.dx:.4g} m long" in msg[0]


def test_a_taut_start_is_not_named():
    """A rope within 0.7 m of the distance between its ends: no warning, and the run goes on."""
    res = rfesim.simulate(liftoff(rope=29.5, dynamics=True))
    assert res.message.startswith("finished")
    assert "pushed through" not in res.message
    assert "pushed through" not in rfesim.simulate(liftoff(boom=30.0)).message
