"""Sea loads on rigid bodies (payloads, buoys) through the splash zone.

A body is one free RFE (rfesim.model.bodies) whose hydrodynamics are not those of a
cylinder along its x axis but of a lump with a displaced volume V, a vertical extent h
and a centre of buoyancy P = r + R c (c in body axes). The submerged fraction is that of
the vertical extent centred on P,

    f = clip((z_s - (P_z - h/2)) / h, 0, 1),       z_s the water surface above the body,

and every term scales with it:

* buoyancy ``rho g V f e_z`` at P;
* drag per body axis k: ``1/2 rho (C_d A)_k |u_k| u_k f``, u = water velocity minus the
  velocity of P, in body axes;
* water inertia: Froude-Krylov ``rho V f a_w`` plus added mass ``R diag(f m_a) R^T a_w``
  (a_w the water acceleration; zero in still water);
* added mass ``R diag(f m_a) R^T`` in the mass matrix (at the centre of mass) and added
  rotational inertia ``f J_a`` (body axes);
* slamming while the body crosses the surface (0 < f < 1) moving down into the water:
  ``1/2 rho C_s A_s u_z^2`` upwards, u_z > 0 the downward speed of P relative to the water
  (DNV-RP-H103 section 3.3).

The kernel overwrites ``sub_frac`` and ``sub_point`` of the body RFE (f and P, outputs) and
its rows of ``Ma`` and ``Ja``; it runs after the line kernels (which skip the body RFE:
its hydrodynamic diameter and displaced area are zero).
"""
from __future__ import annotations

from numba import njit

from ._common import add_force_moment


@njit(cache=True)
def body_hydro_forces(body_rfe, body_volume, body_height, body_cob, body_drag, body_added_mass, body_added_inertia,
                      body_slam, water_density, gravity, scale, R, r, v, w, surface_z, water_vel, water_acc,
                      F, M, Ma, Ja, sub_frac, sub_point):
    """Add the sea loads of every body to F, M (global, about the body centre); write its
    added mass Ma (global), Ja (body axes), submerged fraction and centre of buoyancy."""
    for j in range(body_rfe.shape[0]):
        i = body_rfe[j]
        # centre of buoyancy P = r + R c
        dx = R[i, 0, 0] * body_cob[j, 0] + R[i, 0, 1] * body_cob[j, 1] + R[i, 0, 2] * body_cob[j, 2]
        dy = R[i, 1, 0] * body_cob[j, 0] + R[i, 1, 1] * body_cob[j, 1] + R[i, 1, 2] * body_cob[j, 2]
        dz = R[i, 2, 0] * body_cob[j, 0] + R[i, 2, 1] * body_cob[j, 1] + R[i, 2, 2] * body_cob[j, 2]
        pz = r[i, 2] + dz
        h = body_height[j]
        f = (surface_z[i] - (pz - 0.5 * h)) / h
        if f < 0.0:
            f = 0.0
        elif f > 1.0:
            f = 1.0
        sub_frac[i] = f
        sub_point[i, 0] = r[i, 0] + dx
        sub_point[i, 1] = r[i, 1] + dy
        sub_point[i, 2] = pz
        for a in range(3):
            Ja[i, a] = f * body_added_inertia[j, a]
            for b in range(3):
                s = 0.0
                for k in range(3):
                    s += R[i, a, k] * body_added_mass[j, k] * R[i, b, k]
                Ma[i, a, b] = f * s
        if f <= 0.0:
            continue
        # velocity of P: v + w x d; water velocity relative to it
        ux = water_vel[i, 0] - (v[i, 0] + w[i, 1] * dz - w[i, 2] * dy)
        uy = water_vel[i, 1] - (v[i, 1] + w[i, 2] * dx - w[i, 0] * dz)
        uz = water_vel[i, 2] - (v[i, 2] + w[i, 0] * dy - w[i, 1] * dx)
        fx = 0.0
        fy = 0.0
        fz = scale * water_density * gravity * body_volume[j] * f          # buoyancy
        # drag per body axis: u_k = (R^T u)_k, force R[:, k] * 1/2 rho (CdA)_k |u_k| u_k f
        for k in range(3):
            uk = R[i, 0, k] * ux + R[i, 1, k] * uy + R[i, 2, k] * uz
            fk = 0.5 * water_density * body_drag[j, k] * abs(uk) * uk * f
            fx += R[i, 0, k] * fk
            fy += R[i, 1, k] * fk
            fz += R[i, 2, k] * fk
        # water acceleration: Froude-Krylov rho V f a_w plus added mass Ma a_w
        ax = water_acc[i, 0]
        ay = water_acc[i, 1]
        az = water_acc[i, 2]
        if ax != 0.0 or ay != 0.0 or az != 0.0:
            vol = water_density * body_volume[j] * f
            fx += vol * ax + Ma[i, 0, 0] * ax + Ma[i, 0, 1] * ay + Ma[i, 0, 2] * az
            fy += vol * ay + Ma[i, 1, 0] * ax + Ma[i, 1, 1] * ay + Ma[i, 1, 2] * az
            fz += vol * az + Ma[i, 2, 0] * ax + Ma[i, 2, 1] * ay + Ma[i, 2, 2] * az
        # slamming while crossing the surface, moving down into the water (u_z > 0)
        if f < 1.0 and uz > 0.0:
            fz += 0.5 * water_density * body_slam[j] * uz * uz
        add_force_moment(F, M, i, dx, dy, dz, fx, fy, fz)


def body_buoyancy(water_density: float, gravity: float, volume: float, fraction: float) -> float:
    """Buoyancy of a body with submerged fraction ``fraction`` (N)."""
    return water_density * gravity * volume * fraction

