"""Robustness of the classical / modified / planar formulations and chains: zero-stiffness
directions in statics, diverging explicit steps, default RK4 steps, output times."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.bench.cases import cantilever
from rfesim.formulations.chain import newton_step

G, L = 9.81, 20.0
HANGING = [0.0, 1.20241, 1.20241, 2.76004]     # omega / sqrt(g/L) of the hanging chain (J0 zeros / 2)


def _pinned_hanging(form, statics=True):
    sc = cantilever(10, [], EI=1e-3, L=L, EA=1e9, GA=1e9, shear="kruszewski", mass=5.0, gravity=G)
    ln = sc["lines"]["beam"]
    ln["formulation"] = form
    ln["end_a"].update(direction=[0, 0, -1], connection="pinned")
    sc["analysis"]["statics"]["enabled"] = statics
    return sc


@pytest.mark.parametrize("form", ["modified", "classical"])
def test_pinned_hanging_line_statics_and_modes(form):
    # the spin of the line about its own axis at the spherical joint has zero stiffness:
    # statics must not raise LinAlgError, and the modes are the hanging chain's
    sc = _pinned_hanging(form)
    st = rfesim.statics(sc)
    assert st.status == 0
    tip = st.line("beam").position[0, -1]
    assert abs(tip[2] + L) < 1e-3 and abs(tip[0]) < 1e-9 and abs(tip[1]) < 1e-9
    w = 2 * np.pi * rfesim.modes(sc, n=4).frequencies_hz / math.sqrt(G / L)
    assert abs(w[0]) < 1e-3
    # 10 RFEs: within 1.2 % of the continuous chain (the absolute formulation gives 1.2028, 2.787)
    np.testing.assert_allclose(w[1:], HANGING[1:], rtol=1.2e-2)


def test_newton_step_drops_zero_stiffness_directions():
    K = np.diag([2e9, 5.0, 0.0, 3e-4])
    K[0, 1] = K[1, 0] = 1.0
    r = np.array([1.0, 2.0, 1e-12, 3e-4])
    dx = newton_step(K, r)
    assert dx[2] == 0.0
    np.testing.assert_allclose(K[np.ix_([0, 1, 3], [0, 1, 3])] @ dx[[0, 1, 3]], r[[0, 1, 3]], rtol=1e-9)
    assert np.all(newton_step(np.zeros((2, 2)), np.zeros(2)) == 0.0)


def test_taut_pinned_modified_line_converges():
    # 10 kN tip pull on a 20 m cable (EI ~ 0), pinned: the sag is mu g L^2 / (2 P) = 0.981 m;
    # the residual reaches round-off while the step in the nearly stiffness-free spin does not
    sc = cantilever(10, [{"at": "end_b", "force": [1e4, 0, 0]}], EI=1e-3, L=L, EA=1e9, GA=1e9,
                    shear="kruszewski", mass=5.0, gravity=G)
    sc["lines"]["beam"]["end_a"]["connection"] = "pinned"
    tips = {}
    for form in ("modified", "planar"):
        sc["lines"]["beam"]["formulation"] = form
        tips[form] = rfesim.statics(sc).line("beam").position[0, -1]
    assert abs(tips["modified"][2] - tips["planar"][2]) < 1e-6
    assert abs(tips["modified"][2] + 5.0 * G * L * L / 2e4) < 0.01


def _column(form, n=10):
    EI, Lc = 1e6, 10.0
    P = 1.5 * math.pi ** 2 * EI / (4 * Lc * Lc)
    sc = cantilever(n, [{"at": "end_b", "force": [0, 0, -P]}], EI=EI, L=Lc, EA=1e10, GA=1e10,
                    shear="kruszewski", mass=10.0)
    sc["lines"]["beam"]["formulation"] = form
    sc["lines"]["beam"]["end_a"]["direction"] = [0, 0, 1]
    return sc


def test_unstable_modes_are_negative_and_reported(caplog):
    # a column standing up under 1.5 x its Euler load: negative omega^2, shown as negative Hz
    found = {}
    for form, count in (("absolute", 2), ("modified", 2), ("planar", 1)):
        with caplog.at_level("WARNING", logger="rfesim"):
            md = rfesim.modes(_column(form), n=3)
        assert md.unstable == count
        assert np.all(md.frequencies_hz[:count] < 0.0) and md.frequencies_hz[count] > 0.0
        assert f"the static state is unstable: {count} mode" in md.message
        assert np.isnan(md.periods_s[0])
        found[form] = md.frequencies_hz[0]
    assert "negative stiffness" in caplog.text
    np.testing.assert_allclose(found["modified"], found["absolute"], rtol=1e-3)
    np.testing.assert_allclose(found["planar"], found["absolute"], rtol=1e-3)


@pytest.mark.parametrize("form", ["absolute", "classical", "classical-linear", "modified", "planar"])
def test_mode_count_argument(form):
    sc = cantilever(3, [], EI=1e6, L=10.0, EA=1e9, GA=1e9, shear="kruszewski", mass=10.0)
    sc["lines"]["beam"]["formulation"] = form
    for bad in (0, -1, 2.5):
        with pytest.raises(rfesim.ScenarioError, match=r"^n: the number of modes must be a positive integer"):
            rfesim.modes(sc, n=bad)
    md = rfesim.modes(sc, n=500)
    available = {"absolute": 18, "classical": 18, "classical-linear": 18, "modified": 9, "planar": 3}[form]
    assert len(md.frequencies_hz) == available
    assert f"all {available} modes are given" in md.message
    assert np.all(np.diff(md.frequencies_hz) >= -1e-9)
    md2 = rfesim.modes(sc, n=2)
    assert len(md2.frequencies_hz) == 2 and md2.message == ""


def test_line_shapes_agree_across_formulations():
    ratios = {}
    for form in ("absolute", "classical", "classical-linear", "modified", "planar"):
        sc = cantilever(10, [], EI=1e6, L=10.0, EA=1e9, GA=1e9, shear="kruszewski", mass=10.0)
        sc["lines"]["beam"]["formulation"] = form
        md = rfesim.modes(sc, n=1)
        ls = md.line_shapes["beam"][0]
        assert ls.shape == (12, 3)                       # end A, 10 SDEs, end B
        assert abs(np.abs(ls).max() - 1.0) < 1e-12
        ratios[form] = np.linalg.norm(ls[5]) / np.linalg.norm(ls[-1])
    np.testing.assert_allclose(list(ratios.values()), ratios["absolute"], rtol=1e-3)


def test_torsion_mode_line_shape_is_zero():
    # pure torsion: the points of the axis do not move; line_shapes must not be noise scaled to 1
    sc = cantilever(10, [], EI=1e6, L=10.0, EA=1e8, GA=1e13, shear="kruszewski", EIz=1e6, mass=10.0)
    sc["line_types"]["beam"].update(GJ=2e5, rotary_inertia=0.25)
    md = rfesim.modes(sc, n=6)
    torsion = [k for k in range(6) if np.abs(md.shapes[k][:, :3]).max() < 1e-6]
    assert torsion, md.frequencies_hz
    for k in torsion:
        assert np.abs(md.line_shapes["beam"][k]).max() < 1e-3
    bending = [k for k in range(6) if k not in torsion]
    for k in bending:
        assert abs(np.abs(md.line_shapes["beam"][k]).max() - 1.0) < 1e-12


# ----------------------------------------------------------------------------- dynamics
def _pendulum(step=None, initial=0.3, gravity=G, duration=5.0, output=0.5):
    integ = {"kind": "rk4"}
    if step:
        integ["time_step"] = step
    return {"environment": {"gravity": gravity},
            "chains": {"pendulum": {
                "links": {"upper": {"rigid": True, "length": 1.0, "mass": 1.0},
                          "lower": {"rigid": True, "length": 1.0, "mass": 1.0}},
                "joints": {"top": {"kind": "revolute", "parent": "base", "child": "upper",
                                   "direction": [0, 0, -1], "axis": [0, 1, 0], "initial": initial},
                           "middle": {"kind": "revolute", "parent": "upper", "child": "lower",
                                      "axis": [0, 1, 0]}}}},
            "analysis": {"statics": {"enabled": False},
                         "dynamics": {"duration": duration, "output_interval": output, "integrator": integ}}}


def test_rk4_default_step_without_positive_frequency():
    r = rfesim.simulate(_pendulum(gravity=0.0))            # no gravity: no frequency at all
    assert r.status == 0 and r.counters["time_step"] == pytest.approx(5.0 / 1000)
    for initial in (2.0, 3.0):                              # above the horizontal: negative omega^2
        r = rfesim.simulate(_pendulum(initial=initial))
        assert r.status == 0 and np.isfinite(r.joints["pendulum.top"].coordinate).all()
        assert r.counters["time_step"] < 0.05


def test_rk4_default_step_is_accurate_for_rigid_chains():
    a = rfesim.simulate(_pendulum(initial=1.0))
    b = rfesim.simulate(_pendulum(step=1e-3, initial=1.0))
    for j in ("pendulum.top", "pendulum.middle"):
        assert np.abs(a.joints[j].coordinate - b.joints[j].coordinate).max() < 2e-3   # measured 1.5e-4
    top = a.joints["pendulum.top"].coordinate.ravel()
    assert np.abs(top[-4:]).max() > 0.95                   # was 0.28 at RK4's stability limit


@pytest.mark.parametrize("step", [0.003, 0.004])
def test_chain_output_times_follow_output_interval(step):
    r = rfesim.simulate(_pendulum(step=step, duration=1.0, output=0.01))
    np.testing.assert_allclose(r.time, np.arange(101) * 0.01, atol=1e-12)
    assert r.counters["time_step"] <= step


def _modified_cantilever(integrator):
    sc = cantilever(10, [{"at": "end_b", "force": [0, 0, -1e4]}], EI=2.2e8, L=10.0, EA=3.2e10, GA=1e10,
                    mass=120.0, gravity=G)
    sc["lines"]["beam"]["formulation"] = "modified"
    sc["analysis"]["statics"]["enabled"] = False
    sc["analysis"]["dynamics"] = {"duration": 0.2, "output_interval": 0.005, "integrator": integrator}
    return sc


def test_rk4_step_above_the_stability_limit_raises_solver_error_with_results():
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(_modified_cantilever({"kind": "rk4", "time_step": 5e-3}))
    exc = info.value
    assert "the state diverged" in exc.message and "time step 0.005 s" in exc.message
    assert "stability limit" in exc.message and exc.time is not None and exc.time < 0.2
    res = exc.results
    assert res is not None and res.status == 1 and len(res.time) >= 1
    assert np.all(np.isfinite(res.line("beam").position))


def test_adaptive_failure_raises_solver_error_with_results():
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(_modified_cantilever({"kind": "adaptive", "rtol": 0.5, "atol": 1.0}))
    res = info.value.results
    assert res is not None and res.status == 1 and len(res.time) >= 1
