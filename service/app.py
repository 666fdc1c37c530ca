"""The HTTP service (FastAPI): jobs, sweeps, bundled scenarios. Routes parse, call the
job manager or the library, and format; nothing here simulates.

    rfesim serve --host 127.0.0.1 --port 8000          # or: uvicorn service.app:app

Settings come from ``RFESIM_*`` environment variables (``service.settings``). See
docs/service.md for the routes, examples and the durability semantics.
"""
from __future__ import annotations

import asyncio
import json
import logging
import re
import secrets
import time
from contextlib import asynccontextmanager
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Literal

from fastapi import FastAPI, HTTPException, Query, Request
from fastapi.concurrency import run_in_threadpool
from fastapi.exceptions import RequestValidationError
from fastapi.openapi.utils import get_openapi
from fastapi.responses import FileResponse, JSONResponse, Response, StreamingResponse
from pydantic import BaseModel, Field

import rfesim

from . import results_json, validate
from .executor import make_executor
from .jobs import JobManager, writing_message
from .middleware import BodyLimit, TokenAuth
from .paths import SAFE_NAME, find_scenarios_dir
from .settings import Settings
from .store import STATUSES, TERMINAL, QueueFull, Store

log = logging.getLogger("rfesim.service")

JOB_ID = re.compile(r"^[A-Za-z0-9_-]{8,64}$")
Status = Literal["queued", "running", "done", "failed", "cancelled"]


# --------------------------------------------------------------------------- answers

class JobAccepted(BaseModel):
    id: str = Field(description="Job id (random, not guessable)")
    status: Status
    status_url: str
    events_url: str
    results_url: str
    warnings: list[str] = Field(default_factory=list,
                                description="Warnings found without a solve while checking the scenario (a "
                                            "template's warning, an output interval that does not divide the "
                                            "duration, an RAO table that leaves out part of the sea, and from "
                                            "its built model a line with no unique static shape; or that the "
                                            "model was not built within the submit's time budget); the run's "
                                            "statics and dynamics warnings are added to GET /jobs/{id}")


class JobStatus(BaseModel):
    id: str
    status: Status
    progress: float = Field(description="Fraction of the simulated duration done, 0..1")
    simulated_time: float | None = Field(None, description="Simulated time reached [s]")
    message: str
    name: str = Field(description="The scenario's name")
    created: str | None = None
    started: str | None = None
    finished: str | None = None
    attempts: int = Field(description="Times the job was handed to a worker (more than 1 after a service restart)")
    cancel_requested: bool = False
    worker: str | None = Field(None, description="Where the job runs or ran")
    worker_pid: int | None = Field(None, description="Process id of a local worker")
    wall_time: float | None = Field(None, description="Wall time of the run in the worker [s]")
    summary: dict[str, float | str | None] | None = Field(
        None, description="Max top tension, max/min tension, max bend moment, touchdown range, DAF (SI units, "
                          "numbers), and top_tension_at: the line and end of the max top tension ('riser end B')")
    has_results: bool = Field(False, description="A results file to fetch: that of a finished run, or what a run "
                                                 "failed or cancelled during its dynamics computed up to then")
    warnings: list[str] = Field(default_factory=list,
                                description="Warnings about the scenario and its run: those answered at submit, then "
                                            "those the run logged (statics: no unique static shape, buckling, shear; "
                                            "dynamics: ...), each once")
    compile_time: float | None = Field(None, description="Wall time the worker spent compiling numba kernels for this "
                                                         "run [s] (only on the first runs on a machine; part of "
                                                         "wall_time)")
    sweep_id: str | None = None
    case_index: int | None = None
    links: dict[str, str] = Field(default_factory=dict)


class JobList(BaseModel):
    total: int
    offset: int
    limit: int
    items: list[JobStatus]


class CancelAnswer(BaseModel):
    id: str
    status: Status
    message: str


class PurgeAnswer(BaseModel):
    id: str = Field(description="The job or sweep purged")
    jobs: list[str] = Field(description="The jobs removed (a sweep's: every load case)")
    freed_bytes: int = Field(description="Bytes of files removed: job folders and input copies")
    input_copies_removed: int = Field(description="Copies of input files (<data>/inputs) that no other job named")
    input_copies_kept: int = Field(description="Copies of input files kept: other jobs name them")
    message: str


class ScenarioInfo(BaseModel):
    name: str = Field(description="Name to use in GET /scenarios/{name} and in {\"scenario\": name}")
    title: str
    description: str
    url: str


class Health(BaseModel):
    status: Literal["ok"]
    version: str
    executor: dict[str, Any]
    queued: int
    running: int
    uptime: float
    manager: str
    message: str = Field(description="What the workers are doing: ready, starting, or compiling the numba kernels "
                                     "(the first start on a machine: a few minutes, jobs wait in the queue)")


class SweepAccepted(BaseModel):
    id: str
    status_url: str
    cases: int
    jobs: list[str]
    warnings: list[str] = Field(default_factory=list,
                                description="The cases' warnings found at submit (as POST /jobs): one a warning "
                                            "every case has, with '(all n load cases)', else one per case naming "
                                            "its values; then whether some cases' models were not built within "
                                            "the submit's time budget")


class SweepStatus(BaseModel):
    id: str
    status: Status
    name: str
    cases: int
    counts: dict[str, int]
    progress: float
    vary: dict[str, list[Any]]
    columns: list[str]
    rows: list[dict[str, Any]]


class SweepList(BaseModel):
    total: int
    offset: int
    limit: int
    items: list[SweepStatus]


class JobRequest(BaseModel):
    """A bundled or given scenario with dotted-path overrides (or send the scenario itself)."""

    scenario: dict[str, Any] | str = Field(description="A scenario, or the name of a bundled scenario")
    overrides: dict[str, Any] | None = Field(None, description="{\"analysis.dynamics.duration\": 10}")


class SweepRequest(BaseModel):
    scenario: dict[str, Any] | str = Field(description="A scenario, or the name of a bundled scenario")
    vary: dict[str, list[Any]] = Field(description="Dotted scenario path -> values; several paths make a grid")
    overrides: dict[str, Any] | None = None


ERRORS = {"type": "object", "properties": {"detail": {}}}


def _responses(*codes: int) -> dict:
    text = {401: "API token missing or wrong", 404: "Unknown job or sweep", 409: "Not possible in this state",
            413: "Too large", 422: "Invalid input: detail names each field and the reason",
            429: "Too many queued jobs"}
    return {c: {"description": text[c], "content": {"application/json": {"schema": ERRORS}}} for c in codes}


# --------------------------------------------------------------------------- helpers

def _iso(ts: float | None) -> str | None:
    return datetime.fromtimestamp(ts, timezone.utc).isoformat(timespec="milliseconds") if ts else None


def _job_answer(job: dict) -> dict:
    jid = job["id"]
    links = {"self": f"/jobs/{jid}", "events": f"/jobs/{jid}/events"}
    if job["has_results"]:
        links.update(results=f"/jobs/{jid}/results", netcdf=f"/jobs/{jid}/results.nc")
    if job.get("sweep_id"):
        links["sweep"] = f"/sweeps/{job['sweep_id']}"
    return {"id": jid, "status": job["status"], "progress": float(job["progress"] or 0.0),
            "simulated_time": job["sim_time"], "message": job["message"], "name": job["name"],
            "created": _iso(job["created"]), "started": _iso(job["started"]), "finished": _iso(job["finished"]),
            "attempts": job["attempts"], "cancel_requested": job["cancel_requested"], "worker": job["worker"],
            "worker_pid": job["worker_pid"], "wall_time": job["wall_time"], "summary": job["summary"],
            "has_results": job["has_results"], "warnings": job.get("warnings") or [],
            "compile_time": job.get("compile_time"), "sweep_id": job["sweep_id"], "case_index": job["case_index"],
            "links": links}


def _sweep_answer(sweep: dict) -> dict:
    from rfesim.sweep import SUMMARY_COLUMNS

    jobs = sweep["jobs"]
    counts = {s: 0 for s in STATUSES}
    for j in jobs:
        counts[j["status"]] += 1
    n = len(jobs)
    if counts["queued"] == n:
        status = "queued"
    elif counts["queued"] or counts["running"]:
        status = "running"
    elif counts["done"] == n:
        status = "done"
    elif counts["failed"]:
        status = "failed"
    else:
        status = "cancelled" if counts["cancelled"] else "done"
    vary = sweep["vary"]
    columns = ["case", *vary, *SUMMARY_COLUMNS, "top_tension_at", "wall_time", "status", "message", "job_id"]
    rows = []
    for j in jobs:
        values = j["case_values"] or {}
        summary = j["summary"] or {}
        rows.append({"case": j["case_index"], **{p: values.get(p) for p in vary},
                     **{c: summary.get(c) for c in SUMMARY_COLUMNS},
                     "top_tension_at": summary.get("top_tension_at"), "wall_time": j["wall_time"],
                     "status": j["status"], "message": j["message"], "job_id": j["id"],
                     "progress": float(j["progress"] or 0.0)})
    progress = sum(1.0 if j["status"] in TERMINAL else float(j["progress"] or 0.0) for j in jobs) / max(1, n)
    return {"id": sweep["id"], "status": status, "name": sweep["name"], "cases": n, "counts": counts,
            "progress": progress, "vary": vary, "columns": columns, "rows": rows}


def _has_output_steps(scenario_text: str | None) -> bool:
    """Whether a stored scenario runs dynamics (output steps, where a cancel stops the run);
    True when that cannot be told."""
    from rfesim.scenario.schema import DynamicsSettings

    try:
        dyn = DynamicsSettings.model_validate(json.loads(scenario_text or "{}").get("analysis", {}).get("dynamics", {}))
    except Exception:  # noqa: BLE001 - only the wording of an answer depends on it
        return True
    return bool(dyn.enabled and dyn.duration > 0)


def _not_found(kind: str, ident: str) -> HTTPException:
    shown = ident if len(ident) <= 80 else ident[:77] + "..."
    return HTTPException(404, f"no {kind} {shown!r}")


def _conflict(msg: str) -> HTTPException:
    return HTTPException(409, msg)


def _invalid(exc: validate.Invalid) -> JSONResponse:
    return JSONResponse({"detail": exc.detail()}, status_code=422)


# --------------------------------------------------------------------------- the app

def create_app(settings: Settings | None = None) -> FastAPI:
    settings = settings or Settings()
    data_dir = settings.resolved_data_dir()
    scenarios_dir = find_scenarios_dir(settings.scenarios_dir)

    @asynccontextmanager
    async def lifespan(app: FastAPI):
        (data_dir / "jobs").mkdir(parents=True, exist_ok=True)
        (data_dir / "files").mkdir(parents=True, exist_ok=True)
        store = Store(data_dir / "jobs.sqlite")
        manager = JobManager(store, make_executor(settings), data_dir, max_attempts=settings.max_attempts,
                             shutdown_write_grace=settings.shutdown_write_grace)
        await run_in_threadpool(manager.start)
        app.state.store, app.state.manager = store, manager
        try:
            yield
        finally:
            app.state.stopping = True
            await run_in_threadpool(manager.stop)

    app = FastAPI(title="rfesim service", version=rfesim.__version__, lifespan=lifespan,
                  description="Simulate offshore lines with the Rigid Finite Element method: submit scenarios "
                              "as jobs, follow their progress, fetch results; run parameter sweeps.")
    app.state.settings = settings
    app.state.stopping = False
    app.state.scenarios_dir = scenarios_dir
    # the submit's model builds (validate.ModelCheck): one thread of their own, a time budget per submit
    model_check = validate.ModelCheck(settings.submit_model_check_seconds) if settings.submit_model_check else None

    def manager() -> JobManager:
        return app.state.manager

    def job_or_404(job_id: str) -> dict:
        job = manager().get(job_id) if JOB_ID.match(job_id) else None
        if job is None:
            raise _not_found("job", job_id)
        return job

    # ------------------------------------------------------------------ errors
    @app.exception_handler(RequestValidationError)
    async def _request_invalid(request: Request, exc: RequestValidationError):
        detail = [{"loc": list(e.get("loc", ())), "msg": e.get("msg", "invalid"), "type": e.get("type", "")}
                  for e in exc.errors()]
        return JSONResponse({"detail": detail}, status_code=422)

    @app.exception_handler(validate.Invalid)
    async def _invalid_handler(request: Request, exc: validate.Invalid):
        return _invalid(exc)

    @app.exception_handler(rfesim.ScenarioError)
    async def _scenario_error(request: Request, exc: rfesim.ScenarioError):
        return _invalid(validate.Invalid([(f.split(".") if f else ["body"], r) for f, r in exc.errors]))

    @app.exception_handler(Exception)
    async def _unexpected(request: Request, exc: Exception):
        log.exception("unexpected error on %s %s", request.method, request.url.path)
        return JSONResponse({"detail": f"internal error ({type(exc).__name__}); it has been logged"},
                            status_code=500)

    # ------------------------------------------------------------------ health
    # HEAD too: load balancers and uptime probes often check liveness with HEAD
    @app.api_route("/health", methods=["GET", "HEAD"], response_model=Health, tags=["service"],
                   summary="Liveness and queue size (no token)")
    def health():
        h = manager().health()
        return {"status": "ok", "version": rfesim.__version__, "executor": h["executor"], "queued": h["queued"],
                "running": h["running"], "uptime": time.time() - manager().started_at, "manager": h["manager"],
                "message": h["message"]}

    # ------------------------------------------------------------------ jobs
    job_body = {"requestBody": {"required": True, "content": {
        "application/json": {"schema": {"anyOf": [{"$ref": "#/components/schemas/Scenario"},
                                                  {"$ref": "#/components/schemas/JobRequest"}]}},
        "application/yaml": {"schema": {"$ref": "#/components/schemas/Scenario"}}}}}

    @app.post("/jobs", status_code=202, response_model=JobAccepted, tags=["jobs"], openapi_extra=job_body,
              responses=_responses(401, 413, 422, 429), summary="Submit a scenario as a job")
    async def submit_job(request: Request):
        """The body is a scenario (JSON, or YAML with a YAML content type), or
        ``{"scenario": <scenario or bundled name>, "overrides": {"dotted.path": value}}``.
        It is validated at once and its model is built, as ``rfesim check`` does (422 naming each
        field, what the model compiler refuses included); the job then waits in the queue."""
        body = await request.body()

        def work():
            data = validate.parse_body(body, request.headers.get("content-type"))
            warnings: list[str] = []
            # from the copies of its input files to its stored record: no purge removes a copy meanwhile
            with manager().inputs.shared():
                scenario, sc = validate.prepare_job(data, settings, scenarios_dir, model_check=model_check,
                                                    warnings=warnings)
                job_id = secrets.token_urlsafe(16)
                text = validate.to_json(scenario, ["body"])
                try:
                    app.state.store.insert_jobs([{"id": job_id, "name": sc.name, "scenario": text,
                                                  "warnings": warnings}], settings.max_queued_jobs)
                except QueueFull as exc:
                    raise HTTPException(429, str(exc), headers={"Retry-After": "30"}) from None
            folder = manager().job_dir(job_id)
            folder.mkdir(parents=True, exist_ok=True)
            (folder / "scenario.json").write_text(text, encoding="utf-8")
            manager().notify()
            return job_id, warnings

        job_id, warnings = await run_in_threadpool(work)
        return JSONResponse(status_code=202, headers={"Location": f"/jobs/{job_id}"}, content={
            "id": job_id, "status": "queued", "status_url": f"/jobs/{job_id}", "events_url": f"/jobs/{job_id}/events",
            "results_url": f"/jobs/{job_id}/results", "warnings": warnings})

    @app.get("/jobs", response_model=JobList, tags=["jobs"], responses=_responses(401, 422),
             summary="List jobs, newest first")
    def list_jobs(offset: int = Query(0, ge=0, le=10**9), limit: int = Query(50, ge=1, le=500),
                  status: Status | None = Query(None)):
        total, items = app.state.store.list(offset, limit, status)
        return {"total": total, "offset": offset, "limit": limit,
                "items": [_job_answer(j) for j in manager().overlay(items)]}

    @app.get("/jobs/{job_id}", response_model=JobStatus, tags=["jobs"], responses=_responses(401, 404),
             summary="Status, progress (0-1), simulated time and message of a job")
    def get_job(job_id: str):
        return _job_answer(job_or_404(job_id))

    @app.get("/jobs/{job_id}/scenario", tags=["jobs"], responses=_responses(401, 404),
             summary="The scenario the job runs (after overrides)")
    def get_job_scenario(job_id: str):
        job_or_404(job_id)
        text = app.state.store.scenario(job_id)
        return Response(text, media_type="application/json")

    def purged(ident: str, kind: str, job_ids: list[str], sweep_id: str | None = None) -> JSONResponse:
        try:
            out = manager().purge(job_ids, sweep_id)
        except OSError as exc:
            raise _conflict(f"the files of {kind} {ident} could not all be removed ({exc}); its record is "
                            f"kept: purge it again") from None
        if out is None:                  # purged meanwhile by another request
            raise _not_found(kind, ident)
        files = (f"{out['input_copies_removed']} input file copies removed"
                 + (f", {out['input_copies_kept']} kept (other jobs name them)" if out["input_copies_kept"] else ""))
        what = f"{len(job_ids)} load cases" if sweep_id else "its folder"
        return JSONResponse({"id": ident, **out, "message": f"{kind} {ident} purged: its record, {what} and "
                                                            f"{files}; {out['freed_bytes']} bytes freed"})

    purge_query = Query(False, description="Delete the job (or sweep) instead of cancelling it: one that is over "
                                           "(done, failed, cancelled) is removed with its folder and results and "
                                           "the copies of its input files that no other job names (200); 409 "
                                           "while it is queued or running (cancel it first)")

    @app.delete("/jobs/{job_id}", response_model=CancelAnswer, status_code=202, tags=["jobs"],
                responses={**_responses(401, 404, 409),
                           200: {"model": PurgeAnswer, "description": "purge=true: the job and its files removed"}},
                summary="Cancel a queued or running job (purge=true: delete a job that is over, with its files)")
    def cancel_job(job_id: str, purge: bool = purge_query):
        job = job_or_404(job_id)
        if purge:
            if job["status"] not in TERMINAL:
                raise _conflict(f"job {job_id} is {job['status']}: cancel it first (DELETE /jobs/{job_id}), then "
                                f"purge it once it is over")
            if job["sweep_id"]:
                raise _conflict(f"job {job_id} is load case {job['case_index']} of sweep {job['sweep_id']}: purge "
                                f"the whole sweep (DELETE /sweeps/{job['sweep_id']}?purge=true)")
            return purged(job_id, "job", [job_id])
        if job["status"] in TERMINAL:
            raise _conflict(f"job {job_id} is already {job['status']}: nothing to cancel")
        status = manager().cancel(job_id)
        if status == "cancelled":
            return {"id": job_id, "status": "cancelled", "message": "cancelled before it started"}
        if status == "running":
            t = manager().writing_time(job_id)
            if t is not None:            # the run is over: its results file is being written
                return {"id": job_id, "status": "running",
                        "message": f"cancel requested: {writing_message(t, cancelled=False)}: kept"}
            if not _has_output_steps(app.state.store.scenario(job_id)):
                # statics only: no output step before the end to stop at (the job ended "done")
                return {"id": job_id, "status": "running",
                        "message": "cancel requested: the run has no output step before its end (statics "
                                   "only): it stops when statics ends and keeps the static solution (sooner, "
                                   "without results, at a load step of a stepped statics"
                                   + ("" if settings.scheduler_address else
                                      f", or when its worker is killed after {settings.cancel_grace:g} s, "
                                      f"RFESIM_CANCEL_GRACE") + ")"}
            return {"id": job_id, "status": "running",
                    "message": "cancel requested: the run stops at its next output step and keeps its "
                               "results up to it"}
        raise _conflict(f"job {job_id} is already {status}: nothing to cancel")

    @app.get("/jobs/{job_id}/events", tags=["jobs"], responses={
        200: {"description": "Server-sent events: 'progress' while it runs, 'end' once done",
              "content": {"text/event-stream": {"schema": {"type": "string"}}}}, **_responses(401, 404)},
        summary="Server-sent progress events until the job ends")
    async def job_events(job_id: str, request: Request):
        job_or_404(job_id)

        async def stream():
            last = None
            beat = time.monotonic()
            yield "retry: 1000\n\n"
            while True:
                job = await run_in_threadpool(manager().get, job_id)
                if job is None:
                    return
                payload = {"id": job_id, "status": job["status"], "progress": float(job["progress"] or 0.0),
                           "simulated_time": job["sim_time"], "message": job["message"]}
                # the service stopping (flag set when the stop signal arrives, rfesim serve): end
                # the stream now, with the job as it is (queued or running: it is re-queued and
                # runs again after the restart), so the stop does not wait for the job
                if job["status"] in TERMINAL or app.state.stopping:
                    yield f"event: end\ndata: {json.dumps(payload)}\n\n"
                    return
                if payload != last:
                    yield f"event: progress\ndata: {json.dumps(payload)}\n\n"
                    last = payload
                    beat = time.monotonic()
                elif time.monotonic() - beat > 15.0:
                    yield ": keep-alive\n\n"
                    beat = time.monotonic()
                if await request.is_disconnected():
                    return
                await asyncio.sleep(0.25)

        return StreamingResponse(stream(), media_type="text/event-stream",
                                 headers={"Cache-Control": "no-cache", "X-Accel-Buffering": "no"})

    def results_file(job_id: str) -> Path:
        job = job_or_404(job_id)
        if not job["has_results"]:
            if job["status"] in ("queued", "running"):
                raise _conflict(f"job {job_id} is {job['status']}: results once it is done")
            raise _conflict(f"job {job_id} is {job['status']} and has no results: {job['message']}")
        path = manager().results_path(job_id)
        if not path.is_file():
            raise _conflict(f"the results file of job {job_id} is missing from the data directory")
        return path

    @app.get("/jobs/{job_id}/results", tags=["results"], responses=_responses(401, 404, 409, 413, 422),
             summary="Results as JSON, with channel selection and decimation")
    def get_results(job_id: str,
                    channels: list[str] | None = Query(None, description=(
                        "Channels, comma-separated (lines/riser/tension,lines/riser/position) or the "
                        "parameter repeated (channels=lines/riser/tension&channels=lines/riser/position), "
                        "or both (default: all)")),
                    every: int = Query(1, ge=1, le=10**9, description="Keep every n-th output time")):
        # a list: ?channels=a&channels=b is how HTTP clients send a list (httpx params={"channels":
        # [a, b]}); one string kept only the last of them, silently
        if channels and sum(len(c) for c in channels) > 4000:
            raise validate.Invalid([(["query", "channels"], "at most 4000 characters of channel names in all")])
        path = results_file(job_id)
        names = [n.strip() for c in channels for n in c.split(",") if n.strip()] if channels else None
        try:
            plan = results_json.plan_results(path, names, every, settings.max_result_values)
        except results_json.UnknownChannels as exc:
            raise validate.Invalid([(["query", "channels"], str(exc))]) from None
        except results_json.TooLarge as exc:
            raise HTTPException(413, str(exc)) from None
        except OSError as exc:
            raise _conflict(f"the results file of job {job_id} cannot be read: {exc}") from None
        job = manager().get(job_id)
        head = {"id": job_id, "status": job["status"], "message": job["message"]}
        # streamed a block of output times at a time (Starlette iterates this generator in its
        # thread pool): a whole answer built in memory took ~1 GB for 14 M values and held the
        # GIL long enough to stall /health for seconds
        return StreamingResponse(results_json.stream_results(plan, head), media_type="application/json")

    @app.get("/jobs/{job_id}/results.nc", tags=["results"], responses={
        200: {"description": "The netCDF-4 results file", "content": {"application/x-netcdf": {}}},
        **_responses(401, 404, 409)}, summary="The netCDF results file")
    def get_results_file(job_id: str):
        path = results_file(job_id)
        return FileResponse(path, media_type="application/x-netcdf", filename=f"rfesim-{job_id}.nc")

    # ------------------------------------------------------------------ sweeps
    sweep_body = {"requestBody": {"required": True, "content": {
        "application/json": {"schema": {"$ref": "#/components/schemas/SweepRequest"}}}}}

    @app.post("/sweeps", status_code=202, response_model=SweepAccepted, tags=["sweeps"], openapi_extra=sweep_body,
              responses=_responses(401, 413, 422, 429), summary="Run a grid of load cases")
    async def submit_sweep(request: Request):
        """``{"scenario": <scenario or bundled name>, "vary": {"dotted.path": [v1, v2]}, "overrides": {...}}``:
        one job per combination of the varied values; every case is validated first, and the
        cases' models are built once per distinct model (422 naming the field and the load case)."""
        body = await request.body()

        def work():
            data = validate.parse_body(body, request.headers.get("content-type"))
            case_warnings: list[list[str]] = []
            notes: list[str] = []
            with manager().inputs.shared():          # as POST /jobs: the input copies against a purge
                vary, cases, name = validate.prepare_sweep(data, settings, scenarios_dir, warnings=case_warnings,
                                                           model_check=model_check, notes=notes)
                sweep_id = secrets.token_urlsafe(16)
                jobs = []
                for i, ((values, case), warnings) in enumerate(zip(cases, case_warnings)):
                    text = validate.to_json(case, ["scenario"])
                    jobs.append({"id": secrets.token_urlsafe(16), "name": f"{name} [case {i}]", "scenario": text,
                                 "sweep_id": sweep_id, "case_index": i, "case_values": values,
                                 "warnings": warnings})
                try:
                    app.state.store.insert_jobs(jobs, settings.max_queued_jobs,
                                                sweep={"id": sweep_id, "name": name, "vary": vary})
                except QueueFull as exc:
                    raise HTTPException(429, str(exc), headers={"Retry-After": "30"}) from None
            manager().notify()
            return sweep_id, [j["id"] for j in jobs], validate.sweep_warnings(
                [(values, w) for (values, _), w in zip(cases, case_warnings)]) + notes

        sweep_id, job_ids, warnings = await run_in_threadpool(work)
        return JSONResponse(status_code=202, headers={"Location": f"/sweeps/{sweep_id}"}, content={
            "id": sweep_id, "status_url": f"/sweeps/{sweep_id}", "cases": len(job_ids), "jobs": job_ids,
            "warnings": warnings})

    def sweep_or_404(sweep_id: str) -> dict:
        sweep = app.state.store.get_sweep(sweep_id) if JOB_ID.match(sweep_id) else None
        if sweep is None:
            raise _not_found("sweep", sweep_id)
        manager().overlay(sweep["jobs"])
        return sweep

    @app.get("/sweeps", response_model=SweepList, tags=["sweeps"], responses=_responses(401, 422),
             summary="List sweeps, newest first")
    def list_sweeps(offset: int = Query(0, ge=0, le=10**9), limit: int = Query(20, ge=1, le=200)):
        total, items = app.state.store.list_sweeps(offset, limit)
        for s in items:
            manager().overlay(s["jobs"])
        return {"total": total, "offset": offset, "limit": limit, "items": [_sweep_answer(s) for s in items]}

    @app.get("/sweeps/{sweep_id}", response_model=SweepStatus, tags=["sweeps"], responses=_responses(401, 404),
             summary="Status and the summary table of a sweep (one row per load case)")
    def get_sweep(sweep_id: str):
        return _sweep_answer(sweep_or_404(sweep_id))

    @app.get("/sweeps/{sweep_id}/table.csv", tags=["sweeps"], responses={
        200: {"description": "The summary table", "content": {"text/csv": {}}}, **_responses(401, 404)},
        summary="The summary table as CSV")
    def get_sweep_csv(sweep_id: str):
        import csv
        import io

        # numbers in full precision (repr), as the CSV of rfesim sweep: the console's 6 digits
        # made two load cases 2.0000001 and 2.0000004 read back as the same row
        from rfesim.sweep import _csv_cell

        answer = _sweep_answer(sweep_or_404(sweep_id))
        buf = io.StringIO()
        writer = csv.writer(buf)
        writer.writerow(answer["columns"])
        for row in answer["rows"]:
            writer.writerow([_csv_cell(row.get(c)) for c in answer["columns"]])
        return Response(buf.getvalue(), media_type="text/csv",
                        headers={"Content-Disposition": f'attachment; filename="sweep-{sweep_id}.csv"'})

    @app.delete("/sweeps/{sweep_id}", response_model=SweepStatus, status_code=202, tags=["sweeps"],
                responses={**_responses(401, 404, 409),
                           200: {"model": PurgeAnswer, "description": "purge=true: the sweep, its load cases' jobs "
                                                                      "and their files removed"}},
                summary="Cancel every queued or running case of a sweep (purge=true: delete a sweep that is over, "
                        "with its cases and their files)")
    def cancel_sweep(sweep_id: str, purge: bool = purge_query):
        sweep = sweep_or_404(sweep_id)
        if purge:
            busy = [j for j in sweep["jobs"] if j["status"] not in TERMINAL]
            if busy:
                raise _conflict(f"sweep {sweep_id} has {len(busy)} of {len(sweep['jobs'])} load cases queued or "
                                f"running: cancel it first (DELETE /sweeps/{sweep_id}), then purge it once they "
                                f"are over")
            return purged(sweep_id, "sweep", [j["id"] for j in sweep["jobs"]], sweep_id)
        for j in sweep["jobs"]:
            if j["status"] not in TERMINAL:
                manager().cancel(j["id"])
        return _sweep_answer(sweep_or_404(sweep_id))

    # ------------------------------------------------------------------ scenarios
    def scenario_files() -> list[Path]:
        if scenarios_dir is None:
            return []
        return sorted(p for p in scenarios_dir.glob("*.json") if SAFE_NAME.match(p.stem))

    @app.get("/scenarios", response_model=list[ScenarioInfo], tags=["scenarios"], responses=_responses(401),
             summary="The bundled example scenarios")
    def list_scenarios():
        out = []
        for p in scenario_files():
            try:
                data = json.loads(p.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                continue
            out.append({"name": p.stem, "title": str(data.get("name", p.stem)),
                        "description": str(data.get("description", "")), "url": f"/scenarios/{p.stem}"})
        return out

    @app.get("/scenarios/{name}", tags=["scenarios"], responses=_responses(401, 404),
             summary="One bundled scenario (JSON); run it with POST /jobs {\"scenario\": name}")
    def get_scenario(name: str):
        stem = name[:-5] if name.endswith(".json") else name
        path = next((p for p in scenario_files() if p.stem == stem), None)
        if path is None:
            raise _not_found("bundled scenario", name)
        return Response(path.read_bytes(), media_type="application/json")

    # ------------------------------------------------------------------ OpenAPI with the scenario schema
    def openapi():
        if app.openapi_schema:
            return app.openapi_schema
        schema = get_openapi(title=app.title, version=app.version, description=app.description, routes=app.routes)
        components = schema.setdefault("components", {}).setdefault("schemas", {})
        scenario_schema = rfesim.Scenario.model_json_schema(ref_template="#/components/schemas/Scenario_{model}")
        for name, sub in scenario_schema.pop("$defs", {}).items():
            components[f"Scenario_{name}"] = sub
        components["Scenario"] = scenario_schema
        for model in (JobRequest, SweepRequest):
            sub = model.model_json_schema(ref_template="#/components/schemas/{model}")
            for name, d in sub.pop("$defs", {}).items():
                components.setdefault(name, d)
            components[model.__name__] = sub
        if settings.token():
            components_sec = schema["components"].setdefault("securitySchemes", {})
            components_sec["bearer"] = {"type": "http", "scheme": "bearer"}
            schema["security"] = [{"bearer": []}]
        app.openapi_schema = schema
        return schema

    app.openapi = openapi

    # middlewares: the last added runs first (token, then size)
    app.add_middleware(BodyLimit, limit=settings.max_request_bytes)
    if settings.token():
        app.add_middleware(TokenAuth, token=settings.token())
    return app


def __getattr__(name: str):
    """``service.app.app``: built on first use from the environment (so importing the
    module for ``create_app`` reads no settings)."""
    if name == "app":
        global app
        app = create_app()
        return app
    raise AttributeError(name)
