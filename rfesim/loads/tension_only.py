"""Tension-only SDEs (ropes): the axial SDE force is ``max(0, C_x eps_x + D_x d(eps_x)/dt)``.

Applied after ``rfesim.loads.sde.sde_forces_into`` (and the plastic correction), like the
plastic correction: for every SDE marked in ``sde_tension_only`` whose axial force
sigma_x (eq. 8.86, in the frame {i'}) is negative, the force ``-sigma_x e_x'`` is added
through exactly the map the SDE kernel uses for its forces (eq. 8.90.1 with the
consistency moment of the gap), so the result is what the SDE kernel gives with the axial
force replaced by 0; sigma_x is set to 0. A slack rope element then pushes nothing, while
its shear and bending springs (small for a rope) still act.

``k_tangent`` (nsde, 6) receives the stiffness for the analytic Jacobian with the axial
entry 0 for slack SDEs; with ``fill`` it is first copied from the elastic stiffness (no
plastic correction ran before to fill it).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .sde import apply_section_force, sde_geometry_rest_scratch


@njit(cache=True, _nrt=True)
def tension_only_correction(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_tension_only,
                            R, rbase, roff, sigma, F, M, k_tangent, fill, v3, m33):
    """``tension_only_correction_rest`` for SDEs straight at rest."""
    tension_only_correction_rest(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_tension_only,
                                 np.zeros(0, np.int64), np.zeros((0, 3, 3)), np.zeros((0, 3, 3)), R, rbase, roff,
                                 sigma, F, M, k_tangent, fill, v3, m33)


@njit(cache=True)
def tension_only_correction_rest(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_tension_only,
                                 rest_flag, rest_static, rest_eff, R, rbase, roff, sigma, F, M, k_tangent, fill, v3,
                                 m33):
    """Remove the compressive axial force of the tension-only SDEs from F, M and sigma
    (rest rotations as in ``rfesim.loads.sde.sde_geometry_rest``: the mean frame {i'} of
    the SDE kernel's evaluation)."""
    pa = v3[0]
    pb = v3[1]
    g = v3[2]
    tmp = v3[5]
    tmp2 = v3[6]
    Fp = v3[7]
    Fg = v3[8]
    h = v3[9]
    wth = v3[10]
    zero = v3[11]
    Rp = m33[2]
    Jri = m33[3]
    Jrh = m33[4]
    for k in range(3):
        zero[k] = 0.0
    for s in range(sde_left.shape[0]):
        if fill:
            for k in range(6):
                k_tangent[s, k] = sde_stiffness[s, k]
        if sde_tension_only[s] == 0 or sigma[s, 0] >= 0.0:
            continue
        k_tangent[s, 0] = 0.0
        a = sde_left[s]
        b = sde_right[s]
        sde_geometry_rest_scratch(s, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static,
                                  rest_eff, R, rbase, roff, v3, m33)
        Fp[0] = -sigma[s, 0]
        Fp[1] = 0.0
        Fp[2] = 0.0
        sigma[s, 0] = 0.0
        # the force part of rfesim.loads.sde.sde_forces_into for the section force Fp (no moment)
        apply_section_force(a, b, Fp, zero, g, pa, pb, R[b], Rp, Jri, Jrh, Fg, h, tmp, tmp2, wth, F, M)
