"""A payload resting on a vessel's deck and lifted off by a winch (rfesim.loads.deck,
``bodies.<b>.deck``): the deck force and the rope tension share the weight at rest; under a
slow haul the payload lifts off when the rope has taken the whole weight, at the time the
two springs in series (rope and deck contact) predict; the kernel equals a readable
numpy reference; a deck on an unknown vessel is refused naming the field."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.errors import ScenarioError

W = 10000.0 * 9.81
EA, ROPE = 5e7, 16.0


def scene(rows, duration=8.0, motion=None):
    return {"environment": {"gravity": 9.81},
            "vessels": {"supply": {"position": [0, 0, 0], "motion": motion or {"kind": "fixed"}}},
            "line_types": {"rope": {"EA": EA, "EIy": 300.0, "mass_per_length": 5.0, "tension_only": True}},
            "bodies": {"box": {"mass": 10000.0, "radius_of_gyration": 1.0, "height": 2.0, "position": [0, 0, 3.0],
                               "deck": {"vessel": "supply", "height": 2.0}}},
            "lines": {"rope": {"type": "rope", "length": ROPE, "elements": 8,
                               "end_a": {"attach": "fixed", "position": [0, 0, 20.0], "direction": [0, 0, -1]},
                               "end_b": {"attach": "box", "position": [0, 0, 1.0]}}},
            "winches": {"w": {"line": "rope", "mode": {"kind": "speed", "rows": rows}}},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"duration": duration, "output_interval": 0.01,
                                      "integrator": {"kind": "generalized-alpha", "time_step": 0.01}}}}


def test_deck_and_rope_share_the_weight_then_the_rope_lifts_it_off_on_time():
    v = 0.02                                      # m/s hauled in from 2.5 s (ramped in from 2 s)
    res = rfesim.simulate(scene([[0.0, 0.0], [2.0, 0.0], [2.5, -v]]))
    box = res.body("box")
    t = np.asarray(res.time)
    deck = np.asarray(box.deck_force)
    rope = np.asarray(box.connection_force)[:, 2]
    # at rest: the deck carries what the rope does not (the rope's own weight hangs on its top)
    assert deck[0] > 0.5 * W
    assert deck[0] + rope[0] == pytest.approx(W, rel=1e-6)
    # while it rests, slowly unloaded, the two still share the weight
    resting = (t > 0.5) & (deck > 0.1 * W)
    np.testing.assert_allclose(deck[resting] + rope[resting], W, rtol=2e-3)
    # lift-off: the rope takes the deck's load N0 through the rope and contact springs in series
    N0 = deck[0]
    k_rope = EA / ROPE
    k_deck = W / 0.005
    haul = N0 * (1.0 / k_rope + 1.0 / k_deck)     # m hauled in until the deck force is gone
    # hauled length(t): the winch's monotone cubic from 0 at 2 s to v at 2.5 s, then v
    t_haul = 2.5 + (haul - v * 0.25) / v
    t_off = t[np.argmax(deck <= 0.0)]
    assert deck[-1] == 0.0 and box.position[-1, 2] > box.position[0, 2] + 0.05
    assert t_off == pytest.approx(t_haul, abs=0.1)


def corners_of(a, b, half):
    """The footprint's corners in the body frame (the order of rfesim.model.bodies)."""
    return np.array([[sx * a / 2, sy * b / 2, -half] for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1))])


def deck_reference(R, r, v, w, att_p, att_R, att_v, att_w, z, corners, k, c, mu, anchor=None):
    """The deck law of rfesim.loads.deck for one body, numpy vectors: the sum over the
    footprint's corners of quarter-stiffness contacts (dynamics; statics with anchor)."""
    from rfesim.loads.deck import DECK_ONSET, DECK_SLIP_SPEED
    n = att_R[:, 2]
    P = att_p + att_R @ np.array([0.0, 0.0, z])
    F, M, Ntot = np.zeros(3), np.zeros(3), 0.0
    for ci, p in enumerate(corners):
        off = R @ p
        B = r + off
        delta = -np.dot(B - P, n)
        if delta <= 0.0:
            continue
        u = v + np.cross(w, off) - (att_v + np.cross(att_w, B - att_p))
        un = float(u @ n)
        kq, cq = k / 4, c / 4
        fe = kq * delta ** 2 / (2 * DECK_ONSET) if delta < DECK_ONSET else kq * (delta - DECK_ONSET / 2)
        N = fe - min(1.0, delta / DECK_ONSET) * cq * un
        if N <= 0.0:
            continue
        Ntot += N
        if anchor is None:
            ut = u - un * n
            f = N * n - mu * N * ut / math.sqrt(ut @ ut + DECK_SLIP_SPEED ** 2)
        else:
            s = B - (att_p + att_R @ anchor[ci])
            ft = -kq * (s - (s @ n) * n)
            if np.linalg.norm(ft) > mu * N:
                ft *= mu * N / np.linalg.norm(ft)
            f = N * n + ft
        F += f
        M += np.cross(off, f)
    return F, M, Ntot


def test_deck_kernel_equals_the_reference():
    from rfesim.kinematics import rot_zyx
    from rfesim.loads.deck import deck_forces
    rng = np.random.default_rng(4)
    nb = 40
    r = rng.normal(0, 0.3, (nb, 3)) + [0, 0, 3.0]
    R = np.stack([rot_zyx(*rng.normal(0, 0.05, 3)) for _ in range(nb)])
    v, w = rng.normal(0, 0.3, (nb, 3)), rng.normal(0, 0.2, (nb, 3))
    att_p = np.array([[0.0, 0, 0], [1.0, 2.0, 0.3]])
    att_R = np.stack([np.eye(3), rot_zyx(0.4, 0.05, -0.08)])
    att_v = np.array([[0.0, 0, 0], [0.2, -0.1, 0.4]])
    att_w = np.array([[0.0, 0, 0], [0.01, 0.03, -0.02]])
    att = rng.integers(-1, 2, nb)
    z = rng.uniform(1.5, 2.5, nb)
    corners = np.stack([corners_of(*rng.uniform(1, 4, 2), rng.uniform(0.5, 1.5)) for _ in range(nb)])
    k, c, mu = rng.uniform(1e6, 1e7, nb), rng.uniform(1e4, 1e5, nb), rng.uniform(0, 0.5, nb)
    F, M, N = np.zeros((nb, 3)), np.zeros((nb, 3)), np.zeros(nb)
    mode, anchor = np.zeros(1, np.int64), np.zeros((nb, 4, 3))               # dynamics: no anchor
    deck_forces(np.arange(nb), att.astype(np.int64), z, corners, k, c, mu, att_p, att_R, att_v, att_w, R, r, v, w, F, M,
                N, mode, anchor)
    touched = 0
    for j in range(nb):
        if att[j] < 0:
            assert N[j] == 0.0 and not F[j].any()
            continue
        a = att[j]
        Fr, Mr, Nr = deck_reference(R[j], r[j], v[j], w[j], att_p[a], att_R[a], att_v[a], att_w[a], z[j], corners[j],
                                    k[j], c[j], mu[j])
        touched += Nr > 0.0
        np.testing.assert_allclose(F[j], Fr, rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(M[j], Mr, rtol=1e-12, atol=1e-9)
        assert N[j] == pytest.approx(Nr, rel=1e-12, abs=1e-9)
    assert touched > 5                                # contacts, with and without friction slip, exercised


def test_deck_on_an_unknown_vessel_is_refused():
    data = scene([[0.0, 0.0]])
    data["bodies"]["box"]["deck"]["vessel"] = "tug"
    with pytest.raises(ScenarioError) as err:
        rfesim.simulate(data)
    assert "bodies.box.deck.vessel" in str(err.value) and "unknown vessel 'tug'" in str(err.value)


@pytest.mark.parametrize("deck, refused", [(2.05, False), (2.09, False), (2.5, True), (4.0, True)])
def test_body_started_inside_its_deck_is_refused(deck, refused):
    # the box's underside is at z = 2 m; a deck above it used to reach the statics, which the
    # contact's push (its stiffness, the weight over 5 mm, times the depth) made fail
    data = scene([[0.0, 0.0]])
    data["bodies"]["box"]["deck"]["height"] = deck
    sc = rfesim.load_scenario(data)
    if not refused:
        rfesim.api.check_model(sc)
        return
    with pytest.raises(ScenarioError) as err:
        rfesim.api.check_model(sc)
    depth = deck - 2.0
    (field, reason), = err.value.errors
    assert field == "bodies.box.position"
    assert reason.startswith(f"the body's underside starts {depth:.4g} m inside the deck of vessel 'supply' "
                             f"(bodies.box.deck.height = {deck:.6g} m in its frame)")
    assert f"({depth / 0.005:.3g} times its weight)" in reason


def test_crane_payload_inside_its_deck_names_the_template_fields():
    folder = Path(__file__).resolve().parents[2] / "scenarios"
    data = json.loads((folder / "column_crane_liftoff.json").read_text())
    data["cranes"]["crane"]["payload"]["deck"]["height"] = 4.5
    with pytest.raises(ScenarioError) as err:
        rfesim.api.check_model(rfesim.load_scenario(data, base_dir=folder))
    (field, reason), = err.value.errors
    assert field == "cranes.crane.payload.position"
    assert "(cranes.crane.payload.deck.height = 4.5 m in its frame)" in reason and "1.5 m" in reason


def test_crane_rope_that_cannot_reach_its_payload_is_refused():
    # the rope's ends are placed only when the model is built (the boom tip, the body): a
    # payload set 61 m from the tip of a 35.35 m rope used to reach the statics, which failed
    folder = Path(__file__).resolve().parents[2] / "scenarios"
    data = json.loads((folder / "column_crane_liftoff.json").read_text())
    data["cranes"]["crane"]["slewing_deg"] = 180.0
    data["cranes"]["crane"]["payload"]["position"][1] = 58.4146
    with pytest.raises(ScenarioError) as err:
        rfesim.api.check_model(rfesim.load_scenario(data, base_dir=folder))
    (field, reason), = err.value.errors
    assert field == "cranes.crane.rope.length"
    assert reason.startswith("35.35 m is shorter than the distance between its ends at the start (60.9")
    assert reason.endswith("the line would be stretched by 72.4 %")
