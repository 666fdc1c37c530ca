"""Parameter sweeps on Dask: ``rfesim sweep --local-cluster`` (6 load cases) and the
service with a Dask scheduler address (POST /sweeps, progress, cancel, results file)."""
from __future__ import annotations

import csv
import json
import subprocess
import sys
import time

import pytest

from service_helpers import Api, long_job, riser

distributed = pytest.importorskip("distributed")

VARY = {"vessels.ship.motion.heave.amplitude": [0.2, 0.5, 0.8], "lines.riser.elements": [10, 12]}


def test_rfesim_sweep_on_a_dask_local_cluster(tmp_path):
    scenario = tmp_path / "riser.json"
    scenario.write_text(json.dumps(riser()))
    table = tmp_path / "table.csv"
    args = [sys.executable, "-m", "rfesim.cli", "sweep", str(scenario),
            "--vary", "vessels.ship.motion.heave.amplitude=0.2,0.5,0.8", "--vary", "lines.riser.elements=10,12",
            "--local-cluster", "2", "-o", str(table)]
    t0 = time.monotonic()
    run = subprocess.run(args, capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "6 load cases on a Dask LocalCluster of 2 processes" in run.stderr
    rows = list(csv.DictReader(table.open()))
    assert len(rows) == 6
    assert [(float(r["vessels.ship.motion.heave.amplitude"]), int(r["lines.riser.elements"])) for r in rows] == \
        [(a, n) for a in VARY["vessels.ship.motion.heave.amplitude"] for n in VARY["lines.riser.elements"]]
    for r in rows:
        assert r["status"] == "done", r
        assert float(r["max_top_tension"]) > 0 and float(r["max_bend_moment"]) > 0
        assert float(r["daf"]) > 1.0
        assert 0 < float(r["touchdown_min"]) <= float(r["touchdown_max"]) < 100.0
    # the table the command prints says the same
    assert run.stdout.count("done") == 6
    # a bigger heave amplitude gives a bigger top tension (same discretisation)
    top = {(r["vessels.ship.motion.heave.amplitude"], r["lines.riser.elements"]): float(r["max_top_tension"])
           for r in rows}
    assert top[("0.2", "12")] < top[("0.5", "12")] < top[("0.8", "12")]

    from rfesim.sweep import run_case

    direct = run_case(riser(**{"vessels.ship.motion.heave.amplitude": 0.2, "lines.riser.elements": 10}))
    assert float(rows[0]["max_top_tension"]) == pytest.approx(direct["max_top_tension"], rel=1e-5)
    print(f"rfesim sweep, 6 cases on a 2-process LocalCluster: {time.monotonic() - t0:.1f} s")


@pytest.fixture
def dask_cluster():
    from rfesim.sweep import worker_environment

    with worker_environment():
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                           dashboard_address=None)
    yield cluster
    cluster.close()


def test_service_runs_jobs_and_sweeps_on_a_dask_scheduler(dask_cluster, make_server):
    server = make_server(env={"RFESIM_SCHEDULER_ADDRESS": dask_cluster.scheduler_address})
    api = Api(server)
    health = api.client.get("/health").json()
    assert health["executor"]["kind"] == "dask"

    r = api.client.post("/sweeps", json={"scenario": riser(), "vary": VARY})
    assert r.status_code == 202, r.text
    sweep = r.json()
    assert sweep["cases"] == 6 and len(sweep["jobs"]) == 6
    deadline = time.monotonic() + 240
    while True:
        status = api.client.get(f"/sweeps/{sweep['id']}").json()
        if status["status"] not in ("queued", "running") or time.monotonic() > deadline:
            break
        time.sleep(0.2)
    assert status["status"] == "done", status
    assert status["counts"]["done"] == 6 and status["progress"] == 1.0
    assert [row["case"] for row in status["rows"]] == list(range(6))
    for row in status["rows"]:
        assert row["daf"] > 1.0 and row["max_top_tension"] > 0 and row["touchdown_max"] > 0
        assert row["job_id"] in sweep["jobs"]
    table = api.client.get(f"/sweeps/{sweep['id']}/table.csv")
    assert table.status_code == 200 and len(table.text.strip().splitlines()) == 7

    # the results file came back from the Dask worker and was written here
    job = api.job(sweep["jobs"][0])
    assert job["worker"].startswith("dask") and job["has_results"]
    nc = api.client.get(f"/jobs/{sweep['jobs'][0]}/results.nc")
    assert nc.status_code == 200 and nc.content[:4] == b"\x89HDF"

    # progress and cancel through the Dask executor
    long = api.submit(long_job(600.0))
    api.wait_running(long, min_progress=0.0, timeout=120)
    assert api.client.delete(f"/jobs/{long}").status_code == 202
    assert api.wait(long, timeout=60)["status"] == "cancelled"
    api.close()
