"""Mechanical energy of a state: kinetic (eq. 8.15 for rigid elements), elastic SDE energy
(a rope's axial term only when stretched, or its contact energy: rfesim.loads.tension_only)
and the potential of gravity (eq. 8.19). Used by the stability tests and the benchmark
report; buoyancy and added mass are not included (scenes in water are not conservative)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..loads.sde import sde_elastic_energy
from ..loads.tension_only import arm_sums, rope_axial_energy


@dataclass
class Energy:
    kinetic: float       # J
    elastic: float       # J
    gravity: float       # J
    work: float = 0.0    # J, potential of constant point loads (-F . x)

    @property
    def total(self) -> float:
        return self.kinetic + self.elastic + self.gravity + self.work


def mechanical_energy(system, state) -> Energy:
    """Energy of the scene at a state (the system's workspace is evaluated at it)."""
    system.evaluate(state)
    ws = system.ws
    km = system.km
    free = km.rfe_kind != 2
    m = km.rfe_mass
    kin_t = 0.5 * float((m[free] * (ws.v[free] ** 2).sum(axis=1)).sum())
    kin_r = 0.5 * float((km.rfe_inertia[free] * ws.wb[free] ** 2).sum())
    elastic = float(sde_elastic_energy(km.sde_stiffness, ws.eps))
    if km.has_tension_only:
        # a rope's axial term: 1/2 C eps^2 stretched only, and its contact energy past the closing
        rope = np.flatnonzero(km.sde_tension_only == 1)
        C, gap = km.sde_stiffness[rope, 0], ws.eps[rope, 0]
        reach = arm_sums(km.sde_arm_left, km.sde_arm_right, rope)
        elastic += float((rope_axial_energy(C, gap, reach) - 0.5 * C * gap * gap).sum())
    grav = float(km.gravity * (m * ws.r[:, 2]).sum())
    work = 0.0
    for j in range(km.load_rfe.shape[0]):
        if km.load_local[j]:
            continue
        i = km.load_rfe[j]
        point = ws.r[i] + ws.R[i] @ km.load_arm[j]
        work -= float(km.load_force[j] @ point)
    return Energy(kinetic=kin_t + kin_r, elastic=elastic, gravity=grav, work=work)
