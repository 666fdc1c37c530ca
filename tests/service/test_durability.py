"""A job is never lost: kill the server (SIGKILL) in the middle of a run, start it again
on the same data directory, find the finished results intact and the interrupted job
re-queued and finished."""
from __future__ import annotations

import hashlib
import sqlite3
import time

from service_helpers import Api, alive, long_job, riser


def test_kill_the_server_mid_run_then_restart(make_server):
    server = make_server()
    data_dir = server.data_dir
    api = Api(server)
    finished = [api.submit(riser(**{"vessels.ship.motion.heave.amplitude": a})) for a in (0.2, 0.4, 0.6)]
    for job_id in finished:
        assert api.wait(job_id)["status"] == "done"
    before = {j: api.client.get(f"/jobs/{j}/results", params={"channels": "lines/riser/tension"}).json()
              for j in finished}
    digests = {j: hashlib.sha256((data_dir / "jobs" / j / "results.nc").read_bytes()).hexdigest() for j in finished}

    interrupted = api.submit(long_job(60.0))
    waiting = api.submit(long_job(5.0))
    extra = api.submit(long_job(5.0))            # queued behind the two workers
    pid = api.wait_running(interrupted, min_progress=0.01)["worker_pid"]
    api.close()
    server.kill()                                # SIGKILL: no shutdown code runs

    deadline = time.monotonic() + 15
    while alive(pid) and time.monotonic() < deadline:   # its workers notice and exit by themselves
        time.sleep(0.1)
    assert not alive(pid), "a worker outlived its killed server"
    con = sqlite3.connect(data_dir / "jobs.sqlite")
    left = dict(con.execute("SELECT id, status FROM jobs").fetchall())
    con.close()
    assert left[interrupted] == "running"

    restarted = make_server(data_dir=data_dir, wait_workers=False)
    api = Api(restarted)
    job = api.job(interrupted)
    assert job["status"] in ("queued", "running", "done")
    if job["status"] == "queued":
        assert "re-queued after a service restart" in job["message"]
    for job_id in (interrupted, waiting, extra):
        job = api.wait(job_id, timeout=180)
        assert job["status"] == "done", job
    assert api.job(interrupted)["attempts"] == 2
    assert api.job(interrupted)["simulated_time"] == 60.0

    for job_id in finished:
        job = api.job(job_id)
        assert job["status"] == "done" and job["attempts"] == 1
        digest = hashlib.sha256((data_dir / "jobs" / job_id / "results.nc").read_bytes()).hexdigest()
        assert digest == digests[job_id]
        again = api.client.get(f"/jobs/{job_id}/results", params={"channels": "lines/riser/tension"}).json()
        assert again == before[job_id]
    assert not list(data_dir.glob("jobs/*/.*.tmp")), "temporary files left behind"
    api.close()
