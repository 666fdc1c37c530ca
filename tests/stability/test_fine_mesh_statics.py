"""Statics of the J-lay template on fine meshes at the default tolerance (1e-8).

1 m and 0.5 m elements of the 12-inch steel pipe (EA = 3.18e9 N) hanging 1200 m deep used to
stall: Newton reached a residual of 7.8e-7 (1 m) and 3.55e-6 (0.5 m) x force scale and
stopped there, 'static equilibrium not found'. Statics re-bases every RFE after every update,
so the positions are doubles of up to 1200 m that move in steps of one ulp, 2^-42 m =
2.3e-13 m; one step changes an axial force by EA/l x 2^-42 (7.2e-4 N at 1 m), 61 times the
tolerance's 1e-8 x 1184 N, and no state brings the residual below about that. Statics now
accepts a stagnating residual within POSITION_FLOOR times that force resolution
(rfesim.solvers.statics.position_resolution_force; docs/theory.md, 'Resolution of absolute
positions in statics'). The result matches the same run at a looser tolerance, which
converged before."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
import scenes
from rfesim.model.compile import compile_scenario
from rfesim.solvers.statics import position_resolution_force
from rfesim.solvers.system import System

D, T_WALL, E = 0.3239, 0.0159, 2.07e11
EA = E * math.pi / 4 * (D ** 2 - (D - 2 * T_WALL) ** 2)          # 3.1847e9 N


def j_lay(element_length: float, tolerance: float | None = None):
    """The bundled J-lay template (scenarios/j_lay.json as of this test), statics only."""
    statics = {"enabled": True}
    if tolerance is not None:
        statics["tolerance"] = tolerance
    return rfesim.load_scenario(scenes.j_lay_template(
        element_length, name="J-lay template, fine mesh",
        analysis={"statics": statics, "dynamics": {"enabled": False}}))


def test_force_resolution_of_the_positions_is_above_the_default_tolerance():
    # hand value: the stiffest SDE, EA / l, times one ulp at the deepest RFE (1024 <= |z| <
    # 2048 m: 2^-42 m); the default tolerance asks for 1/61 of it
    sc = j_lay(1.0)
    system = System(compile_scenario(sc))
    state = system.model.initial
    n = sc.lines["lay"].elements
    length = sc.lines["lay"].length
    resolution = position_resolution_force(system, state)
    assert resolution == pytest.approx(EA / (length / n) * 2.0 ** -42, rel=1e-3)     # 7.24e-4 N
    assert 1e-8 * system.force_scale(state) < resolution / 50.0                      # 1.18e-5 N
    # the round-off estimate statics accepted a stalled residual at before: 6 times too small
    assert 10.0 * system.roundoff_force(state) < resolution / 5.0


@pytest.mark.parametrize("element_length, reference_tolerance", [(1.0, 1e-6), (0.5, 1e-5)])
def test_j_lay_fine_mesh_statics_converge_at_the_default_tolerance(element_length, reference_tolerance):
    res = rfesim.statics(j_lay(element_length))                 # raised SolverError before
    assert res.message.startswith("converged in")
    assert res.counters["newton_iterations"] <= 30              # 15 at 1 m and 0.5 m (2.2 s)
    # the same run at a tolerance it reached before (14 iterations each)
    ref = rfesim.statics(j_lay(element_length, reference_tolerance))
    a, b = res.line("lay"), ref.line("lay")
    assert np.abs(a.position - b.position).max() < 1e-8                              # m (found: 4e-11)
    assert np.abs(a.tension - b.tension).max() < 1e-7 * np.abs(b.tension).max()     # 0.047 N (found: 2.6e-3)
    assert np.abs(a.bend_moment - b.bend_moment).max() < 1e-3                        # N m (found: 1.4e-5)
    assert np.abs(a.end_b_force - b.end_b_force).max() < 0.01                        # N (found: 8e-4)
    assert a.touchdown_arc_length[0] == pytest.approx(b.touchdown_arc_length[0], abs=1e-6)
    # a physical check of the equilibrium: the grounded pipe carries the lay tension to end B,
    # 40.8 kN (the horizontal tension of the 85 deg catenary; 40.13 kN in the bending line)
    assert -a.end_b_force[0][0] == pytest.approx(40.8e3, rel=0.03)

