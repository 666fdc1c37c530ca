"""A rope whose elements are pushed through one another stops the run (rfesim.solvers.
kernels.check_ropes): a slack rope carries no compression until its axial contact (rfesim.
loads.tension_only), and once an SDE's gap is past minus its arms' sum (the two elements'
centres have met) a joint pulled apart reads as compression too. Before the check (and the
contact), a 1 kg payload on a stiff crane ended up 11.7 m from the sheave on a 2 m rope, the
rope at zero tension, and the run reported "finished" (status 0)."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.solvers.kernels import ROPE_THROUGH, Q_THROUGH, check_ropes


def _crane(mass, slewing, motor=None, duration=1.0):
    stiff = {"EA": 1e13, "EI": 1e13, "mass_per_length": 100.0}
    crane = {"type": "column", "position": [0.0, 0.0, 2.0],
             "pedestal": {"length": 8.0, "elements": 4, **stiff},
             "boom": {"length": 20.0, "elements": 10, **stiff},
             "slewing_deg": slewing, "luffing_deg": 40.0, "rope": {"length": 2.0, "elements": 4},
             "payload": {"mass": mass, "radius_of_gyration": 0.1}}
    if motor is not None:
        crane["slewing_motor"] = {"max_torque": motor}
    return {"environment": {"gravity": 9.81}, "cranes": {"c": crane},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"duration": duration, "output_interval": 0.1,
                                      "integrator": {"kind": "generalized-alpha", "time_step": 0.01,
                                                     "rho_inf": 0.8}}}}


def test_a_payload_whipped_into_its_rope_stays_on_it():
    """The 1 kg payload whipped about by the near-rigid crane's slew: before the contact it
    passed through its rope (11.7 m from the sheave after 1 s, then a stop at 0.07 s once the
    check came). Now the rope's elements meet in axial contact, which pushes back: the
    payload stays within the rope's reach, the rope carries compression only there, and the
    run says that most of its steps needed substeps."""
    res = rfesim.simulate(_crane(1.0, [[0.0, 0.0], [1.0, 90.0]], motor=20000.0))
    assert res.status == 0 and res.time[-1] == pytest.approx(1.0)
    tip = np.asarray(res.line("c_boom").position)[:, -1]
    hook = np.asarray(res.bodies["c_payload"].position)
    assert np.linalg.norm(hook - tip, axis=1).max() < 2.5 + 0.02        # rope + attachment, not 11.7 m
    assert np.asarray(res.line("c_rope").tension).min() < -1000.0          # the contact pushed back
    assert "failed Newton's iteration at the full step" in res.message
    # and the results say the rope was driven into itself (rfesim.solvers.buckling.dynamic_crammed_warnings)
    assert "dynamics warning: rope 'c_rope' was driven into itself: at t = 0.1 s its elements met in axial " \
           "contact" in res.message
    assert "more than the rope's weight (0.1256 kN)" in res.message


def test_a_realistic_lift_is_not_said_to_be_driven_into_its_rope():
    res = rfesim.simulate(_crane(10000.0, [[0.0, 0.0], [20.0, 90.0]], duration=1.0))
    assert "driven into itself" not in res.message


def test_a_realistic_payload_on_the_same_crane_is_not_stopped():
    """10 t under the same stiff crane, slewed over 20 s: the run goes on, the payload
    stays on its rope."""
    res = rfesim.simulate(_crane(10000.0, [[0.0, 0.0], [20.0, 90.0]], duration=1.0))
    assert res.status == 0
    tip = np.asarray(res.line("c_boom").position)[:, -1]
    hook = np.asarray(res.bodies["c_payload"].position)
    assert np.linalg.norm(hook - tip, axis=1).max() < 2.5 + 0.1


def _reference(km, tension_only, eps):
    """Readable reference of check_ropes: the first tension-only SDE whose gap eps_x is below
    minus its arms' sum (the distance between the two elements' centres at a zero gap)."""
    for s in range(len(tension_only)):
        reach = np.linalg.norm(km.sde_arm_left[s]) + np.linalg.norm(km.sde_arm_right[s])
        if tension_only[s] and eps[s, 0] < -ROPE_THROUGH * reach:
            return 2, int(km.sde_left[s])
    return 0, None


@pytest.fixture(scope="module")
def system():
    from rfesim.model.compile import compile_scenario
    from rfesim.solvers.system import System
    return System(compile_scenario(rfesim.load_scenario(_crane(1000.0, 0.0))))


@pytest.mark.parametrize("seed", range(6))
def test_check_ropes_against_its_reference(system, seed):
    rng = np.random.default_rng(seed)
    n = system.km.sde_left.shape[0]
    tension_only = rng.integers(0, 2, n).astype(np.int64)
    system.ws.eps[:] = rng.normal(0.0, 0.6 + 0.2 * seed, (n, 6))
    km = system.km._replace(sde_tension_only=tension_only, has_tension_only=bool(seed != 5))
    fail = np.full(3, -9.0)
    status = check_ropes(km, system.ws, fail, 1.5)
    want, rfe = _reference(km, tension_only, system.ws.eps) if seed != 5 else (0, None)
    assert status == want
    if want:
        assert fail[0] == 1.5 and int(fail[1]) == rfe and int(fail[2]) == Q_THROUGH
    else:
        assert fail[0] == -9.0


@pytest.mark.parametrize("factor, rope, status", [(-1.01, 1, 2), (-0.99, 1, 0), (-5.0, 0, 0)])
def test_check_ropes_threshold(system, factor, rope, status):
    """Just past minus the arms' sum in a rope stops; just short of it, or a line that is no
    rope, does not. The arms of a rope element are half its length: 0.5 m of a 2 m, 4-element
    rope, so the limit is -0.5 m (it was -1 m for every rope before the axial contact)."""
    n = system.km.sde_left.shape[0]
    rope_sdes = [li for li in system.model.lines if li.name == "c_rope"][0]
    s = (rope_sdes.sde_start + rope_sdes.sde_stop) // 2
    reach = np.linalg.norm(system.km.sde_arm_left[s]) + np.linalg.norm(system.km.sde_arm_right[s])
    assert reach == pytest.approx(0.5)
    system.ws.eps[:] = 0.0
    system.ws.eps[s, 0] = factor * reach
    flags = np.zeros(n, np.int64)
    flags[s] = rope
    km = system.km._replace(sde_tension_only=flags, has_tension_only=True)
    fail = np.zeros(3)
    assert check_ropes(km, system.ws, fail, 0.0) == status
    if status:
        assert int(fail[1]) == int(km.sde_left[s])
