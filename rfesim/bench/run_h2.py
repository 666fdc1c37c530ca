"""``rfesim bench --only h2``: work-precision of rfesim against MoorDyn on line H2 (H1 with
added mass, current and waves). Writes its own section of docs/benchmarks.md (between
the markers ``<!-- h2-bench -->`` and ``<!-- /h2-bench -->``), the plot
docs/img/h2_work_precision.png and the ``h2`` entry of docs/benchmarks.json.

Reference resolutions (measured on this machine, load average 2-3 from other jobs).
rfesim: 400 RFEs, generalized-alpha at 0.0125 s; it is 5e-5 from 200 RFEs at 0.025 s.
MoorDyn: 400 segments at its default dtM (0.104 ms, RK4, fairlead updated at every
internal step). Its values still move by +96, +78, +42 and +21 N per doubling of the
segments from 25 to 400 (first order), so a 200-segment reference would halve MoorDyn's
measured errors at 100 segments and leave no 200-segment point on its curve; an
800-segment reference would cost about 4x the 400-segment run (the 400-segment run is
already 23 of the 35 minutes of the full H2 benchmark: 14 min dynamics, 9 min dynamic
relaxation). 400 is the compromise; the report adds MoorDyn's first-order extrapolation
from 200 and 400 segments, which lands within 0.01 % of rfesim's converged amplitude.
``--quick`` (MoorDyn 25 and 50 segments against 100, rfesim against 200 RFEs) takes about
5 minutes.
"""
from __future__ import annotations

import math
import os
import platform
import time
from pathlib import Path

from .h1 import H1Run, assign_errors, time_to_reach
from .h2 import run_rfesim_h2
from .run import _fmt, converged_text, log, replace_section, results_table, rfesim_grid_runs, store_entry
from .run import _moordyn_run as _moordyn_row
from .run import plot_work_precision as _plot_work_precision

MARK_BEGIN = "<!-- h2-bench -->"
MARK_END = "<!-- /h2-bench -->"
PLOT_NAME = "h2_work_precision.png"


def _ga(h: float) -> tuple[dict, str]:
    return ({"kind": "generalized-alpha", "time_step": h, "rho_inf": 0.8, "tolerance": 1e-6},
            f"generalized-alpha h={h:g} s")


def rfesim_grid(quick: bool):
    """(runs, reference): runs as (elements, integrator, label)."""
    if quick:
        return [(25, *_ga(0.05)), (50, *_ga(0.05)), (100, *_ga(0.05))], (200, *_ga(0.025))
    runs = [(n, *_ga(h)) for n in (25, 50, 100, 200) for h in (0.05, 0.025)]
    runs += [(400, *_ga(0.05))]
    return runs, (400, *_ga(0.0125))


def moordyn_grid(quick: bool):
    """(segment counts, reference segment count), all at the default dtM."""
    if quick:
        return [25, 50], 100
    return [25, 50, 100, 200], 400


def _moordyn_run(segments: int) -> H1Run:
    from .moordyn_h2 import run_moordyn_h2
    return _moordyn_row(run_moordyn_h2, segments)


def run_h2(quick: bool, with_moordyn: bool) -> dict:
    """All H2 runs: rfesim's grid and reference, then MoorDyn's (when installed)."""
    started = time.perf_counter()
    runs, ref_spec = rfesim_grid(quick)
    out: dict = {"moordyn": [], "quick": quick, **rfesim_grid_runs("H2", run_rfesim_h2, runs, ref_spec, quick)}
    if with_moordyn:
        from .moordyn_h1 import moordyn_available
        if moordyn_available():
            from .moordyn_h2 import compare_kinematics
            out["kinematics"] = compare_kinematics()
            segments, ref_segments = moordyn_grid(quick)
            for n in segments:
                log(f"H2 MoorDyn {n} segments")
                out["moordyn"].append(_moordyn_run(n))
            log(f"H2 MoorDyn reference {ref_segments} segments ...")
            mref = _moordyn_run(ref_segments)
            assign_errors(out["moordyn"], mref)
            mref.error = 0.0
            out["moordyn_reference"] = mref
        else:
            log("MoorDyn is not installed (pip install moordyn): skipping the comparison")
    out["bench_wall_time"] = time.perf_counter() - started
    out["load_average"] = list(os.getloadavg()) if hasattr(os, "getloadavg") else [float("nan")] * 3
    return out


def summarise(h2: dict) -> dict:
    """Ratios MoorDyn / rfesim wall time: at error targets 1e-2 and 1e-3 read off the two
    work-precision fronts, and at the error of rfesim's 100- and 200-RFE runs."""
    moordyn = h2.get("moordyn", [])
    targets = []
    for target in (1e-2, 1e-3):
        tr = time_to_reach(h2["rfesim"], target)
        tm = time_to_reach(moordyn, target) if moordyn else math.inf
        targets.append({"error": target, "rfesim": tr, "moordyn": tm,
                        "ratio": tm / tr if math.isfinite(tr) and math.isfinite(tm) else float("nan")})
    at_rfes = []
    for n in (100, 200):
        mine = [r for r in h2["rfesim"] if r.segments == n]
        if not mine:
            continue
        best = min(mine, key=lambda r: r.wall_time)          # the fastest setting at this size
        error = max(best.error, 1e-12)
        tm = time_to_reach(moordyn, error) if moordyn else math.inf
        same = [r for r in moordyn if r.segments == n]
        at_rfes.append({"elements": n, "setting": best.setting, "error": best.error, "rfesim": best.wall_time,
                        "moordyn": tm, "ratio": tm / best.wall_time if math.isfinite(tm) else float("nan"),
                        "moordyn_same_segments": same[0].wall_time if same else float("nan"),
                        "moordyn_same_segments_error": same[0].error if same else float("nan")})
    return {"targets": targets, "at_rfes": at_rfes}


def moordyn_extrapolation(h2: dict) -> dict | None:
    """MoorDyn's limit estimated from its reference and the next coarser run with half its
    segments, assuming first-order convergence in the segment count (limit = 2 fine - coarse;
    its tension amplitudes on H2 changed by +96, +78, +42 and +21 N per doubling from 25 to
    400 segments)."""
    mr = h2.get("moordyn_reference")
    runs = sorted(h2.get("moordyn", []), key=lambda r: r.segments)
    if mr is None or not runs:
        return None
    coarse = [r for r in runs if 2 * r.segments == mr.segments]
    if not coarse:
        return None
    c = coarse[0]
    chain = runs + [mr]
    steps = [b.tension_amplitude - a.tension_amplitude for a, b in zip(chain, chain[1:])]
    return {"coarse": c.segments, "fine": mr.segments,
            "tension_amplitude": 2.0 * mr.tension_amplitude - c.tension_amplitude,
            "max_moment": 2.0 * mr.max_moment - c.max_moment,
            "text": ", ".join(f"{d:+.0f}" for d in steps)}


def from_json(raw: dict) -> dict:
    """The ``h2`` entry of benchmarks.json with its runs as H1Run objects again."""
    fields = ("code", "segments", "setting", "wall_time", "total_time", "tension_amplitude", "max_moment", "error")
    out = {}
    for key, value in raw.items():
        if isinstance(value, dict) and "code" in value:
            out[key] = H1Run(**{k: value[k] for k in fields})
        elif isinstance(value, list) and value and isinstance(value[0], dict) and "code" in value[0]:
            out[key] = [H1Run(**{k: v[k] for k in fields}) for v in value]
        else:
            out[key] = value
    return out


def plot_work_precision(h2: dict, path: Path) -> None:
    _plot_work_precision(h2, path, "H2 (H1 + added mass, current, waves) work-precision\n"
                                   "(labels: elements / segments)")


def report(h2: dict) -> str:
    summary = summarise(h2)
    h2["summary"] = summary
    load = h2.get("load_average") or (os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3)
    lines = [MARK_BEGIN, "## H2: line H1 with added mass, current and waves", ""]
    lines.append(f"`rfesim bench --only h2{' --quick' if h2.get('quick') else ''}` on {platform.machine()}, "
                 f"{os.cpu_count()} cores, Python {platform.python_version()}; load average at the end "
                 f"{load[0]:.2f}, {load[1]:.2f}, {load[2]:.2f}; the whole H2 benchmark took "
                 f"{h2.get('bench_wall_time', float('nan')) / 60:.1f} min (the machine is shared: compare "
                 "ratios measured in this one run, not absolute times across runs).")
    lines.append("")
    lines.append("Line H1 (steel pipe OD 0.3 m, wall 0.02 m, empty, 290 m from the seabed to a fairlead at "
                 "(250, 0, -10) heaving 1 m at 8 s, ramped in over 8 s; C_dn 1.2, C_dt 0.008) with a normal "
                 "added-mass coefficient 1.0 (axial 0); a uniform current of 0.5 m/s flowing toward +y, across "
                 "the line's x-z plane, ramped in linearly over the first 8 s; and a regular Airy wave, height "
                 "3 m, period 9 s, travelling toward +x, eta = 1.5 cos(omega t - k x), from t = 0 (no ramp), "
                 "Wheeler stretching; 60 s. Both codes start from the still-water equilibrium. MoorDyn "
                 "(`rfesim/bench/moordyn_h2.py`): Ca 1.0, CaAx 0, `WaveKin 7` (wave components summed at the "
                 "nodes at every stage, Wheeler stretching), `Currents 2` (a current table in time, linear "
                 "ramp), otherwise the H1 harness (RK4 at its default dtM, fairlead updated every internal "
                 "step, `ICgenDynamic`). Error and wall time as for H1.")
    lines.append("")
    kin = h2.get("kinematics")
    if kin:
        lines.append(f"Water kinematics of the two codes at the same points and times (current ramp and wave, "
                     f"`moordyn_h2.compare_kinematics`): largest difference {kin['velocity']:.2g} m/s in velocity "
                     f"(of up to {kin['velocity_scale']:.2f} m/s), {kin['acceleration']:.2g} m/s^2 in acceleration "
                     f"(of up to {kin['acceleration_scale']:.2f} m/s^2), {kin['elevation']:.2g} m in elevation.")
        lines.append("")
    lines += results_table(h2)
    lines.append("")
    lines.append(f"![H2 work-precision](img/{PLOT_NAME})")
    lines.append("")
    lines.append("| error target | rfesim wall time [s] | MoorDyn wall time [s] | MoorDyn / rfesim |")
    lines.append("|---:|---:|---:|---:|")
    for row in summary["targets"]:
        tm = _fmt(row["moordyn"]) if math.isfinite(row["moordyn"]) else "not reached by the runs"
        lines.append(f"| {row['error']:g} | {_fmt(row['rfesim'])} | {tm} | {_fmt(row['ratio'], 3)} |")
    lines.append("")
    if summary["at_rfes"]:
        lines.append("At 100 and 200 RFEs (rfesim's fastest setting at that size; MoorDyn's time to the same "
                     "error read off its front, and its run with the same number of segments):")
        lines.append("")
        lines.append("| RFEs | rfesim setting | rfesim error | rfesim wall time [s] | MoorDyn wall time to that "
                     "error [s] | MoorDyn / rfesim | MoorDyn same segments: wall time [s] (error) |")
        lines.append("|---:|---|---:|---:|---:|---:|---:|")
        for row in summary["at_rfes"]:
            tm = _fmt(row["moordyn"]) if math.isfinite(row["moordyn"]) else "not reached by the runs"
            lines.append(f"| {row['elements']} | {row['setting']} | {_fmt(row['error'], 3)} | "
                         f"{_fmt(row['rfesim'])} | {tm} | {_fmt(row['ratio'], 3)} | "
                         f"{_fmt(row['moordyn_same_segments'])} ({_fmt(row['moordyn_same_segments_error'], 3)}) |")
        lines.append("")
    if h2.get("moordyn_reference"):
        rr, mr = h2["rfesim_reference"], h2["moordyn_reference"]
        lines.append(converged_text(rr, mr))
        lines.append("")
        extrapolated = moordyn_extrapolation(h2)
        if extrapolated is not None:
            lines.append(f"MoorDyn's values still move with its segment count ({extrapolated['text']} N in the tension "
                         f"amplitude per doubling), about at first order; extrapolated from its "
                         f"{extrapolated['coarse']} and {extrapolated['fine']} segments that way, its limit is "
                         f"{extrapolated['tension_amplitude']:.1f} N and {extrapolated['max_moment']:.0f} N*m, "
                         f"{100 * (extrapolated['tension_amplitude'] / rr.tension_amplitude - 1):+.2f} % and "
                         f"{100 * (extrapolated['max_moment'] / rr.max_moment - 1):+.2f} % from rfesim's converged "
                         "values.")
            lines.append("")
    rr, mr = h2.get("rfesim_reference"), h2.get("moordyn_reference")
    if rr is not None:
        text = f"Reference resolutions: rfesim {rr.segments} RFEs, {rr.setting}"
        if mr is not None:
            text += (f"; MoorDyn {mr.segments} segments, {mr.setting}. A finer MoorDyn reference (twice the "
                     "segments, half the dtM) would cost about four times its reference run again and is left "
                     "out of the run-time budget; MoorDyn's errors are therefore measured against a solution "
                     "that is itself still moving by about 0.1 % per doubling of its segments (see "
                     "`rfesim/bench/run_h2.py`)")
        lines.append(text + ".")
        lines.append("")
    lines.append(MARK_END)
    return "\n".join(lines)


def write_section(text: str, path: Path) -> None:
    """Replace the H2 section of ``path`` (or add it after the core section, else at the end)."""
    old = path.read_text() if path.exists() else "# Benchmarks\n"
    new = replace_section(old, text, MARK_BEGIN, MARK_END)
    if new is None and "<!-- /core-bench -->" in old:
        b = old.index("<!-- /core-bench -->") + len("<!-- /core-bench -->")
        new = old[:b] + "\n\n" + text + old[b:]
    elif new is None:
        new = old.rstrip("\n") + "\n\n" + text + "\n"
    path.write_text(new)


def as_json(h2: dict) -> dict:
    out = {}
    for key, value in h2.items():
        if isinstance(value, H1Run):
            out[key] = value.as_row()
        elif isinstance(value, list):
            out[key] = [v.as_row() if isinstance(v, H1Run) else v for v in value]
        else:
            out[key] = value
    return out


def run_h2_and_write(quick: bool, with_moordyn: bool, report_path: Path) -> str:
    """Run H2, draw the plot, write the H2 section of ``report_path`` and the ``h2`` entry
    of benchmarks.json next to it (other entries kept); return the section's text."""
    h2 = run_h2(quick, with_moordyn)
    img = report_path.parent / "img"
    img.mkdir(parents=True, exist_ok=True)
    plot_work_precision(h2, img / PLOT_NAME)
    text = report(h2)
    write_section(text, report_path)
    store_entry(report_path, "h2", as_json(h2))
    return text
