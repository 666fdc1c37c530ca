"""A heavy line between two ends above the seabed that sags onto it: a U whose bottom lies on
the seabed between two touchdowns (rfesim.model.compile._two_touchdowns, docs/theory.md
section 6, 'Start shapes of clamped and buoyant slack lines').

Before, its start shape was the free catenary with the part below the seabed pushed up onto
it: the clipped sag was shorter than its arc length, the elements bunched up there and
statics either failed (280 m) or converged to the bunched line (300 m: a horizontal tension
of 11.1 kN, four times the 2.83 kN of the U). The reference is the inextensible catenary of
each side, checked here against rfesim.catenary.solve_catenary.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.catenary import solve_catenary
from rfesim.model.compile import _two_touchdowns

G = 9.81
RHO = 1025.0
MASS = 80.0                 # kg/m, a chain-like line
D = 0.1                     # m
DEPTH = 100.0
ZA, ZB, SPAN = -50.0, -30.0, 200.0
W = MASS * G - RHO * G * math.pi / 4.0 * D * D      # N/m submerged
# heights of the ends above the contact level (the seabed plus the line's radius)
HA, HB = ZA + DEPTH - 0.5 * D, ZB + DEPTH - 0.5 * D


def scene(length: float, EI: float = 1.0e3, elements: int = 100) -> dict:
    return {"name": "U-shaped line", "environment": {"gravity": G, "water": {"density": RHO, "depth": DEPTH},
                                                      "seabed": {"normal_stiffness": 1.0e6, "damping_ratio": 0.5}},
            "line_types": {"chain": {"EA": 5.0e8, "EIy": EI, "mass_per_length": MASS, "outer_diameter": D}},
            "lines": {"l": {"type": "chain", "length": length, "elements": elements,
                            "end_a": {"attach": "fixed", "position": [0.0, 0.0, ZA], "connection": "pinned"},
                            "end_b": {"attach": "fixed", "position": [SPAN, 0.0, ZB], "connection": "pinned"}}},
            "analysis": {"statics": {"enabled": True}}}


def test_each_side_is_the_touchdown_catenary_of_solve_catenary():
    """Each side of the U, cut in the middle of its laid part, is the grounded catenary that
    rfesim.catenary solves for its span, height and length: the same horizontal tension."""
    s, x, z, T = _two_touchdowns(HA, HB, SPAN, 280.0, W)
    assert s[-1] == pytest.approx(280.0, rel=1e-14) and x[-1] == SPAN and z[-1] == HB
    assert z[0] == pytest.approx(HA, rel=1e-12) and x[0] == pytest.approx(0.0, abs=1e-9)
    H = float(T.min())
    laid = s[z <= 1e-12]
    assert laid.size > 10
    cut = 0.5 * (laid[0] + laid[-1])
    xc = float(np.interp(cut, s, x))
    for span, height, length in ((xc, HA, cut), (SPAN - xc, HB, 280.0 - cut)):
        sol = solve_catenary(span, height, length, W, 1.0e15, seabed=True)
        assert sol.regime == "grounded"
        assert sol.horizontal_tension == pytest.approx(H, rel=1e-6)
    # the arc length of the polyline is the line's (to the spacing's resolution)
    assert float(np.sum(np.hypot(np.diff(x), np.diff(z)))) == pytest.approx(280.0, rel=1e-5)


def test_no_u_when_the_line_cannot_reach_the_seabed_or_folds():
    limit = HA + HB + SPAN
    assert _two_touchdowns(HA, HB, SPAN, limit + 1.0, W) is None          # folds: no H > 0
    assert _two_touchdowns(HA, HB, SPAN, 220.0, W) is None                # hangs free above the seabed
    assert _two_touchdowns(HA, HB, SPAN, limit - 1.0, W) is not None


@pytest.mark.parametrize("length", [280.0, 300.0])
def test_statics_of_a_u_shaped_line_matches_the_catenary(length):
    res = rfesim.simulate(rfesim.load_scenario(scene(length)))
    line = res.line("l")
    fa, fb = np.asarray(line.end_a_force[0]), np.asarray(line.end_b_force[0])
    s, x, z, T = _two_touchdowns(HA, HB, SPAN, length, W)
    H = float(T.min())
    # the horizontal tension, and each end carrying the weight of its own side
    assert fa[0] == pytest.approx(H, rel=5e-3)
    assert -fb[0] == pytest.approx(H, rel=5e-3)
    va, vb = W * math.sqrt(HA * HA + 2.0 * HA * H / W), W * math.sqrt(HB * HB + 2.0 * HB * H / W)
    assert -fa[2] == pytest.approx(va, rel=5e-3)
    assert -fb[2] == pytest.approx(vb, rel=5e-3)
    # its bottom rests on the seabed over the laid length
    pos = np.asarray(line.position[0])
    on = pos[:, 2] < -DEPTH + D
    laid = float(np.ptp(pos[on, 0]))
    expected = float(np.ptp(x[z <= 1e-12]))
    assert laid == pytest.approx(expected, abs=2.0 * length / 100)


def test_a_u_too_long_to_lie_straight_says_it_folds():
    limit = HA + HB + SPAN
    with pytest.raises(rfesim.SolverError) as err:
        rfesim.simulate(rfesim.load_scenario(scene(330.0)))
    msg = str(err.value)
    assert (f"line 'l' hangs from two points {HA:.4g} m and {HB:.4g} m above the seabed, {SPAN:.4g} m apart, "
            f"and is {330.0 - limit:.4g} m longer (330 m) than can hang vertically from both") in msg


def _stiff_riser(length: float) -> dict:
    """scenarios/h1_riser_heave.json (a 0.3 m steel pipe, EI 3.64e7 N m^2) in 200 m of water:
    its ends 100 m and 190 m above the seabed, 250 m apart; statics only."""
    import json
    from pathlib import Path
    d = json.loads((Path(__file__).resolve().parents[2] / "scenarios" / "h1_riser_heave.json").read_text())
    d["environment"]["water"]["depth"] = 200.0
    d["lines"]["riser"]["length"] = length
    d["analysis"].pop("dynamics", None)
    return d


def test_a_slack_u_of_a_stiff_pipe_says_its_bending_governs():
    """At 500 m (40 m short of the fold) H is 4.75 kN: the bending length is 12 touchdown radii,
    the catenary start is far from the pipe's shape and statics fails; the hint says so, and its
    advice, a shorter line, converges."""
    with pytest.raises(rfesim.SolverError) as err:
        rfesim.simulate(rfesim.load_scenario(_stiff_riser(500.0)))
    msg = str(err.value)
    assert "line 'riser' sags onto the seabed in a U from two ends above it with a horizontal tension of only " in msg
    bend = float(msg.split("sqrt(EI / H) = ")[1].split(" m")[0])
    radius = float(msg.split("the catenary's radius ")[1].split(" m")[0])
    assert bend == pytest.approx(87.5, abs=0.5) and radius == pytest.approx(7.38, abs=0.05)
    res = rfesim.simulate(rfesim.load_scenario(_stiff_riser(450.0)))
    assert res.message.startswith("statics only")
