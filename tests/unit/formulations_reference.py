"""Slow, readable trace-form reference for rfesim.formulations (straight from chapter 8).

Every body's pose is the product of the base matrix and the joint matrices on its path
(eqs. 8.10.2, 8.14, 8.38); its derivatives T_k and T_kl by the product rule. Then, per
body and summed (eqs. 8.12, 8.17, 8.20, 8.31, 8.43, 8.45, 8.46):

    a_kl = tr(T_k H T_l^T)
    e_k  = sum_ij tr(T_k H T_ij^T) q'_i q'_j + tr(T_k H (T_A'' Tbar + 2 T_A' Tbar')^T)
    G_k  = -m g . (T_k r_C)
    Q_k  = F^T T_k r~ + sum of the moment terms of eq. 8.31

No recursion, no composite bodies: O(bodies x n^2) matrix products.
"""
from __future__ import annotations

import numpy as np

from rfesim.formulations.transforms import joint_matrices_into


def joint_terms(model, b, q):
    J = np.empty((4, 4))
    dJ = np.zeros((6, 4, 4))
    d2J = np.zeros((6, 6, 4, 4))
    s, n = model.qstart[b], model.qcount[b]
    joint_matrices_into(model.kind[b], model.axis[b], model.placement[b], np.ascontiguousarray(q[s:s + n]), J, dJ,
                        d2J, np.empty((4, 4)), np.empty((6, 4, 4)), np.empty((6, 6, 4, 4)), np.empty((4, 3, 3)))
    return J, dJ[:n], d2J[:n, :n]


def path(model, b):
    out = []
    while b >= 0:
        out.append(b)
        b = model.parent[b]
    return out[::-1]


def body_derivatives(model, b, q):
    """Tbar (pose relative to the base), {k: Tbar_k}, {(k, l): Tbar_kl} by the product rule."""
    bodies = path(model, b)
    terms = [joint_terms(model, c, q) for c in bodies]

    def product(replace):
        P = np.eye(4)
        for c, (J, dJ, d2J) in zip(bodies, terms):
            s = model.qstart[c]
            mine = [k - s for k in replace if s <= k < s + model.qcount[c]]
            if len(mine) == 0:
                M = J
            elif len(mine) == 1:
                M = dJ[mine[0]]
            else:
                M = d2J[mine[0], mine[1]]
            P = P @ M
        return P

    coords = [k for c in bodies for k in range(model.qstart[c], model.qstart[c] + model.qcount[c])]
    Tk = {k: product([k]) for k in coords}
    Tkl = {(k, l): product([k, l]) for k in coords for l in coords}
    return product([]), Tk, Tkl


def lagrange_terms(model, t, q, qd, load_force=None, load_moment=None):
    """(A, e, G, Q) of the whole model by the trace form, all coordinates."""
    nq = model.nq
    TA, TAd, TAdd = model.base(t)
    A = np.zeros((nq, nq))
    e = np.zeros(nq)
    G = np.zeros(nq)
    Q = np.zeros(nq)
    kinetic = 0.0
    for b in range(model.nbodies):
        H = model.inertia[b]
        Tbar, Tk, Tkl = body_derivatives(model, b, q)
        Tbar_dot = sum((Tk[k] * qd[k] for k in Tk), np.zeros((4, 4)))
        Tdot = TAd @ Tbar + TA @ Tbar_dot
        kinetic += 0.5 * np.trace(Tdot @ H @ Tdot.T)                        # eq. 8.15
        base = TAdd @ Tbar + 2.0 * TAd @ Tbar_dot
        for k in Tk:
            Tk_w = TA @ Tk[k]
            for l in Tk:
                A[k, l] += np.trace(Tk_w @ H @ (TA @ Tk[l]).T)               # eq. 8.17
                for j in Tk:
                    e[k] += np.trace(Tk_w @ H @ (TA @ Tkl[(l, j)]).T) * qd[l] * qd[j]
            e[k] += np.trace(Tk_w @ H @ base.T)
            rC = H[:, 3]                                                     # m [r_C; 1]
            G[k] += -model.gravity @ (Tk_w @ rC)[:3]                         # eq. 8.20
        for i in np.flatnonzero(model.load_body == b):
            r = np.append(model.load_point[i], 1.0)
            T = TA @ Tbar
            F = np.append(load_force[i], 0.0)
            Mloc = T[:3, :3].T @ load_moment[i]                              # moment in {p,i} axes
            for k in Tk:
                Tk_w = TA @ Tk[k]
                Q[k] += F @ Tk_w @ r                                         # eq. 8.31
                Q[k] += Mloc[0] * T[:3, 2] @ Tk_w[:3, 1] + Mloc[1] * T[:3, 0] @ Tk_w[:3, 2] \
                    + Mloc[2] * T[:3, 1] @ Tk_w[:3, 0]
    return A, e, G, Q, kinetic


def classical_elastic(model, q):
    """Elastic energy of the classical SDEs by eqs. 8.21-8.24 (for gradients by differences)."""
    V = 0.0
    for e in range(len(model.sde_left)):
        pts, angs = [], []
        for b, root, pt in ((model.sde_left[e], model.sde_left_root[e], model.sde_point_left[e]),
                            (model.sde_right[e], model.sde_right_root[e], model.sde_point_right[e])):
            if root:
                pts.append(pt)
                angs.append(np.zeros(3))
            else:
                J, _, _ = joint_terms(model, b, q)
                pts.append((J @ np.append(pt, 1.0))[:3])                     # eq. 8.22
                s = model.qstart[b]
                angs.append(q[s + 3:s + 6])
        dr = pts[1] - pts[0]                                                 # eq. 8.23
        dphi = angs[1] - angs[0]
        c = model.sde_stiffness[e]
        V += 0.5 * np.sum(c[:3] * dr ** 2) + 0.5 * np.sum(c[3:] * dphi ** 2)
    return V
