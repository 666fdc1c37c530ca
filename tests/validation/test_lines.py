"""VALIDATION.md P1: catenary with the seabed (MoorPy's published test data), solved by
rfesim statics with EI -> 0 and >= 100 elements, tolerance 1e-3 relative."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.bench.cases import catenary_line


@pytest.mark.parametrize("n", [100, 200])
def test_P1_catenary_on_the_seabed(n):
    """Span 400 m, height 200 m, length 500 m, w = 800 N/m: fairlead H = 96643.4 N,
    V = 237751.8 N, 202.810 m on the seabed."""
    res = rfesim.statics(catenary_line(n, 800.0))
    line = res.line("line")
    fairlead = line.end_b_force[0]               # force of the line on the fairlead
    assert -fairlead[0] == pytest.approx(96643.4, rel=1e-3)
    assert -fairlead[2] == pytest.approx(237751.8, rel=1e-3)
    # the grounded length is carried by the seabed and, at its very end, by the anchor pin:
    # (total seabed force + anchor vertical support) / w
    grounded = (line.seabed_force[0].sum() - line.end_a_force[0][2]) / 800.0
    assert grounded == pytest.approx(202.810, rel=1e-3)
    # effective tension along the suspended part: T(s) = sqrt(H^2 + (V - w (L - s))^2)
    s_sde = line.sde_arc_length
    suspended = s_sde > 202.810 + 10.0
    expected = np.hypot(96643.4, 237751.8 - 800.0 * (500.0 - s_sde[suspended]))
    assert line.tension[0][suspended] == pytest.approx(expected, rel=1e-3)


@pytest.mark.parametrize("n", [100, 200])
def test_P1_fully_suspended(n):
    """Same geometry with w = 200 N/m and no seabed contact: H = 43694.6 N, fairlead
    V = 77634.4 N, anchor V = 22365.6 N (the line leaves the anchor going down)."""
    res = rfesim.statics(catenary_line(n, 200.0, seabed=False))
    line = res.line("line")
    fairlead = line.end_b_force[0]
    anchor = line.end_a_force[0]
    assert -fairlead[0] == pytest.approx(43694.6, rel=1e-3)
    assert -fairlead[2] == pytest.approx(77634.4, rel=1e-3)
    assert anchor[0] == pytest.approx(43694.6, rel=1e-3)
    assert -anchor[2] == pytest.approx(22365.6, rel=1e-3)      # pulls the anchor down
    assert line.position[0, :, 2].min() < -1.0                   # sags below the anchor


def test_P1_matches_the_analytic_elastic_catenary_profile():
    """The RFE shape lies on the analytic catenary (rfesim.catenary) within 1e-3 of the span."""
    from rfesim.catenary import solve_catenary
    res = rfesim.statics(catenary_line(100, 200.0, seabed=False))
    line = res.line("line")
    sol = solve_catenary(400.0, 200.0, 500.0, 200.0, 7.51e12, seabed=False)
    x, z = sol.profile(line.arc_length)
    pos = line.position[0]
    assert np.abs(pos[:, 0] - x).max() < 0.4
    assert np.abs(pos[:, 2] - z).max() < 0.4
