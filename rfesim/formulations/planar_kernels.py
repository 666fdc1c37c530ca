"""Numba kernels of the planar RFE formulation (chapter section 8.3), O(n) per evaluation.

Coordinates (eq. 8.52): ``q = [x, y, phi_0, ..., phi_n]`` -- the point A_0 of the link and
the absolute inclination angle of every RFE. The chapter's mass matrix A (eq. 8.57) is dense
in these coordinates; the kernels never form it. They work on the RFEs as rigid bodies
(centre of mass, angle) joined by revolute joints at A_1..A_n:

* ``accelerations``: forward dynamics. Newton-Euler for every RFE with the joint reactions
  as unknowns; the reactions solve the block-tridiagonal system ``(G M^-1 G^T) lam =
  G M^-1 F - gamma`` (one 3x3 block per joint, block Thomas), then ``a = M^-1 (F - G^T lam)``.
  For ideal joints this is exactly ``A qdd = F - Bbar qd - C q - dVg/dq + Q`` (eq. 8.66) and
  gives, on the way, the reactions of eq. 8.67-8.70 (base: group 0, end B: group n+1).
* ``residual``: inverse dynamics, ``r = A qdd + Bbar qd + C q + D qd + dVg/dq - Q`` (eq. 8.66
  with 8.59-8.65) as ``J^T (M a - F)`` with the body accelerations ``a = J qdd + Jdot qd``
  from a forward recursion and ``J^T`` by suffix sums.
* ``assemble_kkt``: the banded Newton matrix ``[[H, G^T], [G, 0]]`` with
  ``H = c_m M + c_d D + c_k K`` on the bodies, interleaved joint by joint (half bandwidth 6),
  for the statics and generalised-alpha Newton iterations (``J^T H J`` is the chapter's
  ``c_m A + c_d D + c_k K`` in generalised coordinates).

Geometry per RFE i in its local frame at the centre of mass C_i (Fig. 8.8): ``z_in[i]`` is
the vector A_i -> C_i (= -(a_ii, b_ii)), ``z_out[i]`` the vector A_i -> A_{i+1}
(= (a_{i,i+1} - a_ii, b_{i,i+1} - b_ii)); A_{n+1} is the end point B.
End codes: 0 free, 1 pinned, 2 clamped.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

FREE = 0
PINNED = 1
CLAMPED = 2
HALF_BANDWIDTH = 6


@njit(cache=True)
def body_kinematics(q, qd, qdd, z_in, z_out, rot, pc, vc, ac):
    """Centre positions pc, velocities vc and accelerations ac (all (nr, 2)) of the RFEs,
    eq. 8.53 and its time derivatives; rot (nr, 2) = (cos phi, sin phi)."""
    nr = z_in.shape[0]
    px = q[0]
    py = q[1]
    vx = qd[0]
    vy = qd[1]
    ax = qdd[0]
    ay = qdd[1]
    for i in range(nr):
        phi = q[2 + i]
        w = qd[2 + i]
        e = qdd[2 + i]
        c = math.cos(phi)
        s = math.sin(phi)
        rot[i, 0] = c
        rot[i, 1] = s
        rx = c * z_in[i, 0] - s * z_in[i, 1]
        ry = s * z_in[i, 0] + c * z_in[i, 1]
        pc[i, 0] = px + rx
        pc[i, 1] = py + ry
        vc[i, 0] = vx - w * ry
        vc[i, 1] = vy + w * rx
        ac[i, 0] = ax - e * ry - w * w * rx
        ac[i, 1] = ay + e * rx - w * w * ry
        dx = c * z_out[i, 0] - s * z_out[i, 1]
        dy = s * z_out[i, 0] + c * z_out[i, 1]
        px += dx
        py += dy
        ax += -e * dy - w * w * dx
        ay += e * dx - w * w * dy
        vx += -w * dy
        vy += w * dx


@njit(cache=True)
def body_forces(q, qd, rot, mass, z_in, sde_stiffness, sde_damping, sde_rest_angle, gravity,
                load_rfe, load_offset, load_force, load_moment, load_factor, force):
    """Applied forces on every RFE, force (nr, 3) = (Fx, Fy, torque about C_i):
    gravity -m g e_y (eq. 8.60-8.61), Kelvin-Voigt SDE moments (eqs. 8.62-8.63) and point
    loads with their moments about C_i (eq. 8.64). Gravity and point loads scale with
    load_factor (load ramping in statics)."""
    nr = mass.shape[0]
    for i in range(nr):
        force[i, 0] = 0.0
        force[i, 1] = -load_factor * mass[i] * gravity
        force[i, 2] = 0.0
    for j in range(nr - 1):
        # SDE j+1 joins RFE j and RFE j+1: moment c (phi_{j+1} - phi_j - rest) + d (rate)
        moment = (sde_stiffness[j] * (q[3 + j] - q[2 + j] - sde_rest_angle[j])
                  + sde_damping[j] * (qd[3 + j] - qd[2 + j]))
        force[j, 2] += moment
        force[j + 1, 2] -= moment
    for k in range(load_rfe.shape[0]):
        i = load_rfe[k]
        c = rot[i, 0]
        s = rot[i, 1]
        rx = c * load_offset[k, 0] - s * load_offset[k, 1]
        ry = s * load_offset[k, 0] + c * load_offset[k, 1]
        fx = load_factor * load_force[k, 0]
        fy = load_factor * load_force[k, 1]
        force[i, 0] += fx
        force[i, 1] += fy
        force[i, 2] += rx * fy - ry * fx + load_factor * load_moment[k]


@njit(cache=True)
def constraint_blocks(rot, qd, z_in, z_out, end_a, end_b, base_acc, g_left, g_right, gamma, active):
    """Constraint Jacobian blocks of group g (0: base, 1..n: joints A_g, n+1: end B):
    g_left[g] (3x3) on RFE g-1, g_right[g] on RFE g, and the acceleration right-hand side
    gamma[g] (G a = gamma). base_acc = prescribed (x'', y'', phi_0'') of the base (eq. 8.69)."""
    nr = z_in.shape[0]
    ng = nr + 1
    for g in range(ng):
        for a in range(3):
            gamma[g, a] = 0.0
            active[g, a] = False
            for b in range(3):
                g_left[g, a, b] = 0.0
                g_right[g, a, b] = 0.0
    # base, group 0: A_0 of RFE 0 follows (x0, y0); clamped also phi_0
    c = rot[0, 0]
    s = rot[0, 1]
    w = qd[2]
    rx = -(c * z_in[0, 0] - s * z_in[0, 1])      # C_0 -> A_0
    ry = -(s * z_in[0, 0] + c * z_in[0, 1])
    if end_a >= PINNED:
        g_right[0, 0, 0] = 1.0
        g_right[0, 0, 2] = -ry
        g_right[0, 1, 1] = 1.0
        g_right[0, 1, 2] = rx
        gamma[0, 0] = base_acc[0] + w * w * rx
        gamma[0, 1] = base_acc[1] + w * w * ry
        active[0, 0] = True
        active[0, 1] = True
    if end_a == CLAMPED:
        g_right[0, 2, 2] = 1.0
        gamma[0, 2] = base_acc[2]
        active[0, 2] = True
    # joints A_g between RFE g-1 and RFE g
    for g in range(1, nr):
        c1 = rot[g - 1, 0]
        s1 = rot[g - 1, 1]
        w1 = qd[1 + g]
        lx = z_out[g - 1, 0] - z_in[g - 1, 0]
        ly = z_out[g - 1, 1] - z_in[g - 1, 1]
        r1x = c1 * lx - s1 * ly                   # C_{g-1} -> A_g
        r1y = s1 * lx + c1 * ly
        c2 = rot[g, 0]
        s2 = rot[g, 1]
        w2 = qd[2 + g]
        r2x = -(c2 * z_in[g, 0] - s2 * z_in[g, 1])  # C_g -> A_g
        r2y = -(s2 * z_in[g, 0] + c2 * z_in[g, 1])
        g_left[g, 0, 0] = 1.0
        g_left[g, 0, 2] = -r1y
        g_left[g, 1, 1] = 1.0
        g_left[g, 1, 2] = r1x
        g_right[g, 0, 0] = -1.0
        g_right[g, 0, 2] = r2y
        g_right[g, 1, 1] = -1.0
        g_right[g, 1, 2] = -r2x
        gamma[g, 0] = w1 * w1 * r1x - w2 * w2 * r2x
        gamma[g, 1] = w1 * w1 * r1y - w2 * w2 * r2y
        active[g, 0] = True
        active[g, 1] = True
    # end B, group nr: A_{n+1} of RFE n fixed; clamped also phi_n
    n = nr - 1
    c = rot[n, 0]
    s = rot[n, 1]
    w = qd[2 + n]
    lx = z_out[n, 0] - z_in[n, 0]
    ly = z_out[n, 1] - z_in[n, 1]
    rx = c * lx - s * ly                          # C_n -> B
    ry = s * lx + c * ly
    if end_b >= PINNED:
        g_left[nr, 0, 0] = 1.0
        g_left[nr, 0, 2] = -ry
        g_left[nr, 1, 1] = 1.0
        g_left[nr, 1, 2] = rx
        gamma[nr, 0] = w * w * rx
        gamma[nr, 1] = w * w * ry
        active[nr, 0] = True
        active[nr, 1] = True
    if end_b == CLAMPED:
        g_left[nr, 2, 2] = 1.0
        active[nr, 2] = True


@njit(cache=True)
def _solve3(a, b, out):
    """out = a^-1 b for a 3x3 matrix a and a 3x3 (or 3x1 as 3x3 with columns) b."""
    det = (a[0, 0] * (a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1])
           - a[0, 1] * (a[1, 0] * a[2, 2] - a[1, 2] * a[2, 0])
           + a[0, 2] * (a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]))
    inv00 = (a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1]) / det
    inv01 = (a[0, 2] * a[2, 1] - a[0, 1] * a[2, 2]) / det
    inv02 = (a[0, 1] * a[1, 2] - a[0, 2] * a[1, 1]) / det
    inv10 = (a[1, 2] * a[2, 0] - a[1, 0] * a[2, 2]) / det
    inv11 = (a[0, 0] * a[2, 2] - a[0, 2] * a[2, 0]) / det
    inv12 = (a[0, 2] * a[1, 0] - a[0, 0] * a[1, 2]) / det
    inv20 = (a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]) / det
    inv21 = (a[0, 1] * a[2, 0] - a[0, 0] * a[2, 1]) / det
    inv22 = (a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]) / det
    for k in range(b.shape[1]):
        b0 = b[0, k]
        b1 = b[1, k]
        b2 = b[2, k]
        out[0, k] = inv00 * b0 + inv01 * b1 + inv02 * b2
        out[1, k] = inv10 * b0 + inv11 * b1 + inv12 * b2
        out[2, k] = inv20 * b0 + inv21 * b1 + inv22 * b2


@njit(cache=True)
def accelerations(q, qd, base_acc, mass, inertia, z_in, z_out, sde_stiffness, sde_damping,
                  sde_rest_angle, gravity, end_a, end_b, load_rfe, load_offset, load_force,
                  load_moment, load_factor, qdd, reaction,
                  rot, pc, vc, ac, force, g_left, g_right, gamma, active, diag, upper, rhs, tmp33, tmp3):
    """Forward dynamics of one planar link: qdd (n+3,) and the constraint forces
    reaction (nr+1, 3) that the base (group 0), the joints A_1..A_n and end B (group n+1)
    exert on the RFE after them (base, joints) or on RFE n (end B): (Fx, Fy, Mz), eqs.
    8.67-8.70. O(n): block-tridiagonal Schur complement of the joint reactions."""
    nr = mass.shape[0]
    ng = nr + 1
    for a in range(qdd.shape[0]):
        qdd[a] = 0.0
    body_kinematics(q, qd, qdd, z_in, z_out, rot, pc, vc, ac)   # positions, rot; ac rewritten below
    body_forces(q, qd, rot, mass, z_in, sde_stiffness, sde_damping, sde_rest_angle, gravity,
                load_rfe, load_offset, load_force, load_moment, load_factor, force)
    constraint_blocks(rot, qd, z_in, z_out, end_a, end_b, base_acc, g_left, g_right, gamma, active)
    # Schur complement S = G M^-1 G^T: diag[g] (3x3), upper[g] = S[g, g+1]; rhs = G M^-1 F - gamma
    for g in range(ng):
        for a in range(3):
            rhs[g, a] = -gamma[g, a]
            for b in range(3):
                diag[g, a, b] = 0.0
                upper[g, a, b] = 0.0
        if g >= 1:
            i = g - 1
            for a in range(3):
                rhs[g, a] += (g_left[g, a, 0] * force[i, 0] + g_left[g, a, 1] * force[i, 1]) / mass[i] \
                    + g_left[g, a, 2] * force[i, 2] / inertia[i]
                for b in range(3):
                    diag[g, a, b] += (g_left[g, a, 0] * g_left[g, b, 0] + g_left[g, a, 1] * g_left[g, b, 1]) / mass[i] \
                        + g_left[g, a, 2] * g_left[g, b, 2] / inertia[i]
        if g < nr:
            i = g
            for a in range(3):
                rhs[g, a] += (g_right[g, a, 0] * force[i, 0] + g_right[g, a, 1] * force[i, 1]) / mass[i] \
                    + g_right[g, a, 2] * force[i, 2] / inertia[i]
                for b in range(3):
                    diag[g, a, b] += (g_right[g, a, 0] * g_right[g, b, 0] + g_right[g, a, 1] * g_right[g, b, 1]) / mass[i] \
                        + g_right[g, a, 2] * g_right[g, b, 2] / inertia[i]
                    upper[g, a, b] = (g_right[g, a, 0] * g_left[g + 1, b, 0]
                                      + g_right[g, a, 1] * g_left[g + 1, b, 1]) / mass[i] \
                        + g_right[g, a, 2] * g_left[g + 1, b, 2] / inertia[i]
        for a in range(3):
            if not active[g, a]:
                diag[g, a, a] = 1.0
                rhs[g, a] = 0.0
    # block Thomas, forward: diag[g] <- diag[g] - upper[g-1]^T diag[g-1]^-1 upper[g-1]
    for g in range(1, ng):
        _solve3(diag[g - 1], upper[g - 1], tmp33)          # tmp33 = D^-1 U
        for a in range(3):
            tmp3[a, 0] = rhs[g - 1, a]
        _solve3(diag[g - 1], tmp3, tmp3)
        for a in range(3):
            for b in range(3):
                acc = 0.0
                for k in range(3):
                    acc += upper[g - 1, k, a] * tmp33[k, b]
                diag[g, a, b] -= acc
            acc = 0.0
            for k in range(3):
                acc += upper[g - 1, k, a] * tmp3[k, 0]
            rhs[g, a] -= acc
    # backward
    for a in range(3):
        tmp3[a, 0] = rhs[ng - 1, a]
    _solve3(diag[ng - 1], tmp3, tmp3)
    for a in range(3):
        reaction[ng - 1, a] = tmp3[a, 0]
    for g in range(ng - 2, -1, -1):
        for a in range(3):
            acc = rhs[g, a]
            for k in range(3):
                acc -= upper[g, a, k] * reaction[g + 1, k]
            tmp3[a, 0] = acc
        _solve3(diag[g], tmp3, tmp3)
        for a in range(3):
            reaction[g, a] = tmp3[a, 0]
    # body accelerations a = M^-1 (F - G^T lam) and the generalised accelerations
    for i in range(nr):
        for b in range(3):
            f = force[i, b]
            for a in range(3):
                f -= g_right[i, a, b] * reaction[i, a] + g_left[i + 1, a, b] * reaction[i + 1, a]
            if b < 2:
                ac[i, b] = f / mass[i]
            else:
                qdd[2 + i] = f / inertia[i]
    c = rot[0, 0]
    s = rot[0, 1]
    rx = -(c * z_in[0, 0] - s * z_in[0, 1])      # C_0 -> A_0
    ry = -(s * z_in[0, 0] + c * z_in[0, 1])
    w = qd[2]
    qdd[0] = ac[0, 0] - qdd[2] * ry - w * w * rx
    qdd[1] = ac[0, 1] + qdd[2] * rx - w * w * ry
    # constraint forces on the link (eq. 8.70): base and end B: -lam (force at A_0 / B, moment);
    # joint g: the force +lam that RFE g-1 exerts on RFE g at A_g
    for g in range(ng):
        if g == 0 or g == nr:
            for a in range(3):
                reaction[g, a] = -reaction[g, a]
        else:
            reaction[g, 2] = 0.0


@njit(cache=True)
def residual(q, qd, qdd, mass, inertia, z_in, z_out, sde_stiffness, sde_damping, sde_rest_angle,
             gravity, load_rfe, load_offset, load_force, load_moment, load_factor, end_reaction, r,
             rot, pc, vc, ac, force):
    """Generalised residual r = A qdd + B qd + C q + dVg/dq - Q (eqs. 8.57-8.66), with the
    end-B reaction end_reaction = (Fx, Fy, Mz) applied at B counted as a load (eq. 8.67).
    O(n): r = J^T (M a - F) with a = J qdd + Jdot qd."""
    nr = mass.shape[0]
    n = nr - 1
    body_kinematics(q, qd, qdd, z_in, z_out, rot, pc, vc, ac)
    body_forces(q, qd, rot, mass, z_in, sde_stiffness, sde_damping, sde_rest_angle, gravity,
                load_rfe, load_offset, load_force, load_moment, load_factor, force)
    # end-B reaction: force at B on RFE n
    c = rot[n, 0]
    s = rot[n, 1]
    lx = z_out[n, 0] - z_in[n, 0]
    ly = z_out[n, 1] - z_in[n, 1]
    rx = c * lx - s * ly
    ry = s * lx + c * ly
    force[n, 0] += end_reaction[0]
    force[n, 1] += end_reaction[1]
    force[n, 2] += rx * end_reaction[1] - ry * end_reaction[0] + end_reaction[2]
    # suffix sums of the inertial-minus-applied forces
    sx = 0.0
    sy = 0.0
    for i in range(n, -1, -1):
        ex = mass[i] * ac[i, 0] - force[i, 0]
        ey = mass[i] * ac[i, 1] - force[i, 1]
        em = inertia[i] * qdd[2 + i] - force[i, 2]
        c = rot[i, 0]
        s = rot[i, 1]
        zx = c * z_in[i, 0] - s * z_in[i, 1]
        zy = s * z_in[i, 0] + c * z_in[i, 1]
        dx = c * z_out[i, 0] - s * z_out[i, 1]
        dy = s * z_out[i, 0] + c * z_out[i, 1]
        # dp_C/dphi_i = perp(R z_in) for RFE i, perp(R z_out) for the RFEs after it
        r[2 + i] = em + (-zy * ex + zx * ey) + (-dy * sx + dx * sy)
        sx += ex
        sy += ey
    r[0] = sx
    r[1] = sy


@njit(cache=True)
def load_stiffness(rot, mass, z_in, z_out, gravity, load_rfe, load_offset, load_force, load_factor,
                   end_force, k_diag, suffix):
    """Diagonal stiffness of the dead loads in the angle coordinates, k_diag[i] =
    -d Q_phi_i / d phi_i (gravity eq. 8.61 and point loads eq. 8.64 depend on phi_i only).
    end_force (2,): the reaction of a fixed end B, a load at B (the curvature term
    mu . d2 Phi/dq2 of the constraint, eq. 8.67)."""
    nr = mass.shape[0]
    for i in range(nr):
        suffix[i, 0] = 0.0
        suffix[i, 1] = -load_factor * mass[i] * gravity
        k_diag[i] = 0.0
    n = nr - 1
    suffix[n, 0] += end_force[0]
    suffix[n, 1] += end_force[1]
    c = rot[n, 0]
    s = rot[n, 1]
    lx = z_out[n, 0] - z_in[n, 0]
    ly = z_out[n, 1] - z_in[n, 1]
    k_diag[n] += (c * lx - s * ly) * end_force[0] + (s * lx + c * ly) * end_force[1]
    for k in range(load_rfe.shape[0]):
        i = load_rfe[k]
        fx = load_factor * load_force[k, 0]
        fy = load_factor * load_force[k, 1]
        suffix[i, 0] += fx
        suffix[i, 1] += fy
        c = rot[i, 0]
        s = rot[i, 1]
        rx = c * load_offset[k, 0] - s * load_offset[k, 1]
        ry = s * load_offset[k, 0] + c * load_offset[k, 1]
        k_diag[i] += rx * fx + ry * fy
    sx = 0.0
    sy = 0.0
    for i in range(nr - 1, -1, -1):
        c = rot[i, 0]
        s = rot[i, 1]
        zx = c * z_in[i, 0] - s * z_in[i, 1]
        zy = s * z_in[i, 0] + c * z_in[i, 1]
        dx = c * z_out[i, 0] - s * z_out[i, 1]
        dy = s * z_out[i, 0] + c * z_out[i, 1]
        k_diag[i] += zx * suffix[i, 0] + zy * suffix[i, 1] + dx * sx + dy * sy
        sx += suffix[i, 0]
        sy += suffix[i, 1]


@njit(cache=True)
def assemble_kkt(rot, qd, mass, inertia, z_in, z_out, sde_stiffness, sde_damping, k_diag,
                 c_m, c_d, c_k, end_a, end_b, r, end_violation, ab, rhs,
                 g_left, g_right, gamma, active, base_acc):
    """Banded Newton system (LAPACK band storage ab[6 + i - j, j], half bandwidth 6) for the
    correction of the free coordinates: [[H, G^T], [G, 0]] with H = c_m M + c_d D + c_k K on
    the RFEs (K: SDE stiffness C of eq. 8.62 plus the load stiffness k_diag), ordered
    group 0, RFE 0, group 1, RFE 1, ..., RFE n, group n+1 (group g at 6g, RFE i at 6i+3).
    Right-hand side: -f on the RFEs with J^T f = r, -end_violation / c_k on end group B."""
    nr = mass.shape[0]
    size = 6 * nr + 3
    for a in range(ab.shape[0]):
        for j in range(size):
            ab[a, j] = 0.0
    for j in range(size):
        rhs[j] = 0.0
    constraint_blocks(rot, qd, z_in, z_out, end_a, end_b, base_acc, g_left, g_right, gamma, active)
    u = HALF_BANDWIDTH
    for i in range(nr):
        o = 6 * i + 3
        ab[u, o] += c_m * mass[i]
        ab[u, o + 1] += c_m * mass[i]
        kphi = c_m * inertia[i] + c_k * k_diag[i]
        if i >= 1:
            kphi += c_k * sde_stiffness[i - 1] + c_d * sde_damping[i - 1]
            off = -(c_k * sde_stiffness[i - 1] + c_d * sde_damping[i - 1])
            p = o - 6 + 2
            ab[u + p - (o + 2), o + 2] += off
            ab[u + (o + 2) - p, p] += off
        if i < nr - 1:
            kphi += c_k * sde_stiffness[i] + c_d * sde_damping[i]
        ab[u, o + 2] += kphi
    for g in range(nr + 1):
        og = 6 * g
        for a in range(3):
            row = og + a
            if not active[g, a]:
                ab[u, row] = 1.0
                continue
            if g >= 1:
                ob = 6 * (g - 1) + 3
                for b in range(3):
                    v = g_left[g, a, b]
                    if v != 0.0:
                        ab[u + row - (ob + b), ob + b] += v
                        ab[u + (ob + b) - row, row] += v
            if g < nr:
                ob = 6 * g + 3
                for b in range(3):
                    v = g_right[g, a, b]
                    if v != 0.0:
                        ab[u + row - (ob + b), ob + b] += v
                        ab[u + (ob + b) - row, row] += v
    # body-level force f with J^T f = r: (r_x, r_y) on RFE 0, r_phi on every RFE
    c = rot[0, 0]
    s = rot[0, 1]
    zx = c * z_in[0, 0] - s * z_in[0, 1]
    zy = s * z_in[0, 0] + c * z_in[0, 1]
    rhs[3] = -r[0]
    rhs[4] = -r[1]
    rhs[5] = -(r[2] - (-zy * r[0] + zx * r[1]))
    for i in range(1, nr):
        rhs[6 * i + 5] = -r[2 + i]
    for a in range(3):
        if active[nr, a]:
            rhs[6 * nr + a] = -end_violation[a] / c_k


@njit(cache=True)
def correction_from_kkt(rot, z_in, x, nr, dq):
    """Generalised-coordinate correction from the KKT solution x: dphi_i from RFE i,
    d(x, y) of A_0 from the centre of RFE 0 and its rotation."""
    for i in range(nr):
        dq[2 + i] = x[6 * i + 5]
    c = rot[0, 0]
    s = rot[0, 1]
    zx = c * z_in[0, 0] - s * z_in[0, 1]
    zy = s * z_in[0, 0] + c * z_in[0, 1]
    # A_0 = C_0 - R z_in  ->  dA_0 = dC_0 - perp(R z_in) dphi_0
    dq[0] = x[3] + zy * dq[2]
    dq[1] = x[4] - zx * dq[2]


@njit(cache=True)
def end_point(q, z_out):
    """Position of the end point B = A_{n+1} (eq. 8.53 with the joint vectors)."""
    px = q[0]
    py = q[1]
    for i in range(z_out.shape[0]):
        c = math.cos(q[2 + i])
        s = math.sin(q[2 + i])
        px += c * z_out[i, 0] - s * z_out[i, 1]
        py += s * z_out[i, 0] + c * z_out[i, 1]
    return px, py


@njit(cache=True)
def kinetic_energy(q, qd, mass, inertia, z_in, z_out, rot, pc, vc, ac):
    """Sum over RFEs of 1/2 m v_C^2 + 1/2 J phi_dot^2 (eqs. 8.54-8.55)."""
    body_kinematics(q, qd, qd * 0.0, z_in, z_out, rot, pc, vc, ac)
    e = 0.0
    for i in range(mass.shape[0]):
        e += 0.5 * mass[i] * (vc[i, 0] ** 2 + vc[i, 1] ** 2) + 0.5 * inertia[i] * qd[2 + i] ** 2
    return e


@njit(cache=True)
def rk4_run(q, qd, h, nsteps, base_pos, base_vel, base_acc, prescribed,
            mass, inertia, z_in, z_out, sde_stiffness, sde_damping, sde_rest_angle, gravity, end_a, end_b,
            load_rfe, load_offset, load_force, load_moment, record_every, q_out, qd_out,
            rot, pc, vc, ac, force, g_left, g_right, gamma, active, diag, upper, rhs, tmp33, tmp3, reaction):
    """Fixed-step classical RK4 on (q, qd) for nsteps steps. Base motion sampled at the
    stage times: base_*[step, stage] with stages (t, t + h/2, t + h); prescribed (3,) marks
    x, y, phi_0 as prescribed (set from the samples at every stage). Records every
    record_every steps into q_out, qd_out (row 0: initial state). Returns False if the state
    became non-finite."""
    m = q.shape[0]
    k1q = np.empty(m)
    k1v = np.empty(m)
    k2q = np.empty(m)
    k2v = np.empty(m)
    k3q = np.empty(m)
    k3v = np.empty(m)
    k4q = np.empty(m)
    k4v = np.empty(m)
    qs = np.empty(m)
    vs = np.empty(m)
    acc = np.empty(m)
    for a in range(m):
        q_out[0, a] = q[a]
        qd_out[0, a] = qd[a]
    rec = 1
    for step in range(nsteps):
        for stage in range(4):
            if stage == 0:
                for a in range(m):
                    qs[a] = q[a]
                    vs[a] = qd[a]
                si = 0
            elif stage == 1:
                for a in range(m):
                    qs[a] = q[a] + 0.5 * h * k1q[a]
                    vs[a] = qd[a] + 0.5 * h * k1v[a]
                si = 1
            elif stage == 2:
                for a in range(m):
                    qs[a] = q[a] + 0.5 * h * k2q[a]
                    vs[a] = qd[a] + 0.5 * h * k2v[a]
                si = 1
            else:
                for a in range(m):
                    qs[a] = q[a] + h * k3q[a]
                    vs[a] = qd[a] + h * k3v[a]
                si = 2
            for a in range(3):
                if prescribed[a]:
                    qs[a] = base_pos[step, si, a]
                    vs[a] = base_vel[step, si, a]
            accelerations(qs, vs, base_acc[step, si], mass, inertia, z_in, z_out, sde_stiffness, sde_damping,
                          sde_rest_angle, gravity, end_a, end_b, load_rfe, load_offset, load_force,
                          load_moment, 1.0, acc, reaction,
                          rot, pc, vc, ac, force, g_left, g_right, gamma, active, diag, upper, rhs, tmp33, tmp3)
            if stage == 0:
                for a in range(m):
                    k1q[a] = vs[a]
                    k1v[a] = acc[a]
            elif stage == 1:
                for a in range(m):
                    k2q[a] = vs[a]
                    k2v[a] = acc[a]
            elif stage == 2:
                for a in range(m):
                    k3q[a] = vs[a]
                    k3v[a] = acc[a]
            else:
                for a in range(m):
                    k4q[a] = vs[a]
                    k4v[a] = acc[a]
        ok = True
        for a in range(m):
            q[a] += h / 6.0 * (k1q[a] + 2.0 * k2q[a] + 2.0 * k3q[a] + k4q[a])
            qd[a] += h / 6.0 * (k1v[a] + 2.0 * k2v[a] + 2.0 * k3v[a] + k4v[a])
            if not (math.isfinite(q[a]) and math.isfinite(qd[a])):
                ok = False
        for a in range(3):
            if prescribed[a]:
                q[a] = base_pos[step, 2, a]
                qd[a] = base_vel[step, 2, a]
        if not ok:
            return False
        if (step + 1) % record_every == 0:
            for a in range(m):
                q_out[rec, a] = q[a]
                qd_out[rec, a] = qd[a]
            rec += 1
    return True
