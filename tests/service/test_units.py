"""Pieces of the service without a server: the data-directory guard, limits, the job
store's recovery, results as JSON, and the sweep helpers (grid, summary, touchdown)."""
from __future__ import annotations

import json
import os
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from service import validate
from service.paths import UnsafePath, check_scenario_paths, resolve_data_path
from service.settings import Settings
from service.store import QueueFull, Store
from service_helpers import SCENARIOS, riser


def test_file_references_must_stay_inside_the_data_directory(tmp_path):
    data = tmp_path / "data"
    (data / "files").mkdir(parents=True)
    (data / "files" / "motion.csv").write_text("t,heave\n")
    assert resolve_data_path("motion.csv", data) == (data / "files" / "motion.csv").resolve()
    assert resolve_data_path("sub/../motion.csv", data) == (data / "files" / "motion.csv").resolve()
    for bad in ("../jobs.sqlite", "../../etc/passwd", "/etc/passwd", "~/x", "file:///etc/passwd",
                "https://example.org/x.csv", "", "a\x00b"):
        with pytest.raises(UnsafePath):
            resolve_data_path(bad, data)
    os.symlink("/etc", data / "files" / "escape")
    with pytest.raises(UnsafePath):
        resolve_data_path("escape/passwd", data)

    crafted = riser()
    crafted["vessels"]["ship"]["motion"]["time_series_file"] = "../../outside.csv"
    crafted["lines"]["riser"]["loads"] = [{"table_path": "/etc/shadow"}]
    crafted["environment"]["files"] = ["motion.csv", "../x"]
    errors = dict(check_scenario_paths(crafted, data))
    assert set(errors) == {"vessels.ship.motion.time_series_file", "lines.riser.loads.0.table_path",
                           "environment.files.1"}
    assert all("data directory" in msg for msg in errors.values())
    assert check_scenario_paths(riser(), data) == []
    ok = riser()
    ok["vessels"]["ship"]["motion"]["time_series_file"] = "motion.csv"
    assert check_scenario_paths(ok, data) == []


def test_prepare_job_limits_and_wrapper(tmp_path):
    settings = Settings(data_dir=tmp_path, max_rfes=20, max_duration=10.0)
    scenario, sc = validate.prepare_job({"scenario": riser(), "overrides": {"lines.riser.elements": 8}}, settings, None)
    assert scenario["lines"]["riser"]["elements"] == 8 and sc.lines["riser"].elements == 8
    with pytest.raises(validate.Invalid) as err:
        validate.prepare_job(riser(**{"lines.riser.elements": 30}), settings, None)
    assert err.value.errors[0][0] == ["lines"] and "31 RFEs" in err.value.errors[0][1]
    with pytest.raises(validate.Invalid) as err:
        validate.prepare_job(riser(**{"analysis.dynamics.duration": 11.0}), settings, None)
    assert err.value.errors[0][0] == ["analysis", "dynamics", "duration"]
    with pytest.raises(validate.Invalid) as err:
        validate.prepare_job({"scenario": riser(), "extra": 1}, settings, None)
    assert err.value.errors[0][0] == ["extra"]
    with pytest.raises(validate.Invalid):
        validate.prepare_job("scenarios/cantilever_pipe.json", settings, None)     # never a file path
    small = Settings(data_dir=tmp_path, max_output_values=1000)
    with pytest.raises(validate.Invalid) as err:
        validate.prepare_job(riser(**{"analysis.dynamics.output_interval": 0.05,
                                      "analysis.dynamics.duration": 10.0}), small, None)
    assert err.value.errors[0][0] == ["analysis", "dynamics", "output_interval"]


def test_store_requeues_running_jobs_and_bounds_the_queue(tmp_path):
    store = Store(tmp_path / "jobs.sqlite")
    assert store._connect().execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    store.insert_jobs([{"id": f"job{i:04d}xx", "scenario": "{}"} for i in range(3)], max_queued=3)
    with pytest.raises(QueueFull):
        store.insert_jobs([{"id": "one-more-job", "scenario": "{}"}], max_queued=3)
    claimed = store.claim_queued(2)
    assert [c[0] for c in claimed] == ["job0000xx", "job0001xx"] and claimed[0][2] == 1
    store.request_cancel("job0001xx")
    requeued, failed = Store(tmp_path / "jobs.sqlite").requeue_running("re-queued", max_attempts=3)
    assert requeued == ["job0000xx"] and failed == []
    assert store.get("job0001xx")["status"] == "cancelled"
    assert store.get("job0000xx")["status"] == "queued"
    for _ in range(2):                      # interrupted twice more: failed, not re-queued again
        store.claim_queued(3)
        requeued, failed = store.requeue_running("re-queued", max_attempts=3)
    assert "job0000xx" in failed and "interrupted 3 times" in store.get("job0000xx")["message"]
    assert store.get("job0002xx")["status"] == "queued"
    assert store.cancel_queued("job0002xx") and store.get("job0002xx")["status"] == "cancelled"
    assert not store.cancel_queued("job0002xx")


def test_results_as_json_select_and_decimate(tmp_path):
    import rfesim
    from service.results_json import TooLarge, UnknownChannels, read_results

    res = rfesim.simulate(riser())
    path = tmp_path / "r.nc"
    res.to_netcdf(path)
    out = read_results(path, ["lines/riser/tension", "lines/riser/arc_length"], 3, 10**6)
    np.testing.assert_array_equal(out["time"], res.time[::3])
    np.testing.assert_array_equal(out["channels"]["lines/riser/tension"]["data"], res.line("riser").tension[::3])
    assert out["channels"]["lines/riser/arc_length"]["shape"] == [14]        # not along time: whole
    assert "vessels/ship/position" in read_results(path, None, 1, 10**6)["channels"]
    with pytest.raises(UnknownChannels, match="lines/riser/nope"):
        read_results(path, ["lines/riser/nope"], 1, 10**6)
    with pytest.raises(TooLarge):
        read_results(path, None, 1, 1000)
    json.dumps(out, allow_nan=False)


def test_sweep_grid_summary_and_any_executor():
    from rfesim.sweep import grid, parse_vary, run_sweep, summarize

    vary = parse_vary(["a.b=1,2.5,x", 'c=[0,0,1],[0,0,2]', 'd="q,r",true'])
    assert vary == {"a.b": [1, 2.5, "x"], "c": [[0, 0, 1], [0, 0, 2]], "d": ["q,r", True]}
    assert len(grid(vary)) == 12 and grid(vary)[1] == {"a.b": 1, "c": [0, 0, 1], "d": True}
    with pytest.raises(ValueError):
        parse_vary(["novalue"])

    import rfesim

    res = rfesim.simulate(riser())
    s = summarize(res)
    top = res.line("riser").top_tension
    assert s["max_top_tension"] == pytest.approx(top.max())
    assert s["daf"] == pytest.approx(top.max() / top[0])
    assert s["max_tension"] == pytest.approx(res.line("riser").tension.max())
    assert s["min_tension"] == pytest.approx(res.line("riser").tension.min())
    assert 0 < s["touchdown_min"] <= s["touchdown_max"] < 100
    cantilever = rfesim.simulate(rfesim.load_scenario(SCENARIOS / "cantilever_pipe.json",
                                                      overrides={"analysis.dynamics.duration": 0.05}))
    assert summarize(cantilever)["touchdown_min"] is None

    # the executor seam: anything with submit(fn, *args) -> future
    with ThreadPoolExecutor(2) as pool:
        rows = run_sweep(riser(), {"vessels.ship.motion.heave.amplitude": [0.1, 0.3]}, pool)
    assert [r["status"] for r in rows] == ["done", "done"]
    assert rows[0]["max_top_tension"] < rows[1]["max_top_tension"]
    with pytest.raises(rfesim.ScenarioError, match="load case"):
        run_sweep(riser(), {"lines.riser.elements": [0]}, pool)


def test_relative_data_files_come_from_the_data_directory_not_the_working_directory(tmp_path, monkeypatch):
    """A CSV vessel motion named relatively is read from <data_dir>/files; a file of the
    same name in the service's working directory is never read."""
    settings = Settings(data_dir=tmp_path / "data")
    files = tmp_path / "data" / "files"
    files.mkdir(parents=True)
    rows = "\n".join(f"{t},0,0,{0.1 * t},0,0,0" for t in range(6))
    (files / "motion.csv").write_text("t,surge,sway,heave,roll,pitch,yaw\n" + rows + "\n")
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    (cwd / "secret.csv").write_text("t,surge,sway,heave,roll,pitch,yaw\n" + rows + "\n")
    monkeypatch.chdir(cwd)
    scenario = riser()
    scenario["vessels"]["ship"]["motion"] = {"kind": "csv", "file": "motion.csv"}
    stored, sc = validate.prepare_job(scenario, settings, None)
    # the job reads the copy made at submit of <data_dir>/files/motion.csv
    stored_file = Path(stored["vessels"]["ship"]["motion"]["file"])
    assert stored_file.parent.parent == (tmp_path / "data" / "inputs").resolve()
    assert stored_file.read_bytes() == (files / "motion.csv").read_bytes()
    assert sc.vessels["ship"].motion.rows()[-1, 3] == pytest.approx(0.5)
    scenario["vessels"]["ship"]["motion"]["file"] = "secret.csv"
    with pytest.raises(validate.Invalid) as err:
        validate.prepare_job(scenario, settings, None)
    assert err.value.errors[0][0][:4] == ["vessels", "ship", "motion", "file"]
