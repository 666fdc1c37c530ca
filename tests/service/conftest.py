"""Fixtures of the service tests: real uvicorn servers (``rfesim serve``) in subprocesses
on 127.0.0.1, each with its own temporary data directory."""
from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("fastapi")
pytest.importorskip("uvicorn")

from service.launch import ServerProcess  # noqa: E402
from service_helpers import Api  # noqa: E402


@pytest.fixture(scope="session", autouse=True)
def numba_cache():
    """Compile (or load) the numba kernels once in this process before any server starts,
    so that on a cold cache (a fresh clone in CI) the workers only load it."""
    from service.worker import warm_up

    warm_up()


@pytest.fixture
def make_server(tmp_path_factory):
    """A factory of servers on fresh (or given) data directories, stopped at the end."""
    servers: list[ServerProcess] = []

    def make(env: dict | None = None, data_dir: Path | None = None, token: str | None = None,
             wait_workers: bool = True) -> ServerProcess:
        if data_dir is None:
            data_dir = tmp_path_factory.mktemp("service") / "data"
        s = ServerProcess(data_dir, env={"RFESIM_WORKERS": "2", **(env or {})}, token=token)
        servers.append(s)
        return s.start(timeout=600.0, wait_workers=wait_workers)

    yield make
    for s in servers:
        s.stop()


@pytest.fixture(scope="session")
def shared_server(tmp_path_factory):
    """One server (2 workers) for the tests that do not restart or reconfigure it, shared by
    all the modules (each start costs about 5 s: the server and its workers' warm-up)."""
    data_dir = tmp_path_factory.mktemp("shared") / "data"
    s = ServerProcess(data_dir, env={"RFESIM_WORKERS": "2", "RFESIM_CANCEL_GRACE": "10"})
    s.start(timeout=600.0)
    yield s
    s.stop()


@pytest.fixture
def api(shared_server):
    a = Api(shared_server)
    yield a
    a.close()
