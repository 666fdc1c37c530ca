"""Hinged joins (``end_a.hinge_axis``, rfesim.model.joins) and force-driven A-frame cylinders
(``cranes.<c>.cylinder.force``: a hinge plus a push-pull tugger, rfesim.scenario.cranes).

* a stiff bar on a hinge swings with the exact period of its rigid-body pendulum (the
  complete elliptic integral at 20 deg amplitude, the discrete bar's own inertia) and back
  to the opposite amplitude; statics hangs it plumb from 20 deg off;
* the A-frame held by a set cylinder force: in statics the weights and the cylinder put no
  moment on the free hinge (an exact identity with flexible legs), the stroke-driven
  A-frame at the tilt found needs the same force (within the legs' flexibility), and more
  pull tilts the frame further (the weights' moment grows with the outreach);
* undamped, at rho_inf = 1, with the payload pushed sideways, the total energy (kinetic,
  gravity, strain, and -P L of the set push P over the cylinder length L) is conserved
  while the frame rolls over its unstable equilibrium (a set force balances the frame but
  does not hold it: the weights' moment grows with the tilt faster than the cylinder's);
* with the cylinders' end stop the frame rests on it, pulled by what the stroke-driven
  cylinders pull, and stays there when the payload is pushed;
* the cylinder's eye sits on the legs' axis at its arc length; results files keep the
  hinge angle and the tugger's line point; bad input names its field.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import ellipk

import rfesim
from rfesim.api import _static_state
from rfesim.crane_results import crane_summary
from rfesim.errors import ScenarioError
from rfesim.loads.sde import sde_elastic_energy
from rfesim.model.compile import compile_scenario
from rfesim.solvers.dynamics import run_dynamics
from rfesim.solvers.system import System

G = 9.81
BAR = 2.0


def pendulum(tilt=20.0, statics=False, duration=5.0, dt=0.005, axis=(0.0, 1.0, 0.0), **end_a):
    d = [math.sin(math.radians(tilt)), 0.0, -math.cos(math.radians(tilt))]
    return {"environment": {"gravity": G},
            "line_types": {"post": {"EA": 1e10, "EIy": 1e9, "mass_per_length": 10.0},
                           "bar": {"EA": 1e10, "EIy": 1e8, "mass_per_length": 100.0}},
            "lines": {"post": {"type": "post", "length": 1.0, "elements": 2,
                               "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, 1],
                                         "connection": "clamped"},
                               "end_b": {"attach": "free"}},
                      "bar": {"type": "bar", "length": BAR, "elements": 8,
                              "end_a": {"attach": "post:end_b", "connection": "clamped", "direction": d,
                                        "hinge_axis": list(axis), **end_a},
                              "end_b": {"attach": "free"}}},
            "analysis": {"statics": {"enabled": statics},
                         "dynamics": {"enabled": duration > 0, "duration": max(duration, 1.0), "output_interval": dt,
                                      "integrator": {"kind": "generalized-alpha", "time_step": dt}}}}


def test_hinged_bar_swings_with_the_exact_pendulum_period():
    data = pendulum()
    res = rfesim.simulate(data)
    h = res.line("bar").hinge_angle - 20.0          # about the plumb position
    t = res.time
    assert h[0] == pytest.approx(-20.0, abs=1e-9)     # released at rest, 20 deg off plumb
    up = np.where((h[:-1] < 0.0) & (h[1:] >= 0.0))[0]
    crossings = t[up] - h[up] * (t[up + 1] - t[up]) / (h[up + 1] - h[up])
    period = float(np.diff(crossings)[0])
    # the discrete bar as a rigid body: its RFEs' masses at their centres and their own inertia
    system = System(compile_scenario(rfesim.Scenario.model_validate(data)))
    km = system.km
    li = system.model.line("bar")
    idx = np.arange(li.rfe_start, li.rfe_stop)
    system.accelerations(system.model.initial)
    arm = np.linalg.norm(system.ws.r[idx] - np.array([0.0, 0.0, 1.0]), axis=1)
    inertia = float(np.sum(km.rfe_mass[idx] * arm ** 2) + np.sum(km.rfe_inertia[idx, 1]))
    static_moment = float(np.sum(km.rfe_mass[idx] * arm))
    exact = 4.0 * math.sqrt(inertia / (static_moment * G)) * ellipk(math.sin(math.radians(10.0)) ** 2)
    # measured: 2.34295 s against 2.34291 s (the continuous bar's 2.33417 s is another body)
    assert period == pytest.approx(exact, rel=1e-4)
    assert h.max() == pytest.approx(20.0, abs=0.05)   # swings through to the opposite amplitude


def test_hinged_bar_hangs_plumb_in_statics():
    res = rfesim.statics(pendulum(statics=True, duration=0.0))
    bar = res.line("bar")
    assert bar.hinge_angle[-1] == pytest.approx(20.0, abs=1e-6)
    np.testing.assert_allclose(bar.end_b_direction[-1], [0.0, 0.0, -1.0], atol=1e-8)
    # the hinge carries the weight and no moment about its axis
    assert bar.end_a_force[-1][2] == pytest.approx(-(100.0 * BAR) * G, rel=1e-7)
    assert abs(bar.end_a_moment[-1][1]) < 1e-6 * 100.0 * BAR * G


@pytest.mark.parametrize("over, field, words", [
    ({"axis": (1.0, 1.0, 0.0)}, "lines.bar.end_a.hinge_axis", "normal to end A's direction"),
    ({"axis": (0.0, 0.0, 0.0)}, "lines.bar.end_a.hinge_axis", "zero vector"),
    ({"connection": "pinned"}, "lines.bar.end_a.hinge_axis", "clamped join"),
    ({"drives": [{"name": "x", "axis": [0, 1, 0], "angle": [[0, 0], [1, 5]]}]}, "lines.bar.end_a.hinge_axis",
     "no drives"),
])
def test_hinge_errors_name_the_field(over, field, words):
    axis = over.pop("axis", (0.0, 1.0, 0.0))
    with pytest.raises(ScenarioError) as err:
        rfesim.simulate(pendulum(axis=axis, **over))
    assert field in str(err.value) and words in str(err.value)


# ----------------------------------------------------------------------------- A-frame
def a_frame(tilt=20.0, force=None, duration=0.0, dt=0.05, **legs):
    cyl = {"base": [-3.0, 0.0], "eye": 5.0, "count": 2}
    if force is not None:
        cyl["force"] = force
    tpl = {"type": "a-frame", "position": [0.0, 0.0, 2.0], "outboard_deg": 180.0,
           "legs": {"length": 8.0, "outer_diameter": 0.6, "wall_thickness": 0.025, **legs},
           "tilt_deg": tilt, "crossbeam_mass": 2000.0, "cylinder": cyl,
           "rope": {"length": 6.0, "elements": 6},
           "payload": {"mass": 10000.0, "radius_of_gyration": 1.0}}
    return {"environment": {"gravity": G}, "cranes": {"af": tpl},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"enabled": duration > 0, "duration": max(duration, 0.2), "output_interval": dt,
                                      "integrator": {"kind": "generalized-alpha", "time_step": dt}}}}


def stroke_force(tilt: float) -> float:
    """Force per cylinder (N, pushing positive) of the stroke-driven A-frame held at tilt."""
    data = a_frame(tilt=tilt)
    return float(crane_summary(rfesim.statics(data), "af", cylinder=data["cranes"]["af"]["cylinder"])
                 ["cylinder_force"][0])


def test_a_frame_held_by_a_set_cylinder_force_in_statics():
    F = stroke_force(20.0)
    assert F < 0.0                                    # the payload outboard: the cylinders pull
    tilts = {}
    for factor in (1.0, 1.05):
        data = a_frame(force=factor * F)
        res = rfesim.statics(data)
        out = crane_summary(res, "af", cylinder=data["cranes"]["af"]["cylinder"])
        assert out["cylinder_force"][-1] == pytest.approx(factor * F, rel=1e-12)
        tilts[factor] = 20.0 + float(res.line("af_legs").hinge_angle[-1])
        # the tilt from the cylinder's length (its triangle) agrees with the hinge's turn
        assert out["drive_angle"]["luffing"][-1] == pytest.approx(tilts[factor], abs=0.05)
        # exact: about the free hinge, the weights of everything it carries and the cylinder balance
        sc = rfesim.Scenario.model_validate(data)
        system = System(compile_scenario(sc))
        state, _ = _static_state(system, sc)
        system.accelerations(state)
        km, ws = system.km, system.ws
        hinge = np.array([0.0, 0.0, 2.0])
        axis = np.array([0.0, -1.0, 0.0])             # z x outboard (-x): turning the legs outboard
        carried = np.arange(km.rfe_mass.shape[0]) >= system.model.line("af_legs").rfe_start
        weights = np.cross(ws.r[carried] - hinge, np.outer(km.rfe_mass[carried], [0.0, 0.0, -G])).sum(axis=0)
        i, point = int(km.tug_rfe[0]), km.tug_point[0]
        eye = ws.r[i] + ws.R[i] @ point
        base = np.array([3.0, 0.0, 2.0])               # [-3, 0] in the luffing plane: inboard is +x
        push = ws.tug_tension[0] * (base - eye) / ws.tug_length[0]   # the tugger law, tension -P
        cylinder = np.cross(eye - hinge, push)
        # (to the stiff joint's own stretch, micrometres against the nominal hinge point: 4e-6 measured)
        assert abs(float((weights + cylinder) @ axis)) < 2e-5 * abs(float(weights @ axis))
        assert abs(float(weights @ axis)) > 1e5       # a real moment is balanced
    # the set force equal to the stroke-driven one holds the frame where the stroke did, within
    # the legs' flexibility (measured 0.049 deg); more pull tilts the frame further outboard
    assert tilts[1.0] == pytest.approx(20.0, abs=0.1)
    assert tilts[1.05] > tilts[1.0] + 0.5
    # ... where the stroke-driven frame needs that force (measured 1.0531 F against 1.05 F)
    assert stroke_force(tilts[1.05]) == pytest.approx(1.05 * F, rel=5e-3)


def test_a_frame_on_a_set_cylinder_force_conserves_energy():
    """No damping, rho_inf = 1, the payload pushed sideways at 1 m/s from the static state:
    over 4 s the frame rolls 10 deg over its unstable equilibrium, and kinetic + gravity +
    strain - P L stays within 5e-5 of m g x 1 m (measured 0.05 J of 2.18 MJ)."""
    data = a_frame(force=-98981.36, duration=4.0, dt=0.002, damping_ratio=0.0)
    data["cranes"]["af"]["rope"]["damping_ratio"] = 0.0
    data["analysis"]["dynamics"].update(output_interval=0.1)
    data["analysis"]["dynamics"]["integrator"].update(rho_inf=1.0, tolerance=1e-10)
    sc = rfesim.Scenario.model_validate(data)
    system = System(compile_scenario(sc))
    km = system.km
    state, _ = _static_state(system, sc)
    start = state.copy()
    start.qd[system.model.bodies[0].rfe, 1] = 1.0

    def energy(st):
        system.accelerations(st)
        ws = system.ws
        kinetic = 0.5 * np.sum(km.rfe_mass * np.sum(ws.v ** 2, axis=1)) + 0.5 * np.sum(km.rfe_inertia * ws.wb ** 2)
        push = -float(ws.tug_tension[0])
        return (kinetic + G * np.sum(km.rfe_mass * ws.r[:, 2]) + sde_elastic_energy(km.sde_stiffness, ws.eps)
                - push * float(ws.tug_length[0])), kinetic

    e0, _ = energy(start)
    end, rec, _ = run_dynamics(system, start, sc.analysis.dynamics)
    e1, kinetic = energy(end)
    hinge = rec.results().line("af_legs").hinge_angle
    assert hinge[-1] - hinge[0] > 5.0 and kinetic > 1e4      # it rolled over, fast
    assert abs(e1 - e0) < 5e-5 * 10000.0 * G


def test_cylinder_eye_on_the_legs_and_results_files_keep_hinge_and_line_point(tmp_path):
    data = a_frame(force=-98981.36, duration=0.2, dt=0.05)
    sc = rfesim.Scenario.model_validate(data)
    tug = sc.tuggers["af_cylinder"]
    assert (tug.line, tug.at, tug.vessel) == ("af_legs", 5.0, "af_vessel")
    assert tug.deck_point == pytest.approx([3.0, 0.0, 2.0])          # base [-3, 0] inboard of the hinge: +x
    assert tug.mode.rows() == [[0.0, -2.0 * 98981.36]]               # both cylinders
    system = System(compile_scenario(sc))
    km = system.km
    system.accelerations(system.model.initial)
    i = int(km.tug_rfe[0])
    eye = system.ws.r[i] + system.ws.R[i] @ km.tug_point[0]
    tilt = math.radians(20.0)
    np.testing.assert_allclose(eye, [0.0 - 5.0 * math.sin(tilt), 0.0, 2.0 + 5.0 * math.cos(tilt)], atol=1e-9)
    res = rfesim.simulate(data)
    path = tmp_path / "af.nc"
    res.to_netcdf(path)
    back = rfesim.open_results(path)
    np.testing.assert_array_equal(back.line("af_legs").hinge_angle, res.line("af_legs").hinge_angle)
    t = back.tugger("af_cylinder")
    assert (t.line, t.at, t.body) == ("af_legs", 5.0, "")
    np.testing.assert_array_equal(t.tension, 2.0 * 98981.36)
    assert back.line("af_stub").hinge_angle is None


def test_a_frame_resting_on_its_cylinder_end_stop():
    """The cylinders free (set force 0) with their longest length at 25 deg: the payload's
    weight lays the frame on that end stop. Statics: 25 deg to the stop's compression, the
    stop pulls what the stroke-driven frame's cylinders pull at 25 deg (within the legs'
    flexibility: measured 259.68 against 260.42 kN), the cylinder 0.13 mm beyond its stop.
    A 0.3 m/s push of the payload, in the frame's plane or across it, leaves the frame on its
    stop: a stop holds the balance a set force alone cannot."""
    from rfesim.scenario.cranes import CylinderSpec, cylinder_lever
    L25 = cylinder_lever(CylinderSpec(base=[-3.0, 0.0], eye=5.0), math.radians(65.0))[0]
    data = a_frame(tilt=25.0, force=0.0, duration=10.0, dt=0.01)
    data["cranes"]["af"]["cylinder"]["length_max"] = L25
    data["analysis"]["dynamics"]["output_interval"] = 0.5
    res = rfesim.statics(data)
    out = crane_summary(res, "af", cylinder=data["cranes"]["af"]["cylinder"])
    assert out["drive_angle"]["luffing"][-1] == pytest.approx(25.0, abs=0.01)
    pull = float(res.tugger("af_cylinder").tension[-1])
    assert pull == pytest.approx(-2.0 * stroke_force(25.0), rel=5e-3)
    assert res.tugger("af_cylinder").length[-1] - L25 == pytest.approx(pull / 2e9, rel=1e-3)
    sc = rfesim.Scenario.model_validate(data)
    system = System(compile_scenario(sc))
    state, _ = _static_state(system, sc)
    for axis in (0, 1):
        start = state.copy()
        start.qd[system.model.bodies[0].rfe, axis] = 0.3
        _, rec, _ = run_dynamics(system, start, sc.analysis.dynamics)
        hinge = rec.results().line("af_legs").hinge_angle
        assert np.ptp(hinge) < 0.01


@pytest.mark.parametrize("over, field, words", [
    ({"cylinder": {"base": [-3.0, 0.0], "eye": 5.0, "force": 0.0, "length_max": 6.0}},
     "cranes.af.cylinder.length_max", "beyond its length_max"),
    ({"cylinder": {"base": [-3.0, 0.0], "eye": 5.0, "force": 0.0, "length_min": 7.0, "length_max": 6.9}},
     "cranes.af.cylinder.length_max", "not longer than"),
    ({"cylinder": {"base": [-3.0, 0.0], "eye": 5.0, "force": 1e5}, "tilt_deg": [[0, 10], [5, 20]]},
     "cranes.af.tilt_deg", "starting tilt as a constant"),
    ({"cylinder": {"base": [-3.0, 0.0], "eye": 5.0, "force": 1e5, "stroke": [[0, 6.0]]}},
     "cranes.af.cylinder.stroke", "not both"),
    ({"cylinder": {"base": [-3.0, 0.0], "eye": 9.0, "force": 1e5}}, "cranes.af.cylinder.eye", "beyond the legs"),
    ({"cylinder": {"base": [-3.0, 0.0], "eye": 5.0, "force": [[0, 1e5], [0, 2e5]]}},
     "cranes.af.cylinder.force.1.0", "times must increase"),
])
def test_force_cylinder_errors_name_the_field(over, field, words):
    data = a_frame()
    data["cranes"]["af"].update(over)
    with pytest.raises(ScenarioError) as err:
        rfesim.simulate(data)
    assert field in str(err.value) and words in str(err.value)


def test_force_cylinder_is_refused_on_the_column_crane():
    data = {"cranes": {"c": {"type": "column", "position": [0.0, 0.0, 2.0],
                             "pedestal": {"length": 8.0, "outer_diameter": 2.0, "wall_thickness": 0.04},
                             "boom": {"length": 20.0, "outer_diameter": 0.8, "wall_thickness": 0.02},
                             "luffing_deg": 40.0, "rope": {"length": 10.0},
                             "cylinder": {"base": [1.0, -2.0], "eye": 6.0, "force": 1e6},
                             "payload": {"mass": 5000.0, "radius_of_gyration": 1.0}}}}
    with pytest.raises(ScenarioError) as err:
        rfesim.simulate(data)
    assert "cranes.c.cylinder.force" in str(err.value) and "A-frame only" in str(err.value)


@pytest.mark.parametrize("tugger, field, words", [
    ({"line": "bar", "body": "x"}, "tuggers.t.body", "or a line"),
    ({"line": "bar"}, "tuggers.t.at", "arc length"),
    ({"line": "bar", "at": 5.0}, "tuggers.t.at", "beyond"),
    ({"line": "nope", "at": 1.0}, "tuggers.t.line", "unknown line"),
    ({"line": "bar", "at": 1.0, "body_point": [0, 0, 1]}, "tuggers.t.body_point", "leave out"),
])
def test_line_point_tugger_errors_name_the_field(tugger, field, words):
    data = pendulum(duration=0.0, statics=True)
    data["vessels"] = {"quay": {"position": [0, 0, 0], "motion": {"kind": "fixed"}}}
    data["tuggers"] = {"t": {"vessel": "quay", "deck_point": [3.0, 0.0, 0.0], "mode": {"kind": "force", "force": 1.0},
                             **tugger}}
    with pytest.raises(ScenarioError) as err:
        rfesim.simulate(data)
    assert field in str(err.value) and words in str(err.value)
