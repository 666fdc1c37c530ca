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

# a 12-element steel riser from the seabed to a heaving ship: seabed contact (touchdown),
# a top tension at end B (DAF), about 0.1-0.2 s of work per second simulated
RISER: dict = {
    "schema_version": 1, "name": "tiny riser",
    "environment": {"gravity": 9.81, "water": {"density": 1025.0, "depth": 50.0},
                    "seabed": {"normal_stiffness": 1.0e5, "damping_ratio": 0.5}},
    "vessels": {"ship": {"motion": {"kind": "harmonic", "heave": {"amplitude": 0.5, "period": 8.0},
                                    "ramp_duration": 2.0}}},
    "line_types": {"pipe": {"outer_diameter": 0.2, "wall_thickness": 0.012, "youngs_modulus": 2.0e11,
                            "density": 7850.0, "drag_normal": 1.0, "added_mass_normal": 1.0}},
    "lines": {"riser": {"type": "pipe", "length": 100.0, "elements": 12,
                        "end_a": {"attach": "fixed", "position": [-70.0, 0.0, -49.9]},
                        "end_b": {"attach": "ship", "position": [0.0, 0.0, -5.0]}}},
    "analysis": {"statics": {"enabled": True},
                 "dynamics": {"duration": 1.0, "output_interval": 0.1,
                              "integrator": {"kind": "generalized-alpha", "time_step": 0.05}}},
}


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
