"""Seabed friction in dynamics: the stick/slip law stops a sliding pipe at the Coulomb
distance and then holds it still (no creep)."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.model.compile import compile_scenario
from rfesim.solvers.dynamics import run_dynamics
from rfesim.solvers.system import System

G = 9.81


def sliding_pipe(mu, integrator, kt=1e8, k=1e7, mass=100.0, duration=1.0):
    """A 2 m stiff pipe lying on a flat seabed in air at its static penetration."""
    return rfesim.Scenario.model_validate({
        "environment": {"gravity": G, "seabed": {"z": 0.0, "normal_stiffness": k, "damping_ratio": 1.0,
                                                 "friction": mu, "friction_stiffness": kt}},
        "line_types": {"pipe": {"EA": 1e9, "EIy": 1e7, "GJ": 1e7, "mass_per_length": mass}},
        "lines": {"pipe": {"type": "pipe", "length": 2.0, "elements": 2,
                           "end_a": {"attach": "free", "position": [0, 0, -mass * G / k], "direction": [1, 0, 0]},
                           "end_b": {"attach": "free"}}},
        "analysis": {"statics": {"enabled": False},
                     "dynamics": {"duration": duration, "integrator": integrator, "output_interval": 0.01}},
    })


def slide(sc, v0):
    model = compile_scenario(sc)
    system = System(model)
    st = model.initial.copy()
    st.qd[:, 0] = v0
    st.qd[:, 1] = 0.5 * v0          # an oblique push: the pipe slides along the initial velocity
    _, rec, _ = run_dynamics(system, st, sc.analysis.dynamics)
    res = rec.results()
    return res.time, res.line("pipe").position.mean(axis=1)


@pytest.mark.parametrize("integrator", [{"kind": "generalized-alpha", "time_step": 1e-3, "rho_inf": 0.8},
                                        {"kind": "rk4"}])
def test_sliding_pipe_stops_at_the_coulomb_distance_and_stays(integrator):
    mu, v0 = 0.4, 1.0
    speed = v0 * np.hypot(1.0, 0.5)
    t, centre = slide(sliding_pipe(mu, integrator), v0)
    travel = np.linalg.norm(centre[:, :2] - centre[0, :2], axis=1)
    expected = speed ** 2 / (2.0 * mu * G)                # 0.15928 m
    stop_time = speed / (mu * G)                          # 0.2849 s
    assert travel[-1] == pytest.approx(expected, rel=1e-2)
    # the direction of travel is the direction of the push
    d = centre[-1, :2] - centre[0, :2]
    assert d[1] / d[0] == pytest.approx(0.5, rel=1e-3)
    # still from shortly after the stop to the end: no creep
    after = t > stop_time + 0.05
    assert np.ptp(travel[after]) < 1e-5
    # while sliding it decelerates at mu g: travel(t) = v t - mu g t^2 / 2
    during = t < 0.8 * stop_time
    np.testing.assert_allclose(travel[during], speed * t[during] - 0.5 * mu * G * t[during] ** 2,
                               atol=2e-3)


def test_without_friction_the_pipe_keeps_sliding():
    t, centre = slide(sliding_pipe(0.0, {"kind": "generalized-alpha", "time_step": 1e-3}, duration=0.3), 1.0)
    assert centre[-1, 0] - centre[0, 0] == pytest.approx(0.3, rel=1e-3)


# --------------------------------------------------------------------------- laid pipe in a side current

RHO, CD, D, MU_LAT = 1025.0, 1.0, 0.3239, 0.5


def laid_pipe_in_current(speed, duration=20.0):
    """A 20 m 12-inch steel pipe (P2 section: submerged weight 356.25 N/m) lying free on a
    flat seabed at 100 m under a uniform current across it (toward +y), ramped in over 5 s
    (a sudden current would overshoot the stick spring past the friction limit)."""
    k = 1e5
    w_sub = 356.2532
    return rfesim.Scenario.model_validate({
        "environment": {"gravity": G,
                        "water": {"density": RHO, "depth": 100.0,
                                  "current": {"profile": [[0.0, speed]], "direction_deg": 90.0,
                                              "time_factor": [[0.0, 0.0], [5.0, 1.0]]}},
                        "seabed": {"normal_stiffness": k, "damping_ratio": 1.0, "friction": MU_LAT,
                                   "friction_stiffness": 1e6}},
        "line_types": {"pipe": {"outer_diameter": D, "wall_thickness": 0.0159, "youngs_modulus": 2.07e11,
                                "density": 7850.0, "drag_normal": CD, "drag_axial": 0.0}},
        "lines": {"pipe": {"type": "pipe", "length": 20.0, "elements": 10,
                           "end_a": {"attach": "free", "position": [0, 0, -100.0 + 0.5 * D - w_sub / k],
                                     "direction": [1, 0, 0]},
                           "end_b": {"attach": "free"}}},
        "analysis": {"statics": {"enabled": False},
                     "dynamics": {"duration": duration, "output_interval": 0.1,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.01}}},
    })


def test_laid_pipe_holds_still_below_the_friction_limit_and_slides_above():
    """Lateral drag 1/2 rho C_D D U^2 against the friction limit mu w_sub (U_crit = 1.036 m/s):
    at U = 0.9 m/s the pipe sticks (moves only the stick-spring deflection); at U = 1.3 m/s
    it slides at the speed where drag on the relative velocity equals the friction limit."""
    w_sub = 356.2532
    u_crit = np.sqrt(MU_LAT * w_sub / (0.5 * RHO * CD * D))
    assert u_crit == pytest.approx(1.036, abs=1e-3)
    res = rfesim.simulate(laid_pipe_in_current(0.9))
    y = res.line("pipe").position[:, :, 1].mean(axis=1)
    drag = 0.5 * RHO * CD * D * 0.9 ** 2
    assert abs(y[-1] - y[0]) == pytest.approx(drag / 1e6, rel=0.02)    # the stick deflection, no sliding
    assert abs(y[-1] - y[-50]) < 1e-6                     # and no creep
    res = rfesim.simulate(laid_pipe_in_current(1.3))
    y = res.line("pipe").position[:, :, 1].mean(axis=1)
    t = res.time
    speed = np.polyfit(t[t > 10.0], y[t > 10.0], 1)[0]
    assert speed == pytest.approx(1.3 - u_crit, rel=0.02)
    # the friction force on the sliding pipe is at its limit mu N, against the motion
    fr = res.line("pipe").seabed_friction[-1]
    normal = res.line("pipe").seabed_force[-1]
    assert fr[:, 1].sum() == pytest.approx(-MU_LAT * normal.sum(), rel=1e-6)


SLOPE_DEG = 10.0
SLOPE_KT = 1e4                       # N/m/m, the default stick stiffness for normal_stiffness 1e5


def pipe_on_slope(mu, damping_ratio=None, duration=6.0, slope_deg=SLOPE_DEG):
    """A free 20 m pipe (0.5 m x 20 mm steel, 800 kg/m^3 contents, 10 elements) set down along
    the fall line of a sloped seabed 100 m deep, from rest at its normal static penetration:
    its weight's down-slope part comes on at once. Returns (t, down-slope displacement of its
    middle, submerged weight per length)."""
    th = np.radians(slope_deg)
    D, t_w, kn = 0.5, 0.02, 1e5
    steel = np.pi / 4 * (D ** 2 - (D - 2 * t_w) ** 2)
    bore = np.pi / 4 * (D - 2 * t_w) ** 2
    w_sub = G * (7850.0 * steel + 800.0 * bore - RHO * np.pi / 4 * D ** 2)
    normal = np.array([-np.sin(th), 0.0, np.cos(th)])
    up = np.array([np.cos(th), 0.0, np.sin(th)])
    centre = np.array([0.0, 0.0, -100.0]) + normal * (D / 2 - w_sub * np.cos(th) / kn)
    seabed = {"normal_stiffness": kn, "friction": mu, "slope_deg": slope_deg}
    if damping_ratio is not None:
        seabed["friction_damping_ratio"] = damping_ratio
    res = rfesim.simulate({
        "environment": {"gravity": G, "water": {"density": RHO, "depth": 100.0}, "seabed": seabed},
        "line_types": {"p": {"outer_diameter": D, "wall_thickness": t_w, "youngs_modulus": 207e9,
                             "density": 7850.0, "contents_density": 800.0}},
        "lines": {"pipe": {"type": "p", "length": 20.0, "elements": 10,
                           "end_a": {"attach": "free", "position": (centre - 10 * up).tolist()},
                           "end_b": {"attach": "free", "position": (centre + 10 * up).tolist()}}},
        "analysis": {"statics": {"enabled": False},
                     "dynamics": {"duration": duration, "output_interval": 0.05,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.01}}}})
    pos = res.line("pipe").position
    mid = pos[:, pos.shape[1] // 2]
    return res.time, (mid - mid[0]) @ -up, w_sub


def test_a_pipe_set_down_on_a_slope_below_the_friction_limit_holds_at_its_mobilisation_displacement():
    """mu = 0.2 on a 10 deg slope (mu / tan = 1.134): the pipe holds, having moved its
    mobilisation displacement w_sub sin / k_t = 2.87 cm, and does not ring. The stick damper
    (friction_damping_ratio, default 1) makes it so: the undamped stick spring swings the
    suddenly loaded pipe to twice that, past the limit, and it slid 13.5 cm (audit 2026-11-28)."""
    t, down, w_sub = pipe_on_slope(0.2)
    mobilisation = w_sub * np.sin(np.radians(SLOPE_DEG)) / SLOPE_KT
    assert mobilisation == pytest.approx(0.0287, abs=1e-4)
    assert down[-1] == pytest.approx(mobilisation, rel=0.01)
    assert np.ptp(down[t > 3.0]) < 1e-3 * mobilisation           # at rest, no ringing
    assert down.max() < 1.01 * mobilisation                       # no overshoot past the static deflection
    t0, down0, _ = pipe_on_slope(0.2, damping_ratio=0.0)
    assert down0[-1] > 3.0 * mobilisation                          # undamped: slipped


def test_a_pipe_held_by_friction_on_a_steep_slope_comes_to_rest():
    """20 deg, mu = 0.5 (mu / tan = 1.37): held either way, but the undamped stick spring rings
    at 2 pi sqrt(m / k_t) = 1.2 s with about 2 cm for as long as the run lasts; damped it
    settles within the first seconds."""
    t, down, w_sub = pipe_on_slope(0.5, slope_deg=20.0)
    mobilisation = w_sub * np.sin(np.radians(20.0)) / SLOPE_KT
    assert down[-1] == pytest.approx(mobilisation, rel=0.01)
    assert np.ptp(down[t > 3.0]) < 1e-3 * mobilisation
    t0, down0, _ = pipe_on_slope(0.5, damping_ratio=0.0, slope_deg=20.0)
    assert np.ptp(down0[t0 > 3.0]) > 0.5 * mobilisation             # undamped: still ringing


def test_below_the_friction_limit_the_damped_pipe_slides_with_the_coulomb_acceleration():
    """mu = 0.15 < tan 10 deg: sliding from rest, x = a t^2 / 2 with a = w_sub (sin - mu cos) / m
    (the stick damper acts only while the pipe sticks)."""
    t, down, w_sub = pipe_on_slope(0.15, duration=4.0)
    th = np.radians(SLOPE_DEG)
    D, t_w = 0.5, 0.02
    mass = 7850.0 * np.pi / 4 * (D ** 2 - (D - 2 * t_w) ** 2) + 800.0 * np.pi / 4 * (D - 2 * t_w) ** 2
    a = w_sub * (np.sin(th) - 0.15 * np.cos(th)) / mass
    late = t > 1.5
    assert 2.0 * np.polyfit(t[late], down[late], 2)[0] == pytest.approx(a, rel=2e-3)


def test_the_default_rk4_step_keeps_a_heavily_damped_stick_spring_stable():
    """A light 40 m line (4 RFEs of 10 m) on the seabed in a 0.3 m/s side current, its drag 3 %
    of the friction limit, with a stick spring as stiff as the normal one and damped at 10 x
    critical: the stick dampers' rate c l / m = 894 1/s, which the start state (no anchors yet)
    does not show. RK4's default step must stay below 2.785 / rate; at the 1/30 s it took
    before, the friction bounced at the limit and the line slid 4.5 cm in 2 s."""
    mass, diameter, cd, u = 50.0, 0.1, 1.2, 0.3
    sc = {"environment": {"gravity": G, "water": {"density": RHO, "depth": 100.0,
                                                  "current": {"profile": [[0.0, u], [-100.0, u]],
                                                              "direction_deg": 90.0}},
                          "seabed": {"normal_stiffness": 1e5, "friction": 0.5, "friction_stiffness": 1e5,
                                     "friction_damping_ratio": 10.0}},
          "line_types": {"p": {"EA": 1e6, "EIy": 1e2, "GJ": 1e2, "mass_per_length": mass,
                               "outer_diameter": diameter, "drag_normal": cd}},
          "lines": {"pipe": {"type": "p", "length": 40.0, "elements": 4,
                             "end_a": {"attach": "free", "position": [0.0, 0.0, -99.95]},
                             "end_b": {"attach": "free", "position": [40.0, 0.0, -99.95]}}},
          "analysis": {"statics": {"enabled": False},
                       "dynamics": {"duration": 2.0, "output_interval": 0.1, "integrator": {"kind": "rk4"}}}}
    res = rfesim.simulate(sc)
    rate = 2.0 * 10.0 * np.sqrt(1e5 * mass) * 10.0 / (mass * 10.0)
    assert res.counters["time_step"] < 2.785 / rate
    drag = 0.5 * RHO * cd * diameter * u ** 2 * 40.0
    line = res.line("pipe")
    assert -line.seabed_friction[-1, :, 1].sum() == pytest.approx(drag, rel=0.01)     # held, not at mu N
    assert np.ptp(line.position[:, :, 1].mean(axis=1)) < 1e-3
