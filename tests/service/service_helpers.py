"""Helpers of the service tests: small scenarios and a client of a real server."""
from __future__ import annotations

import copy
import os
import time
from pathlib import Path

import httpx

from service.launch import ServerProcess

REPO = Path(__file__).resolve().parents[2]
SCENARIOS = REPO / "scenarios"

# the tiny riser of the tests' shared scenes (tests/scenes.py, importable through
# tests/conftest.py): 12 elements, seabed contact, a top tension at end B, about 0.1-0.2 s
# of work per second simulated
from scenes import RISER  # noqa: E402


def riser(**overrides) -> dict:
    from rfesim.scenario import apply_overrides

    return apply_overrides(copy.deepcopy(RISER), overrides)


def long_job(duration: float = 600.0) -> dict:
    """The bundled cantilever for a long simulated time: runs for many seconds (a step of 0.5 ms,
    a tenth of the bundled one: 60 s simulated take a few seconds of wall time)."""
    return {"scenario": "cantilever_pipe", "overrides": {"analysis.dynamics.duration": duration,
                                                        "analysis.dynamics.output_interval": 0.05,
                                                        "analysis.dynamics.integrator.time_step": 0.0005}}


class Api:
    """A small client of one server."""

    def __init__(self, server: ServerProcess, token: str | None = None):
        self.server = server
        self.client = httpx.Client(base_url=server.url, timeout=30.0,
                                   headers={"Authorization": f"Bearer {token}"} if token else {})

    def submit(self, body) -> str:
        r = self.client.post("/jobs", json=body)
        assert r.status_code == 202, r.text
        return r.json()["id"]

    def job(self, job_id: str) -> dict:
        r = self.client.get(f"/jobs/{job_id}")
        assert r.status_code == 200, r.text
        return r.json()

    def wait(self, job_id: str, until=("done", "failed", "cancelled"), timeout: float = 120.0,
             predicate=None) -> dict:
        deadline = time.monotonic() + timeout
        while True:
            job = self.job(job_id)
            if job["status"] in until and (predicate is None or predicate(job)):
                return job
            if time.monotonic() > deadline:
                raise AssertionError(f"job {job_id} still {job['status']} after {timeout} s: {job}\n"
                                     f"{self.server.read_log()[-2000:]}")
            time.sleep(0.05)

    def wait_running(self, job_id: str, min_progress: float = 0.0, timeout: float = 120.0) -> dict:
        job = self.wait(job_id, until=("running", "done", "failed", "cancelled"), timeout=timeout,
                        predicate=lambda j: j["status"] != "running" or (j["worker"] and j["progress"] > min_progress))
        assert job["status"] == "running", f"the job ended before the test could act: {job}"
        return job

    def close(self) -> None:
        self.client.close()


def alive(pid: int) -> bool:
    """The process runs (a zombie is not alive)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(")")[-1].split()[0] != "Z"
    except OSError:
        return False
