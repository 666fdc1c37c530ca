"""Pipelay statics: VALIDATION.md P2 (natural catenary, S-lay sagbend), a pipe on rollers
carrying its weight, and an S-lay over a stinger of rollers against the natural catenary
within the bending boundary layer sqrt(EI/H)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import rfesim
from rfesim.catenary import natural_catenary, solve_catenary

G = 9.81
D, T_WALL, E, RHO, RHO_W = 0.3239, 0.0159, 2.07e11, 7850.0, 1025.0
AREA = math.pi / 4 * (D ** 2 - (D - 2 * T_WALL) ** 2)
MASS = RHO * AREA
W_SUB = (MASS - RHO_W * math.pi / 4 * D ** 2) * G          # 356.2532 N/m
EI = E * math.pi / 64 * (D ** 4 - (D - 2 * T_WALL) ** 4)
PIPE = {"outer_diameter": D, "wall_thickness": T_WALL, "youngs_modulus": E, "density": RHO}


def test_P2_submerged_weight_of_the_section():
    assert W_SUB == pytest.approx(356.2532, rel=1e-6)


def test_P2_natural_catenary_sagbend():
    """Lift-off 100 m above the seabed, H = 150 kN, EI -> 0: suspended length 306.936 m,
    span 284.733 m, top tension 185.625 kN at 36.0913 deg, touchdown curvature w/H; 0.1 %.
    The line: anchor (end A) pinned on a stiff seabed, 60 m of it grounded, the top (end B)
    pinned at the analytic position; its length makes H = 150 kN for the elastic line."""
    H, h, grounded = 150e3, 100.0, 60.0
    nat = natural_catenary(W_SUB, h, H)
    span_total = nat["horizontal_span"] + grounded
    EA = E * AREA
    length = brentq(lambda L: solve_catenary(span_total, h, L, W_SUB, EA, seabed=True).horizontal_tension - H,
                    nat["suspended_length"] + grounded - 5.0, nat["suspended_length"] + grounded - 1e-6)
    k_bed = 1e9
    z_axis = -130.0 - W_SUB / k_bed             # the grounded line sinks w/k into the seabed
    sc = {"environment": {"gravity": G, "seabed": {"z": -130.0, "normal_stiffness": k_bed, "damping_ratio": 0.0}},
          "line_types": {"p": {"EA": EA, "EIy": 1.0, "GJ": 1.0, "GA": EA / 3, "mass_per_length": W_SUB / G}},
          "lines": {"pipe": {"type": "p", "length": length, "elements": 150, "shear_stiffness": "kruszewski",
                             "end_a": {"attach": "fixed", "position": [0, 0, z_axis], "connection": "pinned"},
                             "end_b": {"attach": "fixed", "position": [span_total, 0, z_axis + h],
                                       "connection": "pinned"}}},
          "analysis": {"dynamics": {"enabled": False}}}
    line = rfesim.statics(sc).line("pipe")
    top = -line.end_b_force[0]                  # force of the top on the line
    assert top[0] == pytest.approx(H, rel=1e-3)
    assert np.linalg.norm(top) == pytest.approx(185.625e3, rel=1e-3)
    angle = math.degrees(math.atan2(top[2], top[0]))
    assert angle == pytest.approx(36.0913, rel=1e-3)
    suspended = top[2] / W_SUB                  # V = w S
    assert suspended == pytest.approx(306.936, rel=1e-3)
    on_bed = (line.seabed_force[0].sum() - line.end_a_force[0][2]) / W_SUB
    assert length - on_bed == pytest.approx(306.936, rel=1e-3)
    assert span_total - on_bed * (1 + H / EA) == pytest.approx(284.733, rel=1e-3)
    assert line.curvature[0].max() == pytest.approx(W_SUB / H, rel=1e-3)
    # the touchdown channel (searched from the top) within one element of the analytic point
    assert length - line.touchdown_arc_length[0] == pytest.approx(306.936, abs=length / 150)


def test_pipe_on_a_v_roller_carries_its_share_of_the_weight():
    """A 12 m pipe pinned at x = 0 rests on a V of two rollers (45 deg) at x = 8 m: the
    rollers carry W L / (2 x) vertically, half each, along their normals; with the pin
    the reactions sum to the weight."""
    rp, rr, v = D / 2, 0.1, math.radians(45.0)
    bottom = np.array([8.0, 0.0, -(rp + rr) / math.cos(v)])
    axes = [np.array([0.0, math.cos(v), math.sin(v)]), np.array([0.0, -math.cos(v), math.sin(v)])]
    sc = {"environment": {"gravity": G},
          "line_types": {"p": PIPE},
          "lines": {"pipe": {"type": "p", "length": 12.0, "elements": 24,
                             "end_a": {"attach": "fixed", "position": [0, 0, 0], "connection": "pinned"},
                             "end_b": {"attach": "free"}}},
          "supports": {"v": {"kind": "rollers", "line": "pipe", "stiffness": 1e8,
                             "rollers": [{"position": list(bottom + 0.3 * a), "axis": list(a), "width": 0.6,
                                          "radius": rr} for a in axes]}},
          "analysis": {"dynamics": {"enabled": False}}}
    res = rfesim.statics(sc)
    weight = MASS * G * 12.0
    sup = res.support("v")
    on_rollers = -sup.roller_force[0][:, 2].sum()
    assert on_rollers == pytest.approx(weight * 6.0 / 8.0, rel=1e-5)
    assert sup.roller_reaction[0] == pytest.approx(np.full(2, weight * 6.0 / 8.0 / (2 * math.cos(v))), rel=1e-5)
    pin = res.line("pipe").end_a_force[0]
    assert -pin[2] + on_rollers == pytest.approx(weight, rel=1e-9)


def s_lay_scenario(elements=218, H=150e3, h=100.0):
    """S-lay: pipe clamped at the tensioner on a fixed vessel, over a 100 m radius stinger
    of V-rollers bent to 36 deg (about the catenary's departure angle), down to a pinned
    end on the seabed placed so that the natural catenary from the stinger tip has H."""
    rp, rr, v = D / 2, 0.15, math.radians(30.0)
    R, theta, z0, x0, k_bed = 100.0, math.radians(36.0), 2.0, 5.0, 1e7
    lift = (rp + rr) / math.cos(v)
    Rp = R + lift
    zA = z0 + lift
    tip = np.array([x0 + Rp * math.sin(theta), 0.0, zA - Rp * (1 - math.cos(theta))])
    z_axis = tip[2] - h
    nat = natural_catenary(W_SUB, h, H)
    grounded = 60.0
    length = x0 + Rp * theta + nat["suspended_length"] + grounded
    end_b = [tip[0] + nat["horizontal_span"] + grounded, 0.0, z_axis]
    sc = {"environment": {"gravity": G, "water": {"density": RHO_W, "depth": -(z_axis - rp + W_SUB / k_bed)},
                          "seabed": {"z": z_axis - rp + W_SUB / k_bed, "normal_stiffness": k_bed,
                                     "damping_ratio": 0.2}},
          "line_types": {"x65": dict(PIPE, drag_normal=1.0, added_mass_normal=1.0)},
          "lines": {"pipe": {"type": "x65", "length": length, "elements": elements,
                             "end_a": {"attach": "fixed", "position": [0, 0, zA], "direction": [1, 0, 0],
                                       "connection": "clamped"},
                             "end_b": {"attach": "fixed", "position": end_b, "connection": "pinned"}}},
          "supports": {"stinger": {"kind": "stinger", "attach": "fixed", "line": "pipe", "start": [x0, 0, z0],
                                   "direction": [1, 0, 0], "radius": R, "length": R * theta, "spacing": 6.0,
                                   "roller_width": 0.6, "roller_radius": rr, "v_angle_deg": 30.0,
                                   "stiffness": 1e7, "damping": 1e4}},
          "analysis": {"dynamics": {"enabled": False}}}
    return sc, z_axis, zA


def test_s_lay_over_a_stinger_matches_the_natural_catenary_within_the_boundary_layer():
    sc, z_axis, zA = s_lay_scenario()
    res = rfesim.statics(sc)
    line = res.line("pipe")
    H = -line.end_b_force[0][0]                 # the grounded pipe carries H to the pinned end
    layer = math.sqrt(EI / H)                   # bending boundary layer, about 16 m
    assert 130e3 < H < 160e3
    # a point in the middle of the free span, well away from both boundary layers
    pts = line.position[0][1:-1]
    k = int(np.argmin(np.abs(pts[:, 2] - z_axis - 50.0)))
    h_p = pts[k, 2] - z_axis
    nat = natural_catenary(W_SUB, h_p, H)
    assert line.tension[0][k] == pytest.approx(H + W_SUB * h_p, abs=W_SUB * layer * 0.1)
    slope = math.degrees(math.atan2(pts[k - 1, 2] - pts[k + 1, 2], pts[k + 1, 0] - pts[k - 1, 0]))
    assert slope == pytest.approx(nat["top_angle_deg"], abs=0.5)
    # touchdown where the catenary through that point meets the seabed, within sqrt(EI/H)
    touchdown = line.touchdown_position[0]
    assert touchdown[0] == pytest.approx(pts[k, 0] + nat["horizontal_span"], abs=layer)
    # top tension: H plus the weight of the height climbed (in water, then in air), the
    # rollers being normal to the pipe; within w sqrt(EI/H)
    top_axial = line.end_a_force[0][0]
    expected = H + W_SUB * (0.0 - z_axis) + MASS * G * zA
    assert top_axial == pytest.approx(expected, abs=W_SUB * layer)
    # the stinger carries the pipe: the first stations press, none pulls
    sup = res.support("stinger")
    assert sup.roller_reaction[0][:4].min() > 0.0
    assert np.all(sup.roller_reaction[0] >= 0.0)


def test_s_lay_scenario_statics_and_results_file(tmp_path):
    """scenarios/s_lay.json: statics on the barge at rest puts the pipe on the stinger; the
    roller reactions go to /supports/stinger in the results file and come back."""
    sc = rfesim.load_scenario("scenarios/s_lay.json")
    res = rfesim.statics(sc)
    sup = res.support("stinger")
    assert sup.roller_reaction.shape == (1, sup.roller_position.shape[0])
    assert sup.roller_reaction[0, :4].min() > 0.0
    res.to_netcdf(tmp_path / "s_lay.nc")
    back = rfesim.open_results(tmp_path / "s_lay.nc")
    np.testing.assert_array_equal(back.support("stinger").roller_reaction, sup.roller_reaction)
    np.testing.assert_array_equal(back.support("stinger").roller_force, sup.roller_force)
    assert back.support("stinger").line == "pipe" and back.support("stinger").attach == "barge"


@pytest.mark.slow
def test_s_lay_scenario_runs_60_s_of_dynamics():
    res = rfesim.simulate("scenarios/s_lay.json")
    assert res.success and res.time[-1] == pytest.approx(60.0)
    reaction = res.support("stinger").roller_reaction
    assert np.all(reaction >= 0.0) and reaction.max() > 0.0
    assert np.all(np.isfinite(res.line("pipe").tension))
