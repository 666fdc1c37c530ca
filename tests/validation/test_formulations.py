"""Validation of the classical (8.1) and modified (8.2) RFE formulations and of kinematic
chains: VALIDATION.md R1, B1, B2, B4, B5, B9, a rigid double pendulum in closed form,
base motion and drives, and geometric stiffening under spin-up (Kane et al. 1987)."""
from __future__ import annotations

import numpy as np
import pytest

from rfesim.bench.cases import B4_RATIOS, BETA_L, CHAIN_C, MATTIASSON, PENDULUM
from rfesim.formulations import (
    BaseMotion,
    BeamProperties,
    Chain,
    ClassicalLink,
    Joint,
    JointForce,
    ModifiedLink,
    Prescribed,
    RigidLink,
    accelerations,
    chain_modes,
    chain_statics,
    equations,
    linear_modes,
    point_motion,
    simulate_chain,
)
from rfesim.formulations.chain import ChainData

G = 9.81
DOWN = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])     # Ry(90 deg): link x -> world -z


# ----------------------------------------------------------------------------- cantilevers
def beam_link(formulation, n, L=10.0, EI=1e6, EA=1e9, GA=None, shear="fem", mu=10.0):
    """A cantilever along x bending in the x-y plane (about z): planar dofs only."""
    props = BeamProperties(EA=EA, EIy=EI, EIz=EI, GJ=EI, mass_per_length=mu, GA=GA, shear=shear, rotary_inertia=0.0)
    if formulation == "modified":
        return ModifiedLink(L, n, props, dofs=("rz",))
    return ClassicalLink(L, n, props, linear=formulation == "classical-linear", dofs=("x", "y", "rz"))


def cantilever(formulation, n, force=(0.0, 0.0, 0.0), moment=(0.0, 0.0, 0.0), load_steps=1, **kw):
    link = beam_link(formulation, n, **kw)
    ch = Chain(gravity=(0.0, 0.0, 0.0))
    ch.add("beam", link)
    ch.add_load("beam", link.length, force=force, moment=moment)
    model = ch.compile()
    st = chain_statics(model, load_steps=load_steps)
    assert st.success, st.message
    z = np.zeros(model.nq)
    tip, _, _ = point_motion(model, 0.0, st.q, z, z, "beam", link.length)
    rot = tip_rotation(model, st.q, formulation)
    return tip, rot


def tip_rotation(model, q, formulation):
    names = [k for k, n in enumerate(model.coordinate_names) if n.endswith("phi_z")]
    return q[names].sum() if formulation == "modified" else q[names[-1]]


FORMULATIONS = ["classical", "classical-linear", "modified"]


@pytest.mark.parametrize("formulation", FORMULATIONS)
@pytest.mark.parametrize("n", [3, 10])
def test_R1_tip_force(formulation, n):
    """Tip rotation PL^2/(2EI) exactly; deflection (PL^3/3EI)(1 - 1/(4n^2)) plus the shear part
    (classical with 12EI/d^3 shear springs: exact PL^3/3EI; modified: no shear)."""
    L, EI = 10.0, 1e6
    P = 100.0 if formulation == "classical-linear" else 1e-3   # nonlinear models: geometrically linear range
    tip, rot = cantilever(formulation, n, force=(0.0, P, 0.0))
    bending = P * L ** 3 / (3 * EI) * (1 - 1 / (4 * n * n))
    shear = 0.0 if formulation == "modified" else P * L ** 3 / (12 * EI * n * n)
    assert tip[1] == pytest.approx(bending + shear, rel=1e-8)
    assert rot == pytest.approx(P * L ** 2 / (2 * EI), rel=1e-8)


@pytest.mark.parametrize("formulation", ["classical", "classical-linear"])
def test_R1_kruszewski_shear_part(formulation):
    """With c = GA/d (eq. 8.88) the shear part is PL/GA exactly."""
    L, EI, GA, n = 10.0, 1e6, 1e7, 6
    P = 1e-3 if formulation == "classical" else 100.0
    tip, _ = cantilever(formulation, n, force=(0.0, P, 0.0), GA=GA, shear="kruszewski")
    assert tip[1] == pytest.approx(P * L ** 3 / (3 * EI) * (1 - 1 / (4 * n * n)) + P * L / GA, rel=1e-8)


@pytest.mark.parametrize("formulation", FORMULATIONS)
def test_R1_tip_moment(formulation):
    """Tip moment M: rotation ML/EI, deflection ML^2/(2EI) exactly for any n."""
    L, EI, n = 10.0, 1e6, 7
    M = 100.0 if formulation == "classical-linear" else 1e-3
    tip, rot = cantilever(formulation, n, moment=(0.0, 0.0, M))
    assert rot == pytest.approx(M * L / EI, rel=1e-8)
    assert tip[1] == pytest.approx(M * L ** 2 / (2 * EI), rel=1e-8)


def test_linear_classical_reproduces_nonlinear_for_small_loads_only():
    """Same cantilever, linear (eq. 8.8) vs nonlinear (eq. 8.7): agree to 1e-7 at w/L ~ 3e-5,
    differ by more than 1 % at w/L ~ 0.3."""
    n = 8
    for P, agree in ((1.0, True), (1.0e5, False)):
        lin, _ = cantilever("classical-linear", n, force=(0.0, P, 0.0))
        non, _ = cantilever("classical", n, force=(0.0, P, 0.0), load_steps=4)
        diff = abs(non[1] / lin[1] - 1.0)
        assert (diff < 1e-7) if agree else (diff > 1e-2), (P, diff)


def mattiasson(formulation, n, alpha, L=1.0, EI=1.0):
    """Inextensible, shear-rigid cantilever under a dead tip load alpha EI/L^2."""
    P = alpha * EI / L ** 2
    tip, rot = cantilever(formulation, n, force=(0.0, -P, 0.0), load_steps=1 if alpha < 5 else 3, L=L, EI=EI,
                          EA=1e6, GA=1e6, shear="kruszewski")
    return -tip[1] / L, 1.0 - tip[0] / L, -rot


@pytest.mark.parametrize("formulation", ["classical", "modified"])
@pytest.mark.parametrize("alpha", [1.0, 10.0])
def test_B1_mattiasson(formulation, alpha):
    """Large deflection, dead tip load: w/L, u/L and the tip rotation within 0.3 % at n = 20."""
    w, u, rot = mattiasson(formulation, 20, alpha)
    ref = MATTIASSON[alpha]
    assert w == pytest.approx(ref[0], rel=3e-3)
    assert u == pytest.approx(ref[1], rel=3e-3)
    assert rot == pytest.approx(ref[2], rel=3e-3)


@pytest.mark.parametrize("formulation", ["classical", "modified"])
def test_B1_convergence_order_is_two(formulation):
    """The error of the tip deflection falls as 1/n^2 (observed order within 0.15 of 2)."""
    err = [abs(mattiasson(formulation, n, 10.0)[0] / MATTIASSON[10.0][0] - 1.0) for n in (10, 20, 40)]
    orders = np.log2(np.array(err[:-1]) / np.array(err[1:]))
    assert np.all(np.abs(orders - 2.0) < 0.15), (err, orders)


@pytest.mark.parametrize("formulation", ["classical", "modified"])
@pytest.mark.parametrize("fraction", [0.5, 1.0])
def test_B2_pure_end_moment(formulation, fraction):
    """Tip moment fraction * 2 pi EI/L at n = 20: tip rotation ML/EI to 1e-8; the tip is the
    end of the RFE polygon (joint rotations M d/EI: the trapezoidal rule of the circle) to
    1e-6 L (penalty springs EA = GA = 1e6 EI/L^2), within 2e-3 L of the circle (half circle,
    the O(1/n^2) polygon error) and within 1e-3 L of the clamp when it closes (full circle)."""
    L, EI, n = 1.0, 1.0, 20
    M = fraction * 2 * np.pi * EI / L
    tip, rot = cantilever(formulation, n, moment=(0.0, 0.0, M), load_steps=8, L=L, EI=EI, EA=1e6, GA=1e6,
                          shear="kruszewski")
    assert rot == pytest.approx(M * L / EI, rel=1e-8)
    d = L / n
    angles = np.arange(n + 1) * M * d / EI
    weights = np.full(n + 1, d)
    weights[[0, -1]] = d / 2
    polygon = np.array([np.sum(weights * np.cos(angles)), np.sum(weights * np.sin(angles)), 0.0])
    assert np.linalg.norm(tip - polygon) < 1e-6 * L
    R = EI / M
    exact = np.array([R * np.sin(M * L / EI), R * (1 - np.cos(M * L / EI)), 0.0])
    assert np.linalg.norm(tip - exact) < (2e-3 if fraction < 1 else 1e-3) * L


# ----------------------------------------------------------------------------- frequencies
def b4_reference(n, L=10.0, EI=1e6, mu=10.0):
    return BETA_L ** 2 * np.sqrt(EI / (mu * L ** 4)) * np.array(B4_RATIOS[n])


@pytest.mark.parametrize("n", [10, 20])
def test_B4_modified_cantilever_frequencies(n):
    """Bending springs only, RFE inertia m l^2/12: the planar-RFE ratios of VALIDATION.md."""
    ch = Chain(gravity=(0, 0, 0))
    ch.add("beam", beam_link("modified", n))
    model = ch.compile()
    w, _ = chain_modes(model, np.zeros(model.nq))
    assert w[:4] == pytest.approx(b4_reference(n), rel=2e-5)


@pytest.mark.parametrize("n", [10, 20])
def test_B4_linear_classical_cantilever_frequencies_sparse(n):
    """Linear classical model with stiff axial and shear springs (EA = GA = 1e12 EI/L^2):
    the same ratios, from the constant diagonal M and block-tridiagonal K (eqs. 8.34, 8.35)."""
    link = beam_link("classical-linear", n, EA=1e14, GA=1e14, shear="kruszewski")
    w, _ = linear_modes(link, 4)
    assert w == pytest.approx(b4_reference(n), rel=2e-5)


def test_B4_nonlinear_classical_linearised_about_equilibrium():
    n = 10
    ch = Chain(gravity=(0, 0, 0))
    ch.add("beam", beam_link("classical", n, EA=1e11, GA=1e11, shear="kruszewski"))
    model = ch.compile()
    w, _ = chain_modes(model, np.zeros(model.nq))
    assert w[:4] == pytest.approx(b4_reference(n), rel=1e-4)


# ----------------------------------------------------------------------------- rigid chains
def double_pendulum(m1=1.3, m2=0.7, L1=1.1, L2=0.8):
    ch = Chain(gravity=(0.0, 0.0, -G))
    ch.add("a", RigidLink(L1, m1, centre=(L1, 0, 0), inertia=(0, 0, 0)), Joint.revolute("y", rotation=DOWN))
    ch.add("b", RigidLink(L2, m2, centre=(L2, 0, 0), inertia=(0, 0, 0)), Joint.revolute("y"), parent="a")
    return ch.compile()


def double_pendulum_closed_form(q, qd, m1=1.3, m2=0.7, L1=1.1, L2=0.8):
    """Lagrange's equations in the absolute angles th1 = a, th2 = a + b, mapped to (a, b)."""
    th1, th2 = q[0], q[0] + q[1]
    w1, w2 = qd[0], qd[0] + qd[1]
    d = th1 - th2
    Mt = np.array([[(m1 + m2) * L1 ** 2, m2 * L1 * L2 * np.cos(d)], [m2 * L1 * L2 * np.cos(d), m2 * L2 ** 2]])
    Ft = np.array([-m2 * L1 * L2 * w2 ** 2 * np.sin(d) - (m1 + m2) * G * L1 * np.sin(th1),
                   m2 * L1 * L2 * w1 ** 2 * np.sin(d) - m2 * G * L2 * np.sin(th2)])
    J = np.array([[1.0, 0.0], [1.0, 1.0]])
    return J.T @ Mt @ J, J.T @ Ft


def test_double_pendulum_matches_closed_form_equations():
    model = double_pendulum()
    rng = np.random.default_rng(0)
    for _ in range(5):
        q, qd = rng.uniform(-3, 3, 2), rng.uniform(-3, 3, 2)
        A, f = equations(model, 0.0, q, qd)
        Mc, Fc = double_pendulum_closed_form(q, qd)
        assert np.abs(A - Mc).max() < 1e-13
        assert np.abs(f - Fc).max() < 1e-12


def test_double_pendulum_small_oscillations_and_energy():
    """Equal masses and lengths: w^2 = (g/L)(2 -+ sqrt 2); RK4 conserves E to 1e-8 over 5 s."""
    model = double_pendulum(1.0, 1.0, 1.0, 1.0)
    w, _ = chain_modes(model, np.zeros(2))
    assert w == pytest.approx(np.sqrt(G * (2 + np.array([-1, 1]) * np.sqrt(2))), rel=1e-8)
    res = simulate_chain(model, 5.0, 1e-3, q0=[1.2, -0.7], output_every=100)
    e = res.energy()
    total = e["kinetic"] + e["gravity"]
    assert np.abs(total - total[0]).max() < 1e-8 * abs(total[0])
    assert e["kinetic"].max() > 1.0                                  # it did move


def hanging_chain(n, L=10.0, mu=2.0):
    ch = Chain(gravity=(0.0, 0.0, -G))
    ell = L / n
    parent = None
    for i in range(n):
        joint = Joint.revolute("y", rotation=DOWN if i == 0 else None)
        ch.add(f"l{i}", RigidLink(ell, mu * ell), joint, parent=parent)
        parent = f"l{i}"
    return ch.compile()


@pytest.mark.parametrize("n", [10, 20])
def test_B5_hanging_chain_first_mode(n):
    """A chain of n rigid rods pinned at the top: omega_1 = 1.20241 sqrt(g/L) within 0.1 %."""
    L = 10.0
    w, _ = chain_modes(hanging_chain(n, L), np.zeros(n))
    assert w[0] == pytest.approx(CHAIN_C[0] * np.sqrt(G / L), rel=1e-3)


def test_B5_hanging_chain_higher_modes_converge_as_n_squared():
    """Modes 2 and 3 converge to c_n from above with order 2; at n = 40 within 0.1 % and 0.5 %."""
    L = 10.0
    errs = np.array([chain_modes(hanging_chain(n, L), np.zeros(n))[0][1:3] / (CHAIN_C[1:3] * np.sqrt(G / L)) - 1
                     for n in (10, 20, 40)])
    assert np.all(errs > 0)
    orders = np.log2(errs[:-1] / errs[1:])
    assert np.all(np.abs(orders - 2.0) < 0.25), (errs, orders)
    assert errs[-1, 0] < 1e-3 and errs[-1, 1] < 5e-3


@pytest.mark.parametrize("theta0", [90.0])
def test_B9_large_amplitude_pendulum(theta0):
    """A rigid rod released at 90 deg: T/T0 = 1.180341 (1e-4)."""
    L = 2.0
    ch = Chain(gravity=(0.0, 0.0, -G))
    ch.add("rod", RigidLink(L, 3.0), Joint.revolute("y", rotation=DOWN))
    model = ch.compile()
    T0 = 2 * np.pi * np.sqrt(2 * L / (3 * G))
    dt = T0 / 2000
    res = simulate_chain(model, 1.3 * T0 * PENDULUM[theta0], dt, q0=[np.radians(theta0)])
    th = res.q[:, 0]
    i = np.flatnonzero(np.sign(th[:-1]) != np.sign(th[1:]))
    crossings = res.t[i] - th[i] * dt / (th[i + 1] - th[i])
    period = 2 * (crossings[1] - crossings[0])
    assert period / T0 == pytest.approx(PENDULUM[theta0], rel=1e-4)


# ----------------------------------------------------------------------------- base motion and drives
def test_pendulum_on_accelerating_base_stays_at_tan_theta_a_over_g():
    a = 3.0
    base = BaseMotion(lambda t: (np.array([0.5 * a * t * t, 0, 0]), np.array([a * t, 0, 0]), np.array([a, 0, 0])))
    ch = Chain(gravity=(0.0, 0.0, -G), base=base)
    ch.add("rod", RigidLink(1.5, 2.0), Joint.revolute("y", rotation=DOWN))
    model = ch.compile()
    th = np.arctan(a / G)
    res = simulate_chain(model, 1.0, 1e-3, q0=[th], output_every=100)
    assert np.abs(res.q[:, 0] - th).max() < 1e-10
    res = simulate_chain(model, 0.05, 1e-3, q0=[0.0])
    assert res.qdd[0, 0] == pytest.approx(a / (2.0 / 3.0 * 1.5), rel=1e-10)   # tipping backwards from rest


def spin(t, rate=2.0, ramp=1.0):
    """Smooth spin-up to `rate` rad/s over `ramp` s: (angle, rate, acceleration)."""
    if t < ramp:
        return (rate / ramp * (t * t / 2 + (ramp / (2 * np.pi)) ** 2 * (np.cos(2 * np.pi * t / ramp) - 1)),
                rate / ramp * (t - ramp / (2 * np.pi) * np.sin(2 * np.pi * t / ramp)),
                rate / ramp * (1 - np.cos(2 * np.pi * t / ramp)))
    return rate * (t - ramp / 2), rate, 0.0


def test_prescribed_joint_equals_the_same_motion_of_the_base():
    """A flexible modified beam on a hub turned by a prescribed revolute joint moves exactly
    as on a base turned by the same angle (prescribed accelerations in the velocity terms)."""
    props = BeamProperties(EA=None, EIy=50.0, EIz=50.0, GJ=40.0, mass_per_length=1.0, rotary_inertia=0.0,
                           polar_inertia=1e-3)
    a = Chain(gravity=(0, 0, -G))
    a.add("hub", RigidLink(0.3, 1.0), Joint.revolute("z", drive=Prescribed(spin)))
    a.add("beam", ModifiedLink(2.0, 4, props, dofs=("ry", "rz")), parent="hub")
    b = Chain(gravity=(0, 0, -G), base=BaseMotion.rotating("z", spin))
    b.add("hub", RigidLink(0.3, 1.0))
    b.add("beam", ModifiedLink(2.0, 4, props, dofs=("ry", "rz")), parent="hub")
    ra = simulate_chain(a.compile(), 1.5, 2e-3, output_every=50)
    rb = simulate_chain(b.compile(), 1.5, 2e-3, output_every=50)
    pa = ra.point("beam", 2.0)[0]
    pb = rb.point("beam", 2.0)[0]
    assert np.abs(pa - pb).max() < 1e-10
    assert np.abs(pa[-1] - pa[0]).max() > 0.5                          # it did turn


def test_joint_torque_drive_accelerates_as_torque_over_inertia():
    tau, m, L = 4.0, 3.0, 2.0
    ch = Chain(gravity=(0.0, 0.0, -G))
    ch.add("rod", RigidLink(L, m), Joint.revolute("z", drive=JointForce(lambda t, q, qd: tau)))
    model = ch.compile()
    qdd = accelerations(model, ChainData(model), 0.0, np.zeros(1), np.zeros(1))
    assert qdd[0] == pytest.approx(tau / (m * L ** 2 / 3), rel=1e-12)


# ----------------------------------------------------------------------------- geometric stiffening
KANE = {"L": 10.0, "EI": 7e10 * 2e-7, "mu": 3000.0 * 4e-4, "rate": 6.0, "ramp": 15.0}


def kane_spin_up(formulation, n, dt, t_end, EA=7e10 * 4e-4 * 1e-2):
    """Kane, Ryan & Banerjee (1987) spin-up: a 10 m beam on a hub spun to 6 rad/s in 15 s,
    above its first bending frequency (3.8 rad/s). Returns t and the tip deflection in the
    rotating frame."""
    k = KANE
    props = BeamProperties(EA=EA, EIy=k["EI"], EIz=k["EI"], GJ=k["EI"], mass_per_length=k["mu"], rotary_inertia=0.0)
    if formulation == "modified":
        link = ModifiedLink(k["L"], n, props, dofs=("rz",))
    else:
        link = ClassicalLink(k["L"], n, props, linear=formulation == "classical-linear", dofs=("x", "y", "rz"))

    def angle(t):
        return spin(t, k["rate"], k["ramp"])
    ch = Chain(gravity=(0, 0, 0), base=BaseMotion.rotating("z", angle))
    ch.add("beam", link)
    res = simulate_chain(ch.compile(), t_end, dt, output_every=max(1, int(0.05 / dt)))
    p = res.point("beam", k["L"])[0]
    th = np.array([angle(t)[0] for t in res.t])
    return res.t, -np.sin(th) * p[:, 0] + np.cos(th) * p[:, 1]


def kane_quasi_static_limit():
    """Tip deflection under the peak inertial load mu*alpha_max*x without centrifugal
    stiffening: 11 q0 L^4 / (120 EI), q0 = mu alpha_max L, alpha_max = 2 rate / ramp."""
    k = KANE
    q0 = k["mu"] * 2 * k["rate"] / k["ramp"] * k["L"]
    return 11 * q0 * k["L"] ** 4 / (120 * k["EI"])


def test_spin_up_modified_shows_geometric_stiffening():
    """The tip lags by less than the unstiffened quasi-static limit (0.629 m) and returns to
    the hub's radial line after spin-up (stays bounded at 6 rad/s > first bending frequency)."""
    t, w = kane_spin_up("modified", 6, 4e-3, 18.0)
    limit = kane_quasi_static_limit()
    assert limit == pytest.approx(0.629, abs=1e-3)
    assert 0.8 * limit < -w.min() < limit
    assert np.abs(w[t > 15.5]).max() < 0.02 * limit


@pytest.mark.slow
def test_spin_up_classical_nonlinear_agrees_linear_diverges():
    """The nonlinear classical model stiffens like the modified one (peak within 5 %); the
    linear model (eq. 8.8) has no geometric stiffness and diverges above the first bending
    frequency (Kane's result)."""
    t, w_mod = kane_spin_up("modified", 6, 4e-3, 18.0)
    t, w_cl = kane_spin_up("classical", 6, 1e-3, 18.0)
    assert w_cl.min() == pytest.approx(w_mod.min(), rel=5e-2)
    assert np.abs(w_cl[t > 15.5]).max() < 0.02 * kane_quasi_static_limit()
    t, w_lin = kane_spin_up("classical-linear", 6, 1e-3, 12.0)
    assert np.abs(w_lin).max() > 10 * kane_quasi_static_limit()


def test_linear_classical_modes_of_a_1000_rfe_line_use_sparsity():
    """1000 RFEs x 6 coordinates (6000 unknowns): the sparse path (constant diagonal M,
    block-tridiagonal K) gives the first bending pair at 3.516 sqrt(EI/(mu L^4)) (within the
    discretisation and shear error, 1e-3)."""
    props = BeamProperties(EA=1e9, EIy=1e6, EIz=1e6, GJ=8e5, mass_per_length=10.0, rotary_inertia=0.0,
                           polar_inertia=0.02)
    link = ClassicalLink(100.0, 1000, props, linear=True)
    w, shapes = linear_modes(link, 4)
    w1 = BETA_L[0] ** 2 * np.sqrt(1e6 / (10.0 * 100.0 ** 4))
    assert w[:2] == pytest.approx([w1, w1], rel=1e-3)
    assert shapes.shape == (6000, 4)
