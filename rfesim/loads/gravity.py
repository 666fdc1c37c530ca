"""Gravity on the RFEs (eq. 8.19: potential m g z of each centre of mass)."""
from __future__ import annotations

from numba import njit


@njit(cache=True)
def gravity_forces(rfe_mass, rfe_kind, gravity, scale, F):
    """Add -m g e_z at each RFE centre (all kinds; clamped RFEs only feed reactions)."""
    for i in range(rfe_mass.shape[0]):
        F[i, 2] -= scale * rfe_mass[i] * gravity


def gravity_energy(rfe_mass, r, gravity):
    """Potential energy of gravity, sum m g z (J)."""
    return float(gravity * (rfe_mass * r[:, 2]).sum())
