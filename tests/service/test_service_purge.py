"""Purge: ``DELETE /jobs/{id}?purge=true`` removes a job that is over with its folder and the
copies of its input files (``<data>/inputs/<sha256>/<name>``) that no other job names;
``DELETE /sweeps/{id}?purge=true`` does it for every load case of a sweep. Queued and running
jobs are refused (409: cancel first), a sweep's case alone too (purge the sweep); at start
the service removes the input copies no job names (a purge interrupted midway). Before,
job folders and input copies were never removed: the disk only filled.

The service runs in this process with a fake executor that "runs" a job at once (it writes
a small results file and reports the job done), so these tests take no simulation."""
from __future__ import annotations

import copy
import math
import sqlite3
import threading
import warnings
from pathlib import Path

import pytest

from service import app as app_module
from service.app import create_app
from service.executor import JobExecutor
from service.settings import Settings
from service.store import Store
from service_helpers import riser

with warnings.catch_warnings():      # starlette's note on its httpx client, which these tests do not mind
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient


class InstantExecutor(JobExecutor):
    """Finishes a job as soon as it is handed out (a results file of a few bytes), but one
    whose scenario is named "hold", which runs until it is cancelled; hands out nothing
    while ``paused``."""

    kind = "instant"

    def __init__(self):
        self.events: list[tuple] = []
        self.woken = threading.Event()
        self.paused = False
        self.held: set[str] = set()

    def free_slots(self) -> int:
        return 0 if self.paused else 4

    def submit(self, job_id, spec, results_path) -> bool:
        self.events.append(("started", job_id, {"worker": "instant", "pid": None}))
        if spec["scenario"].get("name") == "hold":
            self.held.add(job_id)
            return True
        Path(results_path).write_bytes(b"\x89HDF" + bytes(1000))
        self.events.append(("outcome", job_id, {"status": "done", "message": "done", "summary": None,
                                                "has_results": True, "wall_time": 0.0, "progress": 1.0,
                                                "sim_time": 1.0}))
        return True

    def cancel(self, job_id) -> None:
        if job_id in self.held:
            self.held.discard(job_id)
            self.events.append(("outcome", job_id, {"status": "cancelled", "message": "cancelled", "summary": None,
                                                    "has_results": False, "wall_time": 0.0, "progress": 0.5,
                                                    "sim_time": 0.5}))

    def wait(self, timeout):
        if not self.events:
            self.woken.wait(min(timeout, 0.05))
        self.woken.clear()
        events, self.events = self.events, []
        return events

    def wake(self) -> None:
        self.woken.set()


def _motion_csv(heave: float) -> str:
    rows = [f"{t:.2f},0,0,{heave * math.sin(2 * math.pi * t / 8.0):.6f},0,0,0"
            for t in (0.1 * i for i in range(41))]
    return "t,surge,sway,heave,roll,pitch,yaw\n" + "\n".join(rows) + "\n"


def _with_motion(name: str, file: str = "motion.csv") -> dict:
    scenario = copy.deepcopy(riser())
    scenario["name"] = name
    scenario["vessels"]["ship"]["motion"] = {"kind": "csv", "file": file}
    return scenario


@pytest.fixture
def service(monkeypatch, tmp_path):
    """(client, executor, data dir) of a service with the fake executor; motion.csv and
    other.csv (another content) in its files folder."""
    data = tmp_path / "data"
    (data / "files").mkdir(parents=True)
    (data / "files" / "motion.csv").write_text(_motion_csv(1.0))
    (data / "files" / "other.csv").write_text(_motion_csv(2.0))
    executors = []

    def make_executor(settings):
        executors.append(InstantExecutor())
        return executors[-1]

    monkeypatch.setattr(app_module, "make_executor", make_executor)

    def start():
        client = TestClient(create_app(Settings(data_dir=data, workers=1, warmup=False, submit_model_check=False)))
        client.__enter__()
        return client, executors[-1]

    clients = []

    def started():
        clients.append(start())
        return clients[-1]

    yield started, data
    for client, _ in clients:
        client.__exit__(None, None, None)


def _submit(client, body, path="/jobs") -> dict:
    r = client.post(path, json=body)
    assert r.status_code == 202, r.text
    return r.json()


def _status(client, job_id: str) -> str:
    return client.get(f"/jobs/{job_id}").json()["status"]


def _wait(client, job_id: str, status: str) -> None:
    import time

    deadline = time.monotonic() + 30.0
    while _status(client, job_id) != status:
        assert time.monotonic() < deadline, client.get(f"/jobs/{job_id}").json()
        time.sleep(0.02)


def _copies(data: Path) -> list[Path]:
    return sorted(p for p in (data / "inputs").glob("*/*"))


def test_purge_removes_the_job_its_folder_and_the_input_copies_no_other_job_names(service):
    started, data = service
    client, _ = started()
    a = _submit(client, _with_motion("a"))["id"]
    b = _submit(client, _with_motion("b"))["id"]              # the same motion.csv: one shared copy
    c = _submit(client, _with_motion("c", "other.csv"))["id"]
    for j in (a, b, c):
        _wait(client, j, "done")
    shared, other = (client.get(f"/jobs/{j}/scenario").json()["vessels"]["ship"]["motion"]["file"] for j in (a, c))
    assert Path(shared).is_file() and Path(other).is_file() and len(_copies(data)) == 2
    folder = data / "jobs" / a
    size_a = sum(p.stat().st_size for p in folder.iterdir())
    assert size_a > 1000

    r = client.delete(f"/jobs/{a}", params={"purge": "true"})
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["jobs"] == [a] and out["input_copies_removed"] == 0 and out["input_copies_kept"] == 1, out
    assert out["freed_bytes"] == size_a, out
    assert out["message"].startswith(f"job {a} purged: its record, its folder and 0 input file copies removed, "
                                     f"1 kept (other jobs name them)"), out
    assert not folder.exists()
    assert client.get(f"/jobs/{a}").status_code == 404
    assert Path(shared).is_file(), "the copy job b names was removed with job a"
    assert client.delete(f"/jobs/{a}", params={"purge": "true"}).status_code == 404

    size_b = sum(p.stat().st_size for p in (data / "jobs" / b).iterdir()) + Path(shared).stat().st_size
    r = client.delete(f"/jobs/{b}", params={"purge": "true"})
    assert r.status_code == 200, r.text
    assert r.json()["input_copies_removed"] == 1 and r.json()["input_copies_kept"] == 0, r.json()
    assert r.json()["freed_bytes"] == size_b
    assert not Path(shared).exists() and not Path(shared).parent.exists()
    assert _copies(data) == [Path(other)]                      # job c's copy stays
    assert _status(client, c) == "done" and client.get(f"/jobs/{c}/results.nc").status_code == 200
    total = client.get("/jobs").json()["total"]
    assert total == 1


def test_purge_refuses_a_queued_or_running_job_and_delete_still_cancels(service):
    started, data = service
    client, executor = started()
    running = _submit(client, _with_motion("hold"))["id"]
    _wait(client, running, "running")
    executor.paused = True
    queued = _submit(client, _with_motion("q"))["id"]
    for job_id, status in ((running, "running"), (queued, "queued")):
        r = client.delete(f"/jobs/{job_id}", params={"purge": "true"})
        assert r.status_code == 409, r.text
        assert r.json()["detail"] == (f"job {job_id} is {status}: cancel it first (DELETE /jobs/{job_id}), then "
                                      f"purge it once it is over")
        assert (data / "jobs" / job_id).is_dir() and _status(client, job_id) == status
    assert client.delete("/jobs/nosuchjob123", params={"purge": "true"}).status_code == 404
    # DELETE without purge is the cancel it always was
    r = client.delete(f"/jobs/{running}")
    assert r.status_code == 202 and r.json()["status"] == "running", r.text
    _wait(client, running, "cancelled")
    r = client.delete(f"/jobs/{queued}", params={"purge": "false"})
    assert r.status_code == 202 and r.json()["status"] == "cancelled", r.text
    r = client.delete(f"/jobs/{queued}")
    assert r.status_code == 409 and r.json()["detail"] == f"job {queued} is already cancelled: nothing to cancel"
    # over now: purged (both named the same copy: removed with the second)
    assert client.delete(f"/jobs/{running}", params={"purge": "true"}).json()["input_copies_kept"] == 1
    r = client.delete(f"/jobs/{queued}", params={"purge": "true"})
    assert r.status_code == 200 and r.json()["input_copies_removed"] == 1, r.text
    assert _copies(data) == [] and not (data / "jobs" / running).exists() and not (data / "jobs" / queued).exists()


def test_a_sweep_is_purged_whole_and_its_cases_not_alone(service):
    started, data = service
    client, executor = started()
    single = _submit(client, _with_motion("single"))["id"]
    _wait(client, single, "done")
    sweep = _submit(client, {"scenario": _with_motion("sweep"),
                             "vary": {"vessels.ship.motion.interpolation": ["cubic", "linear"]}}, "/sweeps")
    cases = sweep["jobs"]
    for j in cases:
        _wait(client, j, "done")
    r = client.delete(f"/jobs/{cases[1]}", params={"purge": "true"})
    assert r.status_code == 409, r.text
    assert r.json()["detail"] == (f"job {cases[1]} is load case 1 of sweep {sweep['id']}: purge the whole sweep "
                                  f"(DELETE /sweeps/{sweep['id']}?purge=true)")
    # a sweep with a case still running is refused
    executor.paused = True
    busy = _submit(client, {"scenario": _with_motion("hold"),
                            "vary": {"vessels.ship.motion.interpolation": ["cubic", "linear"]}}, "/sweeps")
    r = client.delete(f"/sweeps/{busy['id']}", params={"purge": "true"})
    assert r.status_code == 409, r.text
    assert r.json()["detail"] == (f"sweep {busy['id']} has 2 of 2 load cases queued or running: cancel it first "
                                  f"(DELETE /sweeps/{busy['id']}), then purge it once they are over")
    assert client.delete(f"/sweeps/{busy['id']}").status_code == 202            # the cancel it always was
    r = client.delete(f"/sweeps/{busy['id']}", params={"purge": "true"})
    assert r.status_code == 200 and r.json()["jobs"] == busy["jobs"], r.text

    r = client.delete(f"/sweeps/{sweep['id']}", params={"purge": "true"})
    assert r.status_code == 200, r.text
    out = r.json()
    assert out["jobs"] == cases and out["input_copies_removed"] == 0 and out["input_copies_kept"] == 1, out
    assert out["message"].startswith(f"sweep {sweep['id']} purged: its record, 2 load cases and "), out
    assert client.get(f"/sweeps/{sweep['id']}").status_code == 404
    assert all(client.get(f"/jobs/{j}").status_code == 404 and not (data / "jobs" / j).exists() for j in cases)
    assert client.get("/sweeps").json()["total"] == 0
    # the copy the single job names stays
    stored = client.get(f"/jobs/{single}/scenario").json()["vessels"]["ship"]["motion"]["file"]
    assert Path(stored).is_file() and _copies(data) == [Path(stored)]


def test_the_start_removes_input_copies_no_job_names(service):
    started, data = service
    client, _ = started()
    kept = _submit(client, _with_motion("kept"))["id"]
    gone = _submit(client, _with_motion("gone", "other.csv"))["id"]
    for j in (kept, gone):
        _wait(client, j, "done")
    kept_copy, gone_copy = (Path(client.get(f"/jobs/{j}/scenario").json()["vessels"]["ship"]["motion"]["file"])
                            for j in (kept, gone))
    client.__exit__(None, None, None)
    # a purge interrupted after the job's folder and record: its input copy is left
    con = sqlite3.connect(data / "jobs.sqlite")
    with con:
        assert con.execute("DELETE FROM jobs WHERE id=?", (gone,)).rowcount == 1
    con.close()
    stray = kept_copy.parent / ".motion.csv.0123456789ab.tmp"          # a copy being written at a stop
    stray.write_text("partial")
    client, _ = started()
    assert not gone_copy.exists() and not gone_copy.parent.exists() and not stray.exists()
    assert kept_copy.is_file() and _copies(data) == [kept_copy]
    assert client.get(f"/jobs/{kept}").json()["status"] == "done"


def test_a_copy_reference_is_the_whole_name(tmp_path):
    """A copy ``m.csv`` is not taken as named by a scenario naming ``m.csv2`` of the same content."""
    from service.paths import copy_reference

    store = Store(tmp_path / "jobs.sqlite")
    digest = "ab" * 32
    store.insert_jobs([{"id": "job-00000001", "scenario": f'{{"file":"/x/inputs/{digest}/m.csv2"}}'}])
    assert not store.names(copy_reference(tmp_path / "inputs" / digest / "m.csv"))
    assert store.names(copy_reference(tmp_path / "elsewhere" / "inputs" / digest / "m.csv2"))
    store.close()
