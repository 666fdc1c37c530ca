"""Stokes 5th-order regular waves (rfesim.sea.stokes5, Fenton 1985).

References: the output of Fenton's own program ("Solution by 5-order Stokes theory",
repository ChiaCheng-Tsai/FentonStokesClass, files Solution(Stokes5).res and
Solution(Stokes).res) for L/d = 8, zero Eulerian current, g = d = 1:
H/d = 0.30: T sqrt(g/d) = 8.5184, c = 0.9391, k eta harmonics E_j and potential
coefficients B_j below; H/d = 0.45: T sqrt(g/d) = 8.2861, c = 0.9655.
"""
import math

import numpy as np
import pytest

from rfesim.errors import ScenarioError
from rfesim.scenario.load import load_scenario as load_scenario_dict
from rfesim.sea import stokes5 as s5
from rfesim.sea.kernel import sea_kinematics_into, sea_spec
from rfesim.sea.waves import wave_number

FENTON = {
    0.30: dict(T=8.5184, c=0.9391,
               B=[1.3411476e-01, 1.5378594e-02, 1.4247651e-03, 3.5681394e-05, -2.3287527e-05],
               E=[1.1085623e-01, 2.7030818e-02, 6.3316832e-03, 2.1243859e-03, 6.2180771e-04]),
    0.45: dict(T=8.2861, c=0.9655,
               B=[1.8676141e-01, 2.5616893e-02, 3.3736942e-03, 1.8063706e-04, -1.7683966e-04],
               E=[1.5718425e-01, 4.7920523e-02, 1.4808480e-02, 1.0754704e-02, 4.7218523e-03]),
}


@pytest.mark.parametrize("H", [0.30, 0.45])
def test_against_fentons_program(H):
    ref = FENTON[H]
    w = s5.stokes5(H, ref["T"], 1.0, 1.0)
    k = w.wavenumber
    # the period is given to 5 digits: the wavelength comes back to ~1e-5
    assert w.wavelength == pytest.approx(8.0, rel=2e-5)
    assert w.celerity == pytest.approx(ref["c"], abs=6e-5)
    E = w.elevation * k
    B = [w.velocity[j] / ((j + 1) * math.sqrt(1.0 / k) * math.tanh((j + 1) * k)) for j in range(5)]
    for j in range(5):
        assert E[j] == pytest.approx(ref["E"][j], rel=2e-4, abs=2e-8)
        assert B[j] == pytest.approx(ref["B"][j], rel=2e-3, abs=2e-8)


def test_crest_to_trough_is_the_height():
    w = s5.stokes5(6.0, 10.0, 60.0)
    assert s5.elevation(w, 0.0) - s5.elevation(w, math.pi) == pytest.approx(6.0, rel=1e-13)
    assert s5.elevation(w, 0.0) > 3.0 > -s5.elevation(w, math.pi)       # sharper crests, flatter troughs


def test_small_waves_are_airy():
    H, T, d = 1e-3, 9.0, 50.0
    w = s5.stokes5(H, T, d)
    k = float(wave_number(2 * math.pi / T, d))
    assert w.wavenumber == pytest.approx(k, rel=1e-8)
    assert w.elevation[0] == pytest.approx(H / 2, rel=1e-6)
    assert w.velocity[0] == pytest.approx(H / 2 * 2 * math.pi / T, rel=1e-6)
    assert np.all(np.abs(w.elevation[1:]) < 1e-5 * H)


def _surface_residuals(H, T, d, g=9.81):
    """Max deviations of Bernoulli's constant and of the kinematic condition along the surface,
    in the frame moving with the wave (steady flow): both vanish for the exact wave."""
    w = s5.stokes5(H, T, d, g)
    th = np.linspace(0.0, 2 * math.pi, 721)
    eta = s5.elevation(w, th)
    u, v = s5.velocity(w, th, eta)
    c = w.celerity
    bern = 0.5 * ((u - c) ** 2 + v ** 2) + g * eta
    # x = -theta/k at t = 0: d eta/dx = -k d eta/dtheta
    deta_dx = -w.wavenumber * sum(-(j + 1) * w.elevation[j] * np.sin((j + 1) * th) for j in range(5))
    kin = v - (u - c) * deta_dx
    return (bern.max() - bern.min()) * w.wavenumber / g, np.abs(kin).max() / c


@pytest.mark.parametrize("depth", [30.0, math.inf])
def test_free_surface_conditions_hold_to_sixth_order(depth):
    """Halving the steepness divides both residuals by about 2^6 (a wrong coefficient in any
    order below 6 would show as a lower order)."""
    T = 10.0
    k = float(wave_number(2 * math.pi / T, None if math.isinf(depth) else depth))
    H1 = 0.12 * 2 * math.pi / k * math.tanh(min(k * depth, 50.0)) / 2    # about 0.42 of breaking
    r1 = _surface_residuals(H1, T, depth)
    r2 = _surface_residuals(H1 / 2, T, depth)
    for a, b in zip(r1, r2):
        assert a < 1e-3
        order = math.log2(a / b)
        assert order > 5.7, order


def test_deep_water_limit_without_overflow():
    deep = s5.stokes5(8.0, 12.0, None)
    very = s5.stokes5(8.0, 12.0, 5000.0)
    assert np.all(np.isfinite(deep.velocity))
    assert very.wavenumber == pytest.approx(deep.wavenumber, rel=1e-12)
    assert np.allclose(very.velocity, deep.velocity, rtol=1e-9, atol=1e-12)


def _env(waves, depth=40.0):
    return {"environment": {"water": {"depth": depth, "waves": waves}},
            "line_types": {"p": {"outer_diameter": 0.3, "wall_thickness": 0.02, "youngs_modulus": 2e11,
                                 "density": 7850.0}},
            "lines": {"l": {"type": "p", "length": 10.0, "elements": 4,
                            "end_a": {"attach": "fixed", "position": [0, 0, -5]},
                            "end_b": {"attach": "free", "position": [10, 0, -5]}}}}


def test_kernel_carries_the_five_harmonics():
    sc = load_scenario_dict(_env({"kind": "stokes5", "height": 5.0, "period": 9.0, "direction_deg": 30.0,
                                  "phase_deg": 20.0}))
    spec = sea_spec(sc.environment)
    w = s5.stokes5(5.0, 9.0, 40.0)
    rng = np.random.default_rng(3)
    pts = np.column_stack([rng.uniform(-50, 50, 40), rng.uniform(-50, 50, 40), rng.uniform(-40, -0.5, 40)])
    eta, vel, acc = np.zeros(40), np.zeros((40, 3)), np.zeros((40, 3))
    t = 2.7
    sea_kinematics_into(spec, t, pts, eta, vel, acc)
    b = math.radians(30.0)
    th = w.omega * t - w.wavenumber * (pts[:, 0] * math.cos(b) + pts[:, 1] * math.sin(b)) + math.radians(20.0)
    assert np.allclose(eta, s5.elevation(w, th), rtol=0, atol=1e-12)
    u, v = s5.velocity(w, th, pts[:, 2])
    assert np.allclose(vel[:, 0], u * math.cos(b), atol=1e-12)
    assert np.allclose(vel[:, 1], u * math.sin(b), atol=1e-12)
    assert np.allclose(vel[:, 2], v, atol=1e-12)
    # acceleration: the time derivative at a fixed point
    h = 1e-5
    e2, v2, a2 = np.zeros(40), np.zeros((40, 3)), np.zeros((40, 3))
    e1, v1, a1 = np.zeros(40), np.zeros((40, 3)), np.zeros((40, 3))
    sea_kinematics_into(spec, t + h, pts, e2, v2, a2)
    sea_kinematics_into(spec, t - h, pts, e1, v1, a1)
    assert np.allclose(acc, (v2 - v1) / (2 * h), rtol=1e-6, atol=1e-7)


def test_too_steep_or_too_shallow_is_refused_naming_the_field():
    with pytest.raises(ScenarioError, match=r"water\.waves\.height.*breaking"):
        load_scenario_dict(_env({"kind": "stokes5", "height": 14.0, "period": 7.0}, depth=100.0))
    with pytest.raises(ScenarioError, match=r"water\.waves\.height.*Ursell"):
        load_scenario_dict(_env({"kind": "stokes5", "height": 2.0, "period": 20.0}, depth=8.0))
