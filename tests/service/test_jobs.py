"""Jobs on a real server (2 worker processes): submit -> poll -> results, 20 concurrent
jobs, server-sent events, cancel, a killed worker, validation answers."""
from __future__ import annotations

import json
import os
import signal
import time
from concurrent.futures import ThreadPoolExecutor

import httpx
import numpy as np
import pytest

from service_helpers import SCENARIOS, long_job, riser


def test_submit_poll_results_of_a_bundled_scenario(api, tmp_path):
    scenario = api.client.get("/scenarios/cantilever_pipe").json()
    assert scenario == json.loads((SCENARIOS / "cantilever_pipe.json").read_text())
    r = api.client.post("/jobs", json=scenario)
    assert r.status_code == 202
    body = r.json()
    assert body["status_url"] == f"/jobs/{body['id']}" and r.headers["location"] == body["status_url"]
    assert len(body["id"]) >= 20                      # secrets.token_urlsafe(16): not guessable
    job = api.wait(body["id"])
    assert job["status"] == "done", job
    assert job["progress"] == 1.0 and job["simulated_time"] == pytest.approx(5.0)
    assert job["summary"]["max_bend_moment"] > 0 and job["has_results"]

    r = api.client.get(f"/jobs/{body['id']}/results", params={"channels": "lines/pipe/tension,lines/pipe/position",
                                                              "every": 10})
    assert r.status_code == 200, r.text
    res = r.json()
    tension = res["channels"]["lines/pipe/tension"]
    assert tension["units"] == "N" and tension["long_name"] and tension["dims"] == ["time", "sde"]
    assert set(res["channels"]) == {"lines/pipe/tension", "lines/pipe/position"}

    nc = api.client.get(f"/jobs/{body['id']}/results.nc")
    assert nc.status_code == 200 and nc.headers["content-type"] == "application/x-netcdf"
    path = tmp_path / "r.nc"
    path.write_bytes(nc.content)
    import rfesim

    full = rfesim.open_results(path)
    assert full.success and len(full.time) == 501
    np.testing.assert_array_equal(np.array(res["time"]), full.time[::10])
    np.testing.assert_array_equal(np.array(tension["data"]), full.line("pipe").tension[::10])
    assert tension["shape"] == list(full.line("pipe").tension[::10].shape)
    assert res["channels"]["lines/pipe/position"]["shape"] == [len(full.time[::10]), 22, 3]

    # all channels, and an unknown one named in the 422
    assert len(api.client.get(f"/jobs/{body['id']}/results", params={"every": 100}).json()["channels"]) >= 10
    bad = api.client.get(f"/jobs/{body['id']}/results", params={"channels": "lines/pipe/tension,lines/nope/x"})
    assert bad.status_code == 422
    assert bad.json()["detail"][0]["loc"] == ["query", "channels"] and "lines/nope/x" in bad.json()["detail"][0]["msg"]
    assert api.client.get(f"/jobs/{body['id']}/results", params={"every": 0}).status_code == 422


def test_twenty_concurrent_jobs_all_finish_with_correct_results(api):
    import rfesim

    amplitudes = [0.1 + 0.05 * i for i in range(20)]
    bodies = [{"scenario": riser(), "overrides": {"vessels.ship.motion.heave.amplitude": a}} for a in amplitudes]
    with ThreadPoolExecutor(20) as pool:
        ids = list(pool.map(api.submit, bodies))
    assert len(set(ids)) == 20
    t0 = time.monotonic()
    jobs = [api.wait(i, timeout=240) for i in ids]
    assert [j["status"] for j in jobs] == ["done"] * 20, [j["message"] for j in jobs]
    wall = time.monotonic() - t0
    workers = {j["worker_pid"] for j in jobs}
    assert len(workers) == 2, f"both workers should have taken jobs: {workers}"
    for job_id, a in zip(ids, amplitudes):
        res = api.client.get(f"/jobs/{job_id}/results",
                             params={"channels": "lines/riser/tension,lines/riser/end_b_force"}).json()
        direct = rfesim.simulate(riser(**{"vessels.ship.motion.heave.amplitude": a}))
        np.testing.assert_allclose(np.array(res["channels"]["lines/riser/tension"]["data"]),
                                   direct.line("riser").tension, rtol=1e-9, atol=1e-6)
        np.testing.assert_allclose(np.array(res["channels"]["lines/riser/end_b_force"]["data"]),
                                   direct.line("riser").end_b_force, rtol=1e-9, atol=1e-6)
    print(f"20 jobs finished {wall:.2f} s after the last submission")


def test_server_sent_events_report_progress_until_done(api):
    job_id = api.submit(long_job(60.0))
    events = []
    with httpx.stream("GET", f"{api.server.url}/jobs/{job_id}/events", timeout=120) as r:
        assert r.status_code == 200 and r.headers["content-type"].startswith("text/event-stream")
        name = None
        for line in r.iter_lines():
            if line.startswith("event:"):
                name = line.split(":", 1)[1].strip()
            elif line.startswith("data:"):
                events.append((name, json.loads(line.split(":", 1)[1])))
                if name == "end":
                    break
    assert events[-1][0] == "end" and events[-1][1]["status"] == "done"
    progress = [e["progress"] for n, e in events if n == "progress" and e["status"] == "running"]
    assert any(0.0 < p < 1.0 for p in progress), events
    assert progress == sorted(progress)


def test_cancel_a_running_and_a_queued_job(api):
    first, second = api.submit(long_job()), api.submit(long_job())
    api.wait_running(first, min_progress=0.001)
    api.wait_running(second, min_progress=0.001)
    queued = api.submit(long_job())
    assert api.job(queued)["status"] == "queued"
    r = api.client.delete(f"/jobs/{queued}")
    assert r.status_code == 202 and r.json()["status"] == "cancelled"
    assert api.client.get(f"/jobs/{queued}/results").status_code == 409

    assert api.client.get(f"/jobs/{first}/results").status_code == 409      # running: no results yet
    t0 = time.monotonic()
    r = api.client.delete(f"/jobs/{first}")
    assert r.status_code == 202 and r.json()["status"] == "running"
    job = api.wait(first, timeout=30)
    assert job["status"] == "cancelled", job
    assert "cancelled while running" in job["message"] and job["progress"] < 1.0
    assert time.monotonic() - t0 < 8.0, "the run should stop at its next output step"
    assert api.client.delete(f"/jobs/{first}").status_code == 409
    assert api.client.delete(f"/jobs/{second}").status_code == 202
    assert api.wait(second, timeout=30)["status"] == "cancelled"

    quick = api.submit(riser())                       # the workers are free again
    assert api.wait(quick)["status"] == "done"


def test_a_killed_worker_fails_only_its_job_and_the_pool_recovers(api):
    victim = api.submit(long_job())
    other = api.submit(long_job(60.0))
    pid = api.wait_running(victim, min_progress=0.001)["worker_pid"]
    api.wait_running(other)
    os.kill(pid, signal.SIGKILL)
    job = api.wait(victim, timeout=30)
    assert job["status"] == "failed" and "SIGKILL" in job["message"] and str(pid) in job["message"], job
    assert api.wait(other, timeout=120)["status"] == "done"
    after = [api.submit(riser()) for _ in range(4)]
    assert [api.wait(j)["status"] for j in after] == ["done"] * 4
    health = api.client.get("/health").json()["executor"]
    assert pid not in health["pids"] and len(health["pids"]) == 2


def test_validation_answers_name_the_field(api, shared_server):
    bad = riser(**{"lines.riser.elements": 0})
    r = api.client.post("/jobs", json=bad)
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["lines", "riser", "elements"]
    assert "greater than or equal to 1" in r.json()["detail"][0]["msg"]

    r = api.client.post("/jobs", json={**riser(), "enviroment": {}})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["enviroment"]
    assert "did you mean 'environment'" in r.json()["detail"][0]["msg"]

    r = api.client.post("/jobs", content=b"{not json", headers={"content-type": "application/json"})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body"]

    # a string is never read as a file path
    r = api.client.post("/jobs", json="/etc/passwd")
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body"]

    # a file reference outside the data directory (the guard checks every path-like key,
    # also ones the schema does not know, before the schema)
    crafted = riser()
    crafted["vessels"]["ship"]["motion"] = {"kind": "table", "time_series_file": "../../../etc/passwd"}
    r = api.client.post("/jobs", json=crafted)
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["vessels", "ship", "motion", "time_series_file"]
    assert "data directory" in r.json()["detail"][0]["msg"]

    # limits: number of RFEs, simulated duration (defaults 20000 RFEs, 10800 s)
    r = api.client.post("/jobs", json=riser(**{"lines.riser.elements": 30000}))
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["lines"] and "30001 RFEs" in r.text
    r = api.client.post("/jobs", json=riser(**{"analysis.dynamics.duration": 1e6}))
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["analysis", "dynamics", "duration"]
    r = api.client.post("/jobs", json={"scenario": "no_such_example"})
    assert r.status_code == 422 and "cantilever_pipe" in r.json()["detail"][0]["msg"]
    r = api.client.post("/jobs", json={"scenario": "cantilever_pipe", "overrides": {"lines.pipe.elements": "x"}})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["lines", "pipe", "elements"]

    # request size (default 10 MiB)
    r = api.client.post("/jobs", content=b"{" + b" " * (11 * 1024 * 1024) + b"}",
                        headers={"content-type": "application/json"})
    assert r.status_code == 413

    for path in ("/jobs/doesnotexist12345", "/jobs/doesnotexist12345/results", "/jobs/x/results.nc",
                 "/sweeps/doesnotexist12345"):
        assert api.client.get(path).status_code == 404, path
    assert api.client.delete("/jobs/doesnotexist12345").status_code == 404


def test_scenarios_paging_and_docs(api):
    listed = api.client.get("/scenarios").json()
    names = {s["name"] for s in listed}
    assert {"cantilever_pipe", "catenary_riser", "h1_riser_heave"} <= names
    assert api.client.get("/scenarios/nope").status_code == 404
    assert api.client.get("/scenarios/..%2F..%2Fpyproject").status_code == 404

    for _ in range(3):
        api.submit({"scenario": "cantilever_pipe", "overrides": {"analysis.dynamics.duration": 0.1}})
    page1 = api.client.get("/jobs", params={"limit": 2, "offset": 0}).json()
    page2 = api.client.get("/jobs", params={"limit": 2, "offset": 2}).json()
    assert page1["total"] >= 3 and len(page1["items"]) == 2
    assert not {j["id"] for j in page1["items"]} & {j["id"] for j in page2["items"]}
    assert api.client.get("/jobs", params={"limit": 0}).status_code == 422
    assert api.client.get("/jobs", params={"status": "done"}).status_code == 200

    assert api.client.get("/docs").status_code == 200
    spec = api.client.get("/openapi.json").json()
    for path in ("/jobs", "/jobs/{job_id}", "/jobs/{job_id}/events", "/jobs/{job_id}/results",
                 "/jobs/{job_id}/results.nc", "/scenarios", "/scenarios/{name}", "/health", "/sweeps",
                 "/sweeps/{sweep_id}"):
        assert path in spec["paths"], path
    assert "Scenario" in spec["components"]["schemas"]


def test_sweep_on_the_process_pool(api):
    vary = {"vessels.ship.motion.heave.amplitude": [0.2, 0.6], "analysis.dynamics.duration": [0.5, 1.0, 1.5]}
    r = api.client.post("/sweeps", json={"scenario": riser(), "vary": vary})
    assert r.status_code == 202, r.text
    sweep = r.json()
    for job_id in sweep["jobs"]:
        api.wait(job_id)
    status = api.client.get(f"/sweeps/{sweep['id']}").json()
    assert status["status"] == "done" and status["cases"] == 6
    assert [(row["vessels.ship.motion.heave.amplitude"], row["analysis.dynamics.duration"])
            for row in status["rows"]] == [(a, d) for a in (0.2, 0.6) for d in (0.5, 1.0, 1.5)]
    assert all(row["daf"] > 1.0 and row["touchdown_min"] > 0 for row in status["rows"])
    listed = api.client.get("/sweeps").json()
    assert sweep["id"] in {s["id"] for s in listed["items"]}

    # a bad load case is refused before anything runs, naming the case
    r = api.client.post("/sweeps", json={"scenario": riser(), "vary": {"lines.riser.elements": [10, -1]}})
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["lines", "riser", "elements"]
    assert "load case lines.riser.elements=-1" in r.json()["detail"][0]["msg"]
    assert api.client.post("/sweeps", json={"scenario": riser(), "vary": {}}).status_code == 422

    # cancel a whole sweep
    r = api.client.post("/sweeps", json={"scenario": "cantilever_pipe",
                                         "vary": {"analysis.dynamics.duration": [500.0, 501.0, 502.0]}})
    sweep = r.json()
    api.wait_running(sweep["jobs"][0])
    assert api.client.delete(f"/sweeps/{sweep['id']}").status_code == 202
    for job_id in sweep["jobs"]:
        assert api.wait(job_id, timeout=30)["status"] == "cancelled"
    assert api.client.get(f"/sweeps/{sweep['id']}").json()["status"] == "cancelled"
