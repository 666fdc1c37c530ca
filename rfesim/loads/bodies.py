"""Sea loads on rigid bodies (payloads, buoys) through the splash zone.

A body is one free RFE (rfesim.model.bodies) whose hydrodynamics are not those of a
cylinder along its x axis but of a lump with a displaced volume V, a vertical extent h
and a centre of buoyancy P = r + R c (c in body axes). The submerged fraction is that of
the vertical extent centred on P,

    f = clip((z_s - (P_z - h/2)) / h, 0, 1),       z_s the water surface above the body,

and every term scales with it. A body with box ``dimensions`` (half-sizes h_k > 0 along its
axes, centred on P; ``body_box``, zeros: none) takes its attitude into account instead: f is
the exact fraction of the box below the plane z = z_s and every term acts at the centroid
P_s = P + R x_s of that submerged part (x_s in body axes, from ``box_submerged``), so a
tilted, partly submerged box gets its hydrostatic restoring (or capsizing) moment. The
volume V is spread uniformly over the box. Without ``dimensions`` the height model
above is unchanged, and P_s = P:

* buoyancy ``rho g V f e_z`` at P_s;
* drag per body axis k: ``1/2 rho (C_d A)_k |u_k| u_k f``, u = water velocity minus the
  velocity of P_s, in body axes;
* water inertia: Froude-Krylov ``rho V f a_w`` plus added mass ``R diag(f m_a) R^T a_w``
  (a_w the water acceleration; zero in still water);
* added mass ``R diag(f m_a) R^T`` in the mass matrix (at the centre of mass) and added
  rotational inertia ``f J_a`` (body axes);
* slamming while the body crosses the surface (0 < f < 1) moving down into the water:
  ``1/2 rho C_s A_s u_z^2`` upwards, u_z > 0 the downward speed of P_s relative to the water
  (DNV-RP-H103 section 3.3).

The kernel overwrites ``sub_frac`` and ``sub_point`` of the body RFE (f and P_s, outputs) and
its rows of ``Ma`` and ``Ja``; it runs after the line kernels (which skip the body RFE:
its hydrodynamic diameter and displaced area are zero).
"""
from __future__ import annotations

from numba import njit

from ._common import add_force_moment


@njit(cache=True)
def _box_corner(k, s, m, hx, hy, hz):
    """Corner m (0..3) of the box face x_k = s h_k, counter-clockwise seen from outside."""
    u = 1.0 if m == 0 or m == 3 else -1.0
    w = 1.0 if m < 2 else -1.0
    if s < 0.0:
        w = -w
    if k == 0:
        return s * hx, u * hy, w * hz
    if k == 1:
        return w * hx, s * hy, u * hz
    return u * hx, w * hy, s * hz


@njit(cache=True)
def box_submerged(hx, hy, hz, nx, ny, nz, d):
    """(fraction, x, y, z): the part of the box |x_k| <= h_k (body axes) below the plane
    n . x = d (n the unit upward vertical in body axes, d the height of the water surface
    above the box centre): its fraction of the box volume and its centroid (body axes, from
    the centre). Exact: each face is clipped by the plane and the volume is the sum of the
    tetrahedra from a point O = d n on the plane to the clipped faces' triangles (the cap on
    the plane adds nothing from O)."""
    ext = abs(nx) * hx + abs(ny) * hy + abs(nz) * hz        # vertical half-extent
    if d >= ext:
        return 1.0, 0.0, 0.0, 0.0
    if d <= -ext:
        return 0.0, 0.0, 0.0, 0.0
    ox, oy, oz = d * nx, d * ny, d * nz
    vol = 0.0
    mx = 0.0
    my = 0.0
    mz = 0.0
    for k in range(3):
        for side in range(2):
            s = 1.0 if side == 0 else -1.0
            count = 0
            fx = fy = fz = 0.0          # the fan's first vertex
            lx = ly = lz = 0.0          # the last vertex emitted
            for m in range(4):
                ax, ay, az = _box_corner(k, s, m, hx, hy, hz)
                bx, by, bz = _box_corner(k, s, (m + 1) % 4, hx, hy, hz)
                sa = nx * ax + ny * ay + nz * az - d
                sb = nx * bx + ny * by + nz * bz - d
                for e in range(2):
                    if e == 0:
                        if sa > 0.0:
                            continue
                        px, py, pz = ax, ay, az
                    else:
                        if (sa <= 0.0) == (sb <= 0.0):
                            continue
                        t = sa / (sa - sb)
                        px, py, pz = ax + t * (bx - ax), ay + t * (by - ay), az + t * (bz - az)
                    if count == 0:
                        fx, fy, fz = px, py, pz
                    elif count >= 2:
                        # tetrahedron O, first, last, p
                        ux, uy, uz = fx - ox, fy - oy, fz - oz
                        vx, vy, vz = lx - ox, ly - oy, lz - oz
                        wx, wy, wz = px - ox, py - oy, pz - oz
                        tv = (ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx)) / 6.0
                        vol += tv
                        mx += tv * (ox + fx + lx + px)
                        my += tv * (oy + fy + ly + py)
                        mz += tv * (oz + fz + lz + pz)
                    lx, ly, lz = px, py, pz
                    count += 1
    if vol <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    full = 8.0 * hx * hy * hz
    f = vol / full
    if f > 1.0:
        f = 1.0
    return f, 0.25 * mx / vol, 0.25 * my / vol, 0.25 * mz / vol


@njit(cache=True)
def body_hydro_forces(body_rfe, body_volume, body_height, body_box, body_cob, body_drag, body_added_mass,
                      body_added_inertia, body_slam, water_density, gravity, scale, R, r, v, w, surface_z, water_vel,
                      water_acc, F, M, Ma, Ja, sub_frac, sub_point):
    """Add the sea loads of every body to F, M (global, about the body centre); write its
    added mass Ma (global), Ja (body axes), submerged fraction and the centre of buoyancy
    of its submerged part."""
    for j in range(body_rfe.shape[0]):
        i = body_rfe[j]
        # centre of buoyancy P = r + R c
        dx = R[i, 0, 0] * body_cob[j, 0] + R[i, 0, 1] * body_cob[j, 1] + R[i, 0, 2] * body_cob[j, 2]
        dy = R[i, 1, 0] * body_cob[j, 0] + R[i, 1, 1] * body_cob[j, 1] + R[i, 1, 2] * body_cob[j, 2]
        dz = R[i, 2, 0] * body_cob[j, 0] + R[i, 2, 1] * body_cob[j, 1] + R[i, 2, 2] * body_cob[j, 2]
        pz = r[i, 2] + dz
        if body_box[j, 0] > 0.0:
            # a box: the exact part below the water, acting at its centroid P + R x_s
            f, sx, sy, sz = box_submerged(body_box[j, 0], body_box[j, 1], body_box[j, 2], R[i, 2, 0], R[i, 2, 1],
                                          R[i, 2, 2], surface_z[i] - pz)
            dx += R[i, 0, 0] * sx + R[i, 0, 1] * sy + R[i, 0, 2] * sz
            dy += R[i, 1, 0] * sx + R[i, 1, 1] * sy + R[i, 1, 2] * sz
            ddz = R[i, 2, 0] * sx + R[i, 2, 1] * sy + R[i, 2, 2] * sz
            dz += ddz
            pz += ddz
        else:
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
        # velocity of P_s: v + w x d; water velocity relative to it
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

