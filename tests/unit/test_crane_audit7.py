"""Regression tests for the crane audit 7 (A-frame, winches, payload body, crane outputs):

D1. a free drum released from the static tension with a ratio-damped (so, for its drum-rope
    mode, nearly undamped) light rope slackens the rope: the closed-form release transient is
    reported (the coarse-step failure that follows is the slack light rope's Newton);
D2. the DAF of a lift-off is taken against the hook load in air, not the first sample (the
    rope's share of the weight while the payload stands on the deck);
D3. a speed table whose payout peaks (or troughs) between its rows is checked at that peak;
D4. the rope's mass is conserved when it slips over the sheave to a deck winch, and the slip
    starts at 0;
D5. the single-line A-frame's sheave is legs.length from the hinge;
D6. the A-frame's base moment is about the hinge (and the portal's about the point between
    its hinges);
D7. added_mass.ca without a volume is refused naming the field.
"""
from __future__ import annotations

import logging
import math
import re

import numpy as np
import pytest

import rfesim
from rfesim.crane_results import crane_summary
from rfesim.errors import ScenarioError

G = 9.81
LEG_D, LEG_T = 0.8, 0.03
LEG_MU = 7850.0 * math.pi / 4.0 * (LEG_D ** 2 - (LEG_D - 2 * LEG_T) ** 2)    # kg/m, one leg (steel)
ROPE_D = 0.05
ROPE_MU = 4000.0 * ROPE_D ** 2                                                # kg/m (template default)


def a_frame(tilt=0.0, portal=False, payload=None, rope=None, winch=None, dyn=0.0, dt=0.05, **over):
    tpl = {"type": "a-frame", "vessel": "v", "position": [0.0, 0.0, 2.0], "outboard_deg": 180.0,
           "legs": {"length": 10.0, "outer_diameter": LEG_D, "wall_thickness": LEG_T, "elements": 8},
           "leg_spacing": 6.0, "crossbeam_mass": 4600.0, "tilt_deg": tilt,
           "cylinder": {"base": [-4.0, 0.0], "eye": 6.0, "count": 2},
           "rope": rope or {"length": 5.0, "diameter": ROPE_D, "elements": 5},
           "payload": payload or {"mass": 20000.0, "radius_of_gyration": 1.2}}
    if portal:
        tpl["crossbeam"] = {"length": 6.0, "outer_diameter": LEG_D, "wall_thickness": LEG_T, "elements": 6}
    if winch:
        tpl["winch"] = winch
    tpl.update(over)
    return {"environment": {"gravity": G}, "vessels": {"v": {"position": [0, 0, 0]}}, "cranes": {"af": tpl},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"enabled": dyn > 0, "duration": max(dyn, 0.2), "output_interval": dt,
                                      "integrator": {"kind": "generalized-alpha", "time_step": dt}}}}


def hoist(mode, L0=20.0, n=10, EA=1e8, mu=1.0, m=1000.0, duration=1.0, h=0.02, damping=None, stored=200.0):
    return {"environment": {"gravity": G},
            "line_types": {"rope": {"EA": EA, "EIy": 1.0, "mass_per_length": mu, "tension_only": True,
                                    "damping": damping or {"axial_ratio": 0.2}}},
            "bodies": {"payload": {"mass": m, "radius_of_gyration": 0.5}},
            "lines": {"hoist": {"type": "rope", "length": L0, "elements": n,
                                "end_a": {"attach": "fixed", "position": [0, 0, 0]},
                                "end_b": {"attach": "payload", "position": [0, 0, 0]}}},
            "winches": {"w": {"line": "hoist", "stored": stored, "mode": mode}},
            "analysis": {"statics": {"enabled": True, "start": "straight"},
                         "dynamics": {"duration": duration, "output_interval": h,
                                      "integrator": {"kind": "generalized-alpha", "time_step": h, "rho_inf": 0.8}}}}


# ----------------------------------------------------------------------------- D1

def test_d1_free_drum_release_with_a_ratio_damped_rope_is_reported_in_closed_form(caplog):
    """The audit's case (m = 1000 kg, J = 100 kg m^2, r = 0.5 m, 20 m of 0.05 kg/m rope of EA
    1e8 N, damping ratio 0.2) at steps that resolve it: the drum, released from the static
    tension T0, and the load swing against the rope about T_eq = m_d M g / (m_d + M) with
    amplitude T0 - T_eq > T_eq: the rope goes slack at acos(-T_eq / (T0 - T_eq)) / omega, as the
    run shows, and the start warns with these numbers."""
    m, J, r, mu, L0, EA, stored = 1000.0, 100.0, 0.5, 0.05, 20.0, 1e8, 200.0
    doc = hoist({"kind": "drum", "radius": r, "inertia": J}, mu=mu, m=m, duration=0.03, h=0.002, stored=stored)
    with caplog.at_level(logging.WARNING, logger="rfesim.model.winches"):
        res = rfesim.simulate(doc)
    w = res.winch("w")
    # hand calculation: the load the rope carries at its first SDE (Delta/2 below the top),
    # the drum's mass at the rope with the rope on it (J + mu r^2 S) / r^2
    T0 = (m + mu * (L0 - L0 / 20)) * G
    md = (J + mu * r * r * stored) / (r * r)
    M = T0 / G
    T_eq = md * M * G / (md + M)
    k = 1.0 / (1.0 / (EA / (L0 / 10)) * 10)          # the ten rope SDEs in series: EA / L0
    omega = math.sqrt(k * (md + M) / (md * M))
    t_slack = math.acos(-T_eq / (T0 - T_eq)) / omega
    assert w.tension[0] == pytest.approx(T0, rel=1e-6)
    assert T_eq == pytest.approx(2853.5, rel=1e-3) and t_slack == pytest.approx(0.0152, rel=1e-2)
    # the run (2 ms steps) goes slack within 5 % of the closed form's time (rope mass, connection)
    t = np.asarray(res.time)
    first_slack = t[np.argmax(w.tension <= 0.0)]
    assert w.tension.min() == 0.0 and first_slack == pytest.approx(t_slack, rel=0.1)
    notes = [rec.getMessage() for rec in caplog.records if "released at the start" in rec.getMessage()]
    assert len(notes) == 1, [rec.getMessage() for rec in caplog.records]
    note = notes[0]
    assert f"{T0 / 1e3:.4g} kN" in note and f"{T_eq / 1e3:.4g} kN" in note
    assert f"slack {t_slack * 1e3:.3g} ms" in note
    # the rope's dampers 0.4 sqrt(EA / Delta * m_red), 632 N s/m inside (m_red = mu Delta / 2),
    # ten in series about 63 N s/m, against 2 sqrt(k mu) = 76 kN s/m for the drum-rope mode
    zeta = float(re.search(r"damping ratio ([0-9.e-]+) ", note).group(1))
    assert 0.0007 < zeta < 0.0009


def test_d1_no_warning_when_the_release_keeps_the_rope_taut(caplog):
    """A motor pull of 0.6 T0 (T_eq = 7.0 kN, swing 2.8 kN): the rope stays taut, no warning,
    and the ratio-damped drum runs at 50 ms steps with the closed-form acceleration."""
    m, J, r, mu = 1000.0, 100.0, 0.5, 0.05
    T0 = (m + mu * 19.0) * G
    doc = hoist({"kind": "drum", "radius": r, "inertia": J, "torque": [[0.0, 0.6 * r * T0]]}, mu=mu, m=m,
                duration=2.0, h=0.05)
    with caplog.at_level(logging.WARNING, logger="rfesim.model.winches"):
        res = rfesim.simulate(doc)
    assert not [rec for rec in caplog.records if "released at the start" in rec.getMessage()]
    w = res.winch("w")
    assert w.tension.min() > 0.3 * T0


# ----------------------------------------------------------------------------- D2

def test_d2_lift_off_daf_is_against_the_hook_load_in_air():
    """A 20 t payload standing on a deck 2 mm above where it would hang (the deck carries part
    of the weight), hauled in at 5 cm/s: the static reference is g (m + mu (L - Delta/2)), not
    the first sample, and the DAF is modest."""
    payload = {"mass": 20000.0, "radius_of_gyration": 1.2, "height": 2.0}
    hung = rfesim.statics(a_frame(payload=dict(payload))).body("af_payload").position[-1]
    payload.update(position=[0.0, 0.0, float(hung[2])], deck={"vessel": "v", "height": float(hung[2]) - 1.0 + 0.002})
    res = rfesim.simulate(a_frame(payload=payload, dyn=2.0, dt=0.02,
                                  winch={"mode": {"kind": "speed", "rows": [[0, 0], [0.5, 0], [1.0, -0.05]]}}))
    out = crane_summary(res, "af")
    deck = res.body("af_payload").deck_force
    assert deck[0] > 0.05 * 20000.0 * G and deck[-1] == 0.0            # it stood on the deck, then lifted off
    top = out["rope_tension"]
    k = int(np.argmax(top))
    L = float(res.winch("af_winch").suspended_length[k])
    static = G * (20000.0 + ROPE_MU * (L - L / 10))
    assert out["static_tension"] == pytest.approx(static, rel=1e-12)
    assert top[0] < 0.95 * static                                     # the old reference: the first sample
    assert out["daf"] == pytest.approx(top.max() / static, rel=1e-12)
    assert 1.0 < out["daf"] < 1.1
    # an explicit reference still wins
    assert crane_summary(res, "af", static_tension=1e5)["daf"] == pytest.approx(top.max() / 1e5)


# ----------------------------------------------------------------------------- D3

def test_d3_payout_peak_between_rows_is_checked():
    """[[0, 0], [2, 1], [6, -1]]: D(2) = 1 m, D(6) = 1 m, but v crosses 0 at t = 4 s where D = 2 m:
    1.5 m stored is refused (the rows alone said 1 m)."""
    from rfesim.scenario.winches import payout_extreme_times, speed_payout
    rows = [[0.0, 0.0], [2.0, 1.0], [6.0, -1.0]]
    assert payout_extreme_times(rows, 7.0) == [0.0, 2.0, 4.0, 6.0, 7.0]
    assert max(speed_payout(rows, t)[0] for t in payout_extreme_times(rows, 7.0)) == pytest.approx(2.0, abs=1e-12)
    doc = hoist({"kind": "speed", "rows": rows}, stored=1.5, duration=7.0, h=0.05)
    with pytest.raises(ScenarioError) as exc:
        rfesim.Scenario.model_validate(doc)
    assert "winches.w.mode.rows" in str(exc.value) and "pays out 2 m" in str(exc.value)
    doc["winches"]["w"]["stored"] = 2.0 + 1e-9
    rfesim.Scenario.model_validate(doc)


def test_d3_haul_in_trough_between_rows_is_checked():
    """[[0, 0], [2, -1], [6, 1]] on a 2 m rope: D(2) = D(6) = -1 m (1 m left), but D(4) = -2 m:
    nothing left hanging. Refused; on a 2.2 m rope (0.2 m = 9 % left) accepted."""
    doc = hoist({"kind": "speed", "rows": [[0.0, 0.0], [2.0, -1.0], [6.0, 1.0]]}, L0=2.0, n=2, duration=7.0)
    with pytest.raises(ScenarioError) as exc:
        rfesim.Scenario.model_validate(doc)
    assert "winches.w.mode.rows" in str(exc.value) and "hauls in 2 m" in str(exc.value)
    doc["lines"]["hoist"]["length"] = 2.2
    rfesim.Scenario.model_validate(doc)


# ----------------------------------------------------------------------------- D4

def test_d4_rope_mass_is_conserved_when_it_slips_to_a_deck_winch():
    """The portal A-frame swinging from -10 to 20 deg with its rope led to a deck point 10 m
    forward and the winch holding: the rope slips 3.5 m over the sheave; drum + hanging + run
    stays mu (stored + run + rope) to round-off, the run is mu |lead - sheave| and the slip
    starts at 0 (statics' slip is handed to the hanging rope)."""
    lead = np.array([10.0, 0.0, 2.0])
    doc = a_frame(tilt=[[0.0, -10.0], [1.0, -10.0], [6.0, 20.0], [7.0, 20.0]], portal=True, dyn=7.0,
                  rope={"length": 8.0, "diameter": ROPE_D, "elements": 16},
                  winch={"mode": {"kind": "speed", "rows": [[0, 0]]}, "stored": 100.0}, reeving=list(lead))
    res = rfesim.simulate(doc)
    w = res.winch("af_winch")
    slip = res.line("af_rope").reeving_slip
    total = w.rope_mass_suspended + w.rope_mass_drum + w.rope_mass_run
    assert np.ptp(total) < 1e-12 * total[0]
    assert slip[0] == 0.0 and slip[-1] > 3.0
    sheave = res.line("af_rope").position[0, 0]
    assert w.rope_mass_run[0] == pytest.approx(ROPE_MU * np.linalg.norm(lead - sheave), rel=1e-6)
    # the slip handed over came off the hanging rope and went to the run
    assert w.rope_mass_run[-1] - w.rope_mass_run[0] == pytest.approx(w.rope_mass_suspended[0] - w.rope_mass_suspended[-1],
                                                                     rel=1e-12)
    assert w.rope_mass_drum[-1] == pytest.approx(ROPE_MU * 100.0, rel=1e-12)
    # statics' slip (the sheave moved from its compiled position) is in the hanging rope now
    assert w.suspended_length[0] == pytest.approx(8.0 + 0.0258, abs=2e-3)


# ----------------------------------------------------------------------------- D5 and D6

def test_d5_single_line_a_frame_sheave_is_legs_length_from_the_hinge():
    """Legs 10 m at 20 deg outboard: the sheave at (-10 sin 20, 2 + 10 cos 20) = (-3.420, 11.397)
    but for the legs' deflection (mm), as the portal's; the cylinders balance the lifted
    weights' moment about the hinge (legs 2 mu over the 9.5 m line, crossbeam block and the
    legs' top 0.5 m at 9.75 m, payload and rope at 10 m) within 1 %."""
    doc = a_frame(tilt=20.0)
    res = rfesim.statics(doc)
    out = crane_summary(res, "af", cylinder=doc["cranes"]["af"]["cylinder"])
    th = math.radians(20.0)
    tip = out["tip_position"][0]
    assert np.hypot(tip[0], tip[2] - 2.0) == pytest.approx(10.0, abs=2e-3)
    assert tip[0] == pytest.approx(-10.0 * math.sin(th), abs=0.03)
    assert tip[2] == pytest.approx(2.0 + 10.0 * math.cos(th), abs=0.01)
    moment = G * math.sin(th) * (2 * LEG_MU * 9.5 ** 2 / 2 + (4600.0 + 2 * LEG_MU * 0.5) * 9.75
                                 + (20000.0 + ROPE_MU * 5.0) * 10.0)
    a = math.radians(90.0 - 20.0)
    px, pz = 6.0 * math.cos(a), 6.0 * math.sin(a)
    lever = (px * pz - pz * (px + 4.0)) / math.hypot(px + 4.0, pz)
    assert out["cylinder_force"][0] == pytest.approx(moment / (2.0 * lever), rel=0.01)     # -186.0 kN


@pytest.mark.parametrize("portal", [False, True])
def test_d6_a_frame_base_moment_is_about_the_hinge(portal):
    """Legs upright, a 20 kN tugger pull on the payload along -x: about the hinge (or the point
    between the portal's hinges) the moment is -H L_legs (10 m), up to the legs' deflection
    times the vertical load (about 1 kN m); about the stub's foot it would be H (L + 1 m)."""
    H = 20000.0
    doc = a_frame(tilt=0.0, portal=portal,
                  tuggers={"side": {"deck_point": [-1.0e5, 0.0, 0.0], "mode": {"kind": "tension", "tension": H}}})
    res = rfesim.statics(doc)
    out = crane_summary(res, "af")
    F, M = out["base_force"][0], out["base_moment"][0]
    assert F[0] == pytest.approx(-H, rel=1e-6)
    assert M[1] == pytest.approx(-H * 10.0, rel=0.01)
    # the same loads about the stubs' feet, 1 m below: H more
    stubs = ["af_stub", "af_stub_2"] if portal else ["af_stub"]
    foot = sum(res.line(s).end_a_moment[0] for s in stubs)
    feet = [res.line(s).position[0, 0] for s in stubs]
    centre = sum(feet) / len(feet)
    at_feet = foot + sum(np.cross(f - centre, res.line(s).end_a_force[0]) for s, f in zip(stubs, feet))
    assert at_feet[1] - M[1] == pytest.approx(-H * 1.0, rel=1e-3)      # the stub bends (microns) under W


# ----------------------------------------------------------------------------- D7

def test_d7_added_mass_coefficient_without_volume_is_refused():
    doc = hoist({"kind": "speed", "rows": [[0, 0]]})
    doc["environment"]["water"] = {"density": 1025.0, "depth": 500.0}
    doc["bodies"]["payload"].update(added_mass={"ca": [1.0, 1.0, 2.0]}, drag={"cd": 1.0, "area": [4.0, 4.0, 4.0]})
    with pytest.raises(ScenarioError) as exc:
        rfesim.Scenario.model_validate(doc)
    assert "bodies.payload.added_mass.ca" in str(exc.value) and "volume" in str(exc.value)
    # with a volume, or the added mass itself, it is accepted: ca rho V
    doc["bodies"]["payload"]["volume"] = 2.0
    sc = rfesim.Scenario.model_validate(doc)
    assert sc.bodies["payload"].added_mass_per_axis(1025.0) == [2050.0, 2050.0, 4100.0]
    del doc["bodies"]["payload"]["volume"]
    doc["bodies"]["payload"]["added_mass"] = {"mass": 3000.0}
    rfesim.Scenario.model_validate(doc)
