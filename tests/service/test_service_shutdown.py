"""A clean stop of the service (SIGTERM -> the app's lifespan -> JobManager.stop) keeps the
results of a run that is over and being written: its worker finishes the write (at most
RFESIM_SHUTDOWN_WRITE_GRACE s) and the job is recorded done with them. Before, every worker
had 3 s and nothing it reported during the stop was read: the job was re-queued and its
complete results computed again from the start after the restart. Jobs still computing are
re-queued as before; a job cancelled just before the stop ends cancelled with its results.

The service runs in this process (the app with its lifespan, under a test client; leaving the
client runs the lifespan's stop); its local workers come from ``slow_write_worker``, which
slows the writing of a job's ``results.nc`` by a given time."""
from __future__ import annotations

import contextlib
import functools
import time
import types
import warnings

import pytest
from pydantic import ValidationError

import rfesim
import slow_write_worker
from service import executor as executor_module
from service.app import create_app
from service.executor import DaskExecutor
from service.settings import Settings
from service.store import Store
from service_helpers import alive, long_job, riser

with warnings.catch_warnings():      # starlette's note on its httpx client, which these tests do not mind
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

REQUEUED = "re-queued: the service stopped while it was running"


@contextlib.contextmanager
def service(monkeypatch, tmp_path, delay: float, workers: int = 1, **settings):
    """A service whose local workers take ``delay`` s more to write a results file; yields
    (client, stop) where ``stop()`` stops the service and returns how long the stop took."""
    monkeypatch.setattr(executor_module, "worker_module",
                        types.SimpleNamespace(process_main=functools.partial(slow_write_worker.process_main,
                                                                             delay=delay)))
    app = create_app(Settings(data_dir=tmp_path / "data", workers=workers, warmup=False,
                              submit_model_check=False, **settings))
    client = TestClient(app)
    client.__enter__()
    took = {}

    def stop() -> float:
        t0 = time.monotonic()
        client.__exit__(None, None, None)
        took["s"] = time.monotonic() - t0
        return took["s"]

    try:
        yield client, stop
    finally:
        if "s" not in took:
            stop()


def _job(client, job_id: str) -> dict:
    r = client.get(f"/jobs/{job_id}")
    assert r.status_code == 200, r.text
    return r.json()


def _wait(client, job_id: str, predicate, timeout: float = 120.0) -> dict:
    deadline = time.monotonic() + timeout
    while True:
        job = _job(client, job_id)
        if predicate(job):
            return job
        if time.monotonic() > deadline:
            raise AssertionError(f"job {job_id} after {timeout} s: {job}")
        time.sleep(0.05)


def _submit(client, body) -> str:
    r = client.post("/jobs", json=body)
    assert r.status_code == 202, r.text
    return r.json()["id"]


def _stored(tmp_path, job_id: str) -> dict:
    store = Store(tmp_path / "data" / "jobs.sqlite")
    try:
        return store.get(job_id)
    finally:
        store.close()


def test_a_run_writing_its_results_at_the_stop_is_recorded_done_and_a_computing_one_is_requeued(monkeypatch,
                                                                                                   tmp_path):
    delay = 4.0          # longer than the 3 s every worker had at the stop
    with service(monkeypatch, tmp_path, delay, workers=2, shutdown_write_grace=30.0) as (client, stop):
        computing = _submit(client, long_job())
        _wait(client, computing, lambda j: j["status"] != "queued" and (j["simulated_time"] or 0.0) > 0.1)
        writing = _submit(client, riser())
        job = _wait(client, writing, lambda j: j["status"] not in ("queued", "running") or
                    j["message"].endswith(": writing the results up to t = 1 s"))
        assert job["status"] == "running", job
        took = stop()
    assert took < delay + 10.0, took
    done = _stored(tmp_path, writing)
    assert done["status"] == "done" and done["has_results"] is True and done["progress"] == 1.0, done
    assert done["summary"]["max_top_tension"] > 0.0 and done["sim_time"] == pytest.approx(1.0, abs=1e-9), done
    res = rfesim.open_results(tmp_path / "data" / "jobs" / writing / "results.nc")
    assert float(res.time[-1]) == pytest.approx(1.0, abs=1e-9)
    requeued = _stored(tmp_path, computing)
    assert requeued["status"] == "queued" and requeued["message"] == REQUEUED, requeued
    assert requeued["attempts"] == 0 and requeued["has_results"] is False, requeued     # the hand-out given back
    assert not (tmp_path / "data" / "jobs" / computing / "results.nc").exists()


def test_the_stop_waits_for_a_write_at_most_the_shutdown_write_grace(monkeypatch, tmp_path):
    grace = 5.0
    with service(monkeypatch, tmp_path, 3600.0, shutdown_write_grace=grace) as (client, stop):
        job_id = _submit(client, riser())
        job = _wait(client, job_id, lambda j: j["status"] not in ("queued", "running") or
                    j["message"].endswith(": writing the results up to t = 1 s"))
        assert job["status"] == "running", job
        pid = job["worker_pid"]
        took = stop()
    # the grace, not the 3 s of a worker that computes, and not the hour of the hung write
    assert grace - 0.5 < took < grace + 5.0, took
    assert not alive(pid)
    stored = _stored(tmp_path, job_id)
    assert stored["status"] == "queued" and stored["message"] == REQUEUED and stored["attempts"] == 0, stored


def test_a_job_cancelled_just_before_the_stop_keeps_its_results(monkeypatch, tmp_path):
    with service(monkeypatch, tmp_path, 2.0, shutdown_write_grace=30.0) as (client, stop):
        job_id = _submit(client, long_job())
        _wait(client, job_id, lambda j: j["status"] != "queued" and (j["simulated_time"] or 0.0) > 0.1)
        r = client.delete(f"/jobs/{job_id}")
        assert r.status_code == 202 and r.json()["status"] == "running", r.text
        stop()                     # at once: the cancel may not have reached the worker yet
    job = _stored(tmp_path, job_id)
    assert job["status"] == "cancelled" and job["has_results"] is True, job
    assert job["message"].endswith(f"; the results up to t = {job['sim_time']:.6g} s are kept"), job["message"]
    res = rfesim.open_results(tmp_path / "data" / "jobs" / job_id / "results.nc")
    assert res.status == 3 and float(res.time[-1]) == job["sim_time"]


def test_the_shutdown_write_grace_is_a_validated_setting(monkeypatch):
    for bad in ("-1", "abc"):
        monkeypatch.setenv("RFESIM_SHUTDOWN_WRITE_GRACE", bad)
        with pytest.raises(ValidationError) as err:
            Settings()
        assert err.value.errors()[0]["loc"] == ("shutdown_write_grace",)
    monkeypatch.setenv("RFESIM_SHUTDOWN_WRITE_GRACE", "0")
    assert Settings().shutdown_write_grace == 0.0
    monkeypatch.delenv("RFESIM_SHUTDOWN_WRITE_GRACE")
    assert Settings().shutdown_write_grace == 600.0


def test_dask_stop_collects_the_tasks_that_write_their_results(tmp_path):
    """Dask: a task that said it writes its results is waited for (within the grace) and its
    outcome returned, with its file written; the others are cancelled."""

    class Future:
        def __init__(self, out, done_at):
            self.out, self.done_at = out, done_at

        def done(self):
            return time.monotonic() >= self.done_at

        def result(self, timeout=None):
            return dict(self.out)

    class Queue:
        def __init__(self):
            self.items = [["w", "writing", 2.0], ["c", 0.5, 1.0]]

        def get(self, batch):
            items, self.items = self.items, []
            return items

    class Client:
        cancelled = None

        def cancel(self, futures):
            Client.cancelled = futures

        def close(self, timeout):
            pass

    now = time.monotonic()
    written = {"status": "done", "message": "ok", "summary": None, "has_results": True, "wall_time": 1.0,
               "progress": 1.0, "sim_time": 2.0, "results_bytes": b"\x89HDF results"}
    ex = DaskExecutor("tcp://127.0.0.1:1")
    ex.client, ex._progress = Client(), Queue()
    computing = Future({}, now + 3600.0)
    ex._running = {"w": (Future(written, now + 0.3), tmp_path / "w.nc"), "c": (computing, tmp_path / "c.nc")}
    ex._cancel_events = {"w": "ev-w", "c": "ev-c"}
    ex.cancel = lambda job_id: None             # no scheduler to set the flag on
    events = ex.shutdown(write_grace=5.0)
    outcomes = [e for e in events if e[0] == "outcome"]
    assert [(e[1], e[2]["status"], e[2]["has_results"]) for e in outcomes] == [("w", "done", True)], events
    assert (tmp_path / "w.nc").read_bytes() == b"\x89HDF results"
    assert Client.cancelled == [computing] and not (tmp_path / "c.nc").exists()
