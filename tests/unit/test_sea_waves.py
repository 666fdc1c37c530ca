"""rfesim.sea.waves: dispersion, spectra, discretisation, reproducibility, time series."""
from __future__ import annotations

import math

import numpy as np
import pytest

from rfesim.scenario.schema import Environment
from rfesim.sea.kernel import sea_kinematics_into, sea_spec
from rfesim.sea.waves import (_jonswap_scale, components_from_time_series, discretise_spectrum, dnv_gamma,
                              jonswap_spectrum, pierson_moskowitz_spectrum, spectral_moment, wave_components,
                              wave_number, water_depth)

G = 9.81


def test_dispersion_residual_is_round_off_over_shallow_to_deep():
    rng = np.random.default_rng(0)
    omega = rng.uniform(0.01, 12.0, 2000)
    depth = rng.uniform(0.5, 3000.0)
    for h in (depth, 0.3, 5.0, 5000.0):
        k = wave_number(omega, h, G)
        assert np.max(np.abs(G * k * np.tanh(k * h) / omega ** 2 - 1.0)) < 1e-14


def test_dispersion_limits():
    # deep water k = w^2/g; shallow water k -> w / sqrt(g h)
    assert wave_number(1.0, None, G) == pytest.approx(1.0 / G, rel=1e-15)
    assert wave_number(1.0, 1e4, G) == pytest.approx(1.0 / G, rel=1e-15)
    w = 1e-3
    assert wave_number(w, 10.0, G) == pytest.approx(w / math.sqrt(G * 10.0), rel=1e-6)
    with pytest.raises(ValueError):
        wave_number([1.0, 0.0], 10.0)


def test_dnv_gamma_rule():
    assert dnv_gamma(4.0, 7.0) == 5.0                          # Tp/sqrt(Hs) = 3.5
    assert dnv_gamma(4.0, 8.0) == pytest.approx(math.exp(5.75 - 1.15 * 4.0))
    assert dnv_gamma(4.0, 10.0) == 1.0                         # 5.0
    # continuous at both ends of the middle branch
    assert math.exp(5.75 - 1.15 * 3.6) == pytest.approx(5.0, rel=2e-3)
    assert math.exp(5.75 - 1.15 * 5.0) == pytest.approx(1.0, rel=1e-12)


def test_pierson_moskowitz_area_is_hs_squared_over_16():
    # integral of 5/16 Hs^2 wp^4 w^-5 exp(-5/4 (wp/w)^4) over (0, inf) is exactly Hs^2/16
    hs, tp = 3.0, 9.0
    m0 = spectral_moment(lambda w: pierson_moskowitz_spectrum(w, hs, tp), 0, 0.05, 2000.0, bins=6000)
    assert m0 == pytest.approx(hs ** 2 / 16.0, rel=1e-7)
    assert np.array_equal(pierson_moskowitz_spectrum([-1.0, 0.0], hs, tp), [0.0, 0.0])


def test_jonswap_peak_is_gamma_times_the_normalised_pm_peak():
    hs, tp, gamma = 4.0, 10.0, 3.3
    wp = 2 * math.pi / tp
    ratio = jonswap_spectrum(wp, hs, tp, gamma) / pierson_moskowitz_spectrum(wp, hs, tp)
    assert ratio == pytest.approx(gamma * (1.0 - 0.287 * math.log(gamma)), rel=1e-14)


@pytest.mark.parametrize("method", ["geometric", "equal-spacing", "equal-energy"])
def test_discrete_energy_equals_the_spectrum_over_the_range(method):
    spectrum = (lambda w: jonswap_spectrum(w, 4.0, 10.0, 3.3))
    lo, hi = 0.3, 6.0
    a, w, phase = discretise_spectrum(spectrum, 150, lo, hi, method, np.random.default_rng(4))
    assert np.sum(a ** 2 / 2) == pytest.approx(spectral_moment(spectrum, 0, lo, hi), rel=1e-6)
    assert np.all((w > lo) & (w < hi)) and np.all(np.diff(w) > 0)
    assert np.all((phase >= 0) & (phase < 2 * math.pi))
    if method == "equal-energy":
        assert np.std(a) / np.mean(a) < 1e-3


def _scene(**waves):
    return Environment.model_validate({"water": {"depth": 200.0, "waves": waves}})


def test_same_seed_same_sea_other_seed_other_sea():
    base = {"kind": "jonswap", "hs": 2.0, "tp": 8.0, "direction_deg": 30.0}
    a = wave_components(_scene(**base, seed=7).water.waves, 200.0)
    b = wave_components(_scene(**base, seed=7).water.waves, 200.0)
    c = wave_components(_scene(**base, seed=8).water.waves, 200.0)
    assert np.array_equal(a.phase, b.phase) and np.array_equal(a.omega, b.omega)
    assert not np.allclose(a.phase, c.phase) and not np.allclose(a.omega, c.omega)
    # the stated draws: jitter first, then the phases, from numpy's default_rng(seed)
    rng = np.random.default_rng(7)
    jitter = rng.random(200)
    assert np.array_equal(a.phase, rng.uniform(0.0, 2 * math.pi, 200))
    edges = np.geomspace(0.5 * 2 * math.pi / 8.0, 10 * 2 * math.pi / 8.0, 201)
    assert np.allclose(a.omega, edges[:-1] + jitter * np.diff(edges), rtol=1e-15)


def test_default_gamma_follows_the_dnv_rule():
    hs, tp = 4.0, 8.0
    a = wave_components(_scene(kind="jonswap", hs=hs, tp=tp, seed=1).water.waves, 200.0)
    b = wave_components(_scene(kind="jonswap", hs=hs, tp=tp, seed=1, gamma=dnv_gamma(hs, tp)).water.waves, 200.0)
    c = wave_components(_scene(kind="jonswap", hs=hs, tp=tp, seed=1, gamma=1.0).water.waves, 200.0)
    assert np.array_equal(a.amplitude, b.amplitude) and not np.allclose(a.amplitude, c.amplitude)


def test_pierson_moskowitz_kind_is_jonswap_with_gamma_one():
    a = wave_components(_scene(kind="pierson-moskowitz", hs=3.0, tp=11.0, seed=2).water.waves, 200.0)
    b = wave_components(_scene(kind="jonswap", hs=3.0, tp=11.0, seed=2, gamma=1.0).water.waves, 200.0)
    assert np.allclose(a.amplitude, b.amplitude, rtol=1e-14) and np.array_equal(a.omega, b.omega)


def test_time_series_components_reproduce_the_record_at_its_samples():
    rng = np.random.default_rng(3)
    for n in (64, 101):
        t = 5.0 + 0.5 * np.arange(n)
        eta = rng.normal(size=n)
        a, w, phi = components_from_time_series(t, eta)
        rebuilt = np.cos(np.multiply.outer(t, w) + phi) @ a
        assert np.max(np.abs(rebuilt - (eta - eta.mean()))) < 1e-12


def test_time_series_waves_travel_from_the_record_point():
    # the elevation the kernel gives at the record point equals the record (mean removed)
    t = np.arange(0.0, 60.0, 0.25)
    eta = 0.8 * np.cos(2 * np.pi * t / 7.5 + 0.3) + 0.3 * np.sin(2 * np.pi * t / 4.0)
    env = Environment.model_validate({"water": {"depth": 40.0, "surface_level": 2.0, "waves": {
        "kind": "time-series", "rows": np.column_stack([t, eta]).tolist(), "origin": [30.0, -10.0],
        "direction_deg": 120.0, "stretching": "none"}}})
    spec = sea_spec(env)
    point = np.array([[30.0, -10.0, -5.0]])
    out = np.zeros(1)
    v, a = np.zeros((1, 3)), np.zeros((1, 3))
    for i in (0, 17, 101, 239):
        sea_kinematics_into(spec, float(t[i]), point, out, v, a)
        assert out[0] - 2.0 == pytest.approx(eta[i] - eta.mean(), abs=1e-12)


def test_regular_wave_components_and_depth_from_the_seabed():
    env = Environment.model_validate({"water": {"waves": {"kind": "airy", "height": 3.0, "period": 9.0,
                                                          "phase_deg": 90.0, "direction_deg": 45.0}},
                                      "seabed": {"z": -80.0}})
    assert water_depth(env) == 80.0
    wc = wave_components(env.water.waves, water_depth(env), env.gravity)
    assert wc.amplitude.tolist() == [1.5] and wc.depth == 80.0
    assert wc.omega[0] == pytest.approx(2 * math.pi / 9.0) and wc.phase[0] == pytest.approx(math.pi / 2)
    assert wc.elevation(0.0, 0.0, 0.0) == pytest.approx(0.0, abs=1e-15)
    assert wc.elevation(9.0 * 0.75, 0.0, 0.0) == pytest.approx(1.5, rel=1e-14)   # cos(3pi/2 + pi/2)
    deep = Environment.model_validate({"water": {"waves": {"kind": "airy", "height": 3.0, "period": 9.0,
                                                           "deep_water": True}}})
    wd = wave_components(deep.water.waves, water_depth(deep), deep.gravity)
    assert math.isinf(wd.depth) and wd.wavenumber[0] == pytest.approx((2 * math.pi / 9.0) ** 2 / 9.81)


def test_ramp_starts_the_sea_from_rest():
    env = Environment.model_validate({"water": {"depth": 50.0, "waves": {
        "kind": "airy", "height": 2.0, "period": 8.0, "ramp_duration": 16.0}}})
    spec = sea_spec(env)
    p = np.array([[1.0, 2.0, -3.0]])
    eta, v, a = np.zeros(1), np.zeros((1, 3)), np.zeros((1, 3))
    sea_kinematics_into(spec, 0.0, p, eta, v, a)
    assert eta[0] == 0.0 and not v.any() and not a.any()
    sea_kinematics_into(spec, 8.0, p, eta, v, a)
    full = Environment.model_validate({"water": {"depth": 50.0, "waves": {
        "kind": "airy", "height": 2.0, "period": 8.0}}})
    e2, v2, a2 = np.zeros(1), np.zeros((1, 3)), np.zeros((1, 3))
    sea_kinematics_into(sea_spec(full), 8.0, p, e2, v2, a2)
    assert eta[0] == pytest.approx(0.5 * e2[0], rel=1e-14)


@pytest.mark.parametrize("gamma, sigma_a, sigma_b", [(10.0, 0.07, 0.09), (3.3, 0.2, 0.2), (7.0, 0.15, 0.2)])
def test_jonswap_has_the_hs_it_was_given_outside_the_dnv_fit(gamma, sigma_a, sigma_b):
    """Outside the fit of DNV's A_gamma (gamma 10: m0 7 % short; gamma 3.3 or 7 with wider
    peaks: 36 % and 49 % over) the spectrum is normalised to Hs^2/16; inside it (W2, gamma 3.3,
    sigma 0.07 / 0.09) the DNV form stays (m0 = 1.00242 m^2 for Hs = 4 m)."""
    hs, tp = 4.0, 10.0

    def m0(*args):
        return spectral_moment(lambda w: jonswap_spectrum(w, hs, tp, *args), 0, 0.05, 2000.0, bins=6000)

    assert m0(gamma, sigma_a, sigma_b) == pytest.approx(hs ** 2 / 16.0, rel=1e-6)
    dnv = (1.0 - 0.287 * math.log(gamma)) * m0(gamma, sigma_a, sigma_b) / _jonswap_scale(gamma, sigma_a, sigma_b)
    assert abs(dnv / (hs ** 2 / 16.0) - 1.0) > 0.05           # what the DNV factor alone gives
    assert m0(3.3) == pytest.approx(1.00242, abs=1e-5)
