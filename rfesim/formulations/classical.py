"""Classical RFE formulation (section 8.1).

A beam link p of length L with n = m_p elements is divided into n + 1 rigid finite
elements (Fig. 8.2): RFE 0 (length d/2, d = L/n) carries the link's joint coordinates;
RFEs 1..n each have six coordinates (x, y, z, phi_x, phi_y, phi_z) (eq. 8.6) measured
from their undeformed pose T~(p,i') = Trans(x_i) in the frame {p,0} of RFE 0 (eq. 8.5,
R~(p,i') = I), through the nonlinear matrix of eq. 8.7 or the linear one of eq. 8.8;
T~(p,i) = T~(p,i') T(q~(p,i)) (eq. 8.9). The frame of RFE i (i >= 1) is at its centre
of mass; that of RFE 0 is at the joint.

SDE e (e = 1..n, at x = (e - 1/2) d) joins RFE e-1 and RFE e. Its energy is eq. 8.21/8.24:
translational springs on the gap Delta r = T~(p,r) r~_r - T~(p,l) r~_l in the axes of
{p,0} (eq. 8.23) and rotational springs on the differences of the angles. The generalised
elastic forces S (eq. 8.29) follow by the chain rule with the analytic derivatives of the
transformation matrices; for the linear model they are the constant-matrix form
S = K_T q + S_c (eq. 8.35) of `linear_matrices`.

Since every RFE i >= 1 hangs directly on RFE 0, the kinematic tree has depth 2 inside the
link and the composite-body mass matrix (`tree.mass_matrix`) has the arrow structure of
eq. 8.34: configuration rows dense, the RFE blocks diagonal (6x6 blocks, constant and
diagonal for the linear model). `tree.ltl_factor` factors it in O(n).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numba import njit

from .links import (
    BeamProperties,
    BodySpec,
    Link,
    SdeSpec,
    body_placement,
    check_dofs,
    rfe_lengths,
    sde_translational_stiffness,
)
from .transforms import (
    FIXED,
    FREE_LINEAR,
    FREE_ZYX,
    joint_matrices_into,
    joint_scratch,
    pseudo_inertia,
)

CLASSICAL_DOFS = ("x", "y", "z", "rx", "ry", "rz")
COORD_NAMES = ("x", "y", "z", "phi_x", "phi_y", "phi_z")


class ClassicalLink(Link):
    """A flexible beam link in the classical RFE formulation (section 8.1).

    length m; elements n (= m_p); props: `BeamProperties` (EA needed); linear: use the
    small-rotation matrix of eq. 8.8 instead of eq. 8.7; dofs: the RFE coordinates that are
    free, a subset of ("x", "y", "z", "rx", "ry", "rz") (the others are held at zero,
    the reduced models at the end of section 8.1.4).
    """

    def __init__(self, length: float, elements: int, props: BeamProperties, *, linear: bool = False, dofs=None):
        self.length = float(length)
        self.elements = int(elements)
        self.props = props
        self.linear = bool(linear)
        self.formulation = "classical-linear" if linear else "classical"
        self.dofs = check_dofs(dofs, CLASSICAL_DOFS)
        self.ell = rfe_lengths(self.length, self.elements)
        d = self.length / self.elements
        self.spacing = d
        # centres: RFE 0 frame at the joint; RFE i at its centre of mass
        self.origins = np.concatenate([[0.0], np.arange(1, self.elements) * d, [self.length - 0.25 * d]])
        self._bodies = self._build_bodies()
        self._sdes = self._build_sdes()

    def _build_bodies(self):
        n = self.elements
        d = self.spacing
        out = []
        m0, J0 = self.props.element_inertia(self.ell[0])
        out.append(BodySpec(parent=-1, kind=FIXED, axis=np.zeros(3), placement=np.eye(4),
                            inertia=pseudo_inertia(m0, (0.5 * self.ell[0], 0, 0), J0), undeformed=np.eye(4),
                            s_range=(0.0, 0.5 * d)))
        locked = tuple(name not in self.dofs for name in CLASSICAL_DOFS)
        kind = FREE_LINEAR if self.linear else FREE_ZYX
        for i in range(1, n + 1):
            m, J = self.props.element_inertia(self.ell[i])
            lo = (i - 0.5) * d
            hi = min((i + 0.5) * d, self.length)
            out.append(BodySpec(parent=0, kind=kind, axis=np.zeros(3), placement=body_placement(self.origins[i]),
                                inertia=pseudo_inertia(m, (0, 0, 0), J), undeformed=body_placement(self.origins[i]),
                                s_range=(lo, hi), locked=locked, names=tuple(f"rfe{i}.{c}" for c in COORD_NAMES)))
        return out

    def _build_sdes(self):
        d = self.spacing
        ct = sde_translational_stiffness(self.props, d)
        cr = np.array([self.props.GJ, self.props.EIy, self.props.EIz]) / d
        c = np.concatenate([ct, cr])
        out = []
        for e in range(1, self.elements + 1):
            x = (e - 0.5) * d
            out.append(SdeSpec(left=e - 1, right=e, point_left=np.array([x - self.origins[e - 1], 0, 0]),
                               point_right=np.array([x - self.origins[e], 0, 0]), stiffness=c.copy(),
                               damping=self.props.damping * c))
        return out

    def bodies(self):
        return self._bodies

    def sdes(self):
        return self._sdes


@njit(cache=True)
def sde_forces(kind, C, qstart, sde_left, sde_right, sde_left_root, sde_right_root, sde_point_left,
               sde_point_right, sde_stiffness, sde_damping, q, qd, S):
    """Add the SDE forces dV/dq + damping (eqs. 8.21-8.29) to S (nq,); return the energy.

    The transformation of RFE i in {p,0} is its joint matrix T~(p,i) = C_i M(q_i) (eq. 8.9);
    RFE 0 is the reference itself (T~ = I, angles 0) and contributes no coordinates.
    """
    J, dJ, d2J, M, dM, d2M, work = joint_scratch()
    axis = np.zeros(3)
    pos = np.empty((2, 3))           # SDE point seen from left / right, in {p,0}
    vel = np.empty((2, 3))
    dpos = np.empty((2, 6, 3))       # d pos / d q_k
    ang = np.empty((2, 3))
    angd = np.empty((2, 3))
    energy = 0.0
    for e in range(sde_left.shape[0]):
        for side in range(2):
            b = sde_left[e] if side == 0 else sde_right[e]
            root = sde_left_root[e] if side == 0 else sde_right_root[e]
            pt = sde_point_left[e] if side == 0 else sde_point_right[e]
            if root:
                for i in range(3):
                    pos[side, i] = pt[i]
                    vel[side, i] = 0.0
                    ang[side, i] = 0.0
                    angd[side, i] = 0.0
                continue
            s = qstart[b]
            joint_matrices_into(kind[b], axis, C[b], q[s:s + 6], J, dJ, d2J, M, dM, d2M, work)
            for i in range(3):
                pos[side, i] = J[i, 0] * pt[0] + J[i, 1] * pt[1] + J[i, 2] * pt[2] + J[i, 3]   # eq. 8.22
                v = 0.0
                for k in range(6):
                    dk = dJ[k, i, 0] * pt[0] + dJ[k, i, 1] * pt[1] + dJ[k, i, 2] * pt[2] + dJ[k, i, 3]
                    dpos[side, k, i] = dk
                    v += dk * qd[s + k]
                vel[side, i] = v
                ang[side, i] = q[s + 3 + i]
                angd[side, i] = qd[s + 3 + i]
        fT = np.empty(3)
        fR = np.empty(3)
        for i in range(3):
            gap = pos[1, i] - pos[0, i]                                      # eq. 8.23
            dgap = vel[1, i] - vel[0, i]
            fT[i] = sde_stiffness[e, i] * gap + sde_damping[e, i] * dgap
            rot = ang[1, i] - ang[0, i]
            drot = angd[1, i] - angd[0, i]
            fR[i] = sde_stiffness[e, 3 + i] * rot + sde_damping[e, 3 + i] * drot
            energy += 0.5 * sde_stiffness[e, i] * gap * gap + 0.5 * sde_stiffness[e, 3 + i] * rot * rot   # eq. 8.21
        for side in range(2):
            root = sde_left_root[e] if side == 0 else sde_right_root[e]
            if root:
                continue
            b = sde_left[e] if side == 0 else sde_right[e]
            sign = -1.0 if side == 0 else 1.0
            s = qstart[b]
            for k in range(6):                                               # eq. 8.29
                S[s + k] += sign * (dpos[side, k, 0] * fT[0] + dpos[side, k, 1] * fT[1] + dpos[side, k, 2] * fT[2])
            for i in range(3):
                S[s + 3 + i] += sign * fR[i]
    return energy


def linear_matrices(link: ClassicalLink):
    """Constant matrices of the linear classical model (eqs. 8.25, 8.26, 8.34, 8.35) for the
    RFE coordinates q~(p,f) = [q~(p,1); ...; q~(p,n)] with RFE 0 clamped in its frame.

    Returns (mass (6n,) — the diagonal of A in the RFE part, eq. 8.34 —, K (6n, 6n) sparse
    block-tridiagonal = K_R + K_T, S_c (6n,)). The elastic force is S = K q + S_c.
    """
    n = link.elements
    mass = np.empty(6 * n)
    for i, b in enumerate(link.bodies()[1:]):
        H = b.inertia
        m = H[3, 3]
        second = H[:3, :3]
        J = np.trace(second) * np.eye(3) - second          # inertia about the origin (= centre)
        mass[6 * i:6 * i + 3] = m
        mass[6 * i + 3:6 * i + 6] = np.diag(J)

    def D(pt):                                             # eq. 8.25: r = r' + D q
        x1, x2, x3 = pt
        return np.array([[1, 0, 0, 0, x3, -x2], [0, 1, 0, -x3, 0, x1], [0, 0, 1, x2, -x1, 0]], float)

    rows, cols, vals = [], [], []
    Sc = np.zeros(6 * n)

    a_idx, c_idx = np.divmod(np.arange(36), 6)

    def add(bi, bj, block):
        rows.append(6 * bi + a_idx)
        cols.append(6 * bj + c_idx)
        vals.append(block.ravel())

    for sde in link.sdes():
        CT = np.diag(sde.stiffness[:3])
        CR = np.diag(sde.stiffness[3:])
        sel = np.zeros((3, 6))
        sel[:, 3:] = np.eye(3)
        Bl = D(sde.point_left)
        Br = D(sde.point_right)
        rl = link.bodies()[sde.left].undeformed[:3, 3] + sde.point_left
        rr = link.bodies()[sde.right].undeformed[:3, 3] + sde.point_right
        dr0 = rr - rl                                      # Delta r'_e (eq. 8.26)
        blocks = {}
        # V = 1/2 (dr0 + Br qr - Bl ql)^T CT (...) + 1/2 (qr - ql)^T CR' (qr - ql)
        blocks[("r", "r")] = Br.T @ CT @ Br + sel.T @ CR @ sel
        blocks[("l", "l")] = Bl.T @ CT @ Bl + sel.T @ CR @ sel
        blocks[("r", "l")] = -Br.T @ CT @ Bl - sel.T @ CR @ sel
        blocks[("l", "r")] = blocks[("r", "l")].T
        idx = {"l": sde.left - 1, "r": sde.right - 1}      # RFE 0 (index -1) is clamped
        for (a, c), block in blocks.items():
            if idx[a] >= 0 and idx[c] >= 0:
                add(idx[a], idx[c], block)
        if idx["r"] >= 0:
            Sc[6 * idx["r"]:6 * idx["r"] + 6] += Br.T @ CT @ dr0
        if idx["l"] >= 0:
            Sc[6 * idx["l"]:6 * idx["l"] + 6] -= Bl.T @ CT @ dr0
    cat = (lambda parts: np.concatenate(parts)) if rows else (lambda parts: np.zeros(0))
    K = sp.coo_matrix((cat(vals), (cat(rows).astype(np.int64), cat(cols).astype(np.int64))),
                      shape=(6 * n, 6 * n)).tocsc()
    K.eliminate_zeros()
    return mass, K, Sc


def linear_modes(link: ClassicalLink, n_modes: int = 6):
    """Natural frequencies (rad/s) and mode shapes of a cantilevered linear classical link
    (RFE 0 clamped, free RFE coordinates only): sparse shift-invert Lanczos on K x = w^2 M x
    with M diagonal and K block-tridiagonal (eqs. 8.34, 8.35); O(n) per iteration."""
    import scipy.sparse.linalg as sla
    mass, K, _ = linear_matrices(link)
    free = np.array([name in link.dofs for _ in range(link.elements) for name in CLASSICAL_DOFS])
    idx = np.flatnonzero(free)
    Kf = K[idx][:, idx]
    Mf = sp.diags(mass[idx])
    from ..solvers.modal import signed_omega
    if n_modes < 1:
        raise ValueError(f"n_modes: must be a positive integer, got {n_modes}")
    k = min(n_modes, len(idx))
    stiff = np.abs(Kf.diagonal()) / np.maximum(mass[idx], 1e-300)
    if k >= len(idx) - 1:             # eigsh needs k < n - 1: all modes by the dense solver
        import scipy.linalg
        w2, vec = scipy.linalg.eigh(Kf.toarray(), np.diag(mass[idx]), subset_by_index=[0, k - 1])
        order = np.arange(k)
    else:
        w2, vec = sla.eigsh(Kf.tocsc(), k=k, M=Mf.tocsc(), sigma=0.0, which="LM")
        order = np.argsort(w2)
    shapes = np.zeros((len(mass), k))
    shapes[idx] = vec[:, order]
    return signed_omega(w2[order], float(stiff.max()) if stiff.size else 0.0), shapes


@njit(cache=True)
def sde_gaps(kind, C, qstart, sde_left, sde_right, sde_left_root, sde_right_root, sde_point_left,
             sde_point_right, q, out):
    """Gap Delta r (eq. 8.23) of every SDE in {p,0} into out (ns, 3)."""
    J, dJ, d2J, M, dM, d2M, work = joint_scratch()
    axis = np.zeros(3)
    for e in range(sde_left.shape[0]):
        for i in range(3):
            out[e, i] = 0.0
        for side in range(2):
            b = sde_left[e] if side == 0 else sde_right[e]
            root = sde_left_root[e] if side == 0 else sde_right_root[e]
            pt = sde_point_left[e] if side == 0 else sde_point_right[e]
            sign = -1.0 if side == 0 else 1.0
            if root:
                for i in range(3):
                    out[e, i] += sign * pt[i]
                continue
            s = qstart[b]
            joint_matrices_into(kind[b], axis, C[b], q[s:s + 6], J, dJ, d2J, M, dM, d2M, work)
            for i in range(3):
                out[e, i] += sign * (J[i, 0] * pt[0] + J[i, 1] * pt[1] + J[i, 2] * pt[2] + J[i, 3])


def rechain(model, q_old, q_new, locked_mask):
    """Newton-update correction for classical links (statics): move the RFE translations so
    that every SDE gap changes by exactly its linearised amount (a rotation update of a
    stiff axial spring otherwise opens a second-order gap l dphi^2/2). Returns a corrected
    copy of q_new. RFE i's translations are in axes parallel to {p,0} (R~(p,i') = I)."""
    ns = len(model.sde_left)
    if ns == 0:
        return q_new
    args = (model.kind, model.placement, model.qstart, model.sde_left, model.sde_right, model.sde_left_root,
            model.sde_right_root, model.sde_point_left, model.sde_point_right)
    g0, gp, gm, g1 = (np.empty((ns, 3)) for _ in range(4))
    dq = q_new - q_old
    eps = 1e-4
    sde_gaps(*args, q_old, g0)
    sde_gaps(*args, q_old + eps * dq, gp)
    sde_gaps(*args, q_old - eps * dq, gm)
    sde_gaps(*args, q_new, g1)
    target = g0 + (gp - gm) / (2 * eps)
    out = q_new.copy()
    shift = {}
    for e in range(ns):
        left, right = model.sde_left[e], model.sde_right[e]
        base = np.zeros(3) if model.sde_left_root[e] else shift.get(left, np.zeros(3))
        delta = base + (target[e] - g1[e])
        s = model.qstart[right]
        delta = np.where(locked_mask[s:s + 3], 0.0, delta)
        shift[right] = delta
        out[s:s + 3] += delta
    return out
