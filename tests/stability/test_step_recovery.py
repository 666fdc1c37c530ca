"""Going back past a generalized-alpha failure (rfesim.solvers.dynamics.Recovery).

Found by varying the shipped crane scenarios by factors 0.5-2: at their 0.05 s step the column
crane with a 5 t payload (10 t shipped) lowered into an irregular sea failed at 29.2 s, a
slack rope snatched taut that Newton could not pass even in 64 substeps, where the same run at
0.025 s steps went through. A run now goes back to a checkpoint and takes the stretch at half
the step; with recovery_halvings 0 it stops at the failure as before."""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.api import _compiled
from rfesim.crane_results import crane_summary
from rfesim.solvers.dynamics import EnergyCheck, Recorder, Recovery
from rfesim.solvers.system import System

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def light_payload(halvings: int | None, duration: float = 31.0) -> rfesim.Scenario:
    data = json.loads((SCENARIOS / "column_crane.json").read_text())
    data["cranes"]["crane"]["payload"]["mass"] = 5000.0
    dyn = data["analysis"]["dynamics"]
    dyn["duration"] = duration
    if halvings is not None:
        dyn["integrator"]["recovery_halvings"] = halvings
    return rfesim.load_scenario(data, base_dir=SCENARIOS)


def test_a_failure_is_passed_at_half_the_step_and_said():
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(light_payload(0))
    failed = info.value
    # where the slack rope's snatch fails (29.2 s) is chaotic in the last digits of the static state
    # (30.9 s with a compiled re-chaining that rounded differently): the checkpoint gone back to follows it
    assert failed.quantity == "Newton iteration did not converge" and 20.0 < failed.time < 31.0
    checkpoint = 2.0 * math.floor((failed.time - Recovery.REWIND) / 2.0)
    seen = []
    res = rfesim.simulate(light_payload(None), progress=lambda f, t: seen.append((f, t)))   # up to 3 halvings
    assert res.status == 0 and res.counters["step_recoveries"] >= 1
    # the simulated time went back to the checkpoint, the progress fraction did not
    fractions, times = np.array(seen).T
    assert np.any(np.diff(times) < -0.5) and np.all(np.diff(fractions) >= 0.0) and fractions[-1] == 1.0
    # the output times are the run's own, every 0.1 s to the end
    assert np.allclose(res.time, np.arange(311) * 0.1, atol=1e-9, rtol=0.0)
    message = res.message
    assert f"Newton failed at t = {failed.time:.6g} s at the time step 0.05 s" in message
    assert f"the run went back to t = {checkpoint:g} s" in message and "at 0.025 s steps" in message
    # before the checkpoint the run is the failed one's, bit for bit
    early = res.time <= checkpoint + 1e-9
    a = crane_summary(res, "crane")["rope_tension"][early]
    b = crane_summary(failed.results, "crane")["rope_tension"][failed.results.time <= checkpoint + 1e-9]
    assert a.shape == b.shape and np.array_equal(a, b)


def test_rewind_restores_every_array_and_the_recorder():
    sc = light_payload(3)
    system = System(_compiled(sc))
    state = system.model.initial.copy()
    recorder = Recorder(system, 4)
    recorder.record(state, state.qdd)
    energy = EnergyCheck(system, state)
    qdd_prev = np.zeros_like(state.q)
    rec = Recovery(system, recorder, energy, 3, 0.05, 0.1)
    km, ws = system.km, system.ws
    before_km = {f: getattr(km, f).copy() for f in km._fields if isinstance(getattr(km, f), np.ndarray)}
    before_ws = {f: getattr(ws, f).copy() for f in ws._fields if isinstance(getattr(ws, f), np.ndarray)}
    rec.checkpoint(state, 7, qdd_prev)
    # what a run changes: the model's arrays (a winch's payout), the workspace, the recorder
    km.rfe_length[:] *= 1.5
    ws.fric_anchor[:] += 1.0
    qdd_prev[:] = 3.0
    recorder.record(state, state.qdd)
    back, k_out = rec.rewind(10.0, qdd_prev)
    assert k_out == 7 and recorder.k == 1 and rec.level == 1 and rec.fine_until == pytest.approx(12.0)
    assert np.array_equal(back.q, state.q) and back.t == state.t
    assert all(np.array_equal(getattr(km, f), v) for f, v in before_km.items())
    assert all(np.array_equal(getattr(ws, f), v) for f, v in before_ws.items())
    assert not qdd_prev.any()
    assert rec.can_recover() and Recovery(system, recorder, energy, 0, 0.05, 0.1).can_recover() is False


def test_recovery_halvings_is_checked():
    data = json.loads((SCENARIOS / "column_crane.json").read_text())
    data["analysis"]["dynamics"]["integrator"]["recovery_halvings"] = 7
    with pytest.raises(rfesim.ScenarioError) as info:
        rfesim.load_scenario(data, base_dir=SCENARIOS)
    assert info.value.errors == [("analysis.dynamics.integrator.recovery_halvings",
                                  "must be less than or equal to 6 (got 7)")]


def portal_without_winch(halvings: int) -> rfesim.Scenario:
    """scenarios/a_frame.json without its winch (a scene the compiled recording runs, rfesim.
    solvers.recording) and with the tilt table that stops the legs dead at 35 s: the payload
    snatches its rope, which rings slack and taut. (The rope-free failures this test used
    before, the H1 riser with half its wall at 4.16 s among them, were lines floating at the
    surface, which now run: rfesim.loads.hydro.submergence.)"""
    data = json.loads((SCENARIOS / "a_frame.json").read_text())
    crane = data["cranes"]["aframe"]
    crane.pop("winch")
    crane["tilt_deg"] = [[0.0, -25.0], [5.0, -25.0], [35.0, 35.0]]
    dyn = data["analysis"]["dynamics"]
    dyn["duration"] = 40.0
    dyn["integrator"]["recovery_halvings"] = halvings
    return rfesim.load_scenario(data, base_dir=SCENARIOS)


def test_the_compiled_recording_goes_back_too():
    # a scene without winches runs in the compiled recording (rfesim.solvers.recording): its
    # chunks stop at the checkpoints
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(portal_without_winch(0))
    assert 36.0 < info.value.time < 37.0
    seen = []
    res = rfesim.simulate(portal_without_winch(6), progress=lambda f, t: seen.append((f, t)))
    assert res.status == 0 and res.counters["step_recoveries"] >= 1
    assert res.time[-1] == pytest.approx(40.0) and np.all(np.diff(res.time) > 0.0)
    # a fraction of the duration, never going back (the compiled recording's chunks too)
    fractions, times = np.array(seen).T
    assert np.all((0.0 <= fractions) & (fractions <= 1.0)) and np.all(np.diff(fractions) >= 0.0)
    assert fractions[-1] == 1.0 and times[-1] == pytest.approx(40.0)
    # the compiled recording keeps its checkpoints between its chunks of outputs, whose size
    # follows the wall time: the time gone back to is read from the message
    got = re.search(r"Newton failed at t = ([\d.]+) s at the time step 0.05 s .* the run went back to t = ([\d.]+) s "
                    r"and took the stretch to [\d.]+ s at 0.025 s steps", res.message)
    assert got is not None, res.message
    assert float(got.group(1)) == pytest.approx(info.value.time, abs=1e-4)
    back = float(got.group(2))
    assert 0.0 <= back <= info.value.time - Recovery.REWIND
    # the later failures inside the finer stretches (4 recoveries) went back further, to the
    # checkpoints between the compiled chunks, which this fast scene takes seconds apart (the
    # first output that differs is at 25 s): up to 20 s the recovered run is the failed one,
    # bit for bit
    assert res.counters["step_recoveries"] >= 2
    failed = info.value.results
    n = int(np.searchsorted(failed.time, 20.0 + 1e-9))
    assert n == 101
    assert np.array_equal(res.line("aframe_rope").tension[:n], failed.line("aframe_rope").tension[:n])


def test_a_failure_soon_after_a_stretch_goes_back_to_its_end_and_doubles_the_next():
    """The Recovery bookkeeping (rfesim.solvers.dynamics.Recovery): a stretch at the finer step
    ends with a checkpoint of that step's state; a failure 0.2 s later goes back to it (not to
    the checkpoint 0.5 s before the failure, which may lie before the stretch and its shock)
    and takes a stretch of 4 s; one more than 2 s after the next stretch's end takes 2 s again.
    The warning says how long the longest stretch was."""
    sc = light_payload(3)
    system = System(_compiled(sc))
    state = system.model.initial.copy()
    recorder = Recorder(system, 4)
    recorder.record(state, state.qdd)
    rec = Recovery(system, recorder, EnergyCheck(system, state), 3, 0.05, 0.1)
    qdd_prev = np.zeros_like(state.q)

    def at(t):
        s = state.copy()
        s.t = t
        return s

    rec.checkpoint(at(0.0), 1, qdd_prev)
    back, _ = rec.rewind(0.3, qdd_prev)                  # the first failure: back to t = 0 for 2 s
    assert back.t == 0.0 and rec.level == 1 and rec.fine_until == pytest.approx(2.3)
    assert rec.due(2.3) and not rec.due(1.5)             # the stretch's end takes a checkpoint
    rec.checkpoint(at(2.3), 24, qdd_prev)
    assert rec.checkpoints[-1]["fine"] and not rec.checkpoints[0]["fine"]
    rec.back_to_nominal(2.3)
    back, k_out = rec.rewind(2.5, qdd_prev)              # 0.2 s after it: back to its end, 4 s
    assert back.t == 2.3 and k_out == 24 and rec.fine_until == pytest.approx(6.5) and rec.span == 4.0
    rec.checkpoint(at(6.5), 66, qdd_prev)
    rec.back_to_nominal(6.5)
    rec.checkpoint(at(8.5), 86, qdd_prev)                # an ordinary checkpoint, 2 s on
    assert not rec.checkpoints[-1]["fine"]
    back, _ = rec.rewind(9.0, qdd_prev)                  # 2.5 s after the end: 2 s again, from 8.5 s
    assert back.t == 8.5 and rec.span == 2.0 and rec.fine_until == pytest.approx(11.0)
    (warning,) = rec.warnings()
    assert "3 such recoveries in all, at t = 0.3, 2.5, 9 s" in warning
    assert "failing again within 2 s of a stretch's end, the next stretch was taken twice as long, up to 4 s" in warning
