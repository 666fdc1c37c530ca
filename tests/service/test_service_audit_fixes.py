"""Defects found by an audit of the service, one test (or a few) each: the Dask cancel flag
after a restart, the output-size and RFE limits (output interval shorter than the step,
kinematic chains), every result group in JSON, the streamed JSON answer, 500s on client
input (huge integers, non-text vary keys), event streams at a clean stop, overlapping
varied paths and HEAD /health."""
from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from pathlib import Path

import httpx
import pytest

from service import results_json, validate
from service.settings import Settings
from service_helpers import SCENARIOS, Api, long_job, riser

HUGE = "1" * 5000          # an integer literal beyond Python's 4300-digit conversion cap


def chain_scenario(elements: int, rigid: bool = True) -> dict:
    """A crane-like kinematic chain: a rigid pedestal (optional) and three flexible boom
    sections of ``elements`` elements each, no lines."""
    links: dict = {}
    joints: dict = {}
    prev = "base"
    if rigid:
        links["pedestal"] = {"rigid": True, "length": 5.0, "mass": 2.0e4}
        joints["slew"] = {"kind": "revolute", "parent": "base", "child": "pedestal", "direction": [0, 0, 1],
                          "axis": [0, 0, 1]}
        prev = "pedestal"
    for i in range(3):
        links[f"b{i}"] = {"type": "boom", "length": 30.0, "elements": elements, "formulation": "modified"}
        joints[f"j{i}"] = {"kind": "revolute", "parent": prev, "child": f"b{i}", "axis": [0, 1, 0],
                           "direction": [1, 0, 0]}
        prev = f"b{i}"
    return {"schema_version": 1, "name": "chain", "environment": {"gravity": 9.81},
            "line_types": {"boom": {"outer_diameter": 1.0, "wall_thickness": 0.025, "youngs_modulus": 2.07e11,
                                    "density": 7850.0}},
            "chains": {"crane": {"base": "fixed", "position": [0, 0, 0], "links": links, "joints": joints}},
            "analysis": {"statics": {"enabled": False},
                         "dynamics": {"duration": 2.0e-4, "output_interval": 1.0e-4,
                                      "integrator": {"kind": "rk4", "time_step": 1.0e-4}}}}


# --------------------------------------------------------------------------- limits (items 2, 3)

def test_output_limit_counts_outputs_as_the_driver_schedules_them(tmp_path):
    """An output interval shorter than the time step keeps the interval (the driver shortens
    the step): 10 s at 0.01 s are 1001 output times, not 201."""
    import rfesim

    short = rfesim.load_scenario(riser(**{"analysis.dynamics.output_interval": 0.01,
                                          "analysis.dynamics.integrator.time_step": 0.05}))
    assert validate.output_times(short) == len(rfesim.simulate(short).time) == 101
    settings = Settings(data_dir=tmp_path, max_output_values=5000)
    body = riser(**{"analysis.dynamics.duration": 10.0, "analysis.dynamics.output_interval": 0.01,
                    "analysis.dynamics.integrator.time_step": 0.05})
    with pytest.raises(validate.Invalid) as err:
        validate.prepare_job(body, settings, None)
    loc, msg = err.value.errors[0]
    assert loc == ["analysis", "dynamics", "output_interval"]
    assert "1001 output times x 13 RFEs" in msg


def test_rfe_and_output_limits_count_kinematic_chains(tmp_path):
    import rfesim

    small = chain_scenario(3)
    sc = rfesim.load_scenario(small)
    assert not sc.lines
    total, groups = validate.rfe_count(sc)
    assert total == groups["chains"] == 3 * 4 + 2        # 3 flexible links of 3 elements, 1 rigid link
    # the count is what the results hold: every chain link is output as a line
    res = rfesim.simulate(sc)
    assert total == sum(line.seabed_force.shape[1] for line in res.lines.values())

    settings = Settings(data_dir=tmp_path, max_rfes=100)
    with pytest.raises(validate.Invalid) as err:
        validate.prepare_job(chain_scenario(40), settings, None)      # 3 x 41 + 2 = 125 RFEs
    loc, msg = err.value.errors[0]
    assert loc == ["chains"] and "125 RFEs" in msg and "RFESIM_MAX_RFES" in msg

    settings = Settings(data_dir=tmp_path, max_output_values=1000)
    with pytest.raises(validate.Invalid) as err:
        validate.prepare_job(chain_scenario(120), settings, None)     # 3 output times x 365 RFEs
    assert err.value.errors[0][0] == ["analysis", "dynamics", "output_interval"]
    assert "3 output times x 365 RFEs" in err.value.errors[0][1]


def test_post_a_chain_scenario_over_the_rfe_limit_is_422_naming_chains(api):
    r = api.client.post("/jobs", json=chain_scenario(10000))           # 3 x 10001 + 2 = 30005 RFEs > 20000
    assert r.status_code == 422, r.text
    (entry,) = r.json()["detail"]
    assert entry["loc"] == ["chains"] and "30005 RFEs" in entry["msg"]


# --------------------------------------------------------------------------- results (items 4, 5)

@pytest.fixture(scope="module")
def short_results(tmp_path_factory) -> dict[str, Path]:
    """Results files of bundled scenarios with lay equipment and cranes, 0.2 s long."""
    import rfesim

    folder = tmp_path_factory.mktemp("results")
    out = {}
    for name in ("s_lay", "reel_lay", "column_crane_liftoff"):
        sc = rfesim.load_scenario(SCENARIOS / f"{name}.json", overrides={"analysis.dynamics.duration": 0.2,
                                                                         "analysis.dynamics.output_interval": 0.1})
        path = folder / f"{name}.nc"
        rfesim.simulate(sc).to_netcdf(path)
        out[name] = path
    return out


def test_results_json_has_every_group_of_the_file(short_results):
    import h5py

    seen = set()
    for name, path in short_results.items():
        with h5py.File(path, "r") as f:
            groups = {g for g in f if isinstance(f[g], h5py.Group)}
        out = results_json.read_results(path, None, 1, 10**7)
        assert {c.split("/")[0] for c in out["channels"]} == groups, name
        seen |= groups
    assert {"supports", "tensioners", "reels", "winches", "tuggers", "bodies"} <= seen
    crane = results_json.read_results(short_results["column_crane_liftoff"],
                                      ["winches/crane_winch/tension", "tuggers/crane_fore/tension"], 1, 10**6)
    assert crane["channels"]["winches/crane_winch/tension"]["units"] == "N"
    assert crane["channels"]["winches/crane_winch/tension"]["shape"] == [3]
    s_lay = results_json.read_results(short_results["s_lay"], ["supports/stinger/roller_reaction"], 2, 10**6)
    assert s_lay["channels"]["supports/stinger/roller_reaction"]["dims"][0] == "time"
    assert s_lay["channels"]["supports/stinger/roller_reaction"]["shape"][0] == 2        # 3 times, every 2nd
    reel = results_json.read_results(short_results["reel_lay"], None, 1, 10**7)["channels"]
    assert "reels/lay_reel/payout" in reel and "tensioners/lay_tensioner/grip_force" in reel


def test_streamed_answer_is_exactly_the_documented_json(short_results, monkeypatch):
    """Streamed a few values at a time, the answer is byte for byte json.dumps (compact) of
    the whole answer: the format did not change."""
    import h5py
    import numpy as np

    head = {"id": "abc", "status": "done", "message": "finished"}
    for path in short_results.values():
        for every in (1, 2):
            plan = results_json.plan_results(path, None, every, 10**7)
            whole = b"".join(results_json.stream_results(plan, head))
            monkeypatch.setattr(results_json, "BLOCK_VALUES", 5)       # many blocks per channel
            pieces = list(results_json.stream_results(plan, head))
            monkeypatch.undo()
            assert b"".join(pieces) == whole
            answer = json.loads(whole)
            assert list(answer) == ["id", "status", "message", "time", "every", "channels"]
            # the same as building the answer from the file directly
            with h5py.File(path, "r") as f:
                expected = {}
                for name, ds in results_json.channel_index(f).items():
                    decimate = results_json._dims(ds)[:1] == ["time"]
                    data = ds[::every] if decimate else ds[()]
                    expected[name] = {"units": results_json._text(ds.attrs["units"]),
                                      "long_name": results_json._text(ds.attrs.get("long_name", "")),
                                      "dims": results_json._dims(ds), "shape": list(np.shape(data)),
                                      "data": results_json.to_list(data)}
                time_ = results_json.to_list(f["lines"][next(iter(f["lines"]))]["time"][::every])
            reference = {**head, "time": time_, "every": every, "channels": expected}
            assert whole == json.dumps(reference, separators=(",", ":"), allow_nan=False).encode()


def test_results_of_winches_over_http_and_still_413_when_too_large(api):
    job = api.submit({"scenario": "column_crane", "overrides": {"analysis.dynamics.duration": 0.2,
                                                                "analysis.dynamics.output_interval": 0.1}})
    assert api.wait(job)["status"] == "done"
    r = api.client.get(f"/jobs/{job}/results", params={"channels": "winches/crane_winch/tension"})
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["id"] == job and body["status"] == "done" and len(body["time"]) == 3
    assert body["channels"]["winches/crane_winch/tension"]["shape"] == [3]
    r = api.client.get(f"/jobs/{job}/results", params={"channels": "winches/crane_winch/nope"})
    assert r.status_code == 422 and "winches/crane_winch/tension" in r.text


# --------------------------------------------------------------------------- client input (item 6)

def test_huge_integer_literals_are_a_clean_error(api, tmp_path):
    for content_type, body in (("application/json", f'{{"name": {HUGE}}}'),
                               ("application/yaml", f"name: {HUGE}\n")):
        for route in ("/jobs", "/sweeps"):
            r = api.client.post(route, content=body, headers={"Content-Type": content_type})
            assert r.status_code == 422, (route, content_type, r.text)
            (entry,) = r.json()["detail"]
            assert entry["loc"] == ["body"] and "more than 4300 digits" in entry["msg"]
    # the library and `rfesim check` say the same
    for suffix, text in ((".json", f'{{"name": {HUGE}}}'), (".yaml", f"name: {HUGE}\n")):
        path = tmp_path / f"huge{suffix}"
        path.write_text(text)
        run = subprocess.run([sys.executable, "-m", "rfesim.cli", "check", str(path)], capture_output=True,
                             text=True, timeout=120)
        assert run.returncode == 1, run.stderr
        assert "more than 4300 digits" in run.stderr and "Traceback" not in run.stderr


def test_non_text_vary_keys_are_422_naming_them(api):
    for key in ("1", "~", "2.5"):
        body = f"scenario: cantilever_pipe\nvary:\n  {key}: [0.1, 0.2]\n"
        r = api.client.post("/sweeps", content=body, headers={"Content-Type": "application/yaml"})
        assert r.status_code == 422, (key, r.text)
        (entry,) = r.json()["detail"]
        assert entry["loc"][0] == "vary" and "dotted scenario path" in entry["msg"]


# --------------------------------------------------------------------------- overlapping vary paths (item 8)

def test_grid_refuses_a_varied_path_inside_another():
    import rfesim
    from rfesim.sweep import grid

    with pytest.raises(rfesim.ScenarioError) as err:
        grid({"analysis.dynamics.duration": [1, 2], "analysis.dynamics": [{"duration": 3}]})
    ((field, reason),) = err.value.errors
    assert field == "analysis.dynamics.duration" and "'analysis.dynamics'" in reason
    # parts, not characters: lines.riser and lines.riser2 are different objects
    assert len(grid({"lines.riser.elements": [1, 2], "lines.riser2.elements": [3]})) == 2


def test_post_sweep_with_overlapping_paths_is_422(api):
    r = api.client.post("/sweeps", json={"scenario": "cantilever_pipe", "vary": {
        "analysis.dynamics.duration": [0.1, 0.2], "analysis.dynamics": [{"duration": 0.3}]}})
    assert r.status_code == 422, r.text
    (entry,) = r.json()["detail"]
    assert entry["loc"] == ["vary", "analysis.dynamics.duration"] and "'analysis.dynamics'" in entry["msg"]


def test_rfesim_sweep_with_overlapping_paths_is_a_clear_error(tmp_path):
    args = [sys.executable, "-m", "rfesim.cli", "sweep", str(SCENARIOS / "cantilever_pipe.json"),
            "--vary", "analysis.dynamics.duration=0.1,0.2", "--vary", 'analysis.dynamics={"duration":0.3}']
    run = subprocess.run(args, capture_output=True, text=True, timeout=120, cwd=tmp_path)
    unknown = subprocess.run(args[:5] + ["--vary", "nope.x=1"], capture_output=True, text=True, timeout=120,
                             cwd=tmp_path)
    assert run.returncode == unknown.returncode == 1, run.stderr
    assert "analysis.dynamics.duration" in run.stderr and "'analysis.dynamics'" in run.stderr
    assert "Traceback" not in run.stderr


# --------------------------------------------------------------------------- HEAD /health (item 9)

def test_head_health(api):
    r = api.client.head("/health")
    assert r.status_code == 200 and r.content == b""


# --------------------------------------------------------------------------- event streams at a stop (item 7)

def test_a_clean_stop_ends_open_event_streams_with_end(make_server):
    server = make_server(env={"RFESIM_WORKERS": "1"})
    api = Api(server)
    job = api.submit(long_job(600.0))
    api.wait_running(job)
    lines: list[str] = []
    got_progress = threading.Event()

    def follow():
        with httpx.stream("GET", f"{server.url}/jobs/{job}/events", timeout=60) as s:
            for line in s.iter_lines():
                lines.append(line)
                if line.startswith("event: progress"):
                    got_progress.set()

    reader = threading.Thread(target=follow, daemon=True)
    reader.start()
    assert got_progress.wait(30), lines
    api.close()
    server.stop()
    reader.join(30)
    assert not reader.is_alive()
    ends = [i for i, line in enumerate(lines) if line == "event: end"]
    assert ends, lines
    end = json.loads(lines[ends[0] + 1].removeprefix("data: "))
    assert end["id"] == job and end["status"] == "running"           # not over: it runs again after a restart
    log = server.read_log()
    # the stream did not hold the stop until uvicorn gave up and cancelled it
    assert "timeout graceful shutdown exceeded" not in log and "CancelledError" not in log, log[-3000:]


# --------------------------------------------------------------------------- Dask cancel flag (item 1)

def test_dask_job_stopped_with_the_service_is_not_cancelled_after_the_restart(tmp_path):
    """A clean stop sets the cancel flag of the running job on the scheduler, which outlives
    the service; the job handed out again after the restart must run, not be cancelled."""
    distributed = pytest.importorskip("distributed")
    from rfesim.sweep import worker_environment
    from service.executor import DaskExecutor

    def outcome_of(executor, job_id, timeout=180.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for event in executor.wait(1.0):
                if event[0] == "outcome" and event[1] == job_id:
                    return event[2]
        raise AssertionError(f"no outcome for {job_id} within {timeout} s")

    with worker_environment():
        cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=True, host="127.0.0.1",
                                           dashboard_address=None)
    try:
        job_id = "stopped-with-the-service"
        first = DaskExecutor(cluster.scheduler_address, progress_interval=0.2)
        first.start()
        first.submit(job_id, {"scenario": riser(**{"analysis.dynamics.duration": 600.0})}, tmp_path / "a.nc")
        deadline = time.monotonic() + 120
        while not any(e[0] == "progress" and e[1] == job_id for e in first.wait(0.5)):
            assert time.monotonic() < deadline, "the job did not start running on Dask"
        first.shutdown()                         # a clean stop: cancels the running job

        second = DaskExecutor(cluster.scheduler_address, progress_interval=0.2)     # the restarted service
        second.start()
        try:
            second.submit(job_id, {"scenario": riser()}, tmp_path / "b.nc")
            out = outcome_of(second, job_id)
        finally:
            second.shutdown()
        assert out["status"] == "done", out
        assert (tmp_path / "b.nc").is_file()
    finally:
        cluster.close()


# --------------------------------------------------------------------------- misspelled entry names in vary / overrides

def test_misspelled_entry_in_vary_or_overrides_is_422_naming_the_path(api):
    # vessels.fpsoo (the vessel is fpso) used to be accepted: every case ran the unchanged
    # offset while the sweep table showed the varied values
    bad = "vessels.fpsoo.position"
    r = api.client.post("/sweeps", json={"scenario": "catenary_riser", "vary": {bad: [[0, 0, 0], [20, 0, 0]]}})
    assert r.status_code == 422, r.text
    (entry,) = r.json()["detail"]
    assert bad in ".".join(map(str, entry["loc"])) and "did you mean 'vessels.fpso'?" in entry["msg"]
    r = api.client.post("/jobs", json={"scenario": "catenary_riser", "overrides": {bad: [20, 0, 0]}})
    assert r.status_code == 422, r.text
    (entry,) = r.json()["detail"]
    assert bad in ".".join(map(str, entry["loc"])) and "did you mean 'vessels.fpso'?" in entry["msg"]
    # the right name is accepted
    r = api.client.post("/sweeps", json={"scenario": "catenary_riser",
                                         "vary": {"vessels.fpso.position": [[0, 0, 0], [20, 0, 0]]},
                                         "overrides": {"analysis.dynamics.enabled": False}})
    assert r.status_code == 202, r.text
