"""Ctrl-C (KeyboardInterrupt) keeps the results so far in every formulation, not only for
scenes of absolute-coordinate lines: chains and classical / modified / planar lines
(rfesim.formulations.scene, fixed-step and adaptive), and chains mixed with lines
(rfesim.formulations.mixed); `rfesim run` writes them (status 2). A few seconds each."""
from __future__ import annotations

import json
import signal

import numpy as np
import pytest

import rfesim
import scenes
from rfesim.cli import main



class _InterruptAt:
    """A progress callback that presses Ctrl-C (or sends SIGTERM, which `rfesim run` turns
    into the same KeyboardInterrupt) once the run passes ``t``."""

    def __init__(self, t, sigterm=False):
        self.t = t
        self.sigterm = sigterm
        self.times = []

    def __call__(self, fraction, t):
        self.times.append(t)
        if t >= self.t:
            if self.sigterm:
                signal.raise_signal(signal.SIGTERM)
            raise KeyboardInterrupt

    def close(self):
        pass


_pendulum, _mixed = scenes.pendulum, scenes.mixed_rope


def _planar(kind):
    return scenes.cantilever_line("planar", kind)


def _interrupted(sc, at, **kw):
    with pytest.raises(KeyboardInterrupt) as info:
        rfesim.simulate(sc, progress=_InterruptAt(at, **kw))
    return info.value


def _same_prefix(part, full):
    """Every channel of the partial results equals the full run's at the same output times."""
    n = len(part.time)
    np.testing.assert_array_equal(part.time, full.time[:n])
    assert set(part.lines) == set(full.lines) and set(part.joints) == set(full.joints)
    for name, lr in part.lines.items():
        for ch in ("position", "tension", "shear_force", "bend_moment", "end_a_force"):
            a = getattr(lr, ch)
            assert a.shape[0] == n, (name, ch)
            np.testing.assert_allclose(a, getattr(full.lines[name], ch)[:n], rtol=1e-12, atol=1e-9)
    for name, jr in part.joints.items():
        assert jr.coordinate.shape[0] == n
        np.testing.assert_allclose(jr.coordinate, full.joints[name].coordinate[:n], rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("kind", ["rk4", "adaptive"])
def test_interrupted_chain_keeps_the_results_so_far(kind):
    sc = _pendulum(kind)
    exc = _interrupted(sc, 0.5)
    res = exc.results
    assert res is not None and res.status == 2 and res.kind == "dynamics"
    # outputs every 0.1 s; the callback stopped the run once it had passed t = 0.5 s, with
    # that output recorded (the fixed step reports after recording, DOP853 after its dense
    # outputs up to the end of its step)
    np.testing.assert_allclose(res.time, np.arange(6) * 0.1, atol=1e-12)
    assert res.message == f"interrupted at t = {res.time[-1]:.6g} s"
    assert res.scenario_json and res.version == rfesim.__version__
    _same_prefix(res, rfesim.simulate(sc))
    if kind == "rk4":
        assert res.counters["steps"] == 250 and res.counters["time_step"] == 0.002


@pytest.mark.parametrize("kind", ["rk4", "generalized-alpha", "adaptive"])
def test_interrupted_planar_line_keeps_the_results_so_far(kind):
    sc = _planar(kind)
    exc = _interrupted(sc, 0.1)
    res = exc.results
    assert res is not None and res.status == 2
    # the compiled RK4 reports after stretches of whole outputs (a hundredth of the run, at
    # least one output), generalized-alpha after every output: both stop at the 0.1 s output;
    # DOP853 after each of its steps, its outputs up to the step's end recorded
    if kind == "adaptive":
        assert 0.1 - 1e-12 <= res.time[-1] < 0.2 and res.time[0] == 0.0
    else:
        np.testing.assert_allclose(res.time, np.arange(11) * 0.01, atol=1e-12)
    assert res.message.startswith(f"interrupted at t = {res.time[-1]:.6g} s")
    assert res.line("beam").tension.shape == (len(res.time), 10)
    _same_prefix(res, rfesim.simulate(sc))


def test_interrupted_mixed_scene_keeps_the_results_so_far():
    sc = _mixed()
    exc = _interrupted(sc, 0.1)
    res = exc.results
    assert res is not None and res.status == 2
    np.testing.assert_allclose(res.time, [0.0, 0.05, 0.1], atol=1e-12)
    assert res.message == f"interrupted at t = {res.time[-1]:.6g} s"
    assert res.counters["steps"] == 10 and res.counters["statics_iterations"] >= 1
    assert res.scenario_json and res.version == rfesim.__version__
    _same_prefix(res, rfesim.simulate(sc))


def test_interrupted_units_keep_the_span_all_reached():
    # two chains, integrated one after the other; progress runs over both (0.5 = half of the
    # first), so t >= 0.25 of the 1 s run stops the first chain at 0.5 s, the second not started
    sc = _pendulum(chains=("first", "second"))
    full = rfesim.simulate(sc)
    res = _interrupted(sc, 0.25).results
    assert res.status == 2 and list(res.time) == [0.0]
    assert res.message.startswith("interrupted at t = 0 s") and "chains.second had not started" in res.message
    assert "further: chains.first t = 0.5 s" in res.message
    # the unit not started holds its start state with the accelerations of the run: its
    # t = 0 outputs are the full run's (the link forces carry m (a - g): released from rest
    # 0.3 rad off, the upper link's root shear is 0.83 N, 5.80 N = 2 m g sin 0.3 at rest)
    _same_prefix(res, full)
    assert res.line("second.upper").shear_force[0, 0] == pytest.approx(0.8283, abs=1e-4)
    # stopped in the second chain at 0.7 s (fraction 0.85 of the whole): both reached 0.7 s
    res = _interrupted(sc, 0.85).results
    np.testing.assert_allclose(res.time, np.arange(8) * 0.1, atol=1e-12)
    assert res.message.startswith("interrupted at t = 0.7 s; the units are integrated one after another and "
                                  "chains.second had reached t = 0.7 s")
    assert res.message.endswith("(further: chains.first t = 1 s)")
    _same_prefix(res, full)


def test_interrupt_before_any_output_carries_no_results(monkeypatch):
    # Ctrl-C in the first evaluation of the first unit, before its t = 0 output: nothing to
    # keep (results None, as for a scene of lines); one in the second unit keeps t = 0
    from rfesim.formulations import chain

    sc = _pendulum(chains=("first", "second"))
    calls = {"n": 0}
    real = chain.accelerations

    def accelerations(*args):
        calls["n"] += 1
        if calls["n"] == calls["stop"]:
            raise KeyboardInterrupt
        return real(*args)

    monkeypatch.setattr(chain, "accelerations", accelerations)
    calls.update(n=0, stop=1)
    with pytest.raises(KeyboardInterrupt) as info:
        rfesim.simulate(sc)
    assert getattr(info.value, "results", None) is None
    calls.update(n=0, stop=4 * 500 + 2)      # the first chain's 500 steps, then the second's first evaluation
    with pytest.raises(KeyboardInterrupt) as info:
        rfesim.simulate(sc)
    res = info.value.results
    assert res.status == 2 and list(res.time) == [0.0] and "chains.second had not started" in res.message


@pytest.mark.parametrize("how", ["ctrl-c", "sigterm"])
def test_run_interrupted_chain_writes_the_results_so_far(tmp_path, monkeypatch, capsys, how):
    import rfesim.cli as cli

    path = tmp_path / "pendulum.json"
    path.write_text(json.dumps(_pendulum()), encoding="utf-8")
    monkeypatch.setattr(cli, "_progress_bar", lambda args: _InterruptAt(0.5, sigterm=how == "sigterm"))
    out = tmp_path / "interrupted.nc"
    assert main(["run", str(path), "-o", str(out)]) == 130
    err = capsys.readouterr().err
    assert "interrupted at t = 0.5 s" in err and "partial results (6 output times" in err and str(out) in err
    res = rfesim.open_results(out)
    assert res.status == 2 and res.message == "interrupted at t = 0.5 s"
    np.testing.assert_allclose(res.time, np.arange(6) * 0.1, atol=1e-12)
    assert res.line("pendulum.lower").position.shape[0] == 6
    assert res.joints["pendulum.top"].coordinate.shape[0] == 6
    assert res.joints["pendulum.top"].coordinate[0, 0] == pytest.approx(0.3)


def test_planar_newton_failure_keeps_the_results_so_far(monkeypatch):
    # a planar line whose generalized-alpha Newton fails part way raises a SolverError with
    # the outputs before it (status 1), as a chain that diverges; it used to carry nothing
    from rfesim.formulations import planar

    sc = _planar("generalized-alpha")
    full = rfesim.simulate(sc)
    calls = {"n": 0}
    real = planar._newton_correction

    def correction(*args):
        calls["n"] += 1
        dqdd, dmu = real(*args)
        if calls["n"] > full.counters["steps"] // 2:      # within the first half of the run: NaN increments
            dqdd = dqdd * np.nan
        return dqdd, dmu

    monkeypatch.setattr(planar, "_newton_correction", correction)
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(sc)
    part = info.value.results
    assert part is not None and part.status == 1
    assert "lines.beam" in str(info.value) and "Newton did not converge" in str(info.value)
    assert 1 < len(part.time) < len(full.time)
    _same_prefix(part, full)
