"""Validation cases W1-W3 of VALIDATION.md ("Sea loads"), shared by
tests/validation/test_waves.py and the validation report."""
from __future__ import annotations

import math

import numpy as np

W1_K = {(10.0, 50.0): 0.041528, (12.0, 30.0): 0.035490}         # (T s, h m) -> k 1/m
W1_WHEELER_CREST = 2.1543                                        # m/s, h 100 m, T 10 s, a 4 m, z = 0
W1_LINEAR_CREST = 2.5149
# the W1 references are rounded to 5 significant digits: they are met to half a unit in
# their last digit (1.2e-5 relative for k = 0.041528, 2e-5 for 2.5149)
W1_K_HALF_UNIT = 5e-7
W1_CREST_HALF_UNIT = 5e-5
W2 = {"m0": 1.00242, "T_m02": 7.7778}                            # JONSWAP gamma 3.3, Hs 4 m, Tp 10 s
W2_OMEGA_MAX = 20.0        # rad/s: the reference moments are integrals up to 20 rad/s (to infinity T_m02 = 7.7740)
W3 = {"inertia": 63.1388e3, "drag": 40.4270e3, "total": 65.0795e3}   # N


def _environment(waves: dict, depth: float = 100.0):
    from ..scenario.schema import Environment
    return Environment.model_validate({"gravity": 9.81, "water": {"density": 1025.0, "depth": depth,
                                                                 "waves": waves}})


def w1_wave_numbers() -> dict:
    from ..sea.waves import wave_number
    return {key: float(wave_number(2.0 * math.pi / key[0], key[1], 9.81)) for key in W1_K}


def w1_crest_velocity(stretching: str) -> float:
    """Horizontal particle velocity under the crest at z = 0 (h 100 m, T 10 s, amplitude 4 m)."""
    from ..sea.kernel import sea_kinematics_into, sea_spec
    env = _environment({"kind": "airy", "height": 8.0, "period": 10.0, "stretching": stretching})
    eta, vel, acc = np.zeros(1), np.zeros((1, 3)), np.zeros((1, 3))
    sea_kinematics_into(sea_spec(env), 0.0, np.zeros((1, 3)), eta, vel, acc)
    assert eta[0] == 4.0           # t = 0, x = 0: the crest
    return float(vel[0, 0])


def w2_spectral_moments() -> dict:
    from ..sea.waves import jonswap_spectrum, spectral_moment
    spectrum = (lambda w: jonswap_spectrum(w, 4.0, 10.0, 3.3))
    m0 = spectral_moment(spectrum, 0, 0.05, W2_OMEGA_MAX)
    m2 = spectral_moment(spectrum, 2, 0.05, W2_OMEGA_MAX)
    return {"m0": m0, "T_m02": 2.0 * math.pi * math.sqrt(m0 / m2)}


def w2_realisation(seed: int = 1, duration: float = 10800.0, dt: float = 0.1) -> dict:
    """Variance and mean zero-up-crossing period of a 3 h elevation record at the origin of
    a JONSWAP sea discretised with the defaults (200 components, geometric bins)."""
    from ..sea.waves import wave_components
    env = _environment({"kind": "jonswap", "hs": 4.0, "tp": 10.0, "gamma": 3.3, "seed": seed})
    wc = wave_components(env.water.waves, 100.0, 9.81)
    t = np.arange(0.0, duration, dt)
    eta = np.concatenate([np.cos(np.multiply.outer(chunk, wc.omega) + wc.phase) @ wc.amplitude
                          for chunk in np.array_split(t, 40)])
    up = np.nonzero((eta[:-1] < 0.0) & (eta[1:] >= 0.0))[0]
    crossing = t[up] - eta[up] * dt / (eta[up + 1] - eta[up])
    return {"m0": float(np.mean(eta ** 2)), "T_z": float((crossing[-1] - crossing[0]) / (crossing.size - 1)),
            "components": int(wc.amplitude.size)}


def w3_cylinder_forces(strips: int = 500, which=("inertia", "drag", "total")) -> dict:
    """Maximum horizontal inertia, drag and total Morison force on a fixed vertical cylinder
    (D 1 m, C_D 1, C_M 2, 1025 kg/m^3) from the seabed (h 100 m) to the still water level, in
    a linear Airy wave (T 10 s, amplitude 4 m) without stretching. The column is a stack of
    vertical strips through rfesim.loads.hydro (submergence, morison_forces: Froude-Krylov
    rho V a plus added mass C_a rho V a_n, C_a = C_M - 1), the water kinematics from
    rfesim.sea.kernel; midpoint rule over the strips, maximum over a period refined by a
    bounded scalar search."""
    from scipy.optimize import minimize_scalar

    from ..loads.hydro import morison_forces, submergence
    from ..sea.kernel import sea_kinematics_into, sea_spec
    env = _environment({"kind": "airy", "height": 8.0, "period": 10.0, "stretching": "none"})
    spec = sea_spec(env)
    h, D, cd, cm, rho = 100.0, 1.0, 1.0, 2.0, 1025.0
    dz = h / strips
    n = strips
    length = np.full(n, dz)
    area = np.full(n, math.pi * D * D / 4.0)
    R = np.zeros((n, 3, 3))
    R[:] = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])   # local x along global z
    r = np.zeros((n, 3))
    r[:, 2] = -h + dz * (np.arange(n) + 0.5)
    sub_frac, sub_point = np.zeros(n), np.zeros((n, 3))
    submergence(length, area, R, r, np.zeros(n), sub_frac, sub_point)      # the still surface bounds the column
    zeros = np.zeros((n, 3))
    eta, vel, acc = np.zeros(n), np.zeros((n, 3)), np.zeros((n, 3))

    def force(t: float, drag: bool, inertia: bool) -> float:
        sea_kinematics_into(spec, float(t), sub_point, eta, vel, acc)
        F, M = np.zeros((n, 3)), np.zeros((n, 3))
        Ma, Ja = np.zeros((n, 3, 3)), np.zeros((n, 3))
        morison_forces(length, np.full(n, D), area, np.full(n, cd if drag else 0.0), np.zeros(n),
                       np.full(n, cm - 1.0), np.zeros(n), rho, R, r, zeros, zeros, sub_frac, sub_point,
                       vel, acc if inertia else zeros, F, M, Ma, Ja)
        return float(F[:, 0].sum())

    period = 10.0
    times = np.linspace(0.0, period, 361)
    out = {"submerged_fraction": float(sub_frac.min())}
    for name, drag, inertia in (("inertia", False, True), ("drag", True, False), ("total", True, True)):
        if name not in which:
            continue
        values = np.array([force(t, drag, inertia) for t in times])
        i = int(np.argmax(values))
        step = times[1] - times[0]
        best = minimize_scalar(lambda t, d=drag, m=inertia: -force(t, d, m), bounds=(times[i] - step, times[i] + step),
                               method="bounded", options={"xatol": 1e-10})
        out[name] = max(values[i], -best.fun)
    return out


def validation_rows(row, timed) -> list[dict]:
    """Rows of the validation report (``row`` and ``timed`` from rfesim.bench.validation)."""
    rows = []
    ks, dt = timed(w1_wave_numbers)
    for (T, h), k in ks.items():
        rows.append(row("W1 Airy dispersion", f"k at T = {T:g} s, h = {h:g} m [1/m]", W1_K[(T, h)], k,
                        "Newton", dt, W1_K_HALF_UNIT / W1_K[(T, h)]))
    for stretching, ref in (("wheeler", W1_WHEELER_CREST), ("none", W1_LINEAR_CREST)):
        u, dt = timed(w1_crest_velocity, stretching)
        rows.append(row("W1 crest velocity", f"u at z = 0, {stretching} [m/s]", ref, u, "exact", dt,
                        W1_CREST_HALF_UNIT / ref))
    moments, dt = timed(w2_spectral_moments)
    for name in ("m0", "T_m02"):
        rows.append(row("W2 JONSWAP", f"{name} (to {W2_OMEGA_MAX:g} rad/s)", W2[name], moments[name],
                        "Gauss-Legendre", dt, 1e-5))
    real, dt = timed(w2_realisation)
    rows.append(row("W2 JONSWAP", "m0 of a 3 h realisation [m^2]", W2["m0"], real["m0"],
                    f"{real['components']} components", dt, 3e-2))
    rows.append(row("W2 JONSWAP", "T_z of a 3 h realisation [s]", W2["T_m02"], real["T_z"],
                    f"{real['components']} components", dt, 3e-2))
    forces, dt = timed(w3_cylinder_forces)
    for name in ("inertia", "drag", "total"):
        rows.append(row("W3 Morison, vertical cylinder", f"max {name} force [N]", W3[name], forces[name],
                        "500 strips", dt, 1e-3))
    return rows
