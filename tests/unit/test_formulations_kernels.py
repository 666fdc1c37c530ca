"""rfesim.formulations: transforms, composite-body mass matrix and velocity terms against
the trace-form reference (eqs. 8.7-8.20, 8.31, 8.43), elastic terms (8.21-8.29, 8.35, 8.49)."""
from __future__ import annotations

import formulations_reference as ref
import numpy as np
import pytest

from rfesim.formulations import (
    BaseMotion,
    BeamProperties,
    Chain,
    ClassicalLink,
    Joint,
    ModifiedLink,
    RigidLink,
    equations,
    linear_matrices,
    point_motion,
    tree,
)
from rfesim.formulations import chain as chain_mod
from rfesim.formulations.transforms import (
    FREE_LINEAR,
    FREE_ZYX,
    REVOLUTE,
    SPHERICAL,
    joint_motion_into,
    pseudo_inertia,
)

ROUNDOFF = 1e-12
SEEDS = [0, 1, 2]


def motion(kind, q, axis=(0.0, 0.0, 1.0)):
    M = np.empty((4, 4))
    dM = np.zeros((6, 4, 4))
    d2M = np.zeros((6, 6, 4, 4))
    joint_motion_into(kind, np.asarray(axis, float), np.asarray(q, float), M, dM, d2M, np.empty((4, 3, 3)))
    return M, dM, d2M


def literal_8_7(q):
    """eq. 8.7 as printed (works with complex numbers for complex-step derivatives)."""
    x, y, z, px, py, pz = q
    cx, sx, cy, sy, cz, sz = np.cos(px), np.sin(px), np.cos(py), np.sin(py), np.cos(pz), np.sin(pz)
    return np.array([[cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx, x],
                     [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx, y],
                     [-sy, cy * sx, cy * cx, z],
                     [0 * x, 0 * x, 0 * x, 1 + 0 * x]])


# ----------------------------------------------------------------------------- transforms
@pytest.mark.parametrize("seed", SEEDS)
def test_zyx_matrix_and_first_derivatives_match_eq_8_7_by_complex_step(seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(-1.2, 1.2, 6)
    M, dM, _ = motion(FREE_ZYX, q)
    assert np.abs(M - literal_8_7(q)).max() < ROUNDOFF
    h = 1e-30
    for k in range(6):
        qc = q.astype(complex)
        qc[k] += 1j * h
        assert np.abs(dM[k] - literal_8_7(qc).imag / h).max() < ROUNDOFF


@pytest.mark.parametrize("kind", [FREE_ZYX, SPHERICAL, REVOLUTE])
def test_second_derivatives_are_derivatives_of_the_first(kind):
    rng = np.random.default_rng(7)
    n = {FREE_ZYX: 6, SPHERICAL: 3, REVOLUTE: 1}[kind]
    q = rng.uniform(-1.2, 1.2, n)
    axis = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    _, _dM, d2M = motion(kind, q, axis)
    h = 1e-5
    for l in range(n):
        qp, qm = q.copy(), q.copy()
        qp[l] += h
        qm[l] -= h
        fd = (motion(kind, qp, axis)[1] - motion(kind, qm, axis)[1]) / (2 * h)
        for k in range(n):
            assert np.abs(d2M[k, l] - fd[k]).max() < 1e-9
            assert np.abs(d2M[k, l] - d2M[l, k]).max() == 0.0


def test_linear_matrix_is_eq_8_8_and_first_order_of_eq_8_7():
    q = np.array([0.1, -0.2, 0.3, 1e-4, -2e-4, 3e-4])
    M, _dM, d2M = motion(FREE_LINEAR, q)
    x, y, z, px, py, pz = q
    expected = np.array([[1, -pz, py, x], [pz, 1, -px, y], [-py, px, 1, z], [0, 0, 0, 1]])
    assert np.abs(M - expected).max() == 0.0
    assert np.abs(M - literal_8_7(q)).max() < 1e-7                 # differs at second order
    assert np.abs(d2M).max() == 0.0


def test_revolute_is_a_rotation_about_its_axis():
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    M, _, _ = motion(REVOLUTE, [0.7], axis)
    R = M[:3, :3]
    assert np.abs(R @ R.T - np.eye(3)).max() < ROUNDOFF
    assert np.abs(R @ axis - axis).max() < ROUNDOFF
    assert np.trace(R) == pytest.approx(1 + 2 * np.cos(0.7), abs=ROUNDOFF)


def test_pseudo_inertia_gives_rigid_body_kinetic_energy():
    """1/2 tr(T' H T'^T) = 1/2 m v_C^2 + 1/2 w.J w (eq. 8.15 for one rigid body)."""
    rng = np.random.default_rng(3)
    m, c, J = 2.5, rng.normal(size=3), np.array([0.3, 0.5, 0.7])
    H = pseudo_inertia(m, c, J)
    q, qd = rng.normal(size=6), rng.normal(size=6)
    T, dT, _ = motion(FREE_ZYX, q)
    Td = np.einsum("kij,k->ij", dT, qd)
    R = T[:3, :3]
    W = Td[:3, :3] @ R.T                                             # [w]x in the inertial frame
    w = np.array([W[2, 1], W[0, 2], W[1, 0]])
    vC = Td[:3, :3] @ c + Td[:3, 3]
    wb = R.T @ w
    assert 0.5 * np.trace(Td @ H @ Td.T) == pytest.approx(0.5 * m * vC @ vC + 0.5 * wb @ (J * wb), rel=1e-12)


# ----------------------------------------------------------------------------- models
def props(**kw):
    base = {"EA": 3e4, "EIy": 40.0, "EIz": 60.0, "GJ": 30.0, "mass_per_length": 2.0, "rotary_inertia": 0.01, "polar_inertia": 0.02,
                "damping": 0.0}
    base.update(kw)
    return BeamProperties(**base)


def moving_base():
    return BaseMotion(lambda t: (np.array([0.3 * np.sin(t), 0.1, 0.2 * t]), np.array([0.3 * np.cos(t), 0, 0.2]),
                                 np.array([-0.3 * np.sin(t), 0, 0])),
                      lambda t: (np.array([0.1 * t, -0.2, 0.4 * t * t]), np.array([0.1, 0, 0.8 * t]),
                                 np.array([0.0, 0.0, 0.8])))


def build(name):
    ch = Chain(gravity=(0.3, -0.2, -9.81), base=moving_base())
    if name == "classical":
        ch.add("arm", RigidLink(1.0, 3.0, inertia=(0.1, 0.2, 0.3)), Joint.revolute("z"))
        ch.add("beam", ClassicalLink(2.0, 3, props()), Joint.revolute((0.0, 1.0, 1.0), offset=(0, 0.1, 0)),
               parent="arm")
    elif name == "classical-linear":
        ch.add("beam", ClassicalLink(2.0, 4, props(), linear=True), Joint.spherical())
    elif name == "modified":
        ch.add("slide", RigidLink(0.5, 1.0, inertia=(0.1, 0.1, 0.1)), Joint.prismatic("x"))
        ch.add("beam", ModifiedLink(2.0, 4, props()), Joint.spherical(), parent="slide")
    elif name == "mixed":
        ch.add("a", ClassicalLink(1.5, 2, props()), Joint.revolute("y"))
        ch.add("b", ModifiedLink(1.0, 3, props()), Joint.revolute("z"), parent="a")
        ch.add("c", RigidLink(0.4, 0.7, inertia=(0.01, 0.02, 0.03)), Joint.revolute("x"), parent="b", at=0.5)
        ch.add_load("b", 1.0, force=(1.0, -2.0, 3.0), moment=(0.5, 0.2, -0.4))
        ch.add_load("a", 0.6, force=(-1.0, 0.5, 0.2), moment=(0.1, -0.3, 0.2), offset=(0, 0.05, 0.02))
    return ch.compile()


MODELS = ["classical", "classical-linear", "modified", "mixed"]


def random_state(model, rng, scale=0.4):
    return rng.uniform(-scale, scale, model.nq), rng.uniform(-1.0, 1.0, model.nq)


# ----------------------------------------------------------------------------- fast vs reference
@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("seed", [0, 1])
def test_composite_assembly_equals_trace_form_reference(name, seed):
    """A, e + G - Q and the kinetic energy from the composite-body recursion equal the
    per-body trace form of eqs. 8.17/8.43, 8.20 and 8.31 to round-off, on a moving base."""
    model = build(name)
    rng = np.random.default_rng(seed)
    q, qd = random_state(model, rng)
    t = 0.37
    data = chain_mod.ChainData(model)
    chain_mod.evaluate(model, data, t, q, qd, np.zeros(model.nq))
    forces = np.array([chain_mod._value(F, t) for F in model.load_force]).reshape(-1, 3)
    moments = np.array([chain_mod._value(M, t) for M in model.load_moment]).reshape(-1, 3)
    A, e, G, Q, kinetic = ref.lagrange_terms(model, t, q, qd, forces, moments)
    scaleA = np.abs(A).max()
    assert np.abs(data.A - A).max() < ROUNDOFF * scaleA
    h_ref = e + G - Q
    assert np.abs(data.h - h_ref).max() < 1e-11 * max(1.0, np.abs(h_ref).max())
    _TA, _TAd, _TAdd = model.base(t)
    assert tree.kinetic_energy(model.inertia, data.Td) == pytest.approx(kinetic, rel=1e-12)


@pytest.mark.parametrize("name", MODELS)
def test_mass_matrix_symmetric_positive_definite_and_kinetic_energy(name):
    """A symmetric positive definite; with the base at rest E = 1/2 q'^T A q' (eq. 8.42)."""
    model = build(name)
    model.base = BaseMotion()
    rng = np.random.default_rng(11)
    q, qd = random_state(model, rng)
    data = chain_mod.ChainData(model)
    chain_mod.evaluate(model, data, 0.0, q, qd, np.zeros(model.nq))
    A = data.A
    assert np.abs(A - A.T).max() == 0.0
    assert np.linalg.eigvalsh(A).min() > 0.0
    E = tree.kinetic_energy(model.inertia, data.Td)
    assert E == pytest.approx(0.5 * qd @ A @ qd, rel=1e-12)


@pytest.mark.parametrize("name", MODELS)
def test_branch_sparse_ltl_solve_equals_dense_solve(name):
    model = build(name)
    rng = np.random.default_rng(5)
    q, qd = random_state(model, rng)
    A, _ = equations(model, 0.2, q, qd)
    fr = model.free
    Aff = A[np.ix_(fr, fr)]
    b = rng.normal(size=len(fr))
    L = Aff.copy()
    assert tree.ltl_factor(L, model.lam)
    x = np.empty(len(fr))
    tree.ltl_solve(L, model.lam, b.copy(), x)
    assert np.abs(x - np.linalg.solve(Aff, b)).max() < 1e-10 * np.abs(x).max()


def test_classical_mass_matrix_has_the_arrow_structure_of_eq_8_34():
    """RFE blocks couple only with RFE 0 / the preceding links; in the linear model they are
    constant and diagonal (m, m, m, Jx, Jy, Jz)."""
    model = build("classical-linear")
    rng = np.random.default_rng(2)
    A1, _ = equations(model, 0.1, *random_state(model, rng))
    A2, _ = equations(model, 0.9, *random_state(model, rng))
    info = model.links["beam"]
    blocks = [model.qstart[info.first_body + i] for i in range(1, info.nbodies)]
    mass, _, _ = linear_matrices(info.link)
    for i, si in enumerate(blocks):
        for j, sj in enumerate(blocks):
            B1, B2 = A1[si:si + 6, sj:sj + 6], A2[si:si + 6, sj:sj + 6]
            if i == j:
                assert np.abs(B1 - np.diag(mass[6 * i:6 * i + 6])).max() < ROUNDOFF * mass.max()
                assert np.abs(B1 - B2).max() < ROUNDOFF * mass.max()
            else:
                assert np.abs(B1).max() == 0.0


# ----------------------------------------------------------------------------- elastic terms
def elastic_forces(model, q, qd=None):
    data = chain_mod.ChainData(model)
    qd = np.zeros(model.nq) if qd is None else qd
    chain_mod.evaluate(model, data, 0.0, q, qd, np.zeros(model.nq), mass=False)
    return data.S.copy(), data.elastic_energy


@pytest.mark.parametrize("name", ["classical", "classical-linear"])
def test_classical_sde_forces_are_the_gradient_of_eq_8_21(name):
    model = build(name)
    rng = np.random.default_rng(4)
    q, _ = random_state(model, rng, scale=0.3)
    S, V = elastic_forces(model, q)
    assert V == pytest.approx(ref.classical_elastic(model, q), rel=1e-12)
    h = 1e-6
    for k in range(model.nq):
        qp, qm = q.copy(), q.copy()
        qp[k] += h
        qm[k] -= h
        fd = (ref.classical_elastic(model, qp) - ref.classical_elastic(model, qm)) / (2 * h)
        assert S[k] == pytest.approx(fd, rel=1e-6, abs=1e-6 * np.abs(S).max())


def test_linear_classical_forces_are_the_constant_matrix_form_of_eq_8_35():
    """S = K q + S_c with K = K_R + K_T block-tridiagonal (eqs. 8.26, 8.34, 8.35), to round-off."""
    ch = Chain(gravity=(0, 0, 0))
    link = ClassicalLink(3.0, 5, props(), linear=True)
    ch.add("beam", link)
    model = ch.compile()
    rng = np.random.default_rng(8)
    q = rng.normal(size=model.nq) * 0.1
    S, V = elastic_forces(model, q)
    _, K, Sc = linear_matrices(link)
    qf = q                                                           # RFE 0 is fixed: no coordinates of its own
    assert np.abs(S - (K @ qf + Sc)).max() < ROUNDOFF * np.abs(S).max()
    assert V == pytest.approx(0.5 * qf @ (K @ qf), rel=1e-12)
    Kd = K.toarray()
    assert np.abs(Kd - Kd.T).max() == 0.0
    for i in range(5):
        for j in range(5):
            if abs(i - j) > 1:
                assert np.abs(Kd[6 * i:6 * i + 6, 6 * j:6 * j + 6]).max() == 0.0


def test_modified_elastic_forces_are_eq_8_49_with_kelvin_voigt_damping():
    ch = Chain(gravity=(0, 0, 0))
    p = props(damping=0.01)
    ch.add("beam", ModifiedLink(2.0, 4, p))
    model = ch.compile()
    rng = np.random.default_rng(9)
    q, qd = rng.normal(size=model.nq), rng.normal(size=model.nq)
    S, V = elastic_forces(model, q, qd)
    c = np.tile(np.array([p.GJ, p.EIy, p.EIz]) / 0.5, 4)
    assert np.abs(S - (c * q + 0.01 * c * qd)).max() < ROUNDOFF * np.abs(S).max()
    assert V == pytest.approx(0.5 * np.sum(c * q * q), rel=1e-12)


# ----------------------------------------------------------------------------- points
def test_point_velocity_and_acceleration_are_time_derivatives_of_position():
    model = build("mixed")
    rng = np.random.default_rng(12)
    q, qd = random_state(model, rng)
    qdd = rng.normal(size=model.nq)

    def pos(t):
        qq = q + qd * t + 0.5 * qdd * t * t
        return point_motion(model, 0.3 + t, qq, qd + qdd * t, qdd, "b", 0.8, offset=(0.0, 0.1, -0.05))[0]

    p, v, a = point_motion(model, 0.3, q, qd, qdd, "b", 0.8, offset=(0.0, 0.1, -0.05))
    h = 1e-4
    assert np.abs(v - (pos(h) - pos(-h)) / (2 * h)).max() < 1e-7
    assert np.abs(a - (pos(h) - 2 * p + pos(-h)) / h ** 2).max() < 1e-5
