"""Seabed contact (eq. 8.95, forces F^d): a flat horizontal seabed with a normal spring
and damper per unit length, integrated in closed form along each RFE.

The penetration of the pipe's underside, ``p(s) = z_seabed - (z(s) - a)`` with ``a`` the
contact radius, is linear along a straight RFE; the spring force per unit length ``k p``
over the penetrated part is integrated exactly (a triangle or a trapezoid) and applied
at its centroid, so the force is continuously differentiable in the RFE's position as
contact spreads along it (smooth touchdown, good Newton convergence). The damper
``c v_z`` acts on the same length; the total normal force is never tensile.
"""
from __future__ import annotations

import math

from numba import njit


@njit(cache=True)
def seabed_forces(rfe_length, rfe_contact_radius, rfe_seabed_c, seabed_z, seabed_k, R, r, v, w,
                  F, M, contact_force, contact_length):
    for i in range(rfe_length.shape[0]):
        contact_force[i] = 0.0
        contact_length[i] = 0.0
        hl = 0.5 * rfe_length[i]
        tz = R[i, 2, 0]
        a = rfe_contact_radius[i]
        pl = seabed_z - (r[i, 2] - hl * tz - a)
        pr = seabed_z - (r[i, 2] + hl * tz - a)
        if pl <= 0.0 and pr <= 0.0:
            continue
        L = rfe_length[i]
        if pl > 0.0 and pr > 0.0:
            lc = L
            fk = seabed_k * L * 0.5 * (pl + pr)
            # centroid of the trapezoid, measured from the left end
            sc = L * (pl + 2.0 * pr) / (3.0 * (pl + pr))
        elif pl > 0.0:
            lc = L * pl / (pl - pr)
            fk = 0.5 * seabed_k * lc * pl
            sc = lc / 3.0
        else:
            lc = L * pr / (pr - pl)
            fk = 0.5 * seabed_k * lc * pr
            sc = L - lc / 3.0
        off = sc - hl
        dx = off * R[i, 0, 0]
        dy = off * R[i, 1, 0]
        # vertical velocity at the contact centroid: v + w x d
        dz = off * tz
        vz = v[i, 2] + w[i, 0] * dy - w[i, 1] * dx
        fn = fk - rfe_seabed_c[i] * lc * vz
        if fn < 0.0:
            fn = 0.0
        F[i, 2] += fn
        M[i, 0] += dy * fn
        M[i, 1] -= dx * fn
        contact_force[i] = fn
        contact_length[i] = lc
