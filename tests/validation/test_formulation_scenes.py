"""Scenarios in the classical, classical-linear, modified and planar formulations and scenario
``chains`` through rfesim.statics / simulate / modes: VALIDATION.md R1 and B4 for the same
cantilever in all formulations (and the absolute one), a rigid double pendulum against its
closed-form small-oscillation frequencies, a prescribed drive, the output channels (Newton's
law for the part beyond each SDE) and netCDF output."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.bench.cases import B4_RATIOS, BETA_L, cantilever

G = 9.81
FORMULATIONS = ["classical", "classical-linear", "modified", "planar"]


def beam(formulation, n, loads, **kw):
    d = cantilever(n, loads, **kw)
    d["lines"]["beam"]["formulation"] = formulation
    return d


def r1(formulation, n, L=10.0, EI=1e6, GA=1e9):
    """Tip deflection and rotation per unit tip force (Richardson from P and 2P removes the
    O(P^3) geometric nonlinearity of the nonlinear formulations) and the R1 references."""
    def run(P):
        line = rfesim.statics(beam(formulation, n, [{"at": "end_b", "force": [0, 0, -P]}], EI=EI, L=L, EA=1e12,
                                   GA=GA, shear="kruszewski")).line("beam")
        d = line.end_b_direction[0]
        return -line.position[0, -1, 2] / P, math.atan2(-d[2], d[0]) / P
    P = 1e-3 * EI / L ** 2
    (w1, r1_), (w2, r2) = run(P), run(2 * P)
    shear = 0.0 if formulation in ("modified", "planar") else L / GA      # inextensible, shear-rigid models
    return ((4 * w1 - w2) / 3, (4 * r1_ - r2) / 3), (L ** 3 / (3 * EI) * (1 - 1 / (4 * n * n)) + shear,
                                                     L ** 2 / (2 * EI))


@pytest.mark.parametrize("formulation", FORMULATIONS + ["absolute"])
def test_R1_same_cantilever_all_formulations(formulation):
    """R1 to 1e-7 (1e-8 for the models without geometric nonlinearity in the Richardson
    remainder): tip deflection (PL^3/3EI)(1 - 1/4n^2) + PL/GA and rotation PL^2/2EI."""
    (w, rot), (w_ref, rot_ref) = r1(formulation, 6)
    assert w == pytest.approx(w_ref, rel=1e-7)
    assert rot == pytest.approx(rot_ref, rel=1e-7)


def test_cantilever_statics_outputs_are_the_section_forces():
    """Tip force P on a weightless cantilever: shear P and bending moment P (L - s) at every SDE
    (exactly, from Newton's law for the part beyond the SDE), end-A reaction -P and moment
    P L; all formulations give the same numbers and positions within 1e-6."""
    P, L, n = 100.0, 10.0, 8
    out = {}
    for f in FORMULATIONS:
        st = rfesim.statics(beam(f, n, [{"at": "end_b", "force": [0, 0, -P]}], EI=1e6, L=L, EA=1e12, GA=1e13,
                                 shear="kruszewski"))
        ln = st.line("beam")
        out[f] = ln
        s = ln.sde_arc_length
        tip = ln.position[0, -1]
        lever = tip[0] - ln.position[0, 1:-1, 0]                   # horizontal lever arm of the tip force
        assert ln.bend_moment[0] == pytest.approx(P * lever, rel=1e-9)
        assert np.hypot(ln.tension[0], ln.shear_force[0]) == pytest.approx(np.full(n, P), rel=1e-9)
        assert ln.end_a_force[0] == pytest.approx([0, 0, -P], abs=1e-9 * P)   # the line pulls its clamp down
        assert ln.end_a_moment[0][1] == pytest.approx(P * tip[0], rel=1e-9)
        assert np.allclose(s, (np.arange(n) + 0.5) * L / n)
        assert ln.position.shape == (1, n + 2, 3)
    ref = out["classical"].position[0]
    for f in ("modified", "planar"):                 # the nonlinear models: the same shape
        assert np.abs(out[f].position[0] - ref).max() < 1e-6 * L
    # the linear model differs by the second-order shortening (P L^2 / EI)^2 L / 15 ~ 7e-6 L
    assert 1e-6 * L < np.abs(out["classical-linear"].position[0] - ref).max() < 1e-5 * L


@pytest.mark.parametrize("formulation", FORMULATIONS)
def test_B4_same_cantilever_frequencies_all_formulations(formulation):
    """rfesim.modes: the first four in-plane bending frequencies over the continuum ones are the
    VALIDATION.md B4 ratios at n = 10 (bending springs only, RFE inertia m l^2/12); the
    nonlinear classical model is linearised by central differences (1e-4)."""
    sc = beam(formulation, 10, [], EI=1e6, L=10.0, EA=1e12, GA=1e13, shear="kruszewski", EIz=1e4 * 1e6,
              mass=10.0)
    md = rfesim.modes(sc, n=8)
    shapes = md.line_shapes["beam"]
    inplane = [k for k in range(len(md.frequencies_hz)) if np.abs(shapes[k][:, 2]).max() > 0.9 * np.abs(shapes[k]).max()]
    f = md.frequencies_hz[inplane][:4]
    exact = BETA_L ** 2 * math.sqrt(1e6 / (10.0 * 10.0 ** 4)) / (2 * math.pi)
    tol = 1e-4 if formulation == "classical" else 1e-5
    assert f / exact == pytest.approx(B4_RATIOS[10], abs=tol)


def test_classical_linear_modes_of_1000_rfes_fast_and_sparse():
    """A 1000-element clamped classical-linear line through rfesim.modes uses the sparse path
    (constant diagonal M, block-tridiagonal K, eqs. 8.34-8.35): first bending frequency
    3.516^2 sqrt(EI/(mu L^4)) within 1e-3, in well under the 1 s target."""
    import time
    sc = beam("classical-linear", 1000, [], EI=1e6, L=100.0, EA=1e9, shear="fem", mass=10.0)
    rfesim.modes(sc, n=2)                        # warm up (compile the kernels)
    t0 = time.perf_counter()
    md = rfesim.modes(sc, n=4)
    wall = time.perf_counter() - t0
    f1 = BETA_L[0] ** 2 * math.sqrt(1e6 / (10.0 * 100.0 ** 4)) / (2 * math.pi)
    assert md.frequencies_hz[:2] == pytest.approx([f1, f1], rel=1e-3)
    assert md.line_shapes["beam"].shape == (4, 1002, 3)
    assert wall < 3.0, wall                      # target < 1 s on an idle machine (docs/benchmarks.md)


# ----------------------------------------------------------------------------- chains
def double_pendulum(j1=0.0, j2=0.0, duration=0.0):
    rod = {"rigid": True, "length": 1.0, "mass": 1.0, "centre": [1.0, 0.0, 0.0], "inertia": [0.0, 0.0, 0.0]}
    return {
        "environment": {"gravity": G},
        "chains": {"pendulum": {
            "links": {"upper": dict(rod), "lower": dict(rod)},
            "joints": {"top": {"kind": "revolute", "parent": "base", "child": "upper", "direction": [0, 0, -1],
                               "axis": [0, 1, 0], "initial": j1},
                       "middle": {"kind": "revolute", "parent": "upper", "child": "lower", "direction": [1, 0, 0],
                                  "axis": [0, 1, 0], "initial": j2}}}},
        "analysis": {"statics": {"enabled": False},
                     "dynamics": {"duration": duration, "integrator": {"kind": "rk4", "time_step": 2e-3},
                                  "output_interval": 0.01}},
    }


def test_double_pendulum_modes_closed_form():
    """Equal point masses and lengths: omega^2 = (g/L)(2 -+ sqrt 2) to 1e-8."""
    md = rfesim.modes(double_pendulum(), n=2)
    w = 2 * np.pi * md.frequencies_hz
    assert w == pytest.approx(np.sqrt(G * (2 + np.array([-1, 1]) * np.sqrt(2))), rel=1e-8)


def test_double_pendulum_simulate_first_mode_period():
    """Started in the first mode (theta2 = sqrt2 theta1, 0.01 rad) it swings at omega_1 = sqrt(g
    (2 - sqrt 2)): the period from the zero crossings of the top joint within 1e-4; the lower
    mass hangs on the tension of the lower rod (m g within 1e-3 at this amplitude)."""
    th = 0.01
    res = rfesim.simulate(double_pendulum(th, (math.sqrt(2) - 1) * th, duration=6.0))
    q = res.joints["pendulum.top"].coordinate[:, 0]
    t = res.time
    i = np.flatnonzero(np.sign(q[:-1]) != np.sign(q[1:]))
    crossings = t[i] - q[i] * (t[i + 1] - t[i]) / (q[i + 1] - q[i])
    period = 2 * np.mean(np.diff(crossings))
    assert period == pytest.approx(2 * np.pi / math.sqrt(G * (2 - math.sqrt(2))), rel=1e-4)
    lower = res.line("pendulum.lower")
    assert lower.position.shape == (len(t), 3, 3)                  # joint, the root section, tip
    assert lower.tension[:, 0] == pytest.approx(G * np.cos(q + res.joints["pendulum.middle"].coordinate[:, 0]),
                                                rel=2e-3)               # m g cos(theta2) at small amplitude
    upper = res.line("pendulum.upper")
    assert -upper.end_a_force[:, 2] == pytest.approx(2 * G, rel=2e-3)   # both masses hang on the top pin
    assert upper.end_b_force[:, 2] == pytest.approx(G, rel=2e-3)        # and it holds the lower one up


def test_prescribed_revolute_drive_and_netcdf(tmp_path):
    """A rigid arm on a revolute joint driven harmonically about z follows the profile exactly
    (prescribed coordinates are not unknowns); its tip traces the circle; Results.to_netcdf
    writes a file rfesim.open_results reads back."""
    sc = {
        "environment": {"gravity": G},
        "line_types": {"bar": {"EA": 1e9, "EIy": 1e5, "mass_per_length": 5.0}},
        "chains": {"arm": {
            "links": {"post": {"rigid": True, "length": 2.0, "mass": 10.0},
                      "jib": {"type": "bar", "length": 4.0, "elements": 4, "formulation": "modified",
                              "dofs": ["ry", "rz"]}},
            "joints": {"slew": {"kind": "revolute", "parent": "base", "child": "post", "direction": [0, 0, 1],
                                "axis": [0, 0, 1], "drive": {"kind": "prescribed", "motion": {
                                    "kind": "harmonic", "amplitude": 0.5, "period": 4.0}}},
                       "weld": {"kind": "fixed", "parent": "post", "child": "jib", "direction": [0, 0, -1]}}}},
        "analysis": {"statics": {"enabled": True},
                     "dynamics": {"duration": 1.0, "integrator": {"kind": "rk4", "time_step": 1e-3},
                                  "output_interval": 0.05}},
    }
    res = rfesim.simulate(sc)
    slew = res.joints["arm.slew"].coordinate[:, 0]
    assert slew == pytest.approx(0.5 * np.sin(2 * np.pi * res.time / 4.0), abs=1e-12)
    jib = res.line("arm.jib")
    root = jib.end_a_direction                                       # welded to the post: turns with it
    assert np.arctan2(root[:, 1], root[:, 0]) == pytest.approx(slew, abs=1e-12)
    tip = jib.position[:, -1]
    assert np.hypot(tip[:, 0], tip[:, 1]) == pytest.approx(np.full(len(res.time), 4.0), rel=1e-3)
    lag = np.arctan2(tip[:, 1], tip[:, 0]) - slew                   # the flexible jib lags a little
    assert 1e-4 < np.abs(lag).max() < 1e-2
    path = tmp_path / "arm.nc"
    res.to_netcdf(path)
    back = rfesim.open_results(path)
    assert np.allclose(back.line("arm.jib").position, res.line("arm.jib").position)
    assert back.line("arm.post").tension.shape == (len(res.time), 1)    # a rigid link: its root section


def test_planar_dynamics_generalized_alpha_and_rk4_agree():
    """A planar cantilever released under gravity (straight start, no statics): the tip path of
    generalized-alpha (rho_inf = 1, small step) and RK4 agree within 1e-4 L."""
    tips = []
    for integ in ({"kind": "rk4", "time_step": 2e-4}, {"kind": "generalized-alpha", "time_step": 5e-4,
                                                          "rho_inf": 1.0}):
        sc = beam("planar", 6, [], EI=1e4, L=2.0, EA=1e9, mass=2.0, gravity=G)
        sc["analysis"] = {"statics": {"enabled": False},
                          "dynamics": {"duration": 0.25, "integrator": integ, "output_interval": 0.01}}
        tips.append(rfesim.simulate(sc).line("beam").position[:, -1])
    assert tips[0].shape == tips[1].shape
    assert np.abs(tips[0] - tips[1]).max() < 1e-4 * 2.0
    sag = 2.0 * G * 2.0 ** 4 / (8 * 1e4)                                 # static tip deflection mu g L^4 / 8EI
    assert tips[0][:, 2].min() < -1.5 * sag                              # it swings through twice the sag
