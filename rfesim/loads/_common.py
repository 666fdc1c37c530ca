"""Scalar numba helpers shared by the load kernels."""
from __future__ import annotations

from numba import njit


@njit(cache=True)
def add_force_moment(F, M, i, dx, dy, dz, fx, fy, fz):
    """Add the force f to RFE i and its moment about the RFE centre, d x f, where d is the
    arm from the centre to the point of application (all global)."""
    F[i, 0] += fx
    F[i, 1] += fy
    F[i, 2] += fz
    M[i, 0] += dy * fz - dz * fy
    M[i, 1] += dz * fx - dx * fz
    M[i, 2] += dx * fy - dy * fx
