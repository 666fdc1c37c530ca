"""The executor seam: where jobs run, never in the web process.

The job manager (``service.jobs``) talks to one executor from its one thread:

    executor.start()
    executor.free_slots() -> int                  # jobs it can take now
    executor.submit(job_id, spec, results_path) -> bool
    executor.cancel(job_id)
    executor.wait(timeout) -> [event, ...]        # ("started", id, info) | ("progress", id, fraction, t)
                                                  # | ("compiling", id, bool) | ("writing", id, t)
                                                  # | ("outcome", id, outcome dict)
    executor.wake()                               # from any thread: make wait() return now
    executor.shutdown(write_grace) -> [event, ...]  # the events that came during the stop: the
                                                  # outcome of a job whose results file was being
                                                  # written, given up to write_grace s

:class:`ProcessExecutor` (the default) keeps ``workers`` long-lived processes (spawn
start method), each with its own duplex pipe, one job at a time. A small supervisor
(``wait``) watches every pipe and every process sentinel, so:

* progress arrives over the pipe, throttled by the worker;
* cancel is a message the worker reads inside its progress callback (the run stops at
  the next output step, its results up to there written and kept: the outcome has
  ``has_results``); a worker that does not stop within ``cancel_grace`` seconds
  (e.g. busy in statics, which reports no progress) is killed and replaced, its job
  cancelled without results. A worker says "writing" before it writes a results file
  (``("writing", id, t)`` events): from then on a cancelled job has ``cancel_write_grace``
  seconds counted from that note (never less than what is left of ``cancel_grace``), as a
  long run's file can take longer to write than the cancel grace; a worker still writing
  after that is killed, its job cancelled without results and a message saying so;
* a worker that dies (SIGKILL, out-of-memory killer, a crash in native code) fails only
  the job it was running, with the exit signal in the message, and a new worker is
  started in its place;
* the first worker starts alone and the others once it is ready, so with a cold numba
  cache one process compiles and writes it and the others only load it;
* a worker that compiles numba kernels (a cold cache: in its warm-up, or in a job using
  kernels the warm-up does not) says so; ``status()`` counts those workers, and the job
  it runs gets a ``("compiling", id, True)`` event (``False`` once it runs on).

``concurrent.futures.ProcessPoolExecutor`` was not used: one dead worker marks its
whole pool broken and fails every job running in it.

:class:`DaskExecutor` submits the same job body as a Dask task to a scheduler address.
"""
from __future__ import annotations

import logging
import os
import queue
import signal
import time
import uuid
from multiprocessing import connection as mp_connection
from pathlib import Path
from typing import Any

from . import worker as worker_module

log = logging.getLogger("rfesim.service.executor")


def _describe_exit(code: int | None) -> str:
    if code is None:
        return "is gone"
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        hint = " (killed from outside: the out-of-memory killer or an operator)" if -code == signal.SIGKILL else ""
        return f"was killed by {name}{hint}"
    return f"exited with code {code}"


class JobExecutor:
    """Interface (see the module docstring)."""

    kind = "abstract"

    def start(self) -> None: ...

    def free_slots(self) -> int:
        return 0

    def submit(self, job_id: str, spec: dict, results_path: Path) -> bool:
        raise NotImplementedError

    def cancel(self, job_id: str) -> None: ...

    def wait(self, timeout: float) -> list[tuple]:
        raise NotImplementedError

    def wake(self) -> None: ...

    def shutdown(self, write_grace: float = 0.0) -> list[tuple]:
        return []

    def status(self) -> dict[str, Any]:
        return {"kind": self.kind}


# --------------------------------------------------------------------------- local processes

class _Worker:
    def __init__(self, index: int, process, conn):
        self.index = index
        self.process = process
        self.conn = conn
        self.pid = process.pid
        self.ready = False
        self.job_id: str | None = None
        self.cancel_at: float | None = None
        self.writing_at: float | None = None     # when it said it writes the results file
        self.writing_t: float | None = None      # ... up to this output time (s)
        self.dead = False
        self.compiling = False


class ProcessExecutor(JobExecutor):
    kind = "local processes"

    STOP_GRACE = 3.0      # s a worker has to exit at the service's stop (one that writes results: more)

    def __init__(self, workers: int = 1, *, warmup: bool = True, cancel_grace: float = 10.0,
                 cancel_write_grace: float = 600.0, stagger_timeout: float = 120.0):
        self.size = int(workers)
        self.stagger_timeout = float(stagger_timeout)
        self._deferred: list[int] = []
        self._deferred_until = 0.0
        self.warmup = warmup
        self.cancel_grace = float(cancel_grace)
        self.cancel_write_grace = float(cancel_write_grace)
        self.workers: list[_Worker | None] = [None] * self.size
        self._respawn_at: dict[int, float] = {}
        self._failures: dict[int, int] = {}      # consecutive deaths before "ready", per slot
        self._events: list[tuple] = []
        self._wake_r, self._wake_w = os.pipe()
        os.set_blocking(self._wake_w, False)
        self._closed = False

    # ------------------------------------------------------------------ processes
    def start(self) -> None:
        """Start the first worker now and the others once it is ready (or after
        ``stagger_timeout`` s): with a cold numba cache the first one compiles and writes
        it, and the others only load it instead of all compiling at once."""
        self._spawn(0)
        self._deferred = list(range(1, self.size))
        self._deferred_until = time.monotonic() + self.stagger_timeout

    def _start_deferred(self) -> None:
        for i in self._deferred:
            if self.workers[i] is None and i not in self._respawn_at and not self._closed:
                self._spawn(i)
        self._deferred = []

    def _spawn(self, index: int) -> None:
        import multiprocessing

        from rfesim.sweep import worker_environment

        ctx = multiprocessing.get_context("spawn")
        parent_conn, child_conn = ctx.Pipe(duplex=True)
        process = ctx.Process(target=worker_module.process_main, args=(child_conn, self.warmup),
                              name=f"rfesim-worker-{index}", daemon=True)
        with worker_environment():       # the child inherits one numba/BLAS thread
            process.start()
        child_conn.close()
        self.workers[index] = _Worker(index, process, parent_conn)
        log.info("started worker %d (pid %s)", index, process.pid)

    def _kill(self, w: _Worker) -> None:
        try:
            w.process.kill()
        except (OSError, AttributeError):
            pass
        w.process.join(timeout=5)

    def _retire(self, w: _Worker, why: str) -> None:
        """A worker is dead (or was killed): fail its job, schedule a replacement."""
        w.dead = True
        try:
            w.conn.close()
        except OSError:
            pass
        w.process.join(timeout=1)
        if w.job_id is not None:
            if w.cancel_at is not None:
                self._events.append(("outcome", w.job_id, {
                    "status": "cancelled", "message": f"cancelled: {why}", "summary": None, "has_results": False,
                    "wall_time": None, "progress": None, "sim_time": None}))
            else:
                self._events.append(("outcome", w.job_id, {
                    "status": "failed", "message": f"the worker process (pid {w.pid}) running this job {why}; "
                                                   f"the job was not retried: resubmit it if the cause has gone",
                    "summary": None, "has_results": False, "wall_time": None, "progress": None,
                    "sim_time": None}))
            w.job_id = None
        if self._closed:
            return
        if not w.ready:
            n = self._failures.get(w.index, 0) + 1
            self._failures[w.index] = n
            delay = min(60.0, 0.5 * 2 ** n)
            log.error("worker %d (pid %s) %s before it was ready; restarting in %.3g s", w.index, w.pid, why, delay)
        else:
            delay = 0.0
            log.warning("worker %d (pid %s) %s; restarting it", w.index, w.pid, why)
        self.workers[w.index] = None
        self._respawn_at[w.index] = time.monotonic() + delay

    # ------------------------------------------------------------------ the seam
    def free_slots(self) -> int:
        return sum(1 for w in self.workers if w is not None and w.ready and w.job_id is None and not w.dead)

    def submit(self, job_id: str, spec: dict, results_path: Path) -> bool:
        for w in self.workers:
            if w is not None and w.ready and w.job_id is None and not w.dead:
                try:
                    w.conn.send(("run", {**spec, "id": job_id, "results_path": str(results_path)}))
                except (OSError, EOFError):
                    self._retire(w, _describe_exit(w.process.exitcode))
                    continue
                w.job_id = job_id
                w.cancel_at = None
                w.writing_at = w.writing_t = None
                self._events.append(("started", job_id, {"worker": f"local process {w.pid}", "pid": w.pid}))
                return True
        return False

    def cancel(self, job_id: str) -> None:
        for w in self.workers:
            if w is not None and w.job_id == job_id and not w.dead:
                if w.cancel_at is None:
                    w.cancel_at = time.monotonic()
                try:
                    w.conn.send(("cancel", job_id))
                except (OSError, EOFError):
                    pass               # its death is seen by wait()
                return

    def _deadline(self, w: _Worker) -> float | None:
        """When a cancelled job's worker is killed: ``cancel_grace`` s after the cancel, or,
        once the worker said it writes the results file, ``cancel_write_grace`` s after that
        note if later; None without a cancel."""
        if w.cancel_at is None:
            return None
        due = w.cancel_at + self.cancel_grace
        if w.writing_at is not None:
            due = max(due, w.writing_at + self.cancel_write_grace)
        return due

    def wake(self) -> None:
        try:
            os.write(self._wake_w, b"x")
        except (BlockingIOError, OSError):
            pass

    def wait(self, timeout: float) -> list[tuple]:
        now = time.monotonic()
        if self._deferred and now >= self._deferred_until:
            self._start_deferred()
        for index, due in list(self._respawn_at.items()):
            if due <= now and not self._closed:
                del self._respawn_at[index]
                self._spawn(index)
        if self._events:
            timeout = 0.0
        deadlines = [due for w in self.workers if w is not None and not w.dead
                     and (due := self._deadline(w)) is not None]
        deadlines += list(self._respawn_at.values())
        if self._deferred:
            deadlines.append(self._deferred_until)
        if deadlines:
            timeout = max(0.0, min(timeout, min(deadlines) - now))
        live = [w for w in self.workers if w is not None and not w.dead]
        objects: list[Any] = [self._wake_r] + [w.conn for w in live] + [w.process.sentinel for w in live]
        ready = set(mp_connection.wait(objects, timeout))
        if self._wake_r in ready:
            try:
                os.read(self._wake_r, 4096)
            except BlockingIOError:
                pass
        for w in live:
            if w.conn in ready:
                self._drain(w)
        for w in live:
            if not w.dead and w.process.sentinel in ready:
                self._drain(w)
                w.process.join(timeout=1)
                self._retire(w, _describe_exit(w.process.exitcode))
        now = time.monotonic()
        for w in list(self.workers):
            if w is None or w.dead:
                continue
            due = self._deadline(w)
            if due is None or now <= due:
                continue
            if w.writing_at is not None:
                log.warning("job %s: its results up to t = %.6g s were not written within %.3g s after its cancel: "
                            "killing worker pid %s", w.job_id, w.writing_t, self.cancel_write_grace, w.pid)
                self._kill(w)
                self._retire(w, f"its results up to t = {w.writing_t:.6g} s were not written within "
                                f"{self.cancel_write_grace:g} s of the start of the write (RFESIM_CANCEL_WRITE_GRACE), "
                                f"so its worker process was killed and replaced and the results are lost")
            else:
                log.warning("job %s did not stop within %.3g s of its cancel: killing worker pid %s",
                            w.job_id, self.cancel_grace, w.pid)
                self._kill(w)
                self._retire(w, f"did not stop within {self.cancel_grace:g} s (RFESIM_CANCEL_GRACE), so its worker "
                                f"process was killed and replaced")
        events, self._events = self._events, []
        return events

    def _drain(self, w: _Worker) -> None:
        try:
            while not w.dead and w.conn.poll():
                msg = w.conn.recv()
                kind = msg[0]
                if kind == "ready":
                    w.ready = True
                    w.compiling = False
                    self._failures.pop(w.index, None)
                    if self._deferred:
                        self._start_deferred()
                    log.info("worker %d (pid %s) ready (warm-up %.2f s)", w.index, msg[1], msg[2])
                elif kind == "progress" and msg[1] == w.job_id:
                    self._events.append(("progress", msg[1], msg[2], msg[3]))
                elif kind == "writing" and msg[1] == w.job_id:
                    w.writing_at, w.writing_t = time.monotonic(), float(msg[2])
                    self._events.append(("writing", msg[1], w.writing_t))
                elif kind == "compiling":
                    w.compiling = bool(msg[2])
                    if msg[1] is None:
                        log.warning("worker %d (pid %s) is compiling the numba kernels in its warm-up (a cold "
                                    "cache: the first start on this machine takes a few minutes)", w.index, w.pid)
                    elif msg[1] == w.job_id:
                        self._events.append(("compiling", msg[1], w.compiling))
                elif kind == "outcome" and msg[1] == w.job_id:
                    self._events.append(("outcome", msg[1], msg[2]))
                    w.job_id = None
                    w.cancel_at = None
                    w.writing_at = w.writing_t = None
                    w.compiling = False
        except (EOFError, OSError):
            pass                       # the sentinel says why

    def shutdown(self, write_grace: float = 0.0) -> list[tuple]:
        """Stop every worker and return the events that came meanwhile (an ``outcome`` of a
        job whose results were being written, the ``writing`` notes).

        Each worker is told to stop: a worker computing a run stops at its next output step
        without writing anything (its job is handed back to the queue by the manager), an idle
        one exits. Either has ``STOP_GRACE`` s and is then killed. A worker whose run is over
        and that writes its results file (it said "writing", before or during the stop) has
        ``write_grace`` s from the start of the stop (never less than ``STOP_GRACE``) to write
        it and report the job's outcome, and is killed after that (its job is re-queued: the
        partial file is removed at the next start). Before, every worker had 3 s and nothing
        it reported was read: a finished run whose file took longer was killed, and one whose
        file was written in time was re-queued anyway, its complete results recomputed."""
        self._closed = True
        workers = [w for w in self.workers if w is not None and not w.dead]
        for w in workers:
            try:
                w.conn.send(("stop",))
            except (OSError, EOFError):
                pass
        start = time.monotonic()
        stop_due = start + self.STOP_GRACE
        write_due = start + max(self.STOP_GRACE, float(write_grace))
        pending = list(workers)
        while pending:
            now = time.monotonic()
            for w in list(pending):
                if now <= (write_due if w.writing_at is not None else stop_due):
                    continue
                if w.writing_at is not None:
                    log.warning("job %s: its results up to t = %.6g s were not written within %.3g s of the "
                                "service's stop (RFESIM_SHUTDOWN_WRITE_GRACE): killing worker pid %s; the job "
                                "is re-queued", w.job_id, w.writing_t, write_due - start, w.pid)
                self._kill(w)
                self._close_worker(w)
                pending.remove(w)
            if not pending:
                break
            due = min(write_due if w.writing_at is not None else stop_due for w in pending)
            objects: list[Any] = [w.conn for w in pending] + [w.process.sentinel for w in pending]
            ready = set(mp_connection.wait(objects, max(0.0, due - time.monotonic())))
            for w in list(pending):
                if w.conn in ready:
                    self._drain(w)
                if w.process.sentinel in ready:
                    self._drain(w)
                    w.process.join(timeout=1)
                    self._close_worker(w)
                    pending.remove(w)
        for fd in (self._wake_r, self._wake_w):
            try:
                os.close(fd)
            except OSError:
                pass
        events, self._events = self._events, []
        return events

    def _close_worker(self, w: _Worker) -> None:
        """A worker gone at the stop: no outcome made up for its job (it is re-queued)."""
        w.dead = True
        try:
            w.conn.close()
        except OSError:
            pass

    def status(self) -> dict[str, Any]:
        workers = [w for w in self.workers if w is not None and not w.dead]
        return {"kind": self.kind, "total": self.size, "started": len(workers), "ready": sum(w.ready for w in workers),
                "busy": sum(w.job_id is not None for w in workers),
                "warming_up": sum(not w.ready for w in workers),
                "compiling": sum(w.compiling for w in workers),
                "pids": [w.pid for w in workers]}


# --------------------------------------------------------------------------- Dask

class DaskExecutor(JobExecutor):
    """Jobs as Dask tasks on the cluster of ``address``. At most as many jobs are handed
    to Dask as the cluster has worker threads; the rest wait in our queue (durable)."""

    kind = "dask"

    def __init__(self, address: str, *, progress_interval: float = 1.0):
        self.address = address
        self.progress_interval = progress_interval
        self.client = None
        self.progress_queue = f"rfesim-progress-{uuid.uuid4().hex[:12]}"
        self._progress = None
        self._q: queue.Queue = queue.Queue()
        self._running: dict[str, tuple[Any, Path]] = {}
        self._cancel_events: dict[str, str] = {}     # job id -> its distributed.Event (this hand-out's)
        self._cancelled: set[str] = set()
        self._writing: set[str] = set()              # jobs whose task said it writes its results
        self._threads = (0, 0.0)
        self._last_poll = 0.0

    def start(self) -> None:
        from distributed import Client, Queue

        self.client = Client(self.address, timeout=30, set_as_default=False)
        self._progress = Queue(self.progress_queue, client=self.client)
        log.info("connected to the Dask scheduler %s", self.address)

    def _nthreads(self) -> int:
        n, at = self._threads
        if time.monotonic() - at > 5.0:
            try:
                n = sum(self.client.nthreads().values())
            except Exception as exc:  # scheduler unreachable: take nothing new
                log.warning("Dask scheduler %s: %s", self.address, exc)
                n = 0
            self._threads = (n, time.monotonic())
        return n

    def free_slots(self) -> int:
        return max(0, self._nthreads() - len(self._running))

    def submit(self, job_id: str, spec: dict, results_path: Path) -> bool:
        # one cancel flag per hand-out, not per job: the flag lives on the scheduler, which
        # outlives this service, and a clean stop sets it for every running job (shutdown);
        # a flag named after the job alone would cancel the re-queued job at once after a
        # restart of the service
        submission = uuid.uuid4().hex[:12]
        cancel_event = f"rfesim-cancel-{job_id}-{submission}"
        fut = self.client.submit(worker_module.dask_task, {**spec, "id": job_id,
                                                           "progress_queue": self.progress_queue,
                                                           "cancel_event": cancel_event},
                                 key=f"rfesim-job-{job_id}-{submission}", pure=False, retries=0)
        self._running[job_id] = (fut, Path(results_path))
        self._cancel_events[job_id] = cancel_event
        fut.add_done_callback(lambda f, job_id=job_id: self._q.put(("done", job_id)))
        self._q.put(("started", job_id))
        return True

    def cancel(self, job_id: str) -> None:
        from distributed import Event

        item = self._running.get(job_id)
        if item is None:
            return
        try:
            Event(self._cancel_events[job_id], client=self.client).set()
            self._cancelled.add(job_id)
        except Exception as exc:
            log.warning("could not signal the cancel of %s: %s", job_id, exc)

    def wake(self) -> None:
        self._q.put(("wake", None))

    def wait(self, timeout: float) -> list[tuple]:
        events = []
        try:
            items = [self._q.get(timeout=min(timeout, self.progress_interval))]
        except queue.Empty:
            items = []
        while True:
            try:
                items.append(self._q.get_nowait())
            except queue.Empty:
                break
        for kind, job_id in items:
            if kind == "started" and job_id in self._running:
                events.append(("started", job_id, {"worker": f"dask {self.address}", "pid": None}))
            elif kind == "done" and job_id in self._running:
                events.append(("outcome", job_id, self._collect(job_id)))
        if time.monotonic() - self._last_poll >= self.progress_interval:
            self._last_poll = time.monotonic()
            events += self._poll_progress()
        return events

    def _poll_progress(self) -> list[tuple]:
        """One round trip for the progress of every running job (a distributed.Queue):
        ``[id, fraction, t]`` items, and ``[id, "writing", t]`` once a task writes its results
        file (Dask kills no task after a cancel, so this only changes the job's message)."""
        try:
            items = self._progress.get(batch=True)
        except Exception as exc:
            log.warning("progress from the Dask cluster: %s", exc)
            return []
        latest: dict[str, tuple[float, float]] = {}
        writing: list[tuple] = []
        for item in items:
            if isinstance(item, (list, tuple)) and len(item) == 3 and item[0] in self._running:
                try:
                    if item[1] == "writing":
                        writing.append(("writing", item[0], float(item[2])))
                        self._writing.add(item[0])
                    else:
                        latest[item[0]] = (float(item[1]), float(item[2]))
                except (TypeError, ValueError):
                    continue
        return [("progress", job_id, f, t) for job_id, (f, t) in latest.items()] + writing

    def _collect(self, job_id: str) -> dict:
        fut, path = self._running.pop(job_id)
        cancel_event = self._cancel_events.pop(job_id)
        self._writing.discard(job_id)
        if job_id in self._cancelled:               # drop the flag from the scheduler
            self._cancelled.discard(job_id)
            try:
                from distributed import Event

                Event(cancel_event, client=self.client).clear()
            except Exception:
                pass
        base = {"summary": None, "has_results": False, "wall_time": None, "progress": None, "sim_time": None}
        try:
            out = fut.result(timeout=60)
        except Exception as exc:
            name = type(exc).__name__
            if name == "KilledWorker":
                msg = ("the Dask worker running this job died (and so did its retries); the job was not "
                       "retried again: resubmit it if the cause has gone")
            elif name in ("CancelledError", "FutureCancelledError"):
                return {**base, "status": "cancelled", "message": "cancelled"}
            else:
                msg = f"the Dask task failed: {name}: {exc}"
            return {**base, "status": "failed", "message": msg}
        data = out.pop("results_bytes", None)
        if data is not None:
            try:
                _write_atomic(path, data)
            except OSError as exc:
                # a finished job whose results are lost failed; a cancelled one stays cancelled
                out.update(status="failed" if out.get("status") == "done" else out.get("status", "failed"),
                           has_results=False,
                           message=f"{out.get('message', '')}; the results could not be written: {exc}")
        return out

    def shutdown(self, write_grace: float = 0.0) -> list[tuple]:
        """Cancel the running tasks, but first wait (at most ``write_grace`` s) for those that
        said they write their results (their run is over) and return their outcomes."""
        if self.client is None:
            return []
        events = self._poll_progress()
        deadline = time.monotonic() + write_grace
        while True:
            writing = [job_id for job_id in self._running if job_id in self._writing]
            if not writing:
                break
            for job_id in writing:
                if self._running[job_id][0].done():
                    events.append(("outcome", job_id, self._collect(job_id)))
            if time.monotonic() >= deadline:
                break
            time.sleep(min(0.2, max(0.0, deadline - time.monotonic())))
            events += self._poll_progress()
        for job_id in list(self._running):
            self.cancel(job_id)
        try:
            self.client.cancel([f for f, _ in self._running.values()])
        except Exception:
            pass
        try:
            self.client.close(timeout=5)
        except Exception:
            pass
        return events

    def status(self) -> dict[str, Any]:
        return {"kind": self.kind, "scheduler": self.address, "total": self._threads[0],
                "busy": len(self._running), "ready": self._threads[0]}


def _write_atomic(path: Path, data: bytes) -> None:
    """Write bytes to ``path`` through a temporary file in the same folder and a rename."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:12]}.tmp")
    try:
        with open(tmp, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def make_executor(settings) -> JobExecutor:
    if settings.scheduler_address:
        return DaskExecutor(settings.scheduler_address)
    return ProcessExecutor(settings.workers, warmup=settings.warmup, cancel_grace=settings.cancel_grace,
                           cancel_write_grace=settings.cancel_write_grace)

