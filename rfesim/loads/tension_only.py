"""Tension-only SDEs (ropes): the axial SDE force is ``max(0, C_x eps_x + D_x d(eps_x)/dt)``.

Applied after ``rfesim.loads.sde.sde_forces_into`` (and the plastic correction), like the
plastic correction: for every SDE marked in ``sde_tension_only`` whose axial force
sigma_x (eq. 8.86, in the frame {i'}) is negative, the force ``-sigma_x e_x'`` is added
through exactly the map the SDE kernel uses for its forces (eq. 8.90.1 with the
consistency moment of the gap), so the result is what the SDE kernel gives with the axial
force replaced by 0; sigma_x is set to 0. A slack rope element then pushes nothing, while
its shear and bending springs (small for a rope) still act.

Axial contact: a slack rope element may be driven into its neighbour only so far. Once the
gap eps_x (eq. 8.85) falls below ``-ROPE_CONTACT * (|arm_L| + |arm_R|)`` (for two elements of
a line: their centres nearer than half an element length along the axis), the elastic law
comes back, measured from that closing: sigma_x = min(0, C_x (eps_x - eps_c) + D_x
d(eps_x)/dt), with the axial stiffness in the tangent. Without it two elements driven
together telescope, pass through one another and the rope comes apart with no tension
(docs/theory.md, 'Axial contact of a slack rope'). Continuous in the force: 0 at eps_c.

``k_tangent`` (nsde, 6) receives the stiffness for the analytic Jacobian with the axial
entry 0 for slack SDEs; with ``fill`` it is first copied from the elastic stiffness (no
plastic correction ran before to fill it).
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .sde import apply_section_force, sde_geometry_rest_scratch

ROPE_CONTACT = 0.5       # contact once the gap closes by this fraction of the two arms' sum (half an element)
ROPE_CONTACT_RAMP = 0.1  # its stiffness grows from 0 to C_x over this fraction of the arms' sum further


@njit(cache=True)
def rope_reach(sde_arm_left, sde_arm_right, s):
    """|arm_L| + |arm_R| of SDE s (m): the element length for two elements of a line."""
    a = 0.0
    b = 0.0
    for k in range(3):
        a += sde_arm_left[s, k] * sde_arm_left[s, k]
        b += sde_arm_right[s, k] * sde_arm_right[s, k]
    return np.sqrt(a) + np.sqrt(b)


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
        a = sde_left[s]
        b = sde_right[s]
        sde_geometry_rest_scratch(s, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static,
                                  rest_eff, R, rbase, roff, v3, m33)
        gap = Rp[0, 0] * g[0] + Rp[1, 0] * g[1] + Rp[2, 0] * g[2]          # eps_x, eq. 8.85
        reach = rope_reach(sde_arm_left, sde_arm_right, s)
        depth = -ROPE_CONTACT * reach - gap                                # > 0: in axial contact
        kept = 0.0
        kc = 0.0
        if reach > 0.0 and depth > 0.0:
            c = sde_stiffness[s, 0]
            width = ROPE_CONTACT_RAMP * reach
            if depth < width:
                kc = c * depth / width
                elastic = -0.5 * kc * depth
            else:
                kc = c
                elastic = -c * (depth - 0.5 * width)
            kept = min(0.0, elastic + (sigma[s, 0] - c * gap) * (kc / c))   # damping scaled as the stiffness
        if kept == 0.0:
            k_tangent[s, 0] = 0.0
        else:
            k_tangent[s, 0] = kc
        Fp[0] = kept - sigma[s, 0]
        Fp[1] = 0.0
        Fp[2] = 0.0
        sigma[s, 0] = kept
        # the force part of rfesim.loads.sde.sde_forces_into for the section force Fp (no moment)
        apply_section_force(a, b, Fp, zero, g, pa, pb, R[b], Rp, Jri, Jrh, Fg, h, tmp, tmp2, wth, F, M)


def arm_sums(sde_arm_left, sde_arm_right, rows):
    """|arm_L| + |arm_R| of the SDEs ``rows`` (m): ``rope_reach`` for many, in numpy."""
    return np.linalg.norm(sde_arm_left[rows], axis=1) + np.linalg.norm(sde_arm_right[rows], axis=1)


def rope_axial_energy(stiffness, gap, reach):
    """Axial energy of tension-only SDEs (J), arrays of the axial stiffness C_x, the gap
    eps_x and the arms' sum: 1/2 C eps^2 stretched, 0 slack, and past the contact the energy
    whose derivative is the contact force of ``tension_only_correction_rest`` (C d^3 / (6 w)
    on the ramp, C (d^2/2 - w d/2 + w^2/6) past it; d the depth past the closing, w the
    ramp's width)."""
    stiffness = np.asarray(stiffness, float)
    gap = np.asarray(gap, float)
    reach = np.asarray(reach, float)
    depth = -ROPE_CONTACT * reach - gap
    width = ROPE_CONTACT_RAMP * reach
    safe = np.where(width > 0.0, width, 1.0)
    ramp = stiffness * np.clip(depth, 0.0, None) ** 3 / (6.0 * safe)
    linear = stiffness * (0.5 * depth * depth - 0.5 * width * depth + width * width / 6.0)
    contact = np.where((reach > 0.0) & (depth > 0.0), np.where(depth < width, ramp, linear), 0.0)
    return np.where(gap > 0.0, 0.5 * stiffness * gap * gap, contact)
