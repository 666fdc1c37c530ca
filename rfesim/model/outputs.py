"""Output quantities computed from an evaluated workspace: line points, SDE results and
end reactions. Effective tension is the axial SDE force (buoyancy is applied as a
distributed force, so the axial force is the effective tension)."""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..kinematics import cross_into, matvec_into
from ..loads.drives import torsion_moment_into
from ..loads.sde import sde_forces_rest_into


@njit(cache=True, _nrt=True)
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


@njit(cache=True)
def sde_end_loads_many(km, ws, sdes, F, M, out):
    """sde_end_loads of each SDE in ``sdes`` into out (m, 4, 3)."""
    # one set of scratch arrays for all of them (allocating and zeroing it per SDE cost more
    # than the SDE's loads)
    sc = _end_scratch()
    for j in range(sdes.shape[0]):
        sde_end_loads_scratch(km, ws, sdes[j], F, M, out[j], sc[0], sc[1], sc[2], sc[3], sc[4], sc[5], sc[6])


@njit(cache=True)
def sde_end_loads(km, ws, s, F, M, out):
    """Loads of SDE s of an evaluated workspace on its two RFEs, each about the RFE's end
    point at the SDE (eq. 8.90, as rfesim.loads.sde.sde_forces_rest_into applies them, rest
    rotations and drives included): out (4, 3) = [force on the left RFE, its moment, force
    on the right RFE, its moment]. F, M (n, 3) are scratch."""
    sc = _end_scratch()
    sde_end_loads_scratch(km, ws, s, F, M, out, sc[0], sc[1], sc[2], sc[3], sc[4], sc[5], sc[6])


@njit(cache=True, _nrt=True)
def _end_scratch():
    """Scratch of sde_end_loads_scratch: sig (1, 6), eps (1, 6), point (1, 3), v3 (32, 3),
    m33 (16, 3, 3), arm (3,), tmp (3,). Not zeroed: the SDE kernel writes every entry of
    it before reading it (tests/unit/test_kernel_recording.py fills it with NaN)."""
    return (np.empty((1, 6)), np.empty((1, 6)), np.empty((1, 3)), np.empty((32, 3)), np.empty((16, 3, 3)),
            np.empty(3), np.empty(3))


@njit(cache=True)
def sde_end_loads_scratch(km, ws, s, F, M, out, sig, eps, point, v3, m33, arm, tmp):
    """sde_end_loads with its scratch arrays given (_end_scratch; the SDE kernel writes each
    entry before it reads it, so they need no zeroing)."""
    a = km.sde_left[s]
    b = km.sde_right[s]
    for k in range(3):
        F[a, k] = 0.0
        F[b, k] = 0.0
        M[a, k] = 0.0
        M[b, k] = 0.0
    lo = s if km.sde_has_rest.shape[0] > s else 0
    hi = s + 1 if km.sde_has_rest.shape[0] > s else 0
    sde_forces_rest_into(km.sde_left[s:s + 1], km.sde_right[s:s + 1], km.sde_arm_left[s:s + 1],
                         km.sde_arm_right[s:s + 1], km.sde_stiffness[s:s + 1], km.sde_damping[s:s + 1],
                         km.sde_has_rest[lo:hi], km.sde_rest[lo:hi], ws.sde_rest_eff[lo:hi], ws.sde_rest_rate[lo:hi],
                         ws.R, ws.rbase, ws.roff, ws.v, ws.w, F, M, eps, sig, point, v3, m33)
    if km.has_motors:
        for j in range(km.motor_sde.shape[0]):
            if km.motor_sde[j] == s:
                # the servo motor's moment as the evaluation left it in ws.sigma (rfesim.loads.drives)
                torsion_moment_into(s, ws.sigma[s, 3] - sig[0, 3], km.sde_left, km.sde_right, km.sde_arm_left,
                                    km.sde_arm_right, km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.R, ws.rbase,
                                    ws.roff, M, v3, m33)
    for side in range(2):
        i = a if side == 0 else b
        matvec_into(ws.R[i], km.sde_arm_left[s] if side == 0 else km.sde_arm_right[s], arm)
        cross_into(arm, F[i], tmp)
        for k in range(3):
            out[2 * side, k] = F[i, k]
            out[2 * side + 1, k] = M[i, k] - tmp[k]


@njit(cache=True)
def record_outputs(km, att, ws, qdd, react, sde_length, tension, shear, bend, torque, curvature, line_ranges, pts,
                   end_sdes, end_F, end_M, end):
    """Every output kernel of a recorded time in one call (``reactions``, ``sde_channels``,
    ``line_points`` of each line, ``sde_end_loads_many``): a call from Python unboxes the
    model and workspace tuples (over a hundred arrays, 20-40 us) once instead of once per
    kernel. line_ranges (nlines, 5): rfe_start, rfe_stop, sde_start, sde_stop and the
    line's first row in pts."""
    reactions(km, att, ws, qdd, react)
    sde_channels(ws, sde_length, tension, shear, bend, torque, curvature)
    for j in range(line_ranges.shape[0]):
        o = line_ranges[j, 4]
        m = line_ranges[j, 3] - line_ranges[j, 2] + 2
        line_points(ws, line_ranges[j, 0], line_ranges[j, 1], line_ranges[j, 2], line_ranges[j, 3], km.rfe_length,
                    pts[o:o + m])
    if end_sdes.shape[0] > 0:
        sde_end_loads_many(km, ws, end_sdes, end_F, end_M, end)
