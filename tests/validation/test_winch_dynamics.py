"""Winches against closed forms: payout of 50 m (mass conserved, payload lowered by the
payout plus the change of elastic stretch, tension back to static), a free drum
(g_eff = m g / (m + J / r^2), with the rope on the drum in J: a cosh closed form;
in layers, energy) and a holding motor torque, constant tension within the dead
band, heave compensation (the P controller's omega / sqrt(omega^2 + kp^2), much less with
feedforward), and the shock absorber (static extra stretch T / k_sa; snap load with the
series stiffness)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.errors import SolverError

G = 9.81


def hoist(mode, L0=20.0, n=10, EA=1e8, mu=1.0, m=1000.0, duration=60.0, h=0.02, output=0.1, top="fixed",
          vessels=None, statics=True, damping=0.2, stored=200.0, **winch):
    return {
        "environment": {"gravity": G},
        "vessels": vessels or {},
        "line_types": {"rope": {"EA": EA, "EIy": 1.0, "mass_per_length": mu, "tension_only": True,
                                "damping": damping if isinstance(damping, dict) else {"axial_ratio": damping}}},
        "bodies": {"payload": {"mass": m, "radius_of_gyration": 0.5}},
        "lines": {"hoist": {"type": "rope", "length": L0, "elements": n,
                            "end_a": {"attach": top, "position": [0, 0, 0]},
                            "end_b": {"attach": "payload", "position": [0, 0, 0]}}},
        "winches": {"w": {"line": "hoist", "stored": stored, "mode": mode, **winch}},
        "analysis": {"statics": {"enabled": statics, "start": "straight"},
                     "dynamics": {"duration": duration, "output_interval": output,
                                  "integrator": {"kind": "generalized-alpha", "time_step": h, "rho_inf": 0.8}}},
    }


def stretch(L, m, mu, EA):
    """Elastic elongation (m) of a rope of unstretched length L hanging a mass m (in air)."""
    return (m * G * L + mu * G * L * L / 2.0) / EA


# ----------------------------------------------------------------------------- payout

def test_payout_of_50_m_conserves_rope_mass_and_lowers_the_payload():
    L0, m, mu, EA = 20.0, 1000.0, 1.0, 1e8
    rows = [[0, 0], [5, 1.0], [50, 1.0], [55, 0]]           # 2.5 + 45 + 2.5 = 50 m
    # explicit axial damping (c_x = 5e6 N*s / Delta): ~10 % of critical for the payload's
    # axial mode; uncorrected it would add c_x v / n = 5e6 v / L ~ 100 kN during the payout
    res = rfesim.simulate(hoist({"kind": "speed", "rows": rows}, L0=L0, m=m, mu=mu, EA=EA, duration=60.0,
                                damping={"axial": 5e6}))
    w = res.winch("w")
    body = res.body("payload")
    total = w.rope_mass_suspended + w.rope_mass_drum
    assert total[0] == pytest.approx(mu * (L0 + 200.0), rel=1e-14)
    assert np.ptp(total) < 1e-12 * total[0]
    assert w.rope_mass_suspended[-1] == pytest.approx(mu * (L0 + 50.0), rel=1e-13)
    assert w.payout[-1] == pytest.approx(50.0, abs=1e-12)
    assert w.suspended_length[-1] == pytest.approx(L0 + 50.0, abs=1e-12)
    i = int(np.argmin(np.abs(res.time - 30.0)))
    assert w.speed[i] == pytest.approx(1.0, abs=1e-12)
    # steady payout at 1 m/s: the payload moves at constant speed, the tension is static
    L = w.suspended_length[i]
    assert L == pytest.approx(L0 + 27.5, abs=1e-9)
    assert w.tension[i] == pytest.approx(m * G + mu * G * (L - L / 20), rel=2e-3)
    # lowered by the payout plus the change of the elastic stretch (5.1 mm here)
    extra = stretch(L0 + 50.0, m, mu, EA) - stretch(L0, m, mu, EA)
    assert extra > 5e-3
    drop = body.position[0, 2] - body.position[-20:, 2].mean()
    assert drop == pytest.approx(50.0 + extra, abs=5e-4)
    # tension at the first SDE (Delta/2 below the winch): static again after the payout
    Delta = (L0 + 50.0) / 10
    static = m * G + mu * G * (L0 + 50.0 - Delta / 2)
    assert w.tension[-20:].mean() == pytest.approx(static, rel=1e-3)
    assert w.tension[0] == pytest.approx(m * G + mu * G * (L0 - L0 / 20), rel=1e-6)


def test_speed_ramp_lowers_the_tension_by_all_the_hanging_mass_times_the_acceleration():
    """A payout speeding up at a = 0.2 m/s^2 lowers payload and hanging rope as one body: the
    tension at the first SDE is (m + mu (L - Delta/2)) (g - a). With the material's inertia
    (payout_inertia) to 1e-4; without it the elements near the winch, whose nodes move at
    xi a, ease the tension by only part of their weight times a (+0.28 % here)."""
    m, mu, L0, n = 1000.0, 20.0, 20.0, 10
    rows = [[0, 0], [1, 0], [6, 1.0], [60, 1.0]]

    def offset(payout_inertia):
        sc = hoist({"kind": "speed", "rows": rows}, m=m, mu=mu, L0=L0, n=n, duration=8.0, h=0.01, output=0.01,
                   damping={"axial": 5e6})
        sc["winches"]["w"]["payout_inertia"] = payout_inertia
        res = rfesim.simulate(sc)
        w, t = res.winch("w"), res.time
        ramp = (t > 2.5) & (t < 5.5)
        L = w.suspended_length[ramp]
        expected = (m + mu * (L - L / n / 2.0)) * (G - 0.2)
        return float(np.mean(w.tension[ramp] / expected - 1.0))

    assert abs(offset(True)) < 1e-4
    assert offset(False) > 2e-3


def test_payout_beyond_the_stored_rope_stops_the_run_with_results():
    """A free drum (no torque) runs away; it stops when the 5 m on the drum are out."""
    mode = {"kind": "drum", "radius": 0.5, "inertia": 100.0}
    with pytest.raises(SolverError) as info:
        rfesim.simulate(hoist(mode, stored=5.0, duration=3.0, mu=0.1, h=0.002, damping=DRUM_DAMPING))
    assert "ran out of rope" in str(info.value) and "winches.w.stored" in str(info.value)
    res = info.value.results
    assert res is not None and res.status == 1
    assert 4.0 < res.winch("w").payout.max() <= 5.0


# ----------------------------------------------------------------------------- drum

# Released at t = 0, the rope's tension falls from m g to m (g - a): undamped, the drum-rope
# mode (sqrt(k r^2 / J) ~ 112 rad/s) would overshoot into slack. Axial damping 1.5e6 N*s
# (c = 1.5e6 / L ~ critical for that mode with k = EA / L) keeps the rope taut. The staggered
# drum coupling needed h omega < 2 (sqrt(1 + zeta^2) - zeta): h = 2 ms passed, 20 ms diverged
# at 0.22 s. The drum is now balanced with the tension each step reaches (the step redone
# until it is, WinchController.correct): the same acceleration at 2 ms and at 50 ms.
DRUM_DAMPING = {"axial": 1.5e6}


def drum_mass(m, mu, L0, stored, J, r):
    """Mass (kg) a vertical hoist from a one-radius drum accelerates: the payload, all the
    rope (hanging or on the drum, both moving at the payout speed) and the drum, J / r^2."""
    return m + mu * (L0 + stored) + J / r ** 2

@pytest.mark.parametrize("h", [0.002, 0.05])
def test_free_drum_accelerates_the_payload_at_the_reduced_gravity(h):
    m, J, r = 1000.0, 100.0, 0.5
    mode = {"kind": "drum", "radius": r, "inertia": J}
    res = rfesim.simulate(hoist(mode, m=m, mu=0.05, duration=3.0, h=h, output=max(h, 0.02), damping=DRUM_DAMPING))
    assert res.counters.get("coupling_iterations", 0) > 0
    g_eff = (m + 0.05 * 20.0) * G / drum_mass(m, 0.05, 20.0, 200.0, J, r)
    t = res.time
    z = res.body("payload").position[:, 2]
    keep = t > 0.3
    a = -2.0 * np.polyfit(t[keep], z[keep], 2)[0]
    assert a == pytest.approx(g_eff, rel=0.01)
    D = res.winch("w").payout
    a_drum = 2.0 * np.polyfit(t[keep], D[keep], 2)[0]
    assert a_drum == pytest.approx(g_eff, rel=0.01)
    assert abs(a - G) > 0.2 * G          # the drum's inertia matters


def from_a_moved_static_state(doc: dict, seed: int, eps: float):
    """Results of the scenario's dynamics from its static state with the free positions moved
    by ``eps`` (m) in a seeded random direction."""
    from rfesim.api import _static_state
    from rfesim.model.compile import compile_scenario
    from rfesim.scenario import load_scenario
    from rfesim.solvers.dynamics import Counters, run_dynamics
    from rfesim.solvers.system import System
    sc = load_scenario(doc)
    system = System(compile_scenario(sc))
    state, _ = _static_state(system, sc)
    d = np.random.default_rng(seed).standard_normal(state.q.shape)
    d[:, 3:] = 0.0
    d *= system.mask
    state.q += eps * d / np.linalg.norm(d)
    _, rec, _ = run_dynamics(system, state, sc.analysis.dynamics, counters=Counters())
    return rec.results(status=0, message="", counters={})


def test_free_drum_at_50_ms_steps_is_robust_to_the_last_digits_of_the_static_state():
    """The free drum at 50 ms steps from the static state moved by 1e-10 m in random
    directions (the free coordinates): the same reduced-gravity acceleration. The first
    step ends at the rope's slack onset (the drum, released under m g, unloads the rope in
    ~20 ms), so whether its Newton converges at 50 ms turns on the last digits and the step
    is halved; the halved retry's drum predictor read the workspace of the failed attempt
    (not the state restored), paid out 230 m to 83 km in 25 ms and stopped the run (7 of
    8 directions at 1e-10 m, 2 of 8 at 1e-12 m). The predictor now uses the chord rate kept
    with the controller's state (docs/theory.md, 'Winches and rope payout')."""
    m, J, r, mu = 1000.0, 100.0, 0.5, 0.05
    g_eff = (m + mu * 20.0) * G / drum_mass(m, mu, 20.0, 200.0, J, r)
    doc = hoist({"kind": "drum", "radius": r, "inertia": J}, m=m, mu=mu, duration=3.0, h=0.05, output=0.05,
                damping=DRUM_DAMPING)
    accelerations = []
    for seed in range(4):
        res = from_a_moved_static_state(doc, seed, 1e-10)
        t, z = res.time, res.body("payload").position[:, 2]
        keep = t > 0.3
        accelerations.append(-2.0 * np.polyfit(t[keep], z[keep], 2)[0])
    assert accelerations == pytest.approx([g_eff] * 4, rel=0.01)
    assert np.ptp(accelerations) < 1e-5 * g_eff


@pytest.mark.parametrize("mode", ["held", "ramp", "drum"])
def test_light_rope_at_50_ms_steps_from_a_start_moved_by_1e_8_m(mode):
    """A 1000 kg payload on a light rope (0.05 kg/m, EA 1e8 N) at 50 ms steps, from its static
    state moved by 1e-8 m in seeded directions: the payload-rope connection (omega h about
    1.6e4) starts with large, harmless accelerations that both predictors carry over the
    step into a far iterate (the first residual 2.4e5 force scales, the upper rope turned by
    ~140 rad by the first correction); Newton failed in 5 of 6 directions held, in all 6
    with the free drum, at every halving. A halved step whose two predictor attempts fail
    now tries once more from its start state (docs/theory.md, 'Slack ropes and Newton')."""
    m, mu = 1000.0, 0.05
    winch = {"held": {"kind": "speed", "rows": [[0, 0], [100, 0]]},
             "ramp": {"kind": "speed", "rows": [[0, 0], [1, 0.5], [100, 0.5]]},
             "drum": {"kind": "drum", "radius": 0.5, "inertia": 100.0}}[mode]
    doc = hoist(winch, m=m, mu=mu, duration=2.0, h=0.05, output=0.05, damping=DRUM_DAMPING)
    for seed in range(4):
        res = from_a_moved_static_state(doc, seed, 1e-8)
        z = res.body("payload").position[:, 2]
        assert res.time[-1] == pytest.approx(2.0)
        lowered = z[0] - z[-1]
        if mode == "held":
            assert abs(lowered) < 1e-4
        elif mode == "ramp":                  # 0.25 m over the ramp, then 0.5 m/s; the stretch nearly unchanged
            assert lowered == pytest.approx(0.25 + 0.5, abs=0.02)
        else:                                 # the free drum: the reduced gravity
            g_eff = (m + mu * 20.0) * G / drum_mass(m, mu, 20.0, 200.0, 100.0, 0.5)
            assert lowered == pytest.approx(0.5 * g_eff * 2.0 ** 2, rel=0.03)


@pytest.mark.parametrize("h", [0.005, 0.05])
def test_free_drum_with_a_heavy_rope_follows_the_closed_form(h):
    """The rope on the drum turns with it: J = J_0 + mu S r^2 falls as it pays out, and the
    rope leaving at the drum's surface speed takes its angular momentum with it, so the
    whole hoist is one constant mass M = m + mu (L_0 + S) + J_0 / r^2 pulled by the hanging
    weight (m + mu (L_0 + D)) g: D(t) = (m / mu + L_0) (cosh(sqrt(mu g / M) t) - 1).
    Here the 8 t of rope on the drum outweigh payload and drum; without it (rope_inertia
    false) the drum pays out 34 m in 3 s, not 4.9 m. The hanging rope is short (2 m; a
    longer one in test_payout_inertia_of_a_heavy_hanging_rope_converges_with_the_elements)."""
    m, mu, L0, stored, J, r = 1000.0, 20.0, 2.0, 400.0, 100.0, 0.5
    M = drum_mass(m, mu, L0, stored, J, r)
    t_end = 3.0

    def run(rope_inertia, h):
        mode = {"kind": "drum", "radius": r, "inertia": J, "rope_inertia": rope_inertia}
        return rfesim.simulate(hoist(mode, m=m, mu=mu, L0=L0, stored=stored, EA=1e9, duration=t_end, h=h,
                                     output=0.05, damping={"axial": 1.5e7}))

    res = run(True, h)
    t, D = res.time, res.winch("w").payout
    exact = (m / mu + L0) * (np.cosh(np.sqrt(mu * G / M) * t) - 1.0)
    assert exact[-1] > 4.5
    assert np.abs(D - exact).max() < 4e-3 * exact[-1]
    v = res.winch("w").speed[-1]
    assert v == pytest.approx((m / mu + L0) * np.sqrt(mu * G / M) * np.sinh(np.sqrt(mu * G / M) * t_end),
                              rel=4e-3)
    bare = run(False, 0.005).winch("w").payout[-1]
    assert bare > 3.0 * D[-1]


def test_payout_inertia_of_a_heavy_hanging_rope_converges_with_the_elements():
    """The same closed form with 20 m (400 kg) of rope hanging: the elements' nodes move at
    xi dD/dt while the rope's material runs at dD/dt, and the follower loads
    -m_i (1 - xi_i) d2D/dt2 (payout_inertia) give the material's inertia back. With them the
    payout after 3 s converges to the closed form at first order in the element length (the
    pinned top element's weight bears on the sheave, not on the rope's first SDE); without
    them it converges to a payout more than 3 % too far."""
    m, mu, L0, stored, J, r = 1000.0, 20.0, 20.0, 200.0, 100.0, 0.5
    M = drum_mass(m, mu, L0, stored, J, r)
    exact = (m / mu + L0) * (math.cosh(math.sqrt(mu * G / M) * 3.0) - 1.0)

    def error(n, payout_inertia=True):
        sc = hoist({"kind": "drum", "radius": r, "inertia": J}, m=m, mu=mu, L0=L0, n=n, stored=stored, EA=1e9,
                   duration=3.0, h=0.01, output=0.05, damping={"axial": 1.5e7})
        sc["winches"]["w"]["payout_inertia"] = payout_inertia
        return rfesim.simulate(sc).winch("w").payout[-1] / exact - 1.0

    e10, e20, e40 = error(10), error(20), error(40)
    assert -0.015 < e10 < e20 < e40 < 0.0
    assert abs(e40) < 4e-3
    assert 1.7 < e10 / e20 < 2.3 and 1.7 < e20 / e40 < 2.3
    assert error(40, payout_inertia=False) > 0.03


def test_drum_rope_inertia_integrates_r_squared_over_the_layers():
    """mu * integral of r(l)^2 dl: mu r^2 L on one radius; in layers the closed form equals
    the quadrature of drum_radius^2 over the rope on the drum."""
    from rfesim.scenario.winches import DrumLayers, drum_radius, drum_rope_inertia
    lay = DrumLayers(**LAYERS)
    assert drum_rope_inertia(0.5, None, 200.0, 20.0) == pytest.approx(20.0 * 0.25 * 200.0, rel=1e-15)
    l = np.linspace(0.0, 60.0, 60001)
    r2 = np.array([drum_radius(R1, lay, x) ** 2 for x in l])
    quad = 20.0 * float(np.sum(0.5 * (r2[1:] + r2[:-1]) * np.diff(l)))
    assert drum_rope_inertia(R1, lay, 60.0, 20.0) == pytest.approx(quad, rel=1e-10)
    assert drum_rope_inertia(R1, lay, -1.0, 20.0) == 0.0


def test_motor_torque_r_times_static_tension_holds_the_payload():
    m, mu, L0, r = 1000.0, 0.05, 20.0, 0.5
    T0 = m * G + mu * G * (L0 - L0 / 20)        # first SDE: Delta/2 below the winch
    mode = {"kind": "drum", "radius": r, "inertia": 100.0, "torque": [[0.0, r * T0]]}
    res = rfesim.simulate(hoist(mode, m=m, mu=mu, L0=L0, duration=3.0, h=0.01))
    w = res.winch("w")
    assert w.tension[0] == pytest.approx(T0, rel=1e-9)
    assert np.abs(w.payout).max() < 1e-4
    z = res.body("payload").position[:, 2]
    assert np.ptp(z) < 1e-4



# ----------------------------------------------------------------------------- layered drum

LAYERS = {"width": 0.2, "rope_diameter": 0.05}      # 4 turns a layer
R1 = 0.3                                            # first layer's turn centres


def test_layered_drum_radius_lies_between_the_layers_turn_centres():
    """r = sqrt(r_1^2 + L d^2 / (pi w)): r_1 on an empty drum; with k full layers on it
    (L_k = sum over the layers of (w / d) 2 pi (r_1 + (i - 1) d)) between the k-th and the
    (k + 1)-th layer's turn centres, where a real drum's radius jumps at the crossover."""
    from rfesim.scenario.winches import DrumLayers, drum_radius
    lay = DrumLayers(**LAYERS)
    d, w = LAYERS["rope_diameter"], LAYERS["width"]
    assert drum_radius(R1, lay, 0.0) == R1 and drum_radius(R1, None, 50.0) == R1
    for k in range(1, 8):
        full = sum(w / d * 2.0 * math.pi * (R1 + (i - 1) * d) for i in range(1, k + 1))
        r = drum_radius(R1, lay, full)
        assert R1 + (k - 1) * d < r < R1 + k * d
    assert drum_radius(R1, lay, 60.0) ** 2 == pytest.approx(R1 ** 2 + 60.0 * d * d / (math.pi * w), rel=1e-14)


def test_motor_torque_holds_the_payload_at_the_layered_radius():
    """60 m on the drum put the rope at r = 0.573 m, not the first layer's 0.3 m: the torque
    r T0 holds the payload; R1 T0 (the bare drum's) lets the drum pay out."""
    from rfesim.scenario.winches import DrumLayers, drum_radius
    m, mu, L0, stored = 1000.0, 0.05, 20.0, 60.0
    T0 = m * G + mu * G * (L0 - L0 / 20)
    r = drum_radius(R1, DrumLayers(**LAYERS), stored)
    assert r > 1.8 * R1
    for torque, held in ((r * T0, True), (R1 * T0, False)):
        mode = {"kind": "drum", "radius": R1, "layers": LAYERS, "inertia": 100.0, "torque": [[0.0, torque]]}
        res = rfesim.simulate(hoist(mode, m=m, mu=mu, L0=L0, duration=3.0, h=0.01, stored=stored))
        w = res.winch("w")
        assert w.drum_radius[0] == pytest.approx(r, rel=1e-12)
        if held:
            assert np.abs(w.payout).max() < 1e-4
        else:
            assert w.payout[-1] > 1.0


@pytest.mark.parametrize("h", [0.002, 0.02])
def test_free_layered_drum_conserves_energy_as_its_radius_shrinks(h):
    """A free drum (no torque) with 60 m in layers lets a 1 t payload fall 34 m in 3 s: the
    radius shrinks from 0.573 to about 0.44 m, and with omega = v / r the potential energy
    lost by payload and hanging rope, m g z + mu g (L^2 - L_0^2) / 2, is the kinetic energy
    of payload, hanging rope and drum with its rope, (m + mu L) v^2 / 2 + (J_0 + J_rope)
    omega^2 / 2, to 0.5 %; with the drum's radius and inertia at the start the balance
    misses by more than 10 %. The drum's payout speed is omega r: the payload's. The rope is
    light (0.05 kg/m): a payout stretches the hanging rope's elements, whose kinetic energy
    is then not the rigid mu L v^2 / 2 (docs/theory.md); the heavy rope's inertia on the
    drum is checked in test_free_drum_with_a_heavy_rope_follows_the_closed_form."""
    from rfesim.scenario.winches import DrumLayers, drum_rope_inertia
    m, J, mu, stored, L0 = 1000.0, 100.0, 0.05, 60.0, 20.0
    mode = {"kind": "drum", "radius": R1, "layers": LAYERS, "inertia": J}
    res = rfesim.simulate(hoist(mode, m=m, mu=mu, L0=L0, duration=3.0, h=h, output=0.02, damping=DRUM_DAMPING,
                                stored=stored))
    w = res.winch("w")
    z = res.body("payload").position[:, 2]
    vz = res.body("payload").velocity[:, 2]
    r = w.drum_radius
    assert r[0] > 0.57 and r[-1] < 0.46
    drop = z[0] - z[-1]
    assert drop > 30.0
    v = w.speed[-1]
    assert v == pytest.approx(-vz[-1], rel=5e-3)
    L = w.suspended_length[-1]
    lay = DrumLayers(**LAYERS)
    J_end = J + drum_rope_inertia(R1, lay, stored - w.payout[-1], mu)
    J_start = J + drum_rope_inertia(R1, lay, stored, mu)
    assert J_end < J_start
    released = m * G * drop + mu * G * (L * L - L0 * L0) / 2.0
    hanging = 0.5 * (m + mu * L) * vz[-1] ** 2
    assert hanging + 0.5 * J_end * (v / r[-1]) ** 2 == pytest.approx(released, rel=5e-3)
    assert abs(hanging + 0.5 * J_start * (v / r[0]) ** 2 - released) > 0.1 * released


@pytest.mark.parametrize("h", [0.002, 0.05])
def test_a_brake_that_renders_pays_out_at_the_net_force(h):
    """A brake torque of 0.6 r m g under a 1 t load: the drum renders and pays out at
    (m g - F_b) / (m + J / r^2) (1 %), the same at 50 ms as at 2 ms steps. The staggered
    drum update paid out 74 km by 1 s at 10 ms steps and diverged at 50 ms."""
    m, J, r = 1000.0, 100.0, 0.5
    Fb = 0.6 * m * G
    mode = {"kind": "drum", "radius": r, "inertia": J, "brake_torque": Fb * r}
    res = rfesim.simulate(hoist(mode, m=m, mu=0.05, duration=3.0, h=h, output=max(h, 0.02), damping=DRUM_DAMPING))
    t = res.time
    keep = t > 0.3
    a = 2.0 * np.polyfit(t[keep], res.winch("w").payout[keep], 2)[0]
    assert a == pytest.approx(((m + 0.05 * 20.0) * G - Fb) / drum_mass(m, 0.05, 20.0, 200.0, J, r), rel=0.01)


def test_brake_holds_the_drum():
    m, r = 1000.0, 0.5
    mode = {"kind": "drum", "radius": r, "inertia": 100.0, "brake_torque": 1.2 * r * m * G}
    res = rfesim.simulate(hoist(mode, m=m, mu=0.05, duration=2.0, h=0.01))
    assert np.abs(res.winch("w").payout).max() == 0.0


# ----------------------------------------------------------------------------- constant tension

@pytest.mark.parametrize("h", [0.01, 0.5])
def test_constant_tension_holds_the_set_tension_within_the_dead_band(h):
    """A rope from a fixed sheave down to a point heaving 0.5 m (period 20 s): held at its
    ends it would see k * 0.5 m = 5 kN of tension variation; the winch keeps it within the
    band plus gain times the largest speed it must follow (78.5 N). At 0.5 s steps k h / gain
    is 10: the staggered rule (speed from the tension at t_n) needed it below 2; the winch now
    meets its characteristic at t_{n+1} (WinchController.correct)."""
    EA, L0 = 2e5, 20.0
    k = EA / L0
    set_t, band, gain = 5000.0, 200.0, 500.0
    u_max = 0.5 * 2 * math.pi / 20.0
    sc = hoist({"kind": "tension", "tension": set_t, "dead_band": band, "gain": gain, "max_speed": 2.0},
               L0=L0, EA=EA, m=10.0, mu=0.1, duration=100.0, h=h, output=max(h, 0.1), damping=0.5)
    sc.pop("bodies")
    sc["vessels"] = {"tug": {"position": [0, 0, -L0 - 0.3], "motion": {"kind": "harmonic", "heave": {
        "amplitude": 0.5, "period": 20.0}, "ramp_duration": 10.0}}}
    sc["lines"]["hoist"]["end_b"] = {"attach": "tug", "position": [0, 0, 0]}
    res = rfesim.simulate(sc)
    T = res.winch("w").tension
    t = res.time
    assert T[0] == pytest.approx(k * 0.3, rel=0.02)          # starts 2 kN below the band
    steady = t > 40.0
    dev = np.abs(T[steady] - set_t)
    assert dev.max() < band + 1.1 * gain * u_max + 20.0
    assert np.ptp(res.winch("w").payout[steady]) > 0.8        # it follows the 1 m heave range


# ----------------------------------------------------------------------------- heave compensation

def heave_ratio(hc, Tp=8.0, duration=56.0):
    ship = {"ship": {"motion": {"kind": "harmonic", "heave": {"amplitude": 1.0, "period": Tp},
                                "ramp_duration": 8.0}}}
    res = rfesim.simulate(hoist({"kind": "speed", "rows": [[0, 0]]}, L0=10.0, n=5, EA=1e9, mu=0.5, m=1000.0,
                                duration=duration, h=0.01, output=0.05, top="ship", vessels=ship,
                                heave_compensation=hc))
    t = res.time
    keep = t > duration - 4 * Tp
    w = 2 * math.pi / Tp
    basis = np.column_stack([np.sin(w * t[keep]), np.cos(w * t[keep]), np.ones(keep.sum())])

    def amplitude(x):
        c = np.linalg.lstsq(basis, x[keep], rcond=None)[0]
        return math.hypot(c[0], c[1])

    tip = res.vessel("ship").position[:, 2]
    payload = res.body("payload").position[:, 2]
    return amplitude(payload) / amplitude(tip), w


@pytest.mark.parametrize("kp", [0.5, 1.5])
def test_heave_compensation_p_controller_reduces_motion_by_its_transfer_factor(kp):
    ratio, w = heave_ratio({"kp": kp})
    assert ratio == pytest.approx(w / math.hypot(w, kp), rel=0.03)


def test_heave_compensation_with_feedforward_is_much_better():
    ratio, w = heave_ratio({"kp": 0.5, "feedforward": True})
    assert ratio < 0.1 * w / math.hypot(w, 0.5)


# ----------------------------------------------------------------------------- shock absorber

def test_shock_absorber_static_extra_stretch():
    k_sa = 2e5
    base = hoist({"kind": "speed", "rows": [[0, 0]]}, mu=0.5)
    base["analysis"]["dynamics"]["enabled"] = False
    soft = hoist({"kind": "speed", "rows": [[0, 0]]}, mu=0.5, shock_absorber={"stiffness": k_sa, "damping": 1e4})
    soft["analysis"]["dynamics"]["enabled"] = False
    a = rfesim.statics(base)
    b = rfesim.statics(soft)
    T = b.winch("w").tension[0]
    assert T == pytest.approx(a.winch("w").tension[0], rel=1e-9)
    extra = a.body("payload").position[0, 2] - b.body("payload").position[0, 2]
    assert extra == pytest.approx(T / k_sa, rel=1e-4)


def test_snap_load_with_shock_absorber_uses_the_series_stiffness():
    """C1 (test_bodies.snap_scenario) with an absorber as stiff as the rope: k_eq = k / 2,
    peak mg + sqrt((mg)^2 + k_eq m v^2) = 462 kN instead of 603 kN."""
    m, k, L, drop = 1.0e4, 2.5e6, 10.0, 0.5
    sc = hoist({"kind": "speed", "rows": [[0, 0]]}, L0=L, n=10, EA=k * L, mu=0.1, m=m, duration=0.6, h=0.002,
               output=0.002, statics=False, shock_absorber={"stiffness": k, "damping": 0.0})
    sc["bodies"]["payload"]["position"] = [0.0, 0.0, -(L - drop)]
    sc["bodies"]["payload"]["radius_of_gyration"] = 1.0
    sc["analysis"]["dynamics"]["integrator"].update(rho_inf=0.9, max_iterations=30)
    res = rfesim.simulate(sc)
    k_eq = 1.0 / (1.0 / k + 1.0 / k)
    v = math.sqrt(2.0 * G * drop)
    peak = m * G + math.sqrt((m * G) ** 2 + k_eq * m * v * v)
    assert peak == pytest.approx(461.8e3, rel=1e-3)
    assert res.body("payload").connection_tension.max() == pytest.approx(peak, rel=0.015)
    assert res.winch("w").tension.max() == pytest.approx(peak, rel=0.015)


def test_winch_results_reach_the_netcdf_file(tmp_path):
    import h5py
    sc = hoist({"kind": "speed", "rows": [[0, 0], [1, 0.5]]}, duration=2.0, output=0.5)
    res = rfesim.simulate(sc)
    path = tmp_path / "w.nc"
    res.to_netcdf(path)
    back = rfesim.open_results(path)
    for ch in ("payout", "speed", "tension", "suspended_length", "rope_mass_suspended", "rope_mass_drum",
               "drum_radius"):
        np.testing.assert_array_equal(getattr(back.winch("w"), ch), getattr(res.winch("w"), ch))
    assert np.all(np.isnan(res.winch("w").drum_radius))       # a speed-mode winch has no drum radius
    with h5py.File(path, "r") as f:
        g = f["winches/w"]
        assert g["payout"].attrs["units"] in ("m", b"m")
        assert g["rope_mass_drum"].attrs["units"] in ("kg", b"kg")
        assert g.attrs["line"] in ("hoist", b"hoist")
    assert res.winch("w").payout[-1] == pytest.approx(0.25 + 0.5, abs=1e-12)
