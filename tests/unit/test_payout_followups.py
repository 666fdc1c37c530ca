"""Regression tests for the payout follow-ups of the pipelay audit:

1. the heave compensation's integral does not wind up while its speed is held at max_speed
   (conditional integration): after a heave it cannot follow it settles without the
   overshoot the wound-up integral gave;
2. a driven tensioner's or reel's trial payout lives in the workspace (``tens_D_trial``,
   ``reel_D_trial``), not in the model's payout tables (which stay constant);
3. a constant-tension payout that runs end A of the line out of the tensioner's track stops the run with a SolverError naming it (with the results so far);
4. a tensioner whose grips all slip in statics is named with its capacity field;
5. a payout table that pays out more line than lies behind a tensioner's exit is refused
   before the run, naming supports.<name>.payout, and stops the run if it gets there anyway.
"""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.errors import SolverError

G = 9.81


# --------------------------------------------------------------------------- 1. anti-windup

def _smooth_heave(rise: float, t0: float, t1: float, end: float, dt: float = 0.25) -> list:
    """Table rows of a heave rising by ``rise`` from t0 to t1 (quintic smoothstep), then still."""
    rows = []
    for t in np.arange(0.0, end + 1e-9, dt):
        u = min(max((t - t0) / (t1 - t0), 0.0), 1.0)
        rows.append([float(t), 0.0, 0.0, rise * (10 * u ** 3 - 15 * u ** 4 + 6 * u ** 5), 0.0, 0.0, 0.0])
    return rows


def _compensated_payout(duration: float = 40.0) -> tuple[np.ndarray, np.ndarray]:
    """A 1 t payload on 10 m of rope from a ship's sheave that heaves up 4 m in 6 s (1.25 m/s
    at the most) and stays there; the compensation (kp 1 1/s, ki 0.2 1/s^2) pays out at most
    0.3 m/s."""
    hc = {"kp": 1.0, "ki": 0.2, "max_speed": 0.3}
    ship = {"ship": {"motion": {"kind": "table", "rows": _smooth_heave(4.0, 2.0, 8.0, duration + 1.0)}}}
    sc = {
        "environment": {"gravity": G},
        "vessels": ship,
        "line_types": {"rope": {"EA": 1e8, "EIy": 1.0, "mass_per_length": 0.5, "tension_only": True,
                                "damping": {"axial_ratio": 0.2}}},
        "bodies": {"payload": {"mass": 1000.0, "radius_of_gyration": 0.5}},
        "lines": {"hoist": {"type": "rope", "length": 10.0, "elements": 5,
                            "end_a": {"attach": "ship", "position": [0, 0, 0]},
                            "end_b": {"attach": "payload", "position": [0, 0, 0]}}},
        "winches": {"w": {"line": "hoist", "stored": 200.0, "mode": {"kind": "speed", "rows": [[0, 0]]},
                          "heave_compensation": hc}},
        "analysis": {"statics": {"enabled": True, "start": "straight"},
                     "dynamics": {"duration": duration, "output_interval": 0.1,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.05, "rho_inf": 0.8}}},
    }
    res = rfesim.simulate(sc)
    return np.asarray(res.time), np.asarray(res.winch("w").payout)


def test_heave_compensation_integral_does_not_wind_up():
    """The error reaches about 2.8 m while the speed is held at 0.3 m/s for some 13 s. With
    the integral of all of it (before: about 21 m s, ki times it 4.2 m/s) the compensation
    ran on far past the 4 m it had to pay out; with conditional integration (no integration
    while saturated with the error pushing further into the limit) it overshoots a few cm."""
    t, D = _compensated_payout()
    assert D[t <= 2.0].max() < 1e-6                                # nothing before the heave
    assert np.diff(D)[(t[1:] > 3.0) & (t[1:] < 12.0)].max() <= 0.3 * 0.1 + 1e-9   # held at max_speed
    overshoot = D.max() - 4.0
    assert D.max() > 3.9                                         # it catches up with the heave
    assert overshoot < 0.1                                       # before: 2.14 m
    assert abs(D[-1] - 4.0) < 0.05                               # and settles on it


# --------------------------------------------------------------------------- 2. trial payout in the workspace

MASS_PER_LENGTH = 100.0
PULL = 5.0e4


def _pulled_line(payout, end_a: float = -70.0, capacity: float = 1.0e6, duration: float = 2.0,
                 reel: dict | None = None):
    """A 150 m line without gravity, pulled at end B by PULL, held by a 10 m tensioner from x
    = 0 (end A at x = end_a), or stored on a reel (``reel``: the support, end A on the drum)."""
    sup = {"tensioner": {"kind": "tensioner", "line": "pipe", "entry": [0.0, 0.0, 0.0], "axis": [1.0, 0.0, 0.0],
                         "length": 10.0, "capacity": capacity, "payout": payout}}
    end = {"attach": "free", "position": [end_a, 0.0, 0.0], "direction": [1, 0, 0]}
    if reel is not None:
        sup = {"reel": dict(reel, payout=payout)}
        end = {"attach": "free"}
    return rfesim.Scenario.model_validate({
        "environment": {"gravity": 0.0},
        "line_types": {"pipe": {"EA": 2e9, "EIy": 1e4, "GJ": 1e4, "mass_per_length": MASS_PER_LENGTH,
                                "outer_diameter": 0.3, "damping": {"axial_ratio": 0.05, "bending_ratio": 0.05}}},
        "lines": {"pipe": {"type": "pipe", "length": 150.0, "elements": 75, "end_a": end,
                           "end_b": {"attach": "free"},
                           "loads": [{"at": "end_b", "force": [PULL, 0.0, 0.0]}]}},
        "supports": sup,
        "analysis": {"dynamics": {"duration": duration, "output_interval": 0.05,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.05}}},
    })


DRIVEN = {"kind": "constant-tension", "tension": 3.0e4, "dead_band": 0.5e4, "gain": 1.0e5, "max_speed": 0.5}


def test_driven_trial_payout_is_kept_in_the_workspace_not_the_model():
    from rfesim.model.compile import compile_scenario
    from rfesim.solvers.system import System
    system = System(compile_scenario(_pulled_line(DRIVEN)))
    km, ws = system.km, system.ws
    assert ws.tens_D_trial.shape == ws.tens_D.shape and ws.reel_D_trial.shape == ws.reel_D.shape
    table = km.tens_table_d.copy()
    st = system.model.initial.copy()
    system.evaluate(st)
    system.commit_history()
    st.t = 0.05                          # the unloaded line: the tensioner reels in at up to 0.5 m/s
    system.evaluate(st)
    np.testing.assert_array_equal(km.tens_table_d, table)          # the model stays as compiled
    assert -0.5 * 0.05 <= ws.tens_D_trial[0] < 0.0                # reels in (within h v_max)
    assert ws.tens_D[0] == 0.0
    system.commit_history()
    assert ws.tens_D[0] == ws.tens_D_trial[0]                      # committed from the workspace
    np.testing.assert_array_equal(km.tens_table_d, table)


# --------------------------------------------------------------------------- 3. line run out

def test_tensioner_that_runs_end_a_out_of_its_track_stops_the_run():
    """End A 5 m before the entry of a 10 m track: 15 m held up to the exit. Set 10 kN with a
    gain of 1e4 N s/m against the 50 kN pull pays out at up to 4 m/s: the line's end leaves the
    track after about 5 s (before: the run went on with the line free)."""
    payout = {"kind": "constant-tension", "tension": 1.0e4, "dead_band": 0.0, "gain": 1.0e4, "max_speed": 5.0}
    with pytest.raises(SolverError) as err:
        rfesim.simulate(_pulled_line(payout, end_a=-5.0, duration=10.0))
    exc = err.value
    text = str(exc)
    assert "tensioner 'tensioner'" in text and "line 'pipe'" in text and "out of its track" in text
    held = float(text.split("held ")[1].split(" m")[0])
    assert 14.0 < held < 15.0                     # end A 5 m before the entry, less the pull's stretch
    paid = float(text.split("paid out ")[1].split(" m")[0])
    assert 13.0 < paid < 16.0
    assert exc.results is not None
    t = np.asarray(exc.results.time)
    assert 3.0 < t[-1] < 8.0
    D = np.asarray(exc.results.tensioners["tensioner"].payout)
    assert D[-1] == pytest.approx(paid, rel=1e-5)


# --------------------------------------------------------------------------- 4. capacity in statics

def test_statics_beyond_a_tensioners_capacity_names_its_capacity():
    """A 20 kN track against the 50 kN pull: statics fails with the track slipping; the error
    names supports.tensioner.capacity and the numbers (before: an RFE far away)."""
    with pytest.raises(SolverError) as err:
        rfesim.statics(_pulled_line(None or {"kind": "table", "rows": [[0.0, 0.0]]}, capacity=2.0e4))
    text = str(err.value)
    assert "supports.tensioner.capacity" in text and "tensioner 'tensioner'" in text
    assert "20000 N" in text and "about 50000 N" in text      # 12.5 kN at load factor 0.25
    assert err.value.hint is not None and "supports.tensioner.capacity" in err.value.hint


# --------------------------------------------------------------------------- 5. a table beyond the line held

RUNOUT_TABLE = {"kind": "table", "rows": [[0.0, 0.0], [2.0, 0.0], [18.0, 15.0], [20.0, 15.0]]}


def test_payout_table_beyond_the_line_behind_the_track_is_refused():
    """End A at the entry of a 10 m track, the table pays out 15 m: before, `rfesim check`
    passed it and the run 'finished' with status 0 while the line flew off 494 m under its
    pull (the grip force 0). Now the model build refuses it, naming the field and both
    lengths; 4 m, and 15 m with end A 10 m further back (20 m held), are accepted."""
    from rfesim.api import check_model
    from rfesim.errors import ScenarioError
    with pytest.raises(ScenarioError) as err:
        check_model(_pulled_line(RUNOUT_TABLE, end_a=0.0, duration=20.0))
    text = str(err.value)
    assert "supports.tensioner.payout" in text
    assert "pays out 15 m" in text and "holds only 10 m" in text
    check_model(_pulled_line({"kind": "table", "rows": [[0.0, 0.0], [10.0, 4.0]]}, end_a=0.0))
    check_model(_pulled_line(RUNOUT_TABLE, end_a=-10.0))


def test_payout_table_that_runs_end_a_out_stops_the_run(monkeypatch):
    """The run-time net behind that check (a payout statics shifts, or a scene the start-shape
    check cannot judge): with the check switched off, the 15 m table through the 10 m track
    stops the run once end A's element has left the track (its centre past the exit, about
    9.5 m paid out at 12 s), with a SolverError naming the tensioner, its table and the
    results so far (before: status 0, 'finished: 400 steps')."""
    import rfesim.model.supports as supports
    monkeypatch.setattr(supports, "table_payout_problems", lambda model: [], raising=False)
    with pytest.raises(SolverError) as err:
        rfesim.simulate(_pulled_line(RUNOUT_TABLE, end_a=0.0, duration=20.0))
    exc = err.value
    text = str(exc)
    assert "tensioner 'tensioner'" in text and "out of its track" in text and "payout table" in text
    assert "supports.tensioner.payout" in text
    paid = float(text.split("paid out ")[1].split(" m")[0])
    held = float(text.split("held ")[1].split(" m")[0])
    assert 9.0 < paid < 11.0 and 9.9 < held <= 10.0
    t = np.asarray(exc.results.time)
    assert 10.0 < t[-1] < 14.0
    assert exc.results.status == 1
