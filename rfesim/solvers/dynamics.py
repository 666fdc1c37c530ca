"""Time integration driver: runs the compiled step loops between output times, records
outputs, reports progress, and turns failures into SolverError with the results so far.

Integrators: ``rk4`` (fixed step, default step from the stiffest mode), ``adaptive``
(Dormand-Prince 5(4)), ``generalized-alpha`` (Chung-Hulbert, implicit, Newton on the
block-tridiagonal Jacobian; a step whose Newton iteration fails is retried in halves).
"""
from __future__ import annotations

import logging
import os
import math
import time as _time

import numpy as np

from ..errors import CancelledError, ScenarioError, SolverError
from ..model.compile import State
from ..kinematics import rotation_to_zyx
from ..loads.seabed import seabed_height
from ..model.bodies import connection_force
from ..model.joins import drive_angles, drive_outputs, hinge_angle, joint_loads, rebase_motors
from .banded import bt_matvec
from .kernels import Q_JACOBIAN, Q_NEWTON, Q_POSITION, Q_THROUGH, Q_VELOCITY, dp_advance, ga_advance, genalpha_parameters, \
    rk4_advance, _DP_A, _DP_B, _DP_C, _DP_E
from .recording import END_ORDER, SDE_ORDER
from .system import System
from ..results import WINCH_CHANNELS

log = logging.getLogger("rfesim")

QUANTITY = {Q_POSITION: "position not finite or runaway", Q_VELOCITY: "velocity not finite or runaway",
            Q_NEWTON: "Newton iteration did not converge", Q_JACOBIAN: "singular Jacobian",
            Q_THROUGH: "rope elements pushed through one another (past their axial contact)"}


def highest_frequency(system: System, state: State, iterations: int = 60) -> float:
    """Largest natural circular frequency (rad/s) of the linearised model at the state,
    by power iteration on M^-1 K (K: stiffness from the block-tridiagonal Jacobian)."""
    st = state.copy()
    st.qd[:] = 0.0
    r0 = np.zeros((system.n, 6))
    system.static_residual(st.q, st.ref, 1.0, r0)
    K = system.static_jacobian(st.q, st.ref, 1.0, r0).copy()
    system.evaluate(st)
    Mgen = system.ws.Mgen.copy()
    mask = system.mask
    rng = np.random.default_rng(1)
    x = rng.standard_normal((system.n, 6))
    x[~mask] = 0.0
    y = np.zeros_like(x)
    lam = 0.0
    for _ in range(iterations):
        bt_matvec(K, x, y)
        y[~mask] = 0.0
        z = np.linalg.solve(Mgen, y[:, :, None])[:, :, 0]
        z[~mask] = 0.0
        nz = np.linalg.norm(z)
        nx = np.linalg.norm(x)
        if nx == 0 or nz == 0:
            break
        lam = nz / nx
        x = z / nz
    return math.sqrt(max(lam, 0.0)) * 1.1


def highest_damping_rate(system: System, state: State, iterations: int = 60) -> float:
    """Largest eigenvalue (1/s) of M^-1 C, C the damping matrix (minus the derivative of the
    forces by the velocities) of the model at rest at the state: power iteration on central
    differences of the accelerations in the velocities, times 1.1 as ``highest_frequency``.

    A mode damped beyond critical has a real eigenvalue up to c/m, however low its natural
    frequency: the critically damped body connection (rfesim.model.bodies) acts on the line's
    end RFE through its half-length arm, where the RFE's rotation carries about a quarter of
    its mass, and sets -3.6e5 1/s on a 20 m rope with EA 5.9e7 N and 1 m elements, 3.7 times
    its highest natural frequency (docs/theory.md, the RK4 integrator)."""
    st = state.copy()
    st.qd[:] = 0.0
    mask = system.mask
    if not mask.any():
        return 0.0
    rng = np.random.default_rng(2)
    x = rng.standard_normal((system.n, 6))
    x[~mask] = 0.0
    eps = 1e-6          # m/s, rad/s on the largest component: linear dampers are exact, drag ~ eps
    lam = 0.0
    for _ in range(iterations):
        x /= np.abs(x).max()
        st.qd[:] = eps * x
        a_p = system.accelerations(st)
        st.qd[:] = -eps * x
        a_m = system.accelerations(st)
        z = (a_m - a_p) / (2.0 * eps)
        z[~mask] = 0.0
        nz = np.linalg.norm(z)
        nx = np.linalg.norm(x)
        if not (nz > 0.0 and math.isfinite(nz)):
            break
        lam = nz / nx
        x = z
    # (the workspace is left evaluated at rest, as highest_frequency leaves it)
    st.qd[:] = 0.0
    system.evaluate(st)
    return lam * 1.1


RK4_REAL_LIMIT = 2.785      # RK4 reaches -2.785 on the negative real axis


def stable_rk4_step(system: System, state: State, safety: float) -> float:
    """Default RK4 step: safety * 2.8 / omega_max (RK4 reaches 2*sqrt(2) on the imaginary axis),
    and at most safety * 2.785 / the largest damping rate (the negative real axis)."""
    w = highest_frequency(system, state)
    km = system.km
    if km.has_seabed:
        # any RFE may touch down, and a sticking one rides on the friction spring too
        k = max(km.seabed_k, km.seabed_kt if km.has_friction else 0.0)
        w = max(w, 1.1 * float(np.sqrt(k * km.rfe_length / np.maximum(km.rfe_mass, 1e-300)).max()))
    if km.has_rollers:
        # a roller acts on one RFE at a time (two at an SDE): k / m of the lightest RFE
        w = max(w, 1.1 * float(np.sqrt(2.0 * km.roller_k.max() / max(km.rfe_mass.min(), 1e-300))))
    # a mode damped past critical has a real eigenvalue -c/m (at most) beyond omega_max
    g = highest_damping_rate(system, state)
    if km.has_seabed:
        # the seabed's dampers act only on RFEs in contact (the stick damper once an anchor is
        # set), which the start state need not show: c l / m of each RFE, an upper bound of
        # the rate (an RK4 step past it made a pipe held by friction at 3 % of its limit slip)
        # (the normal damper acts at the contact centroid, which also turns the RFE: up to
        # 1.33 c l / m in partial contact, hence 1.4)
        per_mass = km.rfe_length / np.maximum(km.rfe_mass, 1e-300)
        c = np.maximum(1.4 * km.rfe_seabed_c, 1.1 * km.rfe_seabed_ct if km.has_friction else 0.0)
        g = max(g, float((c * per_mass).max()))
    if w <= 0.0 and g <= 0.0:
        return 0.01
    step = math.inf
    if w > 0.0:
        # SDE damping moves eigenvalues off the imaginary axis; keep inside the region
        zeta = _max_damping_ratio(system)
        step = 2.8 / (w * math.sqrt(1.0 + 4.0 * zeta * zeta))
    if g > 0.0:
        step = min(step, RK4_REAL_LIMIT / g)
    return safety * step


def _max_damping_ratio(system: System) -> float:
    km = system.km
    if not system.model.nsde:
        return 0.0
    c = km.sde_stiffness
    d = km.sde_damping
    m = km.rfe_mass.min()
    with np.errstate(divide="ignore", invalid="ignore"):
        z = d[:, :3] / (2.0 * np.sqrt(c[:, :3] * m))
    z = z[np.isfinite(z)]
    return float(z.max()) if z.size else 0.0


def contact_resolution_force(system: System, state: State) -> float:
    """The force resolution (N) of the springs that compare an RFE's absolute position with a
    point of the scene (not an SDE): tensioner pads and grips, rollers, reels, seabed contact
    and friction, tuggers, deck contact; their stiffness times one ulp of the coordinates
    (``ulp(max |r|)``; the seabed's normal gap: ulp of |z| plus the bed's slope times ulp of
    |x|, |y|), at the state (the start of the run).

    Within a generalised-alpha step the RFE positions are ``ref.X + q`` with ``ref.X`` fixed
    and ``q`` the displacement (re-based after each step): the SDE gaps difference the two
    parts apart (``rfesim.loads.sde``) and are continuous in q, but these springs take the
    rounded sum ``r = ref.X + q``, which moves in steps of ulp(|r|), and no iterate brings
    their forces below about k ulp(|r|) (docs/theory.md, 'Resolution of absolute positions in
    dynamics'). 1e7 N/m/m pads on 1 m elements: 2.3e-6 N at 1200 m from the origin, 9.3e-3 N
    at 6.7e6 m (a UTM northing)."""
    km = system.km
    if system.n == 0:
        return 0.0
    pos = np.abs(state.ref.X + state.q[:, :3])
    ulp = float(np.spacing(pos.max()))
    ulp_xy = float(np.spacing(pos[:, :2].max()))
    ulp_z = float(np.spacing(pos[:, 2].max()))
    length = float(km.rfe_length.max())
    k = [0.0]
    if km.has_tensioners and km.tens_kl.size:
        k.append(max(float(km.tens_kl.max()), float(km.tens_kg.max())) * length * ulp)
    if km.has_rollers and km.roller_k.size:
        k.append(max(float(km.roller_k.max()), float(km.roller_kt.max()) if km.has_roller_friction else 0.0) * ulp)
    if getattr(km, "has_reels", False) and km.reel_kr.size:
        k.append(max(float(km.reel_kr.max()), float(km.reel_kl.max()), float(km.reel_kg.max())) * length * ulp)
    if km.has_seabed:
        slope = 0.0
        if km.bed_s.size > 1:
            slope = float(np.abs(np.diff(km.bed_z) / np.diff(km.bed_s)).max())
        k.append(km.seabed_k * length * (ulp_z + slope * ulp_xy))
        if km.has_friction:
            k.append(km.seabed_kt * length * ulp)
    if getattr(km, "has_tuggers", False) and km.tug_k.size:
        k.append(float(km.tug_k.max()) * ulp)
    if getattr(km, "has_deck", False) and km.body_deck_k.size:
        k.append(float(km.body_deck_k.max()) * ulp)
    return max(k)


def start_acceleration(system: System, state: State, cq: float, cv: float, tol: float = 0.0,
                       force_ref: float = 1.0) -> np.ndarray:
    """The generalised-alpha algorithmic acceleration to start from: a_0 = (M + cq K + cv C)^-1
    M qdd_0, with M qdd_0 = f(q_0, qd_0) the force that gives the true start acceleration
    (``state.qdd``) and K, C the tangents of the step's Jacobian (cq = h^2 beta (1 - af) /
    (1 - am), cv = h gamma (1 - af) / (1 - am)).

    In a mode the step resolves (cq omega^2 << 1) a_0 = qdd_0 (1 - O(cq omega^2)), which keeps
    the method second order from a start out of equilibrium (a_0 = 0 cut it to first order for
    rho_inf < 1); in a stiff mode (cq omega^2 >> 1) a_0 ~ 0, which keeps the method's
    overshoot off: a_0 = qdd_0 there starts a velocity of about 0.02 (omega h) omega x_0 at
    rho_inf 0.8 (x_0 the mode's start offset, 1 m/s from 1e-8 m on a stiff rope at 50 ms
    steps). The residual of the implicit step at q_0 with A = 0 is -cq f and its Jacobian is
    M + cq K + cv C (``residual_q`` mode 1), so a_0 = -J^-1 r / cq, with the coloured
    finite-difference Jacobian the step may use. Fixed coordinates get 0, as in the steps.
    Where the Jacobian cannot be factorised, 0.

    A static equilibrium (``state.static``, set by solve_statics) starts at 0, as do a start
    already in equilibrium to the step's Newton tolerance ``tol`` (relative to ``force_ref``,
    as ``residual_norm`` measures it): their qdd_0 is round-off or what the statics left
    within its own tolerance (0.5 m/s^2 on a payload on deck), and slack-rope runs from
    statics are chaotic enough that a_0 of 1e-9 m/s^2 reordered their slack events
    (docs/theory.md, 'Starting generalised-alpha')."""
    from .banded import bt_factor_closed, bt_solve_closed
    from .kernels import FD_REL_STEP, jacobian_fd_general, residual_q
    km, ws, n = system.km, system.ws, system.n
    if state.static:
        return np.zeros((n, 6))
    system.set_time(state.t)
    Q0 = state.q.copy()
    V0 = state.qd.copy()
    r = np.zeros((n, 6))
    residual_q(km, system.att, state.q, state.ref, ws, 1.0, 1, Q0, V0, cq, cv, system.mask, system.qd_buf,
               system.A_buf, r)
    size = np.abs(r) / cq
    size[:, 3:] /= system.length_scale[:, None]
    a0 = np.zeros((n, 6))
    if not np.any(np.isnan(size)) and float(np.max(size, where=system.mask, initial=0.0)) <= tol * force_ref:
        return a0                   # (the workspace holds the start state's evaluation)
    base = r.copy()                 # forward differences from the residual at q_0
    jacobian_fd_general(km, system.att, state.q, state.ref, ws, 1.0, 1, Q0, V0, cq, cv, system.mask, system.qd_buf,
                        system.A_buf, base, system.qp, system.rp, system.hs, system.length_scale, system.J, False,
                        FD_REL_STEP)
    if bt_factor_closed(system.J, system.Fac, km, ws) < 0:
        dq = np.zeros((n, 6))
        bt_solve_closed(system.Fac, r, dq, km, ws)
        if np.all(np.isfinite(dq)):
            a0 = -dq / cq
    # the workspace back at the start state (the Jacobian left it at a perturbed one)
    system.evaluate(state)
    return a0


def newton_tolerance(system: System, state: State, tolerance: float, force_ref: float) -> float:
    """The generalised-alpha Newton tolerance (residual over ``force_ref``): the scenario's,
    floored at 100 times the round-off of the stiffest SDE (``System.roundoff_force``) and at
    POSITION_FLOOR times the resolution of the contact springs' absolute positions
    (``contact_resolution_force``), below which no iterate gets."""
    from .statics import POSITION_FLOOR
    floor = max(100.0 * system.roundoff_force(state), POSITION_FLOOR * contact_resolution_force(system, state))
    return max(float(tolerance), floor / force_ref)


SDE_CHANNELS = ("tension", "shear_force", "bend_moment", "torque", "curvature")
END_CHANNELS = ("end_a_force", "end_b_force", "end_a_moment", "end_b_moment", "end_a_direction", "end_b_direction")


class Recorder:
    """Preallocated output arrays, filled at output times."""

    def __init__(self, system: System, nt: int):
        from ..model.outputs import record_outputs
        from .fastcall import FastCall
        # the output kernels, all in one call per output time with the same model tuples
        self._record_outputs = FastCall(record_outputs)
        self.system = system
        model = system.model
        # the SDEs whose end loads are outputs: joints between lines, then body connections
        joins = getattr(model, "joins", [])
        # (then the closing joins: their loads are the closing line's end B loads)
        self._end_sdes = np.array([ji.sde for ji in joins] + [b.sde for b in model.bodies]
                                  + [ci.sde for ci in getattr(model, "closures", [])], np.int64)
        self._end = np.zeros((self._end_sdes.shape[0], 4, 3))
        self._end_F = np.zeros((model.n, 3))
        self._end_M = np.zeros((model.n, 3))
        self.nt = nt
        self.k = 0
        self.time = np.zeros(nt)
        self.line_data = {}
        # the channels written for every line at every output live in one array per channel
        # over all lines (each line's arrays are views of its part), so that an output time
        # copies each channel once instead of once per line
        nsde = model.nsde
        nl = len(model.lines)
        # (stacked in the order the compiled recording writes them, rfesim.solvers.recording)
        self._sde_hist = np.zeros((len(SDE_ORDER), nt, nsde))
        self._sde_out = {ch: self._sde_hist[SDE_ORDER.index(ch)] for ch in SDE_CHANNELS}
        self._pos_out = np.zeros((nt, sum(li.elements + 2 for li in model.lines), 3))
        self._ends_hist = np.zeros((len(END_ORDER), nt, nl, 3))
        self._end_out = {ch: self._ends_hist[END_ORDER.index(ch)] for ch in END_CHANNELS}
        # seabed channels over all RFEs and the touchdown point per line (views per line below)
        self._seabed_out = np.zeros((nt, model.n))
        self._friction_out = np.zeros((nt, model.n, 3))
        self._td_pos = np.full((nt, nl, 3), np.nan)
        self._td_arc = np.full((nt, nl), np.nan)
        self._ia = np.array([li.rfe_start for li in model.lines], np.int64)
        self._ib = np.array([li.rfe_stop - 1 for li in model.lines], np.int64)
        row = 0
        for j, li in enumerate(model.lines):
            npts = li.elements + 2
            self.line_data[li.name] = {
                "position": self._pos_out[:, row:row + npts],
                **{ch: self._sde_out[ch][:, li.sde_start:li.sde_stop] for ch in SDE_CHANNELS},
                **{ch: self._end_out[ch][:, j] for ch in END_CHANNELS},
                "seabed_force": self._seabed_out[:, li.rfe_start:li.rfe_stop],
                "seabed_friction": self._friction_out[:, li.rfe_start:li.rfe_stop],
                "touchdown_position": self._td_pos[:, j],
                "touchdown_arc_length": self._td_arc[:, j],
                "von_mises_stress": np.full((nt, li.elements), np.nan),
                "utilisation": np.full((nt, li.elements), np.nan),
                "residual_curvature": np.zeros((nt, li.elements)),
            }
            row += npts
        for ji in getattr(model, "joins", []):     # drives of a joined line end (rfesim.model.joins)
            if ji.drive_names:
                for ch in ("drive_angle", "drive_torque"):
                    self.line_data[ji.child][ch] = np.zeros((nt, len(ji.drive_names)))
            if ji.hinge >= 0:
                self.line_data[ji.child]["hinge_angle"] = np.zeros(nt)
        # ropes that slip over a sheave led to a vessel point (rfesim.loads.reeving)
        km0 = system.km
        self._slipping = []
        if getattr(km0, "has_reeving", False):
            child = {ji.sde: ji.child for ji in joins}
            for j in range(km0.rv_sde.shape[0]):
                if km0.rv_slip[j]:
                    rope = child[int(km0.rv_sde[j])]
                    self._slipping.append((j, rope))
                    self.line_data[rope]["reeving_slip"] = np.zeros(nt)
        self.vessel_names = list(model.scenario.vessels)
        self.vessel_pos = np.zeros((nt, len(self.vessel_names), 3))
        self.vessel_rot = np.zeros((nt, len(self.vessel_names), 3))
        self._ch = {ch: np.zeros(nsde) for ch in SDE_CHANNELS}
        self._react = np.zeros((model.n, 6))
        # the points of every line in one buffer (rows li.elements + 2 per line)
        self._pts_all = np.zeros((sum(li.elements + 2 for li in model.lines), 3))
        self._line_ranges = np.zeros((len(model.lines), 5), np.int64)
        row = 0
        for j, li in enumerate(model.lines):
            assert li.sde_stop - li.sde_start == li.elements
            self._line_ranges[j] = (li.rfe_start, li.rfe_stop, li.sde_start, li.sde_stop, row)
            row += li.elements + 2
        nr = model.km.roller_attach.shape[0]
        self.roller_reaction = np.zeros((nt, nr))
        self.roller_force = np.zeros((nt, nr, 3))
        ntens = len(model.tensioners)
        self.tens_payout = np.zeros((nt, ntens))
        self.tens_force = np.zeros((nt, ntens))
        nreel = len(getattr(model, "reels", []))
        self.reel_payout = np.zeros((nt, nreel))
        self.reel_force = np.zeros((nt, nreel))
        if model.km.has_plastic:
            self._residual = np.zeros(model.nsde)
            self._residual_work = np.zeros((model.nsde, model.plastic_history_width))
        self.winch_data = {c.name: {ch: np.zeros(nt) for ch in WINCH_CHANNELS}
                           for c in getattr(system, "controllers", ())}
        ntug = len(getattr(model, "tuggers", []))
        self.tug_tension = np.zeros((nt, ntug))
        self.tug_length = np.zeros((nt, ntug))
        self.tug_force = np.zeros((nt, ntug, 3))
        self.body_data = {b.name: {ch: np.zeros((nt, 3)) for ch in ("position", "velocity", "acceleration", "rotation",
                                                                    "angular_velocity", "connection_force")}
                          | {ch: np.zeros(nt) for ch in ("connection_tension", "submerged_fraction", "buoyancy",
                                                         "deck_force")}
                          for b in model.bodies}
        # stress outputs (eqs. 8.97-8.98 with hydrostatic pressure) of elasto-plastic pipe lines
        self._stress_geometry = {}
        self._contents_density = {}
        for li in model.lines:
            lt = model.scenario.line_types[model.scenario.lines[li.name].type]
            material = getattr(lt, "material", None)
            if material is not None and getattr(material, "kind", "") == "elastoplastic":
                from ..materials.sde_plastic import plastic_params
                row = plastic_params(material, li.section).stress_geometry
                self._stress_geometry[li.name] = np.tile(row, (li.elements, 1))
                self._contents_density[li.name] = float(getattr(lt, "contents_density", 0.0) or 0.0)

    def record(self, state: State, qdd: np.ndarray) -> None:
        if self.k >= self.nt:
            return
        sysm = self.system
        km = sysm.km
        ws = sysm.ws
        if ws.step_state[0] == 1 and abs(sysm.att.time[0] - state.t) <= 1e-9 * max(1.0, abs(state.t)):
            ws.step_state[0] = 0        # the generalised-alpha step left the evaluation of this very state
        else:
            sysm.evaluate(state)
        ch = self._ch
        self._record_outputs(km, sysm.att, ws, qdd, self._react, km.sde_length, ch["tension"], ch["shear_force"],
                             ch["bend_moment"], ch["torque"], ch["curvature"], self._line_ranges, self._pts_all,
                             self._end_sdes, self._end_F, self._end_M, self._end)
        k = self.k
        self.time[k] = state.t
        if km.has_plastic:
            # from the trial history of this evaluation: the state being recorded
            from ..materials.residual_curvature import residual_curvature_into
            residual_curvature_into(km.plastic_params, ws.plastic_hist_trial, km.sde_plastic, self._residual_work,
                                    ws.out5, self._residual)
        self._pos_out[k] = self._pts_all
        for name, out in self._sde_out.items():
            out[k] = ch[name]
        # force and moment of a line on its attachment = - constraint force on the end RFE
        E, react, ia, ib = self._end_out, self._react, self._ia, self._ib
        np.negative(react[ia, :3], out=E["end_a_force"][k])
        np.negative(react[ib, :3], out=E["end_b_force"][k])
        np.negative(react[ia, 3:], out=E["end_a_moment"][k])
        np.negative(react[ib, 3:], out=E["end_b_moment"][k])
        E["end_a_direction"][k] = ws.R[ia, :, 0]
        E["end_b_direction"][k] = ws.R[ib, :, 0]
        if km.has_seabed or km.has_plastic or self._stress_geometry:
            self._record_line_extras(k, km, ws)
        for j, name in enumerate(self.vessel_names):
            a = 1 + j
            self.vessel_pos[k, j] = sysm.att.p[a]
            R_rel = sysm.vs.R_heading[a].T @ sysm.att.R[a]
            psi, theta, phi = rotation_to_zyx(R_rel)
            self.vessel_rot[k, j] = (math.degrees(phi), math.degrees(theta), math.degrees(psi))
        if km.has_tensioners:
            from ..loads.tensioner import tensioner_payout
            for ti in sysm.model.tensioners:
                self.tens_payout[k, ti.index] = tensioner_payout(km.tens_mode, km.tens_table_t, km.tens_table_d,
                                                                 km.tens_table_v, km.tens_count, ti.index, state.t, ws.tens_D)
                self.tens_force[k, ti.index] = ws.tens_force[ti.index]
        if km.has_reels:
            from ..loads.tensioner import tensioner_payout
            for ri in sysm.model.reels:
                self.reel_payout[k, ri.index] = tensioner_payout(km.reel_mode, km.reel_table_t, km.reel_table_d,
                                                                 km.reel_table_v, km.reel_count, ri.index, state.t,
                                                                 ws.reel_D)
                self.reel_force[k, ri.index] = ws.reel_force[ri.index]
        if sysm.model.bodies:
            self._record_bodies(k, ws, qdd)
        if getattr(sysm.model, "joins", None):
            self._record_joins(k, ws, state.t)
        self._record_closures(slice(k, k + 1), self._end[None])
        for c in getattr(sysm, "controllers", ()):
            for ch, value in c.channels().items():
                self.winch_data[c.name][ch][k] = value
        if km.has_tuggers:
            self._record_tuggers(k, ws)
        for j, rope in self._slipping:
            # the slip still on the sheave's join, and what the rope's winch took over
            handed = sum(c.slipped for c in getattr(sysm, "controllers", ()) if c.lead == j)
            self.line_data[rope]["reeving_slip"][k] = ws.rv_slip_out[j] + handed
        if km.has_rollers:
            self.roller_reaction[k] = ws.roller_normal
            self.roller_force[k] = ws.roller_force
        self.k += 1

    def slip_beyond(self) -> str:
        """A message when a rope has slipped over its sheave by more than the length of its
        first RFE (the sheave must stay on it, rfesim.loads.reeving), else ''."""
        if not self._slipping:
            return ""
        km, ws = self.system.km, self.system.ws
        for j, rope in self._slipping:
            # (a winch hands the slip over to the rope's length before it gets there)
            b = int(km.sde_right[km.rv_sde[j]])
            first = float(km.rfe_length[b])
            slip = float(ws.rv_slip_out[j])
            if abs(slip) > first:
                return (f"rope '{rope}' slipped {slip:.4g} m over its sheave toward the lead, more than its first "
                        f"element ({first:.4g} m) can carry: the slip is modelled while the sheave stays on that "
                        f"element (docs/theory.md, 'Reeving'); a frame luffing far with a deck-winch lead needs "
                        f"the rope led along the boom (\"reeving\": \"boom\") or no reeving")
        return ""

    def _record_line_extras(self, k: int, km, ws) -> None:
        """The line channels of a seabed and of elasto-plastic pipe, line by line."""
        for j, li in enumerate(self.system.model.lines):
            d = self.line_data[li.name]
            if km.has_seabed:           # zero (as allocated) without a seabed
                d["seabed_force"][k] = ws.contact_force[li.rfe_start:li.rfe_stop]
                d["seabed_friction"][k] = ws.friction_force[li.rfe_start:li.rfe_stop]
            if li.name in self._stress_geometry:
                from ..materials.sde_plastic import N_STRESS, pipe_stress_into
                p_ext, p_int = self._sde_pressures(j, li, km, ws)
                out = np.zeros((li.elements, N_STRESS))
                pipe_stress_into(ws.sigma[li.sde_start:li.sde_stop], self._stress_geometry[li.name], p_ext, p_int,
                                 out)
                d["von_mises_stress"][k] = out[:, 5]
                d["utilisation"][k] = out[:, 6]
            if km.has_plastic:
                d["residual_curvature"][k] = self._residual[li.sde_start:li.sde_stop]
            if km.has_seabed:
                td = touchdown(km, ws, li)
                if td is not None:
                    d["touchdown_arc_length"][k], d["touchdown_position"][k] = td

    def _sde_pressures(self, j: int, li, km, ws):
        """Hydrostatic external and internal pressure (Pa) at the SDEs of line j (docs/theory.md,
        "Stresses"), at the SDE points of this evaluation (ws.sde_point):
        p_ext = rho_w g (surface level - z) below the still-water surface, else 0 (no wave
        pressure); p_int = rho_c g (z_top - z), the contents at rest and open (zero gauge
        pressure) at the line's highest point z_top now (its end points and SDE points, the
        rows of the line in self._pts_all written by record_outputs); 0 for an empty pipe."""
        z = ws.sde_point[li.sde_start:li.sde_stop, 2]
        rho_c = self._contents_density[li.name]
        z_top = 0.0
        if rho_c > 0.0:
            row = int(self._line_ranges[j, 4])
            z_top = float(self._pts_all[row:row + li.elements + 2, 2].max())
        rho_w = km.water_density if km.has_water else 0.0
        return hydrostatic_pressures(z, z_top, km.gravity, rho_w, km.water_level, rho_c)

    def _record_tuggers(self, k: int, ws) -> None:
        """Tension, length and force on the body of each tugger line (rfesim.loads.tugger)."""
        km = self.system.km
        att = self.system.att
        self.tug_tension[k] = ws.tug_tension
        self.tug_length[k] = ws.tug_length
        for j in range(km.tug_rfe.shape[0]):
            i, a = km.tug_rfe[j], km.tug_att[j]
            D = att.p[a] + att.R[a] @ km.tug_deck[j]
            P = ws.r[i] + ws.R[i] @ km.tug_point[j]
            L = np.linalg.norm(D - P)
            self.tug_force[k, j] = ws.tug_tension[j] * (D - P) / L if L > 1e-9 else 0.0

    def _record_bodies(self, k: int, ws, qdd: np.ndarray) -> None:
        km = self.system.km
        nj = len(getattr(self.system.model, "joins", []))
        for jb, b in enumerate(self.system.model.bodies):
            d = self.body_data[b.name]
            i = b.rfe
            d["position"][k] = ws.r[i]
            d["velocity"][k] = ws.v[i]
            d["acceleration"][k] = qdd[i, :3]
            psi, theta, phi = rotation_to_zyx(ws.R[i])
            d["rotation"][k] = (math.degrees(phi), math.degrees(theta), math.degrees(psi))
            d["angular_velocity"][k] = ws.w[i]
            force, moment = connection_force(km, ws, b, self._end[nj + jb])
            d["connection_force"][k] = force
            d["connection_tension"][k] = math.sqrt(force[0] * force[0] + force[1] * force[1] + force[2] * force[2])
            frac = float(ws.sub_frac[i]) if km.has_bodies else 0.0
            d["submerged_fraction"][k] = frac
            d["buoyancy"][k] = km.water_density * km.gravity * b.volume * frac
            d["deck_force"][k] = float(ws.deck_normal[jb]) if km.has_deck else 0.0
            line = self.line_data[b.line]           # the line's end B force is the force on the body
            line["end_b_force"][k] = force
            line["end_b_moment"][k] = moment

    def _record_closures(self, rows, end_hist) -> None:
        """A closing join's force and moment as the end B loads of its closing line (the
        sign of an attached end: the line's pull on the target's end B). end_hist (rows, m,
        4, 3): sde_end_loads of the end SDEs."""
        model = self.system.model
        first = len(getattr(model, "joins", [])) + len(model.bodies)
        for c, ci in enumerate(getattr(model, "closures", [])):
            line = self.line_data[ci.child]
            line["end_b_force"][rows] = -end_hist[:, first + c, 2]
            line["end_b_moment"][rows] = -end_hist[:, first + c, 3]

    def _record_joins(self, k: int, ws, t: float) -> None:
        """The joint loads as the end loads of the two joined lines, and the drive channels."""
        km = self.system.km
        for j, ji in enumerate(self.system.model.joins):
            angles = drive_angles(km, ji, t) if ji.drive_stop > ji.drive_start else None
            loads = joint_loads(km, ws, ji, t, self._end[j], angles)
            child, parent = self.line_data[ji.child], self.line_data[ji.parent]
            child["end_a_force"][k] = loads["child_force"]
            child["end_a_moment"][k] = loads["child_moment"]
            parent["end_b_force"][k] = loads["parent_force"]
            parent["end_b_moment"][k] = loads["parent_moment"]
            if ji.drive_names:
                child["drive_angle"][k], child["drive_torque"][k] = drive_outputs(km, ji, loads, t, angles)
            if ji.hinge >= 0:
                child["hinge_angle"][k] = math.degrees(hinge_angle(ws, ji))

    # ------------------------------------------------------------ recording inside the step loop
    def kernel_records(self) -> bool:
        """True when the compiled run (rfesim.solvers.recording.ga_run) records every channel
        of this scene: lines (with the seabed and touchdown channels), bodies, joints with
        prescribed drives, vessels. Scenes with controllers, motors, elasto-plastic pipe,
        tensioners, reels, tuggers, rollers, hinged joins or ropes slipping over a sheave are
        recorded in Python (Recorder.record)."""
        if not self.IN_KERNEL:
            return False
        sysm = self.system
        km = sysm.km
        if getattr(sysm, "controllers", None) or km.has_motors or km.has_plastic \
                or self._stress_geometry or km.has_tensioners or km.has_reels or km.has_tuggers or km.has_rollers:
            return False
        if self._slipping:
            return False
        return all(ji.motor < 0 and ji.hinge < 0 for ji in getattr(sysm.model, "joins", []))

    IN_KERNEL = True        # tests switch it off to compare with the Python recording

    def kernel_arrays(self):
        """The RecordArrays the compiled run writes (views of this recorder's arrays)."""
        if getattr(self, "_rec", None) is not None:
            return self._rec
        from .recording import SEL_WIDTH, VESSEL_WIDTH, RecordArrays
        model = self.system.model
        km = self.system.km
        joins = getattr(model, "joins", [])
        sel = []
        for b in model.bodies:
            if b.rfe not in sel:
                sel.append(b.rfe)
        for ji in joins:
            if ji.drive_names and ji.parent_rfe not in sel:
                sel.append(ji.parent_rfe)
        self._sel = {i: j for j, i in enumerate(sel)}
        nt = self.nt
        self._rec = RecordArrays(
            time=self.time, sde=self._sde_hist, pos=self._pos_out, ends=self._ends_hist, ia=self._ia, ib=self._ib,
            line_ranges=self._line_ranges, react=self._react, end_sdes=self._end_sdes, end_F=self._end_F,
            end_M=self._end_M, end_hist=np.zeros((nt,) + self._end.shape),
            sel=np.array(sel, np.int64), sel_hist=np.zeros((nt, len(sel), SEL_WIDTH)),
            body_rfe=np.array([b.rfe for b in model.bodies], np.int64),
            body_hist=np.zeros((nt, len(model.bodies), 2)),
            vessel_hist=np.zeros((nt, len(self.vessel_names), VESSEL_WIDTH)),
            drive_hist=np.zeros((nt, km.drive_count.shape[0])),
            seabed=self._seabed_out, friction=self._friction_out, td_pos=self._td_pos, td_arc=self._td_arc)
        return self._rec

    def finish_rows(self, k0: int, k1: int) -> None:
        """The body, joint and vessel channels of rows k0..k1-1 that the compiled run wrote
        raw (kernel_arrays), as Recorder.record would have written them."""
        if k1 <= k0:
            return
        rec = self._rec
        sysm = self.system
        km = sysm.km
        rows = slice(k0, k1)
        for j, name in enumerate(self.vessel_names):
            raw = rec.vessel_hist[rows, j]
            self.vessel_pos[rows, j] = raw[:, :3]
            R_rel = sysm.vs.R_heading[1 + j].T @ raw[:, 3:].reshape(-1, 3, 3)
            self.vessel_rot[rows, j] = _zyx_degrees(R_rel)
        model = sysm.model
        joins = getattr(model, "joins", [])
        nj = len(joins)
        for jb, b in enumerate(model.bodies):
            d = self.body_data[b.name]
            raw = rec.sel_hist[rows, self._sel[b.rfe]]
            d["position"][rows] = raw[:, 0:3]
            d["velocity"][rows] = raw[:, 3:6]
            d["acceleration"][rows] = raw[:, 6:9]
            d["angular_velocity"][rows] = raw[:, 9:12]
            d["rotation"][rows] = _zyx_degrees(raw[:, 12:21].reshape(-1, 3, 3))
            force = rec.end_hist[rows, nj + jb, 2]
            moment = rec.end_hist[rows, nj + jb, 3]
            d["connection_force"][rows] = force
            d["connection_tension"][rows] = np.sqrt(force[:, 0] * force[:, 0] + force[:, 1] * force[:, 1]
                                                    + force[:, 2] * force[:, 2])
            frac = rec.body_hist[rows, jb, 0]
            d["submerged_fraction"][rows] = frac
            d["buoyancy"][rows] = km.water_density * km.gravity * b.volume * frac
            d["deck_force"][rows] = rec.body_hist[rows, jb, 1]
            line = self.line_data[b.line]           # the line's end B force is the force on the body
            line["end_b_force"][rows] = force
            line["end_b_moment"][rows] = moment
        self._record_closures(rows, rec.end_hist[rows])
        for j, ji in enumerate(joins):
            end = rec.end_hist[rows, j]
            child, parent = self.line_data[ji.child], self.line_data[ji.parent]
            child["end_a_force"][rows] = -end[:, 2]
            child["end_a_moment"][rows] = -end[:, 3]
            parent["end_b_force"][rows] = -end[:, 0]
            parent["end_b_moment"][rows] = -end[:, 1]
            if ji.drive_names:
                angles = rec.drive_hist[rows, ji.drive_start:ji.drive_stop]
                child["drive_angle"][rows] = np.degrees(angles)
                on_child = end[:, 3]              # - child moment: the joint moment on the child
                R_parent = rec.sel_hist[rows, self._sel[ji.parent_rfe], 12:21].reshape(-1, 3, 3)
                # the drives' axes (rfesim.model.joins.drive_axes), turned by the drives before each
                D = None
                last = ji.drive_stop - 1
                for m, jd in enumerate(range(ji.drive_start, ji.drive_stop)):
                    a = km.drive_axis[jd]
                    ax = np.broadcast_to(a, (k1 - k0, 3)) if D is None else D @ a
                    g = (R_parent @ ax[:, :, None])[:, :, 0]
                    child["drive_torque"][rows, m] = (on_child[:, 0] * g[:, 0] + on_child[:, 1] * g[:, 1]
                                                      + on_child[:, 2] * g[:, 2])
                    if jd < last:
                        Rj = _axis_rotations(a, angles[:, m] - float(km.drive_phi0[jd]))
                        D = Rj if D is None else D @ Rj

    def results(self, **kw):
        from ..results import LineResults, Results, VesselResults
        nt = self.k
        lines = {}
        for li in self.system.model.lines:
            d = self.line_data[li.name]
            lines[li.name] = LineResults(name=li.name, arc_length=li.point_arc_length,
                                         sde_arc_length=li.sde_arc_length,
                                         **{name: arr[:nt] for name, arr in d.items()})
        for ji in getattr(self.system.model, "joins", []):
            lines[ji.child].drive_names = tuple(ji.drive_names)
        vessels = {name: VesselResults(name=name, position=self.vessel_pos[:nt, j], rotation=self.vessel_rot[:nt, j])
                   for j, name in enumerate(self.vessel_names)}
        from ..results import SupportResults, TensionerResults
        tensioners = {ti.name: TensionerResults(name=ti.name, line=ti.line, payout=self.tens_payout[:nt, ti.index].copy(),
                                                grip_force=self.tens_force[:nt, ti.index].copy())
                      for ti in self.system.model.tensioners}
        reels = {ri.name: TensionerResults(name=ri.name, line=ri.line, payout=self.reel_payout[:nt, ri.index].copy(),
                                           grip_force=self.reel_force[:nt, ri.index].copy())
                 for ri in getattr(self.system.model, "reels", [])}
        supports = {si.name: SupportResults(name=si.name, line=si.line, attach=si.attach,
                                            roller_position=si.position, roller_axis=si.axis,
                                            roller_reaction=self.roller_reaction[:nt, si.roller_start:si.roller_stop],
                                            roller_force=self.roller_force[:nt, si.roller_start:si.roller_stop])
                    for si in self.system.model.supports}
        from ..results import BodyResults
        bodies = {b.name: BodyResults(name=b.name, line=b.line,
                                      **{ch: arr[:nt] for ch, arr in self.body_data[b.name].items()})
                  for b in self.system.model.bodies}
        from ..results import WinchResults
        winches = {c.name: WinchResults(name=c.name, line=c.info.line,
                                        **{ch: arr[:nt].copy() for ch, arr in self.winch_data[c.name].items()})
                   for c in getattr(self.system, "controllers", ())}
        from ..results import TuggerResults
        tuggers = {ti.name: TuggerResults(name=ti.name, body=ti.body, vessel=ti.vessel, line=ti.line, at=ti.at,
                                          tension=self.tug_tension[:nt, ti.index].copy(),
                                          length=self.tug_length[:nt, ti.index].copy(),
                                          force=self.tug_force[:nt, ti.index].copy())
                   for ti in getattr(self.system.model, "tuggers", [])}
        return Results(time=self.time[:nt].copy(), lines=lines, vessels=vessels, supports=supports, bodies=bodies,
                       tensioners=tensioners, reels=reels, winches=winches, tuggers=tuggers,
                       **kw)


def _zyx_degrees(R: np.ndarray) -> np.ndarray:
    """(phi, theta, psi) in degrees of each R (m, 3, 3) = Rz(psi) Ry(theta) Rx(phi):
    rotation_to_zyx over many rotations, in the order the results store them."""
    out = np.empty((R.shape[0], 3))
    out[:, 0] = np.degrees(np.arctan2(R[:, 2, 1], R[:, 2, 2]))
    out[:, 1] = np.degrees(-np.arcsin(np.clip(R[:, 2, 0], -1.0, 1.0)))
    out[:, 2] = np.degrees(np.arctan2(R[:, 1, 0], R[:, 0, 0]))
    return out


def _axis_rotations(axis: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """rfesim.model.joins.axis_rotation(axis, angle) for each angle: (m, 3, 3)."""
    x, y, z = float(axis[0]), float(axis[1]), float(axis[2])
    s, c1 = np.sin(angles), 1.0 - np.cos(angles)
    out = np.empty((angles.shape[0], 3, 3))
    out[:, 0, 0] = 1.0 - c1 * (y * y + z * z)
    out[:, 0, 1] = c1 * x * y - s * z
    out[:, 0, 2] = c1 * x * z + s * y
    out[:, 1, 0] = c1 * x * y + s * z
    out[:, 1, 1] = 1.0 - c1 * (x * x + z * z)
    out[:, 1, 2] = c1 * y * z - s * x
    out[:, 2, 0] = c1 * x * z - s * y
    out[:, 2, 1] = c1 * y * z + s * x
    out[:, 2, 2] = 1.0 - c1 * (x * x + y * y)
    return out


def _seabed_tilt(km, r, t):
    """n . t: the RFE axis t against the seabed normal n under its centre r (positive when
    its A side is the lower, the side in contact; rfesim.loads.seabed.seabed_forces)."""
    g = np.zeros(3)
    seabed_height(km.bed_s, km.bed_z, km.bed_dir, float(r[0]), float(r[1]), g)
    return float(t[2] - g[1] * t[0] - g[2] * t[1])


def touchdown(km, ws, li):
    """(arc length from end A, position) of the touchdown point of a line: going from its
    upper end (end B, or end A when that is higher) towards the other, the end of the first
    RFE in seabed contact where its contact begins
    (the contact of an RFE is a contiguous part of it, so its length places the point; an
    RFE lifting off that the seabed no longer pushes has no contact length,
    rfesim.loads.seabed)."""
    lengths = km.rfe_length[li.rfe_start:li.rfe_stop]
    contact = ws.contact_length[li.rfe_start:li.rfe_stop]
    idx = np.nonzero(contact > 0.0)[0]
    if idx.size == 0:
        return None
    # a line hanging from end A (a pipe laid from a vessel) is searched from end A
    from_a = ws.r[li.rfe_start, 2] > ws.r[li.rfe_stop - 1, 2]
    j = int(idx[0]) if from_a else int(idx[-1])
    i = li.rfe_start + j
    s_lo = float(np.sum(lengths[:j]))
    L = lengths[j]
    lc = min(float(contact[j]), L)
    # the contact part of an RFE starts at its lower end: from the A-side end when that is
    # lower (touchdown lc along the RFE), else it reaches the B-side end (mirrored from A)
    # ("lower" against the seabed plane under its centre: on an upslope the B side of the
    # touchdown RFE is the one in contact although it is the higher end)
    t = ws.R[i, :, 0]
    dt = _seabed_tilt(km, ws.r[i], t)
    if from_a:
        off = (0.5 * L - lc) if (dt < 0.0 and lc < L) else -0.5 * L
    else:
        off = (lc - 0.5 * L) if (dt > 0.0 and lc < L) else 0.5 * L
    s = s_lo + 0.5 * L + off
    return s, ws.r[i] + off * t


class Counters(dict):
    def add(self, stats: np.ndarray, names=("steps", "newton_iterations", "jacobians", "rebases")):
        for k, name in enumerate(names):
            self[name] = self.get(name, 0) + int(stats[k])


def _raise(system: System, fail: np.ndarray, status: int, make_results, what: str = "", hint: str | None = None,
           quantity: str | None = None):
    t = float(fail[0])
    elem = int(fail[1])
    if elem < 0 and int(fail[2]) == Q_NEWTON:
        elem = _largest_residual(system)
    where = system.model.describe_rfe(elem) if elem >= 0 else None
    quantity = quantity or QUANTITY.get(int(fail[2]), "failure")
    if int(fail[2]) == Q_NEWTON:
        hint = _slack_hint(system) or (NEWTON_HINT if elem >= 0 else None)
    elif int(fail[2]) == Q_THROUGH:
        hint = THROUGH_HINT + (f"; {hint}" if hint else "")
    res = make_results(status=1, message=f"{what}{quantity} at t = {t:.6g} s" + (f" in {where}" if where else "")
                       + (f"; {hint}" if hint else ""))
    # SolverError adds the time, the place and "(quantity)" to the message: the quantity once
    raise SolverError("the run diverged", time=t, element=where, quantity=quantity, results=res, hint=hint)


NEWTON_HINT = ("the element named is where the last iterate's residual was largest. The step's Newton "
               "iteration failed at the step and in its substeps: something there changes faster than the "
               "step resolves (a shock, a drive or motion table too steep for the structure, a contact or a "
               "prescribed end pulling the line far from its shape), or elements too long or too few for "
               "their loads; check the scenario's warnings, shorten analysis.dynamics.integrator.time_step "
               "or lower analysis.dynamics.integrator.rho_inf (e.g. 0.5)")


def _largest_residual(system: System) -> int:
    """The RFE with the largest residual (moments over the RFE length) in the implicit step's
    residual buffer (the last Newton iterate of the failed step), -1 if it holds none."""
    r = np.abs(np.asarray(system.r, float)).copy()
    if r.shape[0] == 0 or not np.any(r):
        return -1
    r[:, 3:] /= np.maximum(system.length_scale, 1e-12)[:, None]
    r[~system.mask] = 0.0
    r[~np.isfinite(r)] = np.inf
    return int(np.argmax(r.max(axis=1)))


THROUGH_HINT = ("a slack rope carries no compression until its elements overlap by half their length, where "
                "their axial contact stops them; a payload or an element driven into it harder than that "
                "passes through it, and the rope then comes apart with no tension (the run "
                "stops there; generalized-alpha first retries the step in substeps down to 1/64). It happens to a light "
                "payload on a stiff crane whipped by a drive, or to a rope with no damping: damp the rope "
                "(cranes.<name>.rope.damping_ratio for a crane's rope, else line_types.<type>.damping.axial_ratio, "
                "e.g. 0.05), lower analysis.dynamics.integrator.rho_inf (e.g. 0.5), "
                "shorten the time step, or slow the drive")


def _slack_hint(system: System) -> str | None:
    """For a Newton failure: the ropes with slack elements at the last iterate (ws holds its
    evaluation) and what helps. A rope snatched taut again after going slack is a shock that
    a dead stop of a drive or a winch gives for real; Newton then cycles between the taut and
    slack states of its elements (docs/theory.md, 'Slack ropes and Newton')."""
    km, ws, model = system.km, system.ws, system.model
    if not km.has_tension_only:
        return None
    slack = []
    for li in model.lines:
        rows = np.arange(li.sde_start, li.sde_stop)
        rope = rows[km.sde_tension_only[rows] == 1]
        if rope.size == 0:
            continue
        n_slack = int(np.count_nonzero(ws.sigma[rope, 0] <= 0.0))
        if n_slack:
            slack.append(f"'{li.name}' {n_slack} of {rope.size}")
    if not slack:
        return None
    return ("slack rope elements at the last iterate: " + ", ".join(slack)
            + ". A rope snatched taut after going slack is a shock (a drive or winch table that stops "
              "dead gives one); give tables that start and stop smoothly, or damp the rope's ringing "
              "numerically: a lower analysis.dynamics.integrator.rho_inf (e.g. 0.5) at a step of 0.025-0.05 s. "
              "A rope hauled in far keeps its element count on a shorter length: its elements grow stiff "
              "(EA / length) and a shorter analysis.dynamics.integrator.time_step, or fewer rope elements, "
              "helps (a 20 m, 20-element rope hauled in 18 m at 2 m/s ran at 0.002 s or on 5 elements, not at "
              "0.01 s)")


def _check_motor_rates(km, out_dt: float) -> None:
    """A servo motor's joint is rebased between output intervals (rfesim.model.joins.
    rebase_motors): it must turn less than 90 deg within one interval (its set angle's
    rate, bounded by 3x the steepest secant of its table, times the interval)."""
    for j in range(km.motor_sde.shape[0]):
        c = int(km.motor_count[j])
        t, a = km.motor_t[j, :c], km.motor_angle[j, :c]
        rate = 3.0 * float(np.max(np.abs(np.diff(a) / np.diff(t)))) if c > 1 else 0.0
        if rate * out_dt >= 0.5 * math.pi:
            raise ScenarioError([("analysis.dynamics.output_interval",
                                  f"{out_dt:g} s is too long for a servo motor turning up to "
                                  f"{math.degrees(rate):.4g} deg/s: its joint is rebased between outputs and must "
                                  f"turn less than 90 deg in one (give at most {0.5 * math.pi / rate:.3g} s)")])


def energy_inputs(system: System) -> list[str]:
    """What puts energy into a scene, or takes it out through a term that
    ``rfesim.model.energy.mechanical_energy`` does not count (rfesim.api.describe_model lists
    a scene's terms): an empty list for a closed scene - gravity, elastic and tension-only
    SDEs (damped or not, joins and closing joins), rigid bodies and constant dead point
    forces on fixed or pinned supports - whose energy no integrator may raise."""
    km, model = system.km, system.model
    out = [name for flag, name in (
        ("has_water", "water"), ("has_sea", "waves / current"), ("has_morison", "Morison loads"),
        ("has_seabed", "seabed"), ("has_rollers", "rollers"), ("has_tensioners", "tensioners"),
        ("has_reels", "reels"), ("has_plastic", "elasto-plastic SDEs"), ("has_deck", "deck contact"),
        ("has_tuggers", "tugger lines"), ("has_reeving", "reeving"), ("has_drives", "drives"),
        ("has_motors", "servo motors")) if bool(getattr(km, flag, False))]
    if getattr(model, "winches", None) or getattr(system, "controllers", None):
        out.append("winches")
    if model.has_moving_attachments:
        out.append("moving vessels")
    if km.load_rfe.shape[0] and ((km.load_local != 0).any() or (km.load_moment != 0.0).any()):
        out.append("follower loads or moments")
    return out


# growth of the mechanical energy over its scale (EnergyCheck) reported in the results' message,
# and that stops the run as diverged. Measured: the rope snap of audit F1 stays within 3e-5
# through its physical phase, then blows up (1 % at 0.147 s, 12 % at 0.174 s, 28 % at 0.177 s,
# 88 % at 0.24 s with the tension at MN); legitimate closed runs of the tests reach 4.5 %
# (the nearly rigid portal at rho_inf 1, tests/validation/test_closing_joins.py), 3.6 % (a rod
# looping over its pin at rho_inf 1 for 100 s), 0.4 % (the hinged bar), 1.6e-4 (bench B9):
# a stop at 25 % is 5.6 times the worst of them, a warning at 10 % twice it.
ENERGY_WARN = 0.10
ENERGY_STOP = 0.25
ENERGY_HINT = ("damp the ropes and lines (line_types.<type>.damping.axial_ratio, or cranes.<name>.rope.damping_ratio "
               "or pipelay.<name>.pipe.damping_ratio, e.g. 0.05), lower "
               "analysis.dynamics.integrator.rho_inf (e.g. 0.5) or shorten the time step")


class EnergyCheck:
    """Growth of the mechanical energy of a closed scene (``energy_inputs`` empty), checked
    at output times: generalized-alpha with rho_inf <= 1 cannot create energy, nor may a
    stable RK step, so energy E(t) - E(0) growing past a fraction of the scene's energy
    scale is a numerical blow-up (docs/theory.md, section 3). The scale is frame-free: the
    largest kinetic + elastic energy seen plus the range of the gravity potential (and the
    dead loads' work) seen; a round-off floor of 1e-9 of the absolute potential (sum of
    |m g z| and |F . x|) keeps a scene at rest from tripping it."""

    def __init__(self, system: System, state: State):
        from ..model.energy import mechanical_energy
        self.energy = mechanical_energy
        self.system = system
        self.on = not energy_inputs(system)
        self.worst = 0.0            # largest growth / (scale + floor) seen
        self.worst_t = 0.0
        self.worst_dE = 0.0
        self.worst_scale = 0.0
        self.history = []           # (t, E - E0, scale, floor) at each check
        if not self.on:
            return
        e = mechanical_energy(system, state)
        self.e0 = e.total
        self.kin_el = e.kinetic + e.elastic
        self.pot_lo = self.pot_hi = e.gravity + e.work
        ws, km = system.ws, system.km
        self.floor = 1e-9 * (abs(km.gravity) * float((km.rfe_mass * np.abs(ws.r[:, 2])).sum())
                             + abs(e.work) + 1e-3 * e.kinetic + 1e-3 * e.elastic) + 1e-12

    def __call__(self, state: State) -> bool:
        """Check the state (an output time); True when the growth is past ENERGY_STOP."""
        if not self.on:
            return False
        e = self.energy(self.system, state)
        pot = e.gravity + e.work
        self.kin_el = max(self.kin_el, e.kinetic + e.elastic)
        self.pot_lo, self.pot_hi = min(self.pot_lo, pot), max(self.pot_hi, pot)
        scale = self.kin_el + (self.pot_hi - self.pot_lo)
        growth = e.total - self.e0
        if not math.isfinite(growth):
            growth, ratio = math.inf, math.inf
        else:
            ratio = max(0.0, growth - self.floor) / max(scale, self.floor)
        self.history.append((float(state.t), growth, scale, self.floor))
        if ratio > self.worst:
            self.worst, self.worst_t, self.worst_dE, self.worst_scale = ratio, float(state.t), growth, scale
        return ratio > ENERGY_STOP

    def where(self) -> str | None:
        """The RFE with the largest kinetic energy at the state last checked (ws holds its
        evaluation): where a blow-up shows first."""
        km, ws = self.system.km, self.system.ws
        kin = km.rfe_mass * (ws.v ** 2).sum(axis=1) + (km.rfe_inertia * ws.wb ** 2).sum(axis=1)
        kin[km.rfe_kind == 2] = 0.0
        kin[~np.isfinite(kin)] = np.inf
        return self.system.model.describe_rfe(int(np.argmax(kin))) if kin.size else None

    def describe(self) -> str:
        return (f"the mechanical energy of this closed scene (no waves, current, vessels, drives, winches or "
                f"payout) grew by {self.worst_dE:.4g} J by t = {self.worst_t:.6g} s, {100 * self.worst:.3g} % of "
                f"its scale {self.worst_scale:.4g} J (the largest kinetic + elastic energy plus the range of the "
                f"gravity potential seen), where an exact solve keeps it or loses it to damping: numerical error "
                f"(generalized-alpha with rho_inf <= 1 and a stable RK step create no energy) - {ENERGY_HINT}")

    def warning(self) -> str | None:
        return self.describe() if self.on and self.worst > ENERGY_WARN else None


class _Recover(Exception):
    """A generalized-alpha step failed in every substep (Newton) and ``Recovery`` can go back."""

    def __init__(self, time: float):
        super().__init__(time)
        self.time = time


class Recovery:
    """Going back past a failure of generalized-alpha (docs/theory.md, "Going back past a
    failure"): a step whose Newton iteration fails even in 64 substeps is often one the run
    reached in a state its step could not resolve (a slack rope snatched taut among ringing
    elements); a whole run at half the step passes it. So at output times CHECKPOINT_SPACING
    apart (at every output, for longer output intervals; between the chunks of outputs of the
    compiled recording, which grow to about 0.1 s of wall time) the run keeps a checkpoint (the
    state, the committed history, every model and workspace array, the winch controllers, the
    recorder's row, the energy check), and on such a failure it goes back to the newest
    checkpoint at least REWIND before it and takes the stretch at half the step, up to
    RECOVERY_SPAN past the failure, then returns to its step; a failure within that stretch
    halves the step again, down to time_step / 2^halvings
    (``analysis.dynamics.integrator.recovery_halvings``; 0: off, the run stops at the failure
    as before). The outputs keep their times; those between the checkpoint and the end of the
    stretch come from the finer step, and the results' message says where (``warnings``)."""

    CHECKPOINT_SPACING = 2.0    # s simulated between checkpoints (at least one output interval)
    REWIND = 0.5                # s: the checkpoint gone back to lies at least this before the failure
    RECOVERY_SPAN = 2.0         # s past the failure taken at the finer step
    KEEP = 4                    # checkpoints kept

    def __init__(self, system, recorder, energy, halvings: int, h: float, out_dt: float):
        self.system, self.recorder, self.energy = system, recorder, energy
        self.halvings = max(0, int(halvings))
        self.on = self.halvings > 0
        self.h = h
        self.out_dt = out_dt
        self.level = 0
        self.fine_until = -math.inf
        self.checkpoints = []
        self.events = []            # (t of the failure, t gone back to, the finer step)
        self.last = -math.inf
        self.span = self.RECOVERY_SPAN  # the stretch past a failure taken at the finer step
        self.stretch_end = -math.inf    # when the run last returned to its own step
        self.longest = self.span

    def due(self, t: float) -> bool:
        """A checkpoint at outputs CHECKPOINT_SPACING apart, and where a stretch at the finer
        step ends (its state came from that step: a failure soon after may go back to it)."""
        if self.level and t >= self.fine_until - 1e-9 * self.h:
            return True
        return t - self.last >= self.CHECKPOINT_SPACING - 1e-9 * max(1.0, abs(t)) or not self.checkpoints

    def checkpoint(self, st, k_out: int, qdd_prev) -> None:
        system = self.system
        km, ws = system.km, system.ws
        arrays = [(a, a.copy()) for a in (*(getattr(km, f) for f in km._fields), *(getattr(ws, f) for f in ws._fields),
                                         system.length_scale, qdd_prev) if isinstance(a, np.ndarray)]
        energy = dict(vars(self.energy))
        energy["history"] = list(energy.get("history", []))
        self.checkpoints.append({"t": float(st.t), "k_out": k_out, "state": st.copy(), "history": system.history(),
                                 "controllers": [c.save() for c in (getattr(system, "controllers", None) or ())],
                                 "rec_k": self.recorder.k, "arrays": arrays, "energy": energy,
                                 "fine": bool(self.level) and st.t >= self.fine_until - 1e-9 * self.h})
        del self.checkpoints[:-self.KEEP]
        self.last = float(st.t)

    def can_recover(self) -> bool:
        return self.on and self.level < self.halvings and bool(self.checkpoints)

    def rewind(self, t_fail: float, qdd_prev):
        """Restore the checkpoint to go back to; returns (state, k_out) and halves the step."""
        system = self.system
        # the newest checkpoint at least REWIND before the failure, or one taken where a stretch
        # at the finer step ended (its state is that step's, not one the run's own step reached)
        usable = [c for c in self.checkpoints if c["t"] <= t_fail - self.REWIND or (c["fine"] and c["t"] < t_fail)] \
            or self.checkpoints[:1]
        ck = usable[-1]
        if not self.level:
            # failing again within a stretch's length of the last one's end: the run's own step
            # does not pass this part of the run; each such failure doubles the stretch
            self.span = 2.0 * self.span if t_fail - self.stretch_end < self.RECOVERY_SPAN else self.RECOVERY_SPAN
            self.longest = max(self.longest, self.span)
        self.checkpoints = [c for c in self.checkpoints if c["t"] <= ck["t"]]
        for a, saved in ck["arrays"]:
            a[...] = saved
        system.set_history(ck["history"])
        for c, saved in zip(getattr(system, "controllers", None) or (), ck["controllers"]):
            c.restore(saved)
        self.recorder.k = ck["rec_k"]
        self.energy.__dict__.update(ck["energy"])
        self.energy.history = list(ck["energy"].get("history", []))
        self.level += 1
        self.fine_until = max(self.fine_until, t_fail + self.span)
        self.events.append((t_fail, ck["t"], self.h / 2 ** self.level))
        self.last = ck["t"]
        log.info("dynamics: Newton failed at t = %.6g s; going back to t = %.6g s at a step of %.3g s",
                 t_fail, ck["t"], self.h / 2 ** self.level)
        return ck["state"].copy(), ck["k_out"]

    def back_to_nominal(self, t: float) -> float:
        """The stretch is passed: the run's own step again."""
        self.level = 0
        self.fine_until = -math.inf
        self.stretch_end = t
        return self.h

    def warnings(self) -> list[str]:
        if not self.events:
            return []
        first = self.events[0]
        finest = min(e[2] for e in self.events)
        rec = self.recorder
        end = first[0] + self.RECOVERY_SPAN
        if rec.k:
            end = min(end, float(rec.time[rec.k - 1]))       # the run may end within the stretch
        more = (f"; {len(self.events)} such recoveries in all, at t = "
                + ", ".join(f"{e[0]:.6g}" for e in self.events[:10]) + (" ..." if len(self.events) > 10 else "")
                + " s") if len(self.events) > 1 else ""
        doubled = (f"; failing again within {self.RECOVERY_SPAN:g} s of a stretch's end, the next stretch was "
                   f"taken twice as long, up to {self.longest:.6g} s" if self.longest > self.RECOVERY_SPAN else "")
        return [f"Newton failed at t = {first[0]:.6g} s at the time step {self.h:.4g} s even in 64 substeps (a slack "
                f"rope snatched taut, or another shock the step does not resolve); the run went back to t = "
                f"{first[1]:.6g} s and took the stretch to {end:.6g} s at {first[2]:.4g} s "
                f"steps, then went on at its own step{more} (finest step {finest:.4g} s){doubled}: the outputs there come "
                f"from the finer step (analysis.dynamics.integrator.recovery_halvings: 0 stops at the failure "
                f"instead)"]


def halving_warning(counters: dict, duration: float) -> str | None:
    """More than a tenth of the generalized-alpha steps taken in substeps (Newton failed at
    the full step): the step is too long for what the scene does."""
    h = float(counters.get("time_step") or 0.0)
    n = int(round(duration / h)) if h > 0.0 else 0
    # a run that went back past a failure (Recovery) took the stretches it went back over again
    n += int(counters.get("recovery_steps", 0))
    halved = int(counters.get("step_halvings", 0))
    if n <= 0 or halved <= 0.1 * n:
        return None
    return (f"{halved} of the {n} time steps ({100.0 * halved / n:.3g} %) failed Newton's iteration at the full step "
            f"and were retried in substeps: the results may be inaccurate - shorten "
            f"analysis.dynamics.integrator.time_step, damp the lines or lower analysis.dynamics.integrator.rho_inf")


def _whole_intervals(T: float, dt: float) -> int:
    """Number of intervals dt that cover the duration T (at least one for T > 0), the last
    one ending at or after T; a quotient within rounding of a whole number counts as whole."""
    if T <= 0.0:
        return 0
    x = T / dt
    return max(1, int(math.ceil(x - 1e-9 * max(1.0, x))))


def output_size(system: System, nt: int) -> float:
    """Bytes of the result arrays of nt output times (an estimate from above: every SDE and
    RFE channel of the Recorder, in float64)."""
    model = system.model
    nl = max(1, len(model.lines))
    npts = sum(li.elements + 2 for li in model.lines)
    per_time = 11 * model.nsde + 7 * model.n + 3 * npts + 40 * nl + 6 * len(model.scenario.vessels) + 16
    return 8.0 * per_time * nt


def _memory_bytes() -> float:
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):     # pragma: no cover - not a POSIX system
        return math.inf


def _check_output_size(system: System, nt: int) -> None:
    """A clear error, before anything is allocated, when the results would take more than
    half of this machine's memory."""
    need = output_size(system, nt)
    have = _memory_bytes()
    if need > 0.5 * have:
        raise ScenarioError([("analysis.dynamics.output_interval",
                              f"{nt:.4g} output times would store about {need / 2**30:.3g} GiB of results, more than "
                              f"half of this machine's memory ({have / 2**30:.3g} GiB): give a longer output "
                              f"interval or a shorter duration")])


def hydrostatic_pressures(z, z_top, gravity: float, water_density: float, water_level: float,
                          contents_density: float):
    """(p_ext, p_int) Pa at heights z (docs/theory.md, "Stresses"): p_ext = rho_w g (surface
    level - z) below the still-water surface, else 0 (no wave pressure; rho_w 0: no water);
    p_int = rho_c g (z_top - z), the contents at rest and open at the line's highest point
    z_top (0 for an empty pipe). Shared by the von Mises channel and lay_summary's axial strain."""
    z = np.asarray(z, float)
    p_ext = np.zeros_like(z)
    if water_density > 0.0:
        p_ext = water_density * gravity * np.maximum(water_level - z, 0.0)
    p_int = np.zeros_like(z)
    if contents_density > 0.0:
        p_int = contents_density * gravity * (z_top - z)
    return p_ext, p_int


def output_interval_warning(T: float, out_dt: float) -> str | None:
    """The warning of a duration that is not a whole number of output intervals (the run
    goes on to the next output time), or None."""
    n_out = _whole_intervals(T, out_dt)
    if n_out * out_dt > T * (1.0 + 1e-9):
        return (f"analysis.dynamics.duration ({T:g} s) is not a whole number of output intervals ({out_dt:g} s): "
                f"the run goes on to the next output time, t = {n_out * out_dt:g} s")
    return None


def output_schedule(T: float, h: float, output_interval: float | None, adaptive: bool = False):
    """(output interval, number of output intervals, time step) of a run of duration T.

    The last output is at the duration or, for an output interval that does not divide it,
    at the next output time after it (the run covers the whole duration, and says so in a
    warning). Without an output interval: every step, or every few steps of a long run (at
    most about 10000 outputs; duration/1000 for the adaptive integrator), adjusted to divide
    the duration. A fixed step is then shortened, never lengthened, to divide the output
    interval, so outputs land exactly on their times (a step longer than the duration
    becomes the duration)."""
    if output_interval is not None:
        out_dt = float(output_interval)
        n_out = _whole_intervals(T, out_dt)
        note = output_interval_warning(T, out_dt)
        if note:
            log.warning("%s", note)
    else:
        out_dt = T / 1000.0 if adaptive else h * max(1, math.ceil(T / h / 10000.0))
        n_out = _whole_intervals(T, out_dt)
        if n_out:
            out_dt = T / n_out
    if not adaptive:
        per_out = max(1, int(math.ceil(out_dt / h - 1e-9)))
        h = out_dt / per_out
    return out_dt, n_out, h


INTERRUPTED = 2    # Results.status of a run stopped by KeyboardInterrupt (Ctrl-C, or SIGTERM from the command line)
CANCELLED = 3      # Results.status of a run its progress callback stopped (CancelledError: the service's cancel)


def cancelled(exc: Exception, t: float, make_results=None) -> CancelledError:
    """The CancelledError of a run its progress callback stopped (``exc``: what the callback
    raised, or the CancelledError made of it) at the last output time ``t``, with
    ``make_results(status=, message=)`` -> the Results recorded so far (None: nothing recorded)."""
    message = f"cancelled at t = {t:.6g} s"
    reason = str(exc)
    results = make_results(status=CANCELLED, message=message) if make_results is not None else None
    return CancelledError(f"{message}: {reason}" if reason and reason != message else message, time=t,
                          results=results)


ARITHMETIC_HINT = ("a mass, inertia, density, stiffness or size far from the physical (near zero, or huge) makes "
                   "the equations divide by zero or overflow: check the scenario's values and their units")


def _arithmetic_failure(exc: ArithmeticError, t: float, make_results) -> SolverError:
    """The SolverError of an ArithmeticError (ZeroDivisionError, OverflowError,
    FloatingPointError) raised inside the kernels, with the results so far."""
    msg = f"arithmetic error in the solver ({type(exc).__name__}: {exc})"
    return SolverError(msg, time=t, quantity="arithmetic error", hint=ARITHMETIC_HINT,
                       results=make_results(status=1, message=f"{msg} at t = {t:.6g} s; {ARITHMETIC_HINT}"))


def _end_a_point(km, ws, i: int) -> np.ndarray:
    """End A of RFE i (its centre less half its length along its axis) in the evaluated workspace."""
    return ws.r[i] - 0.5 * float(km.rfe_length[i]) * ws.R[i][:, 0]


def _track_xi(km, att, ws, j: int) -> tuple[float, float, float]:
    """(xi of end A of tensioner j's line, xi of that RFE's centre, the centre's distance
    from the axis): along the track's axis from its entry (rfesim.loads.tensioner), in the
    evaluated workspace."""
    a = int(km.tens_att[j])
    R = att.R[a]
    P = att.p[a] + R @ km.tens_point[j]
    e = R @ km.tens_axis[j]
    i = int(km.tens_line_lo[j])
    d = ws.r[i] - P
    xi = float(e @ d)
    return float(e @ (_end_a_point(km, ws, i) - P)), xi, float(np.linalg.norm(d - xi * e))


def _wrap_phi(km, att, ws, j: int) -> float:
    """Wrap angle (rad) of end A of reel j's line on the drum (rfesim.loads.reel: 0 at the
    take-off, growing against the payout; negative past the take-off)."""
    a = int(km.reel_att[j])
    R = att.R[a]
    C = att.p[a] + R @ km.reel_centre[j]
    ax = R @ km.reel_axis[j]
    d = R @ km.reel_dir[j]
    n0 = np.cross(ax, d)
    p = _end_a_point(km, ws, int(km.reel_line_lo[j])) - C
    p = p - (p @ ax) * ax
    phi = math.atan2(-(p @ d), p @ n0)
    return phi + 2.0 * math.pi if phi < -0.5 * math.pi else phi


def _tensioner_payout(km, ws, j: int, t: float) -> float:
    """Paid-out length of tensioner j at time t (m): its table's, or the driven value."""
    from ..loads.tensioner import tensioner_payout
    return float(tensioner_payout(km.tens_mode, km.tens_table_t, km.tens_table_d, km.tens_table_v, km.tens_count,
                                  j, t, ws.tens_D))


def _pays_out(km, j: int) -> bool:
    """Tensioner j can pay its line out: driven (constant tension), or a table reaching past 0."""
    if int(km.tens_mode[j]) == 1:
        return True
    c = max(1, int(km.tens_count[j]))
    return bool((km.tens_table_d[j, :c] > km.tens_table_d[j, 0]).any())


def payout_ends(system: System, t: float = 0.0) -> list[tuple]:
    """The tensioners that pay out (driven by constant tension, or by a table that reaches
    beyond its first row) and the driven reels, and what of their line they hold at the
    start (time t), from the evaluated workspace: (kind, j, name, line, D0, held) with held
    the pipe from end A up to the track's exit (m; end A upstream of the exit) or the pipe
    stored on the drum (m, R times end A's wrap angle). Those whose line's end A is not
    upstream of the exit, lies beside the track (between its entry and exit planes but off
    its axis: a reel-lay line's end A on the drum), or is not on the drum, are left out."""
    from ..loads.tensioner import TRACK_CAPTURE
    km, ws, att, model = system.km, system.ws, system.att, system.model
    out = []
    if km.has_tensioners:
        for ti in model.tensioners:
            j = ti.index
            if not _pays_out(km, j):
                continue
            xi_end, xi_centre, lateral = _track_xi(km, att, ws, j)
            L = float(km.tens_length[j])
            if xi_centre < 0.0 or (xi_centre < L and lateral <= TRACK_CAPTURE):
                out.append(("tensioner", j, ti.name, ti.line, _tensioner_payout(km, ws, j, t), L - xi_end))
    if km.has_reels:
        for ri in model.reels:
            j = ri.index
            if int(km.reel_mode[j]) != 1:
                continue
            phi = _wrap_phi(km, att, ws, j)
            if phi > 0.0:
                out.append(("reel", j, ri.name, ri.line, float(ws.reel_D[j]), float(km.reel_radius[j]) * phi))
    return out


def payout_beyond(system: System, ends: list[tuple], t: float = 0.0) -> str:
    """A message when a tensioner that pays out (driven, or by a table) has run end A of its
    line out of its track (the end-A RFE's centre past the exit: the track holds none of the
    line), or a driven reel has paid out more than it held or let end A off the drum, from
    the evaluated workspace at time t; else ''. The pipe's end would leave and the line drop
    (or fly off under its pull): the run stops there. A table reaching beyond the line held
    at the start is refused before the run (rfesim.model.supports.table_payout_problems);
    this catches what statics' payout shift or the run's motion add."""
    km, ws, att = system.km, system.ws, system.att
    for kind, j, name, line, D0, held in ends:
        if kind == "tensioner":
            D = _tensioner_payout(km, ws, j, t) - D0
            xi_end, xi_centre, _ = _track_xi(km, att, ws, j)
            if xi_centre >= float(km.tens_length[j]):
                driven = int(km.tens_mode[j]) == 1
                how = "(constant tension)" if driven else f"(its payout table, by t = {t:.6g} s)"
                fix = (f"a set tension (supports.{name}.payout) the line's pull does not outrun" if driven else
                       f"a payout table (supports.{name}.payout) that pays out less")
                return (f"tensioner '{name}' ran end A of line '{line}' out of its track: it paid out {D:.6g} m "
                        f"{how} and held {held:.6g} m of the line from end A up to its exit at the "
                        f"start; the track holds none of it now and the line's end is free: start with more "
                        f"line upstream of the track (end A further back), or {fix}")
        else:
            D = float(ws.reel_D[j]) - D0
            phi = _wrap_phi(km, att, ws, j)
            if D > held or phi < 0.0:
                return (f"reel '{name}' ran empty: it paid out {D:.6g} m (constant tension) of the {held:.6g} m "
                        f"of line '{line}' stored on it at the start (supports.{name}.stored_length), and end A "
                        f"{'has left' if phi < 0.0 else 'is leaving'} the drum: store more line on the reel, or "
                        f"a set tension (supports.{name}.payout) the line's pull does not outrun")
    return ""


def run_dynamics(system: System, state: State, settings, progress=None, recorder: Recorder | None = None,
                 counters: Counters | None = None) -> tuple[State, Recorder, Counters]:
    """Integrate from state.t over settings.duration, recording at output times."""
    integ = settings.integrator
    T = float(settings.duration)
    t_start = state.t
    st = state.copy()
    counters = counters if counters is not None else Counters()
    wall0 = _time.perf_counter()
    km, vs, att, ws = system.km, system.vs, system.att, system.ws
    mask = system.mask
    n = system.n
    # initial true acceleration (friction: stick/slip from the anchors statics left, if any)
    system.set_friction_mode(0)
    try:
        st.qdd[:] = system.accelerations(st)
    except ArithmeticError as exc:
        # a division by zero in the kernels before the first step: the start state (statics')
        # goes with the SolverError, as the results so far do later (_arithmetic_failure)
        if recorder is None:
            recorder = Recorder(system, 1)
        if recorder.k < recorder.nt:
            recorder.record(st, st.qdd)
        counters["wall_time"] = _time.perf_counter() - wall0
        raise _arithmetic_failure(exc, st.t, lambda **kw: recorder.results(counters=dict(counters), **kw)) from exc
    system.commit_history()
    controllers = getattr(system, "controllers", None)
    for c in controllers or ():
        c.start(st)                 # winches: tension and sheave position at the start
    rk4_hint = None
    if integ.kind == "generalized-alpha":
        h = float(integ.time_step)
    elif integ.kind == "rk4":
        # the stability limit: 2.8 / the highest natural frequency, or 2.785 / the highest
        # damping rate (an overdamped mode's real eigenvalue) if shorter
        limit = stable_rk4_step(system, st, 1.0)
        h = float(integ.time_step) if integ.time_step else integ.safety * limit
        if integ.time_step:
            # an explicit step beyond the stability limit grows without bound: say so now, and
            # name the limit if the run then diverges
            if h > limit:
                rk4_hint = (f"the RK4 step {h:.3g} s is longer than its stability limit, about {limit:.3g} s "
                            f"(2.8 / the highest natural frequency, 2.785 / the highest damping rate): give "
                            f"analysis.dynamics.integrator.time_step below it, leave it out (the default is "
                            f"{integ.safety:g} x the limit) or use the implicit generalized-alpha")
                log.warning(rk4_hint)
    else:
        h = float(integ.first_step) if integ.first_step else min(stable_rk4_step(system, st, 0.5), T / 10 or 1.0)
    counters["time_step"] = h
    # output times
    out_dt, n_out, h = output_schedule(T, h, settings.output_interval, integ.kind == "adaptive")
    counters["time_step"] = h
    if integ.kind == "rk4" and not integ.time_step:
        # the default step diverging all the same: the estimate missed a mode (named if the run fails)
        rk4_hint = (f"the default RK4 step {h:.3g} s is within {integ.safety:g} x its estimated stability limit, "
                    f"about {limit:.3g} s (2.8 / the highest natural frequency, 2.785 / the highest damping "
                    f"rate), and still diverged: give analysis.dynamics.integrator.time_step well below it (or a "
                    f"lower analysis.dynamics.integrator.safety) or use the implicit generalized-alpha")
    if km.has_motors:
        _check_motor_rates(km, out_dt)
    if recorder is None:
        _check_output_size(system, n_out + 2)
        try:
            recorder = Recorder(system, n_out + 2)
        except MemoryError:
            raise ScenarioError([("analysis.dynamics.output_interval",
                                  f"{n_out + 2} output times do not fit in this machine's memory: give a longer "
                                  f"output interval or a shorter duration")]) from None
    if recorder.k == 0 or recorder.time[recorder.k - 1] < st.t:
        recorder.record(st, st.qdd)
    # tensioners that pay out and driven reels: what of their line they hold at the start (checked at every
    # output time: a payout that runs the line's end out stops the run, ``payout_beyond``;
    # such scenes are recorded in Python, Recorder.kernel_records, so every path passes output)
    ends = getattr(system, "payout_ends", None)
    if ends is None and ((km.has_tensioners and any(_pays_out(km, j) for j in range(km.tens_mode.shape[0]))) or
                         (km.has_reels and (km.reel_mode == 1).any())):
        system.evaluate(st)
        ends = system.payout_ends = payout_ends(system, st.t)
    stats = np.zeros(4, np.int64)
    fail = np.zeros(3)
    # closed scenes: the energy at the start, checked for growth at output times (EnergyCheck)
    energy = recorder.energy_check = EnergyCheck(system, st)

    def make_results(**kw):
        counters["wall_time"] = _time.perf_counter() - wall0
        return recorder.results(counters=dict(counters), **kw)

    def check_slip():
        """Stop with the results so far once a rope has slipped over its sheave past its first
        element (rfesim.loads.reeving: the sheave must stay on that element)."""
        msg = recorder.slip_beyond()
        if msg:
            raise SolverError(msg, time=st.t, quantity="rope slip over a sheave",
                              results=make_results(status=1, message=msg))

    def check_payout():
        """Stop with the results so far once a driven tensioner or reel has run its line's end
        out (``payout_beyond``; the workspace holds the evaluation of the recorded state)."""
        msg = payout_beyond(system, ends, st.t) if ends else ""
        if msg:
            raise SolverError(msg, time=st.t, quantity="payout beyond the line held",
                              results=make_results(status=1, message=msg))

    def check_energy(st):
        """Stop with the results so far once the energy of a closed scene has grown past
        ENERGY_STOP of its scale (EnergyCheck); the workspace is left evaluated at ``st``."""
        if energy.on and energy(st):
            hint = energy.describe() + (f"; {rk4_hint}" if rk4_hint else "")
            where = energy.where()
            msg = f"energy growth at t = {st.t:.6g} s" + (f" in {where}" if where else "") + f"; {hint}"
            raise SolverError("the run diverged", time=st.t, element=where, quantity="energy growth", hint=hint,
                              results=make_results(status=1, message=msg))

    def output(st) -> bool:
        """At an output time: record the state, stop on a rope slipped too far, a line run
        out of its tensioner or reel or the energy of a closed scene grown, rebase the servo
        motors' joints (True when one was: a factorised Jacobian is then stale), report progress."""
        recorder.record(st, st.qdd)
        check_slip()
        check_payout()
        rebased = bool(km.has_motors and rebase_motors(km, ws))
        check_energy(st)
        report(st.t)
        return rebased

    reported = [0.0]    # the fraction reported so far: a rewind (Recovery) runs over it again, and the
                        # fraction stays (a job's progress never goes back), the simulated time says where it is

    def report(t):
        if progress is not None:
            reported[0] = max(reported[0], min(1.0, (t - t_start) / T) if T > 0 else 1.0)
            try:
                progress(reported[0], t)
            except CancelledError:
                raise
            except Exception as exc:  # a callback that raises stops the run as cancelled
                raise CancelledError(str(exc)) from exc

    try:
        z = lambda *s: np.zeros(s)  # noqa: E731
        if integ.kind == "generalized-alpha":
            am, af, beta, gamma = genalpha_parameters(integ.rho_inf)
            force_ref = system.force_scale(st)
            # floored at the round-off of the stiffest SDE and at the resolution of the contact
            # springs' absolute positions (newton_tolerance)
            tol = newton_tolerance(system, st, integ.tolerance, force_ref)
            # the algorithmic acceleration starts at the true one in the modes the step
            # resolves and at zero in the stiff ones: left at zero, a start out of equilibrium
            # (no statics, a step load, waves with no ramp) cut the method to first order for
            # rho_inf < 1; at the true one, a stiff mode's start acceleration overshot into a
            # spurious velocity (docs/theory.md, 'Starting generalised-alpha')
            # (a state a run ended in goes on with its own: a run in parts, as the S-lay bench)
            if st.fresh:
                st.aux[:] = start_acceleration(system, st, h * h * beta * (1.0 - af) / (1.0 - am),
                                               h * gamma * (1.0 - af) / (1.0 - am), tol, force_ref)
            st.fresh = st.static = False
            flags = np.zeros(4, np.int64)   # kernels.ga_advance; [3]: a halved step (a third attempt)
            qdd_prev = st.qdd.copy()
            analytic = integ.jacobian == "analytic"
            from .fastcall import FastCall
            ga_call = FastCall(ga_advance)      # one call per output interval: skip numba's typing of ~50 arguments

            def one_step(trial, t0, hh):
                return ga_call(km, vs, att, ws, trial.q, trial.qd, trial.qdd, trial.aux, trial.ref, t0, hh, 1, am, af,
                               beta, gamma, tol, integ.max_iterations, integ.jacobian_reuse, mask, system.length_scale,
                               force_ref, system.J, system.Fac, system.Q0, system.V0, system.r, system.dq,
                               system.qd_buf, system.A_buf, system.qp, system.rp, system.hs, flags, stats, fail,
                               analytic, system.Ks, system.Kds, system.T, system.Fsde, system.Msde, qdd_prev)

            def redo(saved, saved_history, nsteps, status, h):
                """The output interval from ``saved`` again, step by step, halving a failing step
                down to h/64; the step that failed (Newton) starts at h/2: at h it was just given
                two attempts with fresh Jacobians, and a third one at h fails the same way."""
                j_failed = int(round((float(fail[0]) - saved.t) / h)) - 1 if status == 1 else -1
                st = saved
                system.set_history(saved_history)
                stats[:] = 0
                flags[0] = 0
                flags[2] = 0
                status = 0
                for j in range(nsteps):
                    t_step0 = saved.t + j * h
                    ok = False
                    step_history = system.history()
                    for level in range(1 if j == j_failed else 0, 7):
                        sub = 2 ** level
                        trial = st.copy()
                        system.set_history(step_history)
                        trial.t = t_step0
                        flags[0] = 0
                        flags[3] = 1 if level > 0 else 0
                        s2 = 0
                        for m in range(sub):
                            s2 = ga_call(km, vs, att, ws, trial.q, trial.qd, trial.qdd, trial.aux, trial.ref,
                                         t_step0 + m * h / sub, h / sub, 1, am, af, beta, gamma, tol,
                                         integ.max_iterations, integ.jacobian_reuse, mask, system.length_scale,
                                         force_ref, system.J, system.Fac, system.Q0, system.V0, system.r,
                                         system.dq, system.qd_buf, system.A_buf, system.qp, system.rp, system.hs,
                                         flags, stats, fail, analytic, system.Ks, system.Kds, system.T,
                                         system.Fsde, system.Msde, qdd_prev)
                            if s2 != 0:
                                break
                        if s2 == 0:
                            st = trial
                            ok = True
                            if level > 0:
                                counters["step_halvings"] = counters.get("step_halvings", 0) + 1
                                log.debug("dynamics: the step at t = %.6g s taken as %d substeps of %.3g s",
                                          t_step0, sub, h / sub)
                            break
                        status = s2
                    flags[0] = 0
                    flags[3] = 0
                    if not ok:
                        st.t = t_step0
                        counters.add(stats)
                        stats[:] = 0
                        interval_failed(status)
                    st.t = t_step0 + h
                return st

            recovery = recorder.recovery = Recovery(system, recorder, energy,
                                                    int(getattr(integ, "recovery_halvings", 0) or 0), h, out_dt)
            h_step = h                      # the step in use: h, or h / 2^level while a failure is passed

            def interval_failed(status):
                """A step that failed in every substep: go back and take the stretch at half the
                step (``Recovery``), or stop with the results so far."""
                if int(fail[2]) == Q_NEWTON and recovery.can_recover():
                    raise _Recover(float(fail[0]))
                _raise(system, fail, status, make_results)

            fast = recorder.kernel_records()
            if fast:
                from .recording import ga_run
                run_call = FastCall(ga_run)
                rec = recorder.kernel_arrays()
                save = (st.q.copy(), st.qd.copy(), st.qdd.copy(), st.aux.copy(), st.ref.R.copy(), st.ref.X.copy(),
                        stats.copy())
                hist = system.history()
                done = np.zeros(1, np.int64)
                per_out = int(round(out_dt / h))
            fast_allowed = fast
            k_out = 1
            chunk = 4
            while k_out <= n_out:
                try:
                    if recovery.on and recovery.due(st.t):
                        recovery.checkpoint(st, k_out, qdd_prev)
                    if recovery.level and st.t >= recovery.fine_until - 1e-9 * h:
                        h_step = recovery.back_to_nominal(st.t)
                        flags[0] = 0           # the factorised Jacobian belongs to the finer step
                        fast = fast_allowed
                    if fast:
                        # the compiled run records a chunk of output intervals (rfesim.solvers.recording);
                        # an interval that fails comes back rolled back, for the redo below
                        row0 = recorder.k
                        m = min(chunk, n_out - k_out + 1, recorder.nt - row0)
                        if m <= 0:
                            fast = False        # the recorder is full (a recorder handed in): Python from here
                        else:
                            tw = _time.perf_counter()
                            status = run_call(km, vs, att, ws, st.q, st.qd, st.qdd, st.aux, st.ref, t_start, out_dt,
                                              k_out, m, h, per_out, am, af, beta, gamma, tol, integ.max_iterations,
                                              integ.jacobian_reuse, mask, system.length_scale, force_ref, system.J,
                                              system.Fac, system.Q0, system.V0, system.r, system.dq, system.qd_buf,
                                              system.A_buf, system.qp, system.rp, system.hs, flags, stats, fail,
                                              analytic, system.Ks, system.Kds, system.T, system.Fsde, system.Msde,
                                              qdd_prev, save, hist, rec, row0, done)
                            nd = int(done[0])
                            recorder.finish_rows(row0, row0 + nd)
                            recorder.k = row0 + nd
                            k_out += nd
                            st.t = t_start + (k_out - 1) * out_dt
                            counters.add(stats)
                            stats[:] = 0
                            if status == 0:
                                # chunks of about a tenth of a second of wall time between progress reports
                                # (and cancellations): grown at most twofold a call, cut at once when the
                                # intervals get dearer
                                per = (_time.perf_counter() - tw) / max(nd, 1)
                                chunk = max(1, min(2 * chunk, 4096, int(0.1 / per) if per > 0.0 else 4096))
                                check_energy(st)        # at the chunk's last output time
                                report(st.t)
                                continue
                            # the failed interval (state, history and counters rolled back) is redone below
                            saved = st.copy()
                            saved_history = system.history()
                    t_target = t_start + k_out * out_dt
                    if controllers:
                        # winches: one step at a time with the controllers' hooks (rfesim.solvers.controlled)
                        from .controlled import advance_controlled
                        try:
                            st, status, t_fail = advance_controlled(system, st, t_target, h_step, one_step, flags,
                                                                    counters)
                        except SolverError as exc:
                            if exc.results is None:
                                counters.add(stats)
                                exc.results = make_results(status=1, message=str(exc))
                            raise
                        counters.add(stats)
                        stats[:] = 0
                        if status != 0:
                            interval_failed(status)
                        if output(st):
                            flags[0] = 0           # the factorised Jacobian belongs to the old rest rotation
                        k_out += 1
                        continue
                    nsteps = int(round((t_target - st.t) / h_step))
                    if not fast:
                        saved = st.copy()
                        saved_history = system.history()
                        status = ga_call(km, vs, att, ws, st.q, st.qd, st.qdd, st.aux, st.ref, st.t, h_step, nsteps,
                                         am, af, beta, gamma, tol, integ.max_iterations, integ.jacobian_reuse, mask,
                                         system.length_scale, force_ref, system.J, system.Fac, system.Q0, system.V0,
                                         system.r, system.dq, system.qd_buf, system.A_buf, system.qp, system.rp,
                                         system.hs, flags, stats, fail, analytic, system.Ks, system.Kds, system.T,
                                         system.Fsde, system.Msde, qdd_prev)
                    if status != 0:
                        st = redo(saved, saved_history, nsteps, status, h_step)
                    st.t = t_target
                    counters.add(stats)
                    stats[:] = 0
                    if output(st):
                        flags[0] = 0           # the factorised Jacobian belongs to the old rest rotation
                    k_out += 1
                except _Recover as failed:
                    # back to a checkpoint about a second before the failure, at half the step
                    st, k_out = recovery.rewind(failed.time, qdd_prev)
                    h_step = h / 2 ** recovery.level
                    counters["recovery_steps"] = counters.get("recovery_steps", 0) + \
                        int(round((recovery.fine_until - st.t) / h_step))
                    flags[:] = 0
                    stats[:] = 0
                    fast = False
                    counters["step_recoveries"] = counters.get("step_recoveries", 0) + 1
        elif integ.kind == "rk4":
            k_q, k_v = z(4, n, 6), z(4, n, 6)
            qs, vbuf, acc = z(n, 6), z(n, 6), z(n, 6)
            for k_out in range(1, n_out + 1):
                t_target = t_start + k_out * out_dt
                nsteps = int(round((t_target - st.t) / h))
                status = rk4_advance(km, vs, att, ws, st.q, st.qd, st.qdd, st.ref, st.t, h, nsteps, mask, k_q, k_v, qs,
                                     vbuf, acc, stats, fail)
                counters.add(stats, ("steps", "evaluations", "unused", "rebases"))
                stats[:] = 0
                if status != 0:
                    st.t = float(fail[0])
                    _raise(system, fail, status, make_results, "RK4: ", rk4_hint)
                st.t = t_target
                output(st)
        else:
            k_q, k_v = z(7, n, 6), z(7, n, 6)
            qs, vbuf, acc = z(n, 6), z(n, 6), z(n, 6)
            hout = np.array([h])
            h_max = float(integ.max_step) if integ.max_step else np.inf
            for k_out in range(1, n_out + 1):
                t_target = t_start + k_out * out_dt
                status = dp_advance(km, vs, att, ws, st.q, st.qd, st.qdd, st.ref, st.t, t_target, hout[0], h_max,
                                    float(integ.rtol), float(integ.atol), mask, k_q, k_v, qs, vbuf, acc, _DP_A, _DP_B,
                                    _DP_C, _DP_E, stats, fail, hout)
                counters.add(stats, ("steps", "evaluations", "rejected_steps", "rebases"))
                stats[:] = 0
                if status != 0:
                    st.t = float(fail[0])
                    quantity = hint = None
                    if int(fail[1]) < 0 and int(fail[2]) == Q_VELOCITY:
                        # dp_advance's only failure at no element: the step collapsed (below
                        # 1e-14 * max(1, t) s, or 50 rejections in a row), not a runaway velocity
                        quantity = (f"the adaptive step size collapsed (below {1e-14 * max(1.0, st.t):.3g} s or "
                                    f"rejected 50 times in a row; the step at the previous output was {hout[0]:.3g} s)")
                        hint = (f"the error estimate cannot meet analysis.dynamics.integrator.rtol = {integ.rtol:g} "
                                f"and atol = {integ.atol:g} (round-off) or the state is diverging: loosen rtol / atol, "
                                f"set max_step, or use the rk4 or generalized-alpha integrator")
                    _raise(system, fail, status, make_results, "adaptive RK: ", hint, quantity)
                st.t = t_target
                output(st)
    except ArithmeticError as exc:
        # a division by zero or an overflow raised inside a kernel (FloatingPointError too): a
        # SolverError with the results so far, as a divergence, not a traceback that loses them
        raise _arithmetic_failure(exc, st.t, make_results) from exc
    except KeyboardInterrupt as exc:
        # Ctrl-C (or a SIGTERM the command line turns into it): the results so far go with the
        # interruption, as they go with a SolverError (rfesim.api.simulate, rfesim.cli)
        t = float(recorder.time[recorder.k - 1]) if recorder.k else st.t
        exc.results = make_results(status=INTERRUPTED, message=f"interrupted at t = {t:.6g} s")
        raise
    except CancelledError as exc:
        # the progress callback raised (the service's cancel): the results up to the last
        # output step go with the cancellation too (status CANCELLED)
        raise cancelled(exc, float(recorder.time[recorder.k - 1]) if recorder.k else st.t,
                        make_results if recorder.k else None) from (exc.__cause__ or exc)
    counters["wall_time"] = _time.perf_counter() - wall0
    return st, recorder, counters
