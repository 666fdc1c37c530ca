"""Statics of tension-only lines (ropes, ``tension_only: true``): a rope hanging between two
fixed points is the elastic catenary, the same equilibrium as the identical line that may
also take compression (docs/theory.md, 'Slack ropes in statics').

The catenary start of a strongly sagging line is its chord chain closed at end B, which is
compressed (every element of the 20 m rope on a 5 m span by 0.47 %): every rope element
starts slack, with no axial force and no axial stiffness, and Newton used to fail at load
factor 0. Statics now finds the equilibrium with compression allowed first and goes on from
it with the ropes tension-only, on the exact tangent at the kink of max(0, C eps).
"""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.catenary import solve_catenary

G = 9.81
MASS = 10.0                  # kg/m
EA = 1.0e8                   # N
LENGTH = 20.0                # m
WEIGHT = MASS * G            # N/m (in air)


def rope(span: float, *, tension_only: bool = True, elements: int = 20, EI: float = 0.0,
         gravity: float = G) -> dict:
    """A rope of LENGTH between two fixed points at the same height, ``span`` apart."""
    return {
        "name": "rope",
        "environment": {"gravity": gravity},
        "line_types": {"rope": {"EA": EA, "EIy": EI, "mass_per_length": MASS, "tension_only": tension_only}},
        "lines": {"r": {"type": "rope", "length": LENGTH, "elements": elements,
                        "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0]},
                        "end_b": {"attach": "fixed", "position": [span, 0.0, 0.0]}}},
        "analysis": {"statics": {"enabled": True}},
    }


def statics(scenario: dict):
    res = rfesim.statics(scenario)
    line = res.line("r")
    return res, np.asarray(line.end_a_force[0]), np.asarray(line.end_b_force[0]), np.asarray(line.tension[0])


# span, elements, relative tolerance on H and on the top tension against the analytic elastic
# catenary: the discretisation error of the rigid-element chain (H -0.43 %, top tension
# -2.5e-5 at 20 elements on the 5 m span, where the bottom of the U turns by w Delta / H =
# 1.3 rad per element; -7e-5 and -4e-7 at 40 elements; 15 m span: -6.1e-4 and -1.4e-4)
CASES = [(5.0, 20, 1e-2, 1e-4), (5.0, 40, 2e-4, 2e-6), (15.0, 20, 2e-3, 5e-4)]


@pytest.mark.parametrize("span, elements, tol_h, tol_top", CASES)
def test_hanging_rope_is_the_elastic_catenary(span, elements, tol_h, tol_top):
    res, a, b, tension = statics(rope(span, elements=elements))
    assert res.counters["newton_iterations"] < 20
    assert np.all(tension > 0.0)
    # the same line elastic in compression too: the same equilibrium (it is taut everywhere)
    _, a_el, b_el, tension_el = statics(rope(span, tension_only=False, elements=elements))
    assert np.all(tension_el > 0.0)
    for mine, elastic in ((a, a_el), (b, b_el)):
        assert np.abs(mine - elastic).max() <= 1e-6 * np.linalg.norm(elastic)
    assert np.linalg.norm(b) == pytest.approx(np.linalg.norm(b_el), rel=1e-6)
    # the analytic elastic catenary (rfesim.catenary); the line pulls end B towards A and down
    sol = solve_catenary(span, 0.0, LENGTH, WEIGHT, EA, seabed=False)
    assert -b[0] == pytest.approx(sol.horizontal_tension, rel=tol_h)
    assert a[0] == pytest.approx(sol.horizontal_tension, rel=tol_h)
    assert -b[2] == pytest.approx(sol.vertical_tension_top, rel=1e-7)      # half the weight
    assert -a[2] == pytest.approx(sol.vertical_tension_top, rel=1e-7)
    assert np.linalg.norm(b) == pytest.approx(sol.top_tension, rel=tol_top)
    assert np.linalg.norm(a) == pytest.approx(sol.top_tension, rel=tol_top)


def test_taut_rope_stretched_between_its_ends():
    """Shorter than the span: stretched (0.5 %), taut from the start; the direct solve."""
    span = 20.1
    res, a, b, tension = statics(rope(span))
    _, a_el, b_el, _ = statics(rope(span, tension_only=False))
    assert np.abs(b - b_el).max() <= 1e-6 * np.linalg.norm(b_el)
    sol = solve_catenary(span, 0.0, LENGTH, WEIGHT, EA, seabed=False)
    assert -b[0] == pytest.approx(sol.horizontal_tension, rel=1e-5)
    assert np.linalg.norm(b) == pytest.approx(sol.top_tension, rel=1e-5)
    assert tension.min() > 0.99 * sol.horizontal_tension


def test_weightless_slack_rope_crammed_into_its_contact_is_named():
    """No gravity, 20 m between points 5 m apart: a straight, compressed start. The rope's 20
    elements telescope until their axial contact holds them (rfesim.loads.tension_only), and
    statics converges to a straight column of contacts carrying compression (before the
    contact: every element slack, passed through its neighbours). A rope would buckle
    sideways, so this equilibrium is unstable; a warning says so, names the length field
    and the distance between the ends."""
    res, a, b, tension = statics(rope(5.0, gravity=0.0))
    # 15 m of overlap over 20 SDEs of equal force N, each past its contact's ramp: gap =
    # -(0.5 r + 0.05 r + N / C), r = 1 m inside, 0.75 m at the two ends' half elements
    # (C = EA / 1 m): 18 (0.55 + N/C) + 2 (0.4125 + N/C) = 15, N = 0.21375 C
    assert tension == pytest.approx(-EA * (15.0 - 18 * 0.55 - 2 * 0.4125) / 20.0, rel=1e-6)
    assert a[0] == pytest.approx(tension[0], rel=1e-6) and b[0] == pytest.approx(-tension[0], rel=1e-6)
    msg = res.message
    assert "statics warning: rope 'r' is crammed into itself: 20 of its 20 SDEs hold their elements in axial " \
           "contact" in msg
    assert "with 2.138e+04 kN of compression at arc length" in msg
    assert "more than the rope's weight (0 kN); a rope buckles sideways instead" in msg
    assert "it is 15 m longer than the distance between its ends (5 m): give lines.r.length nearer that" in msg


def test_slack_rope_in_gravity_is_not_named():
    """The same rope with its weight hangs as a catenary: no contact, no warning."""
    res, a, b, tension = statics(rope(5.0))
    assert tension.min() > 0.0 and "crammed" not in res.message


def test_stiff_rope_with_slack_bottom_elements():
    """EI = 1000 N m^2: the bottom of the U carries itself in bending, and the elements there
    are slack (the same line elastic in compression has them compressed). From the elastic
    equilibrium Newton needs the exact tangent at the kink of max(0, C eps) (a central
    difference straddles it and stalls Newton)."""
    res, a, b, tension = statics(rope(5.0, EI=1000.0))
    assert np.all(tension >= 0.0)
    assert np.count_nonzero(tension == 0.0) >= 2
    assert -b[2] == pytest.approx(0.5 * WEIGHT * LENGTH, rel=1e-7)
    assert a[0] == pytest.approx(-b[0], abs=1e-6 * np.linalg.norm(b))
