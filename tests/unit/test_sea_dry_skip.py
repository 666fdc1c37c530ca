"""Sea kinematics of dry RFEs (docs/theory.md 'Sea kinematics of dry RFEs'):
``sea_kinematics_reach`` leaves out the velocity and acceleration of a point whose lowest
wettable level (z - reach) is above the local surface, and even its elevation above every
possible crest (``crest_bound``); every other point equals the plain kernel exactly. Its
use in the model (rfesim.model.assemble.sea_reach) gives the same dynamics as the plain
kernel on a crane whose boom and rope rise far above the sea."""
from __future__ import annotations

import numpy as np
import pytest

from rfesim.sea.current import no_current
from rfesim.sea.kernel import crest_bound, pack_sea, sea_kinematics_into, sea_kinematics_reach
from test_sea_depth_skip import broad_sea


def test_crest_bound_is_the_ramped_sum_of_amplitudes():
    waves = broad_sea(np.random.default_rng(2), 200.0, "wheeler")
    spec = pack_sea(waves, no_current(), 0.0)
    total = float(np.abs(waves.amplitude).sum())
    assert crest_bound(spec, 20.0) == pytest.approx(total, rel=1e-14)
    assert crest_bound(spec, 5.0) == pytest.approx(total * 0.5 * (1.0 - np.cos(np.pi * 5.0 / 10.0)), rel=1e-14)
    assert crest_bound(spec, 0.0) == 0.0


@pytest.mark.parametrize("stretching", ["wheeler", "none", "linear"])
def test_wet_points_are_exact_and_dry_points_are_zero(stretching):
    rng = np.random.default_rng(5)
    waves = broad_sea(rng, 200.0, stretching)
    spec = pack_sea(waves, no_current(), 0.5)
    n = 300
    top = 0.5 + float(np.abs(waves.amplitude).sum())
    points = np.column_stack([rng.uniform(-200, 200, n), rng.uniform(-50, 50, n),
                              np.concatenate([rng.uniform(-30.0, 8.0, n - 60), rng.uniform(top, top + 20.0, 60)])])
    reach = rng.uniform(0.0, 3.0, n)
    for t in (3.0, 27.4):
        eta0, vel0, acc0 = np.zeros(n), np.zeros((n, 3)), np.zeros((n, 3))
        sea_kinematics_into(spec, t, points, eta0, vel0, acc0)
        eta, vel, acc = np.zeros(n), np.zeros((n, 3)), np.zeros((n, 3))
        sea_kinematics_reach(spec, t, points, reach, True, eta, vel, acc)
        low = points[:, 2] - reach
        dry = low > eta0
        above_all = low - 0.5 > crest_bound(spec, t)
        assert dry.sum() > 50 and (~dry).sum() > 50 and above_all.sum() > 20      # every branch is exercised
        np.testing.assert_array_equal(vel[~dry], vel0[~dry])
        np.testing.assert_array_equal(acc[~dry], acc0[~dry])
        np.testing.assert_array_equal(eta[~dry], eta0[~dry])
        assert np.all(vel[dry] == 0.0) and np.all(acc[dry] == 0.0)
        np.testing.assert_array_equal(eta[dry & ~above_all], eta0[dry & ~above_all])
        assert np.all(eta[above_all] == 0.5)
        # without reach the variant is the plain kernel
        sea_kinematics_reach(spec, t, points, reach, False, eta, vel, acc)
        np.testing.assert_array_equal(vel, vel0)
        np.testing.assert_array_equal(eta, eta0)


def test_crane_loads_are_the_same_without_the_dry_points():
    """The column crane of the crane benchmark in irregular waves (pedestal and boom in the
    air, the rope through the surface, the payload 10 m down), after 40 s: the generalised
    forces with the kinematics of the wet points only (rfesim.model.assemble.water_kinematics)
    equal those with the kinematics of every point."""
    from rfesim.api import _static_state
    from rfesim.bench.crane import crane_data
    from rfesim.model.assemble import evaluate, water_kinematics
    from rfesim.model.compile import compile_scenario
    from rfesim.scenario import Scenario
    from rfesim.solvers.dynamics import Counters, run_dynamics
    from rfesim.solvers.system import System
    sc = Scenario.model_validate(crane_data(0.1, 40.0, 0.5, rope_elements=20, boom_elements=10,
                                            pedestal_elements=4))
    system = System(compile_scenario(sc))
    state, _ = _static_state(system, sc)
    state, _, _ = run_dynamics(system, state, sc.analysis.dynamics, counters=Counters())
    km, ws, att = system.km, system.ws, system.att
    system.set_time(state.t)
    forces = []
    for plain in (False, True):
        ws.sea_frozen[0] = 0
        evaluate(km, att, state.q, state.qd, state.ref, ws, 1.0)         # poses at the state
        if plain:
            sea_kinematics_into(km.sea, state.t, ws.r, ws.surface_z, ws.water_vel, ws.water_acc)
        else:
            water_kinematics(km, att, ws)
        dry = int(np.sum(np.all(ws.water_vel == 0.0, axis=1)))
        ws.sea_frozen[0] = 1
        evaluate(km, att, state.q, state.qd, state.ref, ws, 1.0)
        ws.sea_frozen[0] = 0
        forces.append((ws.fgen.copy(), ws.Mgen.copy(), dry))
    assert forces[0][2] > 0.6 * system.n and forces[1][2] == 0       # most points skipped, none in the plain run
    np.testing.assert_allclose(forces[0][0], forces[1][0], rtol=0, atol=1e-9 * np.abs(forces[1][0]).max())
    np.testing.assert_array_equal(forces[0][1], forces[1][1])
