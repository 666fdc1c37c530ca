"""Winch schema (field errors), the speed-table payout, and the payout update of the model
arrays against a model compiled directly at the paid-out length."""
from __future__ import annotations

import math

import numpy as np
import pytest

from rfesim.errors import ScenarioError
from rfesim.model.compile import compile_scenario
from rfesim.model.winches import damping_offset, set_payout
from rfesim.scenario import load_scenario
from rfesim.scenario.winches import speed_payout


def scene(length=20.0, winches=None, damping=None, shear=None, integrator="generalized-alpha", body=True, **line):
    rope = {"EA": 1e8, "EIy": 50.0, "mass_per_length": 2.0, "tension_only": True, "rotary_inertia": 0.01}
    if damping is not None:
        rope["damping"] = damping
    ln = {"type": "rope", "length": length, "elements": 8,
          "end_a": {"attach": "fixed", "position": [0, 0, 0]},
          "end_b": {"attach": "payload", "position": [0, 0, 0.5]} if body else {"attach": "free"},
          "loads": [{"at": 5.0, "force": [0, 0, -100.0]}, {"at": "end_b", "force": [0, 0, -10.0]}], **line}
    if shear:
        ln["shear_stiffness"] = shear
    sc = {"environment": {"gravity": 9.81},
          "line_types": {"rope": rope},
          "lines": {"hoist": ln},
          "winches": winches if winches is not None else {"w": {"line": "hoist", "stored": 100.0}},
          "analysis": {"statics": {"enabled": False, "start": "straight"},
                       "dynamics": {"duration": 10.0, "integrator": {"kind": integrator, "time_step": 0.01}}}}
    if body:
        sc["bodies"] = {"payload": {"mass": 500.0, "radius_of_gyration": 0.4}}
    return sc


def errors_of(sc) -> dict:
    with pytest.raises(ScenarioError) as info:
        load_scenario(sc)
    return dict(info.value.errors)


# ----------------------------------------------------------------------------- schema

def test_winch_field_errors():
    errs = errors_of(scene(winches={"w": {"line": "nope"}}))
    assert "winches.w.line" in errs and "unknown line 'nope'" in errs["winches.w.line"]
    errs = errors_of(scene(winches={"a": {"line": "hoist"}, "b": {"line": "hoist"}}))
    assert "already has winch 'a'" in errs["winches.b.line"]
    errs = errors_of(scene(integrator="rk4"))
    assert "generalized-alpha" in errs["analysis.dynamics.integrator.kind"]
    # 15 m paid out by the end of the 10 s run: within the 20 m stored
    sc = load_scenario(scene(winches={"w": {"line": "hoist", "stored": 20.0,
                                            "mode": {"kind": "speed", "rows": [[0, 0], [10, 3.0]]}}}))
    assert sc.winches["w"].stored == 20.0


def test_speed_table_beyond_stored_rope_is_refused():
    errs = errors_of(scene(winches={"w": {"line": "hoist", "stored": 10.0,
                                          "mode": {"kind": "speed", "rows": [[0, 0], [2, 2.0]]}}}))
    # 2 m in the first 2 s, then 2 m/s for 8 s: 18 m > 10 m stored
    assert "18 m" in errs["winches.w.mode.rows"] and "10 m stored" in errs["winches.w.mode.rows"]
    errs = errors_of(scene(winches={"w": {"line": "hoist", "mode": {"kind": "speed", "rows": [[0, -2.0]]}}}))
    assert "hauls in" in errs["winches.w.mode.rows"]


@pytest.mark.parametrize("winch, field", [
    ({"line": "hoist", "mode": {"kind": "drum", "radius": 0.0, "inertia": 1.0}}, "winches.w.mode.radius"),
    ({"line": "hoist", "mode": {"kind": "speed", "rows": [[0, 0], [0, 1]]}}, "winches.w.mode.rows.1"),
    ({"line": "hoist", "mode": {"kind": "tension", "tension": 1e4, "gain": 0.0, "max_speed": 1.0}},
     "winches.w.mode.gain"),
    ({"line": "hoist", "shock_absorber": {"stiffness": -1.0}}, "winches.w.shock_absorber.stiffness"),
    ({"line": "hoist", "heave_compensation": {"kp": 1.0, "gain": 2.0}}, "winches.w.heave_compensation.gain"),
    ({"line": "hoist", "stored": 0.0}, "winches.w.stored"),
    ({"line": "hoist", "mode": {"kind": "drum", "radius": 0.5, "inertia": 1.0,
                                "layers": {"width": 0.0, "rope_diameter": 0.05}}}, "winches.w.mode.layers.width"),
    ({"line": "hoist", "mode": {"kind": "drum", "radius": 0.5, "inertia": 1.0,
                                "layers": {"width": 1.0}}}, "winches.w.mode.layers.rope_diameter"),
    ({"line": "hoist", "mode": {"kind": "drum", "radius": 0.5, "inertia": 1.0, "rope_inertia": "some"}},
     "winches.w.mode.rope_inertia"),
])
def test_winch_value_errors_name_the_field(winch, field):
    errs = errors_of(scene(winches={"w": winch}))
    assert any(f.startswith(field) or f == field for f in errs), errs


@pytest.mark.parametrize("layers, words", [
    ({"width": 1.0, "rope_diameter": 1.2}, "does not fit a first layer"),
    ({"width": 0.04, "rope_diameter": 0.05}, "wider than the drum"),
])
def test_layers_that_do_not_fit_name_the_rope_diameter(layers, words):
    errs = errors_of(scene(winches={"w": {"line": "hoist", "mode": {"kind": "drum", "radius": 0.5, "inertia": 1.0,
                                                                    "layers": layers}}}))
    assert words in errs["winches.w.mode.layers.rope_diameter"], errs


def test_winch_on_a_line_of_another_formulation_is_refused():
    sc = scene(body=False, formulation="classical", integrator="rk4")
    sc["lines"]["hoist"].pop("loads")
    sc["lines"]["hoist"]["end_a"]["direction"] = [0, 0, -1]
    errs = errors_of(sc)
    assert "classical formulation" in errs["winches.w.line"]


# ----------------------------------------------------------------------------- speed table

def test_speed_payout_is_the_exact_integral():
    rows = [[1.0, 0.5], [3.0, 2.0], [4.0, -1.0], [6.0, 0.0]]
    for t in (-1.0, 0.0, 0.7, 1.0, 2.2, 3.5, 4.0, 5.1, 8.0):
        ts = np.linspace(0.0, t, 200001) if t >= 0 else np.linspace(t, 0.0, 200001)
        v = np.interp(ts, [r[0] for r in rows], [r[1] for r in rows])
        ref = np.trapezoid(v, ts) * (1.0 if t >= 0 else -1.0)
        D, speed = speed_payout(rows, t)
        assert D == pytest.approx(ref, abs=1e-8)
        assert speed == pytest.approx(float(np.interp(t, [r[0] for r in rows], [r[1] for r in rows])), abs=1e-15)


# ----------------------------------------------------------------------------- payout update

def _rope_arrays(km, li, lo_extra=0):
    lo, hi, slo, shi = li.rfe_start, li.rfe_stop, li.sde_start, li.sde_stop
    return dict(rfe_length=km.rfe_length[lo:hi], rfe_mass=km.rfe_mass[lo:hi], rfe_inertia=km.rfe_inertia[lo:hi],
                rfe_pin_arm=km.rfe_pin_arm[lo:hi], sde_length=km.sde_length[slo:shi],
                sde_arm_left=km.sde_arm_left[slo:shi], sde_arm_right=km.sde_arm_right[slo:shi],
                sde_stiffness=km.sde_stiffness[slo:shi], sde_damping=km.sde_damping[slo:shi],
                load_arm=km.load_arm, connection_arm=km.sde_arm_left[shi:shi + 1])


@pytest.mark.parametrize("damping, shear", [(None, None), ({"axial_ratio": 0.3, "bending_ratio": 0.1}, None),
                                            ({"axial": 2e5, "bending": 10.0}, "fem")])
@pytest.mark.parametrize("payout", [30.0, -12.0])
def test_payout_arrays_equal_a_model_compiled_at_the_paid_out_length(damping, shear, payout):
    """After set_payout(D), every array the rope's element length enters equals that of the
    scene compiled with length L0 + D (zero payout speed), to round-off."""
    L0 = 20.0
    grown = compile_scenario(load_scenario(scene(length=L0, damping=damping, shear=shear)))
    info = grown.winches[0]
    # point loads sit at fixed fractions of the line: compile the reference with scaled arc lengths
    direct_sc = scene(length=L0 + payout, damping=damping, shear=shear)
    direct_sc["lines"]["hoist"]["loads"][0]["at"] = 5.0 * (L0 + payout) / L0
    direct = compile_scenario(load_scenario(direct_sc))
    set_payout(grown.km, info, payout, 0.0)
    a = _rope_arrays(grown.km, grown.line("hoist"))
    b = _rope_arrays(direct.km, direct.line("hoist"))
    for key in a:
        np.testing.assert_allclose(a[key], b[key], rtol=1e-12, atol=1e-12, err_msg=key)
    # and back to zero payout: the compiled arrays again
    fresh = compile_scenario(load_scenario(scene(length=L0, damping=damping, shear=shear)))
    set_payout(grown.km, info, 0.0, 0.0)
    c = _rope_arrays(fresh.km, fresh.line("hoist"))
    a = _rope_arrays(grown.km, grown.line("hoist"))
    for key in a:
        np.testing.assert_allclose(a[key], c[key], rtol=1e-14, atol=1e-14, err_msg=key)


def test_payout_speed_lengthens_the_rest_gap_by_the_damping_offset():
    """With speed v the arms grow at (|a_l| + |a_r|) v / L0 per SDE: the rest gap of each
    SDE grows by c_x times that over k_x (cancels the damping force of the growth)."""
    model = compile_scenario(load_scenario(scene(damping={"axial_ratio": 0.3})))
    km, info = model.km, model.winches[0]
    li = model.line("hoist")
    set_payout(km, info, 10.0, 0.0)
    still = km.sde_arm_left[li.sde_start:li.sde_stop, 0].copy()
    conn_still = km.sde_arm_left[li.sde_stop, 0]
    v = 1.5
    set_payout(km, info, 10.0, v)
    grow = (np.abs(info.arm_left0[:, 0]) + np.abs(info.arm_right0[:, 0])) * v / info.length0
    k = km.sde_stiffness[li.sde_start:li.sde_stop, 0]
    c = km.sde_damping[li.sde_start:li.sde_stop, 0]
    assert np.all(c > 0)
    np.testing.assert_allclose(km.sde_arm_left[li.sde_start:li.sde_stop, 0] - still, c * grow / k, rtol=0, atol=1e-15)
    np.testing.assert_allclose(damping_offset(c, k, grow), c * grow / k, rtol=1e-15)
    s = li.sde_stop                       # the body connection: its arm on the rope grows too
    expect = abs(info.ext_arm0[0, 0]) * v / info.length0 * km.sde_damping[s, 0] / km.sde_stiffness[s, 0]
    assert km.sde_arm_left[s, 0] - conn_still == pytest.approx(expect, rel=1e-9)


def test_shock_absorber_damping_has_no_default():
    """An absorber without its damping is refused, naming the field and why (it used to default
    to 0: an undamped spring that rings for ever); an explicit 0 is a plain spring: the first
    SDE then has no axial damping at all, the rest of the rope keeps its own."""
    errs = errors_of(scene(winches={"w": {"line": "hoist", "shock_absorber": {"stiffness": 3e6}}}))
    assert "rings for ever" in errs["winches.w.shock_absorber.damping"], errs
    sc = scene(winches={"w": {"line": "hoist", "shock_absorber": {"stiffness": 3e6, "damping": 0.0}}},
               damping={"axial_ratio": 0.2})
    model = compile_scenario(load_scenario(sc))
    km, li = model.km, model.line("hoist")
    assert km.sde_damping[li.sde_start, 0] == 0.0
    assert np.all(km.sde_damping[li.sde_start + 1:li.sde_stop, 0] > 0.0)


def test_shock_absorber_is_in_series_with_the_first_sde():
    sc = scene(winches={"w": {"line": "hoist", "shock_absorber": {"stiffness": 3e6, "damping": 4e4}}})
    model = compile_scenario(load_scenario(sc))
    km, li, info = model.km, model.line("hoist"), model.winches[0]
    kr = 1e8 / (20.0 / 8)
    assert km.sde_stiffness[li.sde_start, 0] == pytest.approx(kr * 3e6 / (kr + 3e6), rel=1e-14)
    assert km.sde_damping[li.sde_start, 0] == 4e4
    assert km.sde_stiffness[li.sde_start + 1, 0] == pytest.approx(kr, rel=1e-14)
    set_payout(km, info, 20.0, 0.0)
    kr2 = kr / 2.0
    assert km.sde_stiffness[li.sde_start, 0] == pytest.approx(kr2 * 3e6 / (kr2 + 3e6), rel=1e-14)
    assert math.isclose(km.rfe_mass[li.rfe_start:li.rfe_stop].sum(), 2.0 * 40.0, rel_tol=1e-14)
