"""Planar RFE formulation (chapter section 8.3): one link in the XY plane, gravity along -y.

Coordinates (eq. 8.52): ``q = [x, y, phi_0, ..., phi_n]``, the point A_0 of the link and the
absolute inclination angle of every RFE to the X axis. The RFEs are joined at A_1..A_n by
rotational SDEs only (Kelvin-Voigt, eqs. 8.62-8.63): the link is inextensible and rigid in
shear, as in the chapter. The base is RFE 0's point A_0 (eq. 8.69): an end A ``clamped``
follows the prescribed x0(t), y0(t), phi0(t), ``pinned`` follows x0(t), y0(t) with phi_0
free, ``free`` has all three free. End B can be free, pinned or clamped to a fixed point
(reactions of eqs. 8.67-8.68 by Lagrange multipliers).

Use::

    model = planar_beam(length=1.0, bending_stiffness=1.0, mass_per_length=1.0, elements=20,
                        tip_force=(0.0, -10.0))
    st = planar_statics(model)                  # Newton with load ramping
    md = planar_modes(model, st.q)              # md.frequencies_hz
    res = planar_dynamics(model, t_end=1.0, step=1e-3, method="generalized-alpha")

Kernels (O(n) per evaluation) are in ``planar_kernels``; the docs are in docs/theory.md,
"Planar formulation".
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
import scipy.linalg

from ..errors import SolverError
from . import planar_kernels as pk

END_CODES = {"free": pk.FREE, "pinned": pk.PINNED, "clamped": pk.CLAMPED}


# ====================================================================== base motion (eq. 8.69)

def _derivatives(f: Callable[[float], float], t: float, step: float = 1e-3):
    """Value, rate, acceleration of a scalar time function by 4th-order central differences."""
    fm2, fm1, f0, fp1, fp2 = (f(t - 2 * step), f(t - step), f(t), f(t + step), f(t + 2 * step))
    rate = (fm2 - 8.0 * fm1 + 8.0 * fp1 - fp2) / (12.0 * step)
    acc = (-fm2 + 16.0 * fm1 - 30.0 * f0 + 16.0 * fp1 - fp2) / (12.0 * step * step)
    return f0, rate, acc


@dataclass(frozen=True)
class BaseMotion:
    """Prescribed motion of the base point A_0 and of RFE 0's angle (eq. 8.69).

    Each of ``x``, ``y``, ``phi`` is a number (constant), a function ``t -> value`` (rate and
    acceleration by 4th-order central differences, step 1e-3 s) or a function
    ``t -> (value, rate, acceleration)``. ``phi=None``: the link's initial angle."""
    x: float | Callable = 0.0
    y: float | Callable = 0.0
    phi: float | Callable | None = None

    def evaluate(self, t: float, phi_default: float = 0.0):
        """(position, velocity, acceleration), each (3,): x0, y0, phi0 and their rates."""
        out = np.zeros((3, 3))
        for k, f in enumerate((self.x, self.y, self.phi)):
            if f is None:
                out[0, k] = phi_default
            elif callable(f):
                v = f(t)
                if np.ndim(v) == 0:
                    out[:, k] = _derivatives(f, t)
                else:
                    out[:, k] = v
            else:
                out[0, k] = float(f)
        return out[0], out[1], out[2]


def smooth_spin_up(final_rate: float, ramp_time: float, initial_angle: float = 0.0):
    """Angle profile phi(t) of Kane, Ryan & Banerjee (1987): rate rises smoothly from 0 to
    final_rate over ramp_time, then stays constant. Returns t -> (phi, rate, acceleration)."""
    w, T = final_rate, ramp_time

    def profile(t: float):
        if t < T:
            phi = w / T * (t * t / 2.0 + (T / (2 * math.pi)) ** 2 * (math.cos(2 * math.pi * t / T) - 1.0))
            rate = w / T * (t - T / (2 * math.pi) * math.sin(2 * math.pi * t / T))
            acc = w / T * (1.0 - math.cos(2 * math.pi * t / T))
        else:
            phi = w * (t - T / 2.0)
            rate = w
            acc = 0.0
        return initial_angle + phi, rate, acc

    return profile


# ====================================================================== model

@dataclass(frozen=True, eq=False)
class PlanarModel:
    """Frozen arrays of one planar link (section 8.3). nr = n + 1 RFEs, n SDEs."""
    mass: np.ndarray            # (nr,) kg, RFE mass m_i
    inertia: np.ndarray         # (nr,) kg*m^2, J_i about C_i (eq. 8.54)
    joint_start: np.ndarray     # (nr, 2) m, (a_ii, b_ii): A_i in RFE i's frame at C_i (Fig. 8.8)
    joint_end: np.ndarray       # (nr, 2) m, (a_{i,i+1}, b_{i,i+1}): A_{i+1} (for RFE n: end B)
    sde_stiffness: np.ndarray   # (n,) N*m/rad, SDE i joins RFE i and i+1 (eq. 8.62)
    sde_damping: np.ndarray     # (n,) N*m*s/rad (eq. 8.63)
    sde_rest_angle: np.ndarray  # (n,) rad, phi_{i+1} - phi_i at which SDE i is unloaded
    gravity: float              # m/s^2 along -y
    end_a: int                  # 0 free, 1 pinned, 2 clamped (base, eq. 8.69)
    end_b: int
    end_b_position: np.ndarray  # (2,) m, fixed point of a pinned/clamped end B
    end_b_angle: float          # rad, phi_n of a clamped end B
    load_rfe: np.ndarray        # (nl,) int, RFE carrying point load k
    load_offset: np.ndarray     # (nl, 2) m, application point from C_i in RFE i's frame (r, gamma of eq. 8.64)
    load_force: np.ndarray      # (nl, 2) N, dead force (P_x, P_y)
    load_moment: np.ndarray     # (nl,) N*m, moment M_i
    q_initial: np.ndarray       # (n+3,) initial (undeformed) coordinates
    base_motion: BaseMotion = field(default_factory=BaseMotion)
    length: float = 0.0         # m
    z_in: np.ndarray = field(init=False)    # (nr, 2) A_i -> C_i in RFE frame
    z_out: np.ndarray = field(init=False)   # (nr, 2) A_i -> A_{i+1} in RFE frame

    def __post_init__(self):
        object.__setattr__(self, "z_in", np.ascontiguousarray(-self.joint_start))
        object.__setattr__(self, "z_out", np.ascontiguousarray(self.joint_end - self.joint_start))

    @property
    def nrfe(self) -> int:
        return self.mass.shape[0]

    @property
    def ncoord(self) -> int:
        return self.mass.shape[0] + 2

    def prescribed(self) -> np.ndarray:
        """(3,) bool: which of x, y, phi_0 follow the base motion."""
        return np.array([self.end_a >= pk.PINNED, self.end_a >= pk.PINNED, self.end_a == pk.CLAMPED])

    def free_mask(self) -> np.ndarray:
        mask = np.ones(self.ncoord, dtype=bool)
        mask[:3] = ~self.prescribed()
        return mask

    def base_state(self, t: float):
        return self.base_motion.evaluate(t, self.q_initial[2])

    def with_loads(self, scale: float) -> "PlanarModel":
        """A copy with every point load scaled (gravity unchanged)."""
        import dataclasses
        return dataclasses.replace(self, load_force=self.load_force * scale, load_moment=self.load_moment * scale)


def planar_beam(length: float, bending_stiffness: float, mass_per_length: float, elements: int,
                end_a: str = "clamped", end_b: str = "free", axial_stiffness: float | None = None,
                shear_stiffness: float | None = None, bending_damping: float = 0.0,
                rotary_inertia_per_length: float = 0.0, gravity: float = 0.0, angle: float = 0.0,
                base_motion: BaseMotion | None = None, tip_force: Sequence[float] = (0.0, 0.0),
                tip_moment: float = 0.0, point_loads: Sequence[tuple] = ()) -> PlanarModel:
    """A straight uniform link from A_0 = (x0, y0) at inclination ``angle``.

    Primary division into ``elements`` = n segments of length d = L/n; an SDE at the middle
    of each; RFE 0 and RFE n of length d/2, RFEs 1..n-1 of length d (docs/theory.md,
    section 1). ``elements=0`` gives one rigid RFE (the chapter's n_k = 0). RFE mass
    m_i = mu l_i, inertia m_i l_i^2/12 + rho_I l_i; SDE stiffness EI/d (eq. 8.88), damping
    bending_damping/d. ``axial_stiffness`` and ``shear_stiffness`` (EA, GA) must be None:
    the planar formulation of section 8.3 is inextensible and rigid in shear. Point loads:
    (arc_length, Fx, Fy, moment) as dead loads at that point; tip_force / tip_moment act at
    the end B."""
    for name, value in (("axial_stiffness", axial_stiffness), ("shear_stiffness", shear_stiffness)):
        if value is not None and math.isfinite(value):
            raise ValueError(f"{name}: the planar formulation (eq. 8.52) is inextensible and rigid in shear; "
                             f"leave it None or use the classical formulation")
    if not length > 0:
        raise ValueError("length: must be > 0")
    if elements < 0 or int(elements) != elements:
        raise ValueError("elements: must be an integer >= 0")
    if not mass_per_length > 0:
        raise ValueError("mass_per_length: must be > 0")
    if bending_stiffness < 0:
        raise ValueError("bending_stiffness: must be >= 0")
    for name, value in (("end_a", end_a), ("end_b", end_b)):
        if value not in END_CODES:
            raise ValueError(f"{name}: must be one of {sorted(END_CODES)}, got {value!r}")
    n = int(elements)
    if n == 0:
        lengths = np.array([length])
    else:
        d = length / n
        lengths = np.full(n + 1, d)
        lengths[0] = lengths[-1] = d / 2
    nr = lengths.shape[0]
    starts = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
    mass = mass_per_length * lengths
    inertia = mass * lengths ** 2 / 12.0 + rotary_inertia_per_length * lengths
    joint_start = np.zeros((nr, 2))
    joint_end = np.zeros((nr, 2))
    joint_start[:, 0] = -lengths / 2
    joint_end[:, 0] = lengths / 2
    d = length / max(n, 1)
    stiffness = np.full(n, bending_stiffness / d)
    damping = np.full(n, bending_damping / d)
    rest = np.zeros(n)
    loads = [(length, tip_force[0], tip_force[1], tip_moment)] if (any(tip_force) or tip_moment) else []
    loads += [tuple(p) for p in point_loads]
    load_rfe, load_offset, load_force, load_moment = [], [], [], []
    for s, fx, fy, mz in loads:
        if not 0.0 <= s <= length:
            raise ValueError(f"point_loads: arc length {s} outside [0, {length}]")
        i = int(min(np.searchsorted(starts, s, side="right") - 1, nr - 1))
        load_rfe.append(i)
        load_offset.append((s - starts[i] - lengths[i] / 2, 0.0))
        load_force.append((fx, fy))
        load_moment.append(mz)
    motion = base_motion or BaseMotion()
    pos, _, _ = motion.evaluate(0.0, angle)
    q0 = np.concatenate([[pos[0], pos[1]], np.full(nr, angle)])
    if end_a == "clamped":
        q0[2:] = pos[2]
    model = PlanarModel(
        mass=mass, inertia=inertia, joint_start=joint_start, joint_end=joint_end,
        sde_stiffness=stiffness, sde_damping=damping, sde_rest_angle=rest, gravity=float(gravity),
        end_a=END_CODES[end_a], end_b=END_CODES[end_b], end_b_position=np.zeros(2), end_b_angle=float(q0[-1]),
        load_rfe=np.array(load_rfe, dtype=np.int64), load_offset=np.array(load_offset, dtype=float).reshape(-1, 2),
        load_force=np.array(load_force, dtype=float).reshape(-1, 2), load_moment=np.array(load_moment, dtype=float),
        q_initial=q0, base_motion=motion, length=float(length))
    object.__setattr__(model, "end_b_position", np.array(pk.end_point(q0, model.z_out)))
    return model


# ====================================================================== workspace and evaluation

class PlanarWork:
    """Every buffer the kernels need, allocated once per model."""

    def __init__(self, model: PlanarModel):
        nr = model.nrfe
        ng = nr + 1
        self.rot = np.zeros((nr, 2))
        self.pc = np.zeros((nr, 2))
        self.vc = np.zeros((nr, 2))
        self.ac = np.zeros((nr, 2))
        self.force = np.zeros((nr, 3))
        self.g_left = np.zeros((ng, 3, 3))
        self.g_right = np.zeros((ng, 3, 3))
        self.gamma = np.zeros((ng, 3))
        self.active = np.zeros((ng, 3), dtype=np.bool_)
        self.diag = np.zeros((ng, 3, 3))
        self.upper = np.zeros((ng, 3, 3))
        self.rhs = np.zeros((ng, 3))
        self.tmp33 = np.zeros((3, 3))
        self.tmp3 = np.zeros((3, 1))
        self.reaction = np.zeros((ng, 3))
        self.k_diag = np.zeros(nr)
        self.suffix = np.zeros((nr, 2))
        size = 6 * nr + 3
        self.ab = np.zeros((2 * pk.HALF_BANDWIDTH + 1, size))
        self.kkt_rhs = np.zeros(size)
        self.r = np.zeros(model.ncoord)
        self.dq = np.zeros(model.ncoord)

    def schur(self):
        return (self.rot, self.pc, self.vc, self.ac, self.force, self.g_left, self.g_right, self.gamma,
                self.active, self.diag, self.upper, self.rhs, self.tmp33, self.tmp3)


def _loads(model: PlanarModel):
    return model.load_rfe, model.load_offset, model.load_force, model.load_moment


def accelerations(model: PlanarModel, q, qd, t: float = 0.0, work: PlanarWork | None = None,
                  load_factor: float = 1.0):
    """Generalised accelerations qdd (n+3,) and constraint forces (nr+1, 3) (base, joints,
    end B; eqs. 8.66-8.70) at the state (q, qd) and time t. Prescribed coordinates must be
    set in q, qd by the caller."""
    w = work or PlanarWork(model)
    _, _, base_acc = model.base_state(t)
    qdd = np.zeros(model.ncoord)
    pk.accelerations(np.asarray(q, float), np.asarray(qd, float), base_acc, model.mass, model.inertia,
                     model.z_in, model.z_out, model.sde_stiffness, model.sde_damping, model.sde_rest_angle,
                     model.gravity, model.end_a, model.end_b, *_loads(model), load_factor, qdd, w.reaction,
                     *w.schur())
    return qdd, w.reaction.copy()


def residual(model: PlanarModel, q, qd, qdd, end_reaction=(0.0, 0.0, 0.0), work: PlanarWork | None = None,
             load_factor: float = 1.0) -> np.ndarray:
    """r = A qdd + B qd + C q + dVg/dq - Q - K_B R_B (eq. 8.66/8.68), O(n)."""
    w = work or PlanarWork(model)
    r = np.zeros(model.ncoord)
    pk.residual(np.asarray(q, float), np.asarray(qd, float), np.asarray(qdd, float), model.mass, model.inertia,
                model.z_in, model.z_out, model.sde_stiffness, model.sde_damping, model.sde_rest_angle,
                model.gravity, *_loads(model), load_factor, np.asarray(end_reaction, float), r,
                w.rot, w.pc, w.vc, w.ac, w.force)
    return r


def kinetic_energy(model: PlanarModel, q, qd) -> float:
    w = PlanarWork(model)
    return pk.kinetic_energy(np.asarray(q, float), np.asarray(qd, float), model.mass, model.inertia,
                             model.z_in, model.z_out, w.rot, w.pc, w.vc, w.ac)


def potential_energy(model: PlanarModel, q) -> float:
    """Gravity (eq. 8.60, zero at y = 0), SDE strain energy and the potential of the dead
    point loads (-P . r_P - M phi)."""
    w = PlanarWork(model)
    q = np.asarray(q, float)
    zero = np.zeros_like(q)
    pk.body_kinematics(q, zero, zero, model.z_in, model.z_out, w.rot, w.pc, w.vc, w.ac)
    v = model.gravity * float(model.mass @ w.pc[:, 1])
    rel = np.diff(q[2:]) - model.sde_rest_angle
    v += 0.5 * float(model.sde_stiffness @ rel ** 2)
    for k in range(model.load_rfe.shape[0]):
        i = model.load_rfe[k]
        c, s = w.rot[i]
        p = w.pc[i] + np.array([c * model.load_offset[k, 0] - s * model.load_offset[k, 1],
                                s * model.load_offset[k, 0] + c * model.load_offset[k, 1]])
        v -= float(model.load_force[k] @ p) + model.load_moment[k] * q[2 + i]
    return v


def mass_matrix(model: PlanarModel, q) -> np.ndarray:
    """Dense A(q) of eq. 8.57 (n+3 square) as J^T M J from the body Jacobian; O(n^2)."""
    q = np.asarray(q, float)
    nr = model.nrfe
    J = np.zeros((3 * nr, model.ncoord))
    c = np.cos(q[2:])
    s = np.sin(q[2:])
    rin = np.stack([c * model.z_in[:, 0] - s * model.z_in[:, 1], s * model.z_in[:, 0] + c * model.z_in[:, 1]], 1)
    rout = np.stack([c * model.z_out[:, 0] - s * model.z_out[:, 1], s * model.z_out[:, 0] + c * model.z_out[:, 1]], 1)
    for l in range(nr):
        J[3 * l, 0] = J[3 * l + 1, 1] = 1.0
        for j in range(l):
            J[3 * l, 2 + j] = -rout[j, 1]
            J[3 * l + 1, 2 + j] = rout[j, 0]
        J[3 * l, 2 + l] = -rin[l, 1]
        J[3 * l + 1, 2 + l] = rin[l, 0]
        J[3 * l + 2, 2 + l] = 1.0
    mdiag = np.repeat(model.mass, 3)
    mdiag[2::3] = model.inertia
    return J.T @ (mdiag[:, None] * J)


def tip_position(model: PlanarModel, q) -> np.ndarray:
    return np.array(pk.end_point(np.asarray(q, float), model.z_out))


def joint_positions(model: PlanarModel, q) -> np.ndarray:
    """(n+2, 2): A_0, A_1..A_n (the SDEs), B."""
    q = np.asarray(q, float)
    c = np.cos(q[2:])
    s = np.sin(q[2:])
    steps = np.stack([c * model.z_out[:, 0] - s * model.z_out[:, 1], s * model.z_out[:, 0] + c * model.z_out[:, 1]], 1)
    return np.vstack([q[:2], q[:2] + np.cumsum(steps, axis=0)])


def _end_violation(model: PlanarModel, q) -> np.ndarray:
    v = np.zeros(3)
    if model.end_b >= pk.PINNED:
        v[:2] = tip_position(model, q) - model.end_b_position
    if model.end_b == pk.CLAMPED:
        v[2] = q[-1] - model.end_b_angle
    return v


def _newton_correction(model: PlanarModel, w: PlanarWork, q, qd, r, violation, c_m, c_d, c_k, load_factor,
                       end_reaction=np.zeros(3)):
    """Solve the banded KKT system for the correction of the Newton unknown
    (dq for statics, dqdd for generalised-alpha) and the change of the end-B multiplier."""
    pk.load_stiffness(w.rot, model.mass, model.z_in, model.z_out, model.gravity, model.load_rfe,
                      model.load_offset, model.load_force, load_factor, np.asarray(end_reaction, float)[:2],
                      w.k_diag, w.suffix)
    pk.assemble_kkt(w.rot, qd, model.mass, model.inertia, model.z_in, model.z_out, model.sde_stiffness,
                    model.sde_damping, w.k_diag, c_m, c_d, c_k, model.end_a, model.end_b, r, violation,
                    w.ab, w.kkt_rhs, w.g_left, w.g_right, w.gamma, w.active, np.zeros(3))
    u = pk.HALF_BANDWIDTH
    x = scipy.linalg.solve_banded((u, u), w.ab, w.kkt_rhs, overwrite_ab=True, overwrite_b=False,
                                  check_finite=False)
    pk.correction_from_kkt(w.rot, model.z_in, x, model.nrfe, w.dq)
    w.dq[:3][model.prescribed()] = 0.0      # zero up to round-off from the base constraint rows
    nr = model.nrfe
    dmu = -x[6 * nr:6 * nr + 3]   # lam of end group: generalised force -(G J)^T lam
    return w.dq.copy(), dmu


# ====================================================================== statics

@dataclass
class PlanarStatics:
    q: np.ndarray                   # (n+3,) equilibrium coordinates
    end_reaction: np.ndarray        # (3,) force and moment of a fixed end B on the link
    base_reaction: np.ndarray       # (3,) force (at A_0) and moment of the base on the link
    iterations: int
    residual_norm: float
    load_steps: int


def planar_statics(model: PlanarModel, q_start=None, load_steps: int = 1, tolerance: float = 1e-10,
                   max_iterations: int = 50, t: float = 0.0) -> PlanarStatics:
    """Static equilibrium by Newton's method with load ramping (gravity and point loads scaled
    by k/load_steps; a step that fails is halved, down to 1/1024 of the load). The tangent is
    exact (C + load stiffness, banded KKT with the end-B constraint); backtracking line
    search on the residual norm."""
    w = PlanarWork(model)
    pos, _, _ = model.base_state(t)
    q = np.array(model.q_initial if q_start is None else q_start, float)
    pres = model.prescribed()
    q[:3][pres] = pos[pres]
    qd = np.zeros_like(q)
    mu = np.zeros(3)
    free = model.free_mask()
    total_iterations = 0
    lam, dlam = 0.0, 1.0 / load_steps
    steps = 0
    scale = _force_scale(model)

    def norm(r, mu_, q_):
        return math.hypot(np.linalg.norm(r[free]) / scale, np.linalg.norm(_end_violation(model, q_)) / model.length)

    while lam < 1.0 - 1e-14:
        target = min(1.0, lam + dlam)
        q_try, mu_try = q.copy(), mu.copy()
        converged = False
        for it in range(max_iterations):
            r = residual(model, q_try, qd, qd, mu_try, w, target)
            viol = _end_violation(model, q_try)
            res = norm(r, mu_try, q_try)
            if res < tolerance and it > 0:
                converged = True
                break
            dq, dmu = _newton_correction(model, w, q_try, qd, r, viol, 0.0, 0.0, 1.0, target, mu_try)
            total_iterations += 1
            step = 1.0
            for _ in range(30):
                q_new = q_try + step * dq
                mu_new = mu_try + step * dmu
                r_new = residual(model, q_new, qd, qd, mu_new, w, target)
                if norm(r_new, mu_new, q_new) < res or step < 1e-3:
                    break
                step *= 0.5
            q_try, mu_try = q_new, mu_new
            if not np.all(np.isfinite(q_try)):
                break
        if converged:
            q, mu, lam = q_try, mu_try, target
            steps += 1
            dlam = min(dlam * 1.5, 1.0 / load_steps * 4)
        else:
            dlam *= 0.5
            if dlam < 1.0 / 1024 / load_steps:
                raise SolverError(f"planar statics: Newton did not converge at load factor {target:.4g} "
                                  f"(residual {res:.3g})")
    r = residual(model, q, qd, qd, mu, w, 1.0)
    base = np.zeros(3)
    base[:3][pres] = r[:3][pres]
    return PlanarStatics(q=q, end_reaction=mu, base_reaction=base, iterations=total_iterations,
                         residual_norm=norm(r, mu, q), load_steps=steps)


def _force_scale(model: PlanarModel) -> float:
    """Moment scale of the applied loads (N*m): (weight + point forces) * L + point moments;
    the statics tolerance is relative to it (not to the SDE stiffness, so tiny loads converge)."""
    total = (float(model.mass.sum()) * model.gravity + float(np.abs(model.load_force).sum())) * model.length
    total += float(np.abs(model.load_moment).sum())
    return total if total > 0.0 else 1.0


# ====================================================================== modes

@dataclass
class PlanarModes:
    frequencies_hz: np.ndarray      # (nmodes,), negative for unstable modes (omega^2 < 0)
    shapes: np.ndarray              # (nmodes, n+3) generalised-coordinate shapes, zero on prescribed coordinates


def planar_modes(model: PlanarModel, q=None, count: int = 10) -> PlanarModes:
    """Natural frequencies about a static state q (default: statics of the model): K x =
    omega^2 A x on the free coordinates, K = C + load stiffness (exact tangent of eqs.
    8.61-8.64 at zero velocity), A of eq. 8.57. End B must be free. An unstable mode
    (omega^2 < 0) has a negative frequency -sqrt(-omega^2) / (2 pi), listed first."""
    if model.end_b != pk.FREE:
        raise ValueError("end_b: planar_modes supports a free end B only")
    if q is None:
        q = planar_statics(model).q
    q = np.asarray(q, float)
    w = PlanarWork(model)
    zero = np.zeros_like(q)
    pk.body_kinematics(q, zero, zero, model.z_in, model.z_out, w.rot, w.pc, w.vc, w.ac)
    pk.load_stiffness(w.rot, model.mass, model.z_in, model.z_out, model.gravity, model.load_rfe,
                      model.load_offset, model.load_force, 1.0, np.zeros(2), w.k_diag, w.suffix)
    m = model.ncoord
    K = np.zeros((m, m))
    K[2:, 2:] += np.diag(w.k_diag)
    for j, c in enumerate(model.sde_stiffness):
        K[2 + j:4 + j, 2 + j:4 + j] += c * np.array([[1.0, -1.0], [-1.0, 1.0]])
    A = mass_matrix(model, q)
    free = model.free_mask()
    Kf, Af = K[np.ix_(free, free)], A[np.ix_(free, free)]
    lam, vec = scipy.linalg.eigh(Kf, Af)
    count = min(count, lam.size)
    shapes = np.zeros((count, m))
    shapes[:, free] = vec[:, :count].T
    from ..solvers.modal import signed_omega
    omega = signed_omega(lam[:count], float(np.abs(lam).max()) if lam.size else 0.0)
    return PlanarModes(frequencies_hz=omega / (2 * math.pi), shapes=shapes)


# ====================================================================== dynamics

@dataclass
class PlanarDynamics:
    t: np.ndarray                   # (nt,) s
    q: np.ndarray                   # (nt, n+3)
    qd: np.ndarray                  # (nt, n+3)
    method: str
    steps: int
    newton_iterations: int = 0
    success: bool = True
    message: str = ""

    def tip(self, model: PlanarModel) -> np.ndarray:
        """(nt, 2) position of end B."""
        return np.array([tip_position(model, qi) for qi in self.q])


def planar_dynamics(model: PlanarModel, t_end: float, step: float, q0=None, qd0=None,
                    method: str = "rk4", record_every: int = 1, rho_inf: float = 0.8,
                    tolerance: float = 1e-9, max_iterations: int = 25, progress=None) -> PlanarDynamics:
    """Time integration from t = 0. ``rk4``: fixed-step classical Runge-Kutta on the O(n)
    forward dynamics, the whole loop compiled (end-B constraints are then held at the
    acceleration level only and drift as O(h^4)). ``generalized-alpha``: Chung-Hulbert
    with spectral radius rho_inf at infinite frequency, Newton on the banded KKT system
    (O(n) per iteration), end-B constraints at the position level (index 3).

    ``progress(fraction)`` is called after recorded outputs (generalized-alpha: every one;
    rk4: after each compiled stretch of about a hundredth of the run). A KeyboardInterrupt
    (Ctrl-C, or one the progress callback raises) propagates with the outputs recorded so
    far as ``history`` (a PlanarDynamics, success False, message "interrupted at t = ...")."""
    q = np.array(model.q_initial if q0 is None else q0, float)
    qd = np.zeros_like(q) if qd0 is None else np.array(qd0, float)
    nsteps = int(round(t_end / step))
    if nsteps < 1:
        raise ValueError("step: must be smaller than t_end")
    if method == "rk4":
        return _rk4(model, q, qd, step, nsteps, record_every, progress)
    if method in ("generalized-alpha", "generalised-alpha"):
        return _generalized_alpha(model, q, qd, step, nsteps, record_every, rho_inf, tolerance, max_iterations,
                                  progress)
    raise ValueError(f"method: must be 'rk4' or 'generalized-alpha', got {method!r}")


RK4_STRETCHES = 100     # the compiled RK4 runs in about this many stretches (progress, Ctrl-C between them)


def _interrupted(exc, t, q_out, qd_out, rec, method, steps):
    """Attach the first ``rec`` recorded outputs to a KeyboardInterrupt as ``history``."""
    exc.history = PlanarDynamics(t=t[:rec].copy(), q=q_out[:rec].copy(), qd=qd_out[:rec].copy(), method=method,
                                 steps=steps, success=False,
                                 message=f"interrupted at t = {t[rec - 1]:.6g} s") if rec else None


def _rk4(model, q, qd, h, nsteps, record_every, progress=None):
    pres = model.prescribed()
    base = np.zeros((3, nsteps, 3, 3))   # (pos/vel/acc, step, stage, comp)
    for k in range(nsteps):
        for si, dt in enumerate((0.0, 0.5 * h, h)):
            p, v, a = model.base_state(k * h + dt)
            base[0, k, si], base[1, k, si], base[2, k, si] = p, v, a
    q[:3][pres] = base[0, 0, 0][pres]
    qd[:3][pres] = base[1, 0, 0][pres]
    nrec = nsteps // record_every + 1
    q_out = np.zeros((nrec, q.size))
    qd_out = np.zeros((nrec, q.size))
    t = np.arange(nrec) * h * record_every
    w = PlanarWork(model)
    args = (model.mass, model.inertia, model.z_in, model.z_out, model.sde_stiffness, model.sde_damping,
            model.sde_rest_angle, model.gravity, model.end_a, model.end_b, *_loads(model), record_every)
    # stretches of whole output intervals; the kernel writes the stretch's start into its row 0
    # (the previous stretch's last output, the same values) and the outputs after it
    per = max(1, (nrec - 1) // RK4_STRETCHES)
    done = 0            # steps integrated
    rec = 1             # outputs recorded (row 0: the initial state, written by the first stretch)
    q_out[0], qd_out[0] = q, qd
    try:
        while done < nsteps:
            m = min(per * record_every, nsteps - done)
            r0 = done // record_every
            ok = pk.rk4_run(q, qd, h, m, base[0, done:done + m], base[1, done:done + m], base[2, done:done + m],
                            pres, *args, q_out[r0:], qd_out[r0:], *w.schur(), w.reaction)
            if not ok:
                raise SolverError("planar RK4: state became non-finite (step too large?)")
            done += m
            rec = done // record_every + 1
            if progress is not None:
                progress(done / nsteps)
    except KeyboardInterrupt as exc:
        _interrupted(exc, t, q_out, qd_out, rec, "rk4", done)
        raise
    return PlanarDynamics(t=t, q=q_out, qd=qd_out, method="rk4", steps=nsteps)


def genalpha_parameters(rho_inf: float):
    """Chung & Hulbert (1993): alpha_m, alpha_f, beta, gamma for spectral radius rho_inf."""
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 - am + af
    beta = 0.25 * (1.0 - am + af) ** 2
    return am, af, beta, gamma


def start_acceleration(model: PlanarModel, w: PlanarWork, q, qd, qdd, end_reaction, c_q: float, c_v: float,
                       tol: float) -> np.ndarray:
    """The generalised-alpha algorithmic acceleration to start from, as
    rfesim.solvers.dynamics.start_acceleration for absolute-coordinate lines:
    a_0 = (A + c_v B + c_q C)^-1 A qdd_0 over the free coordinates (the step's Newton
    matrix, with the end-B constraint held at the acceleration level), the prescribed ones
    at their qdd_0. In the modes the step resolves a_0 = qdd_0 (1 - O(c_q omega^2)), which
    keeps the method second order; in a stiff mode a_0 ~ 0, where qdd_0 starts the method's
    overshoot (docs/theory.md, 'Starting generalised-alpha'). A start whose qdd_0 moves the
    step's prediction by no more than the Newton tolerance (tol times the link length; a
    static equilibrium's round-off) keeps qdd_0."""
    free = model.free_mask()
    if np.linalg.norm(qdd[free]) * c_q <= tol * model.length:
        return qdd.copy()
    qz = qdd.copy()
    qz[free] = 0.0
    r = residual(model, q, qd, qz, end_reaction, w)       # -A qdd_0 on the free coordinates
    dq, _ = _newton_correction(model, w, q, qd, r, np.zeros(3), 1.0, c_v, c_q, 1.0, end_reaction)
    if not np.all(np.isfinite(dq)):
        return qdd.copy()
    dq[~free] = 0.0
    return qz + dq


def _generalized_alpha(model, q, qd, h, nsteps, record_every, rho_inf, tol, max_iterations, progress=None):
    am, af, beta, gamma = genalpha_parameters(rho_inf)
    w = PlanarWork(model)
    pres = model.prescribed()
    free = model.free_mask()
    p, v, a0 = model.base_state(0.0)
    q[:3][pres] = p[pres]
    qd[:3][pres] = v[pres]
    qdd, reac = accelerations(model, q, qd, 0.0, w)
    mu = reac[-1].copy()                 # end-B reaction on the link
    c_q = h * h * beta * (1.0 - af) / (1.0 - am)       # d q_{n+1} / d qdd_{n+1}
    c_v = h * gamma * (1.0 - af) / (1.0 - am)          # d qd_{n+1} / d qdd_{n+1}
    acc_alg = start_acceleration(model, w, q, qd, qdd, mu, c_q, c_v, tol)   # algorithmic acceleration a_n
    nrec = nsteps // record_every + 1
    q_out = np.zeros((nrec, q.size))
    qd_out = np.zeros((nrec, q.size))
    q_out[0], qd_out[0] = q, qd
    newton_total = 0
    rec = 1
    k = 0
    try:
        for k in range(nsteps):
            t1 = (k + 1) * h
            p, v, a_base = model.base_state(t1)
            qdd1 = qdd.copy()
            qdd1[:3][pres] = a_base[pres]

            def update(qdd_new):
                a_new = ((1.0 - af) * qdd_new + af * qdd - am * acc_alg) / (1.0 - am)
                q_new = q + h * qd + h * h * ((0.5 - beta) * acc_alg + beta * a_new)
                v_new = qd + h * ((1.0 - gamma) * acc_alg + gamma * a_new)
                q_new[:3][pres] = p[pres]
                v_new[:3][pres] = v[pres]
                return a_new, q_new, v_new

            a1, q1, v1 = update(qdd1)
            converged = False
            for it in range(max_iterations):
                r = residual(model, q1, v1, qdd1, mu, w)
                viol = _end_violation(model, q1)
                dqdd, dmu = _newton_correction(model, w, q1, v1, r, viol, 1.0, c_v, c_q, 1.0, mu)
                newton_total += 1
                dqdd[:3][pres] = 0.0
                qdd1 += dqdd
                mu += dmu
                a1, q1, v1 = update(qdd1)
                if np.linalg.norm(dqdd[free]) * c_q <= tol * model.length:
                    converged = True
                    break
            if not converged or not np.all(np.isfinite(q1)):
                q_out, qd_out = q_out[:rec], qd_out[:rec]
                return PlanarDynamics(t=np.arange(rec) * h * record_every, q=q_out, qd=qd_out,
                                      method="generalized-alpha", steps=k, newton_iterations=newton_total,
                                      success=False, message=f"Newton did not converge at t = {t1:.6g} s")
            q, qd, qdd, acc_alg = q1, v1, qdd1, a1
            if (k + 1) % record_every == 0:
                q_out[rec], qd_out[rec] = q, qd
                rec += 1
                if progress is not None:
                    progress((k + 1) / nsteps)
    except KeyboardInterrupt as exc:
        _interrupted(exc, np.arange(nrec) * h * record_every, q_out, qd_out, rec, "generalized-alpha", k)
        raise
    return PlanarDynamics(t=np.arange(nrec) * h * record_every, q=q_out, qd=qd_out, method="generalized-alpha",
                          steps=nsteps, newton_iterations=newton_total)
