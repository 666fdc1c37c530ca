"""Validation report: every case of VALIDATION.md with its reference, rfesim's result, the
error, the discretisation and the run time -> docs/validation.md
(``rfesim bench --only validation``). The same cases are asserted in tests/validation."""
from __future__ import annotations

import math
import time
from pathlib import Path


from . import cases


def _row(case, quantity, reference, value, discretisation, seconds, tolerance):
    err = abs(value / reference - 1.0) if reference != 0 else abs(value)
    return {"case": case, "quantity": quantity, "reference": reference, "rfesim": value, "error": err,
            "discretisation": discretisation, "time": seconds, "tolerance": tolerance,
            "pass": err <= tolerance}


def _timed(fn, *args, **kw):
    t0 = time.perf_counter()
    out = fn(*args, **kw)
    return out, time.perf_counter() - t0


def collect() -> list[dict]:
    import rfesim
    rows = []
    for shear in ("fem", "kruszewski"):
        for n in (3, 20):
            ((w, rot), (w_ref, rot_ref)), dt = _timed(cases.r1_tip_force, n, shear)
            rows.append(_row("R1 tip force", f"deflection / P ({shear})", w_ref, w, f"{n} elements", dt, 1e-8))
            rows.append(_row("R1 tip force", f"tip rotation / P ({shear})", rot_ref, rot, f"{n} elements", dt, 1e-8))
    ((w, rot), (w_ref, rot_ref)), dt = _timed(cases.r1_tip_moment, 12)
    rows.append(_row("R1 tip moment", "deflection / M", w_ref, w, "12 elements", dt, 1e-8))
    rows.append(_row("R1 tip moment", "tip rotation / M", rot_ref, rot, "12 elements", dt, 1e-8))
    for alpha, ref in cases.MATTIASSON.items():
        (w, u, r), dt = _timed(cases.mattiasson, 20, alpha)
        for name, ref_v, v in (("w/L", ref[0], w), ("u/L", ref[1], u), ("tip rotation", ref[2], r)):
            rows.append(_row(f"B1 alpha = {alpha:g}", name, ref_v, v, "20 elements", dt, 3e-3))
    for alpha, ref in cases.MATTIASSON.items():
        (w, u, r), dt = _timed(cases.mattiasson, 40, alpha)
        rows.append(_row(f"B1 alpha = {alpha:g}", "w/L", ref[0], w, "40 elements", dt, 3e-3))
    (line, M, err), dt = _timed(cases.end_moment, 20, 1.0)
    total = float((line.curvature[0] * (1.0 / 20)).sum())
    rows.append(_row("B2 full circle", "tip rotation [rad]", 2 * math.pi, total, "20 elements", dt, 1e-8))
    rows.append({"case": "B2 full circle", "quantity": "tip position error / L", "reference": 0.0, "rfesim": err,
                 "error": err, "discretisation": "20 elements", "time": dt, "tolerance": 1e-3, "pass": err < 1e-3})
    for n in (10, 20):
        ratios, dt = _timed(cases.b4_frequencies, n)
        for k in range(4):
            rows.append(_row("B4 cantilever frequencies", f"f{k + 1} / f{k + 1} continuum",
                             cases.B4_RATIOS[n][k], float(ratios[k]), f"{n} elements", dt, 1.5e-5))
    for n in (10, 40):
        c, dt = _timed(cases.chain_frequencies, n)
        for k, tol in ((0, 1e-3), (1, 1e-3 if n == 40 else 1e-2), (2, 5e-3 if n == 40 else 5e-2)):
            rows.append(_row("B5 hanging chain", f"c{k + 1}", float(cases.CHAIN_C[k]), float(c[k]), f"{n} elements",
                             dt, tol))
    for theta, ref in cases.PENDULUM.items():
        ratio, dt = _timed(cases.pendulum_period_ratio, theta,
                           lambda T0: {"kind": "generalized-alpha", "time_step": T0 / 400, "rho_inf": 1.0})
        rows.append(_row("B9 pendulum", f"T/T0 at {theta:g} deg", ref, ratio, "4 elements, h = T0/400", dt, 5e-4))
    for n in (100, 200):
        res, dt = _timed(rfesim.statics, cases.catenary_line(n, 800.0))
        line = res.line("line")
        fb = line.end_b_force[0]
        grounded = (line.seabed_force[0].sum() - line.end_a_force[0][2]) / 800.0
        for name, ref, v in (("fairlead H [N]", cases.P1_SEABED["H"], -fb[0]),
                             ("fairlead V [N]", cases.P1_SEABED["V"], -fb[2]),
                             ("length on the seabed [m]", cases.P1_SEABED["grounded"], grounded)):
            rows.append(_row("P1 catenary on the seabed", name, ref, float(v), f"{n} elements", dt, 1e-3))
        res, dt = _timed(rfesim.statics, cases.catenary_line(n, 200.0, seabed=False))
        line = res.line("line")
        fb, fa = line.end_b_force[0], line.end_a_force[0]
        for name, ref, v in (("fairlead H [N]", cases.P1_SUSPENDED["H"], -fb[0]),
                             ("fairlead V [N]", cases.P1_SUSPENDED["V"], -fb[2]),
                             ("anchor V [N]", cases.P1_SUSPENDED["V_anchor"], -fa[2])):
            rows.append(_row("P1 fully suspended", name, ref, float(v), f"{n} elements", dt, 1e-3))
    from .sea_cases import validation_rows as sea_rows
    rows += sea_rows(_row, _timed)
    return rows


def report(rows: list[dict]) -> str:
    out = ["# Validation report", "",
           "Every case of `VALIDATION.md` (reference numbers from closed forms or published solutions), "
           "computed by `rfesim bench --only validation`; the same cases are asserted in `tests/validation/` "
           "(plus convergence-order tests: B1 and B2 converge as 1/n^2, B4 with eq. 8.89 from above as 1/n^2). "
           "Time: wall time of the case (statics, modes or dynamics, including numba's cache load on first use).",
           "", "| case | quantity | reference | rfesim | error | tolerance | discretisation | time [s] |",
           "|---|---|---:|---:|---:|---:|---|---:|"]
    for r in rows:
        out.append(f"| {r['case']} | {r['quantity']} | {r['reference']:.7g} | {r['rfesim']:.7g} | {r['error']:.2e} | "
                   f"{r['tolerance']:.1e} | {r['discretisation']} | {r['time']:.2f} |")
    bad = [r for r in rows if not r["pass"]]
    out += ["", f"{len(rows) - len(bad)} of {len(rows)} rows within their tolerance."]
    return "\n".join(out) + "\n"


def write(path: Path) -> str:
    text = report(collect())
    path.write_text(text)
    return text
