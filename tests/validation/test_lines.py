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


@pytest.mark.parametrize("n", [100, 200])
def test_P1_catenary_with_axial_seabed_friction(n):
    """VALIDATION.md P1 with axial seabed friction 0.1, fully mobilised towards the anchor
    (the line was pulled towards the fairlead as it was laid): anchor tension
    H - mu w L_grounded = 80418.6 N; the fairlead is unchanged."""
    res = rfesim.statics(catenary_line(n, 800.0, friction=0.1))
    line = res.line("line")
    assert -line.end_b_force[0][0] == pytest.approx(96643.4, rel=1e-3)
    assert -line.end_b_force[0][2] == pytest.approx(237751.8, rel=1e-3)
    assert line.end_a_force[0][0] == pytest.approx(80418.6, rel=1e-3)
    # the friction force on the grounded length: mu times the seabed reaction, pointing to the anchor
    friction = line.seabed_friction[0]
    assert friction[:, 0] == pytest.approx(-0.1 * line.seabed_force[0], rel=1e-6, abs=1e-9)
    assert np.abs(friction[:, 1:]).max() < 1e-6 * np.abs(friction[:, 0]).max()
    # tension rises linearly along the grounded part from the anchor
    s_sde = line.sde_arc_length
    grounded = s_sde < 202.810 - 10.0
    expected = 80418.6 + 0.1 * 800.0 * s_sde[grounded]
    assert line.tension[0][grounded] == pytest.approx(expected, rel=2e-3)
    # the touchdown point sits at the end of the grounded length
    assert line.touchdown_arc_length[0] == pytest.approx(202.810, abs=500.0 / n)
