"""Limits and safety on a real server: API token, queue bound (429), small request
limit (413)."""
from __future__ import annotations

import httpx

from service_helpers import Api, long_job, riser

TOKEN = "s3cret-token-for-tests"


def test_token_required_on_every_route_but_health(make_server):
    server = make_server(env={"RFESIM_WORKERS": "1", "RFESIM_WARMUP": "false"}, token=TOKEN, wait_workers=False)
    url = server.url
    assert httpx.get(f"{url}/health").status_code == 200
    routes = [("GET", "/jobs"), ("POST", "/jobs"), ("GET", "/jobs/abcdefghijklmnop"),
              ("GET", "/jobs/abcdefghijklmnop/events"), ("GET", "/jobs/abcdefghijklmnop/results"),
              ("GET", "/jobs/abcdefghijklmnop/results.nc"), ("DELETE", "/jobs/abcdefghijklmnop"),
              ("GET", "/scenarios"), ("GET", "/scenarios/cantilever_pipe"), ("POST", "/sweeps"),
              ("GET", "/sweeps"), ("GET", "/docs"), ("GET", "/openapi.json"), ("GET", "/no/such/route")]
    for method, path in routes:
        r = httpx.request(method, url + path, json={})
        assert r.status_code == 401, (method, path, r.status_code)
        assert r.headers["www-authenticate"] == "Bearer"
        r = httpx.request(method, url + path, json={}, headers={"Authorization": "Bearer wrong"})
        assert r.status_code == 401, (method, path)
    good = {"Authorization": f"Bearer {TOKEN}"}
    assert httpx.get(f"{url}/jobs", headers=good).status_code == 200
    assert httpx.get(f"{url}/scenarios", headers=good).status_code == 200
    assert httpx.get(f"{url}/openapi.json", headers=good).json()["security"] == [{"bearer": []}]
    api = Api(server, token=TOKEN)
    job_id = api.submit(riser())
    assert api.wait(job_id, timeout=120)["status"] == "done"
    api.close()


def test_queue_bound_answers_429_and_request_size_413(make_server):
    server = make_server(env={"RFESIM_WORKERS": "1", "RFESIM_MAX_QUEUED_JOBS": "2",
                              "RFESIM_MAX_REQUEST_BYTES": "20000", "RFESIM_MAX_RFES": "50",
                              "RFESIM_MAX_DURATION": "700"})
    api = Api(server)
    running = api.submit(long_job(600.0))
    api.wait_running(running)
    queued = [api.submit(riser()), api.submit(riser())]
    r = api.client.post("/jobs", json=riser())
    assert r.status_code == 429 and "at most 2" in r.json()["detail"] and r.headers["retry-after"]
    r = api.client.post("/sweeps", json={"scenario": riser(), "vary": {"lines.riser.elements": [4, 5]}})
    assert r.status_code in (422, 429)
    r = api.client.post("/jobs", json=riser(**{"lines.riser.elements": 60}))
    assert r.status_code == 422 and "61 RFEs" in r.text
    r = api.client.post("/jobs", json=riser(**{"analysis.dynamics.duration": 800.0}))
    assert r.status_code == 422 and "RFESIM_MAX_DURATION" in r.text
    big = riser(description="x" * 30000)
    r = api.client.post("/jobs", json=big)
    assert r.status_code == 413
    # chunked upload without a Content-Length
    r = api.client.post("/jobs", content=iter([b'{"name": "', b"y" * 25000, b'"}']),
                        headers={"content-type": "application/json"})
    assert r.status_code == 413
    assert api.client.delete(f"/jobs/{running}").status_code == 202
    assert [api.wait(j)["status"] for j in queued] == ["done", "done"]
    api.close()
