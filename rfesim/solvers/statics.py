"""Static equilibrium: Newton with line search, Levenberg regularisation and load ramping.

The residual is the generalised force with all velocities zero; its block-tridiagonal
Jacobian is factored in O(n). Every Newton update is followed by a re-base of every RFE's
reference rotation (statics has no rate history), so large rotations such as a cantilever
rolled into a full circle never meet the Euler-angle singularity.

Load ramping scales the applied loads (gravity, buoyancy, point loads) from a fraction to
1; a failed increment is halved. Lines with both ends placed start from the elastic
catenary (``rfesim.catenary``) and take the full load at once.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ..errors import SolverError
from ..model.assemble import rebase
from ..model.arrays import Reference
from ..model.compile import State
from .banded import bt_factor, bt_solve
from .system import System

log = logging.getLogger("rfesim")


@dataclass
class StaticsInfo:
    iterations: int
    load_steps: int
    residual: float
    converged: bool
    message: str


def _norm(r: np.ndarray, mask: np.ndarray, length_scale: np.ndarray, force_ref: float) -> float:
    s = np.abs(r).copy()
    s[:, 3:] /= length_scale[:, None]
    s[~mask] = 0.0
    return float(s.max()) / force_ref


INCREMENT_TOLERANCE = 1e-12  # Newton increment relative to the element length (rad for angles)
MU_MIN = 1e-10         # smallest Levenberg damping (relative to the diagonal)


ROTATION_FLOOR = 1e-9  # constant damping of rotations, relative to the largest rotational diagonal


def _regularise(J: np.ndarray, mu: float, mask: np.ndarray) -> np.ndarray:
    """J + mu * diag(max(|J_ii|, 1e-6 * max |J_ii| of the same coordinate kind)): a
    Levenberg damping that only matters for coordinates with (nearly) no stiffness.

    Rotations also get a constant 1e-9 of the largest rotational stiffness: coordinates
    softer than that (the torsion of a cable with GJ ~ 0 sits at 1e-16 of the stiffest
    shear springs) are below the resolution of the Jacobian, their Newton steps would be
    noise, and their equilibrium is physically arbitrary; they stay where they are."""
    Jr = J.copy()
    diag = np.abs(np.einsum("nkk->nk", J[:, 1]))
    floor_t = 1e-6 * (diag[:, :3][mask[:, :3]].max() if mask[:, :3].any() else 1.0)
    floor_r = 1e-6 * (diag[:, 3:][mask[:, 3:]].max() if mask[:, 3:].any() else 1.0)
    floor = np.concatenate([np.full(3, floor_t), np.full(3, floor_r)])
    add = mu * np.maximum(diag, floor[None, :])
    add[:, 3:] += ROTATION_FLOOR * 1e6 * floor_r
    add[~mask] = 0.0
    idx = np.arange(6)
    Jr[:, 1, idx, idx] += add
    return Jr


def solve_statics(system: System, state: State | None = None, *, tolerance: float = 1e-8, max_iterations: int = 400,
                  load_steps: int = 1, progress=None) -> tuple[State, StaticsInfo]:
    """Static equilibrium of the scene at the state's time (vessels at their pose then)."""
    model = system.model
    st = (state or model.initial).copy()
    st.qd[:] = 0.0
    st.qdd[:] = 0.0
    st.aux[:] = 0.0
    mask = system.mask
    ls = system.length_scale
    n = system.n
    system.set_time(st.t)
    force_ref = system.force_scale(st)
    # below the round-off of the stiffest SDE the residual only stagnates: accept it there
    floor = 10.0 * system.roundoff_force(st) / force_ref
    r = np.zeros((n, 6))
    dq = np.zeros((n, 6))
    trial = np.zeros((n, 6))
    fac = np.zeros_like(system.Fac)
    dummy = np.zeros((n, 6))

    lam = 1.0 / max(1, load_steps)
    lam_done = 0.0
    dlam = lam
    q_good = st.q.copy()
    R0_good = Reference(st.ref.R.copy(), st.ref.X.copy())
    total_its = 0
    nsteps = 0
    rn = np.inf
    while True:
        lam = min(1.0, lam_done + dlam)
        ok = False
        mu = MU_MIN
        system.static_residual(st.q, st.ref, lam, r)
        rn = _norm(r, mask, ls, force_ref)
        rn_prev = np.inf
        for it in range(max_iterations):
            if rn <= tolerance or (rn <= floor and rn > 0.9 * rn_prev):
                ok = True
                break
            rn_prev = rn
            total_its += 1
            if total_its > max_iterations:
                break
            J = system.static_jacobian_accurate(st.q, st.ref, lam)
            # Solve; raise the Levenberg damping while the direction is not a descent
            # direction (a part in compression has negative geometric stiffness).
            bad = 0
            for _attempt in range(12):
                bad = bt_factor(_regularise(J, mu, mask), fac)
                if bad < 0:
                    bt_solve(fac, r, dq)
                    dq *= -1.0
                    if float(np.sum(dq * r)) < 0.0:
                        break
                mu = max(mu * 100.0, 1e-8)
                if mu > 1e3:
                    bad = 0
                    break
            if bad >= 0:
                break
            # converged when the Newton increment is at round-off level (the residual can
            # stall above the tolerance at the resolution of the stiffest springs)
            inc = max(float((np.abs(dq[:, :3]) / ls[:, None]).max()), float(np.abs(dq[:, 3:]).max()))
            if inc < INCREMENT_TOLERANCE and rn < 1e3 * max(tolerance, floor):
                ok = True
                break
            # limit rotation updates to 0.5 rad and translations to a few element lengths
            rot = np.abs(dq[:, 3:]).max()
            tr = (np.abs(dq[:, :3]) / ls[:, None]).max()
            limit = min(1.0, 0.5 / max(rot, 1e-300), 5.0 / max(tr, 1e-300))
            # Crisfield's line search on the directional derivative of the energy:
            # s(alpha) = dq . r(q + alpha dq) should vanish; r may grow in stiff directions
            # (axial) after a full step without the step being bad.
            s0 = float(np.sum(dq * r))
            alpha = limit
            accepted = False
            R0_trial = Reference(st.ref.R.copy(), st.ref.X.copy())
            a_lo, s_lo = 0.0, s0
            rn_new = np.inf
            for _ in range(8):
                trial[:] = st.q + alpha * dq
                R0_trial.R[:] = st.ref.R
                R0_trial.X[:] = st.ref.X
                rebase(trial, dummy, R0_trial, system.km.rfe_kind, 0.0, dummy, dummy, False)
                system.static_residual(trial, R0_trial, lam, r)
                rn_new = _norm(r, mask, ls, force_ref)
                if not np.isfinite(rn_new):
                    alpha *= 0.25
                    continue
                s1 = float(np.sum(dq * r))
                if s0 == 0.0 or abs(s1) <= 0.8 * abs(s0) or rn_new < 0.5 * rn:
                    accepted = True
                    break
                # secant on s(alpha) between the last bracket point and alpha
                denom = s_lo - s1
                a_new = alpha if denom == 0.0 else a_lo + (alpha - a_lo) * s_lo / denom
                if s1 * s0 < 0:            # overshoot: root between a_lo and alpha
                    a_new = min(max(a_new, a_lo + 0.1 * (alpha - a_lo)), a_lo + 0.9 * (alpha - a_lo))
                else:                      # still descending: the root is beyond alpha
                    a_lo, s_lo = alpha, s1
                    a_new = min(max(a_new, 1.1 * alpha), 4.0 * alpha, limit * 4.0)
                alpha = a_new
            if not accepted:
                if not np.isfinite(rn_new):
                    mu = max(mu * 10.0, 1e-6)
                    system.static_residual(st.q, st.ref, lam, r)
                    continue
            st.q[:] = trial
            st.ref.R[:] = R0_trial.R
            st.ref.X[:] = R0_trial.X
            rn = rn_new
            mu = max(mu * 0.1, MU_MIN) if accepted else min(mu * 10.0, 1.0)
            if progress is not None:
                progress(min(0.999, lam_done + dlam * 0.5), st.t)
        nsteps += 1
        if ok:
            lam_done = lam
            q_good[:] = st.q
            R0_good.R[:] = st.ref.R
            R0_good.X[:] = st.ref.X
            if lam_done >= 1.0:
                break
            dlam = min(2.0 * dlam, 1.0 - lam_done)
            continue
        # failed increment: halve it
        st.q[:] = q_good
        st.ref.R[:] = R0_good.R
        st.ref.X[:] = R0_good.X
        dlam *= 0.5
        if dlam < 1e-4 or total_its > max_iterations:
            system.static_residual(st.q, st.ref, lam_done if lam_done > 0 else lam, r)
            rn = _norm(r, mask, ls, force_ref)
            elem = int(np.argmax(np.abs(r).max(axis=1)))
            raise SolverError("static equilibrium not found: Newton did not converge "
                              f"(load factor {lam_done:.4g} reached, residual {rn:.3g} x force scale {force_ref:.3g} N)",
                              time=st.t, element=model.describe_rfe(elem), quantity="static residual")
    info = StaticsInfo(iterations=total_its, load_steps=nsteps, residual=rn, converged=True,
                       message=f"converged in {total_its} Newton iterations, {nsteps} load steps")
    return st, info
