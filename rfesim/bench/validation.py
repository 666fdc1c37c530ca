"""Validation report: every case of VALIDATION.md with its reference, rfesim's result, the
error, the discretisation, the run time and the test that asserts it -> docs/validation.md
(``rfesim bench --only validation``). The same cases are asserted in tests/validation; the
cases whose scenarios live in those tests (P2, P4, C1, C2) are taken from them."""
from __future__ import annotations

import importlib.util
import math
import sys
import time
from pathlib import Path

from . import cases

ROOT = Path(__file__).resolve().parents[2]
TESTS = ROOT / "tests" / "validation"
P1_FRICTION_ANCHOR = 80418.6        # VALIDATION.md P1: anchor tension with axial seabed friction 0.1


def _row(case, quantity, reference, value, discretisation, seconds, tolerance, test=""):
    err = abs(value / reference - 1.0) if reference != 0 else abs(value)
    return {"case": case, "quantity": quantity, "reference": reference, "rfesim": value, "error": err,
            "discretisation": discretisation, "time": seconds, "tolerance": tolerance,
            "pass": err <= tolerance, "test": test}


def _bound_row(case, quantity, value, discretisation, seconds, test, above=None, below=None):
    """A row checked against a bound (``value > above`` or ``value < below``), not a reference."""
    bound = f"> {above:g}" if above is not None else f"< {below:g}"
    ok = value > above if above is not None else value < below
    return {"case": case, "quantity": quantity, "reference": bound, "rfesim": value, "error": None,
            "discretisation": discretisation, "time": seconds, "tolerance": None, "pass": bool(ok), "test": test}


def _tests_module(name: str):
    """A module of tests/validation (its scenario builders and constants), imported from the
    source tree once (the tests are no package)."""
    key = f"_rfesim_validation_{name}"
    if key not in sys.modules:
        if not (TESTS / f"{name}.py").is_file():
            raise FileNotFoundError(f"the validation report needs the source tree's tests: {TESTS / name}.py")
        spec = importlib.util.spec_from_file_location(key, TESTS / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[key] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            del sys.modules[key]
            raise
    return sys.modules[key]


# the test that asserts each row of rfesim.bench.sea_cases.validation_rows (by case, and quantity prefix)
_SEA_TESTS = {("W1 Airy dispersion", ""): "test_waves.py::test_W1_dispersion",
              ("W1 crest velocity", ""): "test_waves.py::test_W1_wheeler_and_linear_crest_velocity",
              ("W2 JONSWAP", "m0 (to"): "test_waves.py::test_W2_jonswap_spectral_moments",
              ("W2 JONSWAP", "T_m02 (to"): "test_waves.py::test_W2_jonswap_spectral_moments",
              ("W2 JONSWAP", "m0 of a 3 h"): "test_waves.py::test_W2_three_hour_realisation_reproduces_m0_and_Tz",
              ("W2 JONSWAP", "T_z of a 3 h"): "test_waves.py::test_W2_three_hour_realisation_reproduces_m0_and_Tz",
              ("W3 Morison, vertical cylinder", ""): "test_waves.py::test_W3_morison_on_a_fixed_vertical_cylinder"}


def _sea_test(row) -> str:
    hits = [test for (case, prefix), test in _SEA_TESTS.items()
            if row["case"] == case and row["quantity"].startswith(prefix)]
    return max(hits, key=len) if hits else ""


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
            test = f"test_beams.py::test_R1_linear_cantilever_tip_force[{n}-{shear}]"
            rows.append(_row("R1 tip force", f"deflection / P ({shear})", w_ref, w, f"{n} elements", dt, 1e-8, test))
            rows.append(_row("R1 tip force", f"tip rotation / P ({shear})", rot_ref, rot, f"{n} elements", dt, 1e-8,
                             test))
    ((w, rot), (w_ref, rot_ref)), dt = _timed(cases.r1_tip_moment, 12)
    test = "test_beams.py::test_R1_linear_cantilever_tip_moment[12]"
    rows.append(_row("R1 tip moment", "deflection / M", w_ref, w, "12 elements", dt, 1e-8, test))
    rows.append(_row("R1 tip moment", "tip rotation / M", rot_ref, rot, "12 elements", dt, 1e-8, test))
    for alpha, ref in cases.MATTIASSON.items():
        (w, u, r), dt = _timed(cases.mattiasson, 20, alpha)
        for name, ref_v, v in (("w/L", ref[0], w), ("u/L", ref[1], u), ("tip rotation", ref[2], r)):
            rows.append(_row(f"B1 alpha = {alpha:g}", name, ref_v, v, "20 elements", dt, 3e-3,
                             f"test_beams.py::test_B1_mattiasson_large_deflection[{alpha}]"))
    for alpha, ref in cases.MATTIASSON.items():
        (w, u, r), dt = _timed(cases.mattiasson, 40, alpha)
        rows.append(_row(f"B1 alpha = {alpha:g}", "w/L", ref[0], w, "40 elements", dt, 3e-3,
                         f"test_beams.py::test_B1_convergence_order_is_two[{alpha}]"))
    (line, M, err), dt = _timed(cases.end_moment, 20, 1.0)
    total = float((line.curvature[0] * (1.0 / 20)).sum())
    rows.append(_row("B2 full circle", "tip rotation [rad]", 2 * math.pi, total, "20 elements", dt, 1e-8,
                     "test_beams.py::test_B2_pure_end_moment[1.0]"))
    rows.append({"case": "B2 full circle", "quantity": "tip position error / L", "reference": 0.0, "rfesim": err,
                 "error": err, "discretisation": "20 elements", "time": dt, "tolerance": 1e-3, "pass": err < 1e-3,
                 "test": "test_beams.py::test_B2_closes_into_a_circle"})
    for n in (10, 20):
        ratios, dt = _timed(cases.b4_frequencies, n)
        for k in range(4):
            rows.append(_row("B4 cantilever frequencies", f"f{k + 1} / f{k + 1} continuum",
                             cases.B4_RATIOS[n][k], float(ratios[k]), f"{n} elements", dt, 1.5e-5,
                             f"test_beams.py::test_B4_cantilever_frequencies_rigid_shear[{n}]"))
    for n in (10, 40):
        c, dt = _timed(cases.chain_frequencies, n)
        for k, tol in ((0, 1e-3), (1, 1e-3 if n == 40 else 1e-2), (2, 5e-3 if n == 40 else 5e-2)):
            test = (f"test_beams.py::test_B5_hanging_chain_first_mode[{n}]" if k == 0
                    else "test_beams.py::test_B5_hanging_chain_higher_modes")
            rows.append(_row("B5 hanging chain", f"c{k + 1}", float(cases.CHAIN_C[k]), float(c[k]), f"{n} elements",
                             dt, tol, test))
    for theta, ref in cases.PENDULUM.items():
        ratio, dt = _timed(cases.pendulum_period_ratio, theta,
                           lambda T0: {"kind": "generalized-alpha", "time_step": T0 / 400, "rho_inf": 1.0})
        rows.append(_row("B9 pendulum", f"T/T0 at {theta:g} deg", ref, ratio, "4 elements, h = T0/400", dt, 5e-4,
                         f"test_beams.py::test_B9_large_amplitude_pendulum[{theta}]"))
    for n in (100, 200):
        res, dt = _timed(rfesim.statics, cases.catenary_line(n, 800.0))
        line = res.line("line")
        fb = line.end_b_force[0]
        grounded = (line.seabed_force[0].sum() - line.end_a_force[0][2]) / 800.0
        for name, ref, v in (("fairlead H [N]", cases.P1_SEABED["H"], -fb[0]),
                             ("fairlead V [N]", cases.P1_SEABED["V"], -fb[2]),
                             ("length on the seabed [m]", cases.P1_SEABED["grounded"], grounded)):
            rows.append(_row("P1 catenary on the seabed", name, ref, float(v), f"{n} elements", dt, 1e-3,
                             f"test_lines.py::test_P1_catenary_on_the_seabed[{n}]"))
        res, dt = _timed(rfesim.statics, cases.catenary_line(n, 200.0, seabed=False))
        line = res.line("line")
        fb, fa = line.end_b_force[0], line.end_a_force[0]
        for name, ref, v in (("fairlead H [N]", cases.P1_SUSPENDED["H"], -fb[0]),
                             ("fairlead V [N]", cases.P1_SUSPENDED["V"], -fb[2]),
                             ("anchor V [N]", cases.P1_SUSPENDED["V_anchor"], -fa[2])):
            rows.append(_row("P1 fully suspended", name, ref, float(v), f"{n} elements", dt, 1e-3,
                             f"test_lines.py::test_P1_fully_suspended[{n}]"))
        res, dt = _timed(rfesim.statics, cases.catenary_line(n, 800.0, friction=0.1))
        line = res.line("line")
        fb = line.end_b_force[0]
        for name, ref, v in (("anchor tension [N]", P1_FRICTION_ANCHOR, line.end_a_force[0][0]),
                             ("fairlead H [N]", cases.P1_SEABED["H"], -fb[0]),
                             ("fairlead V [N]", cases.P1_SEABED["V"], -fb[2])):
            rows.append(_row("P1 seabed friction 0.1", name, ref, float(v), f"{n} elements", dt, 1e-3,
                             f"test_lines.py::test_P1_catenary_with_axial_seabed_friction[{n}]"))
    rows += _p2_rows()
    rows += _p4_rows()
    from .sea_cases import validation_rows as sea_rows
    for r in sea_rows(_row, _timed):
        r["test"] = _sea_test(r)
        rows.append(r)
    rows += _c1_rows()
    rows += _c2_rows()
    return rows


def _p2_rows() -> list[dict]:
    """P2 as test_pipelay_statics.py::test_P2_natural_catenary_sagbend builds it (its section
    constants): anchor pinned on a stiff seabed with 60 m grounded, the top pinned at the
    analytic position, the length making H = 150 kN for the elastic line, EI -> 0."""
    import rfesim
    from scipy.optimize import brentq

    from ..catenary import natural_catenary, solve_catenary
    tp = _tests_module("test_pipelay_statics")
    w, EA, n = tp.W_SUB, tp.E * tp.AREA, 150
    H, h, grounded = 150e3, 100.0, 60.0
    nat = natural_catenary(w, h, H)
    span_total = nat["horizontal_span"] + grounded
    length = brentq(lambda L: solve_catenary(span_total, h, L, w, EA, seabed=True).horizontal_tension - H,
                    nat["suspended_length"] + grounded - 5.0, nat["suspended_length"] + grounded - 1e-6)
    k_bed = 1e9
    z_axis = -130.0 - w / k_bed
    sc = {"environment": {"gravity": tp.G, "seabed": {"z": -130.0, "normal_stiffness": k_bed, "damping_ratio": 0.0}},
          "line_types": {"p": {"EA": EA, "EIy": 1.0, "GJ": 1.0, "GA": EA / 3, "mass_per_length": w / tp.G}},
          "lines": {"pipe": {"type": "p", "length": length, "elements": n, "shear_stiffness": "kruszewski",
                             "end_a": {"attach": "fixed", "position": [0, 0, z_axis], "connection": "pinned"},
                             "end_b": {"attach": "fixed", "position": [span_total, 0, z_axis + h],
                                       "connection": "pinned"}}},
          "analysis": {"dynamics": {"enabled": False}}}
    res, dt = _timed(rfesim.statics, sc)
    line = res.line("pipe")
    top = -line.end_b_force[0]
    on_bed = (line.seabed_force[0].sum() - line.end_a_force[0][2]) / w
    test = "test_pipelay_statics.py::test_P2_natural_catenary_sagbend"
    rows = []
    for name, ref, v in (("top H [N]", H, top[0]),
                         ("top tension [N]", 185.625e3, math.hypot(top[0], top[2])),
                         ("top angle [deg]", 36.0913, math.degrees(math.atan2(top[2], top[0]))),
                         ("suspended length V / w [m]", 306.936, top[2] / w),
                         ("suspended length, line minus grounded [m]", 306.936, length - on_bed),
                         ("horizontal span [m]", 284.733, span_total - on_bed * (1 + H / EA)),
                         ("touchdown curvature [1/m]", w / H, line.curvature[0].max())):
        rows.append(_row("P2 natural catenary, S-lay sagbend", name, ref, float(v), f"{n} elements", dt, 1e-3, test))
    return rows


def _p4_rows() -> list[dict]:
    """P4 with test_plastic.py's section, laws and kernel helpers: the fibre model
    (rfesim.materials.section) and the SDE kernel built from a scenario material."""
    from scipy.optimize import brentq

    from ..materials.section import moment_curvature, plastic_moment, reeling, yield_curvature, yield_moment
    tp = _tests_module("test_plastic")
    rows = []
    case, tol, fibres = "P4 elasto-plastic bending", tp.TOL, "fibre model, 6 x 720 points"
    t0 = time.perf_counter()
    my, mp, ky = yield_moment(tp.EPP, tp.WALL), plastic_moment(tp.EPP, tp.WALL), yield_curvature(tp.EPP, tp.WALL)
    dt = time.perf_counter() - t0
    test = "test_plastic.py::test_p4_section_constants"
    rows += [_row(case, "M_y [kN m]", 506.01, my / 1e3, "closed form", dt, tol, test),
             _row(case, "M_p [kN m]", 676.34, mp / 1e3, "closed form", dt, tol, test),
             _row(case, "kappa_y [1/m]", 0.01336, ky, "closed form", dt, tol, test)]
    for label, law, ratios in (("epp", tp.EPP, tp.EPP_RATIOS), ("hardening", tp.HARD, tp.HARD_RATIOS)):
        k_law = yield_curvature(law, tp.WALL)
        for ratio, expected in ratios:
            m, dt = _timed(moment_curvature, law, tp.WALL, ratio * k_law)
            rows.append(_row(case, f"M/M_p at kappa/kappa_y = {ratio:g} ({label})", expected, float(m) / mp, fibres,
                             dt, tol, f"test_plastic.py::test_p4_fibre_moment_curvature[{label}]"))
    r, dt = _timed(reeling, tp.EPP, tp.WALL, 8.0)
    test = "test_plastic.py::test_p4_reeling_fibre_model"
    for name, ref, v in (("reeling: pipe axis radius [m]", 8.162, r.axis_radius),
                         ("reeling: outer fibre strain", 0.01984, r.outer_fibre_strain),
                         ("reeling: residual curvature [1/m]", 0.10470, r.residual_curvature)):
        rows.append(_row(case, name, ref, float(v), "fibre model, 4 x 360 points", dt, tol, test))
    kernel = "SDE kernel (scenario material)"
    for label, hardening, ratios in (("epp", 0.0, tp.EPP_RATIOS), ("hardening", 0.02, tp.HARD_RATIOS)):
        t0 = time.perf_counter()
        ps, params, hist = tp._kernel(hardening)
        values = [tp._kernel_moment(params, hist, ratio * ps.yield_curvature)[0][0] / ps.plastic_moment
                  for ratio, _ in ratios]
        dt = time.perf_counter() - t0
        for (ratio, expected), v in zip(ratios, values):
            rows.append(_row(case, f"M/M_p at kappa/kappa_y = {ratio:g} ({label})", expected, float(v), kernel, dt,
                             tol, f"test_plastic.py::test_p4_kernel_moment_curvature[{label}]"))
    t0 = time.perf_counter()
    ps, params, hist = tp._kernel(0.0)
    kappa = 1.0 / (8.0 + 0.5 * 0.3239)
    hist = tp._kernel_moment(params, hist, kappa)[1]
    residual = brentq(lambda k: tp._kernel_moment(params, hist, k)[0][0], 0.0, kappa, xtol=1e-14)
    dt = time.perf_counter() - t0
    rows.append(_row(case, "reeling: residual curvature [1/m]", 0.10470, residual, kernel, dt, tol,
                     "test_plastic.py::test_p4_reeling_kernel"))
    return rows


def _c1_rows() -> list[dict]:
    """C1 with test_bodies.py's snap_scenario: peak tension mg + sqrt((mg)^2 + k m v^2)."""
    import rfesim
    tb = _tests_module("test_bodies")
    m, k = 1.0e4, 2.5e6
    v = math.sqrt(2.0 * tb.G * 0.5)
    peak = m * tb.G + math.sqrt((m * tb.G) ** 2 + k * m * v * v)       # 602951 N (VALIDATION.md: 603 kN)
    rows = []
    for n in (1, 10):
        res, dt = _timed(rfesim.simulate, tb.snap_scenario(n))
        test = f"test_bodies.py::test_c1_snap_load[{n}]"
        for name, value in (("peak tension at the payload [N]", res.body("payload").connection_tension.max()),
                            ("peak tension at the top [N]", (-res.line("hoist").end_a_force[:, 2]).max())):
            rows.append(_row("C1 snap load", name, peak, float(value), f"{n} element{'s' if n > 1 else ''}, h = 2 ms",
                             dt, 1e-2, test))
    return rows


def _c2_rows() -> list[dict]:
    """C2 with test_bodies.py's pendulum_on_heaving_tip: the Mathieu band edges, and the
    growth of the swing (largest |x| after 120 s over that of 10-40 s) at heave frequency
    ratios inside, outside and near the edges of the band (the last four as the slow tests)."""
    tb = _tests_module("test_bodies")
    eps = 4.0 * 1.0 / tb.L_ROPE
    lo, hi = 2.0 / math.sqrt(1.0 + eps / 2 - eps ** 2 / 32), 2.0 / math.sqrt(1.0 - eps / 2 - eps ** 2 / 32)
    test = "test_bodies.py::test_c2_band_edges_from_mathieu"
    rows = [_row("C2 parametric resonance", "band, lower edge Omega/omega0", 1.9081, lo, "Mathieu, 2nd order", 0.0,
                 2e-3 / 1.9081, test),
            _row("C2 parametric resonance", "band, upper edge Omega/omega0", 2.1096, hi, "Mathieu, 2nd order", 0.0,
                 2e-3 / 2.1096, test)]
    for ratio, grows, bound, test in (
            (1.7, False, 1.5, "test_c2_parametric_resonance[1.7-False]"),
            (2.0, True, 10.0, "test_c2_parametric_resonance[2.0-True]"),
            (2.3, False, 1.5, "test_c2_parametric_resonance[2.3-False]"),
            (1.88, False, 1.5, "test_c2_band_edges[1.88-False]"),
            (1.93, True, 3.0, "test_c2_band_edges[1.93-True]"),
            (2.08, True, 3.0, "test_c2_band_edges[2.08-True]"),
            (2.14, False, 1.5, "test_c2_band_edges[2.14-False]")):
        growth, dt = _timed(tb.swing_growth, ratio)
        kw = {"above": bound} if grows else {"below": bound}
        rows.append(_bound_row("C2 parametric resonance", f"swing growth at Omega/omega0 = {ratio:g}", growth,
                               "10 elements, h = 0.02 s, 150 s", dt, f"test_bodies.py::{test}", **kw))
    return rows


def report(rows: list[dict]) -> str:
    out = ["# Validation report", "",
           "Every case of `VALIDATION.md` (reference numbers from closed forms or published solutions), "
           "computed by `rfesim bench --only validation`; each row names the test in `tests/validation/` that "
           "asserts it (plus convergence-order tests: B1 and B2 converge as 1/n^2, B4 with eq. 8.89 from above "
           "as 1/n^2). Error: relative to the reference; a row with a bound instead of a reference (C2: the swing "
           "grows inside the parametric-resonance band, not outside it) passes when the value is within it. "
           "Time: wall time of the case (statics, modes or dynamics, including numba's cache load on first use).",
           "", "| case | quantity | reference | rfesim | error | tolerance | discretisation | time [s] | test |",
           "|---|---|---:|---:|---:|---:|---|---:|---|"]
    for r in rows:
        ref = r["reference"] if isinstance(r["reference"], str) else f"{r['reference']:.7g}"
        err = "" if r["error"] is None else f"{r['error']:.2e}"
        tol = "" if r["tolerance"] is None else f"{r['tolerance']:.1e}"
        test = f"`{r['test']}`" if r.get("test") else ""
        out.append(f"| {r['case']} | {r['quantity']} | {ref} | {r['rfesim']:.7g} | {err} | "
                   f"{tol} | {r['discretisation']} | {r['time']:.2f} | {test} |")
    bad = [r for r in rows if not r["pass"]]
    out += ["", f"{len(rows) - len(bad)} of {len(rows)} rows within their tolerance."]
    return "\n".join(out) + "\n"


def write(path: Path) -> str:
    text = report(collect())
    path.write_text(text)
    return text
