"""Line-to-line joins against closed forms (rfesim.model.joins, docs/theory.md "Line-to-line
joins"): an L-frame of two clamped-joined beams, a pinned join that carries no moment, the
base moment of a crane-like string (an exact statics identity) and a slewing drive."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim

G = 9.81


def beam(EI, EA=1.0e10, GJ=1.0e7, mass=50.0):
    return {"EA": EA, "EIy": EI, "EIz": EI, "GJ": GJ, "mass_per_length": mass}


STATICS = {"statics": {"enabled": True}, "dynamics": {"enabled": False}}


# ----------------------------------------------------------------------------- L-frame

H, A, P = 5.0, 4.0, 1000.0
EI_COLUMN, EI_ARM = 2.0e7, 1.0e7


def l_frame(n: int) -> dict:
    """Column (height H) clamped at the ground, arm (length A) clamped to its top, tip load
    P down, no gravity."""
    return {
        "environment": {"gravity": 0.0},
        "line_types": {"column": beam(EI_COLUMN, mass=100.0), "arm": beam(EI_ARM)},
        "lines": {
            "arm": {"type": "arm", "length": A, "elements": n,
                    "end_a": {"attach": "column:end_b", "connection": "clamped", "direction": [1, 0, 0]},
                    "loads": [{"at": "end_b", "force": [0, 0, -P]}]},
            "column": {"type": "column", "length": H, "elements": n,
                       "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, 1],
                                 "connection": "clamped"}}},
        "analysis": STATICS}


def l_frame_error(n: int) -> tuple[float, object]:
    res = rfesim.statics(l_frame(n))
    exact = P * A ** 3 / (3 * EI_ARM) + P * A ** 2 * H / EI_COLUMN
    tip = res.line("arm").position[0, -1]
    return (H - tip[2]) / exact - 1.0, res


def test_l_frame_tip_deflection_and_base_moment():
    """Tip deflection P a^3/(3 EI_a) + P a^2 h / EI_c within 0.2 % at 10 and 40 elements per
    line (measured +0.108 % and +0.063 %: the shear compliance of the fem SDEs, which the
    closed form leaves out). The joint is nearly rigid (rfesim.model.joins.JOINT_STIFFNESS);
    as plain element-valued SDE it added one element of compliance, +5.9 % at 10 elements."""
    e10, _ = l_frame_error(10)
    e40, res = l_frame_error(40)
    assert abs(e10) < 0.002 and abs(e40) < 0.002
    assert abs(e40) <= abs(e10)
    col, arm = res.line("column"), res.line("arm")
    tip = arm.position[0, -1]
    # base moment: exactly P times the tip's outreach (deformed), about P a
    np.testing.assert_allclose(col.end_a_moment[0], [0.0, P * tip[0], 0.0], atol=1e-6 * P * A)
    assert col.end_a_moment[0][1] == pytest.approx(P * A, rel=1e-3)
    np.testing.assert_allclose(col.end_a_force[0], [0.0, 0.0, -P], atol=1e-6 * P)
    # the joint: the arm pushes the column down with P and turns it with P (tip x - joint x)
    joint = arm.position[0, 0]
    # (the nearly rigid joint's force is its tiny deformation times a large stiffness: it carries the
    # statics tolerance amplified, 1e-5 here)
    np.testing.assert_allclose(arm.end_a_force[0], [0.0, 0.0, -P], atol=2e-5 * P)
    np.testing.assert_allclose(arm.end_a_moment[0], [0.0, P * (tip[0] - joint[0]), 0.0], atol=2e-5 * P * A)
    np.testing.assert_allclose(col.end_b_force[0], -arm.end_a_force[0], atol=1e-9 * P)
    np.testing.assert_allclose(col.end_b_moment[0], -arm.end_a_moment[0], atol=1e-9 * P * A)


# ----------------------------------------------------------------------------- pinned join

LC, EI_C, MU_C = 4.0, 1.0e7, 1.0          # cantilever length, bending stiffness, mass per length
LP, MU_P, HP = 5.0, 100.0, 200.0          # pendant length, mass per length, side load at its foot


def cantilever_with_pendant(connection: str) -> dict:
    """A horizontal cantilever (along x) with a heavy pendant hanging from its tip, pulled
    sideways (y) at its foot."""
    return {
        "line_types": {"cantilever": beam(EI_C, GJ=1.0e7, mass=MU_C),
                       "pendant": {"EA": 1.0e9, "EIy": 1.0e4, "GJ": 1.0e4, "mass_per_length": MU_P}},
        "lines": {
            "cantilever": {"type": "cantilever", "length": LC, "elements": 20,
                           "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                     "connection": "clamped"}},
            "pendant": {"type": "pendant", "length": LP, "elements": 10,
                        "end_a": {"attach": "cantilever:end_b", "connection": connection, "direction": [0, 0, -1]},
                        "loads": [{"at": "end_b", "force": [0, HP, 0]}]}},
        "analysis": {"statics": {"enabled": True, "load_steps": 4}, "dynamics": {"enabled": False}}}


def test_pinned_join_carries_force_only():
    res = rfesim.statics(cantilever_with_pendant("pinned"))
    pend, cant = res.line("pendant"), res.line("cantilever")
    W = MU_P * G * LP
    # the joint force: the pendant's weight and the side load
    np.testing.assert_allclose(pend.end_a_force[0], [0.0, HP, -W], rtol=1e-6, atol=1e-6 * W)
    assert np.linalg.norm(pend.end_a_moment[0]) < 1e-6 * W * LP
    # cantilever tip: force-only deflections (own weight q L^4 / 8EI in z)
    tip = cant.position[0, -1]
    dz = W * LC ** 3 / (3 * EI_C) + MU_C * G * LC ** 4 / (8 * EI_C)
    dy = HP * LC ** 3 / (3 * EI_C)
    assert -tip[2] == pytest.approx(dz, rel=2e-3)
    assert tip[1] == pytest.approx(dy, rel=2e-3)
    # a clamped join, same scene, does carry a moment of the side load (the bent pendant:
    # about 0.4 H L_p)
    clamped = rfesim.statics(cantilever_with_pendant("clamped")).line("pendant")
    assert np.linalg.norm(clamped.end_a_moment[0]) > 0.2 * HP * LP


# ----------------------------------------------------------------------------- crane base moment

def crane_string() -> dict:
    """Column, inclined boom (clamped join), rope on a pinned sheave, payload body; gravity."""
    return {
        "line_types": {"column": beam(5.0e8, mass=800.0), "boom": beam(2.0e8, mass=300.0),
                       "wire": {"EA": 5.0e8, "EIy": 1.0, "mass_per_length": 8.0, "tension_only": True}},
        "bodies": {"payload": {"mass": 5000.0, "inertia": [2000.0, 2000.0, 2000.0]}},
        "lines": {
            "column": {"type": "column", "length": 8.0, "elements": 8,
                       "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, 1],
                                 "connection": "clamped"}},
            "boom": {"type": "boom", "length": 20.0, "elements": 10,
                     "end_a": {"attach": "column:end_b", "connection": "clamped",
                               "direction": [math.cos(math.radians(40)), 0, math.sin(math.radians(40))]}},
            "rope": {"type": "wire", "length": 15.0, "elements": 15,
                     "end_a": {"attach": "boom:end_b", "connection": "pinned"},
                     "end_b": {"attach": "payload", "position": [0, 0, 1.0]}}},
        "analysis": STATICS}


def rfe_masses_and_centres(sc, name, res):
    """RFE masses and centres of a line from its output points (RFE j spans points j, j+1)."""
    line = sc.lines[name]
    mu = sc.line_types[line.type].mass_per_length
    dx = line.length / line.elements
    p = res.line(name).position[0]
    lengths = np.full(line.elements + 1, dx)
    lengths[[0, -1]] = 0.5 * dx
    return mu * lengths, 0.5 * (p[:-1] + p[1:])


def test_crane_base_moment_is_weights_times_outreach():
    sc = rfesim.Scenario.model_validate(crane_string())
    res = rfesim.statics(sc)
    assert "converged" in res.message
    weights, moment = 0.0, np.zeros(3)
    for name in ("column", "boom", "rope"):
        m, c = rfe_masses_and_centres(sc, name, res)
        weights += G * m.sum()
        moment += np.cross(c, np.outer(-G * m, [0, 0, 1])).sum(axis=0)
    body = res.bodies["payload"]
    weights += G * 5000.0
    moment += np.cross(body.position[0], [0, 0, -G * 5000.0])
    base = res.line("column")
    np.testing.assert_allclose(base.end_a_force[0], [0, 0, -weights], rtol=1e-7, atol=1e-7 * weights)
    assert body.position[0][0] > 14.0                       # the payload hangs under the boom tip, 15.3 m out
    np.testing.assert_allclose(base.end_a_moment[0], moment, rtol=1e-6, atol=1e-6 * abs(moment[1]))
    # the rope hangs vertically from the sheave: its joint force is the rope + payload weight
    rope_w = G * (8.0 * 15.0 + 5000.0)
    np.testing.assert_allclose(res.line("rope").end_a_force[0], [0, 0, -rope_w], rtol=1e-6, atol=1e-6 * rope_w)


# ----------------------------------------------------------------------------- slewing drive

SLEW_T = 20.0                                      # s, 0 -> 90 deg
H_COL, GJ_COL = 6.0, 1.0e8                         # column height, torsion stiffness
L_ARM, MU_ARM, EI_SLEW_ARM = 10.0, 100.0, 1.0e8
BETA = 0.02                                        # s, stiffness-proportional (Kelvin-Voigt) damping


def damped(props: dict) -> dict:
    """Damping coefficients beta * stiffness: about 25 % of critical in the lowest torsion
    and bending modes, so the jerk at the start and stop of the drive rings down."""
    return {**props, "damping": {"axial": BETA * props["EA"], "torsion": BETA * props["GJ"],
                                 "bending": BETA * props["EIy"]}}


def slewing_arm(duration: float = 24.0) -> dict:
    return {
        "environment": {"gravity": 9.81},
        "line_types": {"column": damped(beam(5.0e8, GJ=GJ_COL, mass=200.0)),
                       "arm": damped(beam(EI_SLEW_ARM, mass=MU_ARM))},
        "lines": {
            "column": {"type": "column", "length": H_COL, "elements": 6,
                       "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, 1],
                                 "connection": "clamped"}},
            "arm": {"type": "arm", "length": L_ARM, "elements": 10,
                    "end_a": {"attach": "column:end_b", "connection": "clamped", "direction": [1, 0, 0],
                              "drives": [{"name": "slewing", "axis": [0, 0, 1],
                                          "angle": [[0.0, 0.0], [SLEW_T, 90.0]]}]}}},
        "analysis": {"statics": {"enabled": True},
                     "dynamics": {"enabled": True, "duration": duration, "output_interval": 0.25,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.02}}}}


def test_slewing_drive_turns_the_arm(tmp_path):
    """A slow slewing (0 -> 90 deg in 20 s): the tip stays on the turned static tip within
    the elastic lag under the drive's peak angular acceleration (column torsion and arm
    bending, times 3 for the dynamic overshoot of a suddenly applied acceleration), the
    drive torque is the arm's inertia times the angular acceleration, and drive_angle is
    the table."""
    res = rfesim.simulate(slewing_arm())
    arm = res.line("arm")
    t = res.time
    # two rows: the monotone cubic has zero slopes at both (the drive starts and stops smoothly)
    u = np.minimum(t / SLEW_T, 1.0)
    np.testing.assert_allclose(arm.drive_angle[:, 0], 90.0 * u * u * (3.0 - 2.0 * u), atol=1e-9)
    assert arm.drive_names == ("slewing",)
    tip0 = arm.position[0, -1]
    assert 0.0 < H_COL - tip0[2] < 0.05                      # the static sag under gravity
    alpha = 6.0 * (math.pi / 2) / SLEW_T ** 2                # peak angular acceleration, rad/s^2
    inertia = MU_ARM * L_ARM ** 3 / 3.0                      # arm about the slewing axis
    lag = alpha * inertia * H_COL / GJ_COL * L_ARM + 11.0 * MU_ARM * alpha * L_ARM ** 5 / (120.0 * EI_SLEW_ARM)
    miss = []
    for k in range(len(t)):
        phi = math.radians(arm.drive_angle[k, 0])
        Rz = np.array([[math.cos(phi), -math.sin(phi), 0], [math.sin(phi), math.cos(phi), 0], [0, 0, 1]])
        miss.append(np.linalg.norm(arm.position[k, -1] - Rz @ tip0))
    assert max(miss) < 3.0 * lag, (max(miss), lag)
    np.testing.assert_allclose(arm.position[-1, -1], [0.0, tip0[0], tip0[2]], atol=3.0 * lag)
    # drive torque = I d2phi/dt2 (measured within 0.1 %) once the jerk at the start rang down
    torque = arm.drive_torque[:, 0]
    during = (t > 1.5) & (t < SLEW_T - 0.5)
    accel = alpha * (1.0 - 2.0 * t[during] / SLEW_T)
    np.testing.assert_allclose(torque[during], inertia * accel, atol=0.01 * inertia * alpha)
    assert np.abs(torque[t > SLEW_T + 3.0]).max() < 1e-3 * inertia * alpha     # stopped: no drag, no torque
    # the drive channels go through netCDF with their names
    from rfesim.results import open_results
    res.to_netcdf(tmp_path / "slew.nc")
    back = open_results(tmp_path / "slew.nc").line("arm")
    np.testing.assert_array_equal(back.drive_angle, arm.drive_angle)
    np.testing.assert_array_equal(back.drive_torque, arm.drive_torque)
    assert back.drive_names == ("slewing",)
