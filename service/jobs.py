"""The job manager: the one thread between the job records (SQLite) and the executor.

Routes insert jobs as ``queued`` rows and wake the manager; the manager claims the
oldest queued jobs when the executor has free slots, records what the executor
reports (started, progress, outcome) and forwards cancels. Progress is kept in memory
and written to the database at most once a second per job; status changes are written
at once.

At start, jobs left ``running`` by a stopped (or killed) service are re-queued, or
failed after ``max_attempts`` interruptions. At a clean stop, a job whose run is over and
whose worker writes its results file is given ``shutdown_write_grace`` s to finish the
write and is recorded with its outcome (done, with its results); the jobs still computing
are handed back to the queue the same way.
"""
from __future__ import annotations

import json
import logging
import os
import queue
import shutil
import threading
import time
from contextlib import contextmanager
from pathlib import Path

from .executor import JobExecutor
from .paths import copy_reference, input_copies_in, inputs_dir
from .store import Store
from .worker import COMPILING_NOTE, merge_warnings

log = logging.getLogger("rfesim.service.jobs")

PROGRESS_FLUSH = 1.0     # s between database writes of one job's progress


def writing_message(t: float, cancelled: bool) -> str:
    """A running job's message while its results file is written (up to the output time ``t``, s)."""
    text = f"writing the results up to t = {t:.6g} s"
    return f"cancel requested: {text}" if cancelled else text


class InputsLock:
    """Submits (shared: they make or reuse copies in ``<data>/inputs`` and store scenarios
    naming them) against a purge (exclusive: it removes the copies no stored scenario names),
    so a copy a submit has just reused is not removed before its job is stored. A waiting
    purge goes first: new submits wait for it (milliseconds), not the other way round."""

    def __init__(self) -> None:
        self._cond = threading.Condition()
        self._shared = 0
        self._exclusive = False
        self._waiting = 0

    @contextmanager
    def shared(self):
        with self._cond:
            while self._exclusive or self._waiting:
                self._cond.wait()
            self._shared += 1
        try:
            yield
        finally:
            with self._cond:
                self._shared -= 1
                self._cond.notify_all()

    @contextmanager
    def exclusive(self):
        with self._cond:
            self._waiting += 1
            try:
                while self._exclusive or self._shared:
                    self._cond.wait()
            finally:
                self._waiting -= 1
            self._exclusive = True
        try:
            yield
        finally:
            with self._cond:
                self._exclusive = False
                self._cond.notify_all()


def _tree_size(folder: Path) -> int:
    total = 0
    for root, _dirs, files in os.walk(folder):
        for name in files:
            try:
                total += os.lstat(os.path.join(root, name)).st_size
            except OSError:
                pass
    return total


class JobManager:
    def __init__(self, store: Store, executor: JobExecutor, data_dir: Path, *, max_attempts: int = 3,
                 shutdown_write_grace: float = 600.0):
        self.store = store
        self.executor = executor
        self.data_dir = Path(data_dir)
        self.max_attempts = max_attempts
        self.shutdown_write_grace = float(shutdown_write_grace)
        self.live: dict[str, tuple[float, float]] = {}       # job id -> (fraction, simulated time)
        self._running_message: dict[str, str] = {}           # job id -> "running on ..." (its worker)
        self._writing: dict[str, float] = {}                 # job id -> t (s): its results file is being written
        self._writing_lock = threading.Lock()                # its message vs. a cancel from a route
        self._flushed: dict[str, float] = {}
        self._cancels: queue.SimpleQueue = queue.SimpleQueue()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self.inputs = InputsLock()                             # submits vs. purges (input copies)
        self.started_at = time.time()
        self.recovered: tuple[list[str], list[str]] = ([], [])
        self.loop_errors = 0

    # ------------------------------------------------------------------ paths
    def job_dir(self, job_id: str) -> Path:
        return self.data_dir / "jobs" / job_id

    def results_path(self, job_id: str) -> Path:
        return self.job_dir(job_id) / "results.nc"

    # ------------------------------------------------------------------ life
    def start(self) -> None:
        self.recovered = self.store.requeue_running(
            "re-queued after a service restart (it was running when the service stopped)", self.max_attempts)
        if self.recovered[0] or self.recovered[1]:
            log.warning("after the restart: %d jobs re-queued, %d failed (interrupted too often)",
                        len(self.recovered[0]), len(self.recovered[1]))
        # before the executor starts: no worker of this service writes into a job folder yet,
        # so every temporary file found is a leftover (a worker killed mid-write, a service
        # stopped or killed while a job wrote its results: that job is now queued, failed or
        # cancelled, not only among the re-queued ones)
        self._clean_all_job_dirs()
        # no submit runs yet either: a copy no job names is a leftover (a purge interrupted
        # between a job's record and its copies, a submit refused with a 422)
        self._clean_inputs()
        self.executor.start()
        self._thread = threading.Thread(target=self._run, name="rfesim-job-manager", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        self.executor.wake()
        if self._thread is not None:
            self._thread.join(timeout=10)
        # cancels asked for after the loop's last step reach their workers before the stop, so
        # such a run stops at its next output step and writes its results, as after any cancel
        self._forward_cancels()
        # a run that is over and writing its results file finishes the write (at most
        # shutdown_write_grace s) and its outcome is recorded: it was re-queued and computed
        # again from the start, hours of work for a long run
        for event in self.executor.shutdown(self.shutdown_write_grace) or []:
            try:
                self._handle(event)
            except Exception:                       # the others are still recorded
                log.exception("job manager stop: %r", event[:2])
        self._flush(force=True)
        self.store.requeue_running("re-queued: the service stopped while it was running", None, refund=True)

    def _forward_cancels(self) -> None:
        while True:
            try:
                job_id = self._cancels.get_nowait()
            except queue.Empty:
                return
            self.executor.cancel(job_id)

    def _clean_job_dir(self, job_id: str) -> None:
        """Remove temporary files a killed worker may have left (complete results stay).
        Only for a job no worker runs: at start, before the executor, and at its outcome."""
        self._clean_folder(self.job_dir(job_id))

    @staticmethod
    def _clean_folder(folder: Path) -> None:
        try:
            stray = list(folder.glob(".*.tmp"))
        except OSError:
            return
        for tmp in stray:
            try:
                size = tmp.stat().st_size
                tmp.unlink()
            except OSError:
                continue
            log.info("removed the stray temporary file %s (%d bytes)", tmp, size)

    def _clean_all_job_dirs(self) -> None:
        """At start: the stray temporary files of every job folder (a partial results file
        of 10-100 MB stayed for ever when its worker was killed while writing it)."""
        try:
            folders = [p for p in (self.data_dir / "jobs").iterdir() if p.is_dir()]
        except OSError:
            return
        for folder in folders:
            self._clean_folder(folder)

    def _clean_inputs(self) -> None:
        """At start: remove the input copies no job's stored scenario names, and the
        temporary files of copies being written when the service stopped."""
        removed = freed = 0
        try:
            folders = [p for p in inputs_dir(self.data_dir).iterdir() if p.is_dir()]
        except OSError:
            return
        for folder in folders:
            try:
                files = [p for p in folder.iterdir() if p.is_file()]
            except OSError:
                continue
            for path in files:
                stray = path.name.startswith(".") and path.name.endswith(".tmp")
                if not stray and self.store.names(copy_reference(path)):
                    continue
                try:
                    size = path.stat().st_size
                    path.unlink()
                except OSError:
                    continue
                removed += 1
                freed += size
            try:
                folder.rmdir()                 # only when empty
            except OSError:
                pass
        if removed:
            log.info("removed %d input copies that no job names (%d bytes)", removed, freed)

    def purge(self, job_ids: list[str], sweep_id: str | None = None) -> dict | None:
        """Remove jobs that are over (done, failed, cancelled) with their files: their folders,
        then their records (and the sweep's row), then the input copies no other job names.
        None when one of them is not over any more (nothing removed from the database).
        Raises OSError when a folder cannot be removed (the records are kept: retry).

        Folders go before records: a purge interrupted in between leaves a record whose files
        are gone (purge it again), never a results file no record knows of; an input copy left
        by an interruption after the records is removed at the next start."""
        with self.inputs.exclusive():
            copies: set[Path] = set()
            for job_id in job_ids:
                try:
                    copies |= input_copies_in(json.loads(self.store.scenario(job_id) or "null"), self.data_dir)
                except ValueError:
                    pass
            freed = 0
            for job_id in job_ids:
                folder = self.job_dir(job_id)
                if folder.is_dir():
                    freed += _tree_size(folder)
                    shutil.rmtree(folder)
            if not self.store.delete_jobs(job_ids, sweep_id):
                return None
            removed = kept = 0
            for path in sorted(copies):
                if self.store.names(copy_reference(path)):
                    kept += 1
                    continue
                try:
                    size = path.stat().st_size
                    path.unlink()
                except FileNotFoundError:
                    continue
                except OSError as exc:
                    log.warning("purge: could not remove the input copy %s: %s", path, exc)
                    continue
                removed += 1
                freed += size
                try:
                    path.parent.rmdir()
                except OSError:
                    pass
        log.info("purged %d jobs%s: %d bytes freed, %d input copies removed, %d kept (named by other jobs)",
                 len(job_ids), f" (sweep {sweep_id})" if sweep_id else "", freed, removed, kept)
        return {"jobs": list(job_ids), "freed_bytes": freed, "input_copies_removed": removed,
                "input_copies_kept": kept}

    # ------------------------------------------------------------------ from the routes
    def notify(self) -> None:
        self.executor.wake()

    def cancel(self, job_id: str) -> str | None:
        """Cancel a job: the status it has now ("cancelled" for a queued job,
        "running" while a running job is being stopped), or None if unknown."""
        if self.store.cancel_queued(job_id):
            return "cancelled"
        with self._writing_lock:
            requested = self.store.request_cancel(job_id)
            t = self._writing.get(job_id) if requested else None
            if t is not None:                  # the run is over: its results are being written
                self.store.set_running_message(job_id, writing_message(t, cancelled=True))
        if requested:
            self._cancels.put(job_id)
            self.executor.wake()
            return "running"
        job = self.store.get(job_id)
        return job["status"] if job else None

    def writing_time(self, job_id: str) -> float | None:
        """The output time (s) up to which a running job's results file is being written, or
        None when it is not writing one."""
        with self._writing_lock:
            return self._writing.get(job_id)

    def get(self, job_id: str) -> dict | None:
        job = self.store.get(job_id)
        return self.overlay([job])[0] if job is not None else None

    def overlay(self, jobs: list[dict]) -> list[dict]:
        """The live state on job records: the progress of running jobs, and on queued ones
        that no worker can take yet because the workers are compiling numba kernels, a note."""
        waiting = None
        for job in jobs:
            if job["status"] == "running" and job["id"] in self.live:
                job["progress"], job["sim_time"] = self.live[job["id"]]
            elif job["status"] == "queued":
                if waiting is None:
                    waiting = self._warm_up_note()
                if waiting:
                    job["message"] = f"{job['message']} ({waiting})"
        return jobs

    def _warm_up_note(self) -> str:
        """While no worker is ready and one is compiling numba kernels in its warm-up: why the
        queue does not move; else ""."""
        ex = self.executor.status()
        if ex.get("compiling") and not ex.get("ready"):
            return f"waiting for the workers' warm-up: {COMPILING_NOTE}"
        return ""

    # ------------------------------------------------------------------ the loop
    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                self._step()
            except Exception:                       # never let the manager die
                self.loop_errors += 1
                log.exception("job manager loop")
                time.sleep(0.5)

    def _step(self) -> None:
        for event in self.executor.wait(0.5):
            self._handle(event)
        self._forward_cancels()
        self._flush()
        if self._stop.is_set():
            return
        slots = self.executor.free_slots()
        if slots <= 0:
            return
        for job_id, scenario, attempt in self.store.claim_queued(slots):
            self._dispatch(job_id, scenario, attempt)

    def _dispatch(self, job_id: str, scenario_text: str, attempt: int) -> None:
        folder = self.job_dir(job_id)
        try:
            folder.mkdir(parents=True, exist_ok=True)
            spec = {"id": job_id, "scenario": json.loads(scenario_text), "attempt": attempt}
        except (OSError, ValueError) as exc:
            self.store.finish(job_id, "failed", f"could not prepare the job: {exc}")
            return
        if not self.executor.submit(job_id, spec, self.results_path(job_id)):
            # no worker after all (one died just now): back to the queue, first in line
            self.store.requeue_one(job_id)

    def _handle(self, event: tuple) -> None:
        kind, job_id = event[0], event[1]
        if kind == "started":
            info = event[2]
            job = self.store.get(job_id)
            attempt = job["attempts"] if job else 1
            note = f" (attempt {attempt})" if attempt > 1 else ""
            message = f"running on {info['worker']}{note}"
            self._running_message[job_id] = message
            self.store.set_running_info(job_id, message, info.get("worker"), info.get("pid"))
            self.live[job_id] = (0.0, 0.0)
        elif kind == "progress":
            self.live[job_id] = (float(event[2]), float(event[3]))
        elif kind == "compiling":
            # a cold numba cache: the job shows no progress for minutes, say why
            message = self._running_message.get(job_id, "running")
            self.store.set_running_message(job_id, f"{message}: {COMPILING_NOTE}" if event[2] else message)
        elif kind == "writing":
            # the run is over (finished, failed or cancelled) and its results file is being
            # written: after a cancel the executor waits for the write (cancel_write_grace)
            t = float(event[2])
            with self._writing_lock:
                job = self.store.get(job_id)
                if job is not None and job["status"] == "running":
                    self._writing[job_id] = t
                    cancelled = bool(job["cancel_requested"])
                    message = writing_message(t, cancelled=cancelled)
                    if not cancelled:
                        message = f"{self._running_message.get(job_id, 'running')}: {message}"
                    self.store.set_running_message(job_id, message)
        elif kind == "outcome":
            out = event[2]
            self.live.pop(job_id, None)
            self._writing.pop(job_id, None)
            self._flushed.pop(job_id, None)
            self._running_message.pop(job_id, None)
            # the job's worker has ended with it (reported its outcome, or died or was killed:
            # e.g. mid-write, after RFESIM_CANCEL_WRITE_GRACE): nothing writes in its folder any
            # more, so a temporary file there is a partial results file that no rename will claim
            self._clean_job_dir(job_id)
            status = out.get("status", "failed")
            if status not in ("done", "failed", "cancelled"):
                status = "failed"
            warnings = None
            if out.get("warnings"):
                job = self.store.get(job_id)
                warnings = merge_warnings(job["warnings"] if job else [], [str(w) for w in out["warnings"]])
            self.store.finish(job_id, status, str(out.get("message", "")), summary=out.get("summary"),
                              wall_time=out.get("wall_time"), has_results=bool(out.get("has_results")),
                              progress=out.get("progress"), sim_time=out.get("sim_time"), warnings=warnings,
                              compile_time=out.get("compile_time"))
            log.info("job %s %s: %s", job_id, status, out.get("message", ""))

    def _flush(self, force: bool = False) -> None:
        now = time.monotonic()
        for job_id, (fraction, t) in list(self.live.items()):
            if force or now - self._flushed.get(job_id, 0.0) >= PROGRESS_FLUSH:
                self.store.set_progress(job_id, fraction, t)
                self._flushed[job_id] = now

    # ------------------------------------------------------------------ status
    def health(self) -> dict:
        ex = self.executor.status()
        if ex.get("compiling"):
            message = (f"{ex['compiling']} of {ex.get('total', '?')} workers {COMPILING_NOTE}"
                       + ("" if ex.get("ready") else "; jobs wait in the queue until a worker is ready"))
        elif ex.get("warming_up") and not ex.get("ready"):
            message = "the workers are starting (loading the numba kernels); jobs wait in the queue"
        elif "ready" in ex and "total" in ex:
            message = f"{ex['ready']} of {ex['total']} workers ready"
        else:
            message = "ok"
        return {"executor": ex, "queued": self.store.count("queued"), "running": self.store.count("running"),
                "manager": "running" if self._thread is not None and self._thread.is_alive() else "stopped",
                "message": message}

    def disk_free(self) -> int | None:
        try:
            return shutil.disk_usage(self.data_dir).free
        except OSError:
            return None
