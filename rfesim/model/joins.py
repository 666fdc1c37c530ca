"""Line-to-line joins in the absolute-coordinate model (rfesim.scenario.joins).

A string of joined lines (pedestal -> boom -> rope -> body) gets consecutive RFE numbers,
parent then child, and ONE more SDE -- the *joint* -- between the parent's last RFE
(end B, half length) and the child's first RFE (end A, half length). Every SDE still
joins RFEs i and i + 1, so the Jacobian stays block-tridiagonal and the SDE kernels see an
ordinary SDE with a rest rotation:

* stress-free state = the initial geometry: ``sde_rest[s] = R_parent_end(0)^T R_child_start(0)``
  (the kernel measures the joint rotation from R_a sde_rest_eff, crane spec section 2);
* clamped: all six stiffnesses are JOINT_STIFFNESS times the smaller of the two lines' SDE
  values for an element of length (dx_parent + dx_child) / 2 (eqs. 8.88/8.89, the lines'
  own shear models), the dampings sqrt(JOINT_STIFFNESS) times theirs (the same damping
  ratio): the lines' own SDEs already carry the whole flexibility of the two members (each
  SDE stands for its segment, Fig. 8.2), so the joint is nearly rigid -- with the plain
  element values it added one element of compliance, a first-order error (3 % in the
  L-frame tip deflection at 20 elements; tests/validation/test_line_joins_closed_forms.py).
  The softer line sets it: 100 times one of its elements is rigid enough for both, and a
  joint scaled on the stiffer one (a boom on a light rope) made the Newton matrix so
  ill-conditioned that the A-frame's first step failed;
  pinned (a sheave): JOINT_STIFFNESS times the softer line's largest translational value on
  all three translations (isotropic: the joint's mean frame turns freely with the
  rotation), bending and torsion 0
  (the rotation of each end RFE is held by its own line's next SDE, so the Jacobian stays
  regular without a rotational spring);
* hinged (a clamped join with ``hinge_axis``, a luffing pin): the clamped rows with the
  stiffness and damping about the hinge axis set to 0. The child's first frame is chosen
  so that the axis is one of its own axes -- y for an axis normal to end A's direction
  (component 4 of the SDE's eps = [R'^T g, theta], eq. 8.85), x for one along it
  (component 3) -- so theta's component about the axis is the hinge angle, which the joint
  neither resists nor damps; the other five components stay nearly rigid. In a pure turn
  about the hinge, R_b = R_a* Rot(y, phi) and theta = (0, phi, 0) exactly, and the mean
  frame {i'} keeps the axis: the joint's moment has no part about the axis for any angle
  below pi (docs/theory.md, "Hinged joins and force-driven cylinders");
* drives (clamped joins only): sde_rest_eff(t) = Rot(a_1, dphi_1(t)) ... Rot(a_m, dphi_m(t))
  sde_rest with a_k the drive axis in the parent end RFE's body frame at t = 0 and
  dphi_k(t) = phi_k(t) - phi_k(0), phi_k a monotone cubic (PCHIP) through the angle table.

Outputs: the joint's force and moment on the child are the child's ``end_a_force`` /
``end_a_moment`` with the sign of an attached end (force of the line on what holds it:
here the parent), and the parent's ``end_b_force`` / ``end_b_moment`` (force of the parent
on the child); ``drive_angle`` (deg) and ``drive_torque`` (N*m, the joint moment on the
child about the drive's current axis) for a child with drives.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


JOINT_STIFFNESS = 100.0     # joint SDE / the stiffer line's SDE: nearly rigid (module text)


@dataclass
class JoinInfo:
    """Where a join sits in the model arrays."""

    parent: str             # line whose end B carries the join
    child: str              # line whose end A is joined
    connection: str         # "clamped" | "pinned"
    sde: int                # the joint SDE
    parent_rfe: int         # the parent's last RFE (SDE left)
    child_rfe: int          # the child's first RFE (SDE right)
    rest: np.ndarray        # (3, 3) R_parent_end(0)^T R_child_start(0)
    drive_start: int = 0    # rows of the km.drive_* arrays
    drive_stop: int = 0
    drive_names: list[str] = field(default_factory=list)   # the drive rows', then the motor's
    motor: int = -1         # row of the km.motor_* arrays (a servo motor about the joint axis), -1: none
    hinge: int = -1         # the eps component free about the hinge axis (3 torsion, 4 bending y), -1: none


def joint_rows(connection: str, coefficients: list[np.ndarray], dampings: list[np.ndarray]) -> tuple[np.ndarray,
                                                                                                     np.ndarray]:
    """Stiffness and damping rows (6,) of a joint SDE from the two lines' SDE rows for the
    joint's element length (see the module text)."""
    coef = np.asarray(coefficients, float)              # (2, 6)
    damp = np.asarray(dampings, float)
    if connection == "pinned":
        line = int(np.argmin(coef[:, :3].max(axis=1)))  # the softer line's largest translational value
        k = JOINT_STIFFNESS * coef[line, :3].max()
        c = math.sqrt(JOINT_STIFFNESS) * damp[line, :3].max()
        return np.array([k] * 3 + [0.0] * 3), np.array([c] * 3 + [0.0] * 3)
    pick = np.argmin(coef, axis=0)                      # the softer line, per component
    stiffness = JOINT_STIFFNESS * coef[pick, np.arange(6)]
    damping = math.sqrt(JOINT_STIFFNESS) * damp[pick, np.arange(6)]
    return stiffness, damping


HINGE_TOLERANCE = 1e-6      # |cos| of the hinge axis against end A's direction: along it / normal to it


def hinge_frame(tangent: np.ndarray, axis: np.ndarray) -> tuple[int, np.ndarray | str]:
    """(eps component, frame (3, 3) with x = tangent) of a hinged join's child end A: the
    frame's y axis is the hinge axis when that is normal to the tangent (component 4), its x
    axis when along it (component 3, the frame from rfesim.kinematics.frame_from_tangent);
    (-1, reason) for an axis at another angle."""
    from ..kinematics import frame_from_tangent
    t = tangent / np.linalg.norm(tangent)
    a = axis / np.linalg.norm(axis)
    c = float(t @ a)
    if abs(c) >= 1.0 - HINGE_TOLERANCE:
        return 3, frame_from_tangent(t)
    if abs(c) <= HINGE_TOLERANCE:
        z = np.cross(t, a)
        return 4, np.column_stack([t, a, z / np.linalg.norm(z)])
    ang = math.degrees(math.acos(max(-1.0, min(1.0, c))))
    return -1, (f"the hinge axis must be normal to end A's direction (a pin) or along it (a bearing); it is "
                f"{ang:.4g} deg from {np.round(t, 6).tolist()}")


def hinge_angle(ws, info: JoinInfo) -> float:
    """Turn (rad) of a hinged join about its axis from the start: the component of the
    joint SDE's rotation vector theta about the axis (the eps of the last evaluation)."""
    return float(ws.eps[info.sde, info.hinge])


def drive_rows(joins_drives: list[tuple[int, np.ndarray, list]]) -> list[dict]:
    """Drive rows for rfesim.model.arrays.joint_arrays from (joint SDE, parent end rotation
    R_p(0), schema drives) per join: axis in the parent end RFE's body frame at t = 0, angle
    table in rad, in the listed order."""
    rows = []
    for s, Rp, drives in joins_drives:
        for d in drives:
            axis = np.asarray(d.axis, float)
            table = np.asarray(d.angle, float)
            rows.append(dict(sde=s, axis=Rp.T @ (axis / np.linalg.norm(axis)),
                             table=np.column_stack([table[:, 0], np.radians(table[:, 1])])))
    return rows


_DRIVE_TABLE = []
_DRIVE_ROWS: dict = {}      # drive row -> (drive_t, drive_angle, drive_slope, their row slices)


def drive_angle(km, j: int, t: float) -> float:
    """Prescribed angle (rad) of drive row j at time t (the kernel's monotone cubic)."""
    if not _DRIVE_TABLE:
        from ..loads.drives import drive_table
        from ..solvers.fastcall import FastCall
        _DRIVE_TABLE.append(FastCall(drive_table))      # called at every recorded time
    # the row's table slices, kept while the model's arrays are the same objects: the compiled
    # call then sees the same arguments as last time and skips their checks
    held = _DRIVE_ROWS.get(j)
    if held is None or held[0] is not km.drive_t or held[1] is not km.drive_angle or held[2] is not km.drive_slope:
        c = int(km.drive_count[j])
        held = (km.drive_t, km.drive_angle, km.drive_slope,
                (km.drive_t[j, :c], km.drive_angle[j, :c], km.drive_slope[j, :c]))
        _DRIVE_ROWS[j] = held
    tab = held[3]
    return float(_DRIVE_TABLE[0](tab[0], tab[1], tab[2], float(t))[0])


def drive_angles(km, info: JoinInfo, t: float) -> list[float]:
    """drive_angle of every drive of a join at time t."""
    return [drive_angle(km, j, t) for j in range(info.drive_start, info.drive_stop)]


def axis_rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rot(axis, angle) (Rodrigues; axis a unit vector)."""
    x, y, z = float(axis[0]), float(axis[1]), float(axis[2])
    s, c1 = math.sin(angle), 1.0 - math.cos(angle)
    # I + s K + (1 - cos) K^2, K = [axis]x and K^2 = a a^T - I (unit axis), written out
    return np.array([[1.0 - c1 * (y * y + z * z), c1 * x * y - s * z, c1 * x * z + s * y],
                     [c1 * x * y + s * z, 1.0 - c1 * (x * x + z * z), c1 * y * z - s * x],
                     [c1 * x * z - s * y, c1 * y * z + s * x, 1.0 - c1 * (x * x + y * y)]])


def rest_rotation(km, info: JoinInfo, t: float, angles: list[float] | None = None
                  ) -> tuple[np.ndarray, list[np.ndarray]]:
    """sde_rest_eff(t) of a joint and, per drive, its axis in the parent end RFE's frame at
    time t (turned by the drives before it): crane spec section 3. ``angles``: the drives'
    angles at t (drive_angles) if already known."""
    rest = np.asarray(info.rest, float)
    D = np.eye(3)
    axes = []
    for m, j in enumerate(range(info.drive_start, info.drive_stop)):
        a = km.drive_axis[j]
        axes.append(D @ a)
        phi = angles[m] if angles is not None else drive_angle(km, j, t)
        D = D @ axis_rotation(a, phi - float(km.drive_phi0[j]))
    return D @ rest, axes


def drive_axes(km, info: JoinInfo, t: float, angles: list[float] | None = None) -> list[np.ndarray]:
    """The axes of rest_rotation(km, info, t, angles)[1] without the rotations that do not
    turn any axis (the last drive's, and the static rest rotation)."""
    D = None
    axes = []
    last = info.drive_stop - 1
    for m, j in enumerate(range(info.drive_start, info.drive_stop)):
        a = km.drive_axis[j]
        axes.append(a.copy() if D is None else D @ a)
        if j < last:
            phi = angles[m] if angles is not None else drive_angle(km, j, t)
            Rj = axis_rotation(a, phi - float(km.drive_phi0[j]))
            D = Rj if D is None else D @ Rj
    return axes


def joint_loads(km, ws, info: JoinInfo, t: float, end: np.ndarray | None = None,
                angles: list[float] | None = None) -> dict:
    """Force and moment of the joint SDE of an evaluated workspace, as the SDE kernel
    applies them (eq. 8.90, rfesim.model.outputs.sde_end_loads):

    child_force/child_moment: force of the child on the parent and its moment about the
    child's end-A point (the sign of an attached end); parent_force/parent_moment: force of
    the parent on the child, moment about the parent's end-B point; drive_axes: the global
    axis of each drive now. ``end``: the SDE's sde_end_loads if already computed; ``angles``:
    the drives' angles at t (drive_angles) if already known."""
    out = end
    if out is None:
        from .outputs import sde_end_loads
        out = np.empty((4, 3))
        n = ws.R.shape[0]
        sde_end_loads(km, ws, info.sde, np.zeros((n, 3)), np.zeros((n, 3)), out)
    loads = dict(child_force=-out[2], child_moment=-out[3], parent_force=-out[0], parent_moment=-out[1])
    if info.drive_stop > info.drive_start:
        axes = drive_axes(km, info, t, angles)
        loads["drive_axes"] = [ws.R[info.parent_rfe] @ ax for ax in axes]
    else:
        loads["drive_axes"] = []
    if info.motor >= 0:
        # the motor turns the join about the parent end's axis; its angle is the joint twist
        loads["drive_axes"].append(ws.R[info.parent_rfe][:, 0].copy())
        loads["motor_twist"] = float(ws.eps[info.sde, 3])
    return loads


def drive_outputs(km, info: JoinInfo, loads: dict, t: float, angles: list[float] | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """(drive_angle deg, drive_torque N*m) of the drives of one join: the prescribed angle
    and the joint moment on the child about each drive's current axis (``angles``: the
    drives' angles at t in rad, if already known)."""
    on_child = -loads["child_moment"]
    if angles is None:
        angles = drive_angles(km, info, t)
    angles = [math.degrees(a) for a in angles]
    if info.motor >= 0:
        from ..loads.drives import drive_table
        m, c = info.motor, int(km.motor_count[info.motor])
        phi0 = float(drive_table(km.motor_t[m, :c], km.motor_angle[m, :c], km.motor_slope[m, :c], 0.0)[0])
        angles.append(math.degrees(phi0 + float(km.motor_shift[m]) + loads["motor_twist"]))
    angles = np.array(angles)
    torques = np.array([float(on_child @ ax) for ax in loads["drive_axes"]])
    return angles, torques


REBASE_TWIST = math.pi / 3.0    # rad: a motor joint's twist beyond this is moved into its rest rotation


def rebase_motors(km, ws) -> bool:
    """Move the twist of every servo motor joint beyond REBASE_TWIST into the joint's rest
    rotation (between steps, ws holding the evaluation of the state reached): R0 <- R0 Rx(tw)
    and motor_shift += tw, so the joint's rotation vector theta = log(R0^T R_a^T R_b), unique
    within +-pi, stays small however far the motor slews (docs/theory.md, 'Slewing motor with
    a torque limit'). The elastic law is unchanged to first order in the joint's (tiny)
    bending; the servo's set angle is shifted by the same tw (rfesim.loads.drives). Returns
    True when a joint was rebased (the factorised Jacobian then belongs to the old rest)."""
    moved = False
    for j in range(km.motor_sde.shape[0]):
        s = int(km.motor_sde[j])
        tw = float(ws.eps[s, 3])
        if abs(tw) <= REBASE_TWIST:
            continue
        km.sde_rest[s] = km.sde_rest[s] @ axis_rotation(np.array([1.0, 0.0, 0.0]), tw)
        if km.sde_has_rest[s] == 0:
            km.sde_has_rest[s] = 1
        km.motor_shift[j] += tw
        moved = True
    return moved
