"""Rotation kinematics shared by every formulation.

ZYX Euler angles (chapter 8, eqs. 8.7 and 8.73): R = Rz(psi) Ry(theta) Rx(phi). In the
absolute formulation (section 8.4) an RFE's coordinates are ordered as in eq. 8.72,
``[x, y, z, phi_z, phi_y, phi_x]``, i.e. ``(psi, theta, phi)`` for the angles.

To stay away from the Euler-angle singularity at theta = +-90 deg, each RFE keeps a
reference rotation R0 and its Euler angles are measured from it, R = R0 Rzyx(angles);
R0 is re-based when the angles grow (docs/theory.md, "Orientation without
singularities"). Relative rotations between neighbouring RFEs are measured with the
rotation vector (exp/log maps) and their right Jacobians.

All functions are numba-compiled scalar code working on small (3,) and (3, 3) arrays;
the ``*_into`` forms write into preallocated outputs so that hot loops do not allocate.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

SMALL_ANGLE = 1e-4


@njit(cache=True)
def rot_zyx_into(psi, theta, phi, out):
    """eq. 8.73: R = Rz(psi) Ry(theta) Rx(phi), written into out (3, 3)."""
    cz = math.cos(psi)
    sz = math.sin(psi)
    cy = math.cos(theta)
    sy = math.sin(theta)
    cx = math.cos(phi)
    sx = math.sin(phi)
    out[0, 0] = cz * cy
    out[0, 1] = cz * sy * sx - sz * cx
    out[0, 2] = cz * sy * cx + sz * sx
    out[1, 0] = sz * cy
    out[1, 1] = sz * sy * sx + cz * cx
    out[1, 2] = sz * sy * cx - cz * sx
    out[2, 0] = -sy
    out[2, 1] = cy * sx
    out[2, 2] = cy * cx


@njit(cache=True, _nrt=True)
def rot_zyx(psi, theta, phi):
    out = np.empty((3, 3))
    rot_zyx_into(psi, theta, phi, out)
    return out


@njit(cache=True)
def euler_rate_matrix_into(psi, theta, phi, out):
    """Body angular velocity from ZYX Euler rates: omega_body = E (psi', theta', phi')."""
    cy = math.cos(theta)
    sy = math.sin(theta)
    cx = math.cos(phi)
    sx = math.sin(phi)
    out[0, 0] = -sy
    out[0, 1] = 0.0
    out[0, 2] = 1.0
    out[1, 0] = cy * sx
    out[1, 1] = cx
    out[1, 2] = 0.0
    out[2, 0] = cy * cx
    out[2, 1] = -sx
    out[2, 2] = 0.0


@njit(cache=True)
def euler_rate_derivative_into(psi, theta, phi, dpsi, dtheta, dphi, out):
    """The velocity part of d(omega_body)/dt: (dE/dt) * rates, written into out (3,)."""
    cy = math.cos(theta)
    sy = math.sin(theta)
    cx = math.cos(phi)
    sx = math.sin(phi)
    out[0] = -dpsi * dtheta * cy
    out[1] = -dtheta * dphi * sx + dpsi * (-dtheta * sy * sx + cy * cx * dphi)
    out[2] = -dtheta * dphi * cx + dpsi * (-dtheta * sy * cx - cy * sx * dphi)


@njit(cache=True, inline="always")
def skew_into(v, out):
    out[0, 0] = 0.0
    out[0, 1] = -v[2]
    out[0, 2] = v[1]
    out[1, 0] = v[2]
    out[1, 1] = 0.0
    out[1, 2] = -v[0]
    out[2, 0] = -v[1]
    out[2, 1] = v[0]
    out[2, 2] = 0.0


@njit(cache=True, inline="always")
def cross_into(a, b, out):
    x = a[1] * b[2] - a[2] * b[1]
    y = a[2] * b[0] - a[0] * b[2]
    z = a[0] * b[1] - a[1] * b[0]
    out[0] = x
    out[1] = y
    out[2] = z


@njit(cache=True, inline="always")
def matvec_into(A, x, out):
    a = A[0, 0] * x[0] + A[0, 1] * x[1] + A[0, 2] * x[2]
    b = A[1, 0] * x[0] + A[1, 1] * x[1] + A[1, 2] * x[2]
    c = A[2, 0] * x[0] + A[2, 1] * x[1] + A[2, 2] * x[2]
    out[0] = a
    out[1] = b
    out[2] = c


@njit(cache=True, inline="always")
def matTvec_into(A, x, out):
    """out = A^T x."""
    a = A[0, 0] * x[0] + A[1, 0] * x[1] + A[2, 0] * x[2]
    b = A[0, 1] * x[0] + A[1, 1] * x[1] + A[2, 1] * x[2]
    c = A[0, 2] * x[0] + A[1, 2] * x[1] + A[2, 2] * x[2]
    out[0] = a
    out[1] = b
    out[2] = c


@njit(cache=True, inline="always")
def matmul_into(A, B, out):
    for i in range(3):
        a0 = A[i, 0]
        a1 = A[i, 1]
        a2 = A[i, 2]
        for j in range(3):
            out[i, j] = a0 * B[0, j] + a1 * B[1, j] + a2 * B[2, j]


@njit(cache=True, inline="always")
def matTmul_into(A, B, out):
    """out = A^T B."""
    for i in range(3):
        for j in range(3):
            out[i, j] = A[0, i] * B[0, j] + A[1, i] * B[1, j] + A[2, i] * B[2, j]


@njit(cache=True)
def exp_so3_into(w0, w1, w2, out):
    """Rotation matrix of the rotation vector (w0, w1, w2) (Rodrigues)."""
    th2 = w0 * w0 + w1 * w1 + w2 * w2
    if th2 < SMALL_ANGLE * SMALL_ANGLE:
        a = 1.0 - th2 / 6.0 + th2 * th2 / 120.0
        b = 0.5 - th2 / 24.0 + th2 * th2 / 720.0
    else:
        th = math.sqrt(th2)
        a = math.sin(th) / th
        b = (1.0 - math.cos(th)) / th2
    out[0, 0] = 1.0 - b * (w1 * w1 + w2 * w2)
    out[1, 1] = 1.0 - b * (w0 * w0 + w2 * w2)
    out[2, 2] = 1.0 - b * (w0 * w0 + w1 * w1)
    out[0, 1] = -a * w2 + b * w0 * w1
    out[1, 0] = a * w2 + b * w0 * w1
    out[0, 2] = a * w1 + b * w0 * w2
    out[2, 0] = -a * w1 + b * w0 * w2
    out[1, 2] = -a * w0 + b * w1 * w2
    out[2, 1] = a * w0 + b * w1 * w2


@njit(cache=True)
def quaternion_from_matrix(R):
    """Unit quaternion (w, x, y, z) of R with w >= 0 (Shepperd's method), as a tuple."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    if tr >= R[0, 0] and tr >= R[1, 1] and tr >= R[2, 2]:
        s = math.sqrt(1.0 + tr) * 2.0
        w = 0.25 * s
        x = (R[2, 1] - R[1, 2]) / s
        y = (R[0, 2] - R[2, 0]) / s
        z = (R[1, 0] - R[0, 1]) / s
    elif R[0, 0] >= R[1, 1] and R[0, 0] >= R[2, 2]:
        s = math.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2]) * 2.0
        w = (R[2, 1] - R[1, 2]) / s
        x = 0.25 * s
        y = (R[0, 1] + R[1, 0]) / s
        z = (R[0, 2] + R[2, 0]) / s
    elif R[1, 1] >= R[2, 2]:
        s = math.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2]) * 2.0
        w = (R[0, 2] - R[2, 0]) / s
        x = (R[0, 1] + R[1, 0]) / s
        y = 0.25 * s
        z = (R[1, 2] + R[2, 1]) / s
    else:
        s = math.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1]) * 2.0
        w = (R[1, 0] - R[0, 1]) / s
        x = (R[0, 2] + R[2, 0]) / s
        y = (R[1, 2] + R[2, 1]) / s
        z = 0.25 * s
    if w < 0.0:
        w = -w
        x = -x
        y = -y
        z = -z
    n = math.sqrt(w * w + x * x + y * y + z * z)
    return w / n, x / n, y / n, z / n


@njit(cache=True)
def log_so3_into(R, out):
    """Rotation vector of R (angle in [0, pi]), robust near 0 and pi (via the quaternion)."""
    w, x, y, z = quaternion_from_matrix(R)
    vn = math.sqrt(x * x + y * y + z * z)
    if vn < 1e-300:
        out[0] = 0.0
        out[1] = 0.0
        out[2] = 0.0
        return
    angle = 2.0 * math.atan2(vn, w)
    if vn < 1e-7:
        f = 2.0 / w * (1.0 + vn * vn / (3.0 * w * w))
    else:
        f = angle / vn
    out[0] = f * x
    out[1] = f * y
    out[2] = f * z


@njit(cache=True)
def relative_rotation_terms(R, theta, Rhalf, Jri, Jrh):
    """For a relative rotation R (angle < pi): its rotation vector theta = log(R), the half
    rotation Rhalf = exp(theta/2), J_r(theta)^-1 and J_r(theta/2) -- all from the quaternion
    of R with one atan2 (used by every SDE, so it is written for speed; the plain
    log/exp/Jacobian functions above are its readable reference in the tests)."""
    w, x, y, z = quaternion_from_matrix(R)
    s2 = x * x + y * y + z * z
    s = math.sqrt(s2)                      # sin(angle/2)
    angle = 2.0 * math.atan2(s, w)
    if s > 1e-300:
        f = angle / s
    else:
        f = 2.0
    theta[0] = f * x
    theta[1] = f * y
    theta[2] = f * z
    th2 = angle * angle
    # half rotation quaternion: ((1 + w), v) / sqrt(2 (1 + w))
    nh = math.sqrt(2.0 * (1.0 + w))
    hw = (1.0 + w) / nh
    hx = x / nh
    hy = y / nh
    hz = z / nh
    Rhalf[0, 0] = 1.0 - 2.0 * (hy * hy + hz * hz)
    Rhalf[1, 1] = 1.0 - 2.0 * (hx * hx + hz * hz)
    Rhalf[2, 2] = 1.0 - 2.0 * (hx * hx + hy * hy)
    Rhalf[0, 1] = 2.0 * (hx * hy - hz * hw)
    Rhalf[1, 0] = 2.0 * (hx * hy + hz * hw)
    Rhalf[0, 2] = 2.0 * (hx * hz + hy * hw)
    Rhalf[2, 0] = 2.0 * (hx * hz - hy * hw)
    Rhalf[1, 2] = 2.0 * (hy * hz - hx * hw)
    Rhalf[2, 1] = 2.0 * (hy * hz + hx * hw)
    # J_r^-1(theta) = I + 1/2 [th]x + c [th]x^2, c = 1/th^2 - w / (2 th s)
    if angle < 2e-2:
        c = 1.0 / 12.0 + th2 / 720.0 + th2 * th2 / 30240.0
    else:
        c = 1.0 / th2 - w / (2.0 * angle * s)
    # J_r(phi) with phi = theta/2: a = (1 - cos phi)/phi^2 = s^2 / ((1 + w) phi^2),
    # b = (phi - sin phi)/phi^3; cos phi = w, sin phi = s
    ph = 0.5 * angle
    ph2 = ph * ph
    if ph < 1e-2:
        a = 0.5 - ph2 / 24.0 + ph2 * ph2 / 720.0
        b = 1.0 / 6.0 - ph2 / 120.0 + ph2 * ph2 / 5040.0
    else:
        a = s2 / ((1.0 + w) * ph2)
        b = (ph - s) / (ph2 * ph)
    t0 = theta[0]
    t1 = theta[1]
    t2 = theta[2]
    h0 = 0.5 * t0
    h1 = 0.5 * t1
    h2 = 0.5 * t2
    for i in range(3):
        for j in range(3):
            Jri[i, j] = c * theta[i] * theta[j]
    Jri[0, 0] += 1.0 - c * th2
    Jri[1, 1] += 1.0 - c * th2
    Jri[2, 2] += 1.0 - c * th2
    Jri[0, 1] -= 0.5 * t2
    Jri[1, 0] += 0.5 * t2
    Jri[0, 2] += 0.5 * t1
    Jri[2, 0] -= 0.5 * t1
    Jri[1, 2] -= 0.5 * t0
    Jri[2, 1] += 0.5 * t0
    hv = (h0, h1, h2)
    for i in range(3):
        for j in range(3):
            Jrh[i, j] = b * hv[i] * hv[j]
    Jrh[0, 0] += 1.0 - b * ph2
    Jrh[1, 1] += 1.0 - b * ph2
    Jrh[2, 2] += 1.0 - b * ph2
    Jrh[0, 1] += a * h2
    Jrh[1, 0] -= a * h2
    Jrh[0, 2] -= a * h1
    Jrh[2, 0] += a * h1
    Jrh[1, 2] += a * h0
    Jrh[2, 1] -= a * h0


@njit(cache=True)
def right_jacobian_into(w, out):
    """J_r(w): exp(w + dw) = exp(w) exp(J_r(w) dw) to first order."""
    th2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
    if th2 < SMALL_ANGLE * SMALL_ANGLE:
        a = 0.5 - th2 / 24.0
        b = 1.0 / 6.0 - th2 / 120.0
    else:
        th = math.sqrt(th2)
        a = (1.0 - math.cos(th)) / th2
        b = (th - math.sin(th)) / (th2 * th)
    # J_r = I - a [w]x + b [w]x^2 ; [w]x^2 = w w^T - th2 I
    for i in range(3):
        for j in range(3):
            out[i, j] = b * w[i] * w[j]
        out[i, i] += 1.0 - b * th2
    out[0, 1] += a * w[2]
    out[1, 0] -= a * w[2]
    out[0, 2] -= a * w[1]
    out[2, 0] += a * w[1]
    out[1, 2] += a * w[0]
    out[2, 1] -= a * w[0]


@njit(cache=True)
def right_jacobian_inverse_into(w, out):
    """J_r(w)^-1 = I + 1/2 [w]x + c [w]x^2, c = 1/th^2 - (1 + cos th)/(2 th sin th)."""
    th2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2]
    if th2 < SMALL_ANGLE * SMALL_ANGLE:
        c = 1.0 / 12.0 + th2 / 720.0
    else:
        th = math.sqrt(th2)
        c = 1.0 / th2 - (1.0 + math.cos(th)) / (2.0 * th * math.sin(th))
    for i in range(3):
        for j in range(3):
            out[i, j] = c * w[i] * w[j]
        out[i, i] += 1.0 - c * th2
    out[0, 1] -= 0.5 * w[2]
    out[1, 0] += 0.5 * w[2]
    out[0, 2] += 0.5 * w[1]
    out[2, 0] -= 0.5 * w[1]
    out[1, 2] -= 0.5 * w[0]
    out[2, 1] += 0.5 * w[0]


@njit(cache=True)
def solve3_sym_into(A, b, out):
    """Solve a 3x3 system A x = b (Cramer's rule with the adjugate; A need not be symmetric)."""
    c00 = A[1, 1] * A[2, 2] - A[1, 2] * A[2, 1]
    c01 = A[1, 2] * A[2, 0] - A[1, 0] * A[2, 2]
    c02 = A[1, 0] * A[2, 1] - A[1, 1] * A[2, 0]
    det = A[0, 0] * c00 + A[0, 1] * c01 + A[0, 2] * c02
    inv = 1.0 / det
    c10 = A[0, 2] * A[2, 1] - A[0, 1] * A[2, 2]
    c11 = A[0, 0] * A[2, 2] - A[0, 2] * A[2, 0]
    c12 = A[0, 1] * A[2, 0] - A[0, 0] * A[2, 1]
    c20 = A[0, 1] * A[1, 2] - A[0, 2] * A[1, 1]
    c21 = A[0, 2] * A[1, 0] - A[0, 0] * A[1, 2]
    c22 = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    x0 = (c00 * b[0] + c10 * b[1] + c20 * b[2]) * inv
    x1 = (c01 * b[0] + c11 * b[1] + c21 * b[2]) * inv
    x2 = (c02 * b[0] + c12 * b[1] + c22 * b[2]) * inv
    out[0] = x0
    out[1] = x1
    out[2] = x2


def rotation_to_zyx(R: np.ndarray) -> tuple[float, float, float]:
    """(psi, theta, phi) of R = Rz Ry Rx (numpy helper for outputs)."""
    theta = -math.asin(max(-1.0, min(1.0, R[2, 0])))
    psi = math.atan2(R[1, 0], R[0, 0])
    phi = math.atan2(R[2, 1], R[2, 2])
    return psi, theta, phi


def frame_from_tangent(t: np.ndarray, up_hint: np.ndarray | None = None) -> np.ndarray:
    """An orthonormal frame whose x axis is the unit tangent t; y horizontal when possible."""
    t = np.asarray(t, dtype=float)
    t = t / np.linalg.norm(t)
    up = np.array([0.0, 0.0, 1.0]) if up_hint is None else np.asarray(up_hint, dtype=float)
    y = np.cross(up, t)
    if np.linalg.norm(y) < 1e-8:
        y = np.cross(np.array([1.0, 0.0, 0.0]) if abs(t[0]) < 0.9 else np.array([0.0, 1.0, 0.0]), t)
    y = y / np.linalg.norm(y)
    z = np.cross(t, y)
    return np.column_stack([t, y, z])


def _cross3(a, b) -> np.ndarray:
    """np.cross of two 3-vectors: the same products and differences, without its axis
    handling (1 us against 15 us; the model build runs it for every RFE)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def minimal_rotation(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation taking unit vector a to unit vector b (parallel transport)."""
    a = a / np.linalg.norm(a)
    b = b / np.linalg.norm(b)
    v = _cross3(a, b)
    c = float(np.dot(a, b))
    s = float(np.linalg.norm(v))
    if s < 1e-14:
        if c > 0:
            return np.eye(3)
        # 180 degrees about any axis normal to a
        n = np.cross(a, [1.0, 0.0, 0.0])
        if np.linalg.norm(n) < 1e-6:
            n = np.cross(a, [0.0, 1.0, 0.0])
        n /= np.linalg.norm(n)
        return 2.0 * np.outer(n, n) - np.eye(3)
    k = v / s
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + s * K + (1 - c) * K @ K
