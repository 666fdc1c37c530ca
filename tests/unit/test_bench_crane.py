"""The column-crane benchmark's scene (rfesim.bench.crane) and report (rfesim.bench.run_crane)."""
from __future__ import annotations

import rfesim
from rfesim.bench.crane import DEPTH_OF_PAYLOAD, crane_data
from rfesim.bench.run_crane import report
from rfesim.model.compile import compile_scenario


def test_bench_scene_has_about_100_rfes_and_the_payload_under_water():
    sc = rfesim.Scenario.model_validate(crane_data(duration=10.0))
    model = compile_scenario(sc)
    assert model.km.rfe_length.shape[0] == 101          # 13 + 41 + 46 RFEs and the payload
    body = sc.bodies["crane_payload"]
    assert abs(body.position[2] + DEPTH_OF_PAYLOAD) < 1e-9      # its centre, at the start
    assert not sc.winches                                          # the crane holds the payload still


def _run(dt, wall, tmax):
    return {"time_step": dt, "duration": 1800.0, "output_interval": 0.2, "rfes": 101, "wall_time": wall,
            "statics_wall_time": 1.0, "real_time_factor": 1800.0 / wall, "steps": int(1800 / dt), "step_halvings": 0,
            "newton_iterations": 3 * int(1800 / dt), "jacobians": 10, "static_tension": 6e4, "max_tension": tmax}


def test_report_says_met_or_missed():
    runs = {"production": _run(0.1, 8.0, 100.5e3), "half step": _run(0.05, 16.0, 100.1e3),
            "reference": _run(0.025, 32.0, 100.0e3)}
    b = {"runs": runs, "quick": False, "error": 0.005, "reference_error": 0.001, "load_average": [1, 1, 1]}
    text = report(b)
    assert "225x faster than real time (target >= 200x: met)" in text
    assert "0.500 % (target < 1 %: met)" in text
    runs["production"] = _run(0.1, 100.0, 103e3)
    text = report(dict(b, error=0.03))
    assert "18x faster than real time (target >= 200x: missed)" in text and "target < 1 %: missed" in text
