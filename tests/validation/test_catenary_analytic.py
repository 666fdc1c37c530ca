"""Validation of rfesim.catenary against published reference numbers and independent checks.

Reference data: MoorPy (NREL), ``tests/test_catenary.py`` -- inputs
``(XF, ZF, L, EA, W, CB)`` and results ``(fAH, fAV, fBH, fBV, LBot)`` of its ``catenary``
function.  MoorPy converges to an absolute closure error of about 1e-5 m, so its tensions
are accurate to a few 1e-7 relative; the tolerances below (1e-5 relative unless stated) are
well above that and well below any modelling error.

MoorPy's case with W = 200 N/m uses CB = -372.7, i.e. a seabed 372.7 m below end A that the
line never reaches; here that is ``seabed=False``.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from rfesim import catenary as catenary_module
from rfesim.catenary import CatenarySolution, hanging_length, natural_catenary, solve_catenary

# MoorPy test geometry: span 400 m, height 200 m, length 500 m, EA 7.51e12 N.
SPAN = 400.0
HEIGHT = 200.0
LENGTH = 500.0
AXIAL_STIFFNESS = 7.51e12


def one_sided_derivative(function, point, step):
    """Second-order backward difference f'(point) ~ (3 f(p) - 4 f(p - h) + f(p - 2h)) / (2 h)."""
    return (3.0 * function(point) - 4.0 * function(point - step) + function(point - 2.0 * step)) / (2.0 * step)


# ------------------------------------------------------------------ MoorPy reference numbers
def test_partly_grounded_no_friction_matches_moorpy():
    solution = solve_catenary(SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS, seabed=True)
    assert solution.regime == "grounded"
    assert solution.horizontal_tension == pytest.approx(96643.4, rel=1e-5)
    assert solution.vertical_tension_top == pytest.approx(237751.8, rel=1e-5)
    assert solution.grounded_length == pytest.approx(202.810, rel=1e-4)
    # No friction: the anchor sees the full horizontal tension and no vertical load.
    assert solution.vertical_tension_anchor == 0.0
    assert solution.anchor_tension == pytest.approx(solution.horizontal_tension, rel=1e-14)
    assert solution.top_tension == pytest.approx(math.hypot(96643.4, 237751.8), rel=1e-5)
    assert solution.suspended_length + solution.grounded_length == pytest.approx(LENGTH, rel=1e-14)
    assert solution.suspended_length == pytest.approx(solution.vertical_tension_top / 800.0, rel=1e-14)


def test_partly_grounded_with_friction_matches_moorpy():
    solution = solve_catenary(SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS, seabed=True, friction=0.1)
    assert solution.anchor_tension == pytest.approx(80418.6, rel=1e-5)
    # MoorPy: fairlead tensions and grounded length are (almost) unchanged by friction.
    assert solution.horizontal_tension == pytest.approx(96643.4, rel=1e-5)
    assert solution.vertical_tension_top == pytest.approx(237751.8, rel=1e-5)
    assert solution.grounded_length == pytest.approx(202.810, rel=1e-4)
    # Anchor tension = H - C_B w L_b (tension still positive at the anchor).
    expected = solution.horizontal_tension - 0.1 * 800.0 * solution.grounded_length
    assert solution.anchor_tension == pytest.approx(expected, rel=1e-14)


def test_partly_grounded_with_large_friction_has_zero_anchor_tension():
    # MoorPy case CB = 5: fAH = 0, fBH = -96643.435, fBV = -237751.760, LBot = 202.8103.
    solution = solve_catenary(SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS, seabed=True, friction=5.0)
    assert solution.anchor_tension == 0.0
    assert solution.horizontal_tension == pytest.approx(96643.43501616362, rel=1e-5)
    assert solution.vertical_tension_top == pytest.approx(237751.75997440016, rel=1e-5)
    assert solution.grounded_length == pytest.approx(202.81030003199982, rel=1e-4)
    # The tension along the grounded part reaches zero before the anchor.
    zero_point = solution.grounded_length - solution.horizontal_tension / (5.0 * 800.0)
    assert zero_point > 0.0
    assert solution.tension(np.array([0.0, 0.5 * zero_point]))[1] == 0.0


def test_fully_suspended_light_line_matches_moorpy():
    solution = solve_catenary(SPAN, HEIGHT, LENGTH, 200.0, AXIAL_STIFFNESS, seabed=False)
    assert solution.regime == "suspended"
    assert solution.grounded_length == 0.0
    assert solution.horizontal_tension == pytest.approx(43694.6, rel=1e-5)
    assert solution.vertical_tension_top == pytest.approx(77634.4, rel=1e-5)
    # The validation list gives the anchor vertical tension as 22365.6 N (magnitude).  With
    # this module's convention V_A = V_B - w L (MoorPy's fAV), it is negative: the line leaves
    # the anchor going down and sags below it.
    assert solution.vertical_tension_anchor == pytest.approx(-22365.6, rel=1e-5)
    assert abs(solution.vertical_tension_anchor) == pytest.approx(22365.6, rel=1e-5)
    assert solution.anchor_tension == pytest.approx(math.hypot(43694.6, 22365.6), rel=1e-5)
    # MoorPy put its seabed 372.7 m below end A; the line stays clear of it.
    _, z = solution.profile(np.linspace(0.0, LENGTH, 2001))
    assert -372.7 < z.min() < 0.0


def test_fully_suspended_elastic_line_matches_moorpy():
    # MoorPy case 5: (89.9, 59.2, 130.0, EA 7.51e8, W 881.05, CB -372.7): the stretch matters.
    solution = solve_catenary(89.9, 59.2, 130.0, 881.05, 751000000.0, seabed=False)
    assert solution.horizontal_tension == pytest.approx(31373.229006023103, rel=1e-6)
    assert solution.vertical_tension_anchor == pytest.approx(-26650.341270116318, rel=1e-6)
    assert solution.vertical_tension_top == pytest.approx(87886.15872988368, rel=1e-6)


# ------------------------------------------------------------------ natural catenary
def test_natural_catenary_reference_numbers():
    result = natural_catenary(356.2532, 100.0, 150e3)
    assert result["suspended_length"] == pytest.approx(306.936, rel=1e-5)
    assert result["horizontal_span"] == pytest.approx(284.733, rel=1e-5)
    assert result["top_tension"] == pytest.approx(185.625e3, rel=1e-5)
    assert result["top_angle_deg"] == pytest.approx(36.0913, rel=1e-5)
    assert result["touchdown_curvature"] == pytest.approx(356.2532 / 150e3, rel=1e-14)


def test_natural_catenary_agrees_with_inextensible_grounded_solution():
    """A nearly inextensible line ending in a long grounded part has the natural catenary shape."""
    weight, height, horizontal_tension = 356.2532, 100.0, 150e3
    natural = natural_catenary(weight, height, horizontal_tension)
    grounded_length = 400.0
    solution = solve_catenary(
        grounded_length + natural["horizontal_span"], height,
        grounded_length + natural["suspended_length"], weight, 1e15, seabed=True,
    )
    assert solution.horizontal_tension == pytest.approx(horizontal_tension, rel=1e-7)
    assert solution.grounded_length == pytest.approx(grounded_length, rel=1e-7)
    assert solution.top_tension == pytest.approx(natural["top_tension"], rel=1e-7)


# ------------------------------------------------------------------ profile
PROFILE_CASES = [
    # span, height, length, weight, EA, seabed, friction
    pytest.param(SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS, True, 0.0, id="moorpy-grounded"),
    pytest.param(SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS, True, 0.1, id="moorpy-friction"),
    pytest.param(SPAN, HEIGHT, LENGTH, 200.0, AXIAL_STIFFNESS, False, 0.0, id="moorpy-suspended"),
    pytest.param(300.0, 120.0, 400.0, 1500.0, 2e7, True, 0.02, id="elastic-grounded-friction"),
    pytest.param(300.0, 120.0, 400.0, 1500.0, 2e7, True, 20.0, id="elastic-zero-anchor-tension"),
    pytest.param(300.0, 120.0, 340.0, 1500.0, 2e7, True, 0.0, id="elastic-suspended-over-seabed"),
    pytest.param(300.0, -50.0, 400.0, 1500.0, 2e7, False, 0.0, id="fairlead-below-anchor"),
    pytest.param(300.0, 400.0, 480.0, 600.0, 1e8, True, 0.0, id="taut-shorter-than-chord"),
]


@pytest.mark.parametrize("span, height, length, weight, EA, seabed, friction", PROFILE_CASES)
def test_profile_ends_and_fairlead_slope(span, height, length, weight, EA, seabed, friction):
    solution = solve_catenary(span, height, length, weight, EA, seabed=seabed, friction=friction)
    x, z = solution.profile(np.array([0.0, length]))
    scale = max(length, math.hypot(span, height))
    assert x[0] == 0.0 and z[0] == 0.0
    assert abs(x[1] - span) <= 1e-11 * scale
    assert abs(z[1] - height) <= 1e-11 * scale
    # Slope at the fairlead: the line is tangent to the tension, dz/dx = V_B / H.
    step = 1e-3 * length
    dx_ds = one_sided_derivative(lambda s: solution.profile(s)[0], length, step)
    dz_ds = one_sided_derivative(lambda s: solution.profile(s)[1], length, step)
    expected = solution.vertical_tension_top / solution.horizontal_tension
    assert dz_ds / dx_ds == pytest.approx(expected, rel=1e-5)
    assert solution.slope(length) == pytest.approx(expected, rel=1e-14)
    # Scalar input works too.
    x_end, z_end = solution.profile(length)
    assert np.ndim(x_end) == 0 and float(x_end) == pytest.approx(span, rel=1e-11, abs=1e-11 * scale)


@pytest.mark.parametrize("span, height, length, weight, EA, seabed, friction", PROFILE_CASES)
def test_profile_matches_independent_quadrature(span, height, length, weight, EA, seabed, friction):
    """Integrate the stretched tangent numerically: d(x, z)/ds = (H, V(s)) / T(s) * (1 + T(s)/EA)."""
    solution = solve_catenary(span, height, length, weight, EA, seabed=seabed, friction=friction)
    H = solution.horizontal_tension
    grounded = solution.grounded_length

    def vertical_tension(s):
        if grounded > 0.0:
            return 0.0 if s <= grounded else weight * (s - grounded)
        return solution.vertical_tension_anchor + weight * s

    def tension(s):
        if s <= grounded:  # friction: tension decreases toward the anchor, floored at zero
            return max(H - friction * weight * (grounded - s), 0.0)
        return math.hypot(H, vertical_tension(s))

    def dx_ds(s):
        if s <= grounded:
            return 1.0 + tension(s) / EA
        return H / tension(s) * (1.0 + tension(s) / EA)

    def dz_ds(s):
        if s <= grounded:
            return 0.0
        return vertical_tension(s) / tension(s) * (1.0 + tension(s) / EA)

    stations = np.linspace(0.0, length, 9)
    x, z = solution.profile(stations)
    # Kinks of the integrands: touchdown point and, with friction, where the tension hits zero.
    breakpoints = [grounded] if 0.0 < grounded < length else []
    if friction > 0.0 and grounded > 0.0:
        breakpoints.append(max(grounded - H / (friction * weight), 0.0))
    for station, x_station, z_station in zip(stations, x, z):
        points = [p for p in breakpoints if 0.0 < p < station] or None
        x_quad = quad(dx_ds, 0.0, station, points=points, epsabs=1e-12, epsrel=1e-12, limit=200)[0]
        z_quad = quad(dz_ds, 0.0, station, points=points, epsabs=1e-12, epsrel=1e-12, limit=200)[0]
        assert x_station == pytest.approx(x_quad, rel=1e-9, abs=1e-9 * length)
        assert z_station == pytest.approx(z_quad, rel=1e-9, abs=1e-9 * length)


def test_profile_rejects_arc_length_outside_line():
    solution = solve_catenary(SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS)
    with pytest.raises(ValueError, match="arc length"):
        solution.profile([-1.0, 10.0])
    with pytest.raises(ValueError, match="arc length"):
        solution.profile(LENGTH + 1.0)


# ------------------------------------------------------------------ special regimes
def test_taut_line_shorter_than_chord_is_stretched():
    weight, EA, length = 600.0, 1e9, 480.0
    span, height = 300.0, 400.0  # chord 500 m > length 480 m
    solution = solve_catenary(span, height, length, weight, EA)
    assert solution.regime == "suspended"
    assert solution.vertical_tension_anchor > 0.0
    # Mean axial tension ~ EA * strain; the weight only bends the line a little.
    mean_tension = 0.5 * (solution.top_tension + solution.anchor_tension)
    assert mean_tension == pytest.approx(EA * (500.0 / length - 1.0), rel=1e-3)


def test_solution_is_continuous_across_touchdown_onset():
    """Regime change between fully suspended and grounded at V_B = w L: no jump in tension."""
    weight, EA, height, length = 1000.0, 1e9, 100.0, 400.0
    # Find the span at which V_A = 0 (the line just touches down at the anchor).
    suspended = solve_catenary(390.0, height, length, weight, EA)
    grounded = solve_catenary(370.0, height, length, weight, EA)
    assert suspended.regime == "suspended" and grounded.regime == "grounded"
    low, high = 370.0, 390.0
    for _ in range(60):
        middle = 0.5 * (low + high)
        if solve_catenary(middle, height, length, weight, EA).regime == "grounded":
            low = middle
        else:
            high = middle
    below = solve_catenary(low, height, length, weight, EA)
    above = solve_catenary(high, height, length, weight, EA)
    assert below.horizontal_tension == pytest.approx(above.horizontal_tension, rel=1e-9)
    assert below.vertical_tension_top == pytest.approx(weight * length, rel=1e-9)
    assert above.vertical_tension_anchor == pytest.approx(0.0, abs=1e-6 * weight * length)


def test_slack_limit_hangs_vertically_onto_seabed():
    weight, EA, height = 1000.0, 1e8, 100.0
    hanging = hanging_length(weight, EA, height)
    assert hanging + weight * hanging ** 2 / (2 * EA) == pytest.approx(height, rel=1e-14)
    # Just shorter than the slack limit: tiny H, nearly the hanging length suspended.
    nearly = solve_catenary(200.0, height, 200.0 + hanging - 1e-3, weight, EA)
    assert nearly.regime == "grounded"
    assert nearly.horizontal_tension < 1e-2 * weight * height
    # At and beyond the limit: H = 0, vertical hanging part, the rest on the seabed.
    slack = solve_catenary(200.0, height, 250.0 + hanging, weight, EA)
    assert slack.regime == "slack_vertical"
    assert slack.horizontal_tension == 0.0
    assert slack.vertical_tension_top == pytest.approx(weight * hanging, rel=1e-14)
    assert slack.suspended_length == pytest.approx(nearly.suspended_length, rel=1e-3)
    x, z = slack.profile(np.array([0.0, slack.length]))
    assert x[1] == pytest.approx(200.0) and z[1] == pytest.approx(height, rel=1e-12)


def test_line_lying_on_seabed_with_friction_matches_moorpy_profile_type_0():
    weight, EA, length, friction = 1000.0, 1e8, 500.0, 0.5
    # Tension at the anchor: H = EA (span/L - 1) + C_B w L / 2, anchor H - C_B w L.
    solution = solve_catenary(502.0, 0.0, length, weight, EA, friction=friction)
    assert solution.regime == "on_seabed"
    assert solution.horizontal_tension == pytest.approx(EA * 2.0 / length + 0.5 * friction * weight * length)
    assert solution.anchor_tension == pytest.approx(solution.horizontal_tension - friction * weight * length)
    # Smaller stretch: the tension reaches zero before the anchor.
    solution = solve_catenary(500.01, 0.0, length, weight, EA, friction=friction)
    assert solution.horizontal_tension == pytest.approx(math.sqrt(2 * EA * friction * weight * 0.01))
    assert solution.anchor_tension == 0.0
    x, z = solution.profile(np.array([0.0, length]))
    assert x[1] == pytest.approx(500.01, rel=1e-14) and z[1] == 0.0


@pytest.mark.parametrize("height", [150.0, 40.0, -40.0, -150.0])
def test_vertical_line(height):
    weight, EA, length = 1000.0, 1e6, 100.0  # hanging stretched length 105 m
    solution = solve_catenary(0.0, height, length, weight, EA, seabed=False)
    assert solution.regime == "vertical"
    assert solution.vertical_tension_top - solution.vertical_tension_anchor == pytest.approx(weight * length)
    x, z = solution.profile(np.array([0.0, length]))
    assert x[1] == 0.0 and z[1] == pytest.approx(height, rel=1e-12)


def test_root_fallback_is_used_when_newton_fails(monkeypatch):
    reference = solve_catenary(SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS)

    def failing_newton(equations, start, scale, tol, max_iterations=200):
        if failing_newton.calls < 2:  # both Newton starts fail
            failing_newton.calls += 1
            return start[0], start[1], 1.0, False
        return original_newton(equations, start, scale, tol, max_iterations)

    failing_newton.calls = 0
    original_newton = catenary_module._newton
    monkeypatch.setattr(catenary_module, "_newton", failing_newton)
    solution = solve_catenary(SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS)
    assert failing_newton.calls == 2
    assert solution.horizontal_tension == pytest.approx(reference.horizontal_tension, rel=1e-10)
    assert solution.vertical_tension_top == pytest.approx(reference.vertical_tension_top, rel=1e-10)


def test_solution_is_frozen():
    solution = solve_catenary(SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS)
    assert isinstance(solution, CatenarySolution)
    with pytest.raises(AttributeError):
        solution.horizontal_tension = 1.0


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    "arguments, keywords, field",
    [
        ((SPAN, HEIGHT, 0.0, 800.0, AXIAL_STIFFNESS), {}, "length"),
        ((SPAN, HEIGHT, -5.0, 800.0, AXIAL_STIFFNESS), {}, "length"),
        ((SPAN, HEIGHT, LENGTH, 0.0, AXIAL_STIFFNESS), {}, "weight"),
        ((SPAN, HEIGHT, LENGTH, -800.0, AXIAL_STIFFNESS), {}, "weight"),
        ((SPAN, HEIGHT, LENGTH, 800.0, 0.0), {}, "EA"),
        ((SPAN, HEIGHT, LENGTH, 800.0, -1.0), {}, "EA"),
        ((-1.0, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS), {}, "span"),
        ((SPAN, -1.0, LENGTH, 800.0, AXIAL_STIFFNESS), {"seabed": True}, "height"),
        ((SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS), {"friction": -0.1}, "friction"),
        ((SPAN, HEIGHT, LENGTH, 800.0, AXIAL_STIFFNESS), {"tol": 0.0}, "tol"),
        ((SPAN, float("nan"), LENGTH, 800.0, AXIAL_STIFFNESS), {}, "height"),
    ],
)
def test_bad_input_names_the_field(arguments, keywords, field):
    with pytest.raises(ValueError, match=rf"^{field}\b"):
        solve_catenary(*arguments, **keywords)


def test_negative_height_is_allowed_without_seabed():
    solution = solve_catenary(SPAN, -1.0, LENGTH, 800.0, AXIAL_STIFFNESS, seabed=False)
    assert solution.regime == "suspended"


@pytest.mark.parametrize(
    "arguments, field",
    [
        ((0.0, 100.0, 150e3), "weight"),
        ((356.0, -1.0, 150e3), "height"),
        ((356.0, 100.0, 0.0), "horizontal_tension"),
    ],
)
def test_natural_catenary_bad_input_names_the_field(arguments, field):
    with pytest.raises(ValueError, match=rf"^{field}\b"):
        natural_catenary(*arguments)
