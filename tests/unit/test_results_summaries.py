"""Pipelay summaries of line results: range graphs, departure angle, sag/overbend maxima."""
from __future__ import annotations

import numpy as np
import pytest

from rfesim.results import LineResults


def synthetic_line(nt=4, nsde=50):
    """An S-shaped line: z = -cos(pi s / L) style (overbend near the top, sag bend below)."""
    L = 100.0
    pts = np.linspace(0.0, L, nsde + 2)
    s = 0.5 * (pts[:-1] + pts[1:])[:nsde]
    x = pts
    z = np.where(pts < 30.0, -50.0, -50.0 + 50.0 * (1 - np.cos(np.pi * (pts - 30.0) / 70.0)) / 2)
    pos = np.zeros((nt, nsde + 2, 3))
    pos[:, :, 0] = x
    pos[:, :, 2] = z
    rng = np.random.default_rng(1)
    tension = rng.uniform(1e3, 2e3, size=(nt, nsde))
    curvature = np.abs(np.interp(s, pts, np.gradient(np.gradient(z, pts), pts)))[None, :].repeat(nt, 0)
    moment = 1e6 * curvature * (1.0 + 0.1 * np.arange(nt))[:, None]
    z3 = np.zeros((nt, 3))
    direction = np.tile([np.cos(np.radians(30)), 0.0, np.sin(np.radians(30))], (nt, 1))
    return LineResults(name="p", arc_length=pts, sde_arc_length=s, position=pos, tension=tension,
                       shear_force=np.zeros_like(tension), bend_moment=moment, torque=np.zeros_like(tension),
                       curvature=curvature, end_a_force=z3, end_b_force=z3, end_a_moment=z3, end_b_moment=z3,
                       seabed_force=np.zeros((nt, nsde + 1)), end_a_direction=direction, end_b_direction=direction,
                       touchdown_arc_length=np.full(nt, 30.0))


def test_range_graph_is_min_max_mean_over_time():
    line = synthetic_line()
    rg = line.range_graph("tension")
    np.testing.assert_array_equal(rg["min"], line.tension.min(axis=0))
    np.testing.assert_array_equal(rg["max"], line.tension.max(axis=0))
    np.testing.assert_allclose(rg["mean"], line.tension.mean(axis=0))
    np.testing.assert_array_equal(rg["arc_length"], line.sde_arc_length)
    late = line.range_graph("tension", t_from=2.0, time=np.arange(4.0))
    np.testing.assert_array_equal(late["max"], line.tension[2:].max(axis=0))
    z = line.range_graph("position_z")
    assert z["min"].shape == line.arc_length.shape
    with pytest.raises(ValueError):
        line.range_graph("end_b_force")


def test_departure_angle_and_strain():
    line = synthetic_line()
    assert line.departure_angle == pytest.approx(np.full(4, 30.0))
    np.testing.assert_allclose(line.bending_strain(0.3), 0.15 * line.curvature)


def test_sagbend_and_overbend_maxima():
    """z'' > 0 (sag bend) on the lower half of the cosine, < 0 (overbend) on the upper half;
    the largest moment comes from the last time (factor 1.3)."""
    line = synthetic_line()
    out = line.sagbend_overbend()
    s = line.sde_arc_length
    lower = (s > 30.0) & (s < 65.0)
    upper = s > 65.0
    assert out["sagbend_moment"] == pytest.approx(line.bend_moment[-1][lower].max(), rel=1e-2)
    assert out["overbend_moment"] == pytest.approx(line.bend_moment[-1][upper].max(), rel=1e-2)
    assert out["sagbend_curvature"] > 0 and out["overbend_curvature"] > 0
