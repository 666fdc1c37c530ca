"""Output recording without re-evaluation (rfesim.solvers.dynamics.Recorder,
rfesim.solvers.fastcall.FastCall): the recorder reuses the workspace a converged
generalised-alpha step left (ws.step_state) and calls its output kernels through cached
entry points. Both must give exactly the results of the plain path."""
from __future__ import annotations

import numpy as np
import pytest
from numba import njit

import rfesim
from rfesim.solvers.fastcall import FastCall


@njit(cache=True)
def _axpy(a, x, y, out):
    for i in range(x.shape[0]):
        out[i] = a * x[i] + y[i]
    return out.sum()


def test_fastcall_equals_the_kernel_and_retypes_on_other_arguments():
    f = FastCall(_axpy)
    x, y, out = np.arange(5.0), np.ones(5), np.zeros(5)
    assert f(2.0, x, y, out) == _axpy(2.0, x, y, np.zeros(5))
    first = f._entry
    assert first is not None
    assert f(3.0, x, y, out) == pytest.approx(3.0 * 10.0 + 5.0)
    assert f._entry is first                                  # same types: the cached entry point
    xs = np.arange(10.0)[::2]                                 # a strided view: another signature
    assert f(1.0, xs, y, out) == pytest.approx(xs.sum() + 5.0)
    assert f._entry is not first
    xi = np.arange(5)                                         # integers: another signature again
    assert f(1.0, xi, y, out) == pytest.approx(10.0 + 5.0)


def _joined_scene():
    """A pedestal with a driven boom and a rope with a payload (joins, drives, a body)."""
    tube = {"EA": 2e10, "EIy": 5e9, "GJ": 4e9, "mass_per_length": 400.0}
    return {"environment": {"gravity": 9.81},
            "line_types": {"tube": tube, "rope": {"EA": 5e7, "EIy": 300.0, "mass_per_length": 5.0,
                                                  "tension_only": True}},
            "bodies": {"load": {"mass": 2000.0, "radius_of_gyration": 0.8}},
            "lines": {
                "ped": {"type": "tube", "length": 10.0, "elements": 5,
                        "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, 1],
                                  "connection": "clamped"}},
                "boom": {"type": "tube", "length": 15.0, "elements": 8,
                         "end_a": {"attach": "ped:end_b", "connection": "clamped", "direction": [1, 0, 1],
                                   "drives": [{"name": "slewing", "axis": [0, 0, 1],
                                               "angle": [[0, 0], [2, 20]]}]}},
                "rope": {"type": "rope", "length": 8.0, "elements": 8,
                         "end_a": {"attach": "boom:end_b", "connection": "pinned", "direction": [0, 0, -1]},
                         "end_b": {"attach": "load", "position": [0, 0, 0.5]}}},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"duration": 3.0, "output_interval": 0.1,
                                      "integrator": {"kind": "generalized-alpha", "time_step": 0.02}}}}


def test_recording_from_the_step_equals_recording_after_a_new_evaluation(monkeypatch):
    from rfesim.solvers import dynamics
    # the Python recorder (the compiled run's recording is compared with it in test_kernel_recording.py)
    monkeypatch.setattr(dynamics.Recorder, "IN_KERNEL", False)
    fast = rfesim.simulate(_joined_scene())
    original = dynamics.Recorder.record

    def always_evaluate(self, state, qdd):
        self.system.ws.step_state[0] = 0            # forget the step's evaluation: evaluate again
        return original(self, state, qdd)
    monkeypatch.setattr(dynamics.Recorder, "record", always_evaluate)
    slow = rfesim.simulate(_joined_scene())
    for name in ("ped", "boom", "rope"):
        a, b = fast.line(name), slow.line(name)
        for ch in ("position", "tension", "bend_moment", "end_a_force", "end_b_force", "end_a_moment"):
            x, y = np.asarray(getattr(a, ch)), np.asarray(getattr(b, ch))
            # equal to the round-off of the stiff joints (the step's state is re-based before the
            # new evaluation: 1e-16 in the poses times 1e12 N/m); a workspace left at another
            # state (a Jacobian's perturbation of 1e-8) would be off by kN
            np.testing.assert_allclose(x, y, rtol=0, atol=1e-6 * max(1.0, float(np.abs(y).max())))
    for x, y in ((fast.line("boom").drive_torque, slow.line("boom").drive_torque),
                 (fast.body("load").connection_force, slow.body("load").connection_force)):
        np.testing.assert_allclose(x, y, rtol=0, atol=1e-6 * float(np.abs(y).max()))
    assert np.abs(np.asarray(fast.line("boom").drive_torque)).max() > 1e4      # the channels are not trivial


def test_fastcall_keeps_its_entry_for_a_new_tuple_of_the_same_types():
    """A state copied at every step brings a new Reference tuple each time: the same entry
    point serves it (no typing again); a tuple whose member types differ is typed anew."""
    from rfesim.model.arrays import Reference

    class Counting:                 # the dispatcher, counting the calls that go through it
        def __init__(self, kernel):
            self.kernel, self.calls = kernel, 0

        def __call__(self, *args):
            self.calls += 1
            return self.kernel(*args)

        def __getattr__(self, name):
            return getattr(self.kernel, name)

    f = FastCall(Counting(_sum_ref))
    ref = Reference(np.ones((2, 3, 3)), np.ones((2, 3)))
    assert f(ref) == 24.0
    for k in range(3):
        copy = Reference(ref.R.copy() * k, ref.X.copy())
        assert f(copy) == pytest.approx(18.0 * k + 6.0)
    assert f.kernel.calls == 1                    # typed once: the copies took the entry point
    other = Reference(np.ones((2, 3, 3), np.float32), np.ones((2, 3)))
    assert f(other) == pytest.approx(24.0)
    assert f.kernel.calls == 2


@njit(cache=True)
def _sum_ref(ref):
    return ref.R.sum() + ref.X.sum()
