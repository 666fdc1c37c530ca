"""``rfesim bench``: work-precision of rfesim against MoorDyn on line H1, cost per step vs
number of RFEs, start-up time of a second run. Writes docs/benchmarks.md (its own section,
between markers, leaving the other sections alone) and plots next to it.

All ratios are measured in one run on the same machine (which may be shared: the load
average is recorded with the results).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from .h1 import H1Run, assign_errors, run_rfesim_h1, time_to_reach

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
MARK_BEGIN = "<!-- core-bench -->"
MARK_END = "<!-- /core-bench -->"


def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


# ----------------------------------------------------------------------------- H1
def rfesim_grid(quick: bool):
    ga = lambda h: ({"kind": "generalized-alpha", "time_step": h, "rho_inf": 0.8, "tolerance": 1e-6},  # noqa: E731
                    f"generalized-alpha h={h:g} s")
    if quick:
        runs = [(25, *ga(0.1)), (50, *ga(0.05)), (100, *ga(0.05))]
        reference = (200, *ga(0.025))
    else:
        runs = [(n, *ga(h)) for n in (25, 50, 100, 200) for h in (0.1, 0.05, 0.025)]
        runs += [(400, *ga(0.05))]
        reference = (400, *ga(0.0125))
    return runs, reference


def moordyn_grid(quick: bool):
    if quick:
        return [(25,), (50,)], (100,)
    return [(25,), (50,), (100,), (200,)], (400,)


def rfesim_grid_runs(tag: str, run, runs, ref_spec, quick: bool) -> dict:
    """The rfesim side of a work-precision benchmark: the reference run, then every
    (elements, integrator, label) of the grid, each with its error against the reference."""
    log(f"{tag} rfesim reference ...")
    ref = run(*ref_spec)
    rows = []
    for n, integ, label in runs:
        log(f"{tag} rfesim {n} RFEs, {label}")
        rows.append(run(n, integ, label, repeats=1 if quick else 2))
    assign_errors(rows, ref)
    ref.error = 0.0
    return {"rfesim": rows, "rfesim_reference": ref}


def run_h1(quick: bool, with_moordyn: bool) -> dict:
    runs, ref_spec = rfesim_grid(quick)
    out: dict = {"moordyn": [], **rfesim_grid_runs("H1", run_rfesim_h1, runs, ref_spec, quick)}
    if with_moordyn:
        from .moordyn_h1 import moordyn_available, run_moordyn_h1
        if moordyn_available():
            mruns, mref_spec = moordyn_grid(quick)
            log(f"H1 MoorDyn reference {mref_spec[0]} segments ...")
            mref = _moordyn_run(run_moordyn_h1, mref_spec[0])
            for (segments,) in mruns:
                log(f"H1 MoorDyn {segments} segments")
                out["moordyn"].append(_moordyn_run(run_moordyn_h1, segments))
            assign_errors(out["moordyn"], mref)
            mref.error = 0.0
            out["moordyn_reference"] = mref
        else:
            log("MoorDyn is not installed (pip install moordyn): skipping the comparison")
    return out


def _moordyn_run(fn, segments: int) -> H1Run:
    r = fn(segments)
    return H1Run("moordyn", segments, f"{r.get('time_scheme', 'RK4')} dtM={1e3 * r['dt_internal']:.3g} ms, coupled "
                 f"every {1e3 * r.get('coupling_step', r['dt_internal']):.3g} ms, ICgenDynamic",
                 float(r["wall_time"]), float(r["wall_time"] + r.get("ic_wall_time", 0.0)),
                 float(r["tension_amplitude"]), float(r["max_sagbend_moment"]))


# ----------------------------------------------------------------------------- scaling
def run_scaling(quick: bool) -> dict:
    """Cost per implicit step of the H1 line for 25 ... 2000 RFEs (10 s simulated)."""
    from ..model.compile import compile_scenario
    from ..solvers.dynamics import run_dynamics
    from ..solvers.statics import solve_statics
    from ..solvers.system import System
    from .h1 import h1_scenario
    sizes = (25, 50, 100, 200, 400) if quick else (25, 50, 100, 200, 400, 800, 1000, 2000)
    rows = []
    for n in sizes:
        log(f"scaling: {n} RFEs")
        sc = h1_scenario(n, {"kind": "generalized-alpha", "time_step": 0.05, "rho_inf": 0.8, "tolerance": 1e-6},
                         output_interval=0.5)
        sc.analysis.dynamics.duration = 10.0
        system = System(compile_scenario(sc))
        state, _ = solve_statics(system)
        best = math.inf
        counters = {}
        for _ in range(2):
            t0 = time.perf_counter()
            _, _, counters = run_dynamics(system, state, sc.analysis.dynamics)
            best = min(best, time.perf_counter() - t0)
        steps = counters["steps"]
        rows.append({"rfes": n + 1, "elements": n, "wall_time": best, "steps": steps,
                     "time_per_step": best / steps,
                     "evaluations_per_step": counters["newton_iterations"] / steps,
                     "jacobians_per_step": counters["jacobians"] / steps})
    x = np.log([r["rfes"] for r in rows])
    y = np.log([r["time_per_step"] for r in rows])
    big = np.array([r["rfes"] for r in rows]) >= 100
    slope_all = float(np.polyfit(x, y, 1)[0])
    slope_big = float(np.polyfit(x[big], y[big], 1)[0]) if big.sum() >= 2 else slope_all
    return {"rows": rows, "slope": slope_all, "slope_from_100": slope_big}


# ----------------------------------------------------------------------------- start-up
STARTUP_SCRIPT = r"""
import sys, time
t0 = float(sys.argv[1])
import rfesim
first = []
def progress(fraction, t):
    if not first:
        first.append(time.time())
rfesim.simulate(sys.argv[2], progress=progress)
print(first[0] - t0)
"""


def run_startup(scenario: Path) -> dict:
    """Seconds from the start of a new process to the first simulated step, twice: the
    second run loads the compiled kernels from numba's cache."""
    times = []
    for _ in range(2):
        t0 = time.time()
        out = subprocess.run([sys.executable, "-c", STARTUP_SCRIPT, repr(t0), str(scenario)], capture_output=True,
                             text=True, check=True, cwd=str(ROOT))
        times.append(float(out.stdout.strip().splitlines()[-1]))
    return {"scenario": scenario.name, "first_run": times[0], "second_run": times[1]}


# ----------------------------------------------------------------------------- report
def plot_work_precision(h1: dict, path: Path,
                        title: str = "H1 work-precision (labels: elements / segments)") -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 5))
    for code, marker in (("rfesim", "o"), ("moordyn", "s")):
        runs = [r for r in h1.get(code, []) if r.error > 0]
        if not runs:
            continue
        ax.loglog([r.wall_time for r in runs], [r.error for r in runs], marker, label=code)
        for r in runs:
            ax.annotate(str(r.segments), (r.wall_time, r.error), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")
    for level in (1e-2, 1e-3):
        ax.axhline(level, color="grey", lw=0.5, ls="--")
    ax.set_xlabel("wall time of the 60 s run [s]")
    ax.set_ylabel("error against own converged solution [-]")
    ax.set_title(title)
    ax.legend()
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_scaling(scaling: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = scaling["rows"]
    n = np.array([r["rfes"] for r in rows])
    t = np.array([r["time_per_step"] for r in rows]) * 1e3
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.loglog(n, t, "o-", label=f"measured (slope {scaling['slope']:.2f})")
    ax.loglog(n, t[0] * n / n[0], "k--", lw=0.7, label="linear")
    ax.set_xlabel("number of RFEs")
    ax.set_ylabel("wall time per implicit step [ms]")
    ax.legend()
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _fmt(x, digits=4):
    if isinstance(x, float):
        if not math.isfinite(x):
            return "-"
        return f"{x:.{digits}g}"
    return str(x)


def results_table(h: dict) -> list[str]:
    """Markdown table of the runs of both codes (H1Run) and their references."""
    lines = ["| code | elements / segments | settings | wall time [s] | with statics/IC [s] | "
             "tension amplitude [N] | max moment [N*m] | error |",
             "|---|---:|---|---:|---:|---:|---:|---:|"]
    for code in ("rfesim", "moordyn"):
        ref = h.get(f"{code}_reference")
        for r in h.get(code, []) + ([ref] if ref else []):
            tag = " (reference)" if r is ref else ""
            lines.append(f"| {r.code}{tag} | {r.segments} | {r.setting} | {_fmt(r.wall_time)} | "
                         f"{_fmt(r.total_time)} | {_fmt(r.tension_amplitude, 6)} | {_fmt(r.max_moment, 6)} | "
                         f"{_fmt(r.error, 3)} |")
    return lines


def converged_text(rr: H1Run, mr: H1Run) -> str:
    """The converged (reference) solutions of rfesim (rr) and MoorDyn (mr) compared."""
    return (f"Converged solutions: tension amplitude rfesim {rr.tension_amplitude:.1f} N, MoorDyn "
            f"{mr.tension_amplitude:.1f} N ({100 * (mr.tension_amplitude / rr.tension_amplitude - 1):+.2f} %); "
            f"largest moment rfesim {rr.max_moment:.0f} N*m, MoorDyn {mr.max_moment:.0f} N*m "
            f"({100 * (mr.max_moment / rr.max_moment - 1):+.2f} %).")


def report(h1: dict | None, scaling: dict | None, startup: dict | None, quick: bool) -> str:
    lines = [MARK_BEGIN, "## Core solver", ""]
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    lines.append(f"`rfesim bench{' --quick' if quick else ''}` on {platform.machine()}, {os.cpu_count()} cores, "
                 f"Python {platform.python_version()}; load average at the end {load[0]:.2f}, {load[1]:.2f}, "
                 f"{load[2]:.2f} (the machine is shared: compare ratios measured in this one run, not absolute "
                 "times across runs).")
    lines.append("")
    if h1 is not None:
        lines += ["### H1: steel catenary riser on a heaving fairlead, work-precision", "",
                  "Steel pipe OD 0.3 m, wall 0.02 m, E 2.1e11 Pa, 7850 kg/m^3, empty (air inside), water 100 m "
                  "deep; end A pinned on the seabed, end B at the fairlead (250, 0, -10) heaving 1 m at 8 s, "
                  "ramped in with a cosine over 8 s; length 290 m (about 140 m on the seabed); C_dn 1.2, C_dt "
                  "0.008, no added mass; 60 s. Error = max of the relative errors of (a) the first-harmonic "
                  "amplitude of the fairlead tension over 28-60 s (least-squares fit at 0.125 Hz) and (b) the "
                  "largest bending moment over the same window (the sag bend), each code against its own "
                  "converged solution. Wall time: the dynamic run (statics / initial conditions excluded for "
                  "both codes; the total with them is in the table).", ""]
        lines += results_table(h1)
        lines.append("")
        lines.append("![H1 work-precision](img/h1_work_precision.png)")
        lines.append("")
        summary = []
        for target in (1e-2, 1e-3):
            tr = time_to_reach(h1["rfesim"], target)
            tm = time_to_reach(h1.get("moordyn", []), target) if h1.get("moordyn") else math.inf
            ratio = tm / tr if math.isfinite(tr) and math.isfinite(tm) else float("nan")
            summary.append((target, tr, tm, ratio))
        lines.append("| error target | rfesim wall time [s] | MoorDyn wall time [s] | MoorDyn / rfesim |")
        lines.append("|---:|---:|---:|---:|")
        notes = []
        for target, tr, tm, ratio in summary:
            if math.isfinite(tm):
                lines.append(f"| {target:g} | {_fmt(tr)} | {_fmt(tm)} | {_fmt(ratio, 3)} |")
                continue
            # not reached: MoorDyn needs more than its most accurate run took (a finer line
            # only costs more), so the ratio is at least that time over rfesim's
            runs = [r for r in h1.get("moordyn", []) if math.isfinite(r.error)]
            if runs and math.isfinite(tr):
                best = min(runs, key=lambda r: r.error)
                lines.append(f"| {target:g} | {_fmt(tr)} | > {_fmt(best.wall_time)} | > {_fmt(best.wall_time / tr, 3)} |")
                notes.append(f"MoorDyn did not reach {target:g} in these runs: its most accurate one ({best.segments} "
                             f"segments, {_fmt(best.wall_time)} s) is still at {_fmt(best.error, 3)}; a finer line "
                             f"costs more, so at {target:g} MoorDyn needs more than that time: the ratio is a lower "
                             f"bound.")
            else:
                lines.append(f"| {target:g} | {_fmt(tr)} | not reached by the runs | - |")
        lines.append("")
        for note in notes:
            lines += [note, ""]
        if h1.get("moordyn_reference"):
            lines.append(converged_text(h1["rfesim_reference"], h1["moordyn_reference"]))
            lines.append("")
        h1["summary"] = summary
    if scaling is not None:
        lines += ["### Cost per time step vs number of RFEs", "",
                  "H1 line with 25 to 2000 elements, generalized-alpha at 0.05 s, 10 s simulated (best of two runs).",
                  ""]
        lines.append("| RFEs | wall time per step [ms] | per RFE [us] | residual evaluations per step | "
                     "Jacobians per step |")
        lines.append("|---:|---:|---:|---:|---:|")
        for r in scaling["rows"]:
            lines.append(f"| {r['rfes']} | {1e3 * r['time_per_step']:.3f} | {1e6 * r['time_per_step'] / r['rfes']:.2f} | "
                         f"{r['evaluations_per_step']:.2f} | {r['jacobians_per_step']:.2f} |")
        lines.append("")
        lines.append(f"Fitted slope of log(time per step) against log(RFEs): {scaling['slope']:.3f} over all sizes, "
                     f"{scaling['slope_from_100']:.3f} from 100 RFEs up (1 = linear).")
        lines.append("")
        lines.append("![cost per step](img/scaling.png)")
        lines.append("")
    if startup is not None:
        lines += ["### Start-up", "",
                  f"From the start of a new Python process to the first simulated step of `{startup['scenario']}` "
                  f"(import, numba kernels, compile of the scenario, statics): first run {startup['first_run']:.2f} s, "
                  f"second run {startup['second_run']:.2f} s (kernels loaded from numba's cache; target: within 3 s).",
                  ""]
    lines.append(MARK_END)
    return "\n".join(lines)


def replace_section(old: str, text: str, begin: str, end: str) -> str | None:
    """``old`` with its part from the marker ``begin`` to ``end`` replaced by ``text``
    (None when the markers are not both there)."""
    if begin in old and end in old:
        a = old.index(begin)
        b = old.index(end) + len(end)
        return old[:a] + text + old[b:]
    return None


def write_section(text: str, path: Path) -> None:
    old = path.read_text() if path.exists() else "# Benchmarks\n"
    new = replace_section(old, text, MARK_BEGIN, MARK_END)
    if new is None:
        head, _, rest = old.partition("\n")
        new = head + "\n\n" + text + "\n" + rest
    path.write_text(new)


def write_marked_section(text: str, path: Path, begin: str, end: str) -> None:
    """Replace the part of the report ``path`` between the markers ``begin`` and ``end`` by
    ``text`` (which carries the markers), or append ``text`` when the report has none."""
    old = path.read_text() if path.exists() else "# Benchmarks\n"
    new = replace_section(old, text, begin, end)
    if new is None:
        new = old.rstrip("\n") + "\n\n" + text + "\n"
    path.write_text(new)


def write_part(key: str, b: dict, text: str, report_path: Path, begin: str, end: str) -> str:
    """A benchmark part's results: its section ``text`` (between ``begin`` and ``end``) into the
    report and ``b`` as its benchmarks.json entry ``key``; returns ``text``."""
    write_marked_section(text, report_path, begin, end)
    store_entry(report_path, key, b)
    return text


def store_entry(report_path: Path, key: str, value) -> None:
    """Set one entry of benchmarks.json (next to the report), keeping the others."""
    json_path = report_path.parent / "benchmarks.json"
    try:
        raw = json.loads(json_path.read_text())
    except (OSError, ValueError):
        raw = {}
    raw[key] = value
    json_path.write_text(json.dumps(raw, indent=1, default=float))


def _previous(path: Path) -> dict:
    """The results of the last run (benchmarks.json), H1 rows as H1Run again."""
    try:
        raw = json.loads(path.read_text())
    except (OSError, ValueError):
        return {}
    h1 = {}
    for key, value in (raw.get("h1") or {}).items():
        if isinstance(value, list) and value and isinstance(value[0], dict) and "code" in value[0]:
            h1[key] = [H1Run(**row) for row in value]
        elif isinstance(value, dict) and "code" in value:
            h1[key] = H1Run(**value)
        else:
            h1[key] = value
    raw["h1"] = h1
    return raw


def build_parser() -> argparse.ArgumentParser:
    """The runner's options; ``rfesim bench --help`` shows this parser's help (rfesim.cli)."""
    p = argparse.ArgumentParser(prog="rfesim bench", description=__doc__)
    p.add_argument("--quick", action="store_true", help="a small grid (a few minutes)")
    p.add_argument("--no-moordyn", action="store_true", help="skip the MoorDyn comparison")
    p.add_argument("--only", choices=["h1", "h2", "scaling", "startup", "validation", "formulations", "slay",
                                        "crane", "build", "compile"],
                   action="append",
                   help="run only these parts (repeatable)")
    p.add_argument("--output", default=str(DOCS / "benchmarks.md"), help="report file (its core section is replaced)")
    p.add_argument("--validation", action="store_true", help="also write docs/validation.md")
    return p


def checkout_problem(root: Path = ROOT) -> str | None:
    """Why the benchmarks cannot run from ``root`` (None when they can): they read the example
    scenarios and the validation tests and write their reports into docs/, all in a source
    checkout; an installed package (a wheel) has none of them."""
    missing = [d for d in ("scenarios", "tests", "docs") if not (root / d).is_dir()]
    if not missing:
        return None
    return (f"rfesim bench runs in a source checkout of rfesim: it reads scenarios/ and tests/ and writes its "
            f"reports to docs/, and {root} has no {', no '.join(d + '/' for d in missing)} (an installed "
            f"package); clone the repository, `pip install -e '.[dev,bench]'` there and run it from there")


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    problem = checkout_problem()
    if problem is not None:
        log(f"error: {problem}")
        return 2
    parts = set(args.only or ["h1", "h2", "scaling", "startup", "formulations"])
    if args.validation:
        parts.add("validation")
    if "validation" in parts:
        from .validation import write as write_validation
        log("validation cases ...")
        print(write_validation(DOCS / "validation.md"))
        log("slow validation tests (pytest -m slow) ...")
        import subprocess
        import sys
        proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-m", "slow", "-p", "no:cacheprovider",
                               str(ROOT / "tests")], capture_output=True, text=True, cwd=ROOT)
        tail = [ln for ln in proc.stdout.strip().splitlines() if ln.strip()][-1:] or ["(no output)"]
        with open(DOCS / "validation.md", "a") as fh:
            fh.write(f"\nSlow validation tests (`pytest -m slow`, not run by CI): {tail[0]}\n")
        print("slow tests:", tail[0])
        if parts == {"validation"}:
            return 0
    out_path = Path(args.output)
    (out_path.parent / "img").mkdir(parents=True, exist_ok=True)
    if "h2" in parts:
        # H2 (issue 3) has its own section and its own "h2" entry in benchmarks.json
        from .run_h2 import run_h2_and_write
        print(run_h2_and_write(args.quick, not args.no_moordyn, out_path))
        if not parts & {"h1", "scaling", "startup", "formulations"}:
            return 0
    if "slay" in parts:
        # S-lay in irregular waves (issue 3): its own section and "slay" entry of benchmarks.json
        from .run_slay import run_slay_and_write
        print(run_slay_and_write(args.quick, out_path))
        if not parts & {"h1", "scaling", "startup", "formulations"}:
            return 0
    if "crane" in parts:
        # the column crane in irregular waves (issue 5): its own section and "crane" entry of benchmarks.json
        from .run_crane import run_crane_and_write
        print(run_crane_and_write(args.quick, out_path))
        if not parts & {"h1", "scaling", "startup", "formulations"}:
            return 0
    if "compile" in parts:
        # the cold-cache compile, one process against rfesim.precompile's two: its own section and "compile" entry
        from .run_compile import run_compile_and_write
        print(run_compile_and_write(args.quick, out_path))
        if not parts & {"h1", "scaling", "startup", "formulations"}:
            return 0
    if "build" in parts:
        # validation and model build of every bundled scenario: its own section and "build" entry
        from .build import run_build_and_write
        print(run_build_and_write(args.quick, out_path))
        if not parts & {"h1", "scaling", "startup", "formulations"}:
            return 0
    if "formulations" in parts:
        # issue 4: cost per step of each RFE formulation; its own section and benchmarks_formulations.json
        from .formulations import run as run_formulations
        from .formulations import write as write_formulations
        print(write_formulations(run_formulations(args.quick, log), out_path, args.quick))
        if not parts & {"h1", "scaling", "startup"}:
            return 0
    h1 = run_h1(args.quick, not args.no_moordyn) if "h1" in parts else None
    scaling = run_scaling(args.quick) if "scaling" in parts else None
    startup = run_startup(ROOT / "scenarios" / "catenary_riser.json") if "startup" in parts else None
    # parts not run this time keep their last results (benchmarks.json), so the report stays whole
    previous = _previous(out_path.parent / "benchmarks.json")
    if h1 is None and previous.get("h1"):
        h1 = previous["h1"]
    if scaling is None:
        scaling = previous.get("scaling")
    if startup is None:
        startup = previous.get("startup")
    if h1 is not None and "h1" in parts:
        plot_work_precision(h1, out_path.parent / "img" / "h1_work_precision.png")
    if scaling is not None and "scaling" in parts:
        plot_scaling(scaling, out_path.parent / "img" / "scaling.png")
    text = report(h1, scaling, startup, args.quick)
    write_section(text, out_path)
    def _json(v):
        if isinstance(v, H1Run):
            return v.as_row()
        if isinstance(v, list):
            return [_json(x) for x in v]
        return v

    raw = {"h1": {k: _json(v) for k, v in (h1 or {}).items()},
           "scaling": scaling, "startup": startup, "quick": args.quick}
    h2_previous = _previous(out_path.parent / "benchmarks.json").get("h2")
    if h2_previous is not None:
        raw["h2"] = h2_previous
    for key in ("slay", "crane", "build"):
        kept = _previous(out_path.parent / "benchmarks.json").get(key)
        if kept is not None:
            raw[key] = kept
    (out_path.parent / "benchmarks.json").write_text(json.dumps(raw, indent=1, default=float))
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
