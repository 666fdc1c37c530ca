"""Tugger lines (rfesim.loads.tugger, top-level ``tuggers`` and ``cranes.<c>.tuggers``) and
the deck's static friction (rfesim.loads.deck in statics).

* the kernel equals a readable numpy reference (all three kinds, a tension or force table
  in time);
* a payload on a light rope pulled sideways by a constant-tension tugger hangs at the angle
  tan(theta) = T / W, its centre on the rope's line (statics), and the forces on it balance;
* an elastic tugger starts with its pretension and follows T = k (L - L0);
* a crane template's tuggers expand to top-level tuggers on its payload; results files keep
  them;
* a payload resting on the deck under a slanted rope is held by the deck's friction in
  statics (the side pull below mu N), where Coulomb's law at zero slip speed gives none;
* bad input names its field.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.errors import ScenarioError

G = 9.81
MASS = 5000.0
ROPE = 10.0
HALF = 1.0           # the body's half height: the rope hangs on its top, [0, 0, HALF]


def tugger_reference(rfe_R, r, v, w, att_p, att_R, att_v, att_w, deck, point, kind, ts, vs, k, L0, c, t):
    """The tugger law of rfesim.loads.tugger for one line, numpy vectors: (F, M, T, L)."""
    D = att_p + att_R @ deck
    o = rfe_R @ point
    e = D - (r + o)
    L = float(np.linalg.norm(e))
    u = e / L
    if kind == 0:
        T = float(np.interp(t, ts, vs))
    elif kind == 2:                  # a set push (a cylinder): a negative pull of either sign
        T = -float(np.interp(t, ts, vs))
        if k > 0.0:                  # end stops: k their stiffness, L0 the shortest, c the longest length
            if c > 0.0 and L > c:
                T += k * (L - c)
            elif L < L0:
                T -= k * (L0 - L)
        F = T * u
        return F, np.cross(o, F), T, L
    else:
        if L <= L0:
            return np.zeros(3), np.zeros(3), 0.0, L
        vD = att_v + np.cross(att_w, att_R @ deck)
        vP = v + np.cross(w, o)
        T = k * (L - L0) + c * float(u @ (vD - vP))
    if T <= 0.0:
        return np.zeros(3), np.zeros(3), 0.0, L
    F = T * u
    return F, np.cross(o, F), T, L


def test_tugger_kernel_equals_the_reference():
    from rfesim.kinematics import rot_zyx
    from rfesim.loads.tugger import tugger_forces
    rng = np.random.default_rng(7)
    ng, nb = 30, 6
    R = np.stack([rot_zyx(*rng.uniform(-1, 1, 3)) for _ in range(nb)])
    r = rng.normal(0, 3, (nb, 3))
    v, w = rng.normal(0, 0.5, (nb, 3)), rng.normal(0, 0.2, (nb, 3))
    att_p = np.array([[0.0, 0, 0], [1.0, 2.0, 0.3]])
    att_R = np.stack([np.eye(3), rot_zyx(0.4, 0.05, -0.08)])
    att_v = np.array([[0.0, 0, 0], [0.2, -0.1, 0.4]])
    att_w = np.array([[0.0, 0, 0], [0.01, 0.03, -0.02]])
    rfe = rng.integers(0, nb, ng)
    att = rng.integers(0, 2, ng)
    deck = rng.normal(0, 5, (ng, 3))
    point = rng.normal(0, 1, (ng, 3))
    kind = rng.integers(0, 3, ng)
    K = 4
    ts = np.sort(rng.uniform(0, 10, (ng, K)), axis=1)
    vs = rng.uniform(0, 1e4, (ng, K))
    vs[kind == 2] -= 5e3                     # set forces of both signs
    count = rng.integers(1, K + 1, ng)
    for j in range(ng):                    # rows beyond count repeat the last one (rfesim.model.tuggers)
        ts[j, count[j]:] = ts[j, count[j] - 1]
        vs[j, count[j]:] = vs[j, count[j] - 1]
    k, c = rng.uniform(1e4, 1e6, ng), rng.uniform(0, 1e4, ng)
    L0 = rng.uniform(0, 8, ng)
    c[kind == 2] = rng.uniform(2.0, 12.0, int(np.sum(kind == 2)))    # the cylinders' longest lengths
    k[np.where(kind == 2)[0][::3]] = 0.0                             # some without stops
    for t in (0.0, 3.7, 11.0):
        F, M = np.zeros((nb, 3)), np.zeros((nb, 3))
        T, L = np.zeros(ng), np.zeros(ng)
        tugger_forces(rfe, att, deck, point, kind, ts, vs, count, k, L0, c, t, att_p, att_R, att_v, att_w, R, r, v,
                      w, F, M, T, L)
        Fr, Mr = np.zeros((nb, 3)), np.zeros((nb, 3))
        slack = 0
        stops = 0
        for j in range(ng):
            a, i, m = att[j], rfe[j], count[j]
            f, mo, Tr, Lr = tugger_reference(R[i], r[i], v[i], w[i], att_p[a], att_R[a], att_v[a], att_w[a], deck[j],
                                             point[j], kind[j], ts[j, :m], vs[j, :m], k[j], L0[j], c[j], t)
            Fr[i] += f
            Mr[i] += mo
            slack += Tr == 0.0
            stops += kind[j] == 2 and k[j] > 0.0 and (Lr > c[j] or Lr < L0[j])
            assert T[j] == pytest.approx(Tr, rel=1e-12, abs=1e-9)
            assert L[j] == pytest.approx(Lr, rel=1e-12)
        np.testing.assert_allclose(F, Fr, rtol=1e-12, atol=1e-8)
        np.testing.assert_allclose(M, Mr, rtol=1e-12, atol=1e-8)
        assert 0 < slack < ng                # slack and taut elastic lines both exercised
        assert (T < 0).any() and stops > 0   # and pushing force elements, some on their end stops


def hanging(tugger_mode, deck_point=(1000.0, 0.0, -ROPE - HALF), body_point=(0.0, 0.0, 0.0), duration=0.0):
    """A body on a light rope from a fixed point at the origin, a tugger toward +x."""
    return {"environment": {"gravity": G},
            "vessels": {"quay": {"position": [0, 0, 0], "motion": {"kind": "fixed"}}},
            "line_types": {"rope": {"EA": 5e8, "EIy": 10.0, "mass_per_length": 0.01, "tension_only": True}},
            "bodies": {"box": {"mass": MASS, "radius_of_gyration": 1.0, "height": 2 * HALF}},
            "lines": {"rope": {"type": "rope", "length": ROPE, "elements": 5,
                               "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, -1]},
                               "end_b": {"attach": "box", "position": [0, 0, HALF]}}},
            "tuggers": {"tug": {"body": "box", "vessel": "quay", "deck_point": list(deck_point),
                                "body_point": list(body_point), "mode": tugger_mode}},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"enabled": duration > 0, "duration": max(duration, 1.0), "output_interval": 0.05,
                                      "integrator": {"kind": "generalized-alpha", "time_step": 0.05}}}}


def test_a_constant_tension_tugger_holds_the_payload_at_the_angle_of_its_pull():
    T = 0.3 * MASS * G
    res = rfesim.statics(hanging({"kind": "tension", "tension": T}))
    box, tug = res.body("box"), res.tugger("tug")
    theta = math.atan2(T, MASS * G)          # the rope is light and stiff: it points through the centre
    x, z = box.position[-1, 0], box.position[-1, 2]
    assert x == pytest.approx((ROPE + HALF) * math.sin(theta), rel=2e-3)
    assert z == pytest.approx(-(ROPE + HALF) * math.cos(theta), rel=2e-3)
    assert tug.tension[-1] == pytest.approx(T, rel=1e-12)
    # the rope, the tugger and the weight balance on the body
    total = box.connection_force[-1] + tug.force[-1] + np.array([0.0, 0.0, -MASS * G])
    assert np.abs(total).max() < 1e-6 * MASS * G
    assert tug.length[-1] == pytest.approx(np.linalg.norm(np.array([1000.0, 0, -ROPE - HALF]) - box.position[-1]),
                                           rel=1e-9)


def test_an_elastic_tugger_starts_at_its_pretension_and_follows_its_spring():
    k, pre = 2.0e5, 8000.0
    data = hanging({"kind": "elastic", "stiffness": k, "pretension": pre}, deck_point=(30.0, 0.0, -ROPE - HALF))
    data["bodies"]["box"]["position"] = [0.0, 0.0, -ROPE - HALF]
    res = rfesim.statics(data)
    tug = res.tugger("tug")
    L_start = 30.0                               # the box's initial centre is level with the deck point
    L0 = L_start - pre / k
    assert tug.tension[-1] == pytest.approx(k * (tug.length[-1] - L0), rel=1e-9)
    # the box swings toward the tugger until rope, tugger and weight balance: the line shortens
    assert 0.0 < tug.tension[-1] < pre and tug.length[-1] < L_start
    slack = hanging({"kind": "elastic", "stiffness": k, "length": 40.0}, deck_point=(30.0, 0.0, -ROPE - HALF))
    res = rfesim.statics(slack)
    assert res.tugger("tug").tension[-1] == 0.0                              # slack: no pull
    assert abs(res.body("box").position[-1, 0]) < 1e-6                       # hangs plumb


def test_crane_template_tuggers_expand_and_results_files_keep_them(tmp_path):
    from rfesim.scenario.cranes import expand
    import json
    from pathlib import Path
    data = json.loads(Path("scenarios/column_crane.json").read_text())
    data["vessels"]["barge"]["motion"]["file"] = str(Path("scenarios/data/barge_100m_raos.json").resolve())
    data["cranes"]["crane"]["tuggers"] = {
        "aft": {"deck_point": [-12.0, 6.0, 4.0], "body_point": [-1.5, 0.0, 0.0],
                "mode": {"kind": "tension", "tension": [[0.0, 2000.0], [10.0, 6000.0]]}}}
    out = expand(data)
    assert out["tuggers"]["crane_aft"] == {"body": "crane_payload", "vessel": "barge", "deck_point": [-12.0, 6.0, 4.0],
                                           "body_point": [-1.5, 0.0, 0.0],
                                           "mode": {"kind": "tension", "tension": [[0.0, 2000.0], [10.0, 6000.0]]}}
    data["analysis"]["dynamics"].update(duration=2.0, output_interval=0.5)
    res = rfesim.simulate(data)
    tug = res.tugger("crane_aft")
    np.testing.assert_allclose(tug.tension, np.interp(res.time, [0.0, 10.0], [2000.0, 6000.0]), rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(tug.force, axis=1), tug.tension, rtol=1e-9)
    path = tmp_path / "crane.nc"
    res.to_netcdf(path)
    back = rfesim.open_results(path).tugger("crane_aft")
    assert back.body == "crane_payload" and back.vessel == "barge"
    np.testing.assert_array_equal(back.tension, tug.tension)
    np.testing.assert_array_equal(back.force, tug.force)


def test_deck_friction_holds_a_payload_under_a_slanted_rope_in_statics():
    """The rope from a point 3 m to the side pulls the resting box sideways; the deck's
    static friction (mu N above the side pull) holds it where it was put."""
    data = {"environment": {"gravity": G},
            "vessels": {"supply": {"position": [0, 0, 0], "motion": {"kind": "fixed"}}},
            "line_types": {"rope": {"EA": 5e7, "EIy": 300.0, "mass_per_length": 5.0, "tension_only": True}},
            "bodies": {"box": {"mass": 10000.0, "radius_of_gyration": 1.0, "height": 2.0, "position": [0, 0, 3.0],
                               "deck": {"vessel": "supply", "height": 2.0, "friction": 0.5}}},
            "lines": {"rope": {"type": "rope", "length": 16.27, "elements": 8,     # 16.279 m to the box's top
                               "end_a": {"attach": "fixed", "position": [3.0, 0, 20.0]},
                               "end_b": {"attach": "box", "position": [0, 0, 1.0]}}},
            "winches": {"w": {"line": "rope", "mode": {"kind": "speed", "rows": [[0.0, 0.0]]}}},
            "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}}}
    res = rfesim.statics(data)
    box = res.body("box")
    rope = box.connection_force[-1]
    N = box.deck_force[-1]
    assert rope[0] > 1000.0                                 # the rope pulls sideways
    assert N > 0.5 * 10000.0 * G and abs(rope[0]) < 0.5 * N  # below the friction limit
    # held where it was put, give or take the contact springs: the base slides by F_h / k on
    # the corners' stick springs (k in all, W / 5 mm), and the body tilts under the couple of
    # the rope's pull at its top (2 m above the base) on the corners' vertical springs
    # (k (a/2)^2 with the default 2 x 2 m footprint), which moves the centre 1 m up by as much again, twice
    k = 10000.0 * G / 0.005
    tilt = rope[0] * 2.0 / (k * 1.0 ** 2)
    assert box.position[-1, 0] == pytest.approx(rope[0] / k + 1.0 * tilt, rel=0.02)
    assert N + rope[2] == pytest.approx(10000.0 * G, rel=1e-6)


def test_deck_statics_stick_kernel_equals_the_reference():
    """The statics branch of rfesim.loads.deck: each corner's normal force as in dynamics
    (no velocity), friction -k/4 (B - A)_t returned onto |F_t| <= mu N, A the corner's
    anchor in the vessel frame."""
    from test_deck_liftoff import corners_of, deck_reference
    from rfesim.kinematics import rot_zyx
    from rfesim.loads.deck import deck_forces
    rng = np.random.default_rng(5)
    nb = 40
    att_p = np.array([[0.0, 0, 0], [1.0, 2.0, 0.3]])
    att_R = np.stack([np.eye(3), rot_zyx(0.4, 0.05, -0.08)])
    zero = np.zeros((2, 3))
    att = rng.integers(0, 2, nb)
    z = rng.uniform(1.5, 2.5, nb)
    k, mu = rng.uniform(1e6, 1e7, nb), rng.uniform(0.1, 0.5, nb)
    corners = np.stack([corners_of(*rng.uniform(1, 4, 2), rng.uniform(0.5, 1.5)) for _ in range(nb)])
    R = np.stack([rot_zyx(*rng.normal(0, 1e-4, 3)) for _ in range(nb)])
    anchor = np.zeros((nb, 4, 3))
    r = np.zeros((nb, 3))
    for j in range(nb):
        a = att[j]
        # anchors: the corners of the body standing upright with its underside on the deck
        centre = np.array([rng.normal(0, 2), rng.normal(0, 2), z[j] - corners[j, 0, 2]])
        anchor[j] = centre + corners[j]
        # the body a few mm into the deck, moved sideways by 0.1 mm (sticks) or 5 mm (slips), tilted a little
        side = 1e-4 if j % 2 else 5e-3
        angle = rng.uniform(0, 2 * np.pi)
        moved = centre + [side * np.cos(angle), side * np.sin(angle), -rng.uniform(0.002, 0.006)]
        r[j] = att_p[a] + att_R[a] @ moved
        R[j] = att_R[a] @ R[j]
    F, M, N = np.zeros((nb, 3)), np.zeros((nb, 3)), np.zeros(nb)
    deck_forces(np.arange(nb), att.astype(np.int64), z, corners, k, np.zeros(nb), mu, att_p, att_R, zero, zero, R, r,
                np.zeros((nb, 3)), np.zeros((nb, 3)), F, M, N, np.ones(1, np.int64), anchor)
    side = []
    for j in range(nb):
        a = att[j]
        Fr, Mr, Nr = deck_reference(R[j], r[j], np.zeros(3), np.zeros(3), att_p[a], att_R[a], zero[a], zero[a], z[j],
                                    corners[j], k[j], 0.0, mu[j], anchor=anchor[j])
        assert Nr > 0.0 and N[j] == pytest.approx(Nr, rel=1e-12)
        np.testing.assert_allclose(F[j], Fr, rtol=1e-10, atol=1e-6)
        np.testing.assert_allclose(M[j], Mr, rtol=1e-10, atol=1e-6)
        n = att_R[a][:, 2]
        side.append(np.linalg.norm(Fr - (Fr @ n) * n) / (Fr @ n) / mu[j])
    # bodies that stick (side force below mu N) and bodies that slip (all corners at the limit,
    # their directions a little apart as the body is tilted)
    side = np.asarray(side)
    assert np.sum(side < 0.9) >= 10 and np.sum(np.abs(side - 1.0) < 2e-3) >= 10


@pytest.mark.parametrize("change, field, words", [
    (lambda d: d["tuggers"]["tug"].update(body="crate"), "tuggers.tug.body", "unknown body 'crate'"),
    (lambda d: d["tuggers"]["tug"].update(vessel="tug1"), "tuggers.tug.vessel", "unknown vessel 'tug1'"),
    (lambda d: d["tuggers"]["tug"]["mode"].update(tension=-5.0), "tuggers.tug.mode.tension", "a tugger pulls"),
    (lambda d: d["tuggers"]["tug"]["mode"].update(tension=[[0, 1.0], [0, 2.0]]), "tuggers.tug.mode.tension.1.0",
     "does not increase"),
    (lambda d: d["tuggers"]["tug"].update(mode={"kind": "elastic", "stiffness": 10.0, "pretension": 1e6}),
     "tuggers.tug.mode.pretension", "stretches"),
])
def test_bad_tuggers_are_refused_naming_the_field(change, field, words):
    data = hanging({"kind": "tension", "tension": 100.0})
    change(data)
    with pytest.raises(ScenarioError) as err:
        rfesim.statics(data)
    assert field in str(err.value) and words in str(err.value)


def test_crane_tugger_on_an_unknown_vessel_names_the_template_field():
    from rfesim.scenario.cranes import expand
    import json
    from pathlib import Path
    data = json.loads(Path("scenarios/column_crane.json").read_text())
    data["cranes"]["crane"]["tuggers"] = {"aft": {"deck_point": [0, 0, 4], "vessel": "tug",
                                                  "mode": {"kind": "tension", "tension": 1.0}}}
    with pytest.raises(ScenarioError) as err:
        expand(data)
    assert "cranes.crane.tuggers.aft.vessel" in str(err.value) and "unknown vessel 'tug'" in str(err.value)


def test_liftoff_scenario_lifts_the_module_off_the_supply_vessel():
    """scenarios/column_crane_liftoff.json: at rest the deck and the rope share the weight;
    the module lifts off once the winch hauls in, is never set down again, rises by the
    hauled length less the rope's stretch, and the tuggers keep their tension."""
    from pathlib import Path
    sc = rfesim.load_scenario(Path("scenarios/column_crane_liftoff.json"))
    res = rfesim.simulate(sc)
    box = res.body("crane_payload")
    t = np.asarray(res.time)
    W = 10000.0 * G
    tug_z = sum(res.tugger(n).force[0, 2] for n in ("crane_fore", "crane_aft"))
    assert box.deck_force[0] > 0.3 * W and box.connection_force[0, 2] > 0.3 * W      # shared at rest
    assert box.deck_force[0] + box.connection_force[0, 2] + tug_z == pytest.approx(W, rel=1e-6)
    off = int(np.argmax(box.deck_force <= 0.0))
    assert 8.5 < t[off] < 11.0                                # the haul starts at 8 s
    assert np.all(box.deck_force[off:] == 0.0)                # lifted clear, no re-contact
    assert box.connection_tension[off:].min() > 0.3 * W       # the rope never goes slack
    hauled = -res.winch("crane_winch").payout[-1]
    assert hauled == pytest.approx(8.8, rel=1e-6)
    rise = box.position[-1, 2] - box.position[0, 2]
    assert 0.9 * hauled < rise < hauled + 0.5
    for n in ("crane_fore", "crane_aft"):
        np.testing.assert_allclose(res.tugger(n).tension, 3000.0, rtol=1e-12)
