"""A rope whose elements are pushed through one another stops the run (rfesim.solvers.
kernels.check_ropes): a slack rope carries no compression, so past an axial strain of -1
nothing pushes its elements back, and a joint pulled apart then reads as compression too.
Before the check, a 1 kg payload on a stiff crane ended up 11.7 m from the sheave on a
2 m rope, the rope at zero tension, and the run reported "finished" (status 0)."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.solvers.kernels import ROPE_THROUGH_STRAIN, Q_THROUGH, check_ropes


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


def test_a_payload_flung_through_its_rope_stops_the_run_with_the_reason():
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(_crane(1.0, [[0.0, 0.0], [1.0, 90.0]], motor=20000.0))
    exc = info.value
    assert "rope elements pushed through one another" in str(exc) and "line 'c_rope'" in str(exc)
    assert "cranes.<name>.rope.damping_ratio" in str(exc) and "rho_inf" in str(exc)     # the real field names
    assert "line_types.<type>.damping.axial_ratio" in str(exc)
    res = exc.results                   # what was computed before is kept, and it is sound
    assert res is not None and res.status == 1 and 0.0 < res.time[-1] < 1.0
    tip = np.asarray(res.line("c_boom").position)[:, -1]
    hook = np.asarray(res.bodies["c_payload"].position)
    assert np.linalg.norm(hook - tip, axis=1).max() < 2.5 + 0.5       # rope + attachment, not 11.7 m


def test_a_realistic_payload_on_the_same_crane_is_not_stopped():
    """10 t under the same stiff crane, slewed over 20 s: the run goes on, the payload
    stays on its rope."""
    res = rfesim.simulate(_crane(10000.0, [[0.0, 0.0], [20.0, 90.0]], duration=1.0))
    assert res.status == 0
    tip = np.asarray(res.line("c_boom").position)[:, -1]
    hook = np.asarray(res.bodies["c_payload"].position)
    assert np.linalg.norm(hook - tip, axis=1).max() < 2.5 + 0.1


def _reference(tension_only, eps, left):
    """Readable reference of check_ropes: the first tension-only SDE with eps_x < -1."""
    for s in range(len(tension_only)):
        if tension_only[s] and eps[s, 0] < ROPE_THROUGH_STRAIN:
            return 2, int(left[s])
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
    want, rfe = _reference(tension_only, system.ws.eps, km.sde_left) if seed != 5 else (0, None)
    assert status == want
    if want:
        assert fail[0] == 1.5 and int(fail[1]) == rfe and int(fail[2]) == Q_THROUGH
    else:
        assert fail[0] == -9.0


@pytest.mark.parametrize("eps_x, rope, status", [(-1.01, 1, 2), (-0.99, 1, 0), (-5.0, 0, 0)])
def test_check_ropes_threshold(system, eps_x, rope, status):
    """Just past -1 in a rope stops; just short of it, or a line that is no rope, does not."""
    n = system.km.sde_left.shape[0]
    system.ws.eps[:] = 0.0
    system.ws.eps[n // 2, 0] = eps_x
    flags = np.zeros(n, np.int64)
    flags[n // 2] = rope
    km = system.km._replace(sde_tension_only=flags, has_tension_only=True)
    fail = np.zeros(3)
    assert check_ropes(km, system.ws, fail, 0.0) == status
    if status:
        assert int(fail[1]) == int(km.sde_left[n // 2])
