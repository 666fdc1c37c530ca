"""Output times of a run (rfesim.solvers.dynamics.output_schedule): the run covers the whole
duration, outputs land on their times, and result sets too large for the machine are
refused before anything is allocated."""
from __future__ import annotations

import copy
import logging
import math

import pytest

import rfesim
from rfesim.solvers.dynamics import output_schedule

CANTILEVER = {
    "name": "schedule cantilever",
    "environment": {"gravity": 9.81},
    "line_types": {"beam": {"EA": 1.0e8, "EIy": 1.0e5, "mass_per_length": 50.0}},
    "lines": {"pipe": {"type": "beam", "length": 10.0, "elements": 10,
                       "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0],
                                 "connection": "clamped"},
                       "end_b": {"attach": "free"}}},
    "analysis": {"statics": {"enabled": True},
                 "dynamics": {"duration": 2.0,
                              "integrator": {"kind": "generalized-alpha", "time_step": 0.01}}},
}


def scenario(**dynamics) -> dict:
    data = copy.deepcopy(CANTILEVER)
    data["analysis"]["dynamics"].update(dynamics)
    return data


@pytest.mark.parametrize("T, h, interval, expect_n, expect_dt, expect_h", [
    (60.0, 0.05, None, 1200, 0.05, 0.05),         # every step
    (10800.0, 0.1, 0.1, 108000, 0.1, 0.1),        # a quotient within rounding of a whole number
    (2.0, 5.0, None, 1, 2.0, 2.0),                # a step longer than the duration becomes it
    (0.1, 0.01, 0.03, 4, 0.03, 0.01),             # the run goes on to the next output time, 0.12 s
    (1000.0, 0.03, None, 8334, 1000.0 / 8334, 1000.0 / 8334 / 4),   # every 4th step: < 10000 outputs
    (5.0, 0.02, 0.05, 100, 0.05, 0.05 / 3),       # the step is shortened to divide the interval
])
def test_schedule(T, h, interval, expect_n, expect_dt, expect_h):
    out_dt, n_out, step = output_schedule(T, h, interval)
    assert n_out == expect_n
    assert out_dt == pytest.approx(expect_dt, rel=1e-12)
    assert step == pytest.approx(expect_h, rel=1e-12)
    assert step <= h * (1 + 1e-12) or h > T            # shortened, never lengthened
    assert n_out * out_dt >= T * (1 - 1e-12)           # the whole duration is covered
    assert math.isclose(out_dt / step, round(out_dt / step), rel_tol=1e-9)


def test_default_interval_ends_on_the_duration():
    # an RK4 step that does not divide the duration: the outputs still end on it exactly
    h = 9.5e-5
    out_dt, n_out, step = output_schedule(0.01, h, None)
    assert n_out * out_dt == pytest.approx(0.01, rel=1e-14)
    assert step <= h


def test_partial_last_interval_is_run_and_reported(caplog):
    with caplog.at_level(logging.WARNING, logger="rfesim"):
        res = rfesim.simulate(rfesim.load_scenario(scenario(duration=0.1, output_interval=0.03)))
    assert res.time[-1] == pytest.approx(0.12, rel=1e-12)
    assert len(res.time) == 5
    assert "not a whole number of output intervals" in caplog.text and "t = 0.12 s" in caplog.text
    # and the results keep it (a service client or a script sees no log): once, in the message
    assert res.message.count("; dynamics warning: analysis.dynamics.duration (0.1 s) is not a whole number of "
                             "output intervals (0.03 s): the run goes on to the next output time, t = 0.12 s") == 1
    whole = rfesim.simulate(rfesim.load_scenario(scenario(duration=0.12, output_interval=0.03)))
    assert "dynamics warning" not in whole.message


def test_step_longer_than_the_duration_runs_one_step():
    data = scenario(duration=2.0)
    data["analysis"]["dynamics"]["integrator"]["time_step"] = 5.0
    res = rfesim.simulate(rfesim.load_scenario(data))
    assert res.time[-1] == pytest.approx(2.0, rel=1e-12)
    assert res.counters["steps"] >= 1
    assert res.counters["time_step"] == pytest.approx(2.0)


def test_too_many_output_times_is_a_field_error(monkeypatch):
    # 1e7 output times pass the scenario's count (rfesim.scenario.load.MAX_OUTPUTS) and are
    # refused before allocation on a machine of 1 GiB, the count written in short
    from rfesim.solvers import dynamics
    monkeypatch.setattr(dynamics, "_memory_bytes", lambda: float(2**30))
    with pytest.raises(rfesim.ScenarioError) as err:
        rfesim.simulate(rfesim.load_scenario(scenario(duration=10.0, output_interval=1e-6)))
    reason = dict(err.value.errors)["analysis.dynamics.output_interval"]
    assert reason.startswith("1e+07 output times would store about") and "machine's memory (1 GiB)" in reason


def test_output_times_beyond_the_count_are_refused_by_the_scenario():
    with pytest.raises(rfesim.ScenarioError) as err:
        rfesim.load_scenario(scenario(duration=1000.0, output_interval=1e-6))
    reason = dict(err.value.errors)["analysis.dynamics.output_interval"]
    assert reason.startswith("1e-06 s stores 1e+09 output times over the duration 1000 s, more than the 100,000,000")
