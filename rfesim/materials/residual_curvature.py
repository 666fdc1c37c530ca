"""Residual curvature of the elasto-plastic SDEs: the curvature each would keep if it were
unloaded to zero moment from its memory state (the reeling residual curvature, and what
a straightener leaves of it).

For the overlay law (rfesim.materials.sde_plastic) with committed plastic curvatures
kappa_p,j, unloading that stays elastic ends at zero moment at

    kappa_res = sum_j k_j kappa_p,j / (k_inf + sum_j k_j),

since M = k_inf kappa + sum_j k_j (kappa - kappa_p,j). When that point would make a
sub-element yield again (an unloading of more than twice its strength: reverse
yielding), Newton iterations on M(kappa) = 0 with the law's consistent tangent continue
from it, each evaluated from the committed state (the straight unloading path). Elastic
SDEs keep no curvature: 0.
"""
from __future__ import annotations

import math

from numba import njit

from .sde_plastic import plastic_bending_into


@njit(cache=True)
def residual_curvature_into(params, hist, sde_plastic, work, out5, out):
    """out (nsde,) 1/m: magnitude of the residual curvature vector of every SDE.
    params, hist as for plastic_bending_into; sde_plastic (nsde,) int64 (1: elasto-plastic);
    work (nsde, nh) scratch for the trial history; out5 (5,) scratch."""
    for i in range(out.shape[0]):
        if sde_plastic[i] == 0:
            out[i] = 0.0
            continue
        p = params[i]
        n = int(p[0])
        ei = p[1]
        sy = 0.0
        sz = 0.0
        strength = 0.0
        for j in range(n):
            k = p[2 + j]
            ei += k
            sy += k * hist[i, 2 * j]
            sz += k * hist[i, 2 * j + 1]
            strength += p[2 + n + j]
        ky = sy / ei
        kz = sz / ei
        tol = 1e-12 * (strength + ei * 1e-300)
        for _ in range(50):
            plastic_bending_into(params, hist, i, ky, kz, out5, work)
            my = out5[0]
            mz = out5[1]
            if math.sqrt(my * my + mz * mz) <= tol:
                break
            kyy = out5[2]
            kyz = out5[3]
            kzz = out5[4]
            det = kyy * kzz - kyz * kyz
            if det <= 1e-14 * ei * ei:
                break                   # no stiffness left (fully plastic): keep the last point
            ky -= (kzz * my - kyz * mz) / det
            kz -= (kyy * mz - kyz * my) / det
        out[i] = math.sqrt(ky * ky + kz * kz)
