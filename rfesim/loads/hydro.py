"""Sea loads on RFEs: submergence, buoyancy, Morison drag and added mass (eq. 8.95).

Each RFE is a straight cylinder of its length along its local x axis. The part below
the water surface is found from the heights of its two ends (linear along the element);
buoyancy acts at the centroid of that part, drag and added mass use the element's
velocity relative to the water at that point:

* buoyancy ``rho g A_d l_sub e_z`` (Archimedes on the closed outer volume; the SDE axial
  force is then the effective tension);
* drag ``1/2 rho C_dn D l_sub |u_n| u_n`` normal and ``1/2 rho C_dt pi D l_sub |u_t| u_t``
  axial, ``u`` the water velocity relative to the element;
* added mass ``rho C_a A_d l_sub`` normal (and axial with C_at) in the mass matrix, and
  ``m_a l^2/12`` for the element's rotation about its transverse axes.

The water velocity and acceleration at each RFE come in arrays (zero in still water);
the sea-environment modules fill them.
"""
from __future__ import annotations

import math

from numba import njit

from ._common import add_force_moment


@njit(cache=True)
def submergence(rfe_length, rfe_disp_area, R, r, surface_z, sub_frac, sub_point):
    """Fraction of each RFE below the surface and the centroid of the submerged part."""
    for i in range(rfe_length.shape[0]):
        if rfe_disp_area[i] <= 0.0:
            sub_frac[i] = 0.0
            for k in range(3):
                sub_point[i, k] = r[i, k]
            continue
        hl = 0.5 * rfe_length[i]
        tz = R[i, 2, 0]
        zl = r[i, 2] - hl * tz
        zr = r[i, 2] + hl * tz
        zs = surface_z[i]
        if zl <= zs and zr <= zs:
            sub_frac[i] = 1.0
            for k in range(3):
                sub_point[i, k] = r[i, k]
        elif zl > zs and zr > zs:
            sub_frac[i] = 0.0
            for k in range(3):
                sub_point[i, k] = r[i, k]
        else:
            # the low end is submerged; fraction f of the length from it is under water
            if zl < zr:
                f = (zs - zl) / (zr - zl)
                sgn = -1.0       # low end is the left end (local -x)
            else:
                f = (zs - zr) / (zl - zr)
                sgn = 1.0
            sub_frac[i] = f
            # centroid of the submerged part: from the low end, half the submerged length
            off = sgn * (hl - 0.5 * f * rfe_length[i])
            for k in range(3):
                sub_point[i, k] = r[i, k] + off * R[i, k, 0]


@njit(cache=True)
def buoyancy_forces(rfe_length, rfe_disp_area, rfe_kind, water_density, gravity, scale,
                    r, sub_frac, sub_point, F, M):
    """Buoyancy at the centroid of the submerged part of each RFE."""
    for i in range(rfe_length.shape[0]):
        f = sub_frac[i]
        if f <= 0.0:
            continue
        fb = scale * water_density * gravity * rfe_disp_area[i] * rfe_length[i] * f
        F[i, 2] += fb
        # moment (p - r) x (0, 0, fb)
        dx = sub_point[i, 0] - r[i, 0]
        dy = sub_point[i, 1] - r[i, 1]
        M[i, 0] += dy * fb
        M[i, 1] -= dx * fb


@njit(cache=True)
def morison_forces(rfe_length, rfe_diameter, rfe_disp_area, rfe_cdn, rfe_cdt, rfe_can, rfe_cat, water_density,
                   R, r, v, w, sub_frac, sub_point, water_vel, water_acc, F, M, Ma, Ja):
    """Drag (relative velocity), Froude-Krylov plus added-mass inertia of the water
    acceleration, and the added-mass matrix of each RFE (global Ma, body Ja)."""
    for i in range(rfe_length.shape[0]):
        f = sub_frac[i]
        for a in range(3):
            Ja[i, a] = 0.0
            for b in range(3):
                Ma[i, a, b] = 0.0
        if f <= 0.0 or rfe_diameter[i] <= 0.0:
            continue
        lsub = f * rfe_length[i]
        tx = R[i, 0, 0]
        ty = R[i, 1, 0]
        tz = R[i, 2, 0]
        dx = sub_point[i, 0] - r[i, 0]
        dy = sub_point[i, 1] - r[i, 1]
        dz = sub_point[i, 2] - r[i, 2]
        # velocity of the element at the submerged centroid: v + w x d
        vx = v[i, 0] + w[i, 1] * dz - w[i, 2] * dy
        vy = v[i, 1] + w[i, 2] * dx - w[i, 0] * dz
        vz = v[i, 2] + w[i, 0] * dy - w[i, 1] * dx
        ux = water_vel[i, 0] - vx
        uy = water_vel[i, 1] - vy
        uz = water_vel[i, 2] - vz
        ut = ux * tx + uy * ty + uz * tz
        unx = ux - ut * tx
        uny = uy - ut * ty
        unz = uz - ut * tz
        un = math.sqrt(unx * unx + uny * uny + unz * unz)
        cn = 0.5 * water_density * rfe_cdn[i] * rfe_diameter[i] * lsub * un
        ct = 0.5 * water_density * rfe_cdt[i] * math.pi * rfe_diameter[i] * lsub * abs(ut)
        fx = cn * unx + ct * ut * tx
        fy = cn * uny + ct * ut * ty
        fz = cn * unz + ct * ut * tz
        # water acceleration: Froude-Krylov (rho V a) + added mass (C_a rho V a_n)
        vol = water_density * rfe_disp_area[i] * lsub
        man = rfe_can[i] * vol
        mat = rfe_cat[i] * vol
        ax = water_acc[i, 0]
        ay = water_acc[i, 1]
        az = water_acc[i, 2]
        if ax != 0.0 or ay != 0.0 or az != 0.0:
            at = ax * tx + ay * ty + az * tz
            fx += vol * ax + man * (ax - at * tx) + mat * at * tx
            fy += vol * ay + man * (ay - at * ty) + mat * at * ty
            fz += vol * az + man * (az - at * tz) + mat * at * tz
        add_force_moment(F, M, i, dx, dy, dz, fx, fy, fz)
        # added mass matrix: man (I - t t^T) + mat t t^T
        t0 = tx
        t1 = ty
        t2 = tz
        tt = (t0, t1, t2)
        for a in range(3):
            for b in range(3):
                Ma[i, a, b] = (mat - man) * tt[a] * tt[b]
            Ma[i, a, a] += man
        Ja[i, 1] = man * lsub * lsub / 12.0
        Ja[i, 2] = Ja[i, 1]
