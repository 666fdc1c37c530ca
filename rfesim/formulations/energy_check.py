"""Energy growth of the closed units of a formulations scene: chains and classical / modified
/ planar lines (rfesim.formulations.scene), checked after their integration at the output
times, with the rule of the absolute-coordinate dynamics (rfesim.solvers.dynamics.EnergyCheck,
docs/theory.md "Energy growth stops a closed run").

A unit is *closed* when nothing feeds or drains energy except its damping: its base stands
still (fixed, or on a vessel whose motion is ``fixed``), no joint is driven (a prescribed
motion or a force drive), and its point loads are constant forces (their work F . x is part of
the potential; a moment on a link is not, in three dimensions). Its mechanical energy is the
kinetic energy (eq. 8.42), the gravity potential (eq. 8.44), the elastic energy of its SDEs and
joint springs (eqs. 8.21, 8.47, 8.49) and minus the work of its dead loads; for a planar line
eq. 8.60 and its SDE springs (rfesim.formulations.planar.potential_energy). RK4 at a stable
step, DOP853 within its tolerance and generalized-alpha with rho_inf <= 1 create no energy, so
a growth past ENERGY_STOP of the scale (the largest kinetic + elastic energy seen plus the
range of the potential seen) is a numerical blow-up: the run stops there with the outputs up
to it; past ENERGY_WARN it is a dynamics warning.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import planar as pl
from . import tree
from .chain import ChainData, evaluate, fill_prescribed


@dataclass
class Growth:
    """The energy growth of one unit over its outputs."""
    label: str
    ratio: np.ndarray        # (nt,) growth past the floor / scale at each output
    growth: np.ndarray       # (nt,) E(t) - E(0), J
    scale: np.ndarray        # (nt,) J

    def first_over(self, limit: float) -> int | None:
        """The first output whose ratio exceeds ``limit`` (None: none)."""
        idx = np.flatnonzero(self.ratio > limit)
        return int(idx[0]) if idx.size else None

    def describe(self, k: int, t: float) -> str:
        return (f"the mechanical energy of {self.label}, a closed unit (fixed base, no drives, constant point "
                f"forces), grew by {self.growth[k]:.4g} J by t = {t:.6g} s, {100 * self.ratio[k]:.3g} % of its "
                f"scale {self.scale[k]:.4g} J (the largest kinetic + elastic energy plus the range of the "
                f"potential seen), where an exact solve keeps it or loses it to damping: numerical error")


def open_terms(unit, moving_base: bool) -> list[str]:
    """What makes a chain unit (a ChainUnit) open: an empty list for a closed one."""
    model = unit.model
    out = []
    if moving_base:
        out.append("a moving vessel base")
    if model.prescribed or model.forces:
        out.append("joint drives")
    if any(callable(F) for F in model.load_force) or any(
            callable(M) or np.any(np.asarray(M, float) != 0.0) for M in model.load_moment):
        out.append("point loads that vary or carry a moment")
    return out


def chain_energies(model, times, Q, QD) -> tuple[np.ndarray, np.ndarray, float]:
    """(kinetic + elastic (nt,), potential: gravity minus the dead loads' work (nt,), the
    round-off floor from the first output) of a chain model at its outputs."""
    data = ChainData(model)
    nt = len(times)
    kin_el, pot = np.zeros(nt), np.zeros(nt)
    floor = 0.0
    qdd = np.zeros(model.nq)
    g = np.asarray(model.gravity, float)
    for k in range(nt):
        q, qd = np.array(Q[k], float), np.array(QD[k], float)
        qdd[:] = 0.0
        t = float(times[k])
        fill_prescribed(model, t, q, qd, qdd)
        evaluate(model, data, t, q, qd, qdd, mass=False)
        kin = tree.kinetic_energy(model.inertia, data.Td)
        work = 0.0
        for i in range(len(model.load_body)):
            b = int(model.load_body[i])
            p = data.T[b, :3, :3] @ model.load_point[i] + data.T[b, :3, 3]
            work += float(data.load_force[i] @ p)
        kin_el[k] = kin + data.elastic_energy
        pot[k] = tree.gravity_potential(model.inertia, data.T, model.gravity) - work
        if k == 0:
            # sum over the bodies of |m g . r_C| (the absolute potential) and |F . x|
            mr = np.einsum("bij,bj->bi", data.T[:, :3, :], model.inertia[:, :, 3])
            floor = 1e-9 * (float(np.abs(mr @ g).sum()) + abs(work) + 1e-3 * kin_el[0]) + 1e-12
    return kin_el, pot, floor


def planar_energies(model, Q, QD) -> tuple[np.ndarray, np.ndarray, float]:
    """As ``chain_energies`` for a planar line (eqs. 8.54, 8.60; its SDE springs)."""
    nt = len(Q)
    kin_el, pot = np.zeros(nt), np.zeros(nt)
    for k in range(nt):
        q, qd = np.asarray(Q[k], float), np.asarray(QD[k], float)
        rel = np.diff(q[2:]) - model.sde_rest_angle
        elastic = 0.5 * float(model.sde_stiffness @ rel ** 2)
        kin_el[k] = pl.kinetic_energy(model, q, qd) + elastic
        pot[k] = pl.potential_energy(model, q) - elastic
    size = float(np.abs(model.mass).sum()) * abs(model.gravity) * (model.length or 1.0)
    floor = 1e-9 * (size + abs(pot[0]) + 1e-3 * kin_el[0]) + 1e-12 if nt else 1e-12
    return kin_el, pot, floor


def growth(label: str, kin_el: np.ndarray, pot: np.ndarray, floor: float) -> Growth:
    """The growth ratio at each output, as EnergyCheck computes it output by output: the
    growth of kinetic + elastic + potential since the first output, less the round-off floor,
    over the largest kinetic + elastic energy seen plus the range of the potential seen."""
    E = kin_el + pot
    scale = np.maximum.accumulate(kin_el) + np.maximum.accumulate(pot) - np.minimum.accumulate(pot)
    dE = E - E[0]
    excess = dE - floor
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        ratio = np.where(excess > 0.0, excess / np.maximum(scale, floor), 0.0)
    ratio[~np.isfinite(ratio) | ~np.isfinite(dE)] = math.inf
    return Growth(label, ratio, dE, scale)
