"""Defects of the service found by an audit: the sweep CSV rounded every number to 6
significant digits, partial results files of killed workers stayed in the job folders for
ever, a queued job read its data files when it ran (not as they were at submit), repeated
`channels` kept only the last, and smaller ones (a path overridden and varied, cancelling
statics, top_tension_at)."""
from __future__ import annotations

import contextlib
import copy
import csv
import functools
import io
import os
import signal
import time
import types
import warnings
from pathlib import Path

import slow_write_worker
from service import executor as executor_module
from service.app import create_app
from service.settings import Settings
from service_helpers import alive, long_job, riser

with warnings.catch_warnings():      # starlette's note on its httpx client, which these tests do not mind
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient


def _wait_sweep(client, sweep_id: str, timeout: float = 120.0) -> dict:
    deadline = time.monotonic() + timeout
    while True:
        r = client.get(f"/sweeps/{sweep_id}")
        assert r.status_code == 200, r.text
        if r.json()["status"] not in ("queued", "running"):
            return r.json()
        assert time.monotonic() < deadline, r.json()
        time.sleep(0.1)


# --------------------------------------------------------------------------- 1. the sweep CSV

def test_the_sweep_csv_has_the_numbers_of_the_json_table_in_full_precision(api):
    amplitudes = [0.2000001, 0.2000004]
    r = api.client.post("/sweeps", json={"scenario": riser(),
                                         "vary": {"vessels.ship.motion.heave.amplitude": amplitudes}})
    assert r.status_code == 202, r.text
    table = _wait_sweep(api.client, r.json()["id"])
    assert table["status"] == "done", table
    r = api.client.get(f"/sweeps/{table['id']}/table.csv")
    assert r.status_code == 200, r.text
    header, *rows = list(csv.reader(io.StringIO(r.text)))
    assert header == table["columns"] and len(rows) == 2
    # the two load cases: told apart (6 digits made both 0.2)
    assert [row[1] for row in rows] == ["0.2000001", "0.2000004"]
    numbers = 0
    for row, answer in zip(rows, table["rows"]):
        for cell, column in zip(row, header):
            value = answer[column]
            if isinstance(value, float):
                assert float(cell) == value, (column, cell, value)     # read back exactly
                numbers += 1
    assert numbers >= 12


# --------------------------------------------------------------------------- 2. stray partial results files

@contextlib.contextmanager
def _hang_write_service(monkeypatch, tmp_path, **settings):
    """A service with one local worker that writes a partial results file (1 MB) and hangs."""
    monkeypatch.setattr(executor_module, "worker_module", types.SimpleNamespace(
        process_main=functools.partial(slow_write_worker.process_main, delay=3600.0, partial=1 << 20)))
    app = create_app(Settings(data_dir=tmp_path / "data", workers=1, warmup=False, cancel_grace=0.5,
                              submit_model_check=False, **settings))
    with TestClient(app) as client:
        yield client


def _poll(client, job_id: str, predicate, timeout: float = 120.0) -> dict:
    deadline = time.monotonic() + timeout
    while True:
        job = client.get(f"/jobs/{job_id}").json()
        if predicate(job):
            return job
        assert time.monotonic() < deadline, job
        time.sleep(0.05)


def _over(job: dict) -> bool:
    return job["status"] in ("done", "failed", "cancelled")


def _partial_files(folder) -> list[str]:
    return sorted(p.name for p in folder.glob(".*.tmp"))


def test_the_partial_file_of_a_worker_killed_while_writing_is_removed(monkeypatch, tmp_path):
    with _hang_write_service(monkeypatch, tmp_path) as client:
        r = client.post("/jobs", json=riser())
        assert r.status_code == 202, r.text
        job_id = r.json()["id"]
        folder = tmp_path / "data" / "jobs" / job_id
        job = _poll(client, job_id, lambda j: _over(j) or "writing the results" in j["message"])
        assert job["status"] == "running", job
        deadline = time.monotonic() + 10.0
        while not _partial_files(folder) and time.monotonic() < deadline:
            time.sleep(0.02)
        assert len(_partial_files(folder)) == 1
        os.kill(job["worker_pid"], signal.SIGKILL)
        job = _poll(client, job_id, _over)
        assert job["status"] == "failed" and "was killed by SIGKILL" in job["message"], job
        assert _partial_files(folder) == [] and not (folder / "results.nc").exists()


def test_the_partial_file_of_a_write_killed_after_the_write_grace_is_removed(monkeypatch, tmp_path):
    with _hang_write_service(monkeypatch, tmp_path, cancel_write_grace=1.0) as client:
        r = client.post("/jobs", json=long_job())
        assert r.status_code == 202, r.text
        job_id = r.json()["id"]
        folder = tmp_path / "data" / "jobs" / job_id
        job = _poll(client, job_id, lambda j: _over(j) or (j["simulated_time"] or 0.0) >= 0.2)
        assert job["status"] == "running", job
        assert client.delete(f"/jobs/{job_id}").status_code == 202
        job = _poll(client, job_id, lambda j: _over(j) or j["message"].startswith("cancel requested: writing"))
        assert job["status"] == "running", job
        pid = job["worker_pid"]
        assert len(_partial_files(folder)) == 1
        job = _poll(client, job_id, _over, timeout=30.0)
        assert job["status"] == "cancelled" and "the results are lost" in job["message"], job
        assert not alive(pid)
        assert _partial_files(folder) == []


def test_at_start_the_partial_files_of_every_job_folder_are_removed(tmp_path):
    settings = Settings(data_dir=tmp_path / "data", workers=1, warmup=False, submit_model_check=False)
    with TestClient(create_app(settings)) as client:
        r = client.post("/jobs", json=riser())
        assert r.status_code == 202, r.text
        job_id = r.json()["id"]
        assert _poll(client, job_id, _over)["status"] == "done"
    folder = tmp_path / "data" / "jobs" / job_id
    results = (folder / "results.nc").read_bytes()
    # what a worker killed while the service stopped (a done job rerun, a cancelled one) leaves
    (folder / ".results.nc.0123456789ab.tmp").write_bytes(b"\x89HDF" + bytes(1000))
    other = tmp_path / "data" / "jobs" / "a-job-that-was-cancelled"
    other.mkdir()
    (other / ".results.nc.ba9876543210.tmp").write_bytes(b"\x89HDF")
    with TestClient(create_app(settings)) as client:
        assert client.get(f"/jobs/{job_id}").json()["status"] == "done"
        assert client.get(f"/jobs/{job_id}/results.nc").content == results
    assert _partial_files(folder) == [] and (folder / "results.nc").read_bytes() == results
    assert os.listdir(other) == []


# --------------------------------------------------------------------------- 3. data files as submitted

def _motion_csv(heave: float) -> str:
    """A heave of ``heave`` m amplitude, period 8 s, for 0-4 s: t, surge, sway, heave, roll, pitch, yaw."""
    import math

    rows = [f"{t:.2f},0,0,{heave * math.sin(2 * math.pi * t / 8.0):.6f},0,0,0"
            for t in (0.1 * i for i in range(41))]
    return "t,surge,sway,heave,roll,pitch,yaw\n" + "\n".join(rows) + "\n"


def test_a_queued_job_runs_on_the_data_files_as_they_were_at_submit(tmp_path):
    data = tmp_path / "data"
    (data / "files").mkdir(parents=True)
    motion = data / "files" / "motion.csv"
    original, replaced = _motion_csv(3.0), _motion_csv(9.0)
    motion.write_text(original)
    scenario = copy.deepcopy(riser())
    scenario["vessels"]["ship"]["motion"] = {"kind": "csv", "file": "motion.csv"}
    settings = Settings(data_dir=data, workers=1, warmup=False, submit_model_check=False, cancel_grace=30.0)
    with TestClient(create_app(settings)) as client:
        def submit(path: str, body) -> dict:
            r = client.post(path, json=body)
            assert r.status_code == 202, r.text
            return r.json()

        first = _poll(client, submit("/jobs", scenario)["id"], _over)
        assert first["status"] == "done", first
        # the one worker busy: the next ones wait in the queue while the file is replaced
        busy = submit("/jobs", long_job())["id"]
        _poll(client, busy, lambda j: _over(j) or (j["simulated_time"] or 0.0) > 0.0)
        queued = submit("/jobs", scenario)["id"]
        sweep = submit("/sweeps", {"scenario": scenario,
                                   "vary": {"vessels.ship.motion.interpolation": ["cubic", "linear"]}})
        assert client.get(f"/jobs/{queued}").json()["status"] == "queued"
        motion.write_text(replaced)                     # in place: same file, new content
        after = submit("/jobs", scenario)["id"]
        assert client.delete(f"/jobs/{busy}").status_code == 202
        jobs = {k: _poll(client, j, _over) for k, j in
                [("queued", queued), ("after", after), ("cubic", sweep["jobs"][0]), ("linear", sweep["jobs"][1])]}
        assert all(j["status"] == "done" for j in jobs.values()), jobs
        # what was submitted before the replacement runs on the file as it was then
        assert jobs["queued"]["summary"] == first["summary"]
        assert jobs["cubic"]["summary"] == first["summary"]
        # ... and the replacement does change the results of a job submitted after it
        assert jobs["after"]["summary"]["max_top_tension"] != first["summary"]["max_top_tension"]
        # the stored scenario names the file the job read: a copy, as submitted
        stored = client.get(f"/jobs/{queued}/scenario").json()["vessels"]["ship"]["motion"]["file"]
        assert stored.startswith(str(data.resolve() / "inputs")) and stored.endswith("/motion.csv")
        assert open(stored).read() == original
        stored = client.get(f"/jobs/{after}/scenario").json()["vessels"]["ship"]["motion"]["file"]
        assert open(stored).read() == replaced
        # and can be posted again as it is (the path guard accepts the copies)
        again = _poll(client, submit("/jobs", client.get(f"/jobs/{queued}/scenario").json())["id"], _over)
        assert again["summary"] == first["summary"]
    # one copy per content, however many jobs and load cases name it
    assert sorted(p.name for p in (data / "inputs").glob("*/*")) == ["motion.csv", "motion.csv"]


# --------------------------------------------------------------------------- 4. repeated channels

def test_channels_may_be_repeated_comma_separated_or_both(api):
    job = api.wait(api.submit(riser()))
    assert job["status"] == "done", job
    url = f"/jobs/{job['id']}/results"
    a, b, c = "lines/riser/position", "lines/riser/tension", "lines/riser/bend_moment"
    r = api.client.get(url, params={"channels": [a, b], "every": 5})      # ?channels=a&channels=b
    assert r.status_code == 200, r.text
    assert list(r.json()["channels"]) == [a, b]
    r = api.client.get(url, params={"channels": [f"{a},{b}", c], "every": 5})
    assert r.status_code == 200, r.text
    assert list(r.json()["channels"]) == [a, b, c]
    assert list(api.client.get(url, params={"channels": f"{b},{a}"}).json()["channels"]) == [b, a]
    # an unknown one among repeated ones: named
    r = api.client.get(url, params={"channels": [a, "lines/riser/nope"]})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["query", "channels"]
    assert "lines/riser/nope" in r.json()["detail"][0]["msg"]
    r = api.client.get(url, params={"channels": ["x" * 2500, "y" * 2500]})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["query", "channels"], r.text


# --------------------------------------------------------------------------- 5a. a path overridden and varied

def test_a_path_both_overridden_and_varied_is_refused(tmp_path):
    from service import validate

    settings = Settings(data_dir=tmp_path / "data")
    path = "vessels.ship.motion.heave.amplitude"
    body = {"scenario": riser(), "overrides": {path: 0.1, "analysis.dynamics.duration": 0.5},
            "vary": {path: [0.2, 0.4]}}
    try:
        validate.prepare_sweep(body, settings, None)
    except validate.Invalid as exc:
        errors = exc.errors
    else:
        raise AssertionError("the sweep was accepted: the varied values replace the override")
    assert errors == [(["vary", path], f"would replace the override '{path}' in every load case: vary '{path}' "
                                       f"itself, or leave it out of the overrides")]
    # an override inside a varied path is lost the same way
    body = {"scenario": riser(), "overrides": {"vessels.ship.motion.heave.period": 6.0},
            "vary": {"vessels.ship.motion.heave": [{"amplitude": 0.2, "period": 8.0}]}}
    try:
        validate.prepare_sweep(body, settings, None)
    except validate.Invalid as exc:
        assert exc.errors[0][0] == ["vary", "vessels.ship.motion.heave"]
        assert exc.errors[0][1].startswith("would replace the override 'vessels.ship.motion.heave.period'")
    else:
        raise AssertionError("accepted")
    # a varied path inside an overridden one is a combination: accepted
    body = {"scenario": riser(), "overrides": {"vessels.ship.motion.heave": {"amplitude": 0.1, "period": 6.0}},
            "vary": {"vessels.ship.motion.heave.amplitude": [0.2, 0.4]}}
    _, cases, _ = validate.prepare_sweep(body, settings, None)
    assert [c["vessels"]["ship"]["motion"]["heave"] for _, c in cases] == [
        {"amplitude": 0.2, "period": 6.0}, {"amplitude": 0.4, "period": 6.0}]


def test_the_refusal_of_an_overridden_and_varied_path_is_a_422(api):
    path = "vessels.ship.motion.heave.amplitude"
    r = api.client.post("/sweeps", json={"scenario": riser(), "overrides": {path: 0.1}, "vary": {path: [0.2]}})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["vary", path], r.text


# --------------------------------------------------------------------------- 5b. a sweep larger than the queue

def test_a_sweep_larger_than_the_queue_is_a_422_as_the_docs_say(tmp_path):
    from service import validate

    settings = Settings(data_dir=tmp_path / "data", max_queued_jobs=2)
    body = {"scenario": riser(), "vary": {"vessels.ship.motion.heave.amplitude": [0.1, 0.2, 0.3]}}
    try:
        validate.prepare_sweep(body, settings, None)
    except validate.Invalid as exc:
        assert exc.errors == [(["vary"], "3 load cases; this service takes at most 2 at once "
                                         "(RFESIM_MAX_QUEUED_JOBS)")]
    else:
        raise AssertionError("accepted")
    docs = (Path(__file__).resolve().parents[2] / "docs" / "service.md").read_text()
    (row,) = [line for line in docs.splitlines() if line.startswith("| `RFESIM_MAX_QUEUED_JOBS`")]
    assert "a sweep of more load cases than this at all is a 422 naming `vary`" in row


# --------------------------------------------------------------------------- 5c. cancelling a statics-only job

def test_a_statics_only_job_cancelled_while_solving_ends_cancelled_with_the_static_solution(tmp_path):
    settings = Settings(data_dir=tmp_path / "data", workers=1, warmup=False, submit_model_check=False,
                        cancel_grace=60.0)
    # statics of 10 000 elements: a few seconds without a progress call (no load steps)
    body = {"scenario": "catenary_riser", "overrides": {"lines.riser.elements": 10000,
                                                        "analysis.dynamics.duration": 0}}
    with TestClient(create_app(settings)) as client:
        r = client.post("/jobs", json=body)
        assert r.status_code == 202, r.text
        job_id = r.json()["id"]
        job = _poll(client, job_id, lambda j: _over(j) or j["worker_pid"] is not None)
        assert job["status"] == "running", job
        time.sleep(0.3)
        r = client.delete(f"/jobs/{job_id}")
        assert r.status_code == 202 and r.json()["status"] == "running", r.text
        assert r.json()["message"] == (
            "cancel requested: the run has no output step before its end (statics only): it stops when statics "
            "ends and keeps the static solution (sooner, without results, at a load step of a stepped statics, "
            "or when its worker is killed after 60 s, RFESIM_CANCEL_GRACE)")
        job = _poll(client, job_id, _over)
        assert job["status"] == "cancelled", job
        assert job["message"] == ("cancelled during statics (a run with no output step before its end); the "
                                  "static solution is kept")
        assert job["has_results"] and job["summary"]["max_top_tension"] > 0, job
        assert client.get(f"/jobs/{job_id}/results.nc").status_code == 200


# --------------------------------------------------------------------------- 5d. top_tension_at

def test_job_summary_and_sweep_table_say_where_the_max_top_tension_is(api):
    job = api.wait(api.submit(riser()))
    assert job["status"] == "done", job
    # the riser's end B is on the ship: its top tension (rfesim sweep's table says the same)
    assert job["summary"]["top_tension_at"] == "riser end B"
    assert isinstance(job["summary"]["max_top_tension"], float)
    r = api.client.post("/sweeps", json={"scenario": riser(), "vary": {"vessels.ship.motion.heave.amplitude": [0.2]}})
    assert r.status_code == 202, r.text
    table = _wait_sweep(api.client, r.json()["id"])
    columns = table["columns"]
    assert columns[columns.index("daf") + 1] == "top_tension_at"
    assert table["rows"][0]["top_tension_at"] == "riser end B"
    header, row = list(csv.reader(io.StringIO(api.client.get(f"/sweeps/{table['id']}/table.csv").text)))
    assert row[header.index("top_tension_at")] == "riser end B"
