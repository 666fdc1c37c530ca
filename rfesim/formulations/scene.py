"""Scenarios in the classical (8.1), modified (8.2) and planar (8.3) formulations and
scenario ``chains``: compile, statics, dynamics, modes -> the usual Results / ModalResults.

`rfesim.statics`, `rfesim.simulate` and `rfesim.modes` come here when a scenario has a line
whose ``formulation`` is not ``"absolute"`` or has ``chains`` (`uses_formulations`). The
scenario checks (`rfesim.scenario.chains.check_formulations`) have already refused what is
not supported (mixing with absolute lines, sea loads, a fixed end B, ...).

Compilation: every classical/modified line becomes a one-link `Chain` on its end A (fixed
or a vessel: the vessel's motion is the base motion, eq. 8.10.2), clamped (fixed joint) or
pinned (spherical joint), its axis along ``end_a.direction``; every scenario chain becomes a
`Chain`; every planar line a `PlanarModel` in the vertical plane through its end-A
direction. The units are uncoupled, so advancing each with the same fixed step is the same
as one integrator over the block-diagonal system.

Outputs, per line (and per chain link, named ``"chain.link"``), with the channel names of
the absolute formulation: position of end A, every SDE and end B; tension, shear force,
bend moment and torque at each SDE from Newton's law for the part of the line beyond the
SDE (the sum of m (a - g) - external loads over its bodies and of the moments about the SDE,
exact in statics and dynamics and for every formulation, including a modified link that has
no axial spring); curvature = bending part of the relative rotation of the two RFEs over
the SDE spacing; forces and moments on the end-A attachment and on links carried at the tip.
"""
from __future__ import annotations

import logging
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from ..errors import SolverError
from ..results import JointResults, LineResults, Results
from ..scenario.chains import line_frame, planar_axes
from . import energy_check
from . import planar as pl
from . import planar_kernels as pk
from . import tree
from .chain import (
    BaseMotion,
    Chain,
    ChainData,
    Joint,
    JointForce,
    Prescribed,
    accelerations,
    chain_modes,
    chain_statics,
    fill_prescribed,
    simulate_chain,
)
from .classical import ClassicalLink, linear_modes
from .energy_check import open_terms
from .links import BeamProperties, RigidLink
from .modified import ModifiedLink
from .transforms import SPHERICAL


log = logging.getLogger("rfesim")


def uses_formulations(sc) -> bool:
    """True when the scenario needs this module (non-absolute lines or chains)."""
    return bool(getattr(sc, "chains", None)) or any(ln.formulation != "absolute" for ln in sc.lines.values())


# ============================================================================ compile
class VesselBase(BaseMotion):
    """The base frame {A} = a vessel frame: (T_A, T_A', T_A'') from the vessel's pose,
    velocity and acceleration (eq. 8.10.2)."""

    def __init__(self, motion):
        super().__init__()
        self.motion = motion

    def __call__(self, t: float):
        k = self.motion.kinematics(t)
        W = _skew(k.w)
        TA = np.eye(4)
        TA[:3, :3], TA[:3, 3] = k.R, k.p
        TAd = np.zeros((4, 4))
        TAd[:3, :3], TAd[:3, 3] = W @ k.R, k.v
        TAdd = np.zeros((4, 4))
        TAdd[:3, :3], TAdd[:3, 3] = (_skew(k.alpha) + W @ W) @ k.R, k.a
        return TA, TAd, TAdd


def _skew(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def _base(sc, attach: str) -> BaseMotion:
    if attach == "fixed":
        return BaseMotion()
    from ..vessel import make_vessel_motion
    return VesselBase(make_vessel_motion(sc.vessels[attach], sc.environment))


def beam_properties(sc, type_name: str, length: float, elements: int, shear: str | None) -> BeamProperties:
    """BeamProperties of a scenario line type, with the absolute compiler's defaults (shear
    model, torsion inertia) so that the formulations discretise the same beam."""
    from ..model.sections import section_from_type
    lt = sc.line_types[type_name]
    sec = section_from_type(lt)
    dx = length / elements
    if shear is None:
        shear = "kruszewski" if 12.0 * sec.EI_min / dx ** 3 < 1e-6 * sec.GA / dx else "fem"
    polar = max(sec.polar_inertia, 2.0 * (1.0 + lt.poisson_ratio) * sec.mass_per_length * sec.GJ / sec.EA)
    if polar <= 0.0:
        radius = 0.5 * sec.outer_diameter if sec.outer_diameter > 0 else 1e-3 * dx
        polar = sec.mass_per_length * radius * radius
    damping = 0.0
    if lt.damping is not None and lt.damping.bending and sec.EIy > 0.0:
        damping = lt.damping.bending / sec.EIy          # stiffness-proportional factor, s
    return BeamProperties(EA=sec.EA, EIy=sec.EIy, EIz=sec.EIz, GJ=sec.GJ, mass_per_length=sec.mass_per_length,
                          GA=sec.GA, shear=shear, rotary_inertia=sec.rotary_inertia, polar_inertia=polar,
                          damping=damping)


def _flexible_link(sc, type_name, length, elements, formulation, dofs, shear=None):
    props = beam_properties(sc, type_name, length, elements, shear)
    if formulation == "modified":
        return ModifiedLink(length, elements, props, dofs=dofs)
    return ClassicalLink(length, elements, props, linear=formulation == "classical-linear", dofs=dofs)


def _arc(at, length):
    return 0.0 if at == "end_a" else (length if at == "end_b" else float(at))


def _profile(p):
    """t -> (q, q', q'') of a drive profile."""
    if p.kind == "harmonic":
        w, ph = 2.0 * math.pi / p.period, math.radians(p.phase_deg)
        return lambda t: (p.mean + p.amplitude * math.sin(w * t + ph), p.amplitude * w * math.cos(w * t + ph),
                          -p.amplitude * w * w * math.sin(w * t + ph))
    if p.kind == "spin-up":
        return pl.smooth_spin_up(p.rate, p.ramp_time, p.start)
    from scipy.interpolate import CubicSpline
    rows = np.asarray(p.rows, float)
    cs = CubicSpline(rows[:, 0], rows[:, 1], bc_type="natural")
    t0, t1 = rows[0, 0], rows[-1, 0]

    def table(t):
        if t <= t0 or t >= t1:
            return float(cs(min(max(t, t0), t1))), 0.0, 0.0
        return float(cs(t)), float(cs(t, 1)), float(cs(t, 2))
    return table


def _drive(d):
    if d.kind == "prescribed":
        return Prescribed(_profile(d.motion))
    if d.kind == "force":
        value, ramp = d.value, d.ramp_time

        def force(t, q, qd):
            s = 1.0 if ramp <= 0.0 or t >= ramp else 0.5 * (1.0 - math.cos(math.pi * t / ramp))
            return value * s
        return JointForce(force)
    return None


@dataclass
class OutputLine:
    """A results line: one link of a chain unit."""
    name: str                     # results name ("riser" or "crane.boom")
    link: str                     # link name in the chain model
    sde_spacing: float            # m
    serial: bool                  # modified / rigid: RFE i hangs on RFE i-1; classical: all on RFE 0


@dataclass
class ChainUnit:
    label: str                    # scenario path for messages ("lines.beam", "chains.crane")
    model: object                 # ChainModel
    q0: np.ndarray
    qd0: np.ndarray
    outputs: list
    linear_clamped: bool = False  # a clamped classical-linear line on a fixed base: sparse modes
    joints: dict = field(default_factory=dict)   # joint name -> coordinate indices
    cache: dict = field(default_factory=dict)
    open: list = field(default_factory=list)     # what feeds or drains its energy (energy_check.open_terms)


@dataclass
class PlanarUnit:
    label: str
    name: str
    model: object                 # PlanarModel
    e1: np.ndarray                # (3,) planar x in the global frame
    normal: np.ndarray            # (3,) plane normal; planar z = e1 x ez
    offset: float                 # m, position of the plane along the normal


@dataclass
class Scene:
    chains: list
    planars: list
    gravity: float


def compile_scene(sc) -> Scene:
    g = sc.environment.gravity
    gvec = (0.0, 0.0, -g)
    chains, planars = [], []
    for name, ln in sc.lines.items():
        if ln.formulation == "planar":
            planars.append(_planar_line(sc, name, ln))
            continue
        link = _flexible_link(sc, ln.type, ln.length, ln.elements, ln.formulation, ln.dofs, ln.shear_stiffness)
        R = line_frame(ln.end_a.direction)
        kind = "fixed" if ln.end_a.connection == "clamped" else "spherical"
        ch = Chain(gravity=gvec, base=_base(sc, ln.end_a.attach))
        ch.add(name, link, Joint(kind, offset=tuple(ln.end_a.position), rotation=R))
        for load in ln.loads:
            ch.add_load(name, _arc(load.at, ln.length), force=np.asarray(load.force, float),
                        moment=np.asarray(load.moment, float))
        model = ch.compile()
        out = OutputLine(name, name, ln.length / ln.elements, ln.formulation == "modified")
        chains.append(ChainUnit(f"lines.{name}", model, np.zeros(model.nq), np.zeros(model.nq), [out],
                                linear_clamped=(ln.formulation == "classical-linear" and kind == "fixed"
                                                and ln.end_a.attach == "fixed")))
        chains[-1].open = open_terms(chains[-1], _moving(sc, ln.end_a.attach))
    for cname, spec in getattr(sc, "chains", {}).items():
        chains.append(_chain_unit(sc, cname, spec, gvec))
        chains[-1].open = open_terms(chains[-1], _moving(sc, spec.base))
    return Scene(chains, planars, g)


def _moving(sc, attach: str) -> bool:
    """True when a unit's base moves: on a vessel whose motion is not ``fixed``."""
    return attach != "fixed" and getattr(sc.vessels[attach].motion, "kind", None) != "fixed"


def _chain_unit(sc, cname, spec, gvec) -> ChainUnit:
    ch = Chain(gravity=gvec, base=_base(sc, spec.base))
    outputs = []
    for jname in spec.order():
        j = spec.joints[jname]
        ls = spec.links[j.child]
        if ls.rigid:
            mass = ls.mass if ls.mass is not None else sc.line_types[ls.type].mass_per_length * ls.length
            if mass is None:       # a pipe-geometry type: mass from its section
                from ..model.sections import section_from_type
                mass = section_from_type(sc.line_types[ls.type]).mass_per_length * ls.length
            link = RigidLink(ls.length, mass, centre=ls.centre, inertia=ls.inertia)
            outputs.append(OutputLine(f"{cname}.{j.child}", j.child, ls.length, True))
        else:
            link = _flexible_link(sc, ls.type, ls.length, ls.elements, ls.formulation, ls.dofs)
            outputs.append(OutputLine(f"{cname}.{j.child}", j.child, ls.length / ls.elements,
                                      ls.formulation == "modified"))
        R = line_frame(j.direction)
        offset = np.asarray(j.position, float) + (np.asarray(spec.position, float) if j.parent == "base" else 0.0)
        axis = R.T @ np.asarray(j.axis, float) if j.axis is not None else "z"
        joint = Joint(j.kind, axis=axis, offset=tuple(offset), rotation=R, drive=_drive(j.drive),
                      stiffness=j.stiffness, damping=j.damping, rest=j.rest)
        ch.add(j.child, link, joint, parent=None if j.parent == "base" else j.parent, at=j.at)
        for load in ls.loads:
            ch.add_load(j.child, _arc(load.at, ls.length), force=np.asarray(load.force, float),
                        moment=np.asarray(load.moment, float))
    model = ch.compile()
    q0, qd0 = np.zeros(model.nq), np.zeros(model.nq)
    joints = {}
    for jname, j in spec.joints.items():
        idx = model.links[j.child].joint_coords
        joints[f"{cname}.{jname}"] = idx
        if len(idx):
            q0[idx] = j.initial
            qd0[idx] = j.initial_rate
    return ChainUnit(f"chains.{cname}", model, q0, qd0, outputs, joints=joints)


def _planar_line(sc, name, ln) -> PlanarUnit:
    from ..model.sections import section_from_type
    lt = sc.line_types[ln.type]
    sec = section_from_type(lt)
    d = np.asarray(ln.end_a.direction, float)
    e1, normal = planar_axes(d)
    ez = np.array([0.0, 0.0, 1.0])
    pz = np.cross(e1, ez)                      # planar z
    pA = np.asarray(ln.end_a.position, float)
    angle = math.atan2(d @ ez, d @ e1)
    loads = []
    for load in ln.loads:
        F, M = np.asarray(load.force, float), np.asarray(load.moment, float)
        loads.append((_arc(load.at, ln.length), F @ e1, F @ ez, M @ pz))
    damping = lt.damping.bending if (lt.damping is not None and lt.damping.bending) else 0.0
    model = pl.planar_beam(ln.length, sec.EIy, sec.mass_per_length, ln.elements,
                           end_a="clamped" if ln.end_a.connection == "clamped" else "pinned", end_b="free",
                           bending_damping=damping, rotary_inertia_per_length=sec.rotary_inertia,
                           gravity=sc.environment.gravity, angle=angle,
                           base_motion=pl.BaseMotion(x=float(pA @ e1), y=float(pA[2])), point_loads=loads)
    return PlanarUnit(f"lines.{name}", name, model, e1, normal, float(pA @ normal))


# ============================================================================ outputs
class _Kinematics:
    """Poses and their derivatives of a chain model (no mass-matrix buffers)."""

    def __init__(self, model):
        nb, nq = model.nbodies, model.nq
        self.model = model
        self.T, self.Td, self.Tdd = np.zeros((nb, 4, 4)), np.zeros((nb, 4, 4)), np.zeros((nb, 4, 4))
        self.Omega = np.zeros((nq, 4, 4))

    def run(self, t, q, qd, qdd):
        m = self.model
        TA, TAd, TAdd = m.base(t)
        tree.forward_pass(m.parent, m.kind, m.axis, m.placement, m.qstart, m.qcount, np.asarray(q, float),
                          np.asarray(qd, float), np.asarray(qdd, float), TA, TAd, TAdd, self.T, self.Td, self.Tdd,
                          self.Omega)
        return self


def _local(model, body, s):
    """Body-frame coordinates (4,) of the link-axis point at arc length s."""
    U = model.undeformed[body]                      # a rigid transformation: inverse [R^T, -R^T r]
    return np.append(U[:3, :3].T @ (np.array([s, 0.0, 0.0]) - U[:3, 3]), 1.0)


class _LinkGeometry:
    def __init__(self, model, out: OutputLine):
        info = model.links[out.link]
        self.first, self.nb = info.first_body, info.nbodies
        self.bodies = np.arange(self.first, self.first + self.nb)
        self.length = info.link.length
        d = out.sde_spacing
        if self.nb == 1:        # a rigid link: one section, at its root (the joint force and moment)
            self.nsde = 1
            self.sde_s = np.zeros(1)
            self.lb = self.rb = np.array([self.first])
        else:
            self.nsde = self.nb - 1
            self.sde_s = (np.arange(1, self.nsde + 1) - 0.5) * d
            self.lb = self.first + np.arange(self.nsde)
            self.rb = self.lb + 1
        self.arc = np.concatenate([[0.0], self.sde_s, [self.length]])
        self.pA = _local(model, self.first, 0.0)
        self.pB = _local(model, self.first + self.nb - 1, self.length)
        self.left = np.array([_local(model, b, s) for b, s in zip(self.lb, self.sde_s)]).reshape(-1, 4)
        self.right = np.array([_local(model, b, s) for b, s in zip(self.rb, self.sde_s)]).reshape(-1, 4)
        self.serial = out.serial
        self.spacing = d
        inside = set(self.bodies.tolist())
        last = self.first + self.nb - 1
        self.tip_children = np.array([b for b in range(model.nbodies) if model.parent[b] == last and b not in inside],
                                     dtype=np.int64)


def _chain_body_wrenches(model, kin, t):
    """Per body: f = sum m (a - g) - F_ext (3,), and the moment of the same about the global
    origin (3,), from the pseudo-inertia form T H (T'' + Gamma)^T (eqs. 8.11-8.20); then
    summed over each body's subtree."""
    Gamma = np.zeros((4, 4))
    Gamma[:3, 3] = -model.gravity
    F = kin.T @ model.inertia @ np.swapaxes(kin.Tdd + Gamma, 1, 2)
    f = F[:, 3, :3].copy()
    P = F[:, :3, :3]
    m = np.stack([P[:, 1, 2] - P[:, 2, 1], P[:, 2, 0] - P[:, 0, 2], P[:, 0, 1] - P[:, 1, 0]], axis=1)
    for k, b in enumerate(model.load_body):
        r = kin.T[b][:3] @ np.append(model.load_point[k], 1.0)
        Fk = np.asarray(model.load_force[k](t) if callable(model.load_force[k]) else model.load_force[k], float)
        Mk = np.asarray(model.load_moment[k](t) if callable(model.load_moment[k]) else model.load_moment[k], float)
        f[b] -= Fk
        m[b] -= np.cross(r, Fk) + Mk
    for b in range(model.nbodies - 1, -1, -1):
        p = model.parent[b]
        if p >= 0:
            f[p] += f[b]
            m[p] += m[b]
    return f, m


def _rotvec(R):
    from scipy.spatial.transform import Rotation
    return Rotation.from_matrix(R).as_rotvec()


def _link_outputs(model, kin, geo: _LinkGeometry, f, m):
    """One time point of a link: dict of channel -> array."""
    T = kin.T
    pts = np.empty((geo.nsde + 2, 3))
    pts[0] = T[geo.first][:3] @ geo.pA
    pts[-1] = T[geo.first + geo.nb - 1][:3] @ geo.pB
    out = {}
    n = geo.nsde
    tension, shear, bend, torque, curv = (np.zeros(n) for _ in range(5))
    for e in range(1, n + 1):
        bl, br = geo.lb[e - 1], geo.rb[e - 1]
        p = 0.5 * (T[bl][:3] @ geo.left[e - 1] + T[br][:3] @ geo.right[e - 1])
        pts[e] = p
        if geo.serial:
            D, Dm = f[br], m[br]
        else:                                   # classical: RFEs e..n all hang on RFE 0
            D, Dm = f[br:geo.first + geo.nb].sum(axis=0), m[br:geo.first + geo.nb].sum(axis=0)
        t = T[br][:3, 0]
        M = Dm - np.cross(p, D)                 # moment of the end-A side on the end-B side about the SDE
        tension[e - 1] = -D @ t
        shear[e - 1] = np.linalg.norm(D - (D @ t) * t)
        torque[e - 1] = M @ t
        bend[e - 1] = np.linalg.norm(M - (M @ t) * t)
        rv = _rotvec(T[bl][:3, :3].T @ T[br][:3, :3])
        curv[e - 1] = math.hypot(rv[1], rv[2]) / geo.spacing if bl != br else 0.0
    out["position"] = pts
    out.update(tension=tension, shear_force=shear, bend_moment=bend, torque=torque, curvature=curv)
    out["end_a_force"] = -f[geo.first]
    out["end_a_moment"] = -(m[geo.first] - np.cross(pts[0], f[geo.first]))
    fb = f[geo.tip_children].sum(axis=0) if len(geo.tip_children) else np.zeros(3)
    mb = m[geo.tip_children].sum(axis=0) if len(geo.tip_children) else np.zeros(3)
    out["end_b_force"] = fb
    out["end_b_moment"] = mb - np.cross(pts[-1], fb)
    out["end_a_direction"] = T[geo.first][:3, 0].copy()
    out["end_b_direction"] = T[geo.first + geo.nb - 1][:3, 0].copy()
    return out


def _planar_outputs(u: PlanarUnit, q, qd, qdd):
    pm = u.model
    w = pl.PlanarWork(pm)
    pk.body_kinematics(np.asarray(q, float), np.asarray(qd, float), np.asarray(qdd, float), pm.z_in, pm.z_out,
                       w.rot, w.pc, w.vc, w.ac)
    g2 = np.array([0.0, -pm.gravity])
    f = pm.mass[:, None] * (w.ac - g2)
    mom = w.pc[:, 0] * f[:, 1] - w.pc[:, 1] * f[:, 0] + pm.inertia * qdd[2:]
    for k in range(pm.load_rfe.shape[0]):
        i = pm.load_rfe[k]
        c, s = w.rot[i]
        o = pm.load_offset[k]
        r = w.pc[i] + np.array([c * o[0] - s * o[1], s * o[0] + c * o[1]])
        F = pm.load_force[k]
        f[i] -= F
        mom[i] -= r[0] * F[1] - r[1] * F[0] + pm.load_moment[k]
    S = np.cumsum(f[::-1], axis=0)[::-1]          # S[i]: RFEs i..n
    Sm = np.cumsum(mom[::-1])[::-1]
    joints = pl.joint_positions(pm, q)            # (n+2, 2): A_0, A_1..A_n, B
    n = pm.sde_stiffness.shape[0]
    D = S[1:n + 1]
    t = w.rot[1:n + 1]
    A = joints[1:n + 1]
    Mz = Sm[1:n + 1] - (A[:, 0] * D[:, 1] - A[:, 1] * D[:, 0])
    phi = np.asarray(q, float)[2:]
    ez = np.array([0.0, 0.0, 1.0])
    pz = np.cross(u.e1, ez)

    def to3(v2):
        v2 = np.atleast_2d(v2)
        return v2[:, :1] * u.e1 + v2[:, 1:2] * ez

    pos = to3(joints) + u.offset * u.normal
    fa = -S[0]
    ma = -(Sm[0] - (joints[0, 0] * S[0, 1] - joints[0, 1] * S[0, 0]))
    d = pm.length / max(n, 1)
    return {"position": pos, "tension": -(D * t).sum(axis=1), "shear_force": np.abs(D[:, 0] * t[:, 1] - D[:, 1] * t[:, 0]),
            "bend_moment": np.abs(Mz), "torque": np.zeros(n), "curvature": np.abs(np.diff(phi)) / d,
            "end_a_force": to3(fa)[0], "end_a_moment": ma * pz, "end_b_force": np.zeros(3),
            "end_b_moment": np.zeros(3), "end_a_direction": to3(w.rot[0])[0], "end_b_direction": to3(w.rot[-1])[0]}


_VECTOR = ("end_a_force", "end_b_force", "end_a_moment", "end_b_moment", "end_a_direction", "end_b_direction")


def _line_results(name, arc, frames: list[dict]) -> LineResults:
    nt = len(frames)
    stack = {k: np.array([fr[k] for fr in frames]) for k in frames[0]}
    npts = arc.shape[0]
    nsde = npts - 2
    lr = LineResults(name=name, arc_length=arc, sde_arc_length=arc[1:-1].copy(), position=stack["position"],
                       tension=stack["tension"].reshape(nt, nsde), shear_force=stack["shear_force"].reshape(nt, nsde),
                       bend_moment=stack["bend_moment"].reshape(nt, nsde), torque=stack["torque"].reshape(nt, nsde),
                       curvature=stack["curvature"].reshape(nt, nsde),
                       **{k: stack[k].reshape(nt, 3) for k in _VECTOR},
                       seabed_force=np.zeros((nt, nsde + 1)), seabed_friction=np.zeros((nt, nsde + 1, 3)),
                       touchdown_position=np.full((nt, 3), np.nan), touchdown_arc_length=np.full(nt, np.nan))
    for channel in ("von_mises_stress", "utilisation"):      # not computed here: NaN, as for a line without yield
        if hasattr(lr, channel) and getattr(lr, channel) is None:
            setattr(lr, channel, np.full((nt, nsde), np.nan))
    return lr


def _chain_lines(unit: ChainUnit, times, Q, QD, QDD) -> dict:
    model = unit.model
    kin = _Kinematics(model)
    geos = [_LinkGeometry(model, out) for out in unit.outputs]
    frames = {out.name: [] for out in unit.outputs}
    for t, q, qd, qdd in zip(times, Q, QD, QDD):
        kin.run(t, q, qd, qdd)
        f, m = _chain_body_wrenches(model, kin, t)
        for out, geo in zip(unit.outputs, geos):
            frames[out.name].append(_link_outputs(model, kin, geo, f, m))
    return {out.name: _line_results(out.name, geo.arc, frames[out.name]) for out, geo in zip(unit.outputs, geos)}


def _planar_lines(u: PlanarUnit, times, Q, QD, QDD) -> dict:
    frames = [_planar_outputs(u, q, qd, qdd) for q, qd, qdd in zip(Q, QD, QDD)]
    n = u.model.sde_stiffness.shape[0]
    d = u.model.length / max(n, 1)
    arc = np.concatenate([[0.0], (np.arange(1, n + 1) - 0.5) * d, [u.model.length]])
    return {u.name: _line_results(u.name, arc, frames)}


def joint_kinds(sc) -> dict[str, str]:
    """``"<chain>.<joint>"`` -> the joint's kind (revolute, prismatic, spherical, fixed): the
    units of its coordinates in the results (rfesim.results.JointResults)."""
    return {f"{cname}.{jname}": j.kind for cname, spec in (getattr(sc, "chains", None) or {}).items()
            for jname, j in spec.joints.items()}


def _results(sc, scene, times, histories, *, kind, message, counters, version):
    lines, joints = {}, {}
    kinds = joint_kinds(sc)
    for unit, (Q, QD, QDD) in zip(scene.chains, histories[:len(scene.chains)]):
        lines.update(_chain_lines(unit, times, Q, QD, QDD))
        for jname, idx in unit.joints.items():
            joints[jname] = JointResults(jname, Q[:, idx], QD[:, idx], kinds.get(jname, ""))
    for u, (Q, QD, QDD) in zip(scene.planars, histories[len(scene.chains):]):
        lines.update(_planar_lines(u, times, Q, QD, QDD))
    ordered = {k: lines[k] for k in sc.lines if k in lines}
    ordered.update({k: v for k, v in lines.items() if k not in ordered})
    return Results(time=np.asarray(times, float), lines=ordered, joints=joints, status=0, message=message,
                   counters=counters, scenario_json=sc.model_dump_json(), version=version, kind=kind)


# ============================================================================ statics
def _statics_states(sc, scene):
    st = sc.analysis.statics
    states, iters = [], 0
    for unit in scene.chains:
        r = chain_statics(unit.model, q0=unit.q0, load_steps=st.load_steps, tol=float(np.clip(st.tolerance, 1e-10, 1e-8)),
                          max_iter=max(st.max_iterations, 60))
        if not r.success:
            raise SolverError(f"statics of {unit.label}: {r.message}")
        iters += r.iterations
        states.append(r.q)
    for u in scene.planars:
        r = pl.planar_statics(u.model, load_steps=st.load_steps, max_iterations=max(st.max_iterations, 50))
        iters += r.iterations
        states.append(r.q)
    return states, iters


def statics(sc, progress=None):
    from .. import __version__
    from . import mixed
    if mixed.is_mixed(sc):                  # chains with absolute-coordinate lines: one solver over both
        return mixed.statics(sc, progress)
    scene = compile_scene(sc)
    wall0 = _time.perf_counter()
    states, iters = _statics_states(sc, scene)
    hist = [(q[None], np.zeros((1, q.size)), np.zeros((1, q.size))) for q in states]
    counters = {"newton_iterations": iters, "wall_time": _time.perf_counter() - wall0}
    return _results(sc, scene, np.zeros(1), hist, kind="statics", message="converged", counters=counters,
                    version=__version__)


# ============================================================================ dynamics
RK4_LIMIT = 2.785      # RK4 stability limit on the imaginary axis, h * omega_max
DENSE_LIMIT = 400      # coordinates: largest model whose highest frequency is found by a dense eigen-solve
RIGID_STEPS_PER_PERIOD = 40   # default step of all-rigid chains: at most T_min / 40 (accuracy, not stability)
FALLBACK_OUTPUTS = 1000       # default step without any positive frequency: duration / 1000 ...
FALLBACK_ROTATION = 0.01      # ... and at most 0.01 rad of the fastest initial joint rotation per step


def _omega_max(scene, states) -> float:
    """Largest |omega| (rad/s) of the linearisation about the start states: the stability
    scale of the explicit step. An unstable direction (negative omega^2, e.g. a pendulum
    started above the horizontal) counts with its growth rate sqrt(-omega^2)."""
    w = 0.0
    for unit, q in zip(scene.chains, states):
        if len(unit.model.free) > DENSE_LIMIT:
            raise SolverError(f"{unit.label}: {len(unit.model.free)} coordinates; give "
                              f"analysis.dynamics.integrator.time_step (the step estimate needs a dense "
                              f"eigen-solve, limited to {DENSE_LIMIT} coordinates)")
        if len(unit.model.free):
            w = max(w, float(np.abs(chain_modes(unit.model, q)[0]).max()))
    for u, q in zip(scene.planars, states[len(scene.chains):]):
        f = pl.planar_modes(u.model, q, count=u.model.ncoord).frequencies_hz
        if f.size:
            w = max(w, 2 * math.pi * float(np.abs(f).max()))
    return w if math.isfinite(w) else 0.0


def _all_rigid(scene) -> bool:
    """True when every unit is a chain of rigid links only (its highest frequency is a
    physical pendulum-like motion, not a discretisation artefact)."""
    return bool(scene.chains) and not scene.planars and all(
        isinstance(info.link, RigidLink) for u in scene.chains for info in u.model.links.values())


def default_step(scene, states, rates, dyn) -> tuple[float, str]:
    """Default fixed step (s) of a scene without integrator.time_step, and how it was chosen.

    safety x RK4_LIMIT / omega_max (the stability limit, omega_max from `_omega_max`);
    for chains of rigid links only, whose highest frequency is physical, also at most
    T_min / RIGID_STEPS_PER_PERIOD (RK4 near its stability limit damps a 1 rad double
    pendulum swing by 70 % in 5 s; at T_min / 40 its angles stay within 1.5e-4 rad of a
    converged run over 5 s, amplitude error 1e-5).
    Without any non-zero frequency (no gravity, no springs): duration / 1000, at most the
    output interval, and at most 0.01 rad of the fastest initial joint rotation per step."""
    integ = dyn.integrator
    w = _omega_max(scene, states)
    if w > 0.0:
        step = integ.safety * RK4_LIMIT / w
        how = f"{integ.safety:g} x the RK4 stability limit {RK4_LIMIT / w:.4g} s"
        if _all_rigid(scene):
            acc = 2.0 * math.pi / w / RIGID_STEPS_PER_PERIOD
            if acc < step:
                step, how = acc, f"1/{RIGID_STEPS_PER_PERIOD} of the shortest period {2 * math.pi / w:.4g} s"
        return step, how
    step = float(dyn.duration) / FALLBACK_OUTPUTS
    if dyn.output_interval:
        step = min(step, float(dyn.output_interval))
    rate = max((float(np.abs(qd).max()) for qd in rates if qd.size), default=0.0)
    if rate > 0.0:
        step = min(step, FALLBACK_ROTATION / rate)
    return step, "no non-zero natural frequency: duration / 1000 (limited by the joint rates)"


SINGULAR_NEAR = 0.05      # |cos phi_y| of a spherical joint within ~2.9 deg of the ZYX singularity
SINGULAR_RATE = 10.0      # joint rates above this multiple of the rates away from it: not kept


def _spherical_joints(unit):
    """[(name, coordinate indices (phi_x, phi_y, phi_z))] of the integrated spherical joints
    of a chain unit: the chain joints by their scenario name, a pinned line's end_a pin."""
    model = unit.model
    free = set(int(i) for i in model.free)
    out = []
    for info in model.links.values():
        idx = np.asarray(info.joint_coords, int)
        if len(idx) != 3 or int(model.kind[info.first_body]) != SPHERICAL or int(idx[1]) not in free:
            continue
        name = next((f"chains.{n}" for n, j in unit.joints.items() if np.array_equal(np.asarray(j, int), idx)),
                    f"{unit.label}.end_a (pinned)")
        out.append((name, idx))
    return out


def _euler_singularity(unit, times, Q, QD):
    """Whether a chain unit that failed had just taken a spherical joint to the singularity
    of its ZYX angles (|phi_y| = 90 deg about the joint's y axis), where the mass matrix is
    singular and the rates of phi_x, phi_z grow without bound, whatever the time step:
    None, or (joint name, time of its last output near or across the singularity, number
    of outputs to keep: those before the joint rates grew beyond SINGULAR_RATE times their
    largest value before the final approach, and not finite). "Just": within the last 2 outputs or 2 % of the
    outputs before the failure."""
    n = min(len(times), len(Q), len(QD))
    if n == 0:
        return None
    tail = max(2, n // 50)
    for name, idx in _spherical_joints(unit):
        c = np.cos(Q[:n, idx[1]])
        near = ~np.isfinite(c) | (np.abs(c) < SINGULAR_NEAR)
        near[1:] |= np.sign(c[1:]) != np.sign(c[:-1])       # crossed between two outputs
        hits = np.flatnonzero(near)
        if not len(hits) or hits[-1] < n - tail:
            continue
        first = int(hits[hits >= n - tail][0])             # the final approach starts here
        rate = np.abs(QD[:n][:, idx]).max(axis=1)
        ok = (np.isfinite(rate) & ~near)[:first]
        ref = max(1.0, float(rate[:first][ok].max())) if ok.any() else 1.0
        bad = np.flatnonzero(~np.isfinite(rate) | (rate > SINGULAR_RATE * ref)
                             | ~np.all(np.isfinite(Q[:n]), axis=1) | ~np.all(np.isfinite(QD[:n]), axis=1))
        n_keep = int(bad[0]) if len(bad) else n
        return name, float(times[hits[-1]]), max(1, n_keep)
    return None


def _singularity_message(label, sing, why, integrator):
    """The SolverError message of a unit that failed at a spherical joint's singularity."""
    name, t_near, _ = sing
    return (f"{label}: the {integrator} failed ({why}) as the spherical joint {name} reached |phi_y| = 90 deg "
            f"about its y axis (t = {t_near:.6g} s), the singularity of its ZYX joint angles: there the rates "
            f"of phi_x and phi_z grow without bound, and a smaller time step or tighter tolerances do not help; "
            f"orient the joint (its direction) so that the motion stays away from +-90 deg about the joint's "
            f"y axis, or model the link as a pinned line in the absolute formulation (its element angles are "
            f"re-based and never reach the singularity)")


def _partial(sc, scene, times, hist, n_keep, message, counters):
    from .. import __version__
    hist = [(Q[:n_keep], QD[:n_keep], QDD[:n_keep]) for Q, QD, QDD in hist]
    res = _results(sc, scene, np.asarray(times)[:n_keep], hist, kind="dynamics", message=message,
                   counters=counters, version=__version__)
    res.status = 1
    return res


def _unit_rows(unit, times, Q, QD):
    """(Q, QD, QDD) of a unit at ``times`` from its coordinates and rates: the prescribed
    coordinates set from their drives (or the base motion), the accelerations from the
    equations of motion (NaN where the mass matrix is singular, as in `_adaptive`)."""
    Q, QD = np.array(Q, float, copy=True), np.array(QD, float, copy=True)
    QDD = np.zeros_like(Q)
    if isinstance(unit, PlanarUnit):
        pm = unit.model
        pres = pm.prescribed()
        w = pl.PlanarWork(pm)
        for i, t in enumerate(times):
            p, v, _ = pm.base_state(float(t))
            Q[i, :3][pres], QD[i, :3][pres] = p[pres], v[pres]
            QDD[i] = pl.accelerations(pm, Q[i], QD[i], float(t), w)[0]
        return Q, QD, QDD
    model = unit.model
    data = ChainData(model)
    for i, t in enumerate(times):
        fill_prescribed(model, float(t), Q[i], QD[i], np.zeros(model.nq))
        try:
            QDD[i] = accelerations(model, data, float(t), Q[i], QD[i])
        except np.linalg.LinAlgError:
            QDD[i] = np.nan
    return Q, QD, QDD


def _interrupted(sc, scene, states, rates, recorded, counters, per_out=None, failure=None, cancelled=False):
    """The Results (status 2) of a run interrupted by a KeyboardInterrupt (Ctrl-C, or a
    SIGTERM the command line turns into it) while its units were integrated, or None when
    no unit had recorded an output yet (as `rfesim.solvers.dynamics.run_dynamics` before its
    first one). ``cancelled``: the progress callback stopped the run (`_Cancel`): status 3
    (CANCELLED), "cancelled at t = ...", the same time span.

    ``recorded[k]``: (times, Q, QD, QDD or None) that unit k had recorded, or None. The units
    are integrated one after another, so an interruption finds the earlier ones at the end
    of the run, one part way and the later ones not started. The results keep the time span
    every unit reached (the shortest record; a unit not started counts with its start state
    at t = 0, the statics or the initial shape), so that every output time holds the whole
    scene: no unit's channels are padded or extrapolated. The message says when units had
    got further than that, and names a unit that had diverged before (``failure``: label,
    time, reason), which the finished run would have raised as a SolverError."""
    from .. import __version__
    from ..solvers.dynamics import CANCELLED, INTERRUPTED
    units = scene.chains + scene.planars
    if not any(r is not None and len(r[0]) for r in recorded):
        return None
    started = [r is not None and len(r[0]) > 0 for r in recorded]
    rows = [r if ok else (np.zeros(1), q[None], qd[None], None)
            for r, ok, q, qd in zip(recorded, started, states, rates)]
    lengths = [len(r[0]) for r in rows]
    lag = int(np.argmin(lengths))
    n = lengths[lag]
    times = np.asarray(rows[lag][0][:n], float)
    hist = []
    for unit, (_, Q, QD, QDD) in zip(units, rows):
        if QDD is None:
            hist.append(_unit_rows(unit, times, Q[:n], QD[:n]))
        else:
            hist.append((Q[:n], QD[:n], QDD[:n]))
    t_end = float(times[-1])
    message = f"{'cancelled' if cancelled else 'interrupted'} at t = {t_end:.6g} s"
    further = [f"{u.label} t = {float(r[0][-1]):.6g} s" for u, r in zip(units, rows) if len(r[0]) > n]
    if further:
        reached = "had not started" if not started[lag] else f"had reached t = {t_end:.6g} s"
        message += (f"; the units are integrated one after another and {units[lag].label} {reached}: the results "
                    f"keep the time span all units reached (further: {', '.join(further)})")
    if failure is not None:
        label, t_fail, why = failure[:3]
        message += f"; {label} had diverged at t = {t_fail:.6g} s ({why})"
    counters = dict(counters)
    if per_out is not None:
        counters["steps"] = (n - 1) * per_out        # the steps of the time span kept
    res = _results(sc, scene, times, hist, kind="dynamics", message=message, counters=counters,
                   version=__version__)
    res.status = CANCELLED if cancelled else INTERRUPTED
    return res


class _Cancel(KeyboardInterrupt):
    """What `simulate`'s progress report raises when the progress callback raised ``cause``
    (the service's cancel): a KeyboardInterrupt, so that the unit integrators (chain RK4,
    planar RK4 / generalized-alpha, DOP853) attach the outputs they had recorded to it as to
    a Ctrl-C (their ``history``); `simulate` turns it into CancelledError with the results."""

    def __init__(self, cause: Exception):
        super().__init__(str(cause))
        self.cause = cause


def simulate(sc, progress=None):
    """Statics (if enabled) and dynamics of a scene of classical / modified / planar lines
    and chains (mixed with absolute-coordinate lines: `mixed.simulate`) -> Results.

    The units (each line, each chain) are uncoupled and are integrated one after another
    over the whole run. A diverging unit raises SolverError with the results of the time
    span all units reached (status 1). A KeyboardInterrupt in the dynamics (Ctrl-C, or a
    SIGTERM the command line turns into it) propagates with ``results`` attached (status 2,
    "interrupted at t = ..."; `_interrupted`): the time span every unit had reached, so with
    units still to integrate only the start state at t = 0 (statics or the initial shape),
    or None when nothing was recorded yet. A progress callback that raises stops the run as
    CancelledError with the results kept the same way (status 3, "cancelled at t = ...")."""
    from .. import __version__
    from ..solvers.dynamics import output_schedule
    from . import mixed
    if mixed.is_mixed(sc):
        return mixed.simulate(sc, progress)
    scene = compile_scene(sc)
    an = sc.analysis
    wall0 = _time.perf_counter()
    counters = {}
    if an.statics.enabled:
        states, iters = _statics_states(sc, scene)
        counters["statics_iterations"] = iters
        rates = [np.zeros_like(q) for q in states]
        for unit, qd in zip(scene.chains, rates):
            for idx in unit.joints.values():
                qd[idx] = unit.qd0[idx]
    else:
        states = [u.q0.copy() for u in scene.chains] + [u.model.q_initial.copy() for u in scene.planars]
        rates = [u.qd0.copy() for u in scene.chains] + [np.zeros_like(u.model.q_initial) for u in scene.planars]
    dyn = an.dynamics
    if not (dyn.enabled and dyn.duration > 0):
        hist = [(q[None], qd[None], np.zeros((1, q.size))) for q, qd in zip(states, rates)]
        return _results(sc, scene, np.zeros(1), hist, kind="statics", message="statics only", counters=counters,
                        version=__version__)
    integ = dyn.integrator
    nunits = len(scene.chains) + len(scene.planars)
    recorded = [None] * nunits      # per unit: (times, Q, QD, QDD or None) so far, for an interruption
    per_out = None
    failure = None                  # the first unit that diverged: (label, time, message)

    def report(fraction):
        if progress is None:
            return
        try:
            progress(fraction, fraction * dyn.duration)
        except Exception as exc:
            raise _Cancel(exc) from exc         # the integrators attach their outputs (`_Cancel`)

    def keep(k, exc):
        """The outputs unit k recorded before an interruption (its integrator attaches them)."""
        part = getattr(exc, "history", None)
        if part is not None and len(part.t):
            recorded[k] = (part.t, part.q, part.qd, getattr(part, "qdd", None))

    try:
        if integ.kind == "adaptive":
            times, hist, counters2, failure = _adaptive(scene, states, rates, dyn, report, recorded)
            counters.update(counters2)
            if failure is not None:
                label, t_fail, why, n_keep = failure
                msg = (f"{label}: {why}; the adaptive integrator lost accuracy (tighten "
                       f"analysis.dynamics.integrator.rtol / atol or set max_step)")
                for unit, (Q, QD, _) in zip(scene.chains, hist):
                    sing = _euler_singularity(unit, times[:n_keep], Q, QD) if unit.label == label else None
                    if sing is not None:
                        msg = _singularity_message(label, sing, why, "adaptive integrator")
                        n_keep = min(n_keep, sing[2])
                counters["wall_time"] = _time.perf_counter() - wall0
                raise SolverError(msg, time=t_fail, element=label,
                                  results=_partial(sc, scene, times, hist, n_keep, f"{msg} at t = {t_fail:.6g} s",
                                                   counters))
            energy_warnings = _energy_growth(sc, scene, times, hist, counters, wall0,
                                             "tighten analysis.dynamics.integrator.rtol / atol or set max_step")
        else:
            T = float(dyn.duration)
            step = integ.time_step
            if step is None:
                step, how = default_step(scene, states, rates, dyn)
                counters["time_step_rule"] = how
            out_dt, n_out, step = output_schedule(T, float(step), dyn.output_interval)
            per_out = max(1, int(round(out_dt / step)))
            counters["time_step"] = step
            nsteps = n_out * per_out
            t_end = n_out * out_dt
            times, hist = None, []
            for k, (unit, q, qd) in enumerate(zip(scene.chains, states, rates)):
                try:
                    res = simulate_chain(unit.model, t_end, step, q0=q, qd0=qd, output_every=per_out,
                                         progress=lambda f, k=k: report((k + f) / nunits))
                except KeyboardInterrupt as exc:
                    keep(k, exc)
                    raise
                recorded[k] = (res.t, res.q, res.qd, res.qdd)
                if not res.success and failure is None:
                    failure = (unit.label, res.failure_time if res.failure_time is not None else float(res.t[-1]),
                               res.message)
                if times is None or len(res.t) < len(times):
                    times = res.t
                hist.append((res.q, res.qd, res.qdd))
            nch = len(scene.chains)
            for k, (u, q, qd) in enumerate(zip(scene.planars, states[nch:], rates[nch:])):
                method = "rk4" if integ.kind == "rk4" else "generalized-alpha"
                kw = {"rho_inf": integ.rho_inf} if method != "rk4" else {}
                try:
                    r = pl.planar_dynamics(u.model, t_end, step, q0=q, qd0=qd, method=method, record_every=per_out,
                                           progress=lambda f, k=k: report((nch + k + f) / nunits), **kw)
                except KeyboardInterrupt as exc:
                    keep(nch + k, exc)
                    raise
                if not r.success and failure is None:
                    # Newton failed: the outputs before it are kept, as for a chain that diverged
                    failure = (u.label, float(r.t[-1]) if len(r.t) else 0.0, r.message)
                recorded[nch + k] = (r.t, r.q, r.qd, None)
                qdd = np.array([pl.accelerations(u.model, qi, vi, ti)[0] for ti, qi, vi in zip(r.t, r.q, r.qd)])
                recorded[nch + k] = (r.t, r.q, r.qd, qdd)
                if times is None or len(r.t) < len(times):
                    times = r.t
                hist.append((r.q, r.qd, qdd))
            counters.update({"steps": nsteps, "time_step": step})
            if failure is not None:
                label, t_fail, why = failure
                limit = _rk4_limit_text(scene, states)
                msg = (f"{label}: the state diverged ({why}) with the time step {step:.4g} s{limit}; reduce "
                       f"analysis.dynamics.integrator.time_step")
                counters["wall_time"] = _time.perf_counter() - wall0
                n_keep = len(times)
                for unit, (Q, QD, _) in zip(scene.chains, hist):
                    sing = _euler_singularity(unit, times, Q, QD) if unit.label == label else None
                    if sing is not None:
                        msg = _singularity_message(label, sing, why, f"RK4 integration (time step {step:.4g} s)")
                        n_keep = min(n_keep, sing[2])
                raise SolverError(msg, time=t_fail, element=label,
                                  results=_partial(sc, scene, times, hist, n_keep, f"{msg} at t = {t_fail:.6g} s",
                                                   counters))
            energy_warnings = _energy_growth(sc, scene, times, hist, counters, wall0,
                                             _step_remedy(scene, states, step, integ))
    except _Cancel as exc:
        # the progress callback raised (the service's cancel): the time span all units
        # reached goes with the CancelledError, as with an interruption
        from ..solvers.dynamics import cancelled
        counters["wall_time"] = _time.perf_counter() - wall0
        part = _interrupted(sc, scene, states, rates, recorded, counters, per_out, failure, cancelled=True)
        t = float(part.time[-1]) if part is not None else 0.0
        err = cancelled(exc.cause, t, (lambda **kw: part) if part is not None else None)
        raise err from exc.cause
    except KeyboardInterrupt as exc:
        counters["wall_time"] = _time.perf_counter() - wall0
        exc.results = _interrupted(sc, scene, states, rates, recorded, counters, per_out, failure)
        raise
    counters["wall_time"] = _time.perf_counter() - wall0
    from ..api import DYNAMICS_WARNING
    message = f"finished: {counters.get('steps', 0)} steps" + "".join(DYNAMICS_WARNING + w for w in energy_warnings)
    return _results(sc, scene, times, hist, kind="dynamics", message=message, counters=counters,
                    version=__version__)


def _rk4_limit_text(scene, states) -> str:
    """" (its RK4 stability limit is about ... s)" from the scene's highest frequency, or ""
    where it is zero or too costly to find (_omega_max)."""
    try:
        w = _omega_max(scene, states)
    except SolverError:
        return ""
    return f" (its RK4 stability limit is about {RK4_LIMIT / w:.3g} s)" if w > 0.0 else ""


def _step_remedy(scene, states, step: float, integ) -> str:
    """What to change when a fixed-step run of the scene gained energy: the step (against the
    RK4 stability limit where the integrator is RK4), or rho_inf for generalized-alpha."""
    limit = _rk4_limit_text(scene, states) if integ.kind == "rk4" or scene.chains else ""
    text = f"shorten analysis.dynamics.integrator.time_step ({step:.4g} s){limit}"
    if integ.kind != "rk4" and scene.planars:
        text += ", or lower analysis.dynamics.integrator.rho_inf for the planar lines"
    return text


def _energy_growth(sc, scene, times, hist, counters, wall0, remedy: str) -> list[str]:
    """The energy check of the closed units after their integration (energy_check): a unit
    whose mechanical energy grew past ENERGY_STOP of its scale stops the run (SolverError,
    the outputs up to that output, status 1); past ENERGY_WARN the warnings returned."""
    from ..solvers.dynamics import ENERGY_STOP, ENERGY_WARN
    out = []
    checks = []
    n = len(times)
    for unit, (Q, QD, _) in zip(scene.chains, hist):
        if not unit.open:
            kin_el, pot, floor = energy_check.chain_energies(unit.model, times, Q[:n], QD[:n])
            checks.append(energy_check.growth(unit.label, kin_el, pot, floor))
    for u, (Q, QD, _) in zip(scene.planars, hist[len(scene.chains):]):
        kin_el, pot, floor = energy_check.planar_energies(u.model, Q[:n], QD[:n])
        checks.append(energy_check.growth(u.label, kin_el, pot, floor))
    stops = [(g.first_over(ENERGY_STOP), g) for g in checks]
    stops = [(k, g) for k, g in stops if k is not None]
    if stops:
        k, g = min(stops, key=lambda x: x[0])
        t = float(times[k])
        why = f"{g.describe(k, t)} - {remedy}"
        counters["wall_time"] = _time.perf_counter() - wall0
        raise SolverError("the run diverged", time=t, element=g.label, quantity="energy growth", hint=why,
                          results=_partial(sc, scene, times, hist, k + 1,
                                           f"energy growth at t = {t:.6g} s in {g.label}; {why}", counters))
    for g in checks:
        k = int(np.argmax(g.ratio)) if g.ratio.size else 0
        if g.ratio.size and g.ratio[k] > ENERGY_WARN:
            out.append(f"{g.describe(k, float(times[k]))} - {remedy}")
    return out


def _dop853(rhs, y0, times, kw, progress=None):
    """DOP853 stepped by hand with dense output at `times`: (Y (len, n) so far, None) or,
    when a step fails or the right-hand side raises LinAlgError, (Y so far, (t, why)).
    ``progress(fraction)`` after every step, its outputs recorded; a KeyboardInterrupt
    propagates with Y so far as ``history_rows``."""
    from scipy.integrate import DOP853
    T = float(times[-1])
    Y = [np.array(y0, float)]
    k = 1
    solver = None
    try:
        solver = DOP853(rhs, 0.0, np.array(y0, float), T, **kw)
        while k < len(times):
            msg = solver.step()
            if solver.status == "failed":
                return np.array(Y), (solver.t, str(msg))
            dense = solver.dense_output()
            while k < len(times) and times[k] <= solver.t + 1e-12 * max(1.0, T):
                Y.append(dense(min(times[k], solver.t)))
                k += 1
            if solver.status == "finished":
                while k < len(times):
                    Y.append(solver.y.copy())
                    k += 1
            if progress is not None:
                progress(min(1.0, solver.t / T) if T > 0.0 else 1.0)
    except np.linalg.LinAlgError as exc:
        return np.array(Y), (solver.t if solver is not None else 0.0, str(exc))
    except KeyboardInterrupt as exc:
        exc.history_rows = np.array(Y)
        raise
    return np.array(Y), None


def _adaptive(scene, states, rates, dyn, report, recorded=None):
    """DOP853 on each unit's first-order system, output every output_interval (made to divide
    the duration as for the fixed-step integrators, `output_schedule`). Returns (times, hist,
    counters, failure): failure is None or (unit label, time, reason, outputs kept).
    ``recorded`` (a list, one item per unit) gets each unit's (times, Q, QD, QDD or None) as
    it is integrated, the outputs so far of one a KeyboardInterrupt stops included."""
    from ..solvers.dynamics import output_schedule
    integ = dyn.integrator
    out_dt, n_out, _ = output_schedule(float(dyn.duration), 0.0, dyn.output_interval, adaptive=True)
    times = np.arange(n_out + 1) * out_dt
    hist, nfev = [], 0
    kw = {"rtol": integ.rtol, "atol": integ.atol}
    if integ.max_step:
        kw["max_step"] = integ.max_step
    if integ.first_step:
        kw["first_step"] = integ.first_step
    failure = None
    n_keep = len(times)
    nunits = len(scene.chains) + len(scene.planars)
    recorded = recorded if recorded is not None else [None] * nunits

    def integrate(k, rhs, y0, expand):
        """DOP853 of unit k; expand(Y) -> (Q, QD). An interruption leaves its outputs so far
        in recorded[k] (without accelerations: `_interrupted` computes them)."""
        try:
            return _dop853(rhs, y0, times[:n_keep], kw, progress=lambda f: report((k + f) / nunits))
        except KeyboardInterrupt as exc:
            Y = getattr(exc, "history_rows", None)
            if Y is not None and len(Y):
                Q, QD = expand(Y)
                recorded[k] = (times[:len(Y)], Q, QD, None)
            raise

    for k, (unit, q, qd) in enumerate(zip(scene.chains, states, rates)):
        model = unit.model
        data = ChainData(model)
        fr = model.free

        def full(t, y, model=model, q=q, qd=qd, fr=fr):
            n = len(fr)
            qq, vv = q.copy(), qd.copy()
            qq[fr], vv[fr] = y[:n], y[n:]
            fill_prescribed(model, t, qq, vv, np.zeros(model.nq))
            return qq, vv

        def rhs(t, y, model=model, data=data, fr=fr, full=full):
            qq, vv = full(t, y)
            return np.concatenate([vv[fr], accelerations(model, data, t, qq, vv)[fr]])

        def expand(Y, full=full, nq=model.nq):
            rows = [full(t, y) for t, y in zip(times, Y)]
            return (np.array([a for a, _ in rows]).reshape(-1, nq), np.array([b for _, b in rows]).reshape(-1, nq))
        Y, fail = integrate(k, rhs, np.concatenate([q[fr], qd[fr]]), expand)
        nfev += data.nfev
        Q, QD, QDD = [], [], []
        for t, y in zip(times, Y):
            qq, vv = full(t, y)
            try:
                QDD.append(accelerations(model, data, t, qq, vv))
            except np.linalg.LinAlgError:
                QDD.append(np.full(model.nq, np.nan))
            Q.append(qq)
            QD.append(vv)
        hist.append((np.array(Q).reshape(-1, model.nq), np.array(QD).reshape(-1, model.nq),
                     np.array(QDD).reshape(-1, model.nq)))
        recorded[k] = (times[:len(Y)],) + hist[-1]
        if fail is not None and failure is None:
            failure = (unit.label, float(fail[0]), fail[1])
        n_keep = min(n_keep, len(Y))
    nch = len(scene.chains)
    for k, (u, q, qd) in enumerate(zip(scene.planars, states[nch:], rates[nch:]), start=nch):
        pm = u.model
        free = pm.free_mask()
        w = pl.PlanarWork(pm)

        def pfull(y, q=q, qd=qd, free=free):
            n = int(free.sum())
            qq, vv = q.copy(), qd.copy()
            qq[free], vv[free] = y[:n], y[n:]
            return qq, vv

        def prhs(t, y, pm=pm, w=w, pfull=pfull, free=free):
            qq, vv = pfull(y)
            return np.concatenate([vv[free], pl.accelerations(pm, qq, vv, t, w)[0][free]])

        def pexpand(Y, pfull=pfull, m=pm.ncoord):
            rows = [pfull(y) for y in Y]
            return (np.array([a for a, _ in rows]).reshape(-1, m), np.array([b for _, b in rows]).reshape(-1, m))
        Y, fail = integrate(k, prhs, np.concatenate([q[free], qd[free]]), pexpand)
        Q, QD = [], []
        for y in Y:
            a, b = pfull(y)
            Q.append(a)
            QD.append(b)
        QDD = [pl.accelerations(pm, a, b, t, w)[0] for t, a, b in zip(times, Q, QD)]
        m = pm.ncoord
        hist.append((np.array(Q).reshape(-1, m), np.array(QD).reshape(-1, m), np.array(QDD).reshape(-1, m)))
        recorded[k] = (times[:len(Y)],) + hist[-1]
        if fail is not None and failure is None:
            failure = (u.label, float(fail[0]), fail[1])
        n_keep = min(n_keep, len(Y))
    report(1.0)
    if failure is not None:
        failure = failure + (n_keep,)
    return times, hist, {"evaluations": nfev}, failure


# ============================================================================ modes
def _positions(unit, q, t=0.0):
    """Concatenated point positions of all output lines of a unit, (npoints, 3)."""
    if isinstance(unit, PlanarUnit):
        z = np.zeros_like(q)
        return _planar_outputs(unit, q, z, z)["position"]
    model = unit.model
    kin = _Kinematics(model).run(t, q, np.zeros(model.nq), np.zeros(model.nq))
    if "geometry" not in unit.cache:
        unit.cache["geometry"] = [_LinkGeometry(model, out) for out in unit.outputs]
    pts = []
    T = kin.T
    for geo in unit.cache["geometry"]:
        p = np.empty((geo.nsde + 2, 3))
        p[0] = T[geo.first][:3] @ geo.pA
        p[1:-1] = 0.5 * (np.einsum("kij,kj->ki", T[geo.lb][:, :3], geo.left)
                         + np.einsum("kij,kj->ki", T[geo.rb][:, :3], geo.right))
        p[-1] = T[geo.first + geo.nb - 1][:3] @ geo.pB
        pts.append(p)
    return pts


def _free_count(unit) -> int:
    return int(unit.model.free_mask().sum()) if isinstance(unit, PlanarUnit) else len(unit.model.free)


def _length_scale(unit) -> float:
    """Displacement (m) of a unit coordinate: the RFE / SDE spacing (rigid links: length)."""
    if isinstance(unit, PlanarUnit):
        return unit.model.length / max(unit.model.sde_stiffness.shape[0], 1)
    return max(o.sde_spacing for o in unit.outputs)


def modes(sc, n: int | None = None):
    """Modes of a scene with classical / modified / planar lines or chains (ModalResults).

    n: a positive integer (default analysis.modal.modes, else 10); above the number of
    moving coordinates all modes are given and ModalResults.message says so. Unstable modes
    have negative frequencies (ModalResults). shapes: (nmodes, nq) concatenated unit
    coordinates; line_shapes: point displacements, as for absolute-coordinate lines."""
    from ..solvers.modal import ModalResults, SHAPE_FLOOR, checked_mode_count, count_note, join_notes, \
        statics_disabled_note, statics_failed, unstable_note
    from . import mixed
    nmodes = checked_mode_count(n, default=sc.analysis.modal.modes if sc.analysis.modal else 10)
    if mixed.is_mixed(sc):
        from ..errors import UnsupportedError
        raise UnsupportedError("modal analysis of a scene mixing chains with absolute-coordinate lines is not "
                               "supported yet (statics and dynamics are)")
    scene = compile_scene(sc)
    units = scene.chains + scene.planars
    available = sum(_free_count(u) for u in units)
    if available == 0:
        raise SolverError("modal analysis: the scene has no moving coordinates")
    requested, nmodes = nmodes, min(nmodes, available)
    # the linear classical model's modes do not depend on the static state (its K is constant)
    linear_only = not scene.planars and all(u.linear_clamped for u in scene.chains)
    if not linear_only:
        # about the static equilibrium also when analysis.statics.enabled is false (the note says so)
        try:
            states, _ = _statics_states(sc, scene)
        except SolverError as exc:
            raise statics_failed(exc, sc) from None
    else:
        states = [u.q0 for u in scene.chains] + [u.model.q_initial for u in scene.planars]
    found = []                                   # (omega, unit index, full shape)
    omega_max = 0.0                              # the largest |omega| computed: the scale of ModalResults.scale_hz
    for k, (unit, q) in enumerate(zip(scene.chains, states)):
        if not len(unit.model.free):
            continue
        if unit.linear_clamped:                  # eqs. 8.34, 8.35: constant diagonal M, block-tridiagonal K
            link = unit.model.links[unit.outputs[0].link].link
            w, shapes = linear_modes(link, nmodes)
        else:
            w, shapes = chain_modes(unit.model, q)
        omega_max = max(omega_max, float(np.abs(w).max()) if len(w) else 0.0)
        for i in range(min(nmodes, len(w))):
            found.append((float(w[i]), k, shapes[:, i]))
    for k, (u, q) in enumerate(zip(scene.planars, states[len(scene.chains):]), start=len(scene.chains)):
        if not _free_count(u):
            continue
        md = pl.planar_modes(u.model, q, count=nmodes)
        for f, s in zip(md.frequencies_hz, md.shapes):
            omega_max = max(omega_max, 2 * math.pi * abs(float(f)))
            found.append((2 * math.pi * float(f), k, s))
    found.sort(key=lambda x: x[0])
    found = found[:nmodes]
    sizes = [len(s) for s in states]
    offsets = np.concatenate([[0], np.cumsum(sizes)])
    shapes = np.zeros((len(found), int(offsets[-1])))
    names = [[o.name for o in u.outputs] if isinstance(u, ChainUnit) else [u.name] for u in units]
    base_pts = [_as_list(_positions(u, q)) for u, q in zip(units, states)]
    line_shapes = {nm: np.zeros((len(found),) + p.shape) for nms, pts in zip(names, base_pts)
                   for nm, p in zip(nms, pts)}
    for i, (w, k, s) in enumerate(found):
        s = s / max(np.abs(s).max(), 1e-300)      # unit largest coordinate
        shapes[i, offsets[k]:offsets[k + 1]] = s
        eps = 1e-6
        plus = _as_list(_positions(units[k], states[k] + eps * s))
        if getattr(units[k], "linear_clamped", False):      # eq. 8.8: points affine in q, one-sided is exact
            disp = [(a - b) / eps for a, b in zip(plus, base_pts[k])]
        else:
            minus = _as_list(_positions(units[k], states[k] - eps * s))
            disp = [(a - b) / (2 * eps) for a, b in zip(plus, minus)]
        # largest point displacement, but not below SHAPE_FLOOR of a unit coordinate's: a mode
        # that moves no point beyond round-off (pure torsion, a spin) stays (near) zero
        peak = max(np.abs(d).max() for d in disp)
        scale = max(peak, SHAPE_FLOOR * _length_scale(units[k]), 1e-300)
        for nm, d in zip(names[k], disp):
            line_shapes[nm][i] = d / scale
    freqs = np.array([w / (2 * math.pi) for w, _, _ in found])
    unstable = int(np.sum(freqs < 0.0))
    if unstable:
        log.warning("modal analysis: %s", unstable_note(freqs))
    return ModalResults(frequencies_hz=freqs, shapes=shapes, line_shapes=line_shapes,
                        message=join_notes(statics_disabled_note(sc) if not linear_only else "",
                                           unstable_note(freqs), count_note(requested, available)),
                        unstable=unstable, scale_hz=omega_max / (2 * math.pi))


def _as_list(p):
    return p if isinstance(p, list) else [p]
