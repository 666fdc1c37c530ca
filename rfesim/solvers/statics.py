"""Static equilibrium: Newton with line search, Levenberg regularisation and load ramping.

The residual is the generalised force with all velocities zero; its block-tridiagonal
Jacobian is factored in O(n). Every Newton update is followed by a re-base of every RFE's
reference rotation (statics has no rate history), so large rotations such as a cantilever
rolled into a full circle never meet the Euler-angle singularity.

Load ramping scales the applied loads (gravity, buoyancy, point loads, current drag) from a
fraction to 1; a failed increment is halved. Lines with both ends placed start from the elastic
catenary (``rfesim.catenary``) and take the full load at once. Ropes (tension-only SDEs)
whose elements start compressed go through the equilibrium with compression allowed
(``_solve_with_ropes``; docs/theory.md, 'Slack ropes in statics').
"""
from __future__ import annotations

import logging
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np

from ..errors import SolverError
from ..loads.drives import rest_of_workspace
from ..loads.seabed import seabed_height
from ..model.assemble import rebase
from ..model.arrays import Reference
from ..model.compile import State
from .banded import bt_factor_closed, bt_solve_closed
from .rechain import chain_line_into
from .system import System

log = logging.getLogger("rfesim")


@dataclass
class StaticsInfo:
    iterations: int
    load_steps: int
    residual: float
    converged: bool
    message: str
    warnings: list[str] = field(default_factory=list)   # what the user should know about the equilibrium
    through: list[str] = field(default_factory=list)    # of them, ropes left pushed through themselves
                                                        #   (rfesim.solvers.buckling.through_rope_warnings)


def _norm(r: np.ndarray, mask: np.ndarray, length_scale: np.ndarray, force_ref: float) -> float:
    s = np.abs(r).copy()
    s[:, 3:] /= length_scale[:, None]
    s[~mask] = 0.0
    return float(s.max()) / force_ref


ITERATIONS_PER_INCREMENT = 100  # Newton iterations before a load increment is halved
MAX_RISES = 6                  # consecutive residual rises that end an increment
INCREMENT_TOLERANCE = 1e-12  # Newton increment relative to the element length (rad for angles)
# Smallest Levenberg damping, relative to the diagonal. The softest physical mode of a line
# sits at about 1/n^4 of its diagonal (n elements: bending of short stiff elements): a damping
# above that turns Newton into a slow linear iteration. At 1e-10 the 10 m cantilever of
# scenarios/cantilever_pipe.json took 29 iterations on 300 elements and did not converge on
# 1000 (residual 0.06 x force scale); at 1e-16 it takes 3, 5 and 7 on 300, 1000 and 2000.
# Where the factorisation or the descent test fails, the damping is raised (to 1e-8 and up).
MU_MIN = 1e-16


ROTATION_FLOOR = 1e-9  # constant damping of torsion, relative to the largest rotational diagonal

# Residual accepted once Newton stagnates, in multiples of position_resolution_force: the
# J-lay template (1370 m of pipe, 1200 m deep) stalls at 1.3 (1 m elements) and 1.45
# (0.5 m) of it; a one-ulp move of one RFE changes its residual by 1.8 of it
# (docs/theory.md, 'Resolution of absolute positions in statics').
POSITION_FLOOR = 4.0


def position_resolution_force(system: System, state: State) -> float:
    """The force resolution of the positions (N): the largest, over the SDEs, of the SDE's
    stiffness times the spacing of doubles (one ulp) at the farther of its two RFEs from the
    origin (``_solve`` takes it at the start state; a solve hardly changes those sizes).

    Statics re-bases every RFE after every update (``rebase``: ref.X += q, q = 0), so a
    position is a double of magnitude |r| and moves in steps of ulp(|r|) (2.3e-13 m at
    1024-2048 m from the origin); moving an RFE by one step changes the force of an SDE of
    stiffness k by about k ulp(|r|), and no state on that lattice brings the residual below
    it (3.2e9 N/m x 2.3e-13 m = 7.2e-4 N for 1 m elements of a 12-inch steel pipe at 1200 m
    depth). ``System.roundoff_force`` counts the round-off of the gap's difference, which
    grows with the element length, not this, which does not."""
    km = system.km
    if not system.model.nsde:
        return 0.0
    pos = np.abs(state.ref.X + state.q[:, :3]).max(axis=1)
    size = np.maximum(pos[km.sde_left], pos[km.sde_right])
    return float((km.sde_stiffness[:, :3].max(axis=1) * np.spacing(size)).max())


def _regularise(J: np.ndarray, mu: float, mask: np.ndarray, yaw: list | None = None) -> np.ndarray:
    """J + mu * diag(max(|J_ii|, 1e-6 * max |J_ii| of the same coordinate kind)): a
    Levenberg damping that only matters for coordinates with (nearly) no stiffness.

    Torsion also gets a constant 1e-9 of the largest rotational stiffness (statics re-bases
    every RFE to zero angles, where coordinate 5 is the rotation about the element axis):
    the torsion of a cable with GJ ~ 0 sits at 1e-16 of the stiffest shear springs, below
    the resolution of the Jacobian; its Newton steps would be noise and its equilibrium is
    physically arbitrary, so it stays where it is.

    ``yaw`` ((rfe, n) pairs, ``_free_yaw``) gets the same constant damping on the rotation
    about the vertical of each body hanging on a pinned connection: nothing resists that turn
    about its line (a pinned connection has no rotational stiffness and gravity has no moment
    about the vertical), so Newton's steps along it are noise too (an attachment along y
    turned the payload 11 degrees about its rope on the first step), and its yaw stays where
    it starts."""
    Jr = J.copy()
    diag = np.abs(np.einsum("nkk->nk", J[:, 1]))
    floor_t = 1e-6 * (diag[:, :3][mask[:, :3]].max() if mask[:, :3].any() else 1.0)
    floor_r = 1e-6 * (diag[:, 3:][mask[:, 3:]].max() if mask[:, 3:].any() else 1.0)
    floor = np.concatenate([np.full(3, floor_t), np.full(3, floor_r)])
    add = mu * np.maximum(diag, floor[None, :])
    add[:, 5] += ROTATION_FLOOR * 1e6 * floor_r      # coordinate 5 is torsion at re-based (zero) angles
    add[~mask] = 0.0
    idx = np.arange(6)
    Jr[:, 1, idx, idx] += add
    for i, nz in yaw or ():
        Jr[i, 1, 3:, 3:] += ROTATION_FLOOR * 1e6 * floor_r * np.outer(nz, nz)
    return Jr


def _free_yaw(system: System, ref: Reference) -> list:
    """(rfe, n) of every body on a pinned connection that ``hang_bodies`` turned to hang: n the
    rotation about the global vertical in the RFE's re-based angle coordinates (psi, theta,
    phi at zero angles turn about the body's z, y, x axes: n = (v_z, v_y, v_x), v = R^T e_z).
    Only those: a body that hung from the start keeps the Newton path it had (a force-driven
    A-frame portal, whose statics has a second equilibrium with the legs swung over, reached
    that one at 171 deg when its payload's yaw was damped too)."""
    km = system.km
    hung = system.hung_bodies
    out = []
    for info in getattr(system.model, "bodies", None) or []:
        if info.name in hung and np.all(km.sde_stiffness[info.sde, 3:] == 0.0):
            v = ref.R[info.rfe][2]          # R^T e_z: the third row of R
            out.append((info.rfe, np.array([v[2], v[1], v[0]])))
    return out


def _rechain(system: System, st: State, dq: np.ndarray, alpha: float, trial: np.ndarray, trial_ref: Reference,
             lam: float, eps_old: np.ndarray, eps_dir: np.ndarray) -> None:
    """Geometrically consistent Newton update (fills trial, trial_ref).

    Rotations take the Newton step; the RFE centres are then re-chained along each line so
    that every SDE's deformation changes by exactly the linearised amount
    ``alpha * d(eps)/dq . dq``. A linear update of the centres would leave second-order
    gaps (l * dphi^2 / 2) in the axial springs, which are 1e7 times stiffer than bending
    in a long pipe and would swamp the next iteration with spurious tension. Near the
    solution the correction vanishes and Newton keeps its quadratic convergence."""
    km = system.km
    ws = system.ws
    dummy = np.zeros_like(trial)
    trial[:] = st.q + alpha * dq
    trial_ref.R[:] = st.ref.R
    trial_ref.X[:] = st.ref.X
    # poses with the new rotations and linearly updated centres
    st2 = State(st.t, trial, dummy, dummy, trial_ref, dummy)
    system.evaluate(st2, lam)
    R = ws.R.copy()
    r = ws.r.copy()
    rest = rest_of_workspace(km, ws)       # SDE rest rotations (joints, rfesim.loads.drives)
    eps_target = eps_old + alpha * eps_dir

    def link(a, b, sidx):
        """Centre of RFE b from RFE a's across SDE sidx at its target deformation: mean frame
        R' = R_a* exp(theta/2) of the new rotations, R_a* = R_a R0."""
        Ras = R[a] @ rest[sidx]
        Rp = Ras @ _exp(0.5 * _log(Ras.T @ R[b]))
        return r[a] + R[a] @ km.sde_arm_left[sidx] + Rp @ eps_target[sidx, :3] - R[b] @ km.sde_arm_right[sidx]

    # a joined line starts from its parent's re-chained end across the joint SDE (parents come
    # first): a hinged boom turned far in one step keeps its joint closed
    joined = {ji.child: ji for ji in getattr(system.model, "joins", [])}
    if getattr(km, "has_reeving", False):
        # a rope slipping over its sheave: the join's arm moves with the sheave (slip_arms), so
        # the rope keeps its own chain
        for s_slip in km.rv_sde[km.rv_slip == 1]:
            joined = {c: ji for c, ji in joined.items() if ji.sde != int(s_slip)}
    for li in system.model.lines:
        i0, i1 = li.rfe_start, li.rfe_stop - 1
        s0 = li.sde_start
        nsde = li.elements
        ji = joined.get(li.name)
        if ji is not None and km.rfe_kind[i0] == 0:
            r[i0] = link(ji.parent_rfe, i0, ji.sde)
        chain = np.empty((li.nrfe, 3))
        placed_b = r[i1].copy()
        # chain[j + 1] = r[i0 + j + 1] = link(i0 + j, i0 + j + 1, s0 + j) for every element
        chain_line_into(R, r, rest, km.sde_arm_left, km.sde_arm_right, eps_target, i0, s0, nsde, chain)
        if km.rfe_kind[i1] != 0 and nsde > 0:
            # end B placed by its attachment: spread the closure error along the line
            miss = chain[-1] - placed_b
            chain -= miss[None, :] * (np.arange(li.nrfe) / nsde)[:, None]
            r[i1] = placed_b
        free = np.flatnonzero(km.rfe_kind[i0:i0 + li.nrfe] == 0)     # the RFEs not placed by attachments
        trial[i0 + free, :3] = chain[free] - trial_ref.X[i0 + free]
        r[i0 + free] = chain[free]
    rebase(trial, dummy, trial_ref, km.rfe_kind, 0.0, dummy, dummy, False)


def _linear_update(system: System, st: State, dq: np.ndarray, alpha: float, trial: np.ndarray,
                   trial_ref: Reference) -> None:
    """Plain Newton update q + alpha dq, re-based."""
    dummy = np.zeros_like(trial)
    trial[:] = st.q + alpha * dq
    trial_ref.R[:] = st.ref.R
    trial_ref.X[:] = st.ref.X
    rebase(trial, dummy, trial_ref, system.km.rfe_kind, 0.0, dummy, dummy, False)


def _log(R: np.ndarray) -> np.ndarray:
    from ..kinematics import log_so3_into
    out = np.zeros(3)
    log_so3_into(np.ascontiguousarray(R), out)
    return out


def _exp(w: np.ndarray) -> np.ndarray:
    from ..kinematics import exp_so3_into
    out = np.zeros((3, 3))
    exp_so3_into(float(w[0]), float(w[1]), float(w[2]), out)
    return out


def _deformation_direction(system: System, st: State, dq: np.ndarray, lam: float) -> tuple[np.ndarray, np.ndarray]:
    """SDE deformations at the state and their directional derivative along dq."""
    dummy = np.zeros_like(st.q)
    system.evaluate(State(st.t, st.q, dummy, dummy, st.ref, dummy), lam)
    eps0 = system.ws.eps.copy()
    size = max(float((np.abs(dq[:, :3]) / system.length_scale[:, None]).max()), float(np.abs(dq[:, 3:]).max()))
    h = 1e-6 / max(size, 1e-300)        # the perturbation h*dq is 1e-6 of an element length
    system.evaluate(State(st.t, st.q + h * dq, dummy, dummy, st.ref, dummy), lam)
    eps1 = system.ws.eps.copy()
    system.evaluate(State(st.t, st.q - h * dq, dummy, dummy, st.ref, dummy), lam)
    eps2 = system.ws.eps.copy()
    return eps0, (eps1 - eps2) / (2.0 * h)


HANG_ANGLE = 1e-6   # rad: a body turned less than this from hanging is not turned


def hang_bodies(system: System, state: State) -> tuple[State, list[str]]:
    """(start, names): a copy of the start state in which every body hanging free on a pinned
    connection and not hanging under its attachment point is turned to, with the connection
    carrying its weight, and the names of those bodies (the state itself if none).

    Why: in the start state the connection (and the line) carries no force yet, so nothing in
    the Jacobian resists a rotation of the body about its attachment point: gravity acts at
    the centre of mass, where it has no moment, and a connection without force has no
    geometric stiffness. A crane payload with ``payload_attachment`` off its centre line
    ([0, 1, 0.5]: a 63.4 degree roll to hang) made Newton's first step a rotation of
    thousands of radians about those free axes; the step limit cut it to a crawl, the crawl
    wandered about the free yaw and the load step failed at load factor 0 (in the crane's
    symmetry plane, [1, 0, 0.5], it crawled to the pitch in 30 iterations). So each such body is

    * turned by the smallest rotation (about a horizontal axis through the attachment point,
      which stays where it is) that puts its weight centre under the attachment point: the
      centre of mass, less the displaced water at the centre of buoyancy when fully submerged
      (the potential energy g (R w)_z, w = -m a - rho V (c - a), a the attachment point and c
      the centre of buoyancy in body axes, is least with R w pointing down); its yaw about the
      vertical is kept;
    * lowered by its net weight over the connection's axial stiffness (micrometres), so that
      the connection carries that weight from the first Jacobian on, with the pendulum
      stiffness of the hanging body; the residual is then the line's stretch, which Newton
      solves in a few iterations. (A body hanging already is left as it is: its weight has no
      moment, whichever way the first step turns it; the free yaw is damped in
      ``_regularise``.)

    Left alone: clamped connections (the line's end holds the body's rotation), bodies held
    by tuggers or a deck, bodies in the splash zone (the buoyancy's moment changes with the
    attitude), buoyant ones, and bodies in reach of the seabed."""
    km = system.km
    bodies = getattr(system.model, "bodies", None) or []
    if not bodies:
        return state, []
    st = state.copy()
    st.qd[:] = 0.0
    system.evaluate(st)
    ws = system.ws
    held = set(int(i) for i in getattr(km, "tug_rfe", np.zeros(0, np.int64)))
    deck = getattr(km, "body_deck_att", np.full(len(bodies), -1))
    down = np.array([0.0, 0.0, -1.0])
    turned = []
    for info in bodies:
        i, s = info.rfe, info.sde
        k = float(km.sde_stiffness[s, 0])
        if (np.any(km.sde_stiffness[s, 3:] != 0.0) or k <= 0.0 or i in held
                or (len(deck) > info.index and deck[info.index] >= 0)):
            continue
        f = float(ws.sub_frac[i]) if km.has_water else 0.0
        if 0.0 < f < 1.0:
            continue
        displaced = km.water_density * km.body_volume[info.index] * f
        weight = km.gravity * (info.mass - displaced)
        if weight <= 0.0:
            continue
        R = ws.R[i].copy()
        a = np.asarray(km.sde_arm_right[s], float)
        w = -info.mass * a
        if f > 0.0:
            w -= displaced * (np.asarray(km.body_cob[info.index], float) - a)
        wg = R @ w
        size = float(np.linalg.norm(wg))
        if size <= 1e-12 * info.mass * max(float(np.linalg.norm(a)), 1e-12):
            continue                                       # attached at its weight centre
        u = wg / size
        axis = np.cross(u, down)
        angle = float(np.arctan2(np.linalg.norm(axis), float(u @ down)))
        if angle < HANG_ANGLE:
            continue                                       # hanging already
        if np.linalg.norm(axis) < 1e-12:                   # upside down: turn about a horizontal axis
            axis = np.cross(u, [1.0, 0.0, 0.0])
        Q = _exp(angle * axis / np.linalg.norm(axis))
        P = ws.r[i] + R @ a                                # the attachment point stays where it is
        centre = P + Q @ (ws.r[i] - P) + down * (weight / k)
        if km.has_seabed:
            bed = np.zeros(3)
            seabed_height(km.bed_s, km.bed_z, km.bed_dir, float(centre[0]), float(centre[1]), bed)
            if centre[2] - km.rfe_contact_radius[i] < bed[0]:
                continue
        st.ref.R[i] = Q @ R
        st.ref.X[i] = centre
        st.q[i] = 0.0
        turned.append(info.name)
    if not turned:
        return state, []
    log.info("statics: started with %s turned to hang under the attachment point", ", ".join(turned))
    return st, turned


def solve_statics(system: System, state: State | None = None, *, tolerance: float = 1e-8, max_iterations: int = 400,
                  load_steps: int = 1, progress=None, seabed_friction: str = "none",
                  hang: bool | None = None) -> tuple[State, StaticsInfo]:
    """Static equilibrium of the scene at the state's time (vessels at their pose then).

    ``seabed_friction``: ``"none"`` (friction plays no part in statics) or ``"mobilised"``
    (full axial friction on the grounded length, pointing towards end A: the line was
    pulled towards end B as it was laid, as MoorPy assumes). Either way the friction
    anchors are left so that a following dynamic run starts with the same forces.

    ``hang``: start with the bodies hanging under their attachment points (``hang_bodies``);
    by default when starting from the model's initial state (``state`` None), not from a
    given state (an equilibrium being solved again keeps its pose)."""
    model = system.model
    if hang if hang is not None else state is None:
        state, turned = hang_bodies(system, state or model.initial)
        # their free yaw is damped from here on (_free_yaw), in the solves of this system that follow too
        system.hung_bodies = set(turned)
    mobilised = seabed_friction == "mobilised"
    system.set_friction_mode(1 if mobilised else 2)
    system.ws.waves_off[0] = 1          # statics: still water plus current
    if model.km.has_tensioners or model.km.has_reels:
        # the tensioners and reels grip the line where it starts (its initial shape), and hold it there
        st0 = (state or model.initial).copy()
        st0.qd[:] = 0.0
        system.evaluate(st0)
        ws = system.ws
        # RFEs gripped already keep their anchors (a payout since the last solve pulls them
        # along); the others are gripped where they are
        for anchor, on, anchor_trial, on_trial in ((ws.grip_a, ws.grip_on, ws.grip_a_trial, ws.grip_on_trial),
                                                   (ws.reel_grip_a, ws.reel_grip_on, ws.reel_grip_a_trial,
                                                    ws.reel_grip_on_trial)):
            new = (on == 0) | (on_trial == 0)
            anchor[new] = anchor_trial[new]
            on[:] = on_trial
        ws.tens_time[:] = st0.t
        ws.reel_time[:] = st0.t
    try:
        st, info = _solve_with_ropes(system, state, tolerance, max_iterations, load_steps, progress)
        if model.km.has_friction or model.km.has_plastic or model.km.has_tensioners or model.km.has_reels:
            # history of the final state: plastic state of the SDEs, friction anchors at the
            # mobilised forces or none (set at first touch)
            system.evaluate(st)
            system.commit_history()
            if not mobilised:
                system.ws.fric_anchored[:] = 0
    finally:
        system.set_friction_mode(0)
        system.ws.waves_off[0] = 0
    st.static = True
    return st, info


@contextmanager
def _ropes_elastic(km):
    """The tension-only SDEs (ropes, rfesim.loads.tension_only) as ordinary elastic SDEs
    (compression allowed) within the block: their flags are cleared and restored."""
    saved = km.sde_tension_only.copy()
    km.sde_tension_only[:] = 0
    try:
        yield
    finally:
        km.sde_tension_only[:] = saved


def _compressed_ropes(system: System, state: State) -> int:
    """Number of tension-only SDEs whose elastic axial force is compressive (below the force
    resolution) at the state: the ones the tension-only correction would leave slack."""
    km = system.km
    st = state.copy()
    st.qd[:] = 0.0
    with _ropes_elastic(km):
        system.evaluate(st)
    sigma_x = system.ws.sigma[:, 0]
    return int(np.count_nonzero((km.sde_tension_only == 1) & (sigma_x < -system.roundoff_force(st))))


def _solve_with_ropes(system: System, state: State | None, tolerance: float, max_iterations: int,
                      load_steps: int, progress) -> tuple[State, StaticsInfo]:
    """``_solve``, for scenes with ropes (tension-only SDEs) through their elastic equilibrium.

    A slack rope element has no axial force and no axial stiffness, so Newton does not see
    it go taut: from a start with compressed rope elements (a straight start, or the chord
    chain of a strongly curved catenary, which is longer than the curve and closes only
    compressed) the Jacobian has a free axial direction at every slack element and Newton
    fails, and even 1 um of noise on the converged catenary costs it 53 iterations (docs/
    theory.md, 'Slack ropes in statics'). Every equilibrium with the ropes taut is also an
    equilibrium of the same scene with the ropes elastic in compression, whose Newton is
    smooth. So: first the equilibrium with compression allowed, then, from it and at the
    full load, Newton with the ropes tension-only again (0 iterations when they are taut
    everywhere, a few where they go slack). A start without compressed rope elements keeps
    the direct solve; whichever of the two comes first, the other is the fallback."""
    km = system.km
    if not km.has_tension_only:
        return _solve(system, state, tolerance, max_iterations, load_steps, progress)
    start = (state or system.model.initial)
    slack = _compressed_ropes(system, start)
    order = ("elastic first", "direct") if slack else ("direct", "elastic first")
    first_error: SolverError | None = None
    for how in order:
        try:
            if how == "direct":
                return _solve(system, state, tolerance, max_iterations, load_steps, progress)
            return _solve_elastic_first(system, state, tolerance, max_iterations, load_steps, progress)
        except SolverError as exc:
            log.info("statics with ropes (%d compressed rope elements at the start), %s: %s", slack, how, exc)
            if first_error is None:
                first_error = exc
    assert first_error is not None
    raise first_error


def _solve_elastic_first(system: System, state: State | None, tolerance: float, max_iterations: int,
                         load_steps: int, progress) -> tuple[State, StaticsInfo]:
    """The equilibrium with the ropes elastic in compression, then with them tension-only:
    from there the elements that stay slack are those compressed in the elastic equilibrium
    (a stiff rope's U bottom carried in bending), which Newton finds on their exact tangent
    (zero axial stiffness) where the central differences, whose step straddles the kink,
    stall (docs/theory.md, 'Slack ropes in statics')."""
    def part(lo, hi):
        return None if progress is None else (lambda frac, t: progress(lo + (hi - lo) * frac, t))

    with _ropes_elastic(system.km):
        st1, info1 = _solve(system, state, tolerance, max_iterations, load_steps, part(0.0, 0.9))
    # from the elastic equilibrium at the full load (no ramp: a ramp would unload it)
    st2, info2 = _solve(system, st1, tolerance, max(max_iterations - info1.iterations, 1), 1, part(0.9, 1.0),
                        rope_tangent=True)
    its = info1.iterations + info2.iterations
    steps = info1.load_steps + info2.load_steps
    return st2, StaticsInfo(iterations=its, load_steps=steps, residual=info2.residual, converged=True,
                            message=f"converged in {its} Newton iterations, {steps} load steps (ropes: "
                                    f"compression allowed first, then {info2.iterations} tension-only)")


CAPACITY_FRACTION = 0.999      # a track or drum holding this much of its capacity is taken as slipping


def capacity_hint(system: System, lam: float) -> tuple[str, str] | None:
    """(what, hint) naming the tensioners and reels whose grips are all at their capacity in
    the workspace's last evaluation (at the load factor lam), or None. The capacity's shares
    add up to it (rfesim.loads.tensioner): a track or drum carrying its capacity slips as a
    whole, and statics finds no equilibrium beyond that load factor; the full static load
    is then about capacity / lam or more."""
    km, ws, model = system.km, system.ws, system.model
    found = []
    for kind, infos, force, cap in (("tensioner", getattr(model, "tensioners", None) or [], ws.tens_force,
                                     km.tens_cap),
                                    ("reel", getattr(model, "reels", None) or [], ws.reel_force, km.reel_cap)):
        for info in infos:
            F, C = abs(float(force[info.index])), float(cap[info.index])
            # at its capacity, or its load at this load factor scaled to the full load beyond it
            if C > 0.0 and (F >= CAPACITY_FRACTION * C or (0.0 < lam < 1.0 and F / lam > C)):
                found.append((kind, info.name, info.line, F, C))
    if not found:
        return None
    kind, name, line, F, C = found[0]
    more = f" (and {len(found) - 1} more)" if len(found) > 1 else ""
    need = F / lam if 0.0 < lam < 1.0 else None
    load = (f"the full static load is about {need:.6g} N or more" if need is not None
            else "the static load is more than that")
    what = (f"{kind} '{name}'{more} holding line '{line}' carries {F:.6g} N at load factor {lam:.4g}, "
            f"beyond its capacity {C:.6g} N (supports.{name}.capacity) at the full load: its grips slip")
    hint = (f"{kind} '{name}' holds at most supports.{name}.capacity = {C:.6g} N and carries {F:.6g} N at load "
            f"factor {lam:.4g}, so {load}: give supports.{name}.capacity above it (or hold the line elsewhere too)")
    return what, hint


def _solve(system: System, state: State | None, tolerance: float, max_iterations: int, load_steps: int,
           progress, rope_tangent: bool = False) -> tuple[State, StaticsInfo]:
    """Newton with load ramping. ``rope_tangent``: the exact tangent of slack rope elements
    (``System.static_jacobian_ropes``) instead of the central differences."""
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
    # below the round-off of the stiffest SDE, or the resolution of the positions statics
    # holds in absolute coordinates, the residual only stagnates: accept it there
    floor = max(10.0 * system.roundoff_force(st), POSITION_FLOOR * position_resolution_force(system, st)) / force_ref
    r = np.zeros((n, 6))
    dq = np.zeros((n, 6))
    trial = np.zeros((n, 6))
    fac = np.zeros_like(system.Fac)

    # a rope slipping over its sheave (rfesim.loads.reeving.slip_arms) couples the sheave's
    # position with the stiff join: the central-difference Jacobian of that coupling left
    # Newton cycling (the A-frame with a deck winch lead: no convergence in 100 iterations),
    # the analytic one converges in 5 (docs/theory.md, 'Reeving')
    slipping = bool(getattr(system.km, "has_reeving", False) and np.any(system.km.rv_slip == 1))
    # a closing join (rfesim.model.joins) or a rope led along a line (reeving to a line end)
    # couples RFEs that are not neighbours: the coloured differences would mix its blocks into
    # the band (System.static_jacobian_hybrid; with the rope along the boom the column_crane
    # scenario did not converge, docs/theory.md 'Reeving')
    closed = bool(system.km.has_closures) or system.has_line_leads
    # ropes (tension-only SDEs) from their elastic equilibrium: their exact tangent
    # (System.static_jacobian_ropes)
    ropes = bool(rope_tangent and system.km.has_tension_only and np.any(system.km.sde_tension_only == 1))
    lam_done = 0.0
    dlam = 1.0 / max(1, load_steps)
    q_good = st.q.copy()
    ref_good = Reference(st.ref.R.copy(), st.ref.X.copy())
    trial_ref = Reference(st.ref.R.copy(), st.ref.X.copy())
    total_its = 0
    nsteps = 0
    rn = np.inf
    tried = None                # (load factor, least residual) of the last increment that failed
    while True:
        lam = min(1.0, lam_done + dlam)
        ok = False
        mu = MU_MIN
        system.static_residual(st.q, st.ref, lam, r)
        rn = _norm(r, mask, ls, force_ref)
        rn_prev = np.inf
        rises = 0
        for it in range(ITERATIONS_PER_INCREMENT):
            if rn <= tolerance or (rn <= floor and rn > 0.9 * rn_prev):
                ok = True
                break
            if total_its >= max_iterations:
                break
            total_its += 1
            if slipping:
                J = system.static_jacobian_analytic(st.q, st.ref, lam)
            elif ropes:
                J = system.static_jacobian_hybrid(st.q, st.ref, lam, ropes=True)
            elif closed:
                J = system.static_jacobian_hybrid(st.q, st.ref, lam)
            else:
                J = system.static_jacobian_accurate(st.q, st.ref, lam)
            yaw = _free_yaw(system, st.ref)
            # Solve; raise the Levenberg damping while the direction is not a descent
            # direction (a part in compression has negative geometric stiffness).
            bad = 0
            for _attempt in range(12):
                bad = bt_factor_closed(_regularise(J, mu, mask, yaw), fac, system.km, system.ws)
                if bad < 0:
                    bt_solve_closed(fac, r, dq, system.km, system.ws)
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
            # Step limited to 0.5 rad of rotation and 5 element lengths, with the
            # geometrically consistent update (_rechain) and Crisfield's line search on the
            # directional derivative of the energy, s(alpha) = dq . r(q + alpha dq).
            rot = float(np.abs(dq[:, 3:]).max())
            tr = float((np.abs(dq[:, :3]) / ls[:, None]).max())
            limit = min(1.0, 0.5 / max(rot, 1e-300), 5.0 / max(tr, 1e-300))
            eps_old, eps_dir = _deformation_direction(system, st, dq, lam)
            s0 = float(np.sum(dq * r))
            # choose between the re-chained update (large rotations of lines with a free end)
            # and the plain linear one (lines closed at both ends, where re-chaining has to
            # spread a closure error, e.g. into a stiff seabed): whichever leaves less residual
            use_rechain = True
            _rechain(system, st, dq, limit, trial, trial_ref, lam, eps_old, eps_dir)
            system.static_residual(trial, trial_ref, lam, r)
            rn_chain = _norm(r, mask, ls, force_ref)
            _linear_update(system, st, dq, limit, trial, trial_ref)
            system.static_residual(trial, trial_ref, lam, r)
            rn_lin = _norm(r, mask, ls, force_ref)

            if not (rn_lin < rn_chain):
                use_rechain = True
            else:
                use_rechain = False
            alpha = limit
            a_lo, s_lo = 0.0, s0
            rn_new = np.inf
            for _ in range(8):
                if use_rechain:
                    _rechain(system, st, dq, alpha, trial, trial_ref, lam, eps_old, eps_dir)
                else:
                    _linear_update(system, st, dq, alpha, trial, trial_ref)
                system.static_residual(trial, trial_ref, lam, r)
                rn_new = _norm(r, mask, ls, force_ref)
                if not np.isfinite(rn_new):
                    alpha *= 0.25
                    continue
                s1 = float(np.sum(dq * r))
                if abs(s1) <= 0.8 * abs(s0) or rn_new < 0.5 * rn:
                    break
                denom = s_lo - s1
                a_new = alpha if denom == 0.0 else a_lo + (alpha - a_lo) * s_lo / denom
                if s1 * s0 < 0:            # overshoot: the root lies between a_lo and alpha
                    a_new = min(max(a_new, a_lo + 0.1 * (alpha - a_lo)), a_lo + 0.9 * (alpha - a_lo))
                else:                      # still descending: the root lies beyond alpha
                    a_lo, s_lo = alpha, s1
                    a_new = min(max(a_new, 1.1 * alpha), 4.0 * alpha, 4.0 * limit)
                alpha = a_new
            if not np.isfinite(rn_new):
                break
            st.q[:] = trial
            st.ref.R[:] = trial_ref.R
            st.ref.X[:] = trial_ref.X
            rises = rises + 1 if rn_new > rn else 0
            rn_prev = rn
            rn = rn_new
            mu = max(mu * 0.1, MU_MIN)
            if rises >= MAX_RISES:
                break
            if progress is not None:
                progress(min(0.999, lam_done + dlam * 0.5), st.t)
        nsteps += 1
        if not ok and np.isfinite(rn):
            # where this increment left the residual: its size and the RFE it is largest on
            system.static_residual(st.q, st.ref, lam, r)
            tried = (lam, rn, int(np.argmax(np.abs(r).max(axis=1))))
        if ok:
            lam_done = lam
            q_good[:] = st.q
            ref_good.R[:] = st.ref.R
            ref_good.X[:] = st.ref.X
            if lam_done >= 1.0:
                break
            dlam = min(2.0 * dlam, 1.0 - lam_done)
            continue
        # failed increment: go back and halve it
        st.q[:] = q_good
        st.ref.R[:] = ref_good.R
        st.ref.X[:] = ref_good.X
        dlam *= 0.5
        if dlam < 1e-4 or total_its >= max_iterations:
            lam_fail = max(lam_done, dlam)
            system.static_residual(st.q, st.ref, lam_fail, r)
            rn = _norm(r, mask, ls, force_ref)
            elem = int(np.argmax(np.abs(r).max(axis=1))) if tried is None or lam_done <= 0.0 else tried[2]
            # a tensioner or reel whose grips all slip: its capacity, not an element, is the cause
            held = capacity_hint(system, lam_fail)
            if total_its >= max_iterations:
                why = (f"the Newton iterations were used up ({total_its} of max_iterations {max_iterations}, "
                       f"in {nsteps} load step{'s' if nsteps != 1 else ''}): raise analysis.statics.max_iterations, "
                       f"or analysis.statics.load_steps for smaller load increments")
            else:
                why = (f"the load increment was halved below 1e-4 of the full load after {total_its} iterations: "
                       f"Newton failed on every smaller increment")
            # the residual where Newton failed, not at the load factor it reached (there it converged)
            stuck = (f"at load factor {tried[0]:.4g} the residual stayed at {tried[1]:.3g}" if tried is not None
                     and lam_done > 0.0 else f"residual {rn:.3g}")
            raise SolverError("static equilibrium not found: Newton did not converge "
                              f"(load factor {lam_done:.4g} reached, {stuck} x force scale {force_ref:.3g} N; "
                              f"{why})" + (f"; {held[0]}" if held else ""),
                              time=st.t, element=model.describe_rfe(elem), quantity="static residual",
                              hint=held[1] if held else None)
    info = StaticsInfo(iterations=total_its, load_steps=nsteps, residual=rn, converged=True,
                       message=f"converged in {total_its} Newton iterations, {nsteps} load steps")
    return st, info
