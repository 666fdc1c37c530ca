"""VALIDATION.md section "Beams": R1, B1, B2, B4, B5, B9 for the absolute (section 8.4) formulation."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim


def cantilever(n, loads, *, EI=1.0, L=1.0, EA=1e7, GA=None, shear="fem", EIz=None, mass=1.0, rotary=0.0,
               gravity=0.0, load_steps=1):
    lt = {"EA": EA, "EIy": EI, "GA": GA if GA is not None else EA, "mass_per_length": mass,
          "rotary_inertia": rotary}
    if EIz is not None:
        lt["EIz"] = EIz
    return {
        "name": "cantilever",
        "environment": {"gravity": gravity},
        "line_types": {"beam": lt},
        "lines": {"beam": {"type": "beam", "length": L, "elements": n, "shear_stiffness": shear,
                           "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                     "connection": "clamped"},
                           "end_b": {"attach": "free"}, "loads": loads}},
        "analysis": {"statics": {"enabled": True, "tolerance": 1e-12, "load_steps": load_steps},
                     "dynamics": {"enabled": False}},
    }


# --------------------------------------------------------------------------- R1
@pytest.mark.parametrize("shear", ["fem", "kruszewski"])
@pytest.mark.parametrize("n", [3, 10, 20])
def test_R1_linear_cantilever_tip_force(n, shear):
    """Tip force P: rotation PL^2/(2EI) and deflection (PL^3/3EI)(1 - 1/(4n^2)) exactly, plus
    the shear part: PL/GA (eq. 8.88) or PL^3/(12 EI n^2) (eq. 8.89, which makes it exact).
    The geometric nonlinearity O(P^3) is removed by Richardson extrapolation from P, 2P."""
    L, EI, GA = 10.0, 1e6, 1e9

    def run(P):
        sc = cantilever(n, [{"at": "end_b", "force": [0, 0, -P]}], EI=EI, L=L, EA=1e12, GA=GA, shear=shear)
        res = rfesim.statics(sc)
        line = res.line("beam")
        w = -line.position[0, -1, 2]
        d = line.end_b_direction[0]              # axis of the last RFE
        return w / P, np.arctan2(-d[2], d[0]) / P

    P = 1e-3 * EI / L ** 2
    w1, r1 = run(P)
    w2, r2 = run(2 * P)
    w = (4 * w1 - w2) / 3
    rot = (4 * r1 - r2) / 3
    bending = L ** 3 / (3 * EI) * (1 - 1 / (4 * n ** 2))
    shear_part = L / GA if shear == "kruszewski" else L ** 3 / (12 * EI * n ** 2)
    assert w == pytest.approx(bending + shear_part, rel=1e-8)
    assert rot == pytest.approx(L ** 2 / (2 * EI), rel=1e-8)


@pytest.mark.parametrize("n", [4, 12])
def test_R1_linear_cantilever_tip_moment(n):
    """Tip moment M: rotation ML/EI and deflection ML^2/(2EI) exactly (for any n)."""
    L, EI = 10.0, 1e6
    M = 1e-3 * EI / L

    def run(Mi):
        res = rfesim.statics(cantilever(n, [{"at": "end_b", "moment": [0, -Mi, 0]}], EI=EI, L=L, EA=1e12))
        line = res.line("beam")
        d = line.end_b_direction[0]
        return line.position[0, -1, 2] / Mi, np.arctan2(d[2], d[0]) / Mi

    w1, r1 = run(M)
    w2, r2 = run(2 * M)
    assert (4 * w1 - w2) / 3 == pytest.approx(L ** 2 / (2 * EI), rel=1e-8)
    assert (4 * r1 - r2) / 3 == pytest.approx(L / EI, rel=1e-8)


# --------------------------------------------------------------------------- B1
MATTIASSON = {1.0: (0.30172, 0.05643, 0.46135), 10.0: (0.81061, 0.55500, 1.43029)}


def mattiasson(n, alpha):
    res = rfesim.statics(cantilever(n, [{"at": "end_b", "force": [0, 0, -alpha]}]))
    line = res.line("beam")
    tip = line.position[0, -1]
    d = line.end_b_direction[0]
    return -tip[2], 1.0 - tip[0], -np.arctan2(d[2], d[0])


@pytest.mark.parametrize("alpha", [1.0, 10.0])
def test_B1_mattiasson_large_deflection(alpha):
    """Inextensible cantilever, dead tip load, alpha = PL^2/EI: 0.3 % at 20 elements."""
    w, u, rot = mattiasson(20, alpha)
    ref = MATTIASSON[alpha]
    assert w == pytest.approx(ref[0], rel=3e-3)
    assert u == pytest.approx(ref[1], rel=3e-3)
    assert rot == pytest.approx(ref[2], rel=3e-3)


@pytest.mark.parametrize("alpha", [1.0, 10.0])
def test_B1_convergence_order_is_two(alpha):
    """The error of the tip deflection falls as 1/n^2 (observed order within 0.15 of 2)."""
    ns = [10, 20, 40]
    err = [abs(mattiasson(n, alpha)[0] / MATTIASSON[alpha][0] - 1.0) for n in ns]
    orders = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.15), (err, orders)


# --------------------------------------------------------------------------- B2
def end_moment(n, fraction, L=1.0, EI=1.0):
    M = fraction * 2 * np.pi * EI / L
    res = rfesim.statics(cantilever(n, [{"at": "end_b", "moment": [0, M, 0]}], EI=EI, L=L))
    line = res.line("beam")
    kappa = M / EI
    expected = np.array([np.sin(kappa * L), 0.0, -(1 - np.cos(kappa * L))]) / kappa
    return line, M, np.linalg.norm(line.position[0, -1] - expected) / L


@pytest.mark.parametrize("fraction", [0.25, 0.5, 1.0])
def test_B2_pure_end_moment(fraction):
    """Uniform curvature M/EI and tip rotation ML/EI exactly, even when the line rolls up."""
    L, EI = 1.0, 1.0
    line, M, _ = end_moment(20, fraction, L, EI)
    assert line.curvature[0] == pytest.approx(np.full(20, M / EI), rel=1e-8)
    total = (line.curvature[0] * (L / 20)).sum()               # sum of the SDE rotations
    assert total == pytest.approx(M * L / EI, rel=1e-8)
    d = line.end_b_direction[0]                                # tip rotation about -y
    expected = np.array([np.cos(M * L / EI), 0.0, -np.sin(M * L / EI)])
    assert d == pytest.approx(expected, abs=1e-8)


def test_B2_closes_into_a_circle():
    """At M = 2 pi EI/L the tip returns to the clamp: within 1e-3 L at n = 20."""
    _, _, err = end_moment(20, 1.0)
    assert err < 1e-3


def test_B2_tip_position_converges_as_n_squared():
    """Half circle: the tip error is the O(1/n^2) error of the RFE polygon."""
    err = [end_moment(n, 0.5)[2] for n in (10, 20, 40)]
    orders = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.1), (err, orders)
    assert err[1] < 2e-3


# --------------------------------------------------------------------------- B4
BETA_L = np.array([1.875104, 4.694091, 7.854757, 10.995541])
B4_RATIOS = {10: [1.00230, 1.00802, 1.01303, 1.01760], 20: [1.00057, 1.00199, 1.00327, 1.00454]}


def bending_modes_in_plane(md, name="beam", count=4):
    """Frequencies of the modes whose shape is a displacement in z (bending about y)."""
    shapes = md.line_shapes[name]
    inplane = [k for k in range(len(md.frequencies_hz))
               if np.abs(shapes[k][:, 2]).max() > 0.9 * np.abs(shapes[k]).max()]
    return md.frequencies_hz[inplane][:count]


@pytest.mark.parametrize("n", [10, 20])
def test_B4_cantilever_frequencies_rigid_shear(n):
    """Bending springs only (shear and axial springs stiff), RFE inertia m l^2/12: the
    over-prediction ratios of VALIDATION.md B4."""
    L, EI, mu = 10.0, 1e6, 10.0
    sc = cantilever(n, [], EI=EI, L=L, EA=1e12, GA=1e13, shear="kruszewski", EIz=100 * EI, mass=mu)
    md = rfesim.modes(sc, n=12)
    f = bending_modes_in_plane(md)
    exact = BETA_L ** 2 * np.sqrt(EI / (mu * L ** 4)) / (2 * np.pi)
    assert f / exact == pytest.approx(B4_RATIOS[n], abs=1.5e-5)


def test_B4_fem_shear_converges_from_above():
    """With eq. 8.89 shear springs the first frequency converges to the continuum value as 1/n^2."""
    L, EI, mu = 10.0, 1e6, 10.0
    exact = BETA_L[0] ** 2 * np.sqrt(EI / (mu * L ** 4)) / (2 * np.pi)
    err = []
    for n in (10, 20, 40):
        md = rfesim.modes(cantilever(n, [], EI=EI, L=L, EA=1e12, shear="fem", EIz=100 * EI, mass=mu), n=6)
        err.append(abs(bending_modes_in_plane(md, count=1)[0] / exact - 1.0))
    orders = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.2), (err, orders)
    assert err[-1] < 1e-3


# --------------------------------------------------------------------------- B5
C_N = np.array([1.20241, 2.76004, 4.32686])


def hanging_chain(n, L=10.0):
    return {
        "environment": {"gravity": 9.81},
        "line_types": {"chain": {"EA": 1e9, "EIy": 1e-3, "GA": 1e9, "GJ": 1e-3, "mass_per_length": 1.0,
                                 "rotary_inertia": 0.0}},
        "lines": {"chain": {"type": "chain", "length": L, "elements": n, "shear_stiffness": "kruszewski",
                            "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, -1],
                                      "connection": "pinned"},
                            "end_b": {"attach": "free"}}},
    }


def pendulum_frequencies(md, g=9.81, L=10.0):
    """Swinging frequencies as c_n = omega / sqrt(g/L): each comes as a pair (x and y swing),
    the free rotation about the vertical has zero frequency."""
    f = np.sort(md.frequencies_hz[md.frequencies_hz > 1e-6])
    distinct = [f[0]]
    for x in f[1:]:
        if x > distinct[-1] * (1 + 1e-6):
            distinct.append(x)
    return 2 * np.pi * np.array(distinct) / np.sqrt(g / L)


@pytest.mark.parametrize("n", [10, 20, 40])
def test_B5_hanging_chain_first_mode(n):
    """Inextensible chain pinned at the top: omega_1 = 1.20241 sqrt(g/L) within 0.1 % at n >= 10."""
    c = pendulum_frequencies(rfesim.modes(hanging_chain(n), n=6))
    assert c[0] == pytest.approx(C_N[0], rel=1e-3)


def test_B5_hanging_chain_higher_modes():
    """Modes 2 and 3 converge to c_n from above; at n = 40 within 0.1 % and 0.5 %."""
    errs = []
    for n in (10, 20, 40):
        c = pendulum_frequencies(rfesim.modes(hanging_chain(n), n=12))
        errs.append(c[1:3] / C_N[1:3] - 1.0)
    errs = np.array(errs)
    assert np.all(errs > 0) and np.all(np.diff(errs, axis=0) < 0)
    assert errs[-1, 0] < 1e-3 and errs[-1, 1] < 5e-3


# --------------------------------------------------------------------------- B9
B9 = {30.0: 1.017409, 90.0: 1.180341, 150.0: 1.762204}


def pendulum_period_ratio(theta0_deg, integrator, n=4, L=2.0, periods=2.2):
    """A stiff rod pinned at the top released from rest at theta0: measured period over the
    small-amplitude period of the same physical pendulum, T0 = 2 pi sqrt(2L / 3g)."""
    g = 9.81
    th = np.radians(theta0_deg)
    T0 = 2 * np.pi * np.sqrt(2 * L / (3 * g))
    sc = {"environment": {"gravity": g},
          "line_types": {"rod": {"EA": 1e9, "EIy": 1e7, "GA": 1e9, "GJ": 1e7, "mass_per_length": 1.0,
                                 "rotary_inertia": 0.0}},
          "lines": {"rod": {"type": "rod", "length": L, "elements": n,
                            "end_a": {"attach": "fixed", "position": [0, 0, 0],
                                      "direction": [np.sin(th), 0, -np.cos(th)], "connection": "pinned"},
                            "end_b": {"attach": "free"}}},
          "analysis": {"statics": {"enabled": False},
                       "dynamics": {"duration": periods * T0 * B9[theta0_deg], "output_interval": T0 / 400,
                                    "integrator": integrator(T0)}}}
    res = rfesim.simulate(sc)
    x = res.line("rod").position[:, -1, 0]
    t = res.time
    idx = np.flatnonzero(np.sign(x[:-1]) != np.sign(x[1:]))
    crossings = [t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i]) for i in idx]
    return (crossings[2] - crossings[0]) / T0


@pytest.mark.parametrize("theta0", [30.0, 90.0, 150.0])
def test_B9_large_amplitude_pendulum(theta0):
    ratio = pendulum_period_ratio(
        theta0, lambda T0: {"kind": "generalized-alpha", "time_step": T0 / 400, "rho_inf": 1.0})
    assert ratio == pytest.approx(B9[theta0], rel=5e-4)
