"""A job cancelled while it runs keeps the results computed up to the cancel: status
`cancelled` with `has_results`, its summary and simulated time, and `GET /jobs/{id}/results.nc`
and `/results` serve them, on the local worker processes and on a Dask scheduler."""
from __future__ import annotations

import time

import numpy as np
import pytest

import rfesim
from service_helpers import Api, long_job


def _cancel_and_fetch(api: Api, tmp_path, min_time: float = 0.5) -> dict:
    """Submit a long job, cancel it once it has simulated ``min_time`` s, check its results;
    returns the job."""
    job_id = api.submit(long_job())
    api.wait(job_id, until=("running", "done", "failed", "cancelled"), timeout=180,
             predicate=lambda j: j["status"] != "running" or (j["simulated_time"] or 0.0) >= min_time)
    assert api.job(job_id)["status"] == "running"
    assert api.client.get(f"/jobs/{job_id}/results.nc").status_code == 409    # running: nothing yet
    r = api.client.delete(f"/jobs/{job_id}")
    assert r.status_code == 202 and r.json()["status"] == "running"
    assert "keeps its results" in r.json()["message"]
    job = api.wait(job_id, timeout=60)
    assert job["status"] == "cancelled", job
    assert job["has_results"] is True, job
    t_end = job["simulated_time"]
    assert min_time <= t_end < 600.0 and job["progress"] < 1.0
    assert job["message"].startswith("cancelled while running at t = ")
    assert job["message"].endswith(f"; the results up to t = {t_end:.6g} s are kept")
    assert job["summary"] and job["summary"]["max_bend_moment"] > 0.0
    assert job["links"]["netcdf"] == f"/jobs/{job_id}/results.nc"

    nc = api.client.get(f"/jobs/{job_id}/results.nc")
    assert nc.status_code == 200 and nc.content[:4] == b"\x89HDF"
    path = tmp_path / f"{job_id}.nc"
    path.write_bytes(nc.content)
    res = rfesim.open_results(path)
    assert res.status == 3 and res.message == f"cancelled at t = {t_end:.6g} s"
    assert float(res.time[-1]) == t_end and res.time[0] == 0.0
    assert np.all(np.diff(res.time) > 0) and res.line("pipe").tension.shape[0] == len(res.time)

    js = api.client.get(f"/jobs/{job_id}/results", params={"channels": "lines/pipe/tension", "every": 1})
    assert js.status_code == 200, js.text
    body = js.json()
    assert body["status"] == "cancelled" and len(body["time"]) == len(res.time)
    np.testing.assert_array_equal(np.asarray(body["channels"]["lines/pipe/tension"]["data"], float),
                                  res.line("pipe").tension)
    return job


def test_a_cancelled_job_keeps_its_results_up_to_the_cancel(api, tmp_path):
    job = _cancel_and_fetch(api, tmp_path)
    assert job["worker"].startswith("local process")


@pytest.fixture
def dask_cluster():
    distributed = pytest.importorskip("distributed")
    from rfesim.sweep import worker_environment

    with worker_environment():
        cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1",
                                           dashboard_address=None)
    yield cluster
    cluster.close()


def test_a_cancelled_dask_job_keeps_its_results_up_to_the_cancel(dask_cluster, make_server, tmp_path):
    server = make_server(env={"RFESIM_SCHEDULER_ADDRESS": dask_cluster.scheduler_address})
    api = Api(server)
    try:
        assert api.client.get("/health").json()["executor"]["kind"] == "dask"
        t0 = time.monotonic()
        job = _cancel_and_fetch(api, tmp_path)
        assert job["worker"].startswith("dask")
        print(f"dask cancel with results: {time.monotonic() - t0:.1f} s")
    finally:
        api.close()
