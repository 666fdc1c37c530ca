"""Slow, readable planar RFE formulation straight from the chapter (section 8.3, eqs.
8.52-8.70), for checking the O(n) kernels of rfesim.formulations.planar_kernels.

Everything is dense and per-entry: h_{i,j} and phi_{i,j} of eq. 8.53, the coefficients
a_bar, b_bar, A_bar, alpha of eq. 8.57, the mass matrix A, the velocity matrix B_bar of
eq. 8.59, gravity eq. 8.61, the constant stiffness and damping matrices C, D of eqs.
8.62-8.63, the generalised forces of point loads eqs. 8.64-8.65, and the equations of motion
8.66 with the reactions of the base (eqs. 8.67-8.70) and of a fixed end B by Lagrange
multipliers, solved with numpy.linalg.solve.

Two sign details the chapter's typesetting leaves open are fixed from the kinetic energy
(docs/theory.md, "Planar formulation"): the arctangents are quadrant-correct (atan2), and
m_ij = A_bar_ij cos(phi_i - phi_j + alpha_ij) with alpha_ij = atan2(b_bar_ij, a_bar_ij).
"""
from __future__ import annotations

import math

import numpy as np


def geometry(model):
    """h[i, j], phi_ij[i, j] of eq. 8.53 (zero for j > i), from the local joint coordinates
    (a_ii, b_ii) = joint_start[i] and (a_{i,i+1}, b_{i,i+1}) = joint_end[i]."""
    nr = model.mass.shape[0]
    a_start, b_start = model.joint_start[:, 0], model.joint_start[:, 1]
    a_end, b_end = model.joint_end[:, 0], model.joint_end[:, 1]
    h = np.zeros((nr, nr))
    ph = np.zeros((nr, nr))
    for i in range(nr):
        for j in range(i + 1):
            if j < i:
                h[i, j] = math.hypot(a_end[j] - a_start[j], b_end[j] - b_start[j])
                ph[i, j] = math.atan2(b_end[j] - b_start[j], a_end[j] - a_start[j])
            else:
                h[i, i] = math.hypot(a_start[i], b_start[i])
                ph[i, i] = math.atan2(-b_start[i], -a_start[i])   # arctg(b/a) + pi, quadrant-correct
    return h, ph


def centres(model, q):
    """Eq. 8.53: (x_ci, y_ci) of every RFE."""
    h, ph = geometry(model)
    phi = q[2:]
    nr = phi.shape[0]
    x = np.array([q[0] + sum(h[i, j] * math.cos(phi[j] + ph[i, j]) for j in range(i + 1)) for i in range(nr)])
    y = np.array([q[1] + sum(h[i, j] * math.sin(phi[j] + ph[i, j]) for j in range(i + 1)) for i in range(nr)])
    return x, y


def coefficients(model):
    """a_bar_i, b_bar_i, a_bar_ij, b_bar_ij of eq. 8.57."""
    h, ph = geometry(model)
    m = model.mass
    nr = m.shape[0]
    a_i = np.array([sum(m[j] * h[j, i] * math.cos(ph[j, i]) for j in range(i, nr)) for i in range(nr)])
    b_i = np.array([sum(m[j] * h[j, i] * math.sin(ph[j, i]) for j in range(i, nr)) for i in range(nr)])
    a_ij = np.zeros((nr, nr))
    b_ij = np.zeros((nr, nr))
    for i in range(nr):
        for j in range(nr):
            for l in range(max(i, j), nr):
                a_ij[i, j] += m[l] * h[l, i] * h[l, j] * math.cos(ph[l, i] - ph[l, j])
                b_ij[i, j] += m[l] * h[l, i] * h[l, j] * math.sin(ph[l, i] - ph[l, j])
            if i == j:
                a_ij[i, j] += model.inertia[i]
    return a_i, b_i, a_ij, b_ij


def mass_matrix(model, q):
    """A of eq. 8.57: [[M1, M2], [M2^T, M]]."""
    a_i, b_i, a_ij, b_ij = coefficients(model)
    A_i, alpha_i = np.hypot(a_i, b_i), np.arctan2(b_i, a_i)
    A_ij, alpha_ij = np.hypot(a_ij, b_ij), np.arctan2(b_ij, a_ij)
    phi = q[2:]
    nr = phi.shape[0]
    A = np.zeros((nr + 2, nr + 2))
    A[0, 0] = A[1, 1] = model.mass.sum()
    for i in range(nr):
        A[0, 2 + i] = A[2 + i, 0] = -A_i[i] * math.sin(phi[i] + alpha_i[i])
        A[1, 2 + i] = A[2 + i, 1] = A_i[i] * math.cos(phi[i] + alpha_i[i])
        for j in range(nr):
            A[2 + i, 2 + j] = A_ij[i, j] * math.cos(phi[i] - phi[j] + alpha_ij[i, j])
    return A


def velocity_matrix(model, q, qd):
    """B_bar of eq. 8.59 (column i+3 carries phi_dot_i)."""
    a_i, b_i, a_ij, b_ij = coefficients(model)
    A_i, alpha_i = np.hypot(a_i, b_i), np.arctan2(b_i, a_i)
    A_ij, alpha_ij = np.hypot(a_ij, b_ij), np.arctan2(b_ij, a_ij)
    phi, w = q[2:], qd[2:]
    nr = phi.shape[0]
    B = np.zeros((nr + 2, nr + 2))
    for i in range(nr):
        B[0, 2 + i] = -w[i] * A_i[i] * math.cos(phi[i] + alpha_i[i])
        B[1, 2 + i] = -w[i] * A_i[i] * math.sin(phi[i] + alpha_i[i])
        for j in range(nr):
            # d m_ji / d phi_i * phi_dot_i, m_ji = A_ji cos(phi_j - phi_i + alpha_ji)
            B[2 + j, 2 + i] = w[i] * A_ij[j, i] * math.sin(phi[j] - phi[i] + alpha_ij[j, i])
    return B


def gravity_gradient(model, q):
    """dVg/dq of eq. 8.61 with V_g = g sum m_i y_ci (eq. 8.60)."""
    h, ph = geometry(model)
    phi = q[2:]
    nr = phi.shape[0]
    g = model.gravity
    out = np.zeros(nr + 2)
    out[1] = g * model.mass.sum()
    for j in range(nr):
        out[2 + j] = g * sum(model.mass[i] * h[i, j] * math.cos(phi[j] + ph[i, j]) for i in range(j, nr))
    return out


def stiffness_and_damping(model):
    """Constant C and D of eqs. 8.62-8.63 and the offset C q_rest of curved links."""
    nr = model.mass.shape[0]
    C = np.zeros((nr + 2, nr + 2))
    D = np.zeros((nr + 2, nr + 2))
    offset = np.zeros(nr + 2)
    for s in range(nr - 1):
        idx = [2 + s, 3 + s]
        C[np.ix_(idx, idx)] += model.sde_stiffness[s] * np.array([[1.0, -1.0], [-1.0, 1.0]])
        D[np.ix_(idx, idx)] += model.sde_damping[s] * np.array([[1.0, -1.0], [-1.0, 1.0]])
        offset[idx] += model.sde_stiffness[s] * model.sde_rest_angle[s] * np.array([-1.0, 1.0])
    return C, D, offset


def load_forces(model, q, extra=()):
    """Eqs. 8.64-8.65: Q of dead point loads (P_x, P_y, M) at polar (r, gamma) from C_i;
    ``extra`` adds (rfe, local offset, force, moment) tuples."""
    h, ph = geometry(model)
    phi = q[2:]
    Q = np.zeros(q.shape[0])
    loads = [(model.load_rfe[k], model.load_offset[k], model.load_force[k], model.load_moment[k])
             for k in range(model.load_rfe.shape[0])] + list(extra)
    for i, offset, (px, py), mz in loads:
        r, gam = math.hypot(*offset), math.atan2(offset[1], offset[0])
        Q[0] += px
        Q[1] += py
        for j in range(i + 1):
            d = 1.0 if i == j else 0.0
            Q[2 + j] += (-(h[i, j] * math.sin(phi[j] + ph[i, j]) + d * r * math.sin(phi[j] + gam)) * px
                         + (h[i, j] * math.cos(phi[j] + ph[i, j]) + d * r * math.cos(phi[j] + gam)) * py
                         + d * mz)
    return Q


def end_point_jacobian(model, q):
    """d(B, phi_n)/dq for a fixed end B (rows x, y, phi_n): the K^T of eq. 8.67."""
    h, ph = geometry(model)
    phi = q[2:]
    nr = phi.shape[0]
    n = nr - 1
    offset_b = model.joint_end[n] - model.joint_start[n]           # from A_n along RFE n
    G = np.zeros((3, nr + 2))
    G[0, 0] = G[1, 1] = 1.0
    for j in range(nr):
        hj = h[n, j] if j < n else math.hypot(*offset_b)
        pj = ph[n, j] if j < n else math.atan2(offset_b[1], offset_b[0])
        G[0, 2 + j] = -hj * math.sin(phi[j] + pj)
        G[1, 2 + j] = hj * math.cos(phi[j] + pj)
    G[2, 2 + n] = 1.0
    return G


def end_point_curvature(model, q, qd):
    """d/dt(G) qd for the end-B constraint (the quadratic velocity term)."""
    h, ph = geometry(model)
    phi, w = q[2:], qd[2:]
    nr = phi.shape[0]
    n = nr - 1
    offset_b = model.joint_end[n] - model.joint_start[n]
    out = np.zeros(3)
    for j in range(nr):
        hj = h[n, j] if j < n else math.hypot(*offset_b)
        pj = ph[n, j] if j < n else math.atan2(offset_b[1], offset_b[0])
        out[0] += -hj * math.cos(phi[j] + pj) * w[j] ** 2
        out[1] += -hj * math.sin(phi[j] + pj) * w[j] ** 2
    return out


def right_hand_side(model, q, qd):
    """F - B qd - C q of eq. 8.66: Q_P - dVg/dq - (B_bar + D) qd - (C q - C q_rest)."""
    C, D, offset = stiffness_and_damping(model)
    B = velocity_matrix(model, q, qd) + D
    return load_forces(model, q) - gravity_gradient(model, q) - B @ qd - (C @ q - offset)


def accelerations(model, q, qd, base_acc):
    """Solve eq. 8.68 with the base reactions R(0) (eqs. 8.69-8.70) for the prescribed
    coordinates and Lagrange multipliers for a fixed end B. Returns (qdd, R0 (3,), RB (3,)):
    R0 force at A_0 and moment from the base on the link, RB force at B and moment."""
    A = mass_matrix(model, q)
    f = right_hand_side(model, q, qd)
    m = q.shape[0]
    prescribed = [k for k, p in enumerate([model.end_a >= 1, model.end_a >= 1, model.end_a == 2]) if p]
    rows_b = [0, 1] if model.end_b == 1 else ([0, 1, 2] if model.end_b == 2 else [])
    Gb = end_point_jacobian(model, q)[rows_b]
    gb = -end_point_curvature(model, q, qd)[rows_b]
    # unknowns: qdd (m), base reactions (len prescribed), end reactions (len rows_b)
    npres, nb = len(prescribed), len(rows_b)
    K = np.zeros((m + npres + nb, m + npres + nb))
    rhs = np.zeros(m + npres + nb)
    K[:m, :m] = A
    rhs[:m] = f
    for k, c in enumerate(prescribed):
        K[c, m + k] = -1.0                 # A qdd - R0 = f  (base force enters as +R0)
        K[m + k, c] = 1.0
        rhs[m + k] = base_acc[c]
    K[:m, m + npres:] = -Gb.T
    K[m + npres:, :m] = Gb
    rhs[m + npres:] = gb
    sol = np.linalg.solve(K, rhs)
    R0 = np.zeros(3)
    R0[prescribed] = sol[m:m + npres]
    RB = np.zeros(3)
    RB[rows_b] = sol[m + npres:]
    return sol[:m], R0, RB


def kinetic_energy(model, q, qd):
    """Eqs. 8.54-8.55 from the centre velocities of eq. 8.53 differentiated by hand."""
    h, ph = geometry(model)
    phi, w = q[2:], qd[2:]
    nr = phi.shape[0]
    e = 0.0
    for i in range(nr):
        vx = qd[0] - sum(h[i, j] * math.sin(phi[j] + ph[i, j]) * w[j] for j in range(i + 1))
        vy = qd[1] + sum(h[i, j] * math.cos(phi[j] + ph[i, j]) * w[j] for j in range(i + 1))
        e += 0.5 * model.mass[i] * (vx * vx + vy * vy) + 0.5 * model.inertia[i] * w[i] ** 2
    return e
