"""Kinematic chains of rigid and flexible links on a moving base (sections 8.1.4, 8.2, 5.4).

Describe, compile, solve::

    chain = Chain(gravity=(0, 0, -9.81), base=BaseMotion.rotating("z", angle_fn))
    chain.add("column", RigidLink(length=10, mass=5e3), Joint.revolute("z", drive=Prescribed(slew)))
    chain.add("boom", ModifiedLink(30, 20, props), Joint.revolute("y", offset=(0, 0, 0)), parent="column")
    chain.add_load("boom", s=30, force=(0, 0, -1e4))
    model = chain.compile()                       # frozen arrays (ChainModel)
    st = chain_statics(model)                     # Newton
    res = simulate_chain(model, t_end=10, dt=1e-3, q0=st.q)
    tip = res.point("boom", 30)                   # world position/velocity/acceleration

Each link's RFE 0 joins the body of the parent link that carries the attachment point
(by default the parent's tip: its last RFE, as in section 8.1.4). A joint coordinate is
free, driven by a prescribed time function (`Prescribed`: position, velocity and
acceleration), or free with a generalised force (`JointForce`). The equations
A q'' = f (eqs. 8.34, 8.51) are written for all coordinates; prescribed ones (and the RFE
coordinates held at zero) are removed from the unknowns and their accelerations enter
the velocity terms like the base motion (eq. 8.12's base terms).
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from . import tree
from .classical import rechain
from .dynamics import evaluate_kernel, solve_free
from .links import Link
from .transforms import (
    FIXED,
    JOINT_COORDS,
    PRISMATIC,
    REVOLUTE,
    SPHERICAL,
    base_matrices,
    homogeneous,
)

_AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
_KINDS = {"fixed": FIXED, "revolute": REVOLUTE, "prismatic": PRISMATIC, "spherical": SPHERICAL}


def _axis(a) -> np.ndarray:
    v = np.asarray(_AXES[a] if isinstance(a, str) else a, dtype=float)
    nrm = np.linalg.norm(v)
    if v.shape != (3,) or not nrm > 0.0:
        raise ValueError(f"axis must be 'x', 'y', 'z' or a non-zero 3-vector, got {a!r}")
    return v / nrm


# ----------------------------------------------------------------------------- drives
@dataclass(frozen=True)
class Prescribed:
    """Joint coordinates driven by a time function: motion(t) -> (q, q', q'') (scalars for a
    one-coordinate joint, (n,) arrays otherwise)."""
    motion: Callable


@dataclass(frozen=True)
class JointForce:
    """A free joint coordinate loaded by a generalised force (N or N*m):
    force(t, q, q') -> (n,) or scalar."""
    force: Callable


@dataclass(frozen=True)
class Joint:
    """Joint between a link's RFE 0 and its parent (or the base).

    kind: "fixed" | "revolute" | "prismatic" | "spherical" (ZYX angles phi_x, phi_y, phi_z);
    axis: the revolute/prismatic axis in the joint frame; offset (3,) m and rotation (3, 3):
    the joint frame in the parent's attachment frame (the link frame equals the joint frame
    at zero joint coordinates); drive: None (free), `Prescribed` or `JointForce`;
    stiffness (N/m or N*m/rad), damping and rest: an optional spring on the joint coordinates.
    """
    kind: str = "fixed"
    axis: object = "z"
    offset: tuple = (0.0, 0.0, 0.0)
    rotation: object = None
    drive: object = None
    stiffness: float = 0.0
    damping: float = 0.0
    rest: object = 0.0

    def __post_init__(self):
        if self.kind not in _KINDS:
            raise ValueError(f"joint kind must be one of {sorted(_KINDS)}, got {self.kind!r}")
        if self.drive is not None and not isinstance(self.drive, (Prescribed, JointForce)):
            raise ValueError("joint drive must be None, Prescribed or JointForce")
        if self.drive is not None and self.kind == "fixed":
            raise ValueError("a fixed joint cannot be driven")

    @classmethod
    def fixed(cls, offset=(0, 0, 0), rotation=None):
        return cls("fixed", offset=offset, rotation=rotation)

    @classmethod
    def revolute(cls, axis="z", offset=(0, 0, 0), rotation=None, drive=None, **kw):
        return cls("revolute", axis=axis, offset=offset, rotation=rotation, drive=drive, **kw)

    @classmethod
    def prismatic(cls, axis="x", offset=(0, 0, 0), rotation=None, drive=None, **kw):
        return cls("prismatic", axis=axis, offset=offset, rotation=rotation, drive=drive, **kw)

    @classmethod
    def spherical(cls, offset=(0, 0, 0), rotation=None, drive=None, **kw):
        return cls("spherical", offset=offset, rotation=rotation, drive=drive, **kw)

    @property
    def ncoords(self) -> int:
        return JOINT_COORDS[_KINDS[self.kind]]

    def frame(self) -> np.ndarray:
        return homogeneous(np.eye(3) if self.rotation is None else self.rotation, self.offset)


# ----------------------------------------------------------------------------- base
class BaseMotion:
    """Prescribed 6-DOF motion of the base frame {A} in the inertial frame (eq. 8.10.2).

    translation(t) -> (r, r', r'') and angles(t) -> (phi, phi', phi'') with ZYX angles
    (phi_x, phi_y, phi_z), each (3,); None = at rest at zero.
    """

    def __init__(self, translation: Callable | None = None, angles: Callable | None = None):
        self.translation = translation
        self.angles = angles

    @classmethod
    def fixed(cls, position=(0.0, 0.0, 0.0), angles=(0.0, 0.0, 0.0)):
        p = np.asarray(position, float)
        a = np.asarray(angles, float)
        z = np.zeros(3)
        return cls(lambda t: (p, z, z), lambda t: (a, z, z))

    @classmethod
    def rotating(cls, axis: str, angle: Callable):
        """Rotation about the inertial x, y or z axis by angle(t) -> (a, a', a'')."""
        i = "xyz".index(axis)

        def ang(t):
            a, ad, add = angle(t)
            v = np.zeros((3, 3))
            v[0, i], v[1, i], v[2, i] = a, ad, add
            return v[0], v[1], v[2]
        return cls(None, ang)

    def __call__(self, t: float):
        z = np.zeros(3)
        p, v, a = (z, z, z) if self.translation is None else map(np.asarray, self.translation(t))
        ang, rate, acc = (z, z, z) if self.angles is None else map(np.asarray, self.angles(t))
        return base_matrices(p, v, a, ang, rate, acc)


# ----------------------------------------------------------------------------- description
@dataclass
class _LinkEntry:
    name: str
    link: Link
    joint: Joint
    parent: str | None
    at: float | None


@dataclass
class _Load:
    link: str
    s: float
    offset: np.ndarray
    force: object
    moment: object


class Chain:
    """An editable description of a kinematic chain (or tree) of links on a base."""

    def __init__(self, gravity=(0.0, 0.0, -9.81), base: BaseMotion | None = None):
        self.gravity = np.asarray(gravity, float)
        self.base = base if base is not None else BaseMotion()
        self.links: list[_LinkEntry] = []
        self.loads: list[_Load] = []

    def add(self, name: str, link: Link, joint: Joint | None = None, parent: str | None = None,
            at: float | None = None) -> Chain:
        """Append a link joined to `parent` (None: the base) at arc length `at` of the parent
        (default: its tip)."""
        names = [e.name for e in self.links]
        if name in names:
            raise ValueError(f"link {name!r} already exists")
        if parent is not None and parent not in names:
            raise ValueError(f"parent link {parent!r} not found (links: {names})")
        self.links.append(_LinkEntry(name, link, joint if joint is not None else Joint.fixed(), parent, at))
        return self

    def add_load(self, link: str, s: float, force=(0.0, 0.0, 0.0), moment=(0.0, 0.0, 0.0), offset=(0.0, 0.0, 0.0)):
        """A dead force (N) and moment (N*m) in the inertial frame at arc length s of a link
        (+ offset in the link axes); constants or callables of t."""
        if link not in [e.name for e in self.links]:
            raise ValueError(f"link {link!r} not found")
        self.loads.append(_Load(link, float(s), np.asarray(offset, float), force, moment))
        return self

    def compile(self) -> ChainModel:
        return compile_chain(self)


# ----------------------------------------------------------------------------- model
@dataclass
class LinkInfo:
    name: str
    link: Link
    first_body: int
    nbodies: int
    joint_coords: np.ndarray      # indices of the joint coordinates in q
    coords: np.ndarray            # all coordinates of the link


@dataclass
class ChainModel:
    """Frozen arrays of a compiled chain (nb bodies, nq coordinates)."""
    parent: np.ndarray            # (nb,) parent body, -1 = base
    kind: np.ndarray              # (nb,) joint kind (transforms.FIXED ...)
    axis: np.ndarray              # (nb, 3) joint axis
    placement: np.ndarray         # (nb, 4, 4) constant joint placement C in the parent frame
    inertia: np.ndarray           # (nb, 4, 4) pseudo-inertia H, kg, kg*m, kg*m^2
    undeformed: np.ndarray        # (nb, 4, 4) body frame in its link frame at zero coordinates
    qstart: np.ndarray            # (nb,) first coordinate of each body
    qcount: np.ndarray            # (nb,)
    coordinate_names: list
    free: np.ndarray              # (nf,) unknown coordinates
    lam: np.ndarray               # (nf,) parent of each unknown in the branch-sparse order, -1 root
    locked: np.ndarray            # (nl,) coordinates held at zero
    prescribed: list              # [(indices, motion)]
    forces: list                  # [(indices, force)]
    coord_stiffness: np.ndarray   # (nq,) N/m or N*m/rad (eq. 8.49, joint springs)
    coord_damping: np.ndarray     # (nq,)
    coord_rest: np.ndarray        # (nq,)
    sde_left: np.ndarray          # (ns,) body index (classical SDEs, eq. 8.21)
    sde_right: np.ndarray
    sde_left_root: np.ndarray     # (ns,) bool: the left body is the link's RFE 0
    sde_right_root: np.ndarray
    sde_point_left: np.ndarray    # (ns, 3) m
    sde_point_right: np.ndarray
    sde_stiffness: np.ndarray     # (ns, 6)
    sde_damping: np.ndarray       # (ns, 6)
    gravity: np.ndarray           # (3,) m/s^2
    base: BaseMotion
    load_body: np.ndarray         # (npl,)
    load_point: np.ndarray        # (npl, 3) m in the body frame
    load_force: list              # constants or callables
    load_moment: list
    links: dict = field(default_factory=dict)

    @property
    def nq(self) -> int:
        return len(self.coordinate_names)

    @property
    def nbodies(self) -> int:
        return len(self.parent)

    def index(self, name: str) -> int:
        """Index of a coordinate by name, e.g. 'boom.rfe3.phi_z' or 'arm.joint0'."""
        return self.coordinate_names.index(name)

    def locate(self, link: str, s: float, offset=(0.0, 0.0, 0.0)):
        """(body index, point (3,) in that body's frame) of the material point at arc
        length s of a link (+ offset in the link axes)."""
        info = self.links[link]
        i = info.link.locate(s)
        b = info.first_body + i
        U = self.undeformed[b]
        p = np.array([s + offset[0], offset[1], offset[2], 1.0])
        return b, (np.linalg.solve(U, p))[:3]


def compile_chain(chain: Chain) -> ChainModel:
    """Discretise every link into bodies and number the coordinates (eq. 8.33.1)."""
    parent, kind, axis, placement, inertia, undeformed, qstart, qcount = [], [], [], [], [], [], [], []
    names, locked, prescribed, forces = [], [], [], []
    stiff, damp, rest = [], [], []
    sdes = []
    links = {}
    nq = 0
    for entry in chain.links:
        first = len(parent)
        bodies = entry.link.bodies()
        if entry.parent is None:
            attach = np.eye(4)
            attach_body = -1
        else:
            pinfo = links[entry.parent]
            s = pinfo.link.length if entry.at is None else float(entry.at)
            pb = pinfo.first_body + pinfo.link.locate(s)
            attach = np.linalg.solve(undeformed[pb], homogeneous(translation=(s, 0, 0)))
            attach_body = pb
        joint = entry.joint
        link_coords = []
        joint_coords = np.arange(nq, nq + joint.ncoords)
        for i, b in enumerate(bodies):
            if i == 0:
                kb = _KINDS[joint.kind]
                ax = _axis(joint.axis) if kb in (REVOLUTE, PRISMATIC) else np.zeros(3)
                C = attach @ joint.frame()
                par = attach_body
                n = joint.ncoords
                bnames = [f"{entry.name}.joint{j}" for j in range(n)]
                bl = [False] * n
                bs = [joint.stiffness] * n
                bd = [joint.damping] * n
                br = list(np.broadcast_to(np.asarray(joint.rest, float), (n,))) if n else []
                if isinstance(joint.drive, Prescribed):
                    prescribed.append((np.arange(nq, nq + n), joint.drive.motion))
                elif isinstance(joint.drive, JointForce):
                    forces.append((np.arange(nq, nq + n), joint.drive.force))
            else:
                kb = b.kind
                ax = b.axis
                C = b.placement
                par = first + b.parent
                n = JOINT_COORDS[kb]
                bnames = [f"{entry.name}.{x}" for x in b.names]
                bl = list(b.locked) if b.locked else [False] * n
                bs = list(b.stiffness) if len(b.stiffness) else [0.0] * n
                bd = list(b.damping) if len(b.damping) else [0.0] * n
                br = [0.0] * n
            parent.append(par)
            kind.append(kb)
            axis.append(ax)
            placement.append(C)
            inertia.append(b.inertia)
            undeformed.append(b.undeformed)
            qstart.append(nq)
            qcount.append(n)
            names += bnames
            locked += [nq + j for j in range(n) if bl[j]]
            stiff += bs
            damp += bd
            rest += br
            link_coords += list(range(nq, nq + n))
            nq += n
        for sde in entry.link.sdes():
            sdes.append((first + sde.left, first + sde.right, sde.left == 0, sde.right == 0, sde.point_left,
                         sde.point_right, sde.stiffness, sde.damping))
        links[entry.name] = LinkInfo(entry.name, entry.link, first, len(bodies), joint_coords,
                                     np.array(link_coords, dtype=np.int64))
    fixed_coords = set(locked)
    for idx, _ in prescribed:
        fixed_coords |= set(idx.tolist())
    free = np.array([k for k in range(nq) if k not in fixed_coords], dtype=np.int64)
    # branch-sparse parent of each unknown: the previous unknown on the path to the root
    body_of = np.repeat(np.arange(len(parent)), qcount)
    pos = {k: i for i, k in enumerate(free)}
    lam = np.full(len(free), -1, dtype=np.int64)
    for i, k in enumerate(free):
        b = body_of[k]
        j = k - 1
        while j >= qstart[b]:
            if j in pos:
                lam[i] = pos[j]
                break
            j -= 1
        if lam[i] >= 0:
            continue
        c = parent[b]
        while c >= 0 and lam[i] < 0:
            for j in range(qstart[c] + qcount[c] - 1, qstart[c] - 1, -1):
                if j in pos:
                    lam[i] = pos[j]
                    break
            c = parent[c]
    load_body, load_point = [], []
    tmp = ChainModel(parent=np.array(parent, dtype=np.int64), kind=np.array(kind, dtype=np.int64),
                     axis=np.array(axis, float).reshape(-1, 3), placement=np.array(placement).reshape(-1, 4, 4),
                     inertia=np.array(inertia).reshape(-1, 4, 4), undeformed=np.array(undeformed).reshape(-1, 4, 4),
                     qstart=np.array(qstart, dtype=np.int64), qcount=np.array(qcount, dtype=np.int64),
                     coordinate_names=names, free=free, lam=lam, locked=np.array(locked, dtype=np.int64),
                     prescribed=prescribed, forces=forces, coord_stiffness=np.array(stiff, float),
                     coord_damping=np.array(damp, float), coord_rest=np.array(rest, float),
                     sde_left=np.array([s[0] for s in sdes], dtype=np.int64),
                     sde_right=np.array([s[1] for s in sdes], dtype=np.int64),
                     sde_left_root=np.array([s[2] for s in sdes], dtype=np.bool_),
                     sde_right_root=np.array([s[3] for s in sdes], dtype=np.bool_),
                     sde_point_left=np.array([s[4] for s in sdes], float).reshape(-1, 3),
                     sde_point_right=np.array([s[5] for s in sdes], float).reshape(-1, 3),
                     sde_stiffness=np.array([s[6] for s in sdes], float).reshape(-1, 6),
                     sde_damping=np.array([s[7] for s in sdes], float).reshape(-1, 6),
                     gravity=chain.gravity.copy(), base=chain.base, load_body=np.zeros(0, dtype=np.int64),
                     load_point=np.zeros((0, 3)), load_force=[], load_moment=[], links=links)
    for ld in chain.loads:
        b, p = tmp.locate(ld.link, ld.s, ld.offset)
        load_body.append(b)
        load_point.append(p)
    tmp.load_body = np.array(load_body, dtype=np.int64)
    tmp.load_point = np.array(load_point, float).reshape(-1, 3)
    tmp.load_force = [ld.force for ld in chain.loads]
    tmp.load_moment = [ld.moment for ld in chain.loads]
    return tmp


# ----------------------------------------------------------------------------- evaluation
class ChainData:
    """Work buffers for one model, allocated once."""

    def __init__(self, model: ChainModel):
        nb, nq = model.nbodies, model.nq
        self.T = np.zeros((nb, 4, 4))
        self.Td = np.zeros((nb, 4, 4))
        self.Tdd = np.zeros((nb, 4, 4))
        self.Omega = np.zeros((nq, 4, 4))
        self.Hc = np.zeros((nb, 4, 4))
        self.Fc = np.zeros((nb, 4, 4))
        self.Mc = np.zeros((nb, 3, 3))
        self.A = np.zeros((nq, nq))
        self.h = np.zeros(nq)
        self.S = np.zeros(nq)
        self.f = np.zeros(nq)
        nf = len(model.free)
        self.Aff = np.zeros((nf, nf))
        self.rhs = np.zeros(nf)
        self.x = np.zeros(nf)
        npl = len(model.load_body)
        self.load_force = np.zeros((npl, 3))
        self.load_moment = np.zeros((npl, 3))
        self.elastic_energy = 0.0
        self.nfev = 0


def _value(v, t):
    return np.asarray(v(t) if callable(v) else v, float)


def fill_prescribed(model: ChainModel, t: float, q, qd, qdd):
    """Write the prescribed coordinates (and the locked ones, zero) into q, q', q''."""
    q[model.locked] = 0.0
    qd[model.locked] = 0.0
    qdd[model.locked] = 0.0
    for idx, motion in model.prescribed:
        a, b, c = motion(t)
        q[idx] = a
        qd[idx] = b
        qdd[idx] = c


def evaluate(model: ChainModel, data: ChainData, t: float, q, qd, qdd, *, mass: bool = True, load_scale=1.0):
    """Right-hand side f = -e - G - S + Q (eqs. 8.34, 8.51) for all coordinates, with the
    accelerations qdd of the prescribed coordinates in the velocity terms (free entries of
    qdd must be zero for f to be the right-hand side); the mass matrix into data.A.
    The velocity, gravity and load terms e + G - Q are left in data.h, the elastic ones in data.S."""
    TA, TAd, TAdd = model.base(t)
    for i, (F, M) in enumerate(zip(model.load_force, model.load_moment)):
        data.load_force[i] = load_scale * _value(F, t)
        data.load_moment[i] = load_scale * _value(M, t)
    f = data.f
    data.elastic_energy = evaluate_kernel(
        model.parent, model.kind, model.axis, model.placement, model.inertia, model.qstart, model.qcount,
        model.coord_stiffness, model.coord_damping, model.coord_rest, model.sde_left, model.sde_right,
        model.sde_left_root, model.sde_right_root, model.sde_point_left, model.sde_point_right, model.sde_stiffness,
        model.sde_damping, model.load_body, model.load_point, data.load_force, data.load_moment,
        load_scale * model.gravity, TA, TAd, TAdd, q, qd, qdd, mass, data.T, data.Td, data.Tdd, data.Omega,
        data.Hc, data.Fc, data.Mc, data.A, data.h, data.S, f)
    for idx, force in model.forces:
        f[idx] += load_scale * np.asarray(force(t, q[idx], qd[idx]), float)
    data.nfev += 1
    return f.copy()


def equations(model: ChainModel, t: float, q, qd, data: ChainData | None = None):
    """(A (nq, nq), f (nq,)) of A q'' = f with q'' of the prescribed coordinates moved into f;
    the rows and columns of the unknowns are model.free."""
    data = data or ChainData(model)
    q = np.array(q, float)
    qd = np.array(qd, float)
    qdd = np.zeros(model.nq)
    fill_prescribed(model, t, q, qd, qdd)
    f = evaluate(model, data, t, q, qd, qdd)
    return data.A.copy(), f


def accelerations(model: ChainModel, data: ChainData, t: float, q, qd):
    """Full q'' (prescribed from their drives, unknowns from A_ff q''_f = f_f by the
    branch-sparse LTL factorisation). q and qd must hold the prescribed values."""
    qdd = np.zeros(model.nq)
    fill_prescribed(model, t, q, qd, qdd)
    f = evaluate(model, data, t, q, qd, qdd)
    if not solve_free(data.A, f, model.free, model.lam, data.Aff, data.rhs, data.x):
        raise np.linalg.LinAlgError(f"mass matrix not positive definite at t = {t:.6g} s")
    qdd[model.free] = data.x
    return qdd


def chain_energy(model: ChainModel, t: float, q, qd) -> dict:
    """Kinetic energy (eq. 8.42), gravity potential (eq. 8.44) and elastic energy (eqs. 8.21,
    8.47) in J."""
    data = ChainData(model)
    q = np.array(q, float)
    qd = np.array(qd, float)
    qdd = np.zeros(model.nq)
    fill_prescribed(model, t, q, qd, qdd)
    evaluate(model, data, t, q, qd, qdd, mass=False)
    return {"kinetic": tree.kinetic_energy(model.inertia, data.Td),
            "gravity": tree.gravity_potential(model.inertia, data.T, model.gravity),
            "elastic": data.elastic_energy}


def point_motion(model: ChainModel, t: float, q, qd, qdd, link: str, s: float, offset=(0.0, 0.0, 0.0)):
    """World position, velocity and acceleration (3,) each of the material point at arc
    length s (+ offset in the link axes) of a link."""
    b, p = model.locate(link, s, offset)
    data = ChainData(model)
    TA, TAd, TAdd = model.base(t)
    tree.forward_pass(model.parent, model.kind, model.axis, model.placement, model.qstart, model.qcount,
                      np.asarray(q, float), np.asarray(qd, float), np.asarray(qdd, float), TA, TAd, TAdd,
                      data.T, data.Td, data.Tdd, data.Omega)
    r = np.append(p, 1.0)
    return data.T[b][:3] @ r, data.Td[b][:3] @ r, data.Tdd[b][:3] @ r


# ----------------------------------------------------------------------------- solvers
@dataclass
class ChainStatics:
    q: np.ndarray                 # (nq,) equilibrium coordinates
    success: bool
    message: str
    iterations: int
    residual: float               # max |f| over the unknowns at the end, N or N*m


def _residual(model, data, t, qf, q, scale):
    q = q.copy()
    q[model.free] = qf
    fill_prescribed_positions(model, t, q)
    qd = np.zeros(model.nq)
    qdd = np.zeros(model.nq)
    return evaluate(model, data, t, q, qd, qdd, mass=False, load_scale=scale)[model.free]


def fill_prescribed_positions(model, t, q):
    q[model.locked] = 0.0
    for idx, motion in model.prescribed:
        q[idx] = motion(t)[0]


def stiffness_matrix(model: ChainModel, t: float, q, data: ChainData | None = None, h: float = 1e-6, scale=1.0):
    """K = -df/dq over the unknowns at rest (central differences), (nf, nf)."""
    data = data or ChainData(model)
    qf = np.asarray(q, float)[model.free].copy()
    n = len(qf)
    K = np.empty((n, n))
    for j in range(n):
        step = h * max(1.0, abs(qf[j]))
        qp = qf.copy()
        qp[j] += step
        qm = qf.copy()
        qm[j] -= step
        K[:, j] = -(_residual(model, data, t, qp, q, scale) - _residual(model, data, t, qm, q, scale)) / (2 * step)
    return K


MAX_ROTATION_STEP = 0.5     # rad, largest rotation of a chain_statics Newton update


def _rotation_mask(model: ChainModel) -> np.ndarray:
    """(nq,) True for angle coordinates (revolute, spherical, the angles of free RFEs)."""
    rot = np.zeros(model.nq, dtype=bool)
    for b in range(model.nbodies):
        k, s, n = int(model.kind[b]), int(model.qstart[b]), int(model.qcount[b])
        if k in (REVOLUTE, SPHERICAL):
            rot[s:s + n] = True
        elif n == 6:                         # FREE_ZYX / FREE_LINEAR: x, y, z, phi_x, phi_y, phi_z
            rot[s + 3:s + 6] = True
    return rot


def newton_step(K: np.ndarray, r: np.ndarray, rcond: float = 1e-12) -> np.ndarray:
    """Newton step dx of K dx = r that never raises on zero-stiffness directions.

    A chain can have directions of (numerically) zero stiffness: the spin of a pinned line
    about its own axis at the spherical joint, the torsion of a cable with GJ ~ 0, a free
    joint with nothing holding it. K is Jacobi-scaled (each coordinate by the square root
    of its diagonal stiffness, floored at 1e-8 of the largest so unloaded coordinates stay
    comparable) and solved by the pseudo-inverse: singular values below rcond of the
    largest are dropped, so such directions get no step (their equilibrium is arbitrary and
    they stay where they are), as the absolute-coordinate statics' regularisation does.
    A well-conditioned K takes the ordinary LU solve."""
    n = len(r)
    if n == 0:
        return np.zeros(0)
    d = np.abs(np.diag(K))
    dmax = float(d.max()) if np.all(np.isfinite(d)) else 0.0
    if not dmax > 0.0 or not np.all(np.isfinite(K)):
        return np.zeros(n) if not dmax > 0.0 and np.all(np.isfinite(K)) else np.full(n, np.nan)
    s = 1.0 / np.sqrt(np.maximum(d, 1e-8 * dmax))
    Ks = K * s[:, None] * s[None, :]
    U, sv, Vt = np.linalg.svd(Ks)
    keep = sv > rcond * sv[0]
    y = Vt[keep].T @ ((U[:, keep].T @ (s * r)) / sv[keep])
    return s * y


def _load_scale(model: ChainModel, data: ChainData, t: float) -> float:
    """Force scale of the applied loads, N*m: (total weight + point forces) x the largest
    body reach from the base + point moments; the residual tolerance of chain_statics is
    relative to it (as planar statics does)."""
    m = model.inertia[:, 3, 3]
    reach = np.linalg.norm(data.T[:, :3, 3] - data.T[:, None, :3, 3].mean(axis=0), axis=-1).max() \
        if model.nbodies else 0.0
    size = max(reach, sum(float(info.link.length) for info in model.links.values()), 1.0)
    weight = float(m.sum()) * float(np.linalg.norm(model.gravity))
    forces = sum(float(np.linalg.norm(_value(F, t))) for F in model.load_force)
    moments = sum(float(np.linalg.norm(_value(M, t))) for M in model.load_moment)
    total = (weight + forces) * size + moments
    return total if total > 0.0 else 1.0


def chain_statics(model: ChainModel, t: float = 0.0, q0=None, *, load_steps: int = 1, tol: float = 1e-9,
                  max_iter: int = 60) -> ChainStatics:
    """Static equilibrium f(q, 0) = 0 over the unknowns by Newton's method with a
    central-difference Jacobian, backtracking, and gravity and loads ramped in load_steps.

    Converged when the Newton step is below tol (rad or m, relative to max(1, |q|)) or the
    residual is below tol x the load scale (weight and point forces x the chain's size +
    point moments, N*m; `_load_scale`): a residual at round-off can leave a step above tol
    in a nearly stiffness-free direction. Zero-stiffness directions (the spin of a pinned
    line about its axis) get no step (`newton_step`)."""
    data = ChainData(model)
    q = np.zeros(model.nq) if q0 is None else np.array(q0, float)
    fill_prescribed_positions(model, t, q)
    qf = q[model.free].copy()
    total = 0
    res = np.inf
    rechained = len(model.sde_left) > 0
    locked = np.ones(model.nq, dtype=bool)
    locked[model.free] = False
    rot = _rotation_mask(model)[model.free]
    for step in range(1, load_steps + 1):
        scale = step / load_steps
        r = _residual(model, data, t, qf, q, scale)
        fscale = _load_scale(model, data, t) * scale
        K = stiffness_matrix(model, t, _with(q, model.free, qf), data, scale=scale)
        dx = newton_step(K, r)
        ok = False
        for it in range(max_iter):
            total += 1
            small = tol * max(1.0, np.max(np.abs(qf), initial=0.0))
            if np.max(np.abs(dx), initial=0.0) <= small:
                qf = qf + dx
                r = _residual(model, data, t, qf, q, scale)
                ok = True
                break
            if it > 0 and np.max(np.abs(r), initial=0.0) <= tol * fscale:
                ok = True
                break
            # at most MAX_ROTATION_STEP rad of rotation per iteration (a slack line's first
            # steps can be many radians), then backtracking
            alpha = min(1.0, MAX_ROTATION_STEP / max(float(np.max(np.abs(dx[rot]), initial=0.0)), 1e-300))
            while True:      # accept when the next Newton step is shorter (affine covariant, Deuflhard)
                trial = qf + alpha * dx
                if rechained:
                    trial = rechain(model, _with(q, model.free, qf), _with(q, model.free, trial), locked)[model.free]
                rt = _residual(model, data, t, trial, q, scale)
                if np.all(np.isfinite(rt)):
                    Kt = stiffness_matrix(model, t, _with(q, model.free, trial), data, scale=scale)
                    dt = newton_step(Kt, rt)
                    if np.linalg.norm(dt) <= np.linalg.norm(dx) or alpha < 1e-3:
                        break
                elif alpha < 1e-3:
                    raise FloatingPointError("non-finite residual in chain_statics")
                alpha *= 0.5
            qf, r, K, dx = trial, rt, Kt, dt
        res = float(np.max(np.abs(r))) if len(r) else 0.0
        if not ok:
            q[model.free] = qf
            return ChainStatics(q, False, f"Newton did not converge at load step {step}/{load_steps} "
                                          f"(max |f| = {res:.3e}); try more load_steps", total, res)
    q[model.free] = qf
    return ChainStatics(q, True, "converged", total, res)


def _with(q, idx, vals):
    out = q.copy()
    out[idx] = vals
    return out


def chain_modes(model: ChainModel, q, t: float = 0.0):
    """Natural frequencies (rad/s, ascending) and mode shapes (nq, nf) of the free
    coordinates linearised about an equilibrium q: K x = w^2 A x.

    An unstable direction (w^2 < 0: negative stiffness) gives a negative frequency
    -sqrt(-w^2) (rfesim.solvers.modal.signed_omega); round-off zero modes give 0."""
    from ..solvers.modal import signed_omega
    data = ChainData(model)
    q = np.array(q, float)
    if len(model.free) == 0:
        return np.zeros(0), np.zeros((model.nq, 0))
    K = stiffness_matrix(model, t, q, data)
    K = 0.5 * (K + K.T)
    A, _ = equations(model, t, q, np.zeros(model.nq), data)
    Aff = A[np.ix_(model.free, model.free)]
    w2, vec = scipy.linalg.eigh(K, Aff)
    shapes = np.zeros((model.nq, len(w2)))
    shapes[model.free] = vec
    return signed_omega(w2, float(np.abs(w2).max())), shapes


@dataclass
class ChainResult:
    """Time history of a chain (in the spirit of scipy's OdeResult)."""
    model: ChainModel
    t: np.ndarray                 # (nt,) s
    q: np.ndarray                 # (nt, nq)
    qd: np.ndarray                # (nt, nq)
    qdd: np.ndarray               # (nt, nq)
    success: bool
    message: str
    nsteps: int
    nfev: int
    failure_time: float | None = None   # s, where a failed run stopped (success False)

    def coordinate(self, name: str) -> np.ndarray:
        return self.q[:, self.model.index(name)]

    def point(self, link: str, s: float, offset=(0.0, 0.0, 0.0)):
        """World position, velocity and acceleration (nt, 3) of a material point."""
        out = np.empty((3, len(self.t), 3))
        for i, t in enumerate(self.t):
            p, v, a = point_motion(self.model, t, self.q[i], self.qd[i], self.qdd[i], link, s, offset)
            out[0, i], out[1, i], out[2, i] = p, v, a
        return out[0], out[1], out[2]

    def energy(self) -> dict:
        keys = ("kinetic", "gravity", "elastic")
        e = [chain_energy(self.model, t, q, qd) for t, q, qd in zip(self.t, self.q, self.qd)]
        return {k: np.array([x[k] for x in e]) for k in keys}


def simulate_chain(model: ChainModel | Chain, t_end: float, dt: float, q0=None, qd0=None, *,
                   output_every: int = 1, progress: Callable | None = None) -> ChainResult:
    """Integrate A q'' = f over the unknowns with the classical fixed-step RK4 from t = 0.

    Explicit: dt must resolve the highest frequency of the model (dt < 2.8 / w_max); the
    flexible links' dofs selection removes coordinates that are not needed. A step above
    that limit makes the state diverge: the run stops (success False, message and
    failure_time say where) with the history recorded so far, never raises.

    ``progress(fraction)`` is called after every step, once that step's output (if it is
    an output step) is recorded. A KeyboardInterrupt (Ctrl-C, or one the progress callback
    raises) propagates with the history recorded so far as ``history`` (a ChainResult,
    success False, message "interrupted at t = ..."; None before the first output).
    """
    if isinstance(model, Chain):
        model = model.compile()
    data = ChainData(model)
    nq = model.nq
    q = np.zeros(nq) if q0 is None else np.array(q0, float)
    qd = np.zeros(nq) if qd0 is None else np.array(qd0, float)
    fr = model.free
    nsteps = round(t_end / dt)
    ts, qs, qds, qdds = [], [], [], []

    def rhs(t, yq, yv):
        qq = q.copy()
        vv = qd.copy()
        qq[fr] = yq
        vv[fr] = yv
        fill_prescribed(model, t, qq, vv, np.zeros(nq))
        return accelerations(model, data, t, qq, vv), qq, vv

    t = 0.0
    yq = q[fr].copy()
    yv = qd[fr].copy()
    message = "completed"
    success = True
    failure_time = None

    def result(success, message, failure_time):
        # the rows recorded in full (an interruption may fall between the appends)
        k = min(len(ts), len(qs), len(qds), len(qdds))
        shape = (0, nq)
        return ChainResult(model, np.array(ts[:k]), np.array(qs[:k]).reshape(-1, nq) if k else np.zeros(shape),
                           np.array(qds[:k]).reshape(-1, nq) if k else np.zeros(shape),
                           np.array(qdds[:k]).reshape(-1, nq) if k else np.zeros(shape), success, message, nsteps,
                           data.nfev, failure_time)

    try:
        for n in range(nsteps + 1):
            try:
                qdd, qq, vv = rhs(t, yq, yv)
            except np.linalg.LinAlgError as exc:         # a diverged state: stop with what was recorded
                success, message, failure_time = False, str(exc), t
                break
            if not (np.all(np.isfinite(yq)) and np.all(np.isfinite(yv)) and np.all(np.isfinite(qdd))):
                success, message, failure_time = False, f"non-finite state at t = {t:.6g} s", t
                break
            if n % output_every == 0 or n == nsteps:
                ts.append(t)
                qs.append(qq)
                qds.append(vv)
                qdds.append(qdd)
            if n > 0 and progress is not None:
                progress(t / t_end)
            if n == nsteps:
                break
            try:
                k1q, k1v = yv, qdd[fr]
                k2q = yv + 0.5 * dt * k1v
                k2v = rhs(t + 0.5 * dt, yq + 0.5 * dt * k1q, k2q)[0][fr]
                k3q = yv + 0.5 * dt * k2v
                k3v = rhs(t + 0.5 * dt, yq + 0.5 * dt * k2q, k3q)[0][fr]
                k4q = yv + dt * k3v
                k4v = rhs(t + dt, yq + dt * k3q, k4q)[0][fr]
            except np.linalg.LinAlgError as exc:
                success, message, failure_time = False, str(exc), t
                break
            yq = yq + dt / 6.0 * (k1q + 2 * k2q + 2 * k3q + k4q)
            yv = yv + dt / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v)
            t = (n + 1) * dt
    except KeyboardInterrupt as exc:
        part = result(False, "interrupted", None)
        if len(part.t):
            part.message = f"interrupted at t = {part.t[-1]:.6g} s"
        exc.history = part if len(part.t) else None
        raise
    return result(success, message, failure_time)
