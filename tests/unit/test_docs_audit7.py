"""Docs audit 7: LineResults.sagbend_overbend for a line grounded at either end (a pipe laid
from a vessel has end B on the seabed), the validation report covering every VALIDATION.md
case with the test that asserts each row, and the package and Results docstrings."""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.results import LineResults, Results

ROOT = Path(__file__).resolve().parents[2]
KEYS = ("sagbend_moment", "sagbend_curvature", "overbend_moment", "overbend_curvature")


def s_shaped_line(nt=3, n=60, reverse=False, touchdown=30.0):
    """A line 100 m long lying on the seabed (z = -50) over its first 30 m, then rising to z = 0
    along a half cosine: sag bend (concave up) below s = 65, overbend above. ``reverse``: the
    same line numbered from its top (end A up, end B on the seabed, as a laid pipe)."""
    L = 100.0
    pts = np.linspace(0.0, L, n + 2)
    z = np.where(pts < 30.0, -50.0, -50.0 + 25.0 * (1.0 - np.cos(np.pi * (pts - 30.0) / 70.0)))
    s = 0.5 * (pts[:-1] + pts[1:])[:n]
    curvature = np.abs(np.interp(s, pts, np.gradient(np.gradient(z, pts), pts)))
    # a moment that tells sag bend and overbend apart, largest at the last time
    moment = np.where(s < 65.0, 1e5, 3e5) * curvature / curvature.max() * (1.0 + 0.2 * np.arange(nt))[:, None]
    curvature = np.repeat(curvature[None], nt, 0)
    td = touchdown
    if reverse:
        pts, s, z, td = L - pts[::-1], L - s[::-1], z[::-1], L - touchdown
        moment, curvature = moment[:, ::-1], curvature[:, ::-1]
    pos = np.zeros((nt, n + 2, 3))
    pos[:, :, 0] = pts if not reverse else L - pts
    pos[:, :, 2] = z
    z3 = np.zeros((nt, 3))
    zs = np.zeros((nt, n))
    return LineResults(name="pipe", arc_length=pts, sde_arc_length=s, position=pos, tension=zs, shear_force=zs,
                       bend_moment=moment, torque=zs, curvature=curvature, end_a_force=z3, end_b_force=z3,
                       end_a_moment=z3, end_b_moment=z3, seabed_force=np.zeros((nt, n + 1)),
                       end_a_direction=z3, end_b_direction=z3, touchdown_arc_length=np.full(nt, td))


def test_sagbend_overbend_is_the_same_from_either_end():
    """The line grounded at end A (a riser) and the same line grounded at end B (a laid pipe)
    give the same sag bend and overbend maxima: 1e5 * 1.4 and 3e5 * 1.4 N m."""
    riser = s_shaped_line().sagbend_overbend()
    lay = s_shaped_line(reverse=True).sagbend_overbend()
    for key in KEYS:
        assert lay[key] == pytest.approx(riser[key], rel=1e-12), key
    assert lay["sagbend_moment"] == pytest.approx(1.4e5, rel=0.05)
    assert lay["overbend_moment"] == pytest.approx(4.2e5, rel=0.05)


@pytest.mark.parametrize("reverse", [False, True])
def test_sagbend_overbend_seabed_touchdown_false_splits_at_the_lowest_point(reverse):
    """A touchdown channel past the sag bend (s = 70 m from the grounded end) hides it; with
    ``seabed_touchdown=False`` the line is split at its lowest point instead and finds it."""
    line = s_shaped_line(reverse=reverse, touchdown=70.0)
    assert line.sagbend_overbend()["sagbend_moment"] == 0.0
    out = line.sagbend_overbend(seabed_touchdown=False)
    assert out["sagbend_moment"] == pytest.approx(1.4e5, rel=0.05)
    assert out["overbend_moment"] == pytest.approx(4.2e5, rel=0.05)


def test_sagbend_overbend_of_the_s_lay_scenario_matches_lay_summary():
    """scenarios/s_lay.json statics: end A on the barge, end B on the seabed. The maxima are
    lay_summary's (before the fix: sagbend 3388 against 91085 N m, overbend 59 against
    413027 N m, from the grounded part)."""
    from rfesim.lay_results import lay_summary
    res = rfesim.statics(rfesim.load_scenario(ROOT / "scenarios" / "s_lay.json"))
    line = res.line("pipe")
    assert line.position[0, 0, 2] > line.position[0, -1, 2]          # end A is the top
    out = line.sagbend_overbend()
    ref = lay_summary(res)
    for key in KEYS:
        assert out[key] == pytest.approx(ref[key], rel=1e-12), key
    # the overbend on the stinger is the most bent part of the suspended pipe
    above = line.sde_arc_length <= line.touchdown_arc_length[0]
    assert out["overbend_moment"] == pytest.approx(line.bend_moment[0][above].max(), rel=1e-12)
    assert out["sagbend_moment"] > 10.0 * line.bend_moment[0][~above].max()


# --------------------------------------------------------------------------- validation report
CASES = ("R1 tip force", "R1 tip moment", "B1 alpha = 1", "B1 alpha = 10", "B2 full circle",
         "B4 cantilever frequencies", "B5 hanging chain", "B9 pendulum", "P1 catenary on the seabed",
         "P1 fully suspended", "P1 seabed friction 0.1", "P2 natural catenary, S-lay sagbend",
         "P4 elasto-plastic bending", "W1 Airy dispersion", "W1 crest velocity", "W2 JONSWAP",
         "W3 Morison, vertical cylinder", "C1 snap load", "C2 parametric resonance")


def _named_test_exists(name: str) -> bool:
    file, func = name.split("::")
    path = ROOT / "tests" / "validation" / file
    return path.is_file() and re.search(rf"^def {re.escape(func.split('[')[0])}\(", path.read_text(), re.M)


def test_validation_report_has_every_case_and_names_its_tests():
    """docs/validation.md (written by rfesim.bench.validation): a row for every case of
    VALIDATION.md, each naming an existing test in tests/validation, all within tolerance."""
    text = (ROOT / "docs" / "validation.md").read_text()
    rows = [[c.strip() for c in ln.strip("|").split("|")] for ln in text.splitlines()
            if ln.startswith("| ") and not ln.startswith("| case ")]
    assert {r[0] for r in rows} == set(CASES)
    for r in rows:
        test = r[-1].strip("`")
        assert test and _named_test_exists(test), r
    m = re.search(r"(\d+) of (\d+) rows within their tolerance", text)
    assert m and m.group(1) == m.group(2) == str(len(rows))


def test_validation_rows_of_the_cases_built_in_the_tests():
    """P2, P4, C1, C2 are computed from the tests' own builders and constants, and pass."""
    from rfesim.bench import validation
    rows = validation._p2_rows() + validation._p4_rows() + validation._c1_rows() + validation._c2_rows()
    assert {r["case"][:2] for r in rows} == {"P2", "P4", "C1", "C2"}
    assert all(r["pass"] for r in rows), [r for r in rows if not r["pass"]]
    assert all(_named_test_exists(r["test"]) for r in rows)
    text = validation.report(rows)
    assert "| C2 parametric resonance | swing growth at Omega/omega0 = 2 | > 10 |" in text


# --------------------------------------------------------------------------- docstrings
def test_package_docstring_example_scenario_exists():
    names = re.findall(r'load_scenario\("([^"]+)"\)', rfesim.__doc__)
    assert names and all((ROOT / n).is_file() for n in names)


def test_results_docstring_status_2_is_an_interruption():
    doc = Results.__doc__
    assert "2: interrupted" in doc and "2: cancelled" not in doc
