"""Tangent stiffness and damping of the SDEs (for the implicit solver's Jacobian).

For SDE s between RFEs a and b, with spatial virtual displacements
x = (dr_a, da_a, dr_b, da_b) (da: small rotation, dR = [da]x R), the deformation rate map
B of ``rfesim.loads.sde`` gives d(eps) = B dx and the generalised forces f = -B^T sigma.
The tangent K = -df/dx is

* material: B^T C B (exact), and B^T D B for the velocity dependence of the damping;
* geometric: d(B^T sigma)/dx at fixed sigma, from the rotation of F = R' F' with the mean
  frame, the arms p x F, the moment m = R_b J_r^-T M' (which turns with the mean frame)
  and the gap moment F x g. In these geometric terms J_r(theta) and W are taken as the
  identity: an error of the order of the relative rotation theta of neighbouring RFEs
  (0.01-0.05 rad), which leaves Newton's convergence linear with a tiny rate.

Rest rotations (``rfesim.loads.sde.sde_geometry_rest``): the spatial variation of
R_a* = R_a R0 is that of R_a (d R_a* = [da_a]x R_a*, i.e. R_a* [R0^T R_a^T da_a]x), so B
and the geometric terms keep their form with the geometry (R', J_r, W) of R_a*; the
tangent is as exact with rest rotations as without. The position dependence of the drive
rate R_a omega0 in the damping (a velocity-level term) is left out, like the position
dependence of the other damping terms.

Tested against finite differences of ``sde_forces`` in tests/unit/test_sde_tangent.py
(and with rest rotations in tests/unit/test_sde_rest_rotation.py).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from ..kinematics import matmul_into, matvec_into, skew_into
from .sde import sde_geometry_rest


@njit(cache=True, _nrt=True)
def sde_tangent(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping, R, rbase, roff,
                sigma, K, Kd):
    """``sde_tangent_rest`` for SDEs straight at rest."""
    sde_tangent_rest(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping,
                     np.zeros(0, np.int64), np.zeros((0, 3, 3)), np.zeros((0, 3, 3)), R, rbase, roff, sigma, K, Kd)


@njit(cache=True, _nrt=True)
def sde_tangent_rest(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping, rest_flag,
                     rest_static, rest_eff, R, rbase, roff, sigma, K, Kd):
    """K (nsde, 12, 12): tangent stiffness -df/dx; Kd (nsde, 12, 12): B^T D B.
    ``sigma`` (nsde, 6) are the SDE forces of the evaluated state (F', M' in {i'});
    rest rotations as in ``rfesim.loads.sde.sde_geometry_rest``."""
    B = np.zeros((6, 12))
    Ras = np.empty((3, 3))
    Rrel = np.empty((3, 3))
    Rh = np.empty((3, 3))
    Rp = np.empty((3, 3))
    Jri = np.empty((3, 3))
    Jrh = np.empty((3, 3))
    W = np.empty((3, 3))
    T1 = np.empty((3, 3))
    T2 = np.empty((3, 3))
    Pa = np.empty((3, 3))
    Pb = np.empty((3, 3))
    Gx = np.empty((3, 3))
    Fx = np.empty((3, 3))
    mx = np.empty((3, 3))
    th = np.empty(3)
    pa = np.empty(3)
    pb = np.empty(3)
    g = np.empty(3)
    F = np.empty(3)
    m = np.empty(3)
    tmp = np.empty(3)
    CB = np.empty((6, 12))
    DB = np.empty((6, 12))
    FPa = np.empty((3, 3))
    PaF = np.empty((3, 3))
    FPb = np.empty((3, 3))
    PbF = np.empty((3, 3))
    for s in range(sde_left.shape[0]):
        b = sde_right[s]
        Rb = R[b]
        sde_geometry_rest(s, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static, rest_eff, R,
                          rbase, roff, pa, pb, g, Rrel, th, Rh, Rp, Jri, Jrh, Ras)
        # W = Rp Jrh Jri Rb^T
        matmul_into(Jrh, Jri, T1)
        matmul_into(Rp, T1, T2)
        for i in range(3):
            for j in range(3):
                W[i, j] = T2[i, 0] * Rb[j, 0] + T2[i, 1] * Rb[j, 1] + T2[i, 2] * Rb[j, 2]
        skew_into(pa, Pa)
        skew_into(pb, Pb)
        skew_into(g, Gx)
        # ---- B (6 x 12): rows delta' then theta; columns dr_a, da_a, dr_b, da_b
        for i in range(6):
            for j in range(12):
                B[i, j] = 0.0
        for i in range(3):
            for j in range(3):
                G_ij = Rp[j, i]                       # G = Rp^T
                B[i, j] = -G_ij                       # d/dr_a
                B[i, 6 + j] = G_ij                    # d/dr_b
        # d/da_a: G ([pa]x + [g]x (I - W/2)) ; d/da_b: G (-[pb]x + [g]x W / 2)
        for i in range(3):
            for j in range(3):
                ga = Pa[i, j]
                gb = -Pb[i, j]
                for k in range(3):
                    ga += Gx[i, k] * ((1.0 if k == j else 0.0) - 0.5 * W[k, j])
                    gb += Gx[i, k] * 0.5 * W[k, j]
                T1[i, j] = ga
                T2[i, j] = gb
        for i in range(3):
            for j in range(3):
                sa = 0.0
                sb = 0.0
                for k in range(3):
                    sa += Rp[k, i] * T1[k, j]
                    sb += Rp[k, i] * T2[k, j]
                B[i, 3 + j] = sa
                B[i, 9 + j] = sb
        # theta rows: Jri Rb^T (da_b - da_a)
        for i in range(3):
            for j in range(3):
                v = Jri[i, 0] * Rb[j, 0] + Jri[i, 1] * Rb[j, 1] + Jri[i, 2] * Rb[j, 2]
                B[3 + i, 3 + j] = -v
                B[3 + i, 9 + j] = v
        # ---- material parts: B^T C B and B^T D B
        # (C and D diagonal: B^T C B and B^T D B in one pass, each term as C B then B^T (C B))
        st = sde_stiffness[s]
        sd = sde_damping[s]
        for i in range(6):
            for j in range(12):
                CB[i, j] = st[i] * B[i, j]
                DB[i, j] = sd[i] * B[i, j]
        for i in range(12):
            for j in range(12):
                acc = 0.0
                accd = 0.0
                for k in range(6):
                    acc += B[k, i] * CB[k, j]
                    accd += B[k, i] * DB[k, j]
                K[s, i, j] = acc
                Kd[s, i, j] = accd
        # ---- geometric part (sigma fixed), spatial; see the module docstring
        for k in range(3):
            tmp[k] = sigma[s, k]
        matvec_into(Rp, tmp, F)
        for k in range(3):
            tmp[k] = sigma[s, 3 + k]
        matvec_into(Rp, tmp, m)                       # m ~ R' M'
        skew_into(F, Fx)
        skew_into(m, mx)
        # helper products: [F]x[pa]x, [pa]x[F]x, [F]x[pb]x, [pb]x[F]x
        matmul_into(Fx, Pa, FPa)
        matmul_into(Pa, Fx, PaF)
        matmul_into(Fx, Pb, FPb)
        matmul_into(Pb, Fx, PbF)
        # d(B^T sigma) rows: [-F_a; -M_a; -F_b; -M_b]; columns dr_a, da_a, dr_b, da_b
        # dg = dr_b - dr_a - [pb]x da_b + [pa]x da_a
        for i in range(3):
            for j in range(3):
                # -F_a = -F : d = +1/2 [F]x (da_a + da_b)
                K[s, i, 3 + j] += 0.5 * Fx[i, j]
                K[s, i, 9 + j] += 0.5 * Fx[i, j]
                # -F_b = +F : d = -1/2 [F]x (da_a + da_b)
                K[s, 6 + i, 3 + j] -= 0.5 * Fx[i, j]
                K[s, 6 + i, 9 + j] -= 0.5 * Fx[i, j]
                # -M_a = -pa x F - m + h/2
                hh = 0.5 * (PaF[i, j] + mx[i, j])
                K[s, 3 + i, 3 + j] += -FPa[i, j] + hh
                K[s, 3 + i, 9 + j] += hh
                # -M_b = pb x F + m + h/2
                hb = -0.5 * (PbF[i, j] + mx[i, j])
                K[s, 9 + i, 9 + j] += FPb[i, j] + hb
                K[s, 9 + i, 3 + j] += hb
        # +1/2 [F]x dg in both moment rows
        matmul_into(Gx, Fx, T1)                              # [g]x [F]x: from dF x g in dh
        for row in (3, 9):
            for i in range(3):
                for j in range(3):
                    K[s, row + i, 3 + j] += 0.25 * T1[i, j]
                    K[s, row + i, 9 + j] += 0.25 * T1[i, j]
                    K[s, row + i, j] -= 0.5 * Fx[i, j]            # dr_a
                    K[s, row + i, 6 + j] += 0.5 * Fx[i, j]        # dr_b
                    K[s, row + i, 3 + j] += 0.5 * FPa[i, j]      # da_a via [pa]x
                    K[s, row + i, 9 + j] -= 0.5 * FPb[i, j]      # da_b via -[pb]x
