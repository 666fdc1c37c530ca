"""Service settings, read from ``RFESIM_*`` environment variables (pydantic-settings).

    RFESIM_DATA_DIR=/data RFESIM_WORKERS=2 RFESIM_API_TOKEN=... rfesim serve

Every limit is a plain number here so an operator can see and change it; the defaults
suit one machine with a few cores.
"""
from __future__ import annotations

import os
from pathlib import Path

from pydantic import Field, SecretStr
from pydantic_settings import BaseSettings, SettingsConfigDict


def _default_workers() -> int:
    return max(1, min(2, os.cpu_count() or 1))


class Settings(BaseSettings):
    """What an operator can set. Environment variable = ``RFESIM_`` + the field name in
    capitals (``RFESIM_MAX_QUEUED_JOBS=500``)."""

    model_config = SettingsConfigDict(env_prefix="RFESIM_", extra="ignore")

    data_dir: Path = Field(Path("rfesim-data"), description="Job database, job folders and results files")
    workers: int = Field(default_factory=_default_workers, ge=1, le=256,
                         description="Worker processes of the local process pool (one simulation each)")
    scheduler_address: str | None = Field(None, description="Dask scheduler address (tcp://host:8786): run jobs "
                                                            "on that cluster instead of the local process pool")
    api_token: SecretStr | None = Field(None, description="When set, every route but /health needs "
                                                          "'Authorization: Bearer <token>'")
    scenarios_dir: Path | None = Field(None, description="Folder of the bundled example scenarios (default: "
                                                         "found next to the package)")

    max_request_bytes: int = Field(10 * 1024 * 1024, ge=1024, description="Largest request body (413 above)")
    max_rfes: int = Field(20_000, ge=1, description="Largest number of RFEs in one scenario: sum over lines of "
                                                    "(elements + 1) (422 above)")
    max_duration: float = Field(10_800.0, gt=0.0, description="Longest simulated duration in s (422 above)")
    max_output_values: int = Field(20_000_000, ge=1000,
                                   description="Largest number of stored output times x RFEs of one job "
                                               "(bounds the memory of a worker; 422 above)")
    max_queued_jobs: int = Field(1000, ge=1, description="Largest number of queued jobs (429 above)")
    max_result_values: int = Field(20_000_000, ge=1000,
                                   description="Largest number of values in one JSON results answer (413 above: "
                                               "select channels or decimate with every)")
    max_attempts: int = Field(3, ge=1, description="A job interrupted by this many service stops is failed "
                                                   "instead of re-queued")
    cancel_grace: float = Field(10.0, gt=0.0, description="Seconds a running job has to stop after a cancel "
                                                          "before its worker process is killed and replaced")
    cancel_write_grace: float = Field(600.0, gt=0.0,
                                      description="Seconds a cancelled job's worker has to write the results up to "
                                                  "the cancel, counted from when it starts writing them (a long "
                                                  "run's file can take longer than cancel_grace); a worker still "
                                                  "writing after that is killed and replaced, and the job has no "
                                                  "results. Never shortens cancel_grace")
    shutdown_write_grace: float = Field(600.0, ge=0.0,
                                        description="Seconds a clean stop of the service (SIGTERM) waits for a "
                                                    "worker writing the results file of a run that is over, "
                                                    "counted from the stop (never less than the 3 s every worker "
                                                    "has to exit); the job is then recorded done with its "
                                                    "results. A worker still writing after that is killed and "
                                                    "its job re-queued. Jobs still computing are re-queued at "
                                                    "once")
    warmup: bool = Field(True, description="Workers run a tiny scenario at start to load the numba cache")
    submit_model_check: bool = Field(True, description="Build each submitted scenario's model (POST /jobs, and once "
                                                       "per distinct model in POST /sweeps), as `rfesim check` does: "
                                                       "what the model compiler refuses is a 422 at submit")
    submit_model_check_seconds: float = Field(3.0, gt=0.0, le=600.0,
                                              description="Wall-time budget of the model builds of one submit; "
                                                          "models not built by then are not checked (a warning says "
                                                          "so) and their errors fail the job when it runs")

    def resolved_data_dir(self) -> Path:
        return self.data_dir.expanduser().resolve()

    def token(self) -> str | None:
        if self.api_token is None:
            return None
        value = self.api_token.get_secret_value()
        return value or None
