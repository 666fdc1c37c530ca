"""Payloads on ropes: VALIDATION.md C1 (snap load) and C2 (parametric resonance under tip
heave), the static hanging payload, the splash zone, energy of an undamped payload
pendulum, and the body results in the netCDF file."""
from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

import rfesim
from rfesim.loads.sde import sde_elastic_energy
from rfesim.model.compile import compile_scenario
from rfesim.solvers.dynamics import run_dynamics
from rfesim.solvers.system import System

G, RHO = 9.81, 1025.0


# ----------------------------------------------------------------------------- C1 snap load

def snap_scenario(elements: int) -> dict:
    """A 10 t payload on a 10 m tension-only rope of stiffness k = EA / L = 2.5e6 N/m,
    released at rest 0.5 m above the taut position (the rope slack, straight)."""
    m, k, L, drop = 1.0e4, 2.5e6, 10.0, 0.5
    return {
        "environment": {"gravity": G},
        # a light rope (0.01 % of the payload); axial damping of its element modes (2 zeta
        # sqrt(k m) per element) leaves the payload's own mode with a damping ratio ~ 1e-4
        "line_types": {"rope": {"EA": k * L, "EIy": 1.0, "mass_per_length": 0.1, "tension_only": True,
                                "damping": {"axial_ratio": 0.2}}},
        "bodies": {"payload": {"mass": m, "radius_of_gyration": 1.0, "position": [0.0, 0.0, -(L - drop)]}},
        "lines": {"hoist": {"type": "rope", "length": L, "elements": elements,
                            "end_a": {"attach": "fixed", "position": [0, 0, 0]},
                            "end_b": {"attach": "payload", "position": [0, 0, 0]}}},
        "analysis": {"statics": {"enabled": False, "start": "straight"},
                     "dynamics": {"duration": 0.5, "output_interval": 0.002,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.002, "rho_inf": 0.9,
                                                 "max_iterations": 30}}},
    }


@pytest.mark.parametrize("elements", [1, 10])
def test_c1_snap_load(elements):
    """Peak tension mg + sqrt((mg)^2 + k m v^2) = 603 kN, v = sqrt(2 g 0.5); 1 %. The rope
    pushes nothing while slack, and its top carries the same peak."""
    m, k = 1.0e4, 2.5e6
    res = rfesim.simulate(snap_scenario(elements))
    body = res.body("payload")
    v = math.sqrt(2.0 * G * 0.5)
    peak_ref = m * G + math.sqrt((m * G) ** 2 + k * m * v * v)
    assert peak_ref == pytest.approx(603e3, rel=1e-3)
    tension = body.connection_tension
    assert tension.max() == pytest.approx(peak_ref, rel=0.01)
    top = -res.line("hoist").end_a_force[:, 2]
    assert top.max() == pytest.approx(peak_ref, rel=0.01)
    # free fall while slack: no force on the body before it reaches the taut length
    t_taut = math.sqrt(2.0 * 0.5 / G)
    before = res.time < 0.9 * t_taut
    assert np.abs(tension[before]).max() < 1e-3 * m * G
    np.testing.assert_allclose(body.position[before, 2], -9.5 - 0.5 * G * res.time[before] ** 2, atol=1e-3)
    # the peak stretch: T / k below the taut position
    j = int(np.argmax(tension))
    assert -10.0 - body.position[j, 2] == pytest.approx(tension[j] / k, rel=0.02)


# ----------------------------------------------------------------------------- C2 parametric resonance

L_ROPE = 20.0
OMEGA0 = math.sqrt(G / L_ROPE)


def pendulum_on_heaving_tip(ratio: float, duration: float = 150.0) -> dict:
    """A 1 t payload on a 20 m rope hanging from a crane tip that heaves 1 m at
    Omega = ratio * omega0 (a 1 cm surge at the same frequency seeds the swing)."""
    period = 2.0 * math.pi / (ratio * OMEGA0)
    return {
        "environment": {"gravity": G},
        "vessels": {"tip": {"motion": {"kind": "harmonic", "heave": {"amplitude": 1.0, "period": period},
                                       "surge": {"amplitude": 0.01, "period": period}, "ramp_duration": 10.0}}},
        "line_types": {"rope": {"EA": 1e9, "EIy": 1.0, "mass_per_length": 0.2, "tension_only": True}},
        "bodies": {"payload": {"mass": 1000.0, "radius_of_gyration": 0.5}},
        "lines": {"hoist": {"type": "rope", "length": L_ROPE, "elements": 10,
                            "end_a": {"attach": "tip", "position": [0, 0, 0]},
                            "end_b": {"attach": "payload", "position": [0, 0, 0]}}},
        "analysis": {"statics": {"enabled": True},
                     "dynamics": {"duration": duration, "output_interval": 0.1,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.02, "rho_inf": 0.8}}},
    }


def swing_growth(ratio: float) -> float:
    res = rfesim.simulate(pendulum_on_heaving_tip(ratio))
    x = res.body("payload").position[:, 0]
    t = res.time
    return float(np.abs(x[t > 120.0]).max() / np.abs(x[(t > 10.0) & (t < 40.0)]).max())


def test_c2_band_edges_from_mathieu():
    """The band quoted in VALIDATION.md is the first Mathieu tongue with eps = 4 a / L:
    delta = 4 / (Omega/omega0)^2 = 1 -+ eps/2 - eps^2/32 (to second order)."""
    eps = 4.0 * 1.0 / L_ROPE
    lo, hi = 2.0 / math.sqrt(1.0 + eps / 2 - eps ** 2 / 32), 2.0 / math.sqrt(1.0 - eps / 2 - eps ** 2 / 32)
    assert lo == pytest.approx(1.9081, abs=2e-3)
    assert hi == pytest.approx(2.1096, abs=2e-3)


@pytest.mark.parametrize("ratio, grows", [(1.7, False), (2.0, True), (2.3, False)])
def test_c2_parametric_resonance(ratio, grows):
    """Inside the band the swing grows (~ e^(0.05 omega0 t) at 2.0: x30 over 110 s); outside it stays put."""
    growth = swing_growth(ratio)
    if grows:
        assert growth > 10.0
    else:
        assert growth < 1.5


@pytest.mark.slow
@pytest.mark.parametrize("ratio, grows", [(1.88, False), (1.93, True), (2.08, True), (2.14, False)])
def test_c2_band_edges(ratio, grows):
    """Just inside and just outside both edges of [1.9081, 2.1096]."""
    growth = swing_growth(ratio)
    if grows:
        assert growth > 3.0
    else:
        assert growth < 1.5


# ----------------------------------------------------------------------------- statics and splash zone

def hanging(top_z: float, volume: float = 2.0, height: float = 2.0, cob=(0.0, 0.0, 0.0)) -> dict:
    return {
        "environment": {"gravity": G, "water": {"density": RHO, "depth": 200.0}},
        "line_types": {"rope": {"EA": 1e9, "EIy": 10.0, "mass_per_length": 1.0, "tension_only": True}},
        "bodies": {"payload": {"mass": 1e4, "inertia": [1e4, 1.2e4, 1.4e4], "volume": volume, "height": height,
                               "centre_of_buoyancy": list(cob)}},
        "lines": {"hoist": {"type": "rope", "length": 20.0, "elements": 10,
                            "end_a": {"attach": "fixed", "position": [0, 0, top_z]},
                            "end_b": {"attach": "payload", "position": [0, 0, 1.0]}}},
        "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}},
    }


def test_static_hanging_payload_tension_is_submerged_weight(tmp_path):
    """Rope tension at the body (m - rho V) g; at the top plus the rope's weight. The
    results go to /bodies/payload in the netCDF file and read back."""
    st = rfesim.statics(hanging(top_z=5.0))
    body = st.body("payload")
    submerged_weight = (1e4 - RHO * 2.0) * G
    assert body.connection_tension[0] == pytest.approx(submerged_weight, rel=1e-9)
    assert body.submerged_fraction[0] == 1.0
    assert body.buoyancy[0] == pytest.approx(RHO * G * 2.0, rel=1e-12)
    line = st.line("hoist")
    assert line.end_b_force[0, 2] == pytest.approx(submerged_weight, rel=1e-9)
    assert -line.end_a_force[0, 2] == pytest.approx(submerged_weight + 20.0 * G, rel=1e-9)
    # hangs straight: 5 - 20 (1 + strain) - 1 below the top
    assert body.position[0, 2] == pytest.approx(5.0 - 20.0 - 1.0, abs=2e-3)
    path = tmp_path / "payload.nc"
    st.to_netcdf(path)
    back = rfesim.open_results(path)
    np.testing.assert_array_equal(back.body("payload").position, body.position)
    np.testing.assert_array_equal(back.body("payload").connection_force, body.connection_force)
    with h5py.File(path, "r") as f:
        g = f["bodies/payload"]
        assert g["position"].attrs["units"] in ("m", b"m")
        assert g["connection_tension"].attrs["units"] in ("N", b"N")
        assert g["rotation"].shape == (1, 3)


@pytest.mark.parametrize("cob_z", [0.0, 0.4])
def test_splash_zone_buoyancy_rises_over_the_height(cob_z):
    """Lowered through the surface (statics at five depths), the rope tension falls by the
    buoyancy rho g V f, f the submerged fraction of the 2 m extent centred on the centre of
    buoyancy: 0 above, 1 below, linear between."""
    weight = 1e4 * G
    fractions = []
    for target in (1.5, 0.5, 0.0, -0.5, -1.5):         # centre of buoyancy z
        top_z = target - cob_z + 21.0                    # rope 20 m, attachment 1 m above the centre
        st = rfesim.statics(hanging(top_z, cob=(0.0, 0.0, cob_z)))
        body = st.body("payload")
        z_cob = body.position[0, 2] + cob_z
        f = min(max((0.0 - (z_cob - 1.0)) / 2.0, 0.0), 1.0)
        fractions.append(f)
        assert body.submerged_fraction[0] == pytest.approx(f, abs=1e-12)
        assert body.connection_tension[0] == pytest.approx(weight - RHO * G * 2.0 * f, rel=1e-9)
    assert fractions[0] == 0.0 and fractions[-1] == 1.0
    np.testing.assert_allclose(fractions[1:4], [0.25, 0.5, 0.75], atol=2e-3)


# ----------------------------------------------------------------------------- energy

def total_energy(system: System, state) -> tuple[float, float]:
    system.evaluate(state)
    ws, km = system.ws, system.km
    kinetic = 0.5 * np.sum(km.rfe_mass * np.sum(ws.v ** 2, axis=1)) + 0.5 * np.sum(km.rfe_inertia * ws.wb ** 2)
    potential = G * np.sum(km.rfe_mass * ws.r[:, 2]) + sde_elastic_energy(km.sde_stiffness, ws.eps)
    return kinetic + potential, kinetic


def test_undamped_payload_pendulum_conserves_energy():
    """Released 37 deg from the vertical, a payload on a 5 m rope (pinned at its top, body
    attached 0.5 m above its centre so it also rocks) keeps its total energy (kinetic of
    every RFE and the body, gravity, SDE strain energy) to 1e-6 of m g x 1 m over 3 s."""
    sc = rfesim.Scenario.model_validate({
        "environment": {"gravity": G},
        "line_types": {"rope": {"EA": 1e8, "EIy": 1.0, "mass_per_length": 1.0}},
        "bodies": {"payload": {"mass": 500.0, "inertia": [40.0, 50.0, 60.0], "position": [3.0, 0.0, -4.5]}},
        "lines": {"hoist": {"type": "rope", "length": 5.0, "elements": 5, "shear_stiffness": "kruszewski",
                            "end_a": {"attach": "fixed", "position": [0, 0, 0]},
                            "end_b": {"attach": "payload", "position": [0, 0, 0.5]}}},
        "analysis": {"statics": {"enabled": False},
                     "dynamics": {"duration": 3.0, "output_interval": 0.5,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 1e-3, "rho_inf": 1.0,
                                                 "tolerance": 1e-10}}}})
    model = compile_scenario(sc)
    system = System(model)
    e0, _ = total_energy(system, model.initial)
    state, rec, _ = run_dynamics(system, model.initial, sc.analysis.dynamics)
    e1, kinetic = total_energy(system, state)
    x = rec.results().body("payload").position[:, 0]
    assert x.min() < -2.0 and kinetic > 1000.0           # it swung through and is moving
    assert abs(e1 - e0) < 1e-6 * 500.0 * G
