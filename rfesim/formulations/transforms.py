"""Homogeneous transformations shared by the classical, modified and chain formulations.

Chapter 8 writes every body's pose as a 4x4 homogeneous matrix T (eq. 8.5), a product of
joint matrices along the kinematic chain (eqs. 8.9, 8.10.2, 8.38), and its kinetic energy
in the trace form E = 1/2 tr(T' H T'^T) (eqs. 8.11, 8.15, 8.42) with the pseudo-inertia H
of the body. The equations of motion need the first and second partial derivatives
T_k = dT/dq_k and T_kl = d2T/dq_k dq_l (eqs. 8.12, 8.17, 8.43).

A joint matrix is J(q) = C M(q): a constant placement C (the undeformed pose T~(p,i'),
eq. 8.5, or the offset l(p,i-1) of eq. 8.36) times the joint motion M(q). Joint kinds:

===========  ======  =====================================================================
kind         coords  motion M(q)
===========  ======  =====================================================================
FIXED        0       identity
REVOLUTE     1       rotation about the unit axis a by q (Rodrigues)
PRISMATIC    1       translation a q
SPHERICAL    3       ZYX Euler angles (phi_x, phi_y, phi_z): Rz Ry Rx (eqs. 8.36.1, 8.37)
FREE_ZYX     6       (x, y, z, phi_x, phi_y, phi_z): eq. 8.7 (classical, nonlinear)
FREE_LINEAR  6       (x, y, z, phi_x, phi_y, phi_z): eq. 8.8 (classical, linear)
===========  ======  =====================================================================

All kernels are numba-compiled scalar code writing into preallocated outputs; they are
also callable from Python (the tests compare them with complex-step derivatives).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

FIXED = 0
REVOLUTE = 1
PRISMATIC = 2
SPHERICAL = 3
FREE_ZYX = 4
FREE_LINEAR = 5

JOINT_COORDS = {FIXED: 0, REVOLUTE: 1, PRISMATIC: 1, SPHERICAL: 3, FREE_ZYX: 6, FREE_LINEAR: 6}
MAX_JOINT_COORDS = 6


@njit(cache=True)
def elementary_rotation_into(axis, angle, order, out):
    """d^order/dangle^order of the rotation about coordinate axis 0/1/2 (x/y/z), into out (3, 3).

    The derivative of order k replaces angle by angle + k pi/2 in cos and sin and removes
    the constant 1 on the axis.
    """
    c = math.cos(angle + 0.5 * math.pi * order)
    s = math.sin(angle + 0.5 * math.pi * order)
    one = 1.0 if order == 0 else 0.0
    for i in range(3):
        for j in range(3):
            out[i, j] = 0.0
    if axis == 0:
        out[0, 0] = one
        out[1, 1] = c
        out[1, 2] = -s
        out[2, 1] = s
        out[2, 2] = c
    elif axis == 1:
        out[1, 1] = one
        out[0, 0] = c
        out[0, 2] = s
        out[2, 0] = -s
        out[2, 2] = c
    else:
        out[2, 2] = one
        out[0, 0] = c
        out[0, 1] = -s
        out[1, 0] = s
        out[1, 1] = c


@njit(cache=True)
def zyx_rotation_derivative_into(phi_x, phi_y, phi_z, dx, dy, dz, work, out):
    """d^(dx+dy+dz) R / dphi_x^dx dphi_y^dy dphi_z^dz of R = Rz(phi_z) Ry(phi_y) Rx(phi_x)
    (eq. 8.7), into out (3, 3); work is scratch (3, 3, 3)."""
    elementary_rotation_into(2, phi_z, dz, work[0])
    elementary_rotation_into(1, phi_y, dy, work[1])
    elementary_rotation_into(0, phi_x, dx, work[2])
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for k in range(3):
                acc += work[0, i, k] * work[1, k, j]
            out[i, j] = acc                      # Rz Ry into out first, then times Rx
    for i in range(3):
        a0 = out[i, 0]
        a1 = out[i, 1]
        a2 = out[i, 2]
        for j in range(3):
            out[i, j] = a0 * work[2, 0, j] + a1 * work[2, 1, j] + a2 * work[2, 2, j]


@njit(cache=True)
def joint_motion_into(kind, axis, q, M, dM, d2M, work):
    """Joint motion M(q) (4, 4), its first derivatives dM (6, 4, 4) and second derivatives
    d2M (6, 6, 4, 4) for a joint of the given kind; q holds the joint's coordinates.
    Only the leading [:n, :n] entries are written (n = number of joint coordinates)."""
    for i in range(4):
        for j in range(4):
            M[i, j] = 1.0 if i == j else 0.0
    n = 0
    if kind == REVOLUTE or kind == PRISMATIC:
        n = 1
    elif kind == SPHERICAL:
        n = 3
    elif kind == FREE_ZYX or kind == FREE_LINEAR:
        n = 6
    for a in range(n):
        for i in range(4):
            for j in range(4):
                dM[a, i, j] = 0.0
        for b in range(n):
            for i in range(4):
                for j in range(4):
                    d2M[a, b, i, j] = 0.0
    if kind == REVOLUTE:
        # R = I + s K + (1 - c) K^2, K = [a]x (Rodrigues); dR = c K + s K^2; d2R = -s K + c K^2
        c = math.cos(q[0])
        s = math.sin(q[0])
        ax = axis[0]
        ay = axis[1]
        az = axis[2]
        K = work[0]
        K[0, 0] = 0.0
        K[0, 1] = -az
        K[0, 2] = ay
        K[1, 0] = az
        K[1, 1] = 0.0
        K[1, 2] = -ax
        K[2, 0] = -ay
        K[2, 1] = ax
        K[2, 2] = 0.0
        K2 = work[1]
        for i in range(3):
            for j in range(3):
                K2[i, j] = axis[i] * axis[j] - (1.0 if i == j else 0.0)
        for i in range(3):
            for j in range(3):
                M[i, j] = (1.0 if i == j else 0.0) + s * K[i, j] + (1.0 - c) * K2[i, j]
                dM[0, i, j] = c * K[i, j] + s * K2[i, j]
                d2M[0, 0, i, j] = -s * K[i, j] + c * K2[i, j]
    elif kind == PRISMATIC:
        for i in range(3):
            M[i, 3] = axis[i] * q[0]
            dM[0, i, 3] = axis[i]
    elif kind == SPHERICAL or kind == FREE_ZYX:
        o = 0 if kind == SPHERICAL else 3
        if kind == FREE_ZYX:
            for i in range(3):
                M[i, 3] = q[i]
                dM[i, i, 3] = 1.0
        px = q[o]
        py = q[o + 1]
        pz = q[o + 2]
        R = work[3]
        zyx_rotation_derivative_into(px, py, pz, 0, 0, 0, work, R)
        for i in range(3):
            for j in range(3):
                M[i, j] = R[i, j]
        for a in range(3):
            ax = 1 if a == 0 else 0
            ay = 1 if a == 1 else 0
            az = 1 if a == 2 else 0
            zyx_rotation_derivative_into(px, py, pz, ax, ay, az, work, R)
            for i in range(3):
                for j in range(3):
                    dM[o + a, i, j] = R[i, j]
            for b in range(a, 3):
                bx = ax + (1 if b == 0 else 0)
                by = ay + (1 if b == 1 else 0)
                bz = az + (1 if b == 2 else 0)
                zyx_rotation_derivative_into(px, py, pz, bx, by, bz, work, R)
                for i in range(3):
                    for j in range(3):
                        d2M[o + a, o + b, i, j] = R[i, j]
                        d2M[o + b, o + a, i, j] = R[i, j]
    elif kind == FREE_LINEAR:
        # eq. 8.8: I + [phi]x with the translation; first derivatives constant, second zero
        for i in range(3):
            M[i, 3] = q[i]
            dM[i, i, 3] = 1.0
        M[0, 1] = -q[5]
        M[0, 2] = q[4]
        M[1, 0] = q[5]
        M[1, 2] = -q[3]
        M[2, 0] = -q[4]
        M[2, 1] = q[3]
        dM[3, 1, 2] = -1.0
        dM[3, 2, 1] = 1.0
        dM[4, 0, 2] = 1.0
        dM[4, 2, 0] = -1.0
        dM[5, 0, 1] = -1.0
        dM[5, 1, 0] = 1.0
    return n


@njit(cache=True)
def joint_matrices_into(kind, axis, C, q, J, dJ, d2J, M, dM, d2M, work):
    """Joint matrix J = C M(q) with dJ = C dM, d2J = C d2M (eqs. 8.9, 8.36); returns n coords."""
    n = joint_motion_into(kind, axis, q, M, dM, d2M, work)
    mul4_into(C, M, J)
    for a in range(n):
        mul4_into(C, dM[a], dJ[a])
        for b in range(n):
            mul4_into(C, d2M[a, b], d2J[a, b])
    return n


@njit(cache=True, inline="always")
def mul4_into(A, B, out):
    for i in range(4):
        for j in range(4):
            out[i, j] = A[i, 0] * B[0, j] + A[i, 1] * B[1, j] + A[i, 2] * B[2, j] + A[i, 3] * B[3, j]


@njit(cache=True)
def affine_inverse_into(T, out):
    """Inverse of an affine 4x4 matrix [A p; 0 1] (A need not be orthogonal: eq. 8.8)."""
    a = T[0, 0]
    b = T[0, 1]
    c = T[0, 2]
    d = T[1, 0]
    e = T[1, 1]
    f = T[1, 2]
    g = T[2, 0]
    h = T[2, 1]
    k = T[2, 2]
    A00 = e * k - f * h
    A01 = c * h - b * k
    A02 = b * f - c * e
    A10 = f * g - d * k
    A11 = a * k - c * g
    A12 = c * d - a * f
    A20 = d * h - e * g
    A21 = b * g - a * h
    A22 = a * e - b * d
    det = a * A00 + b * A10 + c * A20
    inv = 1.0 / det
    out[0, 0] = A00 * inv
    out[0, 1] = A01 * inv
    out[0, 2] = A02 * inv
    out[1, 0] = A10 * inv
    out[1, 1] = A11 * inv
    out[1, 2] = A12 * inv
    out[2, 0] = A20 * inv
    out[2, 1] = A21 * inv
    out[2, 2] = A22 * inv
    for i in range(3):
        out[i, 3] = -(out[i, 0] * T[0, 3] + out[i, 1] * T[1, 3] + out[i, 2] * T[2, 3])
    out[3, 0] = 0.0
    out[3, 1] = 0.0
    out[3, 2] = 0.0
    out[3, 3] = 1.0


def homogeneous(rotation=None, translation=None) -> np.ndarray:
    """4x4 homogeneous matrix [R r; 0 1] (eq. 8.5)."""
    T = np.eye(4)
    if rotation is not None:
        T[:3, :3] = np.asarray(rotation, dtype=float)
    if translation is not None:
        T[:3, 3] = np.asarray(translation, dtype=float)
    return T


def zyx_matrix(x, y, z, phi_x, phi_y, phi_z) -> np.ndarray:
    """eq. 8.7: the homogeneous matrix of translation (x, y, z) and ZYX angles."""
    M = np.empty((4, 4))
    dM = np.empty((6, 4, 4))
    d2M = np.empty((6, 6, 4, 4))
    joint_motion_into(FREE_ZYX, np.zeros(3), np.array([x, y, z, phi_x, phi_y, phi_z], float), M, dM, d2M,
                      np.empty((4, 3, 3)))
    return M


def pseudo_inertia(mass: float, centre, inertia) -> np.ndarray:
    """Pseudo-inertia H = integral of [r; 1][r; 1]^T dm in the body frame (eqs. 8.11, 8.15).

    mass kg; centre (3,) m, the centre of mass in the body frame; inertia (3,) principal
    moments about the centre of mass along the body axes or a (3, 3) tensor, kg*m^2.
    The second-moment block is 1/2 tr(J) I - J + m c c^T.
    """
    c = np.asarray(centre, dtype=float)
    J = np.asarray(inertia, dtype=float)
    if J.ndim == 1:
        J = np.diag(J)
    H = np.zeros((4, 4))
    H[:3, :3] = 0.5 * np.trace(J) * np.eye(3) - J + mass * np.outer(c, c)
    H[:3, 3] = mass * c
    H[3, :3] = mass * c
    H[3, 3] = mass
    return H


def base_matrices(pos, vel, acc, ang, rate, angacc):
    """Base frame {A} in the inertial frame and its first and second time derivatives
    (T_A, T_A', T_A'') from its translation and ZYX angles (phi_x, phi_y, phi_z) with their
    rates and accelerations (eq. 8.10.2, chain rule with the derivatives of eq. 8.7)."""
    q = np.empty(6)
    qd = np.empty(6)
    qdd = np.empty(6)
    q[:3], q[3:] = pos, ang
    qd[:3], qd[3:] = vel, rate
    qdd[:3], qdd[3:] = acc, angacc
    out = np.empty((3, 4, 4))
    _base_kernel(q, qd, qdd, out)
    return out[0], out[1], out[2]


@njit(cache=True)
def _base_kernel(q, qd, qdd, out):
    M = np.empty((4, 4))
    dM = np.empty((6, 4, 4))
    d2M = np.empty((6, 6, 4, 4))
    joint_motion_into(FREE_ZYX, np.zeros(3), q, M, dM, d2M, np.empty((4, 3, 3)))
    for i in range(4):
        for j in range(4):
            out[0, i, j] = M[i, j]
            vd = 0.0
            vdd = 0.0
            for k in range(6):
                vd += dM[k, i, j] * qd[k]
                vdd += dM[k, i, j] * qdd[k]
                for m in range(6):
                    vdd += d2M[k, m, i, j] * qd[k] * qd[m]
            out[1, i, j] = vd
            out[2, i, j] = vdd


@njit(cache=True)
def joint_scratch():
    """Scratch for ``joint_matrices_into``: J, dJ, d2J (joint matrix and its first and
    second derivatives), M, dM, d2M and work (4, 3, 3), allocated once per kernel call."""
    return (np.empty((4, 4)), np.empty((6, 4, 4)), np.empty((6, 6, 4, 4)), np.empty((4, 4)),
            np.empty((6, 4, 4)), np.empty((6, 6, 4, 4)), np.empty((4, 3, 3)))
