"""A run its progress callback cancels (the HTTP service's cancel) keeps the results it
computed: `rfesim.CancelledError.results` holds every output recorded up to the last output
step (status 3, "cancelled at t = ... s"), bit for bit the uninterrupted run's, in every
formulation: absolute-coordinate lines (run_dynamics), scenes of chains and classical /
modified / planar lines (rfesim.formulations.scene) and chains mixed with lines
(rfesim.formulations.mixed); the service's worker writes them for the cancelled job. A few
seconds each."""
from __future__ import annotations

import copy
import dataclasses

import numpy as np
import pytest

import rfesim
import scenes
from rfesim.solvers.dynamics import CANCELLED, INTERRUPTED


# the tiny riser (absolute coordinates), 3 s of dynamics
RISER = copy.deepcopy(scenes.RISER)
RISER["analysis"]["dynamics"]["duration"] = 3.0
_pendulum, _line, _mixed = scenes.pendulum, scenes.cantilever_line, scenes.mixed_rope


class Stop(Exception):
    """What the test's progress callback raises (the service raises its own)."""


class _CancelAt:
    """A progress callback that raises once the run passes ``t``."""

    def __init__(self, t):
        self.t = t
        self.calls = 0

    def __call__(self, fraction, t):
        self.calls += 1
        if t >= self.t:
            raise Stop("stop, please")


def _cancelled(sc, at, reached=True) -> rfesim.CancelledError:
    """The CancelledError of ``sc`` cancelled once its progress passed ``at``; ``reached``: the
    results go at least that far (one unit: progress times are simulated times)."""
    cb = _CancelAt(at)
    with pytest.raises(rfesim.CancelledError) as info:
        rfesim.simulate(sc, progress=cb)
    exc = info.value
    assert isinstance(exc.__cause__, Stop) and str(exc).endswith(": stop, please")
    res = exc.results
    assert res is not None and res.status == CANCELLED == 3 and res.kind == "dynamics"
    assert res.scenario_json and res.version == rfesim.__version__
    assert exc.time == float(res.time[-1])
    assert res.time[-1] >= at or not reached
    assert str(exc).startswith(f"cancelled at t = {res.time[-1]:.6g} s")
    return exc


GROUPS = ("lines", "vessels", "bodies", "supports", "tensioners", "reels", "winches", "tuggers", "joints")


def _same_prefix(part, full) -> int:
    """Every channel of the partial results is the full run's at the same output times, bit
    for bit; returns the number of time-dependent arrays compared."""
    n, nt = len(part.time), len(full.time)
    assert 1 < n < nt
    np.testing.assert_array_equal(part.time, full.time[:n])
    compared = 0
    for group in GROUPS:
        a, b = getattr(part, group), getattr(full, group)
        assert set(a) == set(b), group
        for name, obj in a.items():
            for f in dataclasses.fields(obj):
                x, y = getattr(obj, f.name), getattr(b[name], f.name)
                if not isinstance(y, np.ndarray):
                    continue
                if y.ndim and y.shape[0] == nt:            # a channel over time
                    assert x.shape == (n, *y.shape[1:]), (group, name, f.name)
                    np.testing.assert_array_equal(x, y[:n], err_msg=f"{group}.{name}.{f.name}")
                    compared += 1
                else:
                    np.testing.assert_array_equal(x, y, err_msg=f"{group}.{name}.{f.name}")
    assert compared > 0
    return compared


def _moves(values) -> bool:
    """The channel is not constant over the kept span (the comparison means something)."""
    values = np.asarray(values)
    return bool(np.nanmax(np.abs(values - values[:1])) > 0.0)


def test_cancelled_absolute_lines_keep_the_results_up_to_the_cancel():
    full = rfesim.simulate(RISER)
    exc = _cancelled(RISER, 1.0)
    res = exc.results
    # the compiled run reports after chunks of output intervals: the cancel comes at the end
    # of the chunk that passed t = 1 s, its outputs recorded
    assert 1.0 <= res.time[-1] < 3.0
    assert res.message == f"cancelled at t = {res.time[-1]:.6g} s"
    assert res.counters["statics_iterations"] >= 1 and res.counters["steps"] == round(res.time[-1] / 0.05)
    _same_prefix(res, full)
    assert _moves(res.line("riser").tension) and _moves(res.vessel("ship").position)


@pytest.mark.parametrize("kind", ["rk4", "adaptive"])
def test_cancelled_chain_keeps_the_results_up_to_the_cancel(kind):
    sc = _pendulum(kind)
    res = _cancelled(sc, 0.5).results
    # the fixed step reports after recording an output, DOP853 after its dense outputs up to
    # the end of its step: both stop with the 0.5 s output recorded
    np.testing.assert_allclose(res.time, np.arange(6) * 0.1, atol=1e-12)
    assert res.message == "cancelled at t = 0.5 s"
    _same_prefix(res, rfesim.simulate(sc))
    assert _moves(res.joints["pendulum.top"].coordinate)


@pytest.mark.parametrize("formulation, kind", [("planar", "rk4"), ("planar", "generalized-alpha"),
                                               ("modified", "rk4")])
def test_cancelled_line_of_another_formulation_keeps_the_results_up_to_the_cancel(formulation, kind):
    sc = _line(formulation, kind)
    res = _cancelled(sc, 0.1).results
    assert 0.1 - 1e-12 <= res.time[-1] < 0.2
    assert res.message == f"cancelled at t = {res.time[-1]:.6g} s"
    _same_prefix(res, rfesim.simulate(sc))
    assert _moves(res.line("beam").bend_moment)


def test_cancelled_units_keep_the_span_all_reached():
    # two chains integrated one after the other; progress runs over both: t >= 0.85 of the
    # 1 s run stops the second chain at 0.7 s, the first having finished
    sc = _pendulum(chains=("first", "second"))
    # (the progress time of a scene of units is the fraction of all their work x the duration)
    exc = _cancelled(sc, 0.85, reached=False)
    res = exc.results
    np.testing.assert_allclose(res.time, np.arange(8) * 0.1, atol=1e-12)
    assert res.message.startswith("cancelled at t = 0.7 s; the units are integrated one after another and "
                                  "chains.second had reached t = 0.7 s")
    _same_prefix(res, rfesim.simulate(sc))


def test_cancelled_mixed_scene_keeps_the_results_up_to_the_cancel():
    sc = _mixed()
    res = _cancelled(sc, 0.1).results
    np.testing.assert_allclose(res.time, [0.0, 0.05, 0.1], atol=1e-12)
    assert res.message == "cancelled at t = 0.1 s"
    assert res.counters["steps"] == 10 and res.counters["statics_iterations"] >= 1
    _same_prefix(res, rfesim.simulate(sc))
    assert _moves(res.line("rope").tension)


def test_ctrl_c_from_the_callback_is_still_an_interruption():
    # a KeyboardInterrupt is not a cancel: status 2, the KeyboardInterrupt itself
    def ctrl_c(fraction, t):
        if t >= 0.5:
            raise KeyboardInterrupt

    for sc in (_pendulum(), RISER):
        with pytest.raises(KeyboardInterrupt) as info:
            rfesim.simulate(sc, progress=ctrl_c)
        assert info.value.results.status == INTERRUPTED
        assert info.value.results.message.startswith("interrupted at t = ")


def test_the_service_worker_keeps_a_cancelled_runs_results(tmp_path):
    # service.worker.execute, as a worker process runs a job: the callback raises Cancelled
    # (the "cancel" read from the pipe); the outcome keeps the results (results.nc)
    pytest.importorskip("h5netcdf")
    from rfesim.sweep import summarize
    from service.worker import Cancelled, execute

    def progress(fraction, t):
        if t >= 1.0:
            raise Cancelled("cancelled")

    path = tmp_path / "results.nc"
    out = execute({"id": "job", "scenario": RISER}, progress, path)
    assert out["status"] == "cancelled" and out["has_results"] is True, out
    kept = rfesim.open_results(path)
    t_end = float(kept.time[-1])
    assert out["sim_time"] == t_end and 1.0 <= t_end < 3.0
    assert out["message"] == f"cancelled while running at t = {t_end:.6g} s; the results up to t = {t_end:.6g} s " \
                             f"are kept"
    summary = dict(out["summary"])
    assert summary.pop("top_tension_at") == "riser end B"      # the job summary names where, as rfesim sweep
    assert summary == summarize(kept) and summary["max_top_tension"] > 0.0
    assert kept.status == CANCELLED and kept.message == f"cancelled at t = {t_end:.6g} s"
    _same_prefix(kept, rfesim.simulate(RISER))
