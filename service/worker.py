"""What runs outside the web process: one job = load the scenario, simulate, write the
results file, summarise.

Two ways in, one body (:func:`execute`):

* :func:`process_main` is the main function of a local worker process (see
  ``service.executor.ProcessExecutor``). It sets one numba/BLAS thread, imports rfesim,
  runs a tiny scenario so the numba cache is loaded before the first job, says "ready",
  then runs one job at a time from its pipe. Progress goes back over the pipe; a
  "cancel" message read from the pipe inside the progress callback stops the run
  (the callback raises, rfesim stops with CancelledError, which carries the results up to
  the last output step: the job keeps them). Before it writes a results file the worker
  says "writing" over the pipe: the executor then gives a cancelled job's write its own,
  longer deadline (a long run's file can take longer to write than the cancel grace).
  When the web process dies
  the worker ends within a second, whatever it is doing (a forked watcher process SIGKILLs
  it: :func:`watch_parent`), and the job it was running is re-queued at the service's next
  start. While numba compiles kernels (the first run on a machine, a cache miss) the worker
  says so over the pipe (:class:`CompileWatch`): the job's message and ``/health`` show it.
* :func:`dask_task` runs one job as a Dask task (``service.executor.DaskExecutor``):
  progress (and the "writing" note) through a ``distributed.Queue``, cancel through a
  ``distributed.Event``,
  the results file returned as bytes (a Dask worker need not share our disk).

This module imports nothing heavy at import time: the thread variables must be set
before numba is imported.
"""
from __future__ import annotations

import logging
import os
import signal
import sys
import tempfile
import threading
import time
import traceback
from pathlib import Path
from typing import Any, Callable

log = logging.getLogger("rfesim.service.worker")

THREAD_ENV = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1",
              "MKL_NUM_THREADS": "1"}

PROGRESS_INTERVAL = 0.2   # s of wall time between progress messages of one job
PARENT_CHECK_INTERVAL = 0.5   # s between two looks at whether the web process is still there
MAX_JOB_WARNINGS = 50     # warnings kept in a job's record (the server log has them all)
COMPILING_NOTE = "compiling numba kernels (first run on this machine, a few minutes)"

# a tiny scene that touches the common kernels: water, seabed, a heaving vessel, a pinned
# riser, a clamped cantilever with a point load, statics and generalised-alpha dynamics
WARMUP_SCENARIO: dict[str, Any] = {
    "schema_version": 1,
    "name": "worker warm-up",
    "environment": {"gravity": 9.81, "water": {"density": 1025.0, "depth": 20.0},
                    "seabed": {"normal_stiffness": 1.0e5, "damping_ratio": 0.5}},
    "vessels": {"v": {"motion": {"kind": "harmonic", "heave": {"amplitude": 0.5, "period": 5.0},
                                 "ramp_duration": 5.0}}},
    "line_types": {"p": {"outer_diameter": 0.2, "wall_thickness": 0.01, "youngs_modulus": 2.0e11,
                         "density": 7850.0, "drag_normal": 1.0, "drag_axial": 0.01, "added_mass_normal": 1.0,
                         "damping": {"axial_ratio": 0.02, "bending_ratio": 0.02}}},
    "lines": {
        "riser": {"type": "p", "length": 30.0, "elements": 4,
                  "end_a": {"attach": "fixed", "position": [-20.0, 0.0, -19.9]},
                  "end_b": {"attach": "v", "position": [0.0, 0.0, -2.0]}},
        "arm": {"type": "p", "length": 2.0, "elements": 2, "shear_stiffness": "fem",
                "end_a": {"attach": "fixed", "position": [5.0, 0.0, -5.0], "direction": [1.0, 0.0, 0.0],
                          "connection": "clamped"},
                "end_b": {"attach": "free"},
                "loads": [{"at": "end_b", "force": [0.0, 0.0, -100.0]}]},
    },
    "analysis": {"statics": {"enabled": True},
                 "dynamics": {"duration": 0.1, "output_interval": 0.05,
                              "integrator": {"kind": "generalized-alpha", "time_step": 0.025}}},
}


class Cancelled(Exception):
    """Raised by the progress callback to stop a run."""


class ParentGone(Cancelled):
    """The web process went away: stop the run and exit."""


def set_thread_environment() -> None:
    os.environ.update(THREAD_ENV)


def watch_parent(parent_pid: int, interval: float = PARENT_CHECK_INTERVAL) -> int | None:
    """Make this worker end within about ``interval`` s of the web process ``parent_pid``
    going away, whatever it is doing. Statics and the time steps between two output times
    call no progress callback, and a numba kernel holds the GIL, so neither a check in the
    callback nor a thread of this process can act while a long run is inside a kernel: a
    worker computed on for a minute after its service was SIGKILLed.

    On POSIX a small watcher process is forked (returns its pid): every ``interval`` s it
    looks whether the web process is gone (multiprocessing's parent sentinel, a pipe the
    parent holds open, reads end-of-file; else ``os.kill(pid, 0)``) and then SIGKILLs this
    worker; it exits by itself once this worker is gone (its ``os.getppid()`` changes).
    ``prctl(PR_SET_PDEATHSIG)`` is not used: Linux sends it when the parent *thread* that
    started the worker ends, and workers are started from the job manager's and the server's
    pool threads (a pool thread ends when idle). Without ``fork`` a daemon thread does the
    same check (it acts once the run is back in Python). The watcher closes every file it
    inherited but the sentinel and the standard streams."""
    import multiprocessing

    parent = multiprocessing.parent_process()
    sentinel = getattr(parent, "sentinel", None)
    if not hasattr(os, "fork"):
        thread = threading.Thread(target=_watch, args=(os.getpid(), parent_pid, sentinel, interval, False),
                                  name="rfesim-parent-watch", daemon=True)
        thread.start()
        return None
    worker = os.getpid()
    pid = os.fork()                 # the worker has one thread yet: no lock can be held
    if pid == 0:
        try:
            # keep only the standard streams and the sentinel: a copy of the pipe to the web
            # process, or of the end whose closing tells the web process this worker died
            # (its process sentinel), must not outlive the worker in here
            keep = sentinel if isinstance(sentinel, int) else 2
            os.closerange(3, keep)
            os.closerange(max(3, keep + 1), _max_fd())
            _watch(worker, parent_pid, sentinel, interval, True)
        finally:
            os._exit(0)
    return pid


def _max_fd() -> int:
    try:
        return max(256, min(os.sysconf("SC_OPEN_MAX"), 65536))
    except (AttributeError, ValueError, OSError):
        return 256


def _parent_gone(parent_pid: int, sentinel, interval: float) -> bool:
    if sentinel is not None:
        from multiprocessing import connection as mp_connection

        return bool(mp_connection.wait([sentinel], timeout=interval))
    time.sleep(interval)
    try:
        os.kill(parent_pid, 0)
    except ProcessLookupError:
        return True
    except OSError:
        pass
    return False


def _watch(worker: int, parent_pid: int, sentinel, interval: float, forked: bool) -> None:
    """The watch of :func:`watch_parent`: in the forked watcher (``forked``) or a thread."""
    try:
        while not _parent_gone(parent_pid, sentinel, interval):
            if forked and os.getppid() != worker:
                return                                 # the worker ended: so does its watcher
    except Exception:  # noqa: BLE001 - cannot watch: the pipe and the progress checks remain
        return
    if forked and os.getppid() != worker:
        # the worker died first (killed by the service after its cancel grace, or crashed) and
        # the service, cleaning up after it, closed the sentinel: nothing to stop or to say (it
        # said "the service is gone" of a healthy service, and SIGKILLed a dead pid)
        return
    try:
        os.kill(parent_pid, 0)
        gone = False
    except ProcessLookupError:
        gone = True
    except OSError:
        gone = False
    why = "is gone" if gone else "let go of it"
    try:
        sys.stderr.write(f"rfesim worker {worker}: the service (pid {parent_pid}) {why}; stopping it\n")
        sys.stderr.flush()
    except Exception:  # noqa: BLE001
        pass
    if forked:
        try:
            os.kill(worker, signal.SIGKILL)
        except OSError:
            pass
    else:
        os._exit(1)


class CompileWatch:
    """Notices numba compiling a kernel: numba's ``numba:compile`` event, which fires on a
    cache miss only (a kernel loaded from the cache fires nothing). ``on_compile()`` is
    called when an outermost compile starts; ``seconds`` adds up the outermost compiles'
    wall time; ``active`` is True while one runs. One per process: :func:`compile_watch`."""

    def __init__(self) -> None:
        self.depth = 0
        self.started = 0.0
        self.seconds = 0.0
        self.on_compile: Callable[[], None] | None = None

    @property
    def active(self) -> bool:
        return self.depth > 0

    def start(self) -> None:
        self.depth += 1
        if self.depth == 1:
            self.started = time.perf_counter()
            if self.on_compile is not None:
                try:
                    self.on_compile()
                except Exception:  # noqa: BLE001 - a note that cannot be sent must not stop the compile
                    pass

    def end(self) -> None:
        self.depth = max(0, self.depth - 1)
        if self.depth == 0:
            self.seconds += time.perf_counter() - self.started


_COMPILE_WATCH: CompileWatch | None = None


def compile_watch() -> CompileWatch:
    """This process's :class:`CompileWatch`, registered with numba on first use."""
    global _COMPILE_WATCH
    if _COMPILE_WATCH is None:
        from numba.core import event

        watch = CompileWatch()

        class Listener(event.Listener):
            def on_start(self, ev) -> None:
                watch.start()

            def on_end(self, ev) -> None:
                watch.end()

        event.register("numba:compile", Listener())
        _COMPILE_WATCH = watch
    return _COMPILE_WATCH


def _warning_key(text: str) -> str:
    """A warning without the "statics: " / "dynamics: " the run's log puts before it."""
    for prefix in ("statics: ", "dynamics: ", "scenario: ", "modal analysis: "):
        if text.startswith(prefix):
            return text[len(prefix):]
    return text


def merge_warnings(first: list[str], more: list[str], limit: int = MAX_JOB_WARNINGS) -> list[str]:
    """``first`` then those of ``more`` that say something new (the same text under another
    prefix is the same warning: the run logs again what the submit found), at most ``limit``
    (then a last entry says how many more the server log has)."""
    out = list(first)
    seen = {_warning_key(w) for w in out}
    extra = 0
    for w in more:
        key = _warning_key(w)
        if key in seen:
            continue
        seen.add(key)
        if len(out) >= limit:
            extra += 1
        else:
            out.append(w)
    if extra:
        out.append(f"... and {extra} more warnings (see the service's log)")
    return out


class _WarningLog(logging.Handler):
    """Keeps the messages of the warnings rfesim logs (not the service's own)."""

    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        if record.name.startswith("rfesim.service"):
            return
        try:
            self.messages.append(record.getMessage())
        except Exception:  # noqa: BLE001 - a bad record must not fail the job
            pass


WARMUP_PREFIX = "rfesim-warmup-"      # + the worker's pid + "-": the warm-up's temporary folder


def _remove_stale_warmups() -> None:
    """Remove the warm-up folders of workers that are gone (a worker killed while warming up
    leaves its folder: TemporaryDirectory's clean-up never runs), known by the pid in their
    name; the folders of live workers, and any other folder, are left alone."""
    import shutil

    root = Path(tempfile.gettempdir())
    try:
        folders = list(root.glob(f"{WARMUP_PREFIX}*-*"))
    except OSError:
        return
    for folder in folders:
        pid_text = folder.name[len(WARMUP_PREFIX):].split("-", 1)[0]
        if not pid_text.isdigit() or int(pid_text) == os.getpid():
            continue
        try:
            os.kill(int(pid_text), 0)
            continue                                   # its worker is alive
        except ProcessLookupError:
            pass
        except OSError:
            continue                                   # alive, another user's
        shutil.rmtree(folder, ignore_errors=True)


def warm_up() -> float:
    """Run the warm-up scenario (loads numba's cache, imports the netCDF writer; a cold cache
    is filled first by ``rfesim.precompile``, as every first run's); returns its wall time in s."""
    import rfesim

    from rfesim.sweep import summarize

    t0 = time.perf_counter()
    try:
        res = rfesim.simulate(WARMUP_SCENARIO)
        summarize(res)
        _remove_stale_warmups()
        with tempfile.TemporaryDirectory(prefix=f"{WARMUP_PREFIX}{os.getpid()}-") as tmp:
            res.to_netcdf(Path(tmp) / "warmup.nc")            # imports h5netcdf / h5py now
    except Exception:  # a warm-up that fails must not stop the worker: the job will say what is wrong
        log.warning("worker warm-up failed:\n%s", traceback.format_exc())
    return time.perf_counter() - t0


def execute(spec: dict, progress: Callable[[float, float], None], results_path: Path,
            writing: Callable[[float], None] | None = None) -> dict[str, Any]:
    """Run one job. ``spec``: ``{"id", "scenario"}`` (a scenario dict). ``progress(fraction,
    t)`` may raise :class:`Cancelled`. Writes ``results_path`` (atomically) when there are
    results: those of a finished run, and those recorded before a solver failure or a cancel
    (rfesim's ``CancelledError.results``: up to the last output step); ``writing(t)`` is
    called just before the file is written (``t``: the last output time, s). Returns the outcome:
    ``status`` (done / failed / cancelled), ``message``, ``summary``, ``wall_time``,
    ``has_results``, ``progress``, ``sim_time``, ``warnings`` (what rfesim logged as warnings
    during the run: statics, dynamics, template notes) and ``compile_time`` (s the run spent
    compiling numba kernels)."""
    watch = compile_watch()
    compiled0 = watch.seconds
    warnings = _WarningLog()
    rfesim_log = logging.getLogger("rfesim")
    rfesim_log.addHandler(warnings)
    try:
        out = _execute(spec, progress, results_path, writing)
    finally:
        rfesim_log.removeHandler(warnings)
    out["warnings"] = merge_warnings([], warnings.messages)
    out["compile_time"] = watch.seconds - compiled0
    return out


def _execute(spec: dict, progress: Callable[[float, float], None], results_path: Path,
             writing: Callable[[float], None] | None) -> dict[str, Any]:
    import rfesim
    from rfesim.sweep import _summary

    wall0 = time.perf_counter()
    last = {"fraction": 0.0, "t": None}

    def callback(fraction: float, t: float) -> None:
        last["fraction"], last["t"] = float(fraction), float(t)
        progress(float(fraction), float(t))

    def outcome(status, message, res=None, **kw):
        out = {"status": status, "message": message, "summary": None, "has_results": False,
               "progress": last["fraction"], "sim_time": last["t"]}
        if res is not None and len(res.time):
            if writing is not None:
                writing(float(res.time[-1]))
            try:
                res.to_netcdf(results_path)
            except OSError as exc:
                # a finished run whose results are lost failed; a cancelled one stays cancelled
                out.update(status="failed" if status == "done" else status,
                           message=f"{message}; the results could not be written: {exc}")
            else:
                out["has_results"] = True
            # the summary columns and, beside them as in rfesim sweep's table, where the max top
            # tension is ("riser end B"); a crane's structure with the real frame's moments when the
            # scenario's crane template gives its luffing cylinder or rope
            summary, where = _summary(res, spec.get("scenario"))
            out["summary"] = {**summary, "top_tension_at": where}
            out["sim_time"] = float(res.time[-1])
        out.update(kw)
        out["wall_time"] = time.perf_counter() - wall0
        return out

    try:
        sc = rfesim.load_scenario(spec["scenario"])
        res = rfesim.simulate(sc, progress=callback)
    except (rfesim.CancelledError, Cancelled) as exc:
        cause = exc.__cause__ if exc.__cause__ is not None else exc
        if isinstance(cause, ParentGone):
            raise cause from None
        where = f" at t = {last['t']:.6g} s" if last["t"] is not None else ""
        part = getattr(exc, "results", None)
        if part is not None and len(part.time):
            # the dynamics recorded up to the cancel: kept (results.nc, summary), as for a
            # failed run
            return outcome("cancelled", f"cancelled while running{where}; the results up to "
                                        f"t = {float(part.time[-1]):.6g} s are kept", part)
        return outcome("cancelled", f"cancelled while running{where}")
    except rfesim.SolverError as exc:
        return outcome("failed", f"solver error: {exc}", exc.results)
    except rfesim.ScenarioError as exc:
        return outcome("failed", f"scenario error: {exc}")
    except MemoryError:
        return outcome("failed", "out of memory: the scenario needs more memory than the worker has "
                                 "(fewer elements, a shorter duration or a longer output_interval)")
    except Exception as exc:  # a bug: say what, keep the worker
        log.error("job %s failed:\n%s", spec.get("id"), traceback.format_exc())
        return outcome("failed", f"internal error: {type(exc).__name__}: {exc}")
    if len(res.time) <= 1:
        # a run with no output step (statics only): a cancel that came while statics solved had no
        # step to stop at, and the job ended "done" although DELETE had answered that it stops;
        # it stops here, at its one output (the static solution), which it keeps
        try:
            progress(1.0, float(res.time[-1]) if len(res.time) else 0.0)
        except Cancelled as exc:
            if isinstance(exc, ParentGone):
                raise
            return outcome("cancelled", "cancelled during statics (a run with no output step before its end); "
                                        "the static solution is kept", res)
    return outcome("done", res.message, res, progress=1.0)


# --------------------------------------------------------------------------- local process

def process_main(conn, warmup: bool = True) -> None:
    """Main function of a local worker process: ``("run", spec)`` in, messages out.

    Out: ``("ready", pid, warmup_seconds)``, ``("started", job_id)``,
    ``("progress", job_id, fraction, t)``, ``("writing", job_id, t)`` (the results file up
    to the output time ``t`` is being written: the executor's deadline of a cancelled job
    becomes the write grace), ``("outcome", job_id, outcome)``.
    In: ``("run", spec)``, ``("cancel", job_id)``, ``("stop",)``.
    """
    set_thread_environment()
    signal.signal(signal.SIGINT, signal.SIG_IGN)     # Ctrl-C goes to the web process, which stops us
    import multiprocessing

    parent_process = multiprocessing.parent_process()
    parent = parent_process.pid if parent_process is not None and parent_process.pid else os.getppid()
    watch_parent(parent)
    # numba compiling (a cold cache): say so once per stretch, the job's progress clears it
    watch = compile_watch()
    compiling = {"job": None, "said": False}

    def say_compiling() -> None:
        if not compiling["said"]:
            compiling["said"] = True
            conn.send(("compiling", compiling["job"], True))

    watch.on_compile = say_compiling
    seconds = warm_up() if warmup else 0.0
    compiling["said"] = False                          # "ready" ends the warm-up's compiling
    try:
        conn.send(("ready", os.getpid(), seconds))
    except (OSError, EOFError):
        return
    while True:
        try:
            msg = conn.recv()
        except (EOFError, OSError):
            return                                    # the web process is gone
        if msg[0] == "stop":
            return
        if msg[0] != "run":
            continue                                  # e.g. a late cancel of a finished job
        spec = msg[1]
        job_id = spec["id"]
        state = {"last": 0.0}
        compiling.update(job=job_id, said=False)

        def progress(fraction: float, t: float, job_id=job_id, state=state) -> None:
            if compiling["said"] and not watch.active:
                compiling["said"] = False
                try:
                    conn.send(("compiling", job_id, False))
                except (OSError, EOFError):
                    raise ParentGone("the service is gone") from None
            now = time.monotonic()
            if now - state["last"] >= PROGRESS_INTERVAL:
                state["last"] = now
                try:
                    conn.send(("progress", job_id, fraction, t))
                except (OSError, EOFError):
                    raise ParentGone("the service is gone") from None
            if os.getppid() != parent:
                raise ParentGone("the service is gone")
            try:
                while conn.poll():
                    m = conn.recv()
                    if m[0] == "cancel" and m[1] == job_id:
                        raise Cancelled("cancelled")
                    if m[0] == "stop":
                        raise ParentGone("the service is stopping")
            except (EOFError, OSError):
                raise ParentGone("the service is gone") from None

        def writing(t: float, job_id=job_id) -> None:
            try:
                conn.send(("writing", job_id, t))
            except (OSError, EOFError):
                raise ParentGone("the service is gone") from None

        try:
            conn.send(("started", job_id))
            result = execute(spec, progress, Path(spec["results_path"]), writing)
        except ParentGone:
            return
        except (OSError, EOFError):
            return
        compiling.update(job=None, said=False)
        try:
            conn.send(("outcome", job_id, result))
        except (OSError, EOFError):
            return


# --------------------------------------------------------------------------- Dask task

def dask_task(spec: dict) -> dict[str, Any]:
    """Run one job on a Dask worker; the outcome carries the results file as bytes.

    Progress goes to the ``distributed.Queue`` named in the spec, at most once a second
    (``[job_id, fraction, t]``), and so does the note that the results file is being
    written (``[job_id, "writing", t]``); the cancel flag is the ``distributed.Event``
    named in the spec (``cancel_event``: one per hand-out of the job, so a flag set when
    the service stopped does not cancel the job handed out again after its restart),
    checked twice a second."""
    set_thread_environment()
    from distributed import Event, Queue

    job_id = spec["id"]
    progress_queue = Queue(spec["progress_queue"]) if spec.get("progress_queue") else None
    cancel = Event(spec.get("cancel_event") or f"rfesim-cancel-{job_id}")
    state = {"sent": 0.0, "checked": 0.0}

    def progress(fraction: float, t: float) -> None:
        now = time.monotonic()
        if progress_queue is not None and now - state["sent"] >= 1.0:
            state["sent"] = now
            progress_queue.put([job_id, fraction, t])
        if now - state["checked"] >= 0.5:
            state["checked"] = now
            if cancel.is_set():
                raise Cancelled("cancelled")

    def writing(t: float) -> None:
        if progress_queue is not None:
            try:
                progress_queue.put([job_id, "writing", t])
            except Exception as exc:  # noqa: BLE001 - a note that cannot be sent must not lose the results
                log.warning("job %s: could not say that its results are being written: %s", job_id, exc)

    if cancel.is_set():
        return {"status": "cancelled", "message": "cancelled before it started", "summary": None,
                "has_results": False, "wall_time": 0.0, "progress": 0.0, "sim_time": None}
    with tempfile.TemporaryDirectory(prefix="rfesim-job-") as tmp:
        path = Path(tmp) / "results.nc"
        out = execute(spec, progress, path, writing)
        out["results_bytes"] = path.read_bytes() if out["has_results"] else None
    return out
