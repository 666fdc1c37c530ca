"""A local worker process whose results files take ``delay`` s longer to write, for the
service tests: ``service.executor.worker_module`` replaced by
``SimpleNamespace(process_main=functools.partial(process_main, delay=...))`` makes a
``ProcessExecutor`` start its workers here (the spawned process imports this module by
name: the tests' folder is on the path it inherits). The warm-up's file is not slowed."""
from __future__ import annotations

import os
import secrets
import time
from pathlib import Path

from service import worker


def process_main(conn, warmup: bool = True, *, delay: float = 0.0, partial: int = 0) -> None:
    worker.set_thread_environment()                 # before rfesim (numba) is imported
    from rfesim.results import Results

    original = Results.to_netcdf

    def slow_to_netcdf(self, path):
        if Path(path).name == "results.nc":
            tmp = None
            if partial:
                tmp = Path(path).with_name(f".results.nc.{secrets.token_hex(6)}.tmp")
                tmp.write_bytes(b"\x89HDF" + bytes(partial))
            time.sleep(delay)
            if tmp is not None:
                os.unlink(tmp)
        return original(self, path)

    Results.to_netcdf = slow_to_netcdf
    worker.process_main(conn, warmup)
