"""Spring-damping elements (SDEs) of the large-deflection formulation, section 8.4.

SDE ``s`` joins RFE ``a`` (its left neighbour, RFE i-1 in the chapter) and RFE ``b``
(RFE i). Following eqs. 8.76-8.85 its deformation is measured in the frame {i'} that
follows the mean orientation of the two RFEs:

* ``g = r_R - r_L``: gap between the left end of RFE b (eq. 8.79) and the right end of
  RFE a (eq. 8.78), in the global frame;
* ``theta = log(R_a^T R_b)``: the relative rotation vector, the singularity-free form of
  the Euler-angle difference of eq. 8.75 (identical to first order);
* ``R' = R_a exp(theta/2)``: the mean orientation (geodesic midpoint, eq. 8.77);
* deformation ``eps = [R'^T g, theta]`` (eq. 8.85).

The SDE forces in {i'} are ``F' = C_r eps_r + D_r d(eps_r)/dt`` and
``M' = C_phi theta + D_phi d(theta)/dt`` (eqs. 8.86-8.87, Kelvin-Voigt damping). They are
applied to the RFEs with the exact transpose of the deformation rate map,
``generalised force = -B^T sigma``, so the elastic forces are the gradient of
``V = 1/2 eps^T C eps`` and conserve momentum and energy to round-off (eqs. 8.90-8.91
and 8.96 are the leading-order terms of this; docs/theory.md).

Rest rotation (joints between lines, rfesim.loads.drives): an SDE with ``rest_flag[s]``
1 or 2 measures its rotational deformation from R_a* = R_a R0 (R0 = ``rest_static[s]``,
or ``rest_eff[s]`` for a driven SDE, filled at the evaluation time): Rrel = R_a*^T R_b,
theta = log(Rrel), R' = R_a* exp(theta/2); the arm p_a still turns with R_a. The spatial
variation of R_a* is that of R_a, so the map from virtual displacements to d(eps) has the
same form and the force application is unchanged. A driven SDE subtracts the drive's
angular velocity R_a omega0 (``rest_rate[s]``) from the relative angular velocity of the
RFEs in d(theta)/dt and adds it to the angular velocity of {i'}: the deformation rate is
measured relative to the driven rest state (no damping drag from the drive rate).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from ..kinematics import (cross_into, matmul_into, matTmul_into, matTvec_into, matvec_into,
                          relative_rotation_terms)
from ..materials.sde_plastic import plastic_bending_into


@njit(cache=True)
def sde_geometry_r0(a, b, arm_a, arm_b, R, rbase, roff, use_rest, R0, Ras, pa, pb, g, Rrel, th, Rh, Rp, Jri, Jrh):
    """Arms pa, pb (global) from the RFE centres to the SDE ends, the gap g, the relative
    rotation Rrel = R_a*^T R_b, its rotation vector th, half rotation Rh, the mean frame
    Rp = R' and the right Jacobians J_r(th)^-1, J_r(th/2) of SDE (a, b); R_a* = R_a R0
    with ``use_rest`` (Ras (3, 3) receives it), R_a otherwise (R0, Ras unused)."""
    Ra = R[a]
    Rb = R[b]
    matvec_into(Ra, arm_a, pa)
    matvec_into(Rb, arm_b, pb)
    for k in range(3):
        # eq. 8.78-8.79: r_R - r_L, differencing reference positions and displacements apart
        g[k] = (rbase[b, k] - rbase[a, k]) + (roff[b, k] - roff[a, k]) + (pb[k] - pa[k])
    if use_rest:
        matmul_into(Ra, R0, Ras)                                    # R_a* = R_a R0 (rest rotation)
        matTmul_into(Ras, Rb, Rrel)
        relative_rotation_terms(Rrel, th, Rh, Jri, Jrh)
        matmul_into(Ras, Rh, Rp)
    else:
        matTmul_into(Ra, Rb, Rrel)
        # eq. 8.75 in rotation-vector form, the half rotation and the right Jacobians
        relative_rotation_terms(Rrel, th, Rh, Jri, Jrh)
        matmul_into(Ra, Rh, Rp)                                     # eq. 8.77: mean orientation {i'}


@njit(cache=True)
def sde_geometry(a, b, arm_a, arm_b, R, rbase, roff, pa, pb, g, Rrel, th, Rh, Rp, Jri, Jrh):
    """``sde_geometry_r0`` of an SDE straight at rest (R0 = I)."""
    sde_geometry_r0(a, b, arm_a, arm_b, R, rbase, roff, False, Rrel, Rrel, pa, pb, g, Rrel, th, Rh, Rp, Jri, Jrh)


@njit(cache=True)
def sde_geometry_rest(s, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static, rest_eff, R,
                      rbase, roff, pa, pb, g, Rrel, th, Rh, Rp, Jri, Jrh, Ras):
    """``sde_geometry_r0`` of SDE s with its rest rotation: none when ``rest_flag`` is empty
    or 0 at s, ``rest_static[s]`` at 1, ``rest_eff[s]`` (driven) at 2. Returns the flag."""
    a = sde_left[s]
    b = sde_right[s]
    fl = 0
    if rest_flag.shape[0] > 0:
        fl = rest_flag[s]
    if fl == 0:
        sde_geometry_r0(a, b, sde_arm_left[s], sde_arm_right[s], R, rbase, roff, False, Ras, Ras, pa, pb, g, Rrel,
                        th, Rh, Rp, Jri, Jrh)
    elif fl == 1:
        sde_geometry_r0(a, b, sde_arm_left[s], sde_arm_right[s], R, rbase, roff, True, rest_static[s], Ras, pa, pb,
                        g, Rrel, th, Rh, Rp, Jri, Jrh)
    else:
        sde_geometry_r0(a, b, sde_arm_left[s], sde_arm_right[s], R, rbase, roff, True, rest_eff[s], Ras, pa, pb, g,
                        Rrel, th, Rh, Rp, Jri, Jrh)
    return fl


@njit(cache=True)
def sde_geometry_scratch(s, sde_left, sde_right, sde_arm_left, sde_arm_right, R, rbase, roff, v3, m33):
    """``sde_geometry`` of SDE s into the fixed scratch slots shared by the SDE kernels:
    pa, pb, g, th in v3[0], v3[1], v3[2], v3[4]; Rrel, Rh, Rp, Jri, Jrh in m33[0:5]."""
    sde_geometry(sde_left[s], sde_right[s], sde_arm_left[s], sde_arm_right[s], R, rbase, roff, v3[0], v3[1], v3[2],
                 m33[0], v3[4], m33[1], m33[2], m33[3], m33[4])


@njit(cache=True)
def sde_geometry_rest_scratch(s, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static, rest_eff,
                              R, rbase, roff, v3, m33):
    """``sde_geometry_rest`` into the scratch slots of ``sde_geometry_scratch`` (R_a* in
    m33[5]). Returns the rest flag of SDE s."""
    return sde_geometry_rest(s, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static, rest_eff,
                             R, rbase, roff, v3[0], v3[1], v3[2], m33[0], v3[4], m33[1], m33[2], m33[3], m33[4],
                             m33[5])


@njit(cache=True)
def apply_section_force(a, b, Fp, mg, g, pa, pb, Rb, Rp, Jri, Jrh, Fg, h, tmp, tmp2, wth, F, M):
    """Apply the section force Fp (in {i'}) of SDE (a, b) and the global moment mg (from
    the section moment, eq. 8.90.2) to F and M through the exact transpose of the
    deformation rate map: eq. 8.90.1 with the consistency moment h = Fg x g of the gap.
    Fg, h, tmp, tmp2, wth are (3,) scratch; Fg and h are left holding their values."""
    matvec_into(Rp, Fp, Fg)                                         # eq. 8.90.1
    cross_into(Fg, g, h)                                            # consistency moment (tiny: g is the gap)
    # W^T h = Rb Jri^T Jrh^T Rp^T h
    matTvec_into(Rp, h, tmp)
    matTvec_into(Jrh, tmp, tmp2)
    matTvec_into(Jri, tmp2, tmp)
    matvec_into(Rb, tmp, wth)
    cross_into(pb, Fg, tmp)
    cross_into(pa, Fg, tmp2)
    for k in range(3):
        F[b, k] -= Fg[k]
        F[a, k] += Fg[k]
        M[b, k] += -tmp[k] - mg[k] - 0.5 * wth[k]
        M[a, k] += tmp2[k] + mg[k] - h[k] + 0.5 * wth[k]


@njit(cache=True, _nrt=True)
def sde_forces(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping,
               R, rbase, roff, v, w, F, M, eps_out, sigma_out, point_out):
    """Convenience form of ``sde_forces_into`` that allocates its own scratch."""
    sde_forces_into(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping,
                    R, rbase, roff, v, w, F, M, eps_out, sigma_out, point_out, np.zeros((32, 3)),
                    np.zeros((16, 3, 3)))


@njit(cache=True, _nrt=True)
def sde_forces_rest(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping, rest_flag,
                    rest_static, rest_eff, rest_rate, R, rbase, roff, v, w, F, M, eps_out, sigma_out, point_out):
    """Convenience form of ``sde_forces_rest_into`` that allocates its own scratch."""
    sde_forces_rest_into(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping, rest_flag,
                         rest_static, rest_eff, rest_rate, R, rbase, roff, v, w, F, M, eps_out, sigma_out, point_out,
                         np.zeros((32, 3)), np.zeros((16, 3, 3)))


@njit(cache=True, _nrt=True)
def sde_forces_into(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping,
                    R, rbase, roff, v, w, F, M, eps_out, sigma_out, point_out, v3, m33):
    """``sde_forces_rest_into`` for SDEs straight at rest (no rest rotations)."""
    sde_forces_rest_into(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping,
                         np.zeros(0, np.int64), np.zeros((0, 3, 3)), np.zeros((0, 3, 3)), np.zeros((0, 3)), R, rbase,
                         roff, v, w, F, M, eps_out, sigma_out, point_out, v3, m33)


@njit(cache=True)
def sde_forces_rest_into(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping, rest_flag,
                         rest_static, rest_eff, rest_rate, R, rbase, roff, v, w, F, M, eps_out, sigma_out, point_out,
                         v3, m33):
    """Add the SDE forces and moments (global, about each RFE's centre) to F and M.

    Inputs per SDE: neighbour indices, body-frame arms from the RFE centres to the SDE
    ends (8.76/8.79), stiffness and damping (nsde, 6) in the order
    [axial x, shear y, shear z, torsion x, bending y, bending z]; the rest rotations
    (``sde_geometry_rest``: rest_flag (nsde,) or empty, rest_static, rest_eff (nsde, 3, 3))
    and the drive rates rest_rate (nsde, 3) of the driven SDEs (left RFE's body frame).
    Outputs per SDE: eps (deformation), sigma (forces F' and moments M' in {i'}), and the
    SDE point (midpoint of the gap).
    """
    pa = v3[0]
    pb = v3[1]
    g = v3[2]
    gdot = v3[3]
    th = v3[4]
    tmp = v3[5]
    tmp2 = v3[6]
    dw = v3[7]
    thdot = v3[8]
    wp = v3[9]
    dlt = v3[10]
    dltdot = v3[11]
    Fp = v3[12]
    Mp = v3[13]
    Fg = v3[14]
    h = v3[15]
    mg = v3[16]
    wth = v3[17]
    wr = v3[18]
    Rp = m33[2]
    Jri = m33[3]
    Jrh = m33[4]
    for s in range(sde_left.shape[0]):
        a = sde_left[s]
        b = sde_right[s]
        Rb = R[b]
        fl = sde_geometry_rest_scratch(s, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static,
                                       rest_eff, R, rbase, roff, v3, m33)
        matTvec_into(Rp, g, dlt)                                    # eq. 8.85: R'^T (r_R - r_L)
        # rates
        cross_into(w[b], pb, tmp)
        cross_into(w[a], pa, tmp2)
        if fl == 2:
            matvec_into(R[a], rest_rate[s], wr)                     # angular velocity of R0(t) (global)
        else:
            for k in range(3):
                wr[k] = 0.0
        for k in range(3):
            gdot[k] = v[b, k] + tmp[k] - v[a, k] - tmp2[k]
            dw[k] = w[b, k] - w[a, k] - wr[k]                      # relative to the driven rest state
        matTvec_into(Rb, dw, tmp)
        matvec_into(Jri, tmp, thdot)                                # d(theta)/dt
        matvec_into(Jrh, thdot, tmp)
        matvec_into(Rp, tmp, tmp2)
        for k in range(3):
            wp[k] = w[a, k] + wr[k] + 0.5 * tmp2[k]                 # angular velocity of {i'}
        cross_into(g, wp, tmp)
        for k in range(3):
            tmp[k] += gdot[k]
        matTvec_into(Rp, tmp, dltdot)                               # d(R'^T g)/dt
        # eqs. 8.86-8.87 with Kelvin-Voigt damping
        st = sde_stiffness[s]
        sd = sde_damping[s]
        for k in range(3):
            Fp[k] = st[k] * dlt[k] + sd[k] * dltdot[k]
            Mp[k] = st[3 + k] * th[k] + sd[3 + k] * thdot[k]
            eps_out[s, k] = dlt[k]
            eps_out[s, 3 + k] = th[k]
            sigma_out[s, k] = Fp[k]
            sigma_out[s, 3 + k] = Mp[k]
            point_out[s, k] = rbase[a, k] + roff[a, k] + pa[k] + 0.5 * g[k]
        matTvec_into(Jri, Mp, tmp)
        matvec_into(Rb, tmp, mg)                                    # eq. 8.90.2 with the exact J_r^-T
        apply_section_force(a, b, Fp, mg, g, pa, pb, Rb, Rp, Jri, Jrh, Fg, h, tmp, tmp2, wth, F, M)


@njit(cache=True)
def sde_elastic_energy(sde_stiffness, eps):
    """V = 1/2 sum eps^T C eps over all SDEs (J)."""
    e = 0.0
    for s in range(eps.shape[0]):
        for k in range(6):
            e += 0.5 * sde_stiffness[s, k] * eps[s, k] * eps[s, k]
    return e


@njit(cache=True)
def plastic_sde_correction(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_length, sde_plastic,
                           plastic_params, hist, hist_trial, R, rbase, roff, eps, sigma, M, k_tangent, out5, v3,
                           m33, rest_flag, rest_static, rest_eff):
    """Elasto-plastic bending of the SDEs marked in ``sde_plastic`` (section 8.4.2, eqs.
    8.97-8.98 and Figs. 8.15-8.16), after ``sde_forces_into`` has applied the elastic law.

    The curvature of SDE s is theta_{y,z} / Delta; the bending moment follows the law with
    memory of ``rfesim.materials.sde_plastic`` from the COMMITTED history (``hist``), its
    new state goes to ``hist_trial``. The difference from the elastic moment C_phi theta is
    applied like the SDE moment itself (through J_r^-T, eq. 8.90.2), so the result is exactly
    what the SDE kernel would give with the plastic moment; sigma is corrected too.
    ``k_tangent`` (nsde, 6) receives the stiffness with the consistent bending tangent
    (dM/dkappa / Delta) for the analytic Jacobian; M is the moment accumulator. The rest
    rotations (``sde_geometry_rest``) are those of the SDE kernel's evaluation."""
    dm = v3[5]
    tmp = v3[6]
    mg = v3[7]
    for s in range(sde_left.shape[0]):
        for k in range(6):
            k_tangent[s, k] = sde_stiffness[s, k]
        if sde_plastic[s] == 0:
            continue
        d = sde_length[s]
        ty = eps[s, 4]
        tz = eps[s, 5]
        plastic_bending_into(plastic_params, hist, s, ty / d, tz / d, out5, hist_trial)
        dm[0] = 0.0
        dm[1] = out5[0] - sde_stiffness[s, 4] * ty
        dm[2] = out5[1] - sde_stiffness[s, 5] * tz
        sigma[s, 4] += dm[1]
        sigma[s, 5] += dm[2]
        k_tangent[s, 4] = out5[2] / d
        k_tangent[s, 5] = out5[4] / d
        sde_moment_change_into(s, dm, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static,
                               rest_eff, R, rbase, roff, M, tmp, mg, v3, m33)


@njit(cache=True)
def sde_moment_change_into(s, dm, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static, rest_eff,
                           R, rbase, roff, M, tmp, mg, v3, m33):
    """Add a change dm (3,) of SDE s's section moment (in {i'}) to M as the SDE kernel applies
    its moments: eq. 8.90.2 through the exact J_r^-T (-mg on the right RFE, +mg on the left).
    tmp, mg (3,) scratch outside v3[0:5]; the geometry scratch is v3[0:5], m33[0:6]."""
    a = sde_left[s]
    b = sde_right[s]
    sde_geometry_rest_scratch(s, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static,
                              rest_eff, R, rbase, roff, v3, m33)
    matTvec_into(m33[3], dm, tmp)
    matvec_into(R[b], tmp, mg)
    for k in range(3):
        M[b, k] -= mg[k]
        M[a, k] += mg[k]


@njit(cache=True)
def commit_plastic(hist, hist_trial):
    for s in range(hist.shape[0]):
        for k in range(hist.shape[1]):
            hist[s, k] = hist_trial[s, k]
