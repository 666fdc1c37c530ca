"""Sea loads on RFEs: submergence, buoyancy, Morison drag and added mass (eq. 8.95).

Each RFE is a straight cylinder of its length along its local x axis. The part below
the water surface is found from the heights of its two ends (linear along the element) and
its section (a circular segment where the surface cuts it: ``submergence``); buoyancy acts
at the centroid of that part, drag and added mass use the element's
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

import numpy as np
from numba import njit

from ._common import add_force_moment


SMALL_RISE = 1e-3      # |u_r - u_l| below which submergence integrates by Gauss-Legendre
GAUSS_X = np.array([-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640])
GAUSS_W = np.array([0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                    0.2369268850561891])


@njit(cache=True)
def wet_area_fraction(u):
    """Fraction of a circle's area below a horizontal line ``u`` radii above its centre
    (the circular segment): 1 at u <= -1, 0 at u >= 1, (acos u - u sqrt(1 - u^2)) / pi
    between."""
    if u >= 1.0:
        return 0.0
    if u <= -1.0:
        return 1.0
    return (math.acos(u) - u * math.sqrt(1.0 - u * u)) / math.pi


@njit(cache=True)
def _wet_integral(u):
    """Phi(u), an antiderivative of wet_area_fraction: (u acos u - s + s^3 / 3) / pi with
    s = sqrt(1 - u^2) for |u| <= 1; 0 above (Phi(1) = 0), u below (Phi(-1) = -1)."""
    if u >= 1.0:
        return 0.0
    if u <= -1.0:
        return u
    s = math.sqrt(1.0 - u * u)
    return (u * math.acos(u) - s + s * s * s / 3.0) / math.pi


@njit(cache=True)
def _wet_moment_integral(u):
    """Psi(u), an antiderivative of u wet_area_fraction(u): for |u| <= 1
    (u^2 acos(u) / 2 + (asin u - u s) / 4 - (asin u - u s (1 - 2 u^2)) / 8) / pi, s as in
    _wet_integral; Psi(1) = 1/16 above, Psi(-1) + (u^2 - 1) / 2 below (Psi(-1) = 7/16)."""
    if u >= 1.0:
        return 1.0 / 16.0
    if u <= -1.0:
        return 7.0 / 16.0 + 0.5 * (u * u - 1.0)
    s = math.sqrt(1.0 - u * u)
    a = math.asin(u)
    return (0.5 * u * u * math.acos(u) + 0.25 * (a - u * s) - 0.125 * (a - u * s * (1.0 - 2.0 * u * u))) / math.pi


@njit(cache=True)
def submergence(rfe_length, rfe_disp_area, R, r, surface_z, sub_frac, sub_point):
    """Fraction of each RFE below the surface and the centroid of the submerged part.

    The RFE is a cylinder of radius a = sqrt(A_d / pi) around its axis. A cross-section whose
    centre lies h above the surface is wet over the circular segment below it: the fraction
    phi(h / c) of its area (``wet_area_fraction``), c = a sqrt(1 - t_z^2) the section's
    vertical half-extent (a for a horizontal RFE, 0 for a vertical one). Along the axis h
    varies linearly between its ends, so the RFE's wet fraction is the mean of phi over
    u = h / c from u_l to u_r, (Phi(u_r) - Phi(u_l)) / (u_r - u_l) (``_wet_integral``), and
    the centroid of the wet part along the axis is at the phi-weighted mean of u
    (``_wet_moment_integral``). A horizontal RFE at the surface is then wet in proportion to
    its immersed section, smoothly (the axis alone made its buoyancy jump from 0 to full as
    the axis crossed the surface, and Newton could not follow a floating line); a vertical
    one (c = 0) is the axis' wet length, as before. Nearly level RFEs (|u_r - u_l| below
    SMALL_RISE) integrate phi by 5-point Gauss-Legendre instead: the antiderivatives'
    differences cancel there, and the centroid came out as noise of the element's length. docs/theory.md, 'Wet fraction of an RFE at the surface'."""
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
        # clear of the surface by a whole radius a (>= c): wet or dry without the square roots
        # (most RFEs of a scene; the section's extent c is needed only near the surface)
        a2 = rfe_disp_area[i] / math.pi
        below = zs - max(zl, zr)
        above = min(zl, zr) - zs
        if below > 0.0 and below * below >= a2:
            sub_frac[i] = 1.0
            for k in range(3):
                sub_point[i, k] = r[i, k]
            continue
        if above > 0.0 and above * above >= a2:
            sub_frac[i] = 0.0
            for k in range(3):
                sub_point[i, k] = r[i, k]
            continue
        c = math.sqrt(a2) * math.sqrt(max(0.0, 1.0 - tz * tz))
        if zl <= zs - c and zr <= zs - c:
            sub_frac[i] = 1.0
            for k in range(3):
                sub_point[i, k] = r[i, k]
        elif zl >= zs + c and zr >= zs + c:
            sub_frac[i] = 0.0
            for k in range(3):
                sub_point[i, k] = r[i, k]
        elif c <= 1e-9 * rfe_length[i]:
            # a vertical RFE: the wet length of its axis; the low end is submerged
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
        else:
            ul = (zl - zs) / c
            ur = (zr - zs) / c
            du = ur - ul
            off = 0.0
            if abs(du) < SMALL_RISE:
                # nearly level: 5-point Gauss-Legendre along the axis (the antiderivatives'
                # differences would cancel: their centroid is then noise of the element's length)
                um = 0.5 * (ul + ur)
                wet = 0.0
                mom = 0.0
                for k in range(5):
                    p = wet_area_fraction(um + 0.5 * du * GAUSS_X[k]) * GAUSS_W[k]
                    wet += p
                    mom += p * GAUSS_X[k]
                f = 0.5 * wet
                if wet > 0.0:
                    off = 0.5 * rfe_length[i] * mom / wet
            else:
                wet = _wet_integral(ur) - _wet_integral(ul)
                f = wet / du
                if f > 1e-12:
                    # the wet part's centroid, from u to the axis: s = (u - u_l) / du along it
                    um = (_wet_moment_integral(ur) - _wet_moment_integral(ul)) / wet
                    off = ((um - ul) / du - 0.5) * rfe_length[i]
            sub_frac[i] = min(1.0, max(0.0, f))
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
