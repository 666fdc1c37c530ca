"""Line-to-line joins (rfesim.scenario.joins, rfesim.model.joins): the schema refuses every
malformed join with an error naming the field; the compile numbers the RFEs of a string
consecutively, adds one joint SDE with the right rest rotation, stiffness and drive rows,
and starts the child at the parent's end B."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import rfesim
from rfesim import ScenarioError
from rfesim.model.compile import _sde_coefficients, compile_scenario
from rfesim.model.joins import JOINT_STIFFNESS
from rfesim.model.joins import axis_rotation, rest_rotation

COLUMN = {"EA": 1.0e10, "EIy": 2.0e8, "EIz": 3.0e8, "GJ": 1.0e8, "mass_per_length": 400.0}
ARM = {"EA": 2.0e10, "EIy": 1.0e8, "EIz": 1.0e8, "GJ": 5.0e8, "mass_per_length": 200.0}
WIRE = {"EA": 1.0e8, "EIy": 10.0, "mass_per_length": 10.0, "tension_only": True}

CRANE = {
    "environment": {"gravity": 9.81},
    "line_types": {"column": COLUMN, "arm": ARM, "wire": WIRE},
    "bodies": {"payload": {"mass": 2000.0, "inertia": [100.0, 100.0, 100.0]}},
    # the children come first in the dict: the model still numbers column -> boom -> rope
    "lines": {
        "rope": {"type": "wire", "length": 8.0, "elements": 8,
                 "end_a": {"attach": "boom:end_b", "connection": "pinned"},
                 "end_b": {"attach": "payload", "position": [0.0, 0.0, 0.5]}},
        "boom": {"type": "arm", "length": 12.0, "elements": 6,
                 "end_a": {"attach": "column:end_b", "connection": "clamped", "direction": [0.8, 0.0, 0.6],
                           "drives": [{"name": "slewing", "axis": [0, 0, 2], "angle": [[0, 10], [10, 40], [20, 100]]},
                                      {"name": "luffing", "axis": [0, -1, 0], "angle": [[0, 0], [5, 15]]}]}},
        "column": {"type": "column", "length": 6.0, "elements": 4,
                   "end_a": {"attach": "fixed", "position": [1.0, 2.0, 0.0], "direction": [0, 0, 1],
                             "connection": "clamped"}},
    },
    "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}},
}


def crane(**changes):
    data = copy.deepcopy(CRANE)
    for dotted, value in changes.items():
        keys = dotted.split("__")
        cur = data
        for k in keys[:-1]:
            cur = cur[int(k)] if isinstance(cur, list) else cur.setdefault(k, {})
        if value is DELETE:
            del cur[keys[-1]]
        else:
            cur[keys[-1]] = value
    return data


DELETE = object()


def errors_of(data, compile_too=False):
    with pytest.raises(ScenarioError) as info:
        sc = rfesim.Scenario.model_validate(data)
        if compile_too:
            compile_scenario(sc)
    return info.value.errors


def assert_error(data, path, *words, compile_too=False):
    errs = errors_of(data, compile_too)
    hits = [r for p, r in errs if p == path]
    assert hits, f"no error for {path}: {errs}"
    assert any(all(w in r for w in words) for r in hits), f"{path}: {hits} lacks {words}"


# ----------------------------------------------------------------------------- schema

def test_valid_crane_string_validates():
    sc = rfesim.Scenario.model_validate(crane())
    assert sc.lines["boom"].end_a.drives[1].name == "luffing"
    assert sc.lines["rope"].end_a.position is None


@pytest.mark.parametrize("path, value, field, words", [
    ("lines__boom__end_a__attach", "mast:end_b", "lines.boom.end_a.attach", ("unknown line", "mast")),
    ("lines__boom__end_a__attach", "column:end_a", "lines.boom.end_a.attach", ("end_b",)),
    ("lines__boom__end_a__attach", "boom:end_b", "lines.boom.end_a.attach", ("own end B",)),
    ("lines__rope__end_a__attach", "column:end_b", "lines.boom.end_a.attach", ("already carries", "rope")),
    ("lines__column__end_b", {"attach": "fixed", "position": [1, 2, 6]}, "lines.column.end_b.attach",
     ("carries line 'boom'",)),
    ("lines__column__end_b", {"attach": "boom:end_b"}, "lines.column.end_b.attach", ("carries line 'boom'",)),
    ("lines__boom__formulation", "classical", "lines.boom.formulation", ()),
    ("lines__boom__end_a__connection", "pinned", "lines.boom.end_a.drives", ("clamped",)),
    ("lines__column__end_a__drives", [{"name": "x", "axis": [0, 0, 1], "angle": [[0, 0]]}],
     "lines.column.end_a.drives", ("clamped join",)),
    ("lines__boom__end_a__drives__0__axis", [0, 0, 0], "lines.boom.end_a.drives.0.axis", ("zero",)),
    ("lines__boom__end_a__drives__0__angle", [[0, 0], [5, 1], [5, 2]], "lines.boom.end_a.drives.0.angle.2",
     ("does not increase",)),
    ("lines__boom__end_a__drives__1__name", "slewing", "lines.boom.end_a.drives.1.name", ("twice",)),
    ("lines__boom__end_a__drives__0__speed", 1.0, "lines.boom.end_a.drives.0.speed", ("unknown key",)),
    ("chains", {"c": {"base": "fixed", "position": [0, 0, 0],
                      "links": {"l": {"rigid": True, "length": 1.0, "mass": 1.0}},
                      "joints": {"j": {"kind": "revolute", "parent": "base", "child": "l", "axis": [0, 0, 1],
                                       "direction": [1, 0, 0]}}}},
     "lines.boom.end_a.attach", ("chains",)),
])
def test_bad_join_names_the_field(path, value, field, words):
    assert_error(crane(**{path: value}), field, *words)


def test_a_closed_loop_of_joins_is_refused():
    data = crane(lines__column__end_a={"attach": "rope:end_b", "connection": "clamped"},
                 lines__rope__end_b={"attach": "free"}, bodies={})
    errs = errors_of(data)
    assert any(p.endswith("end_a.attach") and "closed loop" in r for p, r in errs), errs


def test_parent_in_another_formulation_is_refused():
    # the join check comes before the rule on mixing formulations
    data = crane(lines__column__formulation="classical")
    assert_error(data, "lines.column.formulation", "absolute", "'column' -> 'boom'")


def test_join_position_must_agree_with_the_parent_end():
    # parent end B computed at the compile: a position 1 mm off is refused there
    assert_error(crane(lines__boom__end_a__position=[1.0, 2.0, 6.001]), "lines.boom.end_a.position", "1e-6 m",
                 compile_too=True)
    # within 1e-6 m it is accepted
    compile_scenario(rfesim.Scenario.model_validate(crane(lines__boom__end_a__position=[1.0, 2.0, 6.0 + 1e-8])))
    # parent end B given: checked with the references
    data = crane(lines__column__end_b={"attach": "free", "position": [1.0, 2.0, 6.0]},
                 lines__boom__end_a__position=[1.0, 2.0, 6.5])
    assert_error(data, "lines.boom.end_a.position", "0.5")


# ----------------------------------------------------------------------------- compile

@pytest.fixture(scope="module")
def model():
    return compile_scenario(rfesim.Scenario.model_validate(crane()))


def test_string_rfes_are_consecutive_parent_then_child(model):
    names = [li.name for li in model.lines]
    assert names == ["column", "boom", "rope"]
    col, boom, rope = (model.line(n) for n in ("column", "boom", "rope"))
    assert (col.rfe_start, col.rfe_stop) == (0, 5)
    assert (boom.rfe_start, boom.rfe_stop) == (5, 12)
    assert (rope.rfe_start, rope.rfe_stop) == (12, 21)
    assert model.bodies[0].rfe == 21
    # line SDEs, joint SDEs between them, the body connection last
    assert (col.sde_start, col.sde_stop, boom.sde_start, boom.sde_stop, rope.sde_start) == (0, 4, 5, 11, 12)
    km = model.km
    assert [(j.sde, j.parent_rfe, j.child_rfe) for j in model.joins] == [(4, 4, 5), (11, 11, 12)]
    # every SDE still joins RFEs i and i + 1: block-tridiagonal
    np.testing.assert_array_equal(km.sde_right - km.sde_left, 1)


def _end_points(model, i):
    X, R, L = model.initial.ref.X, model.initial.ref.R, model.km.rfe_length
    return X[i] - 0.5 * L[i] * R[i][:, 0], X[i] + 0.5 * L[i] * R[i][:, 0]


def test_child_starts_at_the_parent_end_along_its_direction(model):
    for j in model.joins:
        np.testing.assert_allclose(_end_points(model, j.child_rfe)[0], _end_points(model, j.parent_rfe)[1],
                                   atol=1e-12)
    np.testing.assert_allclose(_end_points(model, 4)[1], [1.0, 2.0, 6.0], atol=1e-12)
    R = model.initial.ref.R
    np.testing.assert_allclose(R[5][:, 0], [0.8, 0.0, 0.6], atol=1e-12)     # the boom's end_a.direction
    # the rope (no direction) runs toward its end B, the body hanging under the boom tip
    np.testing.assert_allclose(R[12][:, 0], [0.0, 0.0, -1.0], atol=1e-12)
    tip = np.array([1.0, 2.0, 6.0]) + 12.0 * np.array([0.8, 0.0, 0.6])
    np.testing.assert_allclose(_end_points(model, 20)[1], tip - [0.0, 0.0, 8.0], atol=1e-9)


def test_rest_rotation_is_the_initial_relative_rotation(model):
    R = model.initial.ref.R
    for j in model.joins:
        np.testing.assert_allclose(R[j.parent_rfe] @ model.km.sde_rest[j.sde], R[j.child_rfe], atol=1e-13)
    eye_rows = [s for s in range(model.nsde) if s not in (4, 11)]
    np.testing.assert_array_equal(model.km.sde_rest[eye_rows], np.broadcast_to(np.eye(3), (len(eye_rows), 3, 3)))


def test_joint_stiffness_clamped_and_pinned(model):
    km = model.km
    col, boom, rope = (model.line(n) for n in ("column", "boom", "rope"))
    dxm = 0.5 * (col.dx + boom.dx)
    expect = JOINT_STIFFNESS * np.minimum(_sde_coefficients(col.section, dxm, col.shear_model),
                                          _sde_coefficients(boom.section, dxm, boom.shear_model))
    np.testing.assert_allclose(km.sde_stiffness[4], expect, rtol=1e-14)
    assert km.sde_length[4] == pytest.approx(dxm)
    dxm = 0.5 * (boom.dx + rope.dx)
    k = min(_sde_coefficients(boom.section, dxm, boom.shear_model)[:3].max(),
            _sde_coefficients(rope.section, dxm, rope.shear_model)[:3].max())
    k *= JOINT_STIFFNESS
    np.testing.assert_allclose(km.sde_stiffness[11], [k, k, k, 0.0, 0.0, 0.0], rtol=1e-14)
    np.testing.assert_array_equal(km.sde_damping[11, 3:], 0.0)


def test_drive_rows(model):
    km = model.km
    j = model.joins[0]
    assert (j.drive_start, j.drive_stop, j.drive_names) == (0, 2, ["slewing", "luffing"])
    assert km.has_drives
    np.testing.assert_array_equal(km.drive_sde, [4, 4])
    Rp = model.initial.ref.R[j.parent_rfe]
    np.testing.assert_allclose(Rp @ km.drive_axis[0], [0, 0, 1], atol=1e-14)
    np.testing.assert_allclose(Rp @ km.drive_axis[1], [0, -1, 0], atol=1e-14)
    np.testing.assert_allclose(km.drive_t[0, :3], [0, 10, 20])
    np.testing.assert_allclose(km.drive_angle[0, :3], np.radians([10, 40, 100]))
    assert list(km.drive_count) == [3, 2]
    np.testing.assert_allclose(km.drive_phi0, np.radians([10.0, 0.0]))
    from scipy.interpolate import PchipInterpolator
    slopes = PchipInterpolator([0, 10, 20], np.radians([10, 40, 100])).derivative()([0, 10, 20])
    assert slopes[0] > 0.0
    slopes[0] = 0.0             # from rest at its first row (rfesim.model.supports.drive_slopes)
    np.testing.assert_allclose(km.drive_slope[0, :3], slopes, rtol=1e-12)


def test_rest_rotation_with_drives_composes_slewing_then_luffing(model):
    km = model.km
    j = model.joins[0]
    t = 5.0
    rest, axes = rest_rotation(km, j, t)
    from rfesim.model.joins import drive_angle
    d1 = drive_angle(km, 0, t) - math.radians(10.0)
    d2 = drive_angle(km, 1, t)
    assert d2 == pytest.approx(math.radians(15.0))
    Rp = model.initial.ref.R[j.parent_rfe]
    # in global terms: the child frame turned by the luffing about the slewed luffing axis,
    # then by the slewing about z
    Rg = axis_rotation(np.array([0, 0, 1.0]), d1)
    luff_axis = Rg @ np.array([0, -1.0, 0])
    expect = Rg @ axis_rotation(np.array([0, -1.0, 0]), d2) @ Rp @ km.sde_rest[j.sde]
    np.testing.assert_allclose(Rp @ rest, expect, atol=1e-13)
    np.testing.assert_allclose(Rp @ axes[1], luff_axis, atol=1e-13)


def test_rest_rotation_agrees_with_the_kernel_helper(model):
    """rfesim.model.joins.rest_rotation (outputs) against rfesim.loads.drives.rest_at (the
    kernel's Python twin) at times before, inside and after the tables."""
    from rfesim.loads.drives import rest_at
    for t in (-1.0, 0.0, 2.5, 7.0, 13.0, 25.0):
        rest, _ = rest_at(model.km, t)
        for j in model.joins:
            np.testing.assert_allclose(rest_rotation(model.km, j, t)[0], rest[j.sde], atol=1e-14)
