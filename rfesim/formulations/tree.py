"""Kinematic-tree kernels in the trace (4x4) form: poses, mass matrix, velocity terms.

Every formulation of this package (classical RFE, modified RFE, rigid links, joints)
compiles to one tree of bodies: body b hangs on body parent[b] (-1: the base {A}) through
a joint matrix J_b = C_b M_b(q_b) (`transforms`). Its pose is T_b = T_parent J_b
(eqs. 8.10.2, 8.14, 8.38) and its kinetic energy 1/2 tr(T_b' H_b T_b'^T) (eq. 8.15).

The chapter's Lagrange terms (eqs. 8.12, 8.17, 8.43) are

    a_kl = sum_b tr(T^b_k H_b T^b_l^T),
    e_k  = sum_b tr(T^b_k H_b (T^b'')^T)   with T^b'' evaluated at free q'' = 0,

summed over the bodies b that move with coordinate k (and l). Evaluated per entry, that
costs O(n) bodies x O(depth) matrix products for each of n^2 entries. Here it is
evaluated with a composite-body recursion (the trace-form counterpart of Featherstone's
CRBA and RNEA):

* Omega_k = T^c_k T_c^{-1} (4x4, c the body of coordinate k) maps the pose of every body
  below c to its derivative: T^b_k = Omega_k T_b (T_c is affine and invertible, also for
  the linear classical model, eq. 8.8);
* the composite pseudo-inertia Hc_d = sum_{b below d} T_b H_b T_b^T and the composite
  "inertial force" Fc_d = sum_{b below d} T_b H_b (T_b'' + Gamma)^T - point loads are
  accumulated leaves to root in O(n);
* a_kl = tr(Omega_k Hc_d Omega_l^T), with d the deeper of the two bodies, for the
  O(n * depth) pairs of coordinates on one branch; e_k + G_k - Q_k = tr(Omega_k Fc_c) (O(n)).

Cost: the poses and composites O(n); the mass matrix O(n * depth) entries of 16 flops
(O(n^2) for a modified-RFE chain, O(n) for a classical link whose RFEs all hang on RFE 0);
the equations are solved by the LTL^T factorisation of a branch-sparse matrix
(Featherstone 2005) in O(n * depth^2): O(n) for a classical link (eq. 8.34's arrow
structure), O(n^3) for the dense modified chain.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .transforms import affine_inverse_into, joint_matrices_into, joint_scratch, mul4_into


@njit(cache=True)
def forward_pass(parent, kind, axis, C, qstart, qcount, q, qd, qdd, TA, TAd, TAdd, T, Td, Tdd, Omega):
    """Poses T (nb, 4, 4), their time derivatives Td, Tdd (with the given qdd) and the
    coordinate twists Omega (nq, 4, 4) = T^c_k T_c^{-1}, parents before children."""
    nb = parent.shape[0]
    J, dJ, d2J, M, dM, d2M, work = joint_scratch()
    Jd = np.empty((4, 4))
    Jdd = np.empty((4, 4))
    tmp = np.empty((4, 4))
    tmp2 = np.empty((4, 4))
    Tinv = np.empty((4, 4))
    for b in range(nb):
        p = parent[b]
        if p < 0:
            P = TA
            Pd = TAd
            Pdd = TAdd
        else:
            P = T[p]
            Pd = Td[p]
            Pdd = Tdd[p]
        s = qstart[b]
        n = joint_matrices_into(kind[b], axis[b], C[b], q[s:s + qcount[b]], J, dJ, d2J, M, dM, d2M, work)
        for i in range(4):
            for j in range(4):
                vd = 0.0
                vdd = 0.0
                for a in range(n):
                    vd += dJ[a, i, j] * qd[s + a]
                    vdd += dJ[a, i, j] * qdd[s + a]
                    for c in range(n):
                        vdd += d2J[a, c, i, j] * qd[s + a] * qd[s + c]
                Jd[i, j] = vd
                Jdd[i, j] = vdd
        mul4_into(P, J, T[b])
        mul4_into(Pd, J, tmp)
        mul4_into(P, Jd, tmp2)
        for i in range(4):
            for j in range(4):
                Td[b, i, j] = tmp[i, j] + tmp2[i, j]
        mul4_into(Pdd, J, tmp)
        for i in range(4):
            for j in range(4):
                Tdd[b, i, j] = tmp[i, j]
        mul4_into(Pd, Jd, tmp)
        mul4_into(P, Jdd, tmp2)
        for i in range(4):
            for j in range(4):
                Tdd[b, i, j] += 2.0 * tmp[i, j] + tmp2[i, j]
        if n > 0:
            affine_inverse_into(T[b], Tinv)
            for a in range(n):
                mul4_into(P, dJ[a], tmp)
                mul4_into(tmp, Tinv, Omega[s + a])


@njit(cache=True)
def composite_pass(parent, H, T, Tdd, gravity, pl_body, pl_point, pl_force, pl_moment, Hc, Fc, Mc):
    """Composite pseudo-inertia Hc (nb, 4, 4), inertial-force matrix Fc (nb, 4, 4) and
    moment matrix Mc (nb, 3, 3) of every subtree, in the inertial frame.

    Fc_b = T_b H_b (T_b'' + Gamma)^T - sum (T_b r~) [F; 0]^T with Gamma[:3, 3] = -g, so that
    tr(Omega_k Fc) = e_k + G_k - Q_k(forces) (eqs. 8.12, 8.20, 8.31). The moment terms of
    eq. 8.31, sum_i M~_i (R e_a)^T R_k e_b with (a, b) = (3, 2), (1, 3), (2, 1) and
    M~ = R^T M the moment in the body axes, are tr(Omega_k[:3, :3] Mc) with
    Mc_b = sum_i M~_i (R e_b)(R e_a)^T (= M . omega_k for an orthogonal R).
    """
    nb = parent.shape[0]
    tmp = np.empty((4, 4))
    A = np.empty((4, 4))
    for b in range(nb):
        mul4_into(T[b], H[b], tmp)
        for i in range(4):
            for j in range(4):
                acc = 0.0
                for k in range(4):
                    acc += tmp[i, k] * T[b, j, k]
                Hc[b, i, j] = acc
        for i in range(4):
            for j in range(4):
                A[i, j] = Tdd[b, i, j]
        for i in range(3):
            A[i, 3] -= gravity[i]
        for i in range(4):
            for j in range(4):
                acc = 0.0
                for k in range(4):
                    acc += tmp[i, k] * A[j, k]
                Fc[b, i, j] = acc
        for i in range(3):
            for j in range(3):
                Mc[b, i, j] = 0.0
    for ip in range(pl_body.shape[0]):
        b = pl_body[ip]
        r = np.empty(4)
        for i in range(4):
            r[i] = T[b, i, 0] * pl_point[ip, 0] + T[b, i, 1] * pl_point[ip, 1] + T[b, i, 2] * pl_point[ip, 2] + T[b, i, 3]
        for i in range(4):
            for j in range(3):
                Fc[b, i, j] -= r[i] * pl_force[ip, j]
        ml = np.empty(3)
        for i in range(3):                                   # moment in the body axes
            ml[i] = T[b, 0, i] * pl_moment[ip, 0] + T[b, 1, i] * pl_moment[ip, 1] + T[b, 2, i] * pl_moment[ip, 2]
        for i in range(3):
            for j in range(3):
                Mc[b, i, j] += (ml[0] * T[b, i, 1] * T[b, j, 2] + ml[1] * T[b, i, 2] * T[b, j, 0]
                                + ml[2] * T[b, i, 0] * T[b, j, 1])
    for b in range(nb - 1, -1, -1):
        p = parent[b]
        if p >= 0:
            for i in range(4):
                for j in range(4):
                    Hc[p, i, j] += Hc[b, i, j]
                    Fc[p, i, j] += Fc[b, i, j]
            for i in range(3):
                for j in range(3):
                    Mc[p, i, j] += Mc[b, i, j]


@njit(cache=True, inline="always")
def _trace_product(A, B):
    """tr(A B) for 4x4 matrices."""
    acc = 0.0
    for i in range(4):
        for j in range(4):
            acc += A[i, j] * B[j, i]
    return acc


@njit(cache=True)
def generalized_bias(qstart, qcount, Omega, Fc, Mc, h):
    """h_k = e_k + G_k - Q_k (velocity, base-motion, gravity and point-load terms), (nq,)."""
    for c in range(qstart.shape[0]):
        for a in range(qcount[c]):
            k = qstart[c] + a
            Om = Omega[k]
            val = _trace_product(Om, Fc[c])
            for i in range(3):
                for j in range(3):
                    val -= Om[i, j] * Mc[c, j, i]
            h[k] = val


@njit(cache=True)
def mass_matrix(parent, qstart, qcount, Omega, Hc, A):
    """Composite-body assembly of the mass matrix A (nq, nq) (eqs. 8.17, 8.34, 8.43, 8.51):
    a_kl = tr(Omega_k Hc_d Omega_l^T) for coordinates on one branch; other entries zero."""
    A[:, :] = 0.0
    Y = np.empty((4, 4))
    for d in range(parent.shape[0]):
        for a in range(qcount[d]):
            l = qstart[d] + a
            Ol = Omega[l]
            for i in range(4):
                for j in range(4):
                    acc = 0.0
                    for m in range(4):
                        acc += Hc[d, i, m] * Ol[j, m]
                    Y[i, j] = acc
            c = d
            while c >= 0:
                for e in range(qcount[c]):
                    k = qstart[c] + e
                    if c == d and k > l:
                        break
                    v = _trace_product(Omega[k], Y)
                    A[k, l] = v
                    A[l, k] = v
                c = parent[c]


@njit(cache=True)
def kinetic_energy(H, Td):
    """E = 1/2 sum_b tr(T_b' H_b T_b'^T) (eqs. 8.15, 8.42)."""
    E = 0.0
    for b in range(H.shape[0]):
        for i in range(4):
            for j in range(4):
                for k in range(4):
                    E += 0.5 * Td[b, i, j] * H[b, j, k] * Td[b, i, k]
    return E


@njit(cache=True)
def gravity_potential(H, T, gravity):
    """V = -sum_b m_b g . r_C,b (eqs. 8.19, 8.44), r_C,b m_b = (T_b H_b e4)[:3]."""
    V = 0.0
    for b in range(H.shape[0]):
        for i in range(3):
            mr = T[b, i, 0] * H[b, 0, 3] + T[b, i, 1] * H[b, 1, 3] + T[b, i, 2] * H[b, 2, 3] + T[b, i, 3] * H[b, 3, 3]
            V -= gravity[i] * mr
    return V


@njit(cache=True)
def ltl_factor(Hm, lam):
    """In place H = L^T L for a branch-sparse symmetric positive definite H (Featherstone,
    RBDA Table 6.3): lam[k] < k is the parent coordinate of k (-1 at a root); H[i, j] may be
    non-zero only if i, j are on one branch. Cost O(n depth^2). Returns False if not SPD."""
    n = Hm.shape[0]
    for k in range(n - 1, -1, -1):
        if not Hm[k, k] > 0.0:
            return False
        Hm[k, k] = math.sqrt(Hm[k, k])
        i = lam[k]
        while i >= 0:
            Hm[k, i] /= Hm[k, k]
            i = lam[i]
        i = lam[k]
        while i >= 0:
            j = i
            while j >= 0:
                Hm[i, j] -= Hm[k, i] * Hm[k, j]
                j = lam[j]
            i = lam[i]
    return True


@njit(cache=True)
def ltl_solve(L, lam, b, x):
    """Solve L^T L x = b with the factor of ltl_factor (b is overwritten)."""
    n = L.shape[0]
    for i in range(n - 1, -1, -1):
        b[i] /= L[i, i]
        j = lam[i]
        while j >= 0:
            b[j] -= L[i, j] * b[i]
            j = lam[j]
    for i in range(n):
        v = b[i]
        j = lam[i]
        while j >= 0:
            v -= L[i, j] * x[j]
            j = lam[j]
        x[i] = v / L[i, i]
