"""Start a real service (``rfesim serve`` with uvicorn) in a subprocess on 127.0.0.1, for
the tests and the benchmark.

    with ServerProcess(data_dir, env={"RFESIM_WORKERS": "2"}) as server:
        httpx.get(server.url + "/health")
"""
from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class ServerProcess:
    """``python -m rfesim.cli serve --host 127.0.0.1 --port P`` with ``RFESIM_DATA_DIR``
    and the given environment; its output goes to ``<data_dir>/../server-<port>.log``."""

    def __init__(self, data_dir: Path, env: dict[str, str] | None = None, port: int | None = None,
                 token: str | None = None):
        self.data_dir = Path(data_dir)
        self.env = dict(env or {})
        self.port = port or free_port()
        self.token = token
        self.proc: subprocess.Popen | None = None
        self.log_path = self.data_dir.parent / f"server-{self.port}.log"

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    def headers(self) -> dict[str, str]:
        return {"Authorization": f"Bearer {self.token}"} if self.token else {}

    def start(self, timeout: float = 60.0, wait_workers: bool = True) -> "ServerProcess":
        import httpx

        env = {**os.environ, **self.env, "RFESIM_DATA_DIR": str(self.data_dir)}
        if self.token:
            env["RFESIM_API_TOKEN"] = self.token
        self.log = open(self.log_path, "ab")
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "rfesim.cli", "serve", "--host", "127.0.0.1", "--port", str(self.port), "-v"],
            env=env, stdout=self.log, stderr=subprocess.STDOUT, start_new_session=True)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError(f"the server exited with code {self.proc.returncode}: {self.read_log()[-3000:]}")
            try:
                r = httpx.get(self.url + "/health", timeout=2.0)
                if r.status_code == 200:
                    ex = r.json()["executor"]
                    if not wait_workers or ex.get("kind") != "local processes" or ex.get("ready") == ex.get("total"):
                        return self
            except httpx.HTTPError:
                pass
            time.sleep(0.1)
        self.stop()
        raise RuntimeError(f"the server did not start within {timeout} s: {self.read_log()[-3000:]}")

    def read_log(self) -> str:
        try:
            return self.log_path.read_text(errors="replace")
        except OSError:
            return ""

    def kill(self) -> None:
        """SIGKILL the server process only (its workers notice and exit by themselves)."""
        if self.proc is not None and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGKILL)
            self.proc.wait(timeout=10)

    def stop(self, timeout: float = 20.0) -> None:
        """SIGTERM (uvicorn's clean shutdown), then SIGKILL of the process group."""
        if self.proc is None:
            return
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                pass
        try:
            os.killpg(self.proc.pid, signal.SIGKILL)     # anything left of this server's own session
        except (ProcessLookupError, PermissionError):
            pass
        if self.proc.poll() is None:
            self.proc.wait(timeout=10)
        self.log.close()

    def __enter__(self) -> "ServerProcess":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()
