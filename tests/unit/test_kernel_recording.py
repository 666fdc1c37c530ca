"""Recording inside the compiled run (rfesim.solvers.recording.ga_run) against the Python
recorder it replaces (rfesim.solvers.dynamics.Recorder.record, kept as the readable
reference and switched on here with Recorder.IN_KERNEL = False): the same steps, the same
counters and the same outputs, for lines with joints, drives and a payload, on a vessel
in waves, on a seabed with friction, and through intervals that fail and are redone in
shorter steps."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.solvers import dynamics
from test_fastcall_recorder import _joined_scene

LINE_CHANNELS = ("position", "tension", "shear_force", "bend_moment", "torque", "curvature", "end_a_force",
                 "end_b_force", "end_a_moment", "end_b_moment", "end_a_direction", "end_b_direction",
                 "seabed_force", "seabed_friction", "touchdown_position", "touchdown_arc_length")
BODY_CHANNELS = ("position", "velocity", "acceleration", "rotation", "angular_velocity", "connection_force",
                 "connection_tension", "submerged_fraction", "buoyancy", "deck_force")


def _both(data, monkeypatch):
    """(kernel-recorded results, Python-recorded results, whether the kernel recorded)."""
    used = []
    original = dynamics.Recorder.kernel_records

    def spy(self):
        out = original(self)
        used.append(out)
        return out
    monkeypatch.setattr(dynamics.Recorder, "kernel_records", spy)
    fast = rfesim.simulate(data)
    monkeypatch.setattr(dynamics.Recorder, "IN_KERNEL", False)
    slow = rfesim.simulate(data)
    return fast, slow, any(used)


def _assert_same(fast, slow, rtol=1e-13):
    np.testing.assert_array_equal(fast.time, slow.time)
    for key in ("steps", "newton_iterations", "jacobians", "rebases", "step_halvings"):
        assert fast.counters.get(key) == slow.counters.get(key), key
    for name in slow.lines:
        a, b = fast.line(name), slow.line(name)
        for ch in LINE_CHANNELS:
            x, y = np.asarray(getattr(a, ch)), np.asarray(getattr(b, ch))
            scale = max(1e-300, float(np.nanmax(np.abs(y)))) if np.isfinite(y).any() else 1.0
            np.testing.assert_allclose(x, y, rtol=0, atol=rtol * scale, err_msg=f"{name}.{ch}")
            np.testing.assert_array_equal(np.isnan(x), np.isnan(y))
        if b.drive_names:
            for ch in ("drive_angle", "drive_torque"):
                y = np.asarray(getattr(b, ch))
                np.testing.assert_allclose(getattr(a, ch), y, rtol=0, atol=rtol * float(np.abs(y).max()))
    for name in slow.bodies:
        for ch in BODY_CHANNELS:
            y = np.asarray(getattr(slow.body(name), ch))
            np.testing.assert_allclose(getattr(fast.body(name), ch), y, rtol=0,
                                       atol=rtol * max(1e-300, float(np.abs(y).max())), err_msg=f"{name}.{ch}")
    for name in slow.vessels:
        for ch in ("position", "rotation"):
            y = np.asarray(getattr(slow.vessels[name], ch))
            np.testing.assert_allclose(getattr(fast.vessels[name], ch), y, rtol=0,
                                       atol=rtol * max(1.0, float(np.abs(y).max())))


def _joined(max_iterations=20, duration=3.0):
    """The joined scene of test_fastcall_recorder (pedestal, driven boom, rope, payload) with a
    second drive (luffing) on the boom."""
    data = _joined_scene()
    data["lines"]["boom"]["end_a"]["drives"] = [
        {"name": "slewing", "axis": [0, 0, 1], "angle": [[0, 0], [2, 40]]},
        {"name": "luffing", "axis": [0, 1, 0], "angle": [[0, 0], [1, 0], [3, -15]]}]
    dynamics_settings = data["analysis"]["dynamics"]
    dynamics_settings["duration"] = duration
    dynamics_settings["integrator"]["max_iterations"] = max_iterations
    return data


def _motor():
    """_joined with a slewing motor on a turret between pedestal and boom."""
    data = _joined(duration=0.2)
    data["lines"]["boom"]["end_a"].pop("drives")
    data["lines"]["turret"] = {"type": "tube", "length": 0.5, "elements": 1,
                               "end_a": {"attach": "ped:end_b", "connection": "clamped", "direction": [0, 0, 1],
                                         "motor": {"angle": [[0, 0], [1, 10]], "max_torque": 1e7,
                                                   "stiffness": 2e8, "damping": 4e7}}}
    data["lines"]["boom"]["end_a"]["attach"] = "turret:end_b"
    return data


def test_joints_drives_and_a_payload_are_recorded_as_by_the_python_recorder(monkeypatch):
    fast, slow, used = _both(_joined(), monkeypatch)
    assert used
    _assert_same(fast, slow)
    # the channels are not trivial: both drives turn and carry moments
    torque = np.abs(np.asarray(fast.line("boom").drive_torque))
    assert torque[:, 0].max() > 1e3 and torque[:, 1].max() > 1e4
    assert np.ptp(np.asarray(fast.line("boom").drive_angle)[:, 1]) == pytest.approx(15.0, abs=1e-9)


def test_failed_intervals_are_rolled_back_and_redone_as_by_the_python_driver(monkeypatch):
    # two Newton iterations a step: some steps fail and their intervals are redone in halves
    fast, slow, used = _both(_joined(max_iterations=2, duration=1.5), monkeypatch)
    assert used
    assert slow.counters.get("step_halvings", 0) > 0
    _assert_same(fast, slow)


def test_crane_on_a_vessel_in_waves_is_recorded_as_by_the_python_recorder(monkeypatch):
    from rfesim.bench.crane import crane_data
    fast, slow, used = _both(crane_data(0.1, 6.0, 0.2), monkeypatch)
    assert used
    _assert_same(fast, slow)
    assert np.ptp(np.asarray(fast.vessels["barge"].rotation)[:, 1]) > 0.1      # the vessel pitches


def test_seabed_and_touchdown_channels_are_recorded_as_by_the_python_recorder(monkeypatch):
    from rfesim.bench.h1 import h1_scenario
    sc = h1_scenario(20, {"kind": "generalized-alpha", "time_step": 0.05}, output_interval=0.1)
    data = sc.model_dump(mode="json", exclude_none=True)
    data["analysis"]["dynamics"]["duration"] = 4.0
    fast, slow, used = _both(data, monkeypatch)
    assert used
    _assert_same(fast, slow, rtol=1e-12)
    riser = fast.line("riser")
    assert np.isfinite(riser.touchdown_arc_length).all()
    assert np.asarray(riser.seabed_force).max() > 0.0


def test_scenes_the_kernel_does_not_record_go_through_the_python_recorder(monkeypatch):
    data = _motor()
    calls = []
    original = dynamics.Recorder.record

    def spy(self, state, qdd):
        calls.append(state.t)
        return original(self, state, qdd)
    monkeypatch.setattr(dynamics.Recorder, "record", spy)
    res = rfesim.simulate(data)
    assert len(calls) == len(res.time) == 3                     # every output time, in Python


def test_end_load_scratch_is_written_before_it_is_read():
    """sde_end_loads_scratch takes scratch that is not zeroed: filled with NaN or huge values
    it gives the loads of zeroed scratch to the bit (joint rest rotations, drives, a motor)."""
    from rfesim.model.compile import compile_scenario
    from rfesim.model.outputs import _end_scratch, sde_end_loads_scratch
    from rfesim.scenario import Scenario
    from rfesim.solvers.system import System
    checked = 0
    for data in (_joined(), _motor()):
        system = System(compile_scenario(Scenario.model_validate(data)))
        state = system.model.initial.copy()
        rng = np.random.default_rng(3)
        state.q[:] += 1e-3 * rng.standard_normal(state.q.shape) * system.mask
        state.qd[:] += 1e-2 * rng.standard_normal(state.qd.shape) * system.mask
        system.evaluate(state)
        n = system.n
        for s in range(system.model.nsde):
            outs = []
            for fill in (0.0, np.nan, 1e300):
                out = np.zeros((4, 3))
                sde_end_loads_scratch(system.km, system.ws, s, np.full((n, 3), fill), np.full((n, 3), fill), out,
                                      *[np.full(a.shape, fill) for a in _end_scratch()])
                outs.append(out)
            assert np.isfinite(outs[0]).all()
            np.testing.assert_array_equal(outs[1], outs[0])
            np.testing.assert_array_equal(outs[2], outs[0])
            checked += np.abs(outs[0]).max() > 0.0
    assert checked > 20


def test_runs_free_every_array_they_allocate():
    """The evaluation chain runs without reference counting (docs/theory.md, 'Reference
    counting off in the evaluation chain'): the kernels that allocate still free all they
    allocate. numba's allocation counters (NUMBA_NRT_STATS, read in a fresh process) over a
    run with joints, drives, a payload and a slewing motor: as many frees as allocations,
    and allocations there are."""
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path
    code = (
        "import json, sys\n"
        "sys.path.insert(0, %r)\n"
        "from numba.core.runtime import rtsys\n"
        "import rfesim\n"
        "from test_kernel_recording import _joined, _motor\n"
        "rfesim.simulate(_joined(duration=0.3))\n"
        "s0 = rtsys.get_allocation_stats()\n"
        "rfesim.simulate(_joined(duration=1.0)); rfesim.simulate(_motor())\n"
        "s1 = rtsys.get_allocation_stats()\n"
        "print(json.dumps([s1.alloc - s0.alloc, s1.free - s0.free,\n"
        "                  s1.mi_alloc - s0.mi_alloc, s1.mi_free - s0.mi_free]))\n"
    ) % str(Path(__file__).parent)
    env = dict(os.environ, NUMBA_NRT_STATS="1")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    alloc, free, mi_alloc, mi_free = json.loads(out.stdout.strip().splitlines()[-1])
    assert alloc > 100
    assert free == alloc and mi_free == mi_alloc


def test_the_compiled_run_reports_progress_and_stops_when_the_callback_raises():
    """Progress comes between chunks of output intervals: increasing fractions ending at 1,
    and a callback that raises stops the run (rfesim.CancelledError) at the next chunk."""
    data = _joined(duration=2.0)
    seen = []
    rfesim.simulate(data, progress=lambda f, t: seen.append((f, t)))
    fractions = [f for f, _ in seen]
    assert len(fractions) >= 3 and fractions == sorted(fractions) and fractions[-1] == pytest.approx(1.0)
    assert all(t == pytest.approx(f * 2.0) for f, t in seen)

    calls = []

    def stop(f, t):
        calls.append(f)
        if f > 0.0:
            raise RuntimeError("stop")
    with pytest.raises(rfesim.CancelledError):
        rfesim.simulate(data, progress=stop)
    assert len(calls) == 1 and 0.0 < calls[0] < 1.0           # stopped at the first report
