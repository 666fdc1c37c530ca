"""Audit 32, fix G: failure messages that name the real cause (the ZYX singularity of a
spherical joint, ...) and the inputs that led to them."""
import numpy as np
import pytest

import rfesim

G, M, L = 9.81, 2.0, 1.0


def _pendulum(kind="rk4", init=(0.0, 2.0, 0.0), inertia=True, duration=5.0):
    """A rigid link on a spherical joint released at 115 deg about the joint's y axis: it
    swings through |phi_y| = 90 deg, the singularity of the joint's ZYX angles."""
    rod = {"rigid": True, "length": L, "mass": M}
    if inertia:
        rod["inertia"] = [1e-4, M * L ** 2 / 12, M * L ** 2 / 12]
    return {"environment": {"gravity": G},
            "chains": {"p": {"links": {"rod": rod},
                             "joints": {"j": {"kind": "spherical", "parent": "base", "child": "rod",
                                              "direction": [0, 0, -1], "initial": list(init)}}}},
            "analysis": {"statics": {"enabled": False},
                         "dynamics": {"duration": duration, "output_interval": 0.01,
                                      "integrator": {"kind": kind}}}}


def test_rk4_spherical_singularity_named_and_absurd_outputs_dropped():
    with pytest.raises(rfesim.SolverError) as ei:
        rfesim.simulate(_pendulum(inertia=False))
    msg = str(ei.value)
    assert "spherical joint chains.p.j" in msg and "singularity of its ZYX joint angles" in msg
    assert "reduce analysis.dynamics.integrator.time_step" not in msg
    r = ei.value.results
    rate = np.abs(r.joint("p.j").rate)
    # was: kept to t = 2.45 s with joint rates up to 5e14 rad/s
    assert np.isfinite(rate).all() and rate.max() < 100.0
    assert 2.3 < r.time[-1] < 2.45
    assert r.status == 1 and "singularity" in r.message


def test_adaptive_spherical_singularity_named():
    with pytest.raises(rfesim.SolverError) as ei:
        rfesim.simulate(_pendulum(kind="adaptive"))
    msg = str(ei.value)
    assert "spherical joint chains.p.j" in msg and "|phi_y| = 90 deg" in msg
    assert "tighten" not in msg
    r = ei.value.results
    assert np.abs(r.joint("p.j").rate).max() < 100.0


def test_euler_singularity_not_blamed_far_from_it():
    from rfesim.formulations.scene import _euler_singularity, compile_scene
    from rfesim.scenario import load_scenario
    unit = compile_scene(load_scenario(_pendulum())).chains[0]
    t = np.linspace(0.0, 1.0, 101)
    Q = np.zeros((101, 3))
    Q[:, 1] = 0.5 * np.sin(3.0 * t)                    # |phi_y| <= 0.5 rad
    assert _euler_singularity(unit, t, Q, np.gradient(Q, t, axis=0)) is None
    Q[-1, 1] = np.pi / 2                               # at the singularity at the end
    name, t_near, n_keep = _euler_singularity(unit, t, Q, np.gradient(Q, t, axis=0))
    assert (name, t_near) == ("chains.p.j", 1.0)


# -------------------------------------------------------------- 2. adaptive tolerances
def _cantilever(integ):
    import json
    from pathlib import Path
    sc = json.loads((Path(__file__).parents[2] / "scenarios" / "cantilever_pipe.json").read_text())
    sc["lines"]["pipe"]["elements"] = 10
    sc["analysis"].pop("modal", None)
    sc["analysis"]["dynamics"].update(duration=0.05, output_interval=0.01, integrator=integ)
    return sc


@pytest.mark.parametrize("integ, field, words", [
    ({"kind": "adaptive", "rtol": 1e-300}, "analysis.dynamics.integrator.rtol", "the adaptive step collapses"),
    ({"kind": "adaptive", "atol": 1e-300}, "analysis.dynamics.integrator.atol", "round-off"),
    ({"kind": "adaptive", "atol": 1e300}, "analysis.dynamics.integrator.atol", "controls nothing"),
])
def test_adaptive_tolerances_bounded(integ, field, words):
    from rfesim.errors import ScenarioError
    from rfesim.scenario import load_scenario
    with pytest.raises(ScenarioError) as ei:
        load_scenario(_cantilever(integ))
    assert field in str(ei.value) and words in str(ei.value)


def test_adaptive_step_collapse_message(monkeypatch):
    """dp_advance's failure at no element (the step fell below 1e-14 s or 50 rejections in a
    row) was reported as 'velocity not finite or runaway'."""
    import rfesim.solvers.dynamics as dy
    from rfesim.solvers.kernels import Q_VELOCITY

    def collapsed(*args):
        fail = args[-2]
        fail[0], fail[1], fail[2] = 0.0, -1, Q_VELOCITY
        return 2
    monkeypatch.setattr(dy, "dp_advance", collapsed)
    with pytest.raises(rfesim.SolverError) as ei:
        rfesim.simulate(_cantilever({"kind": "adaptive", "rtol": 1e-12, "atol": 1e-15}))
    msg = str(ei.value)
    assert "adaptive step size collapsed" in msg and "velocity not finite" not in msg
    assert "rtol = 1e-12" in ei.value.hint and "atol = 1e-15" in ei.value.hint


# -------------------------------------------------------------- 3. statics failure: which limit
def test_statics_failure_says_max_iterations_used_up():
    """A cantilever rolled into a full circle by its tip moment with max_iterations 5: the
    message said only 'Newton did not converge', for both the iteration limit and a load
    increment halved below 1e-4."""
    import math
    EI, EA, L = 1e8, 1e10, 10.0
    sc = {"environment": {"gravity": 0.0},
          "line_types": {"b": {"EA": EA, "EIy": EI, "EIz": EI, "GJ": EI, "GA": EA, "mass_per_length": 100.0}},
          "lines": {"b": {"type": "b", "length": L, "elements": 40, "formulation": "absolute",
                          "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                    "connection": "clamped"},
                          "end_b": {"attach": "free"},
                          "loads": [{"at": "end_b", "moment": [0, -2 * math.pi * EI / L, 0]}]}},
          "analysis": {"statics": {"enabled": True, "max_iterations": 5, "load_steps": 1, "tolerance": 1e-8}}}
    with pytest.raises(rfesim.SolverError) as ei:
        rfesim.statics(sc)
    msg = str(ei.value)
    assert ("Newton iterations were used up (5 of max_iterations 5, in 1 load step): raise "
            "analysis.statics.max_iterations, or analysis.statics.load_steps") in msg


# -------------------------------------------------------------- 4. range_graph t_from
def test_range_graph_t_from_without_time_is_refused():
    """LineResults.range_graph("tension", t_from=15.0) ignored t_from without `time` and
    returned the whole run (200165 N instead of 185078 N from 15 s on)."""
    from rfesim.results import LineResults
    nt, ns = 4, 2
    z = np.zeros
    line = LineResults("l", np.arange(3.0), np.array([0.5, 1.5]), z((nt, 3, 3)),
                       np.array([[9.0, 9.0], [1.0, 2.0], [1.0, 3.0], [2.0, 1.0]]), z((nt, ns)), z((nt, ns)),
                       z((nt, ns)), z((nt, ns)), z((nt, 3)), z((nt, 3)), z((nt, 3)), z((nt, 3)), z((nt, 3)),
                       z((nt, 3)), z((nt, 3)))
    with pytest.raises(ValueError, match=r"t_from = 1 s needs the run's time axis.*time=results.time"):
        line.range_graph("tension", t_from=1.0)
    assert line.range_graph("tension", t_from=1.0, time=np.arange(4.0))["max"].tolist() == [2.0, 3.0]
