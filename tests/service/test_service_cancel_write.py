"""A cancelled job whose results file takes longer to write than the cancel grace keeps its
results: the worker says it writes them, the executor then waits ``cancel_write_grace`` s
(RFESIM_CANCEL_WRITE_GRACE) from that note instead of killing it ``cancel_grace`` s after
the cancel, and the job's message says so while it writes. A worker that hangs in the
write is still killed once the write grace is over, and the job says why.

The service runs in this process (the app with its lifespan, under a test client); its
local workers are spawned from ``slow_write_worker``, which slows the writing of a job's
``results.nc`` by a given time."""
from __future__ import annotations

import contextlib
import functools
import os
import subprocess
import sys
import time
import types
import warnings

import numpy as np
import pytest
from pydantic import ValidationError

import rfesim
import slow_write_worker
from service import executor as executor_module
from service.app import create_app
from service.executor import DaskExecutor
from service.settings import Settings
from service_helpers import alive, long_job, riser

with warnings.catch_warnings():      # starlette's note on its httpx client, which these tests do not mind
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

CANCEL_GRACE = 0.5


@contextlib.contextmanager
def slow_write_service(monkeypatch, tmp_path, delay: float, **settings):
    """A service with one local worker whose results files take ``delay`` s more to write."""
    monkeypatch.setattr(executor_module, "worker_module",
                        types.SimpleNamespace(process_main=functools.partial(slow_write_worker.process_main,
                                                                             delay=delay)))
    app = create_app(Settings(data_dir=tmp_path / "data", workers=1, warmup=False, cancel_grace=CANCEL_GRACE,
                              submit_model_check=False, **settings))
    with TestClient(app) as client:
        yield client


def _job(client, job_id: str) -> dict:
    r = client.get(f"/jobs/{job_id}")
    assert r.status_code == 200, r.text
    return r.json()


def _watch(client, job_id: str, predicate, timeout: float = 120.0) -> tuple[dict, list[dict]]:
    """Poll a job until ``predicate(job)``: (that job, every answer seen)."""
    seen = []
    deadline = time.monotonic() + timeout
    while True:
        job = _job(client, job_id)
        seen.append(job)
        if predicate(job):
            return job, seen
        if time.monotonic() > deadline:
            raise AssertionError(f"job {job_id} after {timeout} s: {job}")
        time.sleep(0.05)


def _over(job: dict) -> bool:
    return job["status"] in ("done", "failed", "cancelled")


def _cancel_while_running(client, min_time: float = 0.2) -> tuple[str, float]:
    """Submit a long job, cancel it once it has simulated ``min_time`` s: (its id, the time of the cancel)."""
    r = client.post("/jobs", json=long_job())
    assert r.status_code == 202, r.text
    job_id = r.json()["id"]
    job, _ = _watch(client, job_id, lambda j: _over(j) or (j["simulated_time"] or 0.0) >= min_time)
    assert job["status"] == "running", job
    r = client.delete(f"/jobs/{job_id}")
    assert r.status_code == 202 and r.json()["status"] == "running", r.text
    return job_id, time.monotonic()


def test_a_cancelled_job_whose_write_outlasts_the_cancel_grace_keeps_its_results(monkeypatch, tmp_path):
    delay = 2.0                                     # 4 x the cancel grace
    with slow_write_service(monkeypatch, tmp_path, delay, cancel_write_grace=30.0) as client:
        job_id, cancelled_at = _cancel_while_running(client)
        job, seen = _watch(client, job_id, _over)
        took = time.monotonic() - cancelled_at
        assert job["status"] == "cancelled" and job["has_results"] is True, job
        t_end = job["simulated_time"]
        assert job["message"].endswith(f"; the results up to t = {t_end:.6g} s are kept"), job["message"]
        # while it wrote, the job said so (and was not killed after the cancel grace)
        writing = f"cancel requested: writing the results up to t = {t_end:.6g} s"
        assert sum(j["status"] == "running" and j["message"] == writing for j in seen) >= 5, \
            [j["message"] for j in seen]
        assert took >= delay > CANCEL_GRACE
        nc = client.get(f"/jobs/{job_id}/results.nc")
        assert nc.status_code == 200 and nc.content[:4] == b"\x89HDF"
    res = rfesim.open_results(tmp_path / "data" / "jobs" / job_id / "results.nc")
    assert res.status == 3 and float(res.time[-1]) == t_end and np.all(np.diff(res.time) > 0)


def test_a_worker_that_hangs_writing_after_a_cancel_is_killed_after_the_write_grace(monkeypatch, tmp_path):
    write_grace = 1.0
    with slow_write_service(monkeypatch, tmp_path, 3600.0, cancel_write_grace=write_grace) as client:
        job_id, cancelled_at = _cancel_while_running(client)
        writing, _ = _watch(client, job_id, lambda j: _over(j) or j["message"].startswith("cancel requested: "))
        assert writing["status"] == "running", writing
        pid = writing["worker_pid"]
        t = float(writing["message"].removeprefix("cancel requested: writing the results up to t = ")
                  .removesuffix(" s"))
        job, _ = _watch(client, job_id, _over, timeout=30.0)
        took = time.monotonic() - cancelled_at
        assert job["status"] == "cancelled" and job["has_results"] is False and job["summary"] is None, job
        assert job["message"] == (f"cancelled: its results up to t = {t:.6g} s were not written within 1 s of the "
                                  f"start of the write (RFESIM_CANCEL_WRITE_GRACE), so its worker process was "
                                  f"killed and replaced and the results are lost"), job["message"]
        assert write_grace < took < write_grace + 10.0, took
        assert client.get(f"/jobs/{job_id}/results.nc").status_code in (404, 409)
        deadline = time.monotonic() + 10.0
        while alive(pid) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not alive(pid)
        # a replacement worker is started
        while time.monotonic() < deadline:
            executor = client.get("/health").json()["executor"]
            if executor["ready"] == 1:
                break
            time.sleep(0.05)
        assert executor["ready"] == 1 and executor["pids"] != [pid], executor


def test_a_cancel_that_comes_while_a_finished_run_writes_does_not_kill_it(monkeypatch, tmp_path):
    with slow_write_service(monkeypatch, tmp_path, 2.0, cancel_write_grace=30.0) as client:
        r = client.post("/jobs", json=riser())
        assert r.status_code == 202, r.text
        job_id = r.json()["id"]
        job, _ = _watch(client, job_id, lambda j: _over(j) or j["message"].endswith(": writing the results up "
                                                                                       "to t = 1 s"))
        assert job["status"] == "running" and job["message"].startswith("running on local process "), job
        r = client.delete(f"/jobs/{job_id}")
        assert r.status_code == 202 and r.json()["status"] == "running", r.text
        assert r.json()["message"] == "cancel requested: writing the results up to t = 1 s: kept", r.text
        assert _job(client, job_id)["message"] == "cancel requested: writing the results up to t = 1 s"
        job, _ = _watch(client, job_id, _over)
        assert job["status"] == "done" and job["has_results"] is True and job["progress"] == 1.0, job
        assert job["simulated_time"] == pytest.approx(1.0, abs=1e-9)


def test_the_write_grace_is_a_validated_setting(monkeypatch):
    for bad in ("0", "-5", "abc"):
        monkeypatch.setenv("RFESIM_CANCEL_WRITE_GRACE", bad)
        with pytest.raises(ValidationError) as err:
            Settings()
        assert err.value.errors()[0]["loc"] == ("cancel_write_grace",)
    monkeypatch.setenv("RFESIM_CANCEL_WRITE_GRACE", "45")
    assert Settings().cancel_write_grace == 45.0
    monkeypatch.delenv("RFESIM_CANCEL_WRITE_GRACE")
    assert Settings().cancel_write_grace == 600.0
    # rfesim serve refuses it with a message naming the setting
    proc = subprocess.run([sys.executable, "-m", "rfesim.cli", "serve", "--port", "1"],
                          env={**os.environ, "RFESIM_CANCEL_WRITE_GRACE": "-1"},
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode != 0
    assert "invalid service settings" in proc.stderr and "cancel_write_grace" in proc.stderr, proc.stderr


def test_dask_progress_queue_carries_the_writing_note():
    class Queue:
        def get(self, batch):
            return [["a", 0.25, 1.5], ["a", "writing", 3.0], ["b", 0.5, 2.0], ["gone", "writing", 1.0],
                    ["a", "nonsense", 1.0]]

    ex = DaskExecutor("tcp://127.0.0.1:1")
    ex._progress = Queue()
    ex._running = {"a": (None, None), "b": (None, None)}
    assert ex._poll_progress() == [("progress", "a", 0.25, 1.5), ("progress", "b", 0.5, 2.0), ("writing", "a", 3.0)]
