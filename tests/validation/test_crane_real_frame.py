"""Crane member loads of the real frame (rfesim.crane_results.crane_summary, docs/theory.md
'Member loads of the real frame'). A table-driven luffing joint (an angle, stroke or rope
length table) holds the boom or legs by a moment at the hinge, where the real frame has a pin
and the cylinders (a luffing rope) push (pull) at their eye: the model's members between the
hinge and the eye, and the loads the hinge puts on the deck, are those of a frame without
cylinders. crane_summary takes them over to the real frame.

Checked: a tilt-driven A-frame (portal and equivalent line) against the same frame
force-driven (hinged, the cylinders at their eye: the model is the real frame), at the tilt
the force holds; the column crane of scenarios/column_crane.json against the hand formula
M(s) - (M_hinge / e)(e - s) below the eye, its peak at the eye, the cylinder's push along
the boom; a column crane's cylinder based on the deck and a luffing rope; the crossbeam's
peak at the sheave (end moments in the ranges); the rebuilt section loads against the
model's; the command line and a sweep."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.crane_results import crane_summary, section_loads, structure_loads, template_actuators
from test_cranes import column      # the test crane of the crane validation (tests/ dirs are on sys.path)

G = 9.81
ROOT = Path(__file__).resolve().parents[2]


def a_frame(portal=True, tilt=35.0, **cylinder):
    """A 10 m A-frame holding 20 t 5 m under its sheave, cylinders from 4 m inboard to 6 m up
    the legs (the auditor's frame)."""
    tpl = {"type": "a-frame", "position": [-48.0, 0.0, 4.0], "outboard_deg": 180.0,
           "legs": {"length": 10.0, "outer_diameter": 0.8, "wall_thickness": 0.03, "elements": 16},
           "leg_spacing": 6.0, "crossbeam_mass": 4600.0, "tilt_deg": tilt,
           "cylinder": {"base": [-4.0, 0.0], "eye": 6.0, "count": 2, **cylinder},
           "rope": {"length": 5.0, "diameter": 0.05, "elements": 10},
           "payload": {"mass": 20000.0, "radius_of_gyration": [1.2, 1.2, 1.3], "volume": 8.0, "height": 2.5}}
    if portal:
        tpl["crossbeam"] = {"length": 6.0, "outer_diameter": 0.8, "wall_thickness": 0.03, "elements": 6}
    return {"environment": {"gravity": G}, "cranes": {"af": tpl},
            "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}}}


def column_crane_statics():
    data = json.load(open(ROOT / "scenarios" / "column_crane.json"))
    data["vessels"]["barge"]["motion"]["file"] = str(ROOT / "scenarios" / "data" / "barge_100m_raos.json")
    data["analysis"]["dynamics"]["enabled"] = False
    return data


@pytest.mark.parametrize("portal", [True, False])
def test_tilt_driven_a_frame_loads_are_those_of_the_force_driven_frame(portal):
    """The frame force-driven at 430 kN per cylinder (hinged legs, the cylinders at their eye)
    settles at a tilt; the same frame tilt-driven to that tilt, with crane_summary's
    correction, has its member loads within 1 % of the largest of each member (measured at
    most 0.4 %: the two models' members bend differently between the hinge and the eye), its
    axial forces and hinge forces within 0.5 % (measured 0.26 %), its shear forces within 1 %
    (measured 0.39 %) and torques within 0.5 % of the frame's largest, no moment about the
    hinge axis, and the cylinders' reaction on the deck apart. Uncorrected, the legs' largest
    moment was 2.7 times the real one (918 against 343 kN m, the portal) and their
    compression below the eye 3.6 times too small."""
    data = a_frame(portal, force=-430.0e3)
    cyl = data["cranes"]["af"]["cylinder"]
    ref = crane_summary(rfesim.statics(data), "af", cylinder=cyl)
    tilt = float(ref["drive_angle"]["luffing"][0])
    assert 34.0 < tilt < 38.0
    table = a_frame(portal, tilt=tilt)
    res = rfesim.statics(table)
    out = crane_summary(res, "af", cylinder=table["cranes"]["af"]["cylinder"])
    assert out["member_loads_of"] == ref["member_loads_of"] == "real frame"
    assert out["member_loads_residual"] < 1e-6
    lines = ["af_stub", "af_legs", "af_crossbeam"] + (["af_stub_2", "af_legs_2", "af_crossbeam_2"] if portal else [])
    assert sorted(out["member_loads"]) == sorted(lines)
    torque_scale = max(float(np.max(np.abs(ref["member_loads"][n]["torque"]))) for n in lines) + 1.0
    for line in lines:
        a, b = out["member_loads"][line], ref["member_loads"][line]
        np.testing.assert_allclose(a["arc_length"], b["arc_length"])
        peak = np.max(b["bend_moment"])
        assert np.max(np.abs(a["bend_moment"] - b["bend_moment"])) < 0.01 * peak, line
        assert np.max(np.abs(a["axial_force"] - b["axial_force"])) < 5e-3 * np.max(np.abs(b["axial_force"])), line
        # shear within 1 % of the member's largest (measured 0.39 %), torque within 0.5 % of the
        # largest of the frame (the stubs', 51 kN m in the portal; measured 0.3 %)
        assert np.max(np.abs(a["shear_force"] - b["shear_force"])) < 0.01 * np.max(b["shear_force"]), line
        assert np.max(np.abs(a["torque"] - b["torque"])) < 5e-3 * torque_scale, line
        assert out["bend_moment_range"][line]["max"] == pytest.approx(a["bend_moment"][0])
        assert out["axial_force_range"][line]["min"] == pytest.approx(a["axial_force"][0])
        assert out["shear_force_range"][line]["max"] == pytest.approx(a["shear_force"][0])
        assert out["torque_range"][line]["mean"] == pytest.approx(a["torque"][0])
    legs = out["member_loads"]["af_legs"]
    # the real leg's peak is at the eye (6 m), where the model's member had 30 % of its root moment
    assert legs["arc_length"][np.argmax(legs["bend_moment"][0])] == pytest.approx(6.0)
    raw = res.line("af_legs")
    assert np.max(raw.bend_moment) > 2.5 * np.max(legs["bend_moment"])
    below = raw.sde_arc_length < 6.0
    assert np.min(legs["axial_force"][0][below]) < 3.0 * np.min(raw.tension[0][below])
    # uncorrected, the deck stub's shear missed nearly all of the cylinders' horizontal push (the
    # portal's: 12 against 359 kN)
    stub = out["member_loads"]["af_stub"]["shear_force"][0]
    assert np.max(res.line("af_stub").shear_force) < 0.1 * np.max(stub)
    for key in ("base_force", "cylinder_deck_force") + (("base_force_legs",) if portal else ()):
        assert np.max(np.abs(out[key] - ref[key])) < 5e-3 * np.max(np.abs(ref[key])), key
    # through the hinges (pins about the y axis) nothing about it; the cylinders' deck ends
    # and the hinges together carry what the model's stubs carried
    deck = np.max(np.abs(out["cylinder_deck_moment"][0]))
    assert abs(out["base_moment"][0][1]) < 1e-6 * deck and abs(ref["base_moment"][0][1]) < 1e-6 * deck
    stubs = ["af_stub", "af_stub_2"] if portal else ["af_stub"]
    np.testing.assert_allclose((out["base_force"] + out["cylinder_deck_force"])[0],
                               sum(res.line(s).end_a_force[0] for s in stubs), atol=1e-6 * deck)
    assert out["legs_per_line"] == (1 if portal else 2)


def test_column_crane_boom_peaks_at_the_cylinder_eye():
    """scenarios/column_crane.json, statics: below the eye (10 m) the boom's moment is the
    model's less the cylinders' moment, M(s) - (M_hinge / e)(e - s) with M_hinge the drive
    torque (the hand formula, to 1e-3 of M_hinge); the peak is at the eye, the model's moment
    there (2298 kN m; the model's range peaked at its first SDE, 3774 kN m); below the eye the
    cylinders' push along the boom (count F u . t, 978 kN) is added to its axial force; the
    cylinders sit on the pedestal, so the pedestal's base loads are the model's and its
    sections below the cylinder base (4 m under the hinge) too."""
    data = column_crane_statics()
    cyl = data["cranes"]["crane"]["cylinder"]
    res = rfesim.statics(data)
    out = crane_summary(res, "crane", cylinder=cyl)
    boom = out["member_loads"]["crane_boom"]
    raw = res.line("crane_boom")
    e, torque = 10.0, float(out["drive_torque"]["luffing"][0])
    s = boom["arc_length"]
    moment = boom["bend_moment"][0]
    for k in np.flatnonzero((s > 0.0) & (s < e)):
        j = int(np.flatnonzero(raw.sde_arc_length == s[k])[0])
        assert moment[k] == pytest.approx(raw.bend_moment[0][j] - torque / e * (e - s[k]), abs=1e-3 * torque)
    assert moment[0] < 1e-6 * torque                          # the pin
    # at the eye: the model's moment there, from its SDE at 10.5 m and the weights between
    sc = rfesim.Scenario.model_validate(data)
    mu_b = sc.line_types["crane_boom_section"].mass_per_length
    tip = G * (10000.0 + sc.line_types["crane_rope_section"].mass_per_length * 32.0)

    def hand(x):
        return G * math.cos(math.radians(45.0)) * (mu_b * (30.0 - x) ** 2 / 2.0) + tip * math.cos(
            math.radians(45.0)) * (30.0 - x)

    eye = int(np.flatnonzero(s == e)[0])
    j = int(np.flatnonzero(raw.sde_arc_length == 10.5)[0])
    assert moment[eye] == pytest.approx(raw.bend_moment[0][j] + hand(10.0) - hand(10.5), abs=1e-3 * torque)
    peak = out["bend_moment_range"]["crane_boom"]
    assert peak["arc_length"][np.argmax(peak["max"])] == e
    assert np.max(raw.bend_moment) > 1.6 * np.max(peak["max"])
    # the cylinders' push along the boom, below the eye
    from rfesim.scenario.cranes import CylinderSpec, cylinder_lever
    a = math.radians(45.0)
    u = np.array([e * math.cos(a) - 2.5, e * math.sin(a) + 4.0])
    push = 2.0 * out["cylinder_force"][0] * float(u @ [math.cos(a), math.sin(a)]) / np.linalg.norm(u)
    assert push == pytest.approx(977.8e3, rel=1e-3)
    assert 2.0 * out["cylinder_force"][0] * cylinder_lever(CylinderSpec.model_validate(cyl), a)[1] == \
        pytest.approx(torque, rel=1e-9)
    below = raw.sde_arc_length < e
    np.testing.assert_allclose(boom["axial_force"][0][below], raw.tension[0][below] + push, rtol=1e-6)
    np.testing.assert_array_equal(boom["axial_force"][0][~below], raw.tension[0][~below])
    # the pedestal: its base is the model's, its sections under the cylinder base too
    ped, rped = out["member_loads"]["crane_pedestal"], res.line("crane_pedestal")
    np.testing.assert_array_equal(out["base_force"], rped.end_a_force)
    np.testing.assert_array_equal(out["base_moment"], rped.end_a_moment)
    assert "cylinder_deck_force" not in out
    low = rped.sde_arc_length < 12.0 - 4.0
    np.testing.assert_array_equal(ped["axial_force"][0][low], rped.tension[0][low])
    assert np.all(ped["axial_force"][0][~low] > 0.0) and np.all(rped.tension[0] < 0.0)  # the hinge pulls it up
    assert out["member_loads_residual"] < 1e-6


def test_column_crane_cylinder_based_on_the_deck_takes_its_reaction_off_the_pedestal():
    """A cylinder based at the pedestal's foot level (8 m under the hinge) stands on the deck:
    the pedestal's base loads and its sections are the real frame's, and with the cylinders'
    own deck force and moment they add up to the model's base loads."""
    data = column(cylinder={"base": [3.0, -8.0], "eye": 8.0, "count": 2})
    res = rfesim.statics(data)
    out = crane_summary(res, "c", cylinder=data["cranes"]["c"]["cylinder"])
    ped = res.line("c_pedestal")
    scale = float(np.max(np.abs(ped.end_a_moment)))
    np.testing.assert_allclose(out["base_force"] + out["cylinder_deck_force"], ped.end_a_force, atol=1e-9 * scale)
    np.testing.assert_allclose(out["base_moment"] + out["cylinder_deck_moment"], ped.end_a_moment, atol=1e-9 * scale)
    assert out["cylinder_deck_force"][0][2] < -0.5 * abs(ped.end_a_force[0][2])       # pushing down on the deck
    assert np.all(out["member_loads"]["c_pedestal"]["axial_force"] > 0.0) and np.all(ped.tension < 0.0)


def test_luffing_rope_pulls_at_its_eye_and_the_hinge_is_a_pin():
    """A boom luffed by a two-fall rope from a gantry (eye at the tip): the real hinge carries
    no moment, and every boom section gets the falls' pull toward the gantry along the boom
    (its compression grows by 2 T u . t)."""
    rope = {"gantry": [-2.0, 6.0], "falls": 2, "length": [[0.0, 17.0], [1.0, 17.0]]}
    data = column(luffing_deg=None, luffing_rope=rope)
    res = rfesim.statics(data)
    kw = template_actuators(rfesim.Scenario.model_validate(data), "c")
    assert kw == {"luffing_rope": rope, "boom_length": 20.0}
    out = crane_summary(res, "c", **kw)
    boom, raw = out["member_loads"]["c_boom"], res.line("c_boom")
    torque = abs(float(out["drive_torque"]["luffing"][0]))
    assert boom["bend_moment"][0][0] < 1e-6 * torque and raw.end_a_moment[0] @ [0, 1, 0] != 0.0
    a = math.radians(float(out["drive_angle"]["luffing"][0]))
    t = np.array([math.cos(a), math.sin(a)])
    u = np.array([-2.0, 6.0]) - 20.0 * t
    pull = 2.0 * out["luffing_rope_tension"][0] * float(u @ t) / np.linalg.norm(u)
    assert pull < 0.0
    np.testing.assert_allclose(boom["axial_force"][0], raw.tension[0] + pull, rtol=1e-3)
    assert np.max(boom["bend_moment"]) < 0.5 * np.max(raw.bend_moment)


def test_crossbeam_range_has_its_peak_at_the_sheave():
    """Audit: the portal's crossbeam (6 elements) peaked at mid-span, the sheave, where only
    its end B moment shows it (252.6 kN m), while its range over the SDEs said 201.7 kN m.
    The ranges take the end moments (a closing line's onto end B included): the peak is at
    end B, P L / 4 + w L^2 / 8 - M_end of the beam between the legs' tops (legs upright)."""
    data = a_frame(tilt=0.0)
    data["cranes"]["af"]["crossbeam"]["elements"] = 6
    res = rfesim.statics(data)
    out = crane_summary(res, "af", cylinder=data["cranes"]["af"]["cylinder"])
    sc = rfesim.Scenario.model_validate(data)
    w = G * sc.line_types["af_crossbeam_section"].mass_per_length
    P = float(np.linalg.norm(res.line("af_rope").end_a_force[0]))
    for line in ("af_crossbeam", "af_crossbeam_2"):
        rng = out["bend_moment_range"][line]
        M_end = rng["max"][0]                    # at the leg's top, end A
        assert rng["arc_length"][-1] == 3.0 and np.argmax(rng["max"]) == len(rng["max"]) - 1
        assert rng["max"][-1] == pytest.approx(P * 6.0 / 4.0 + w * 36.0 / 8.0 - M_end, rel=5e-3)
        assert rng["max"][-1] > 1.2 * np.max(res.line(line).bend_moment)


def test_rebuilt_section_loads_are_the_models():
    """section_loads rebuilds each SDE's force and moment from the line's end-A loads and its
    RFEs' weights (statics): the model's bending moment to 1e-6, its axial force to 2e-4."""
    res = rfesim.statics(column(cylinder={"base": [2.0, -3.0], "eye": 8.0, "count": 2}))
    for line in ("c_pedestal", "c_boom"):
        r, lr = section_loads(res, line), res.line(line)
        # (the tangent from the points: the SDE frame's to their shear offsets, 5e-5 of the force)
        np.testing.assert_allclose(np.sum(r["force"] * r["tangent"], axis=-1), lr.tension,
                                   atol=2e-4 * np.max(np.abs(lr.tension)))
        M = r["moment"]
        bend = np.linalg.norm(M - np.sum(M * r["tangent"], axis=-1, keepdims=True) * r["tangent"], axis=-1)
        np.testing.assert_allclose(bend, lr.bend_moment, atol=1e-6 * np.max(lr.bend_moment))


def test_statics_command_prints_the_real_frames_loads(tmp_path, capsys):
    """`rfesim statics` on a tilt-driven A-frame: the stubs' end A force is the hinge's (the
    cylinders' deck reaction apart) and the legs' tension the real one, with a note."""
    from rfesim.cli import _kn, _vector_kn, main
    data = a_frame(portal=False)
    path = tmp_path / "af.json"
    path.write_text(json.dumps(data))
    assert main(["statics", str(path)]) == 0
    out = capsys.readouterr().out
    res = rfesim.statics(data)
    summary = crane_summary(res, "af", cylinder=data["cranes"]["af"]["cylinder"])
    row = next(line for line in out.splitlines() if line.strip().startswith("af_stub ")).split()
    hinge = summary["base_force"][0]
    assert " ".join(row[1:4]) == _vector_kn(hinge) and row[4] == _kn(np.linalg.norm(hinge))
    assert _kn(np.linalg.norm(res.line("af_stub").end_a_force[0])) not in row      # the model's, with the cylinders
    legs = next(line for line in out.splitlines() if line.strip().startswith("af_legs ")).split()
    assert legs[-2] == _kn(summary["member_loads"]["af_legs"]["axial_force"][0].min())
    note = next(line for line in out.splitlines() if "loads of the real crane frame" in line)
    assert note.split(":")[0].split(", ") == ["  af_stub", "af_legs", "af_crossbeam"]


def test_sweep_max_bend_moment_is_the_real_frames():
    """A sweep case of a tilt-driven portal A-frame heaving 1 s: max_bend_moment is the largest
    of crane_summary's real-frame ranges (the legs at the cylinder eye), not the model's legs'
    or stubs' root moment, 2.7 times that."""
    from rfesim.sweep import run_case
    data = a_frame()
    data["vessels"] = {"v": {"motion": {"kind": "harmonic", "heave": {"amplitude": 0.3, "period": 4.0},
                                        "ramp_duration": 1.0}}}
    data["cranes"]["af"]["vessel"] = "v"
    data["analysis"]["dynamics"] = {"duration": 1.0, "output_interval": 0.1,
                                    "integrator": {"kind": "generalized-alpha", "time_step": 0.05}}
    row = run_case(json.loads(json.dumps(data)))
    assert row["status"] == "done", row["message"]
    res = rfesim.simulate(data)
    summary = crane_summary(res, "af", cylinder=data["cranes"]["af"]["cylinder"])
    real = max(float(np.max(r["max"])) for r in summary["bend_moment_range"].values())
    assert row["max_bend_moment"] == pytest.approx(real, rel=1e-9)
    assert max(float(np.max(m["bend_moment"])) for m in structure_loads(res, data).values()) == real
    assert max(float(np.max(lr.bend_moment)) for lr in res.lines.values()) > 2.0 * real
