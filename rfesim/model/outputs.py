"""Output quantities computed from an evaluated workspace: line points, SDE results and
end reactions. Effective tension is the axial SDE force (buoyancy is applied as a
distributed force, so the axial force is the effective tension)."""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..kinematics import cross_into, matvec_into


@njit(cache=True)
def reactions(km, att, ws, qdd, out):
    """Constraint force and moment (global, on the RFE) at every pinned or clamped end RFE:
    out (n, 6) = [F, M about the attached point]; zero for free RFEs."""
    c = np.empty(3)
    P = np.empty(3)
    aP = np.empty(3)
    al = np.empty(3)
    tmp = np.empty(3)
    tmp2 = np.empty(3)
    ac = np.empty(3)
    Fr = np.empty(3)
    for i in range(out.shape[0]):
        for k in range(6):
            out[i, k] = 0.0
        kind = km.rfe_kind[i]
        if kind == 0:
            continue
        a = km.rfe_attach[i]
        R = ws.R[i]
        matvec_into(att.R[a], km.rfe_attach_offset[i], P)
        for k in range(3):
            P[k] += att.p[a, k]
            c[k] = ws.r[i, k] - P[k]
        # acceleration of the attached point
        for k in range(3):
            tmp2[k] = P[k] - att.p[a, k]
        cross_into(att.alpha[a], tmp2, tmp)
        cross_into(att.w[a], tmp2, ac)
        cross_into(att.w[a], ac, tmp2)
        for k in range(3):
            aP[k] = att.a[a, k] + tmp[k] + tmp2[k]
        if kind == 1:
            matvec_into(ws.E[i], qdd[i, 3:6], tmp)
            for k in range(3):
                tmp[k] += ws.Edot[i, k]
            matvec_into(R, tmp, al)
        else:
            for k in range(3):
                al[k] = att.alpha[a, k]
        w = ws.w[i]
        cross_into(al, c, tmp)
        cross_into(w, c, tmp2)
        cross_into(w, tmp2, ac)
        for k in range(3):
            ac[k] += aP[k] + tmp[k]
        m = km.rfe_mass[i]
        for k in range(3):
            s = m * ac[k]
            for j in range(3):
                s += ws.Ma[i, k, j] * ac[j]
            Fr[k] = s - ws.F[i, k]
            out[i, k] = Fr[k]
        if kind == 2:
            # M_r = Jg alpha + w x Jg w - M - (P - r) x F_r   (about the centre), then about P
            for k in range(3):
                s = 0.0
                s2 = 0.0
                for j in range(3):
                    Jkj = 0.0
                    for l in range(3):
                        Jkj += R[k, l] * (km.rfe_inertia[i, l] + ws.Ja[i, l]) * R[j, l]
                    s += Jkj * al[j]
                    s2 += Jkj * w[j]
                tmp[k] = s
                tmp2[k] = s2
            cross_into(w, tmp2, ac)
            for k in range(3):
                tmp[k] += ac[k] - ws.M[i, k]
            for k in range(3):
                tmp2[k] = -c[k]          # P - r
            cross_into(tmp2, Fr, ac)
            for k in range(3):
                out[i, 3 + k] = tmp[k] - ac[k]


@njit(cache=True)
def line_points(ws, rfe_start, rfe_stop, sde_start, sde_stop, rfe_length, out):
    """Points of a line: end A, every SDE point, end B -> out (nsde + 2, 3)."""
    i0 = rfe_start
    i1 = rfe_stop - 1
    for k in range(3):
        out[0, k] = ws.r[i0, k] - 0.5 * rfe_length[i0] * ws.R[i0, k, 0]
        out[out.shape[0] - 1, k] = ws.r[i1, k] + 0.5 * rfe_length[i1] * ws.R[i1, k, 0]
    for s in range(sde_start, sde_stop):
        for k in range(3):
            out[1 + s - sde_start, k] = ws.sde_point[s, k]


@njit(cache=True)
def sde_channels(ws, sde_length, tension, shear, bend, torque, curvature):
    for s in range(ws.sigma.shape[0]):
        sg = ws.sigma[s]
        tension[s] = sg[0]
        shear[s] = math.sqrt(sg[1] * sg[1] + sg[2] * sg[2])
        torque[s] = sg[3]
        bend[s] = math.sqrt(sg[4] * sg[4] + sg[5] * sg[5])
        e = ws.eps[s]
        curvature[s] = math.sqrt(e[4] * e[4] + e[5] * e[5]) / sde_length[s]
