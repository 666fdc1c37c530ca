"""Scenes that mix absolute-coordinate lines (section 8.4) with kinematic chains (sections
8.1, 8.2, 5.4): one implicit integrator over both coordinate sets.

A line end attaches to a point of a chain link (``"attach": "<chain>.<link>"``, ``at`` on
the link, ``position`` offset in the link's axes). The line sees that point as a moving
attachment: its pose, velocity and acceleration come from the chain state (the forward pass
of `tree`, as `chain.point_motion`), written into an extra slot of the line model's
attachment state (after the vessels, so the compiled vessel kinematics never touches it).
The chain sees the force and moment of the line's end connection (``model.outputs.reactions``
with the sign reversed) as a point load at that point: the generalised force J^T [F; M]
of eq. 8.94, formed by the chain kernel's load terms.

Unknowns of a step: the line coordinates q_L (n, 6) and the chain's free coordinates q_C
(nc, all chains back to back). Generalised-alpha (Chung & Hulbert, in the form of Arnold &
Bruls like ``solvers.kernels.ga_advance``) on both with the same parameters; Newton on the
coupled residual

    r_L = cq (M_L A_L - f_L(q_L, q_C))                    block-tridiagonal Jacobian J_LL
    r_C = cq (A_CC A_C - f_C(q_C) - J^T [F; M](q_L, q_C))  small dense J_CC

with the coupling blocks J_LC (6n x nc) and J_CL (nc x 6n, non-zero only in the columns of
the attached end RFEs and their neighbours) by finite differences, solved by the Schur
complement on the chain coordinates:

    X = J_LL^-1 J_LC,  S = J_CC - J_CL X,  dq_C = S^-1 (r_C - J_CL J_LL^-1 r_L),
    dq_L = J_LL^-1 r_L - X dq_C.

The step loop is Python calling the compiled line kernels (``residual_q``, ``jacobian_fd``,
``bt_factor``/``bt_solve``, ``reactions``) and the chain kernel (``chain.evaluate``); the
pure absolute path (``ga_advance``) is not involved. See docs/theory.md, "Mixed scenes".
"""
from __future__ import annotations

import logging
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from ..errors import CancelledError, SolverError
from ..model.assemble import commit_history, rebase, solve_accelerations
from ..model.compile import State, compile_scenario
from ..model.outputs import reactions
from ..scenario.chains import chain_point
from ..solvers.banded import bt_factor, bt_solve
from ..solvers.buckling import buckling_warnings, shear_warnings
from ..solvers.dynamics import newton_tolerance, output_schedule
from ..solvers.kernels import REBASE_THRESHOLD, genalpha_parameters, jacobian_fd, jacobian_fd_general, residual_q
from ..solvers.residual import residual_norm
from ..solvers.system import System
from .chain import ChainData, evaluate, fill_prescribed
from .scene import _chain_lines, _chain_unit, _Kinematics, JointResults, joint_kinds

log = logging.getLogger("rfesim")


def is_mixed(sc) -> bool:
    """True for a scene with chains and absolute-coordinate lines."""
    return bool(getattr(sc, "chains", None)) and any(ln.formulation == "absolute" for ln in sc.lines.values())


# ============================================================================ compile
class CouplingLoad:
    """The load of a line end on a chain point (N, N*m, global): a chain load whose value
    the solver sets before every chain evaluation; for the outputs, a table over time."""

    def __init__(self):
        self.value = np.zeros(3)
        self.times = None
        self.table = None

    def __call__(self, t):
        if self.table is None:
            return self.value
        k = int(np.argmin(np.abs(self.times - t)))
        return self.table[k]


@dataclass
class ChainPoint:
    name: str                     # "<chain>.<link>" (with "@s" when not at the tip)
    unit: int                     # index of the chain unit
    link: str
    s: float                      # m, arc length on the link
    body: int                     # chain body that carries the point
    origin: np.ndarray            # (4,) the link-axis point at s in the body frame (homogeneous)
    axes: np.ndarray              # (3, 3) link axes in the body frame (attachment frame = T_R @ axes)
    slot: int                     # attachment slot of the line model
    rfe: int                      # the attached line RFE
    force: CouplingLoad = field(default_factory=CouplingLoad)
    moment: CouplingLoad = field(default_factory=CouplingLoad)


def _vee(W):
    return 0.5 * np.array([W[2, 1] - W[1, 2], W[0, 2] - W[2, 0], W[1, 0] - W[0, 1]])


class MixedScene:
    """The compiled line model (a `System` with extra attachment slots) and the chain units."""

    def __init__(self, sc):
        self.sc = sc
        self.statics_warnings: list[str] = []      # the lines' buckling check after statics (initial_state)
        g = sc.environment.gravity
        gvec = (0.0, 0.0, -g)
        names = list(sc.chains)
        self.units = [_chain_unit(sc, cname, sc.chains[cname], gvec) for cname in names]
        self.kins = [_Kinematics(u.model) for u in self.units]
        for u, kin in zip(self.units, self.kins):        # chain pose at its initial coordinates
            q, qd, qdd = u.q0.copy(), np.zeros(u.model.nq), np.zeros(u.model.nq)
            fill_prescribed(u.model, 0.0, q, qd, qdd)
            kin.run(0.0, q, qd, qdd)
        # --- the line model: chain ends compiled as fixed ends at the initial pose, then re-pointed
        points, new_lines, ends = [], dict(sc.lines), []
        for lname, ln in sc.lines.items():
            for end_name in ("end_a", "end_b"):
                end = getattr(ln, end_name)
                cp = chain_point(sc, end.attach)
                if cp is None:
                    continue
                cname, link = cp
                k = names.index(cname)
                model = self.units[k].model
                length = model.links[link].link.length
                s = length if end.at is None else float(end.at)
                body, origin = model.locate(link, s)
                axes = model.undeformed[body][:3, :3].T
                T = self.kins[k].T[body]
                R0 = T[:3, :3] @ axes
                p0 = T[:3] @ np.append(origin, 1.0)
                offset = np.zeros(3) if end.position is None else np.asarray(end.position, float)
                upd = {"attach": "fixed", "position": list(p0 + R0 @ offset), "at": None}
                if end.direction is not None:
                    upd["direction"] = list(R0 @ np.asarray(end.direction, float))
                new_lines[lname] = new_lines[lname].model_copy(update={end_name: end.model_copy(update=upd)})
                ends.append((lname, end_name, k, link, s, body, origin, axes, R0, offset))
        sc2 = sc.model_copy(update={"lines": new_lines, "chains": {}})
        model = compile_scenario(sc2)
        model.scenario = sc
        km = model.km
        for lname, end_name, k, link, s, body, origin, axes, R0, offset in ends:
            li = model.line(lname)
            i = li.rfe_start if end_name == "end_a" else li.rfe_stop - 1
            slot = len(model.attachment_names)
            model.attachment_names.append(f"{self.units[k].label[len('chains.'):]}.{link}@{s:g}")
            km.rfe_attach[i] = slot
            km.rfe_attach_offset[i] = offset
            km.rfe_clamp_R[i] = R0.T @ km.rfe_clamp_R[i]     # compiled against the identity (fixed)
            pt = ChainPoint(model.attachment_names[-1], k, link, s, body, np.append(origin, 1.0), axes, slot, i)
            cm = self.units[k].model                          # the coupling load at the attached point
            b, p = cm.locate(link, s, offset)
            cm.load_body = np.append(cm.load_body, b).astype(np.int64)
            cm.load_point = np.vstack([cm.load_point, p[None]])
            cm.load_force.append(pt.force)
            cm.load_moment.append(pt.moment)
            points.append(pt)
        self.points = points
        self.model = model
        self.system = System(model)
        self.cdata = [ChainData(u.model) for u in self.units]
        self.free = [u.model.free for u in self.units]
        self.offsets = np.concatenate([[0], np.cumsum([len(f) for f in self.free])]).astype(int)
        self.nc = int(self.offsets[-1])
        self.react = np.zeros((model.n, 6))
        # line coordinates that the coupling loads depend on: attached RFEs and their SDE neighbours
        cols = set()
        for pt in points:
            for i in (pt.rfe - 1, pt.rfe, pt.rfe + 1):
                if 0 <= i < model.n and self._same_line(i, pt.rfe):
                    cols |= {(i, a) for a in range(6) if model.dof_mask[i, a]}
        self.coupled_cols = sorted(cols)
        # reference generalised force of the chain coordinates (N*m): weights times the reach
        reach = max(1.0, sum(u.model.links[o.link].link.length for u in self.units for o in u.outputs))
        mass = sum(float(u.model.inertia[:, 3, 3].sum()) for u in self.units) + float(km.rfe_mass.sum())
        self.total_weight = mass * max(g, 1e-3)
        self.chain_ref = max(self.total_weight * reach, 1e-9)

    def _same_line(self, i, j):
        for li in self.model.lines:
            if li.rfe_start <= j < li.rfe_stop:
                return li.rfe_start <= i < li.rfe_stop
        return False

    # ------------------------------------------------------------------ chain state
    def chain_full(self, t, x, v, a):
        """Per unit (q, qd, qdd) over all coordinates from the unknowns (prescribed ones from
        their drives at t, locked ones zero)."""
        out = []
        for u, fr, o0, o1 in zip(self.units, self.free, self.offsets[:-1], self.offsets[1:]):
            nq = u.model.nq
            q, qd, qdd = np.zeros(nq), np.zeros(nq), np.zeros(nq)
            q[fr], qd[fr], qdd[fr] = x[o0:o1], v[o0:o1], a[o0:o1]
            fill_prescribed(u.model, t, q, qd, qdd)
            out.append((q, qd, qdd))
        return out

    def set_points(self, t, full):
        """Chain forward pass and the attachment slots of the chain points."""
        att = self.system.att
        for kin, (q, qd, qdd) in zip(self.kins, full):
            kin.run(t, q, qd, qdd)
        for pt in self.points:
            kin = self.kins[pt.unit]
            T, Td, Tdd = kin.T[pt.body], kin.Td[pt.body], kin.Tdd[pt.body]
            R = T[:3, :3] @ pt.axes
            W = Td[:3, :3] @ T[:3, :3].T
            Aa = Tdd[:3, :3] @ T[:3, :3].T - W @ W
            att.p[pt.slot] = T[:3] @ pt.origin
            att.R[pt.slot] = R
            att.v[pt.slot] = Td[:3] @ pt.origin
            att.a[pt.slot] = Tdd[:3] @ pt.origin
            att.w[pt.slot] = _vee(W)
            att.alpha[pt.slot] = _vee(Aa)

    def set_loads(self, qdd_line, scale=1.0):
        """Coupling loads from the evaluated line workspace: minus the end reactions."""
        reactions(self.system.km, self.system.att, self.system.ws, qdd_line, self.react)
        for pt in self.points:
            pt.force.value = -self.react[pt.rfe, :3] / scale
            pt.moment.value = -self.react[pt.rfe, 3:] / scale

    def chain_rhs(self, t, full, scale=1.0, mass=True):
        """Per unit: (A_ff, f_f) with the current coupling loads (A_ff None without mass)."""
        out = []
        for u, data, fr, (q, qd, qdd) in zip(self.units, self.cdata, self.free, full):
            a0 = qdd.copy()
            a0[fr] = 0.0
            f = evaluate(u.model, data, t, q, qd, a0, mass=mass, load_scale=scale)
            out.append((data.A[np.ix_(fr, fr)].copy() if mass else None, f[fr]))
        return out


# ============================================================================ energy
def mixed_energy(ms: MixedScene, state: State, x, v, t=None) -> dict:
    """Kinetic, gravity and elastic energy (J) of the line (all RFEs, including those that
    move with a chain point) and of the chains."""
    from ..loads.sde import sde_elastic_energy
    from .chain import chain_energy
    t = state.t if t is None else t
    full = ms.chain_full(t, x, v, np.zeros(ms.nc))
    ms.set_points(t, full)
    sysm = ms.system
    sysm.evaluate(state)
    ms.set_points(t, full)
    from ..model.assemble import evaluate as line_eval
    line_eval(sysm.km, sysm.att, state.q, state.qd, state.ref, sysm.ws, 1.0)
    ws, km = sysm.ws, sysm.km
    kin = 0.5 * float((km.rfe_mass * (ws.v ** 2).sum(axis=1)).sum()) + 0.5 * float((km.rfe_inertia * ws.wb ** 2).sum())
    out = {"kinetic": kin, "gravity": float(km.gravity * (km.rfe_mass * ws.r[:, 2]).sum()),
           "elastic": float(sde_elastic_energy(km.sde_stiffness, ws.eps))}
    for u, (q, qd, _) in zip(ms.units, full):
        e = chain_energy(u.model, t, q, qd)
        for k in out:
            out[k] += e[k]
    out["total"] = out["kinetic"] + out["gravity"] + out["elastic"]
    return out


# ============================================================================ the coupled Newton
class Coupled:
    """Residual, Jacobian and Newton solve of the coupled line + chain equations, for
    statics (mode 0) or one generalised-alpha step (mode 1)."""

    def __init__(self, ms: MixedScene):
        self.ms = ms
        sysm = ms.system
        n = sysm.n
        self.n = n
        z = np.zeros
        self.rL = z((n, 6))
        self.work = z((n, 6))
        self.zero_acc = z((n, 6))
        self.JLC = z((ms.nc, n, 6))
        self.JCL = z((ms.nc, n, 6))
        self.JCC = z((ms.nc, ms.nc))
        self.X = z((ms.nc, n, 6))
        self.S = None
        self.y = z((n, 6))
        self.Q0c = self.V0c = None
        self.t = 0.0
        self.mode = 0
        self.scale = 1.0
        self.cq, self.cv = 1.0, 0.0
        self.factored = False

    def setup(self, mode, t, scale=1.0, Q0=None, V0=None, Q0c=None, V0c=None, cq=1.0, cv=0.0):
        sysm = self.ms.system
        self.mode, self.t, self.scale, self.cq, self.cv = mode, t, scale, cq, cv
        if mode == 1:
            sysm.Q0[:] = Q0
            sysm.V0[:] = V0
            self.Q0c, self.V0c = Q0c.copy(), V0c.copy()
        else:
            sysm.Q0[:] = 0.0
            sysm.V0[:] = 0.0

    def residual(self, q, ref, xc, rL):
        """r_L (n, 6) into rL and r_C (nc,) returned, at line q and chain unknowns xc."""
        ms, sysm = self.ms, self.ms.system
        if self.mode == 1:
            Ac = (xc - self.Q0c) / self.cq
            vc = self.V0c + self.cv * Ac
        else:
            Ac = np.zeros(ms.nc)
            vc = np.zeros(ms.nc)
        full = ms.chain_full(self.t, xc, vc, Ac)
        ms.set_points(self.t, full)
        residual_q(sysm.km, sysm.att, q, ref, sysm.ws, self.scale, self.mode, sysm.Q0, sysm.V0, self.cq, self.cv,
                   sysm.mask, sysm.qd_buf, sysm.A_buf, rL)
        ms.set_loads(sysm.A_buf if self.mode == 1 else self.zero_acc, self.scale)
        rC = np.empty(ms.nc)
        for (A, f), o0, o1 in zip(ms.chain_rhs(self.t, full, self.scale, mass=self.mode == 1), ms.offsets[:-1],
                                  ms.offsets[1:]):
            rC[o0:o1] = self.cq * (A @ Ac[o0:o1] - f) if self.mode == 1 else -f
        return rC

    def jacobian(self, q, ref, xc, rL0, rC0, central=False):
        """J_LL (coloured differences, into system.J), J_LC, J_CL, J_CC; factor J_LL and form
        the Schur complement. Returns the index of a singular block or -1."""
        ms, sysm = self.ms, self.ms.system
        if central:
            jacobian_fd_general(sysm.km, sysm.att, q, ref, sysm.ws, self.scale, self.mode, sysm.Q0, sysm.V0, self.cq,
                                self.cv, sysm.mask, sysm.qd_buf, sysm.A_buf, self.work, sysm.qp, sysm.rp, sysm.hs,
                                sysm.length_scale, sysm.J, True, 1e-6)
        else:
            self.work[:] = rL0
            jacobian_fd(sysm.km, sysm.att, q, ref, sysm.ws, self.scale, self.mode, sysm.Q0, sysm.V0, self.cq, self.cv,
                        sysm.mask, sysm.qd_buf, sysm.A_buf, self.work, sysm.qp, sysm.rp, sysm.hs, sysm.length_scale,
                        sysm.J)
        self.Jraw = sysm.J.copy()
        rp = np.zeros_like(rL0)
        rm = np.zeros_like(rL0)
        for j in range(ms.nc):                      # chain columns: J_LC and J_CC
            h = (1e-6 if central else 1e-7) * max(1.0, abs(xc[j]))
            xp = xc.copy()
            xp[j] += h
            cp = self.residual(q, ref, xp, rp)
            if central:
                xm = xc.copy()
                xm[j] -= h
                cm = self.residual(q, ref, xm, rm)
                self.JLC[j] = (rp - rm) / (2 * h)
                self.JCC[:, j] = (cp - cm) / (2 * h)
            else:
                self.JLC[j] = (rp - rL0) / h
                self.JCC[:, j] = (cp - rC0) / h
        self.JCL[:] = 0.0
        qp = q.copy()
        for i, a in ms.coupled_cols:                # line columns of the coupling loads: J_CL
            typical = sysm.length_scale[i] if a < 3 else 1.0
            h = (1e-5 if central else 1e-7) * max(abs(q[i, a]), typical)
            qp[i, a] = q[i, a] + h
            cp = self.residual(qp, ref, xc, rp)
            if central:
                qp[i, a] = q[i, a] - h
                cm = self.residual(qp, ref, xc, rm)
                self.JCL[:, i, a] = (cp - cm) / (2 * h)
            else:
                self.JCL[:, i, a] = (cp - rC0) / h
            qp[i, a] = q[i, a]
        return self.factor(1e-10 if self.mode == 0 else 0.0)

    def factor(self, mu):
        """Factor J_LL (statics: with the Levenberg damping mu of solvers.statics) and form
        the Schur complement. Returns the index of a singular block or -1."""
        ms, sysm = self.ms, self.ms.system
        if mu > 0.0:
            from ..solvers.statics import _regularise
            sysm.J[:] = _regularise(self.Jraw, mu, sysm.mask)
        else:
            sysm.J[:] = self.Jraw
        bad = bt_factor(sysm.J, sysm.Fac)
        if bad >= 0:
            self.factored = False
            return bad
        for j in range(ms.nc):
            bt_solve(sysm.Fac, self.JLC[j], self.X[j])
        n6 = 6 * self.n
        self.S = self.JCC - self.JCL.reshape(ms.nc, n6) @ self.X.reshape(ms.nc, n6).T
        self.factored = True
        return -1

    def solve(self, rL, rC):
        """Newton increments (dL (n, 6), dC (nc,)) of J [dL; dC] = [rL; rC]."""
        ms, sysm = self.ms, self.ms.system
        bt_solve(sysm.Fac, rL, self.y)
        if ms.nc == 0:
            return self.y.copy(), np.zeros(0)
        n6 = 6 * self.n
        dC = np.linalg.solve(self.S, rC - self.JCL.reshape(ms.nc, n6) @ self.y.reshape(n6))
        dL = self.y - np.tensordot(dC, self.X, axes=(0, 0))
        return dL, dC

    def chain_norm(self, rC):
        return float(np.max(np.abs(rC), initial=0.0)) / self.cq / self.ms.chain_ref


# ============================================================================ statics
@dataclass
class MixedStatics:
    state: State                  # line state
    x: np.ndarray                 # chain unknowns
    iterations: int
    residual: float
    warnings: list[str] = field(default_factory=list)   # the lines' buckling check (rfesim.solvers.buckling)


def mixed_statics(ms: MixedScene, *, tolerance=1e-8, max_iterations=200, load_steps=1) -> MixedStatics:
    """Static equilibrium of lines and chains by one Newton iteration over both (Schur
    complement, backtracking on the residual), after the lines' own statics with the
    chains held at their initial coordinates as the starting point."""
    from ..solvers.statics import solve_statics
    sysm = ms.system
    x = np.concatenate([u.q0[fr] for u, fr in zip(ms.units, ms.free)]) if ms.nc else np.zeros(0)
    full = ms.chain_full(0.0, x, np.zeros(ms.nc), np.zeros(ms.nc))
    ms.set_points(0.0, full)
    st, _ = solve_statics(sysm, tolerance=max(tolerance, 1e-8), max_iterations=max_iterations,
                          load_steps=load_steps)
    st = st.copy()
    cp = Coupled(ms)
    force_ref = sysm.force_scale(st)
    tol = max(tolerance, 100.0 * sysm.roundoff_force(st) / force_ref)
    sysm.ws.waves_off[0] = 1
    sysm.set_friction_mode(2)
    total = 0
    rn = np.inf
    try:
        # load increments: start with 1 / load_steps, halve a failed one (from its start), grow after success
        done, dlam = 0.0, 1.0 / max(1, load_steps)
        while done < 1.0:
            scale = min(1.0, done + dlam)
            saved = (st.q.copy(), st.ref.R.copy(), st.ref.X.copy(), x.copy())
            x_new, ok, rn, its = _newton(ms, cp, st, x, scale, force_ref, tol, 40 if scale < 1.0 else max_iterations)
            total += its
            if ok:
                x = x_new
                done = scale
                dlam = min(2.0 * dlam, 1.0)
                continue
            st.q[:], st.ref.R[:], st.ref.X[:], x = saved
            dlam *= 0.5
            if dlam < 1e-3:
                raise SolverError(f"statics of the mixed scene did not converge (residual {rn:.3e} of the "
                                  f"typical force at load {scale:.3g}); try more analysis.statics.load_steps")
    finally:
        sysm.ws.waves_off[0] = 0
        sysm.set_friction_mode(0)
    st.qd[:] = 0.0
    st.qdd[:] = 0.0
    return MixedStatics(st, x, total, rn)


def _newton(ms: MixedScene, cp: Coupled, st: State, x, scale, force_ref, tol, max_iterations):
    """Newton on the static residual at one load scale (st updated in place). Returns
    (x, converged, residual, iterations)."""
    from ..solvers.statics import _rechain
    sysm = ms.system
    cp.setup(0, st.t, scale)
    rL = np.zeros((sysm.n, 6))
    rC = cp.residual(st.q, st.ref, x, rL)
    rn = max(_line_norm(sysm, rL, force_ref), cp.chain_norm(rC))
    its = stalls = 0
    for _ in range(max_iterations):
        if rn <= tol:
            return x, True, rn, its
        its += 1
        bad = cp.jacobian(st.q, st.ref, x, rL, rC, central=True)
        mu = 1e-10
        while bad >= 0:             # Levenberg damping for coordinates without stiffness
            mu = max(100.0 * mu, 1e-8)
            if mu > 1e3:
                raise SolverError(f"statics of the mixed scene: singular Jacobian at {sysm.model.describe_rfe(bad)}")
            bad = cp.factor(mu)
        rC = cp.residual(st.q, st.ref, x, rL)
        dL, dC = cp.solve(rL, rC)
        # geometrically consistent update (solvers.statics._rechain): the RFE centres are
        # re-chained from the moved chain point so that every SDE deformation changes by
        # its linearised amount (a linear update leaves O(dq^2) gaps in stiff axial springs)
        eps_old, eps_dir = _deformation_direction(ms, st, x, -dL, -dC, scale)
        alpha = 1.0
        while True:
            q2 = np.zeros_like(st.q)
            ref2 = type(st.ref)(st.ref.R.copy(), st.ref.X.copy())
            x2 = _rechain_chains(ms, st.t, x, x - alpha * dC)
            ms.set_points(st.t, ms.chain_full(st.t, x2, np.zeros(ms.nc), np.zeros(ms.nc)))
            _rechain(sysm, st, -dL, alpha, q2, ref2, scale, eps_old, eps_dir)
            rL2 = np.zeros_like(rL)
            rC2 = cp.residual(q2, ref2, x2, rL2)
            rn2 = max(_line_norm(sysm, rL2, force_ref), cp.chain_norm(rC2))
            if (np.isfinite(rn2) and rn2 < rn * (1 - 1e-4 * alpha)) or alpha < 1e-3:
                break
            alpha *= 0.5
        stalls = 0 if (np.isfinite(rn2) and rn2 < rn) else stalls + 1
        if stalls > 3 or not np.isfinite(rn2):
            break                   # no descent: stalled
        st.q[:], st.ref.R[:], st.ref.X[:], x = q2, ref2.R, ref2.X, x2
        rL, rC, rn = rL2, rC2, rn2
        small = np.max(np.abs(alpha * dL[sysm.mask]), initial=0.0) < 1e-13 * max(1.0, float(
            np.abs(st.q).max())) and np.max(np.abs(alpha * dC), initial=0.0) < 1e-13
        if small:
            break
    # stalled at the resolution of the differences: accept below 1e-4 of the typical force
    return x, rn <= max(tol, 1e-4), rn, its


def _rechain_chains(ms: MixedScene, t, x, x2):
    """The classical links' own geometrically consistent update (classical.rechain)."""
    from .chain import fill_prescribed_positions
    from .classical import rechain
    out = x2.copy()
    for u, fr, o0, o1 in zip(ms.units, ms.free, ms.offsets[:-1], ms.offsets[1:]):
        m = u.model
        if len(m.sde_left) == 0:
            continue
        q_old, q_new = np.zeros(m.nq), np.zeros(m.nq)
        q_old[fr], q_new[fr] = x[o0:o1], x2[o0:o1]
        fill_prescribed_positions(m, t, q_old)
        fill_prescribed_positions(m, t, q_new)
        locked = np.ones(m.nq, dtype=bool)
        locked[fr] = False
        out[o0:o1] = rechain(m, q_old, q_new, locked)[fr]
    return out


def _deformation_direction(ms: MixedScene, st: State, x, dq, dx, scale):
    """SDE deformations at (q, x) and their directional derivative along (dq, dx)."""
    sysm = ms.system
    dummy = np.zeros_like(st.q)
    z = np.zeros(ms.nc)
    size = max(float((np.abs(dq[:, :3]) / sysm.length_scale[:, None]).max()), float(np.abs(dq[:, 3:]).max()),
               float(np.abs(dx).max(initial=0.0)))
    h = 1e-6 / max(size, 1e-300)
    out = []
    for sgn in (0.0, 1.0, -1.0):
        ms.set_points(st.t, ms.chain_full(st.t, x + sgn * h * dx, z, z))
        sysm.evaluate(State(st.t, st.q + sgn * h * dq, dummy, dummy, st.ref, dummy), scale)
        out.append(sysm.ws.eps.copy())
    return out[0], (out[1] - out[2]) / (2.0 * h)


def _line_norm(sysm, rL, force_ref):
    s = np.abs(rL).copy()
    s[:, 3:] /= sysm.length_scale[:, None]
    s[~sysm.mask] = 0.0
    return float(s.max(initial=0.0)) / force_ref


# ============================================================================ dynamics
def initial_accelerations(ms: MixedScene, st: State, x, v):
    """Consistent accelerations at a state: the chain's (nc,) and the line's (n, 6), from
    the coupled equations (affine in the chain accelerations: nc + 1 evaluations)."""
    sysm = ms.system
    qddL = np.zeros((sysm.n, 6))

    def g(a):
        full = ms.chain_full(st.t, x, v, a)
        ms.set_points(st.t, full)
        sysm.evaluate(st)
        ms.set_points(st.t, full)
        from ..model.assemble import evaluate as line_eval
        line_eval(sysm.km, sysm.att, st.q, st.qd, st.ref, sysm.ws, 1.0)
        solve_accelerations(sysm.ws, qddL)
        ms.set_loads(qddL)
        r = np.empty(ms.nc)
        for (A, f), o0, o1 in zip(ms.chain_rhs(st.t, full), ms.offsets[:-1], ms.offsets[1:]):
            r[o0:o1] = A @ a[o0:o1] - f
        return r

    a = np.zeros(ms.nc)
    if ms.nc:
        g0 = g(a)
        G = np.empty((ms.nc, ms.nc))
        for j in range(ms.nc):
            e = np.zeros(ms.nc)
            e[j] = 1.0
            G[:, j] = g(e) - g0
        a = np.linalg.solve(G, -g0)
    g(a)
    return a, qddL.copy()


@dataclass
class StepStats:
    steps: int = 0
    newton_iterations: int = 0
    jacobians: int = 0
    rebases: int = 0
    step_halvings: int = 0


class Integrator:
    """Generalised-alpha over the line and chain coordinates with Newton on the coupled
    residual (modified Newton: the Jacobian and its Schur complement are kept while
    Newton converges fast)."""

    def __init__(self, ms: MixedScene, rho_inf, tol, maxit, reuse, chain_tol=None):
        self.ms = ms
        self.chain_tol = tol if chain_tol is None else chain_tol
        self.cp = Coupled(ms)
        self.am, self.af, self.beta, self.gamma = genalpha_parameters(rho_inf)
        self.tol = tol
        self.maxit = maxit
        self.reuse = reuse
        self.h_fact = None
        self.slow = 0
        self.central = False
        self.stats = StepStats()

    def step(self, st: State, c, h, force_ref) -> bool:
        """One step of size h from st.t; st (line) and c = dict(x, v, a, aux) (chain) are
        updated in place on success. Returns False (state untouched) when Newton fails."""
        cp, sysm = self.cp, self.ms.system
        am, af, beta, gamma = self.am, self.af, self.beta, self.gamma
        cq = h * h * beta * (1.0 - af) / (1.0 - am)
        cv = h * gamma * (1.0 - af) / (1.0 - am)
        t1 = st.t + h
        sysm.set_time(t1)
        ab = (af * st.qdd - am * st.aux) / (1.0 - am)
        Q0 = st.q + h * st.qd + h * h * (0.5 - beta) * st.aux + h * h * beta * ab
        V0 = st.qd + h * (1.0 - gamma) * st.aux + h * gamma * ab
        abc = (af * c["a"] - am * c["aux"]) / (1.0 - am)
        Q0c = c["x"] + h * c["v"] + h * h * (0.5 - beta) * c["aux"] + h * h * beta * abc
        V0c = c["v"] + h * (1.0 - gamma) * c["aux"] + h * gamma * abc
        cp.setup(1, t1, 1.0, Q0, V0, Q0c, V0c, cq, cv)
        q = Q0 + cq * st.qdd
        x = Q0c + cq * c["a"]
        rL = np.zeros((sysm.n, 6))
        converged = False
        for attempt in range(2):
            need = self.h_fact != h or not self.reuse or attempt > 0 or self.slow > 4
            fresh = False
            rn_prev = np.inf
            evals = 0
            for it in range(self.maxit):
                rC = cp.residual(q, st.ref, x, rL)
                evals += 1
                self.stats.newton_iterations += 1
                # residuals relative to their tolerances (each floored at the round-off of the stiffest SDE)
                rn = max(float(residual_norm(rL, cq, sysm.mask, sysm.length_scale, force_ref)) / self.tol,
                         cp.chain_norm(rC) / self.chain_tol)
                if not math.isfinite(rn):
                    break
                if rn <= 1.0:
                    converged = True
                    break
                if it > 0 and rn > 0.25 * rn_prev:
                    need = True          # slow (linear) convergence: full Newton from here
                if need:
                    if cp.jacobian(q, st.ref, x, rL, rC, central=self.central) >= 0:
                        self.h_fact = None
                        return False
                    self.stats.jacobians += 1
                    self.h_fact = h
                    fresh, need = True, False
                    rC = cp.residual(q, st.ref, x, rL)     # the workspace after the differences
                dL, dC = cp.solve(rL, rC)
                q -= dL
                x -= dC
                rn_prev = rn
                small = np.all(np.abs(dL[sysm.mask]) <= 1e-13 * np.maximum(np.abs(q[sysm.mask]), 1.0)) and \
                    np.all(np.abs(dC) <= 1e-13 * np.maximum(np.abs(x), 1.0))
                if small:
                    converged = True
                    break
            self.slow = evals
            if converged or fresh:
                break
            q = Q0 + cq * st.qdd
            x = Q0c + cq * c["a"]
        if not converged:
            self.h_fact = None
            return False
        commit_history(sysm.km, sysm.ws)
        A = (q - Q0) / cq
        st.aux[:] = (af * st.qdd + (1.0 - af) * A - am * st.aux) / (1.0 - am)
        st.qd[:] = V0 + cv * A
        st.qdd[:] = A
        st.q[:] = q
        Ac = (x - Q0c) / cq
        c["aux"] = (af * c["a"] + (1.0 - af) * Ac - am * c["aux"]) / (1.0 - am)
        c["v"] = V0c + cv * Ac
        c["a"] = Ac
        c["x"] = x
        st.t = t1
        self.stats.rebases += rebase(st.q, st.qd, st.ref, sysm.km.rfe_kind, REBASE_THRESHOLD, st.qdd, st.aux, True)
        self.stats.steps += 1
        if not (np.all(np.isfinite(st.q)) and np.all(np.isfinite(x))):
            # SolverError adds "at t = ..." to the message
            raise SolverError("the run diverged: non-finite state", time=t1)
        return True

    def advance(self, st: State, c, h, force_ref) -> None:
        """One step of size h, retried in 2, 4, ... 64 sub-steps when Newton fails."""
        for level in range(7):
            sub = 2 ** level
            st_try, c_try = st.copy(), {k: np.array(v, copy=True) for k, v in c.items()}
            saved = self.ms.system.history()
            ok = all(self.step(st_try, c_try, h / sub, force_ref) for _ in range(sub))
            if ok:
                st.t, st.q[:], st.qd[:], st.qdd[:], st.aux[:] = st_try.t, st_try.q, st_try.qd, st_try.qdd, st_try.aux
                st.ref.R[:], st.ref.X[:] = st_try.ref.R, st_try.ref.X
                c.update(c_try)
                if level:
                    self.stats.step_halvings += 1
                return
            self.ms.system.set_history(saved)
        raise SolverError("the run diverged", time=st.t + h, quantity="Newton iteration did not converge")


# ============================================================================ scenario entry points
class _Recorded:
    def __init__(self, ms: MixedScene, nt):
        from ..solvers.dynamics import Recorder
        self.ms = ms
        self.rec = Recorder(ms.system, nt)
        self.Q = [[] for _ in ms.units]
        self.QD = [[] for _ in ms.units]
        self.QDD = [[] for _ in ms.units]
        self.loads = [[] for _ in ms.points]

    def record(self, st: State, c):
        ms = self.ms
        full = ms.chain_full(st.t, c["x"], c["v"], c["a"])
        ms.system.set_time(st.t)
        ms.set_points(st.t, full)
        self.rec.record(st, st.qdd)           # evaluates the line at st (attachment slots as set)
        ms.set_loads(st.qdd)
        for k, (q, qd, qdd) in enumerate(full):
            self.Q[k].append(q)
            self.QD[k].append(qd)
            self.QDD[k].append(qdd)
        for k, pt in enumerate(ms.points):
            self.loads[k].append((pt.force.value.copy(), pt.moment.value.copy()))

    def complete(self) -> int:
        """The number of outputs recorded in full (an interruption may stop a `record`
        half way), the line recorder cut back to them."""
        n = min([self.rec.k] + [len(a) for a in self.Q + self.QD + self.QDD + self.loads])
        self.rec.k = n
        return n

    def results(self, sc, **kw):
        from .. import __version__
        ms = self.ms
        res = self.rec.results(scenario_json=sc.model_dump_json(), version=__version__, **kw)
        times = res.time
        for pt, hist in zip(ms.points, self.loads):
            pt.force.times = pt.moment.times = times
            pt.force.table = np.array([f for f, _ in hist[:len(times)]]).reshape(-1, 3)
            pt.moment.table = np.array([m for _, m in hist[:len(times)]]).reshape(-1, 3)
        joints, kinds = {}, joint_kinds(sc)
        for k, unit in enumerate(ms.units):
            Q, QD, QDD = (np.array(a[:len(times)]) for a in (self.Q[k], self.QD[k], self.QDD[k]))
            res.lines.update(_chain_lines(unit, times, Q, QD, QDD))
            for jname, idx in unit.joints.items():
                joints[jname] = JointResults(jname, Q[:, idx], QD[:, idx], kinds.get(jname, ""))
        for pt in ms.points:
            pt.force.table = pt.moment.table = None
        res.joints = joints
        return res


def _statics_start(ms: MixedScene, sc):
    """The mixed statics, then the Euler buckling check of its lines (rfesim.solvers.buckling,
    as rfesim.api does for a scene of lines only: the chains stand still at their static
    coordinates, where the lines' attachment points are)."""
    s = sc.analysis.statics
    r = mixed_statics(ms, tolerance=s.tolerance, max_iterations=min(s.max_iterations, 200),
                      load_steps=s.load_steps)
    ms.set_points(0.0, ms.chain_full(0.0, r.x, np.zeros(ms.nc), np.zeros(ms.nc)))
    r.warnings = buckling_warnings(ms.system, r.state) + shear_warnings(ms.system, r.state)
    for w in r.warnings:
        log.warning("statics: %s", w)
    return r


def _with_warnings(message: str, warnings) -> str:
    """The results' message with the statics warnings after it (as rfesim.api)."""
    from ..api import STATICS_WARNING
    return "".join([message] + [f"{STATICS_WARNING}{w}" for w in warnings])


def statics(sc, progress=None):
    ms = MixedScene(sc)
    wall0 = _time.perf_counter()
    r = _statics_start(ms, sc)
    rec = _Recorded(ms, 1)
    c = {"x": r.x, "v": np.zeros(ms.nc), "a": np.zeros(ms.nc)}
    rec.record(r.state, c)
    counters = {"newton_iterations": r.iterations, "wall_time": _time.perf_counter() - wall0}
    return rec.results(sc, status=0, message=_with_warnings("converged", r.warnings), counters=counters,
                       kind="statics")


def initial_state(ms: MixedScene, sc, counters=None):
    """(line State, chain dict x, v, a, aux) at t = 0: the statics (if enabled) or the
    compiled initial shape and the joints' initial values; accelerations not yet set."""
    x0 = np.concatenate([u.q0[fr] for u, fr in zip(ms.units, ms.free)]) if ms.nc else np.zeros(0)
    v0 = np.concatenate([u.qd0[fr] for u, fr in zip(ms.units, ms.free)]) if ms.nc else np.zeros(0)
    ms.statics_warnings = []
    if sc.analysis.statics.enabled:
        r = _statics_start(ms, sc)
        st, x, ms.statics_warnings = r.state, r.x, r.warnings
        if counters is not None:
            counters["statics_iterations"] = r.iterations
    else:
        st, x = ms.model.initial.copy(), x0
    return st, {"x": x.copy(), "v": v0.copy(), "a": np.zeros(ms.nc), "aux": np.zeros(ms.nc)}


def make_integrator(ms: MixedScene, st: State, rho_inf, tolerance, max_iterations=12, reuse=True):
    """An Integrator whose tolerances are floored at the round-off of the stiffest SDE
    (line: its force resolution over the typical force; chain: the same force times the
    chains' reach over their typical generalised force)."""
    sysm = ms.system
    force_ref = sysm.force_scale(st)
    roundoff = sysm.roundoff_force(st)
    reach = ms.chain_ref / max(ms.total_weight, 1e-300)
    # the lines' floor also holds the resolution of contact springs' absolute positions
    # (solvers.dynamics.newton_tolerance), as for a scene of lines
    tol = newton_tolerance(sysm, st, tolerance, force_ref)
    chain_tol = max(float(tolerance), 100.0 * roundoff * reach / ms.chain_ref)
    return Integrator(ms, rho_inf, tol, max_iterations, reuse, chain_tol)


def start_dynamics(ms: MixedScene, st: State, c) -> None:
    """Consistent initial accelerations (line and chain), the algorithmic ones equal to them."""
    ms.system.set_friction_mode(0)
    c["a"], st.qdd[:] = initial_accelerations(ms, st, c["x"], c["v"])
    c["aux"] = c["a"].copy()
    st.aux[:] = st.qdd
    ms.system.commit_history()


def filter_start(ms: MixedScene, st: State, c, ig: "Integrator", h: float, force_ref: float) -> bool:
    """The algorithmic accelerations to start generalised-alpha from a state out of
    equilibrium, as rfesim.solvers.dynamics.start_acceleration for a scene of lines:
    a_0 = (M + cq K + cv C)^-1 M qdd_0 over lines and chains together, from one coupled
    Jacobian of the step at the start (the residual of the step at x_0 with A = 0 is
    -cq M qdd_0). In the modes the step resolves that is qdd_0, which start_dynamics gives;
    in a stiff mode it is about 0 where qdd_0 starts the method's overshoot (docs/theory.md,
    'Starting generalised-alpha'). A static equilibrium (``st.static``) and a start in
    equilibrium to the integrator's tolerances keep qdd_0 (round-off there, so the runs
    from statics are as they were), as does a Jacobian that cannot be factorised. Returns
    whether the accelerations were filtered."""
    if st.static:
        return False
    cp, sysm = ig.cp, ms.system
    cq = h * h * ig.beta * (1.0 - ig.af) / (1.0 - ig.am)
    cv = h * ig.gamma * (1.0 - ig.af) / (1.0 - ig.am)
    sysm.set_time(st.t)
    cp.setup(1, st.t, 1.0, st.q.copy(), st.qd.copy(), c["x"], c["v"], cq, cv)
    q = st.q.copy()
    rL = np.zeros((sysm.n, 6))
    rC = cp.residual(q, st.ref, c["x"], rL)
    rn = max(float(residual_norm(rL, cq, sysm.mask, sysm.length_scale, force_ref)) / ig.tol,
             cp.chain_norm(rC) / ig.chain_tol)
    done = False
    if math.isfinite(rn) and rn > 1.0 and cp.jacobian(q, st.ref, c["x"], rL, rC) < 0:
        rC = cp.residual(q, st.ref, c["x"], rL)      # the workspace after the differences
        dL, dC = cp.solve(rL, rC)
        if np.all(np.isfinite(dL)) and np.all(np.isfinite(dC)):
            st.aux[:] = -dL / cq
            st.aux[~sysm.mask] = 0.0
            c["aux"] = -dC / cq
            done = True
    ig.h_fact = None                  # the first step factors its own Jacobian
    # the workspace back at the start state
    ms.set_points(st.t, ms.chain_full(st.t, c["x"], c["v"], c["a"]))
    sysm.evaluate(st)
    return done


def simulate(sc, progress=None):
    """Statics (if enabled) and dynamics of a scene mixing chains with absolute-coordinate
    lines -> Results. ``progress(fraction, time)`` after every output (an exception from it
    stops the run as CancelledError, with the results up to that output: ``results``, status
    3, "cancelled at t = ..."). A SolverError carries the results so far (status 1),
    a KeyboardInterrupt in the dynamics (Ctrl-C, or a SIGTERM the command line turns into
    it) too (``results``, status 2, "interrupted at t = ..."), as for a scene of lines."""
    ms = MixedScene(sc)
    an = sc.analysis
    wall0 = _time.perf_counter()
    counters = {}
    st, c = initial_state(ms, sc, counters)
    dyn = an.dynamics
    if not (dyn.enabled and dyn.duration > 0):
        rec = _Recorded(ms, 1)
        rec.record(st, c)
        counters["wall_time"] = _time.perf_counter() - wall0
        return rec.results(sc, status=0, message=_with_warnings("statics only", ms.statics_warnings),
                           counters=counters, kind="statics")
    integ = dyn.integrator
    sysm = ms.system
    start_dynamics(ms, st, c)
    h = float(integ.time_step)
    T = float(dyn.duration)
    out_dt, n_out, h = output_schedule(T, h, dyn.output_interval)
    per_out = max(1, int(round(out_dt / h)))
    rec = _Recorded(ms, n_out + 1)
    rec.record(st, c)
    force_ref = sysm.force_scale(st)
    ig = make_integrator(ms, st, integ.rho_inf, integ.tolerance, integ.max_iterations, integ.jacobian_reuse)
    filter_start(ms, st, c, ig, h, force_ref)
    wall1 = _time.perf_counter()
    try:
        for k_out in range(1, n_out + 1):
            for _ in range(per_out):
                ig.advance(st, c, h, force_ref)
            st.t = k_out * out_dt
            rec.record(st, c)
            if progress is not None:
                try:
                    progress(min(1.0, st.t / T), st.t)
                except Exception as exc:
                    raise CancelledError(str(exc)) from exc
    except SolverError as exc:
        counters.update(vars(ig.stats))
        exc.results = rec.results(sc, status=1, message=_with_warnings(str(exc), ms.statics_warnings),
                                  counters=counters, kind="dynamics")
        raise
    except (KeyboardInterrupt, CancelledError) as exc:
        # Ctrl-C (or a SIGTERM the command line turns into it; status INTERRUPTED) or a progress
        # callback that raised (the service's cancel; status CANCELLED): the results up to the
        # last output go with it, as for a scene of lines (rfesim.solvers.dynamics.run_dynamics)
        from ..solvers.dynamics import INTERRUPTED, cancelled
        counters.update(vars(ig.stats))
        counters["time_step"] = h
        counters["wall_time"] = _time.perf_counter() - wall0
        n = rec.complete()

        def part(status, message):
            return rec.results(sc, status=status, message=_with_warnings(message, ms.statics_warnings),
                               counters=counters, kind="dynamics")

        if isinstance(exc, KeyboardInterrupt):
            if n:
                exc.results = part(INTERRUPTED, f"interrupted at t = {float(rec.rec.time[n - 1]):.6g} s")
            raise
        raise cancelled(exc, float(rec.rec.time[n - 1]) if n else st.t, part if n else None) \
            from (exc.__cause__ or exc)
    counters.update(vars(ig.stats))
    counters["time_step"] = h
    counters["wall_time"] = _time.perf_counter() - wall0
    counters["wall_time_per_step"] = (_time.perf_counter() - wall1) / max(ig.stats.steps, 1)
    message = _with_warnings(f"finished: {ig.stats.steps} steps", ms.statics_warnings)
    return rec.results(sc, status=0, message=message, counters=counters, kind="dynamics")
