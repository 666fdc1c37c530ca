"""The ``rfesim`` command line (see CONTRACT.md): parse, call the library, format.

    rfesim run SCENARIO [-o OUT.nc] [--plot OUT.png]   # statics + dynamics, progress bar
    rfesim statics SCENARIO [-o OUT.nc]
    rfesim modes SCENARIO [-n 10]
    rfesim check SCENARIO [--expand]                   # validate only, clear errors
    rfesim bench [--quick] [--only PART]               # work-precision report (--help: every option)
    rfesim serve [--host 127.0.0.1 --port 8000]        # the HTTP service
    rfesim sweep SCENARIO --vary path=v1,v2,... [--scheduler ADDRESS]
    rfesim schema [--json | --markdown] [-o FILE]      # the scenario's JSON Schema, or its field reference

Exit codes: 0 success; 1 bad input (scenario error, missing file); 2 usage error or a
missing optional component (an analysis not provided for the scene: rfesim.UnsupportedError); 3 the solver failed (partial results are still written);
130 interrupted (Ctrl-C, or SIGTERM during `run` and `sweep`: `run` writes the results
recorded so far, status 2, and its plot, and a further Ctrl-C or SIGTERM does not stop that
write; `sweep` keeps the rows of the finished cases in its CSV).
"""
from __future__ import annotations

import argparse
import contextlib
import importlib
import importlib.util
import logging
import os
import sys
import time
from pathlib import Path

EXIT_OK = 0
EXIT_INPUT = 1
EXIT_USAGE = 2
EXIT_SOLVER = 3
EXIT_INTERNAL = 4          # an unexpected exception: a bug (RFESIM_DEBUG=1 shows its traceback)
EXIT_INTERRUPTED = 130


class CliError(Exception):
    """A failure the CLI reports as one message and an exit code, without a traceback."""

    def __init__(self, message: str, code: int = EXIT_INPUT):
        super().__init__(message)
        self.code = code


# --------------------------------------------------------------------------- helpers

def _err(*lines: str) -> None:
    for line in lines:
        print(line, file=sys.stderr)


def _scenario_path(path: str) -> Path:
    p = Path(path)
    if not p.exists():
        raise CliError(f"error: scenario file not found: {path}")
    if not p.is_file():
        raise CliError(f"error: not a file: {path}")
    return p


def _load(path: str):
    import rfesim

    return rfesim.load_scenario(_scenario_path(path))


def _output_path(out: str | None, scenario: Path, default_suffix: str | None, results: bool = False) -> Path | None:
    """The output file: ``out``, or ``<scenario stem><suffix>`` in the current directory;
    ``results``: a results file (netCDF), which may replace only an earlier one."""
    if out is None:
        if default_suffix is None:
            return None
        out = scenario.stem + default_suffix
    p = Path(out)
    if out.endswith(("/", os.sep)):     # "newdir/": a folder (Path drops the slash), not a file called newdir
        if p.is_dir():
            raise CliError(f"error: the output path is a folder: {out} (give a file in it)")
        raise CliError(f"error: the output folder does not exist: {out}")
    folder = p.parent if str(p.parent) else Path(".")
    if not folder.is_dir():
        raise CliError(f"error: the output folder does not exist: {folder}")
    if p.is_dir():
        raise CliError(f"error: the output path is a folder: {p}")
    if p.exists() and p.resolve() == scenario.resolve():
        raise CliError(f"error: the output file would overwrite the scenario: {p}")
    if p.is_file():
        _check_replaceable(p, results)
    check_writable(p)
    return p


HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def _check_replaceable(p: Path, results: bool) -> None:
    """CliError when the existing file ``p`` is not one an output may replace: a scenario
    file (JSON or YAML: another scenario, not the run's own, is still somebody's input), or
    for a results file (``rfesim run/statics -o``) anything but an earlier results file
    (HDF5/netCDF)."""
    if p.suffix.lower() in (".json", ".yaml", ".yml"):
        raise CliError(f"error: the output file {p} exists and is a {p.suffix.lstrip('.').upper()} file "
                       "(a scenario?): it would be replaced; give another name (results: .nc)")
    if results:
        try:
            with open(p, "rb") as f:
                head = f.read(len(HDF5_SIGNATURE))
        except OSError:
            return                      # check_writable says why
        if head and head != HDF5_SIGNATURE:
            raise CliError(f"error: the output file {p} exists and is not a results file (netCDF/HDF5): "
                           "it would be replaced; give another name or remove it first")


def check_writable(p: Path) -> None:
    """CliError now, before a long run, when the file ``p`` cannot be written (a folder that
    is read-only, or a file that is): a probe file is created and removed beside it."""
    import tempfile

    folder = p.parent if str(p.parent) else Path(".")
    try:
        if p.exists():
            with open(p, "ab"):
                pass
        else:
            with tempfile.NamedTemporaryFile(dir=folder, prefix=f".{p.name}.", suffix=".probe"):
                pass
    except OSError as exc:
        raise CliError(f"error: cannot write {p}: {exc.strerror or exc}") from None


def _plot_path(plot: str, scenario: Path, out: Path | None) -> Path:
    """The --plot file: a writable path, not the results file, in a format matplotlib writes."""
    p = _output_path(plot, scenario, None)
    if out is not None and (p.resolve() == out.resolve()):
        raise CliError(f"error: --plot and -o name the same file ({p}): the plot would replace the results",
                       EXIT_USAGE)
    suffix = p.suffix.lower().lstrip(".")
    from .plot import _pyplot

    plt = _pyplot()
    fig = plt.figure()
    formats = fig.canvas.get_supported_filetypes()
    plt.close(fig)
    known = ", ".join("." + f for f in sorted(formats))
    if not suffix:      # matplotlib would add one of its own and write plot.png for "plot"
        raise CliError(f"error: --plot {plot}: give the image format as the file's extension, e.g. {plot}.png "
                       f"(one of {known})", EXIT_USAGE)
    if suffix not in formats:
        raise CliError(f"error: --plot {plot}: matplotlib cannot write '.{suffix}' files; give one of {known}",
                       EXIT_USAGE)
    return p


def _write(res, path: Path) -> None:
    try:
        res.to_netcdf(path)
    except OSError as exc:     # Results.to_netcdf's reason ("the folder ... does not exist"), without [Errno]
        raise CliError(f"error: could not write {path}: {exc.strerror or exc}") from None
    except Exception as exc:   # h5py's ValueError (a name it cannot take as a group), ...: say so, no traceback
        raise CliError(f"error: could not write the results to {path} ({type(exc).__name__}: {exc}); "
                       f"the results of this run are lost") from None


@contextlib.contextmanager
def sigterm_as_interrupt():
    """Within the block SIGTERM (a batch system stopping the job) raises KeyboardInterrupt,
    as Ctrl-C does, so that what was computed is kept; in the main thread only."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum, frame):
        raise KeyboardInterrupt(f"signal {signum}")

    old = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old if old is not None else signal.SIG_DFL)


class _RunSignals:
    """SIGINT and SIGTERM during ``rfesim run`` (a context manager; the main thread only).

    While the run computes, the first of them raises KeyboardInterrupt (SIGTERM too: a batch
    system stopping the job), with which rfesim.simulate hands back the results so far. Any
    later one, and any one once the run is ``finishing`` (its results and plot being written),
    is only noted, with one line on stderr: a second Ctrl-C in the write used to remove the
    half-written file and lose every result, and one while the process was ending made its
    exit code -2 rather than 130. ``interrupted`` says whether a signal (or a
    KeyboardInterrupt) came; the command then exits 130.

    ``keep_ignoring``: when a signal came, leave SIGINT and SIGTERM ignored after the block
    (the program is about to exit 130, and the interpreter's shutdown takes a few tenths of
    a second); otherwise the caller's handlers are restored (``main`` called in-process)."""

    _SIGNALS = ("SIGINT", "SIGTERM")

    def __init__(self, out: Path | None, keep_ignoring: bool = False):
        self.out = out
        self.keep_ignoring = keep_ignoring
        self.interrupted = False
        self._finishing = False
        self._noted = False
        self._old: dict = {}

    def __enter__(self):
        import signal
        import threading

        if threading.current_thread() is threading.main_thread():
            for name in self._SIGNALS:
                num = getattr(signal, name)
                self._old[num] = signal.signal(num, self._handle)
        return self

    def __exit__(self, *exc):
        import signal

        for num, old in self._old.items():
            if self.interrupted and self.keep_ignoring:
                signal.signal(num, signal.SIG_IGN)
            else:
                signal.signal(num, old if old is not None else signal.SIG_DFL)
        return False

    def finishing(self, interrupted: bool = False) -> None:
        """From now on signals do not interrupt: the results are being written."""
        self._finishing = True
        self.interrupted = self.interrupted or interrupted

    def _handle(self, signum, frame):
        if not (self._finishing or self.interrupted):
            self.interrupted = True
            raise KeyboardInterrupt(f"signal {signum}")
        self.interrupted = True
        if not self._noted and self.out is not None:
            try:    # not _err: a signal that arrives inside a write to stderr must not break it
                sys.stderr.write(f"still writing the results to {self.out}, please wait\n")
                sys.stderr.flush()
                self._noted = True
            except (RuntimeError, ValueError, OSError):   # a reentrant write, a closed stream
                pass


def _kn(x: float) -> str:
    return f"{x / 1e3:.6g}"


def _vector_kn(force) -> str:
    """``[fx, fy, fz]`` in kN, round-off (below 1e-9 of the largest component) shown as 0."""
    import numpy as np

    f = np.asarray(force, dtype=float)
    f = np.where(np.abs(f) <= 1e-9 * np.max(np.abs(f), initial=0.0), 0.0, f) + 0.0  # + 0.0: no "-0"
    return "[" + ", ".join(f"{x / 1e3:.5g}" for x in f) + "]"


def _table(header: list[str], rows: list[list[str]], indent: str = "  ") -> list[str]:
    """Right-aligned columns (the first left-aligned)."""
    widths = [max(len(str(r[i])) for r in [header] + rows) for i in range(len(header))]
    out = []
    for r in [header] + rows:
        cells = [str(c).ljust(w) if i == 0 else str(c).rjust(w) for i, (c, w) in enumerate(zip(r, widths))]
        out.append(indent + "  ".join(cells).rstrip())
    return out


def _line_extremes(res, sc=None) -> list[str]:
    """Per line: max top tension (the end held on board, rfesim.sweep.line_top_tension, and
    which force it is), max/min tension, max bend moment over the run; a crane's structure
    lines with the real frame's loads (rfesim.crane_results.structure_loads)."""
    import numpy as np

    from .crane_results import structure_loads
    from .sweep import line_top_tension

    crane = structure_loads(res, sc)
    rows = []
    for name, lr in res.lines.items():
        if len(res.time) == 0:
            rows.append([name, "-", "-", "-", "-", "-"])
            continue
        top, where = line_top_tension(res, name)
        tension, bend = np.asarray(lr.tension), np.asarray(lr.bend_moment)
        if name in crane:
            m = crane[name]
            tension, bend = m["axial_force"], m["bend_moment"]
            top = np.linalg.norm(m["end_a_force" if where == "end A" else "end_b_force"], axis=-1)
        rows.append([name, _kn(float(np.nanmax(top))), where, _kn(float(np.max(tension))),
                     _kn(float(np.min(tension))), _kn(float(np.max(bend)))])
    return _table(["line", "max top tension [kN]", "taken at", "max tension [kN]", "min tension [kN]",
                   "max bend moment [kN*m]"], rows) + _crane_note(crane)


def _crane_note(crane: dict) -> list[str]:
    """What the crane structure rows of the line tables hold (rfesim.crane_results.structure_loads)."""
    real = [n for n, m in crane.items() if m["of"] == "real frame"]
    model = [n for n, m in crane.items() if m["of"] != "real frame"]
    out = []
    if real:
        out.append(f"  {', '.join(real)}: loads of the real crane frame, its luffing cylinders or rope at their eye "
                   f"(crane_summary; the results file keeps the model's, docs/theory.md 'Member loads of the real "
                   f"frame')")
    if model:
        out.append(f"  {', '.join(model)}: loads of the model, whose luffing joint carries the drive's moment (no "
                   f"cylinder or luffing rope in the crane template to put at its eye)")
    return out


def _run_summary(res, wall: float, sc=None) -> list[str]:
    c = res.counters
    nt = len(res.time)
    lines = []
    if res.kind == "statics":
        lines.append(f"statics only ({c.get('statics_iterations', c.get('newton_iterations', '?'))} Newton "
                     f"iterations), wall time {wall:.3g} s")
    else:
        simulated = float(res.time[-1] - res.time[0]) if nt else 0.0
        step = c.get("time_step")
        halvings = int(c.get("step_halvings", 0) or 0)
        if isinstance(step, (int, float)) and halvings:
            # the steps then include the halves of the halved ones
            step_txt = (f" (time step {step:.4g} s, {halvings} step halving{'s' if halvings != 1 else ''} where "
                        f"Newton needed a shorter step)")
        elif isinstance(step, (int, float)) and c.get("rejected_steps") is None:
            step_txt = f" of {step:.4g} s"
        elif isinstance(step, (int, float)):
            step_txt = f" (adaptive, first step {step:.4g} s, {c.get('rejected_steps', 0)} rejected)"
        else:
            step_txt = ""
        lines.append(f"simulated {simulated:.6g} s: {c.get('steps', 0)} steps{step_txt}, {nt} output times, "
                     f"wall time {wall:.3g} s")
    return lines + _line_extremes(res, sc)


# --------------------------------------------------------------------------- commands

def cmd_check(args) -> int:
    sc = _load(args.scenario)
    if getattr(args, "expand", False):
        # the scenario with its pipelay and crane templates expanded (rfesim.scenario.expand), as JSON
        import json

        from .scenario import expand, parse_text
        from .scenario.files import resolve_data_files
        from .scenario.load import _read_file
        path = _scenario_path(args.scenario)
        data = parse_text(*_read_file(path))
        # data files as absolute paths: the printed scenario works saved anywhere
        data = resolve_data_files(data, path.parent)
        print(json.dumps(resolve_data_files(expand(data), path.parent), indent=2))
        return EXIT_OK
    from .errors import ScenarioError
    from .scenario.load import check_runnable
    if check_runnable(sc):          # what `run` refuses too (rfesim.model.compile)
        raise ScenarioError(check_runnable(sc))
    from .api import check_model
    found = check_model(sc)         # and what compiling the model refuses (no solve)
    for w in getattr(sc, "_template_warnings", []):
        # a template's warnings (a mesh too coarse for the rollers), as a run logs them
        logging.getLogger("rfesim").warning("scenario: %s", w)
    for w in found:                 # the built model's (no unique static shape), as statics logs them
        logging.getLogger("rfesim").warning("statics: %s", w)
    from .scenario.motion_warnings import input_motion_warnings
    for w in input_motion_warnings(sc):   # motions that start or stop with a jolt, as the run's message has them
        logging.getLogger("rfesim").warning("dynamics: %s", w)
    an = sc.analysis
    parts = [f"{len(sc.lines)} lines", f"{len(sc.vessels)} vessels", f"{len(sc.line_types)} line types",
             f"{sum(li.elements for li in sc.lines.values())} elements"]
    analyses = []
    if an.statics.enabled:
        analyses.append("statics")
    if an.dynamics.enabled and an.dynamics.duration > 0:
        integ = an.dynamics.integrator
        step = getattr(integ, "time_step", None)
        analyses.append(f"dynamics {an.dynamics.duration:g} s ({integ.kind}"
                        + (f", step {step:g} s" if step else "") + ")")
    if an.modal is not None:
        analyses.append(f"{an.modal.modes} modes")
    print(f"OK: {sc.name}: {', '.join(parts)}; " + (", ".join(analyses) or "no analysis enabled"))
    return EXIT_OK


def cmd_schema(args) -> int:
    """The scenario's JSON Schema (``rfesim.Scenario.model_json_schema()``), or with
    ``--markdown`` the field reference of docs/scenario.md (rfesim.scenario.reference)."""
    if args.format == "markdown":
        from .scenario.reference import scenario_reference_markdown

        text = scenario_reference_markdown()
    else:
        import json

        from .scenario import Scenario

        text = json.dumps(Scenario.model_json_schema(), indent=2) + "\n"
    if args.output is None:
        sys.stdout.write(text)
        return EXIT_OK
    path = Path(args.output)
    if path.is_dir():
        raise CliError(f"error: the output path is a folder: {path}")
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise CliError(f"error: could not write {path}: {exc.strerror or exc}") from None
    _err(f"{'scenario reference' if args.format == 'markdown' else 'JSON Schema'} written to {path}")
    return EXIT_OK


def numba_cache_is_cold() -> bool:
    """True when the compiled numba kernels are not in the cache yet (rfesim._precompile.cache_is_cold)."""
    from ._precompile import cache_is_cold

    return cache_is_cold()


def _note_cold_cache() -> None:
    """A cold cache: say so, and compile the kernels ahead in parallel processes
    (rfesim.precompile; RFESIM_PRECOMPILE=0 leaves them to compile as the run calls them)."""
    if numba_cache_is_cold():
        from ._precompile import precompile, processes_default

        n = processes_default()
        if n < 2:          # one process compiles them as the run calls them: no more than it needs
            _err("compiling the numba kernels: the first run after an install takes several minutes (about 8 in "
                 "one process); they are cached, so later runs start in seconds")
            return
        _err(f"compiling the numba kernels in {n} processes: the first run after an install takes several "
             "minutes (about 4 on 2 cores); they are cached, so later runs start in seconds")
        tty = sys.stderr.isatty()

        def progress(done: int, total: int) -> None:
            sys.stderr.write(f"\r  {done} of {total} kernels compiled")
            sys.stderr.flush()

        t0 = time.perf_counter()
        try:
            total = precompile(n, progress=progress if tty else None)
            if tty:
                sys.stderr.write("\n")
            if total:
                _err(f"{total} kernels compiled in {time.perf_counter() - t0:.0f} s")
        except Exception as exc:   # the run compiles what it calls, as without it
            _err(f"note: compiling the kernels ahead failed ({type(exc).__name__}: {exc}); the run compiles "
                 "them as it calls them")


def _progress_bar(args):
    from .progress import ProgressBar

    if args.progress is False:
        return None
    if args.progress:
        return ProgressBar(sys.stderr, delay=0.0)
    if sys.stderr.isatty():
        return ProgressBar(sys.stderr, delay=1.0)
    return None


def cmd_run(args) -> int:
    import rfesim

    scenario = _scenario_path(args.scenario)
    out = _output_path(args.output, scenario, ".nc", results=True)
    if args.plot:
        _plot_path(args.plot, scenario, out)
    sc = rfesim.load_scenario(scenario)
    _note_cold_cache()
    bar = _progress_bar(args)
    wall0 = time.perf_counter()
    failure = interrupted = None
    with _RunSignals(out, keep_ignoring=getattr(args, "program", False)) as signals:
        try:
            res = rfesim.simulate(sc, progress=bar)
        except rfesim.SolverError as exc:
            failure = exc
        except KeyboardInterrupt as exc:
            interrupted = exc
        finally:
            signals.finishing(interrupted is not None)
            if bar is not None:
                bar.close()
        if interrupted is not None:
            return _interrupted(interrupted, out, args.plot)
        if failure is not None:
            code = _solver_failure(failure, out, args.plot)
        else:
            code = _finished(res, sc, out, args.plot, time.perf_counter() - wall0)
        if signals.interrupted:     # Ctrl-C while the results were written: they are whole, but say it came
            _err("interrupted after the run had ended" + (f": its results were written to {out} first"
                                                          if code == EXIT_OK else ""))
            return EXIT_INTERRUPTED
        return code


def _finished(res, sc, out: Path, plot: str | None, wall: float) -> int:
    _write(res, out)
    print(f"{sc.name}: {_summary_message(res.message)}")
    for line in _run_summary(res, wall, sc):
        print(line)
    print(f"results written to {out}")
    if plot:
        from .plot import plot_results

        plot_results(res, plot)
        print(f"plot written to {plot}")
    return EXIT_OK


def _interrupted(exc: KeyboardInterrupt, out: Path | None, plot: str | None = None) -> int:
    """Ctrl-C or SIGTERM during a run: write (and plot) the results recorded so far (status 2,
    "interrupted at t = ..."; rfesim.simulate attaches them to the interruption as ``results``),
    as a solver failure does."""
    res = getattr(exc, "results", None)
    if res is None or not len(res.time):
        _err("interrupted before any results were recorded: nothing written")
        return EXIT_INTERRUPTED
    _err(_summary_message(res.message))        # "interrupted at t = ... s"
    if out is not None:
        _write(res, out)
        _err(f"partial results ({len(res.time)} output times, t = {res.time[0]:.6g} .. {res.time[-1]:.6g} s, "
             f"status {res.status}) written to {out}")
    if plot:
        from .plot import plot_results

        plot_results(res, plot)
        _err(f"plot of the partial results written to {plot}")
    return EXIT_INTERRUPTED


def _solver_failure(exc, out: Path | None, plot: str | None = None) -> int:
    """Report a SolverError; write (and plot) the results computed before it, if any. An
    analysis not provided for the scene (rfesim.errors.UnsupportedError) is a missing
    component: exit 2, not 3."""
    from .errors import UnsupportedError
    if isinstance(exc, UnsupportedError):
        _err(f"error: {exc}")
        return EXIT_USAGE
    _err(f"solver error: {exc}")
    res = getattr(exc, "results", None)
    if res is not None and len(res.time):
        if out is not None:
            _write(res, out)
            _err(f"partial results ({len(res.time)} output times, t = {res.time[0]:.6g} .. {res.time[-1]:.6g} s) "
                 f"written to {out}")
        if plot:
            from .plot import plot_results

            plot_results(res, plot)
            _err(f"plot of the partial results written to {plot}")
    return EXIT_SOLVER


def cmd_statics(args) -> int:
    import numpy as np

    import rfesim

    scenario = _scenario_path(args.scenario)
    out = _output_path(args.output, scenario, None, results=True)
    sc = rfesim.load_scenario(scenario)
    _note_cold_cache()
    wall0 = time.perf_counter()
    try:
        res = rfesim.statics(sc)
    except rfesim.SolverError as exc:
        return _solver_failure(exc, out)
    wall = time.perf_counter() - wall0
    print(f"{sc.name}: statics {_summary_message(res.message)} (wall time {wall:.3g} s)")
    from .crane_results import structure_loads

    crane = structure_loads(res, sc)
    rows = []
    for name, lr in res.lines.items():
        fa, fb, tension = lr.end_a_force[-1], lr.end_b_force[-1], lr.tension[-1]
        if name in crane:           # a crane's structure: the real frame's loads
            m = crane[name]
            fa, fb, tension = m["end_a_force"][-1], m["end_b_force"][-1], m["axial_force"][-1]
        rows.append([name, _vector_kn(fa), _kn(float(np.linalg.norm(fa))), _vector_kn(fb), _kn(float(np.linalg.norm(fb))),
                     _kn(float(tension.min())), _kn(float(tension.max()))])
    for line in _table(["line", "end A force [kN]", "|A| [kN]", "end B force [kN]", "|B| [kN]",
                        "min tension [kN]", "max tension [kN]"], rows) + _crane_note(crane):
        print(line)
    if out is not None:
        _write(res, out)
        print(f"results written to {out}")
    return EXIT_OK


def cmd_modes(args) -> int:
    import numpy as np

    import rfesim

    sc = _load(args.scenario)
    if args.n is not None and args.n < 1:
        raise CliError("error: -n must be at least 1", EXIT_USAGE)
    _note_cold_cache()
    try:
        md = rfesim.modes(sc, n=args.n)
    except rfesim.SolverError as exc:
        return _solver_failure(exc, None)
    from .solvers.modal import RIGID_BODY_FRACTION

    freqs = np.asarray(md.frequencies_hz, dtype=float)
    # a frequency at round-off of the stiffness scale is a rigid-body mode: 0, as the negative
    # round-off rfesim.modes gives 0 already (a pinned riser's spin computed 7.8e-7 Hz)
    rigid = np.asarray(getattr(md, "rigid_body", freqs == 0.0), bool)
    rows = []
    for k, (f, zero) in enumerate(zip(freqs, rigid), start=1):
        period = "inf" if zero else f"{1.0 / f:.6g}" if f > 0 else "unstable"
        rows.append([str(k), "0" if zero else f"{f:.6g}", period])
    print(f"{sc.name}: {len(freqs)} modes")
    for line in _table(["mode", "frequency [Hz]", "period [s]"], rows):
        print(line)
    # the unstable-mode warning is already logged by rfesim.modes; the other notes are not
    for note in (getattr(md, "message", "") or "").split("; "):
        if note and not note.startswith("the static state is unstable"):
            _err(f"note: {note}")
    shown = [k for k, (f, zero) in enumerate(zip(freqs, rigid), start=1) if zero and f != 0.0]
    if shown:
        _err(f"note: mode{'s' if len(shown) > 1 else ''} {', '.join(map(str, shown))} printed as 0 (rigid-body): "
             f"below {RIGID_BODY_FRACTION:g} of the stiffness-scale frequency {md.scale_hz:.4g} Hz "
             f"(ModalResults.rigid_body; md.frequencies_hz keeps the computed "
             f"{', '.join(f'{freqs[k - 1]:.3g}' for k in shown)} Hz)")
    return EXIT_OK


def _missing(component: str, hint: str) -> int:
    _err(f"error: {component} is not available in this installation ({hint})")
    return EXIT_USAGE


def _module_exists(name: str) -> bool:
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError):
        return False


def _exit_code(value) -> int:
    return EXIT_OK if value is None else int(value)


def cmd_bench(args) -> int:
    if not _module_exists("rfesim.bench.run"):
        return _missing("the benchmark runner (rfesim.bench.run)", "it has not been built yet")
    runner = importlib.import_module("rfesim.bench.run")

    argv = (["--quick"] if args.quick else []) + list(args.extra)
    # a bad option, or no checkout, is refused before any compiling
    if hasattr(runner, "build_parser") and hasattr(runner, "checkout_problem"):
        runner.build_parser().parse_args(argv)
        if runner.checkout_problem() is None:
            _note_cold_cache()
    return _exit_code(runner.main(argv))


def cmd_sweep(args) -> int:
    if not _module_exists("rfesim.sweep"):
        return _missing("parameter sweeps (rfesim.sweep)", "it has not been built yet")
    from rfesim.sweep import main as sweep_main

    argv = [args.scenario]
    for v in args.vary:
        argv += ["--vary", v]
    if args.scheduler:
        argv += ["--scheduler", args.scheduler]
    if args.local_cluster is not None:
        argv += ["--local-cluster", str(args.local_cluster)]
    if args.workers is not None:
        argv += ["--workers", str(args.workers)]
    if args.output:
        argv += ["-o", args.output]
    return _exit_code(sweep_main(argv + list(args.extra)))


def cmd_serve(args) -> int:
    if not _module_exists("service.app"):
        return _missing("the HTTP service (service.app)", "it has not been built yet")
    # options override the RFESIM_* environment variables the service reads its settings from
    if args.data_dir is not None:
        os.environ["RFESIM_DATA_DIR"] = args.data_dir
    if args.workers is not None:
        os.environ["RFESIM_WORKERS"] = str(args.workers)
    try:
        module = importlib.import_module("service.app")
        import uvicorn
    except ImportError as exc:
        return _missing("the HTTP service", f"{exc}; install the extra: pip install 'rfesim[service]'")
    try:
        app = getattr(module, "app", None)
        if app is None and callable(getattr(module, "create_app", None)):
            app = module.create_app()
    except ValueError as exc:   # pydantic's ValidationError of the settings
        raise CliError(f"error: invalid service settings (RFESIM_* environment variables): {exc}", EXIT_USAGE) \
            from None
    if app is None:
        return _missing("the HTTP service", "service.app defines neither 'app' nor 'create_app'")
    print(f"serving rfesim on http://{args.host}:{args.port} (OpenAPI at /docs); Ctrl-C to stop", file=sys.stderr)

    class Server(uvicorn.Server):
        """Tells the app it is stopping as soon as the signal arrives. uvicorn waits for open
        connections before the app's lifespan shutdown, so a flag set there would come too
        late for an open event stream (GET /jobs/{id}/events), which would hold the stop
        until the graceful timeout and then be cut without its "event: end"."""

        def handle_exit(self, sig, frame) -> None:
            state = getattr(app, "state", None)
            if state is not None:
                state.stopping = True
            super().handle_exit(sig, frame)

    # a bounded graceful shutdown still: a slow client must not hold a stop for ever
    config = uvicorn.Config(app, host=args.host, port=args.port, log_level="info" if args.verbose else "warning",
                            timeout_graceful_shutdown=10)
    Server(config).run()
    return EXIT_OK


# --------------------------------------------------------------------------- parser

class _BenchHelp(argparse.Action):
    """``rfesim bench --help``: the help of the benchmark runner, to which `rfesim bench` passes
    the options it does not know itself (``--only PART`` with its parts, ``--no-moordyn``,
    ...), rather than the ``--quick`` alone this subcommand declares."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        if _module_exists("rfesim.bench.run"):
            from rfesim.bench.run import build_parser as runner_parser

            runner_parser().print_help()
        else:
            parser.print_help()
        parser.exit()


FORWARDS_EXTRA = ("bench", "sweep")


def build_parser() -> argparse.ArgumentParser:
    from . import __version__

    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("-v", "--verbose", action="count", default=argparse.SUPPRESS,
                        help="log library messages (-v: info, -vv: debug)")

    parser = argparse.ArgumentParser(
        prog="rfesim", description="Rigid Finite Element dynamics of offshore pipes, cables and risers.",
        epilog="exit codes: 0 ok, 1 bad input, 2 usage or missing component, 3 solver failure, 4 internal error "
               "(a bug; RFESIM_DEBUG=1 shows its traceback), 130 interrupted")
    parser.add_argument("--version", action="version", version=f"rfesim {__version__}")
    parser.add_argument("-v", "--verbose", action="count", default=0,
                        help="log library messages (-v: info, -vv: debug)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    p = sub.add_parser("run", parents=[common], help="statics + dynamics, write a netCDF results file")
    p.add_argument("scenario", metavar="SCENARIO", help="scenario file (JSON or YAML)")
    p.add_argument("-o", "--output", metavar="OUT.nc",
                   help="results file (default: <scenario stem>.nc in the current directory)")
    p.add_argument("--plot", metavar="OUT.png", help="also draw line shapes and top tension to this image")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--progress", dest="progress", action="store_true", default=None,
                   help="always draw the progress bar (default: on a terminal, for runs longer than ~1 s)")
    g.add_argument("--no-progress", dest="progress", action="store_false", help="never draw the progress bar")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("statics", parents=[common], help="static equilibrium: end forces and tension range")
    p.add_argument("scenario", metavar="SCENARIO")
    p.add_argument("-o", "--output", metavar="OUT.nc", help="write the static results to this file")
    p.set_defaults(func=cmd_statics)

    p = sub.add_parser("modes", parents=[common], help="natural frequencies about the static equilibrium")
    p.add_argument("scenario", metavar="SCENARIO")
    p.add_argument("-n", type=int, default=None, metavar="N",
                   help="number of modes (default: analysis.modal.modes, or 10)")
    p.set_defaults(func=cmd_modes)

    p = sub.add_parser("check", parents=[common], help="validate a scenario and build its model (no solve)")
    p.add_argument("scenario", metavar="SCENARIO")
    p.add_argument("--expand", action="store_true",
                   help="print the scenario with its pipelay and crane templates expanded (JSON)")
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("bench", parents=[common], add_help=False,
                       help="work-precision report (extra options go to the runner)")
    p.add_argument("-h", "--help", action=_BenchHelp, help="show the benchmark runner's options and exit")
    p.add_argument("--quick", action="store_true", help="a short subset")
    p.set_defaults(func=cmd_bench)

    p = sub.add_parser("serve", parents=[common], help="the HTTP service")
    p.add_argument("--host", default="127.0.0.1")
    p.add_argument("--port", type=int, default=8000)
    p.add_argument("--data-dir", default=None, metavar="DIR",
                   help="job database and results (default: $RFESIM_DATA_DIR or ./rfesim-data)")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes (default: $RFESIM_WORKERS or min(2, cores))")
    p.set_defaults(func=cmd_serve)

    p = sub.add_parser("sweep", parents=[common], help="run a scenario over parameter values")
    p.add_argument("scenario", metavar="SCENARIO")
    p.add_argument("--vary", action="append", required=True, metavar="PATH=V1,V2,...",
                   help="dotted scenario path and its values (repeat for a grid)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="address of a distributed scheduler")
    p.add_argument("--local-cluster", type=int, metavar="N", help="run on a Dask LocalCluster of N processes")
    p.add_argument("--workers", type=int, metavar="N", help="size of the local process pool (default: cores)")
    p.add_argument("-o", "--output", metavar="TABLE.csv", help="also write the table as CSV")
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("schema", parents=[common],
                       help="print the scenario's JSON Schema, or its field reference (--markdown, docs/scenario.md)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--json", dest="format", action="store_const", const="json", default="json",
                   help="the JSON Schema, with units and bounds (default)")
    g.add_argument("--markdown", dest="format", action="store_const", const="markdown",
                   help="every section and field as Markdown tables: type, unit, default, bounds, description")
    p.add_argument("-o", "--output", metavar="FILE", help="write to this file (UTF-8) instead of stdout")
    p.set_defaults(func=cmd_schema)
    return parser


def _summary_message(message: str) -> str:
    """A results' message for the summary line: its statics and dynamics warnings were logged
    on stderr as they were found (the results file keeps them in full), so only their count."""
    from .api import DYNAMICS_WARNING, STATICS_WARNING
    head, _, dynamics = message.partition(DYNAMICS_WARNING)
    head, *statics = head.split(STATICS_WARNING)
    counts = [(len(statics), "statics")] + [(dynamics.count(DYNAMICS_WARNING) + 1, "dynamics")] * bool(dynamics)
    counts = [f"{n} {kind} warning{'s' if n > 1 else ''}" for n, kind in counts if n]
    return f"{head} ({', '.join(counts)}, above)" if counts else message


class _StderrHandler(logging.StreamHandler):
    """Writes to whatever ``sys.stderr`` is when a record arrives (main() may be called
    again, in-process, with another stderr)."""

    @property
    def stream(self):
        return sys.stderr

    @stream.setter
    def stream(self, value):
        pass


def _configure_logging(verbosity: int) -> None:
    level = logging.WARNING if verbosity <= 0 else logging.INFO if verbosity == 1 else logging.DEBUG
    logger = logging.getLogger("rfesim")
    logger.setLevel(level)
    handler = next((h for h in logger.handlers if isinstance(h, _StderrHandler)), None)
    if handler is None:
        handler = _StderrHandler()
        handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
        logger.addHandler(handler)
    handler.setLevel(level)


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code (the console script exits with it)."""
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra and args.command not in FORWARDS_EXTRA:
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    args.extra = extra
    args.program = argv is None     # the console script (not a call in-process): see _RunSignals
    _configure_logging(getattr(args, "verbose", 0) or 0)

    from .errors import CancelledError, RfesimError, ScenarioError, SolverError

    try:
        return _exit_code(args.func(args))
    except CliError as exc:
        _err(str(exc))
        return exc.code
    except ScenarioError as exc:
        _err("scenario error:", *(f"  {f}: {r}" if f else f"  {r}" for f, r in exc.errors))
        return EXIT_INPUT
    except SolverError as exc:
        return _solver_failure(exc, None)
    except CancelledError as exc:
        _err(f"cancelled: {exc}")
        return EXIT_INTERRUPTED
    except RfesimError as exc:
        _err(f"error: {exc}")
        return EXIT_INPUT
    except KeyboardInterrupt:
        _err("interrupted")
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # `rfesim modes x.json | head`
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return EXIT_OK
    except Exception as exc:
        # the last resort: an exception none of the above expects is a bug; one line that says so
        # rather than a bare traceback (KeyboardInterrupt and SystemExit are not Exceptions)
        if os.environ.get("RFESIM_DEBUG", "").strip() not in ("", "0"):
            raise
        _err(f"rfesim: internal error: {type(exc).__name__}: {exc} (a bug; please report it with the scenario; "
             f"set RFESIM_DEBUG=1 for the traceback)")
        return EXIT_INTERNAL


if __name__ == "__main__":
    raise SystemExit(main())
