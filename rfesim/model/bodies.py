"""Rigid bodies in the absolute-coordinate model: one free RFE per body.

A body hangs on end B of one line. It becomes one more free RFE with the body's mass and
principal inertia (its frame = the body's principal axes), placed in the global RFE
ordering right after the last RFE of its line, and one more SDE -- the *connection* --
joins the line's end RFE to it at the attachment point (the end's ``position``, body
frame). Every SDE still joins RFEs i and i + 1, so the Jacobian stays block-tridiagonal
and the SDE kernels are unchanged.

Connection stiffness: ``CONNECTION_STIFFNESS_FACTOR`` times the line's own axial SDE
stiffness EA/Delta on all three translations (isotropic, so the joint does not depend on
how the body frame is turned against the line's end frame); rotations free for
``pinned`` (a shackle), the same factor times the line's largest rotational SDE
stiffness for ``clamped`` (the body's x axis must then continue the line's end tangent:
the SDE measures its rotation from equal frames). The connection adds the compliance
Delta / (factor EA) in series with the line's L / EA: 1/(factor n) relative. Its own
high-frequency mode (the line's half end RFE on that spring) is damped critically.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..kinematics import rot_zyx
from ..loads.seabed import seabed_damping

CONNECTION_STIFFNESS_FACTOR = 100.0


@dataclass
class BodyInfo:
    """Where a body sits in the model arrays."""

    name: str
    index: int          # row of the km.body_* arrays
    rfe: int            # the body's RFE
    sde: int            # the connection SDE (line end B -> body)
    line: str           # the line it hangs on
    mass: float         # kg
    volume: float       # m^3


def body_rotation(body) -> np.ndarray:
    """Orientation of the body axes at t = 0 from roll, pitch, yaw (deg, ZYX)."""
    roll, pitch, yaw = (math.radians(a) for a in body.orientation_deg)
    return rot_zyx(yaw, pitch, roll)


def body_pose(body, line, end_a_position: np.ndarray | None, down: np.ndarray):
    """(centre of mass, rotation, end B position) of a body at t = 0. Without a given
    position the line hangs straight down (along ``down``) from end A, the body under it."""
    R = body_rotation(body)
    arm = R @ np.asarray(line.end_b.position, float)
    if body.position is not None:
        centre = np.asarray(body.position, float)
        return centre, R, centre + arm
    if end_a_position is None:
        return None
    B = np.asarray(end_a_position, float) + line.length * down
    return B - arm, R, B


def connection_rows(line_coefficients: np.ndarray, connection: str, end_mass: float, body_mass: float,
                    end_inertia: np.ndarray, body_inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and damping rows (6,) of the connection SDE (see the module text)."""
    k = CONNECTION_STIFFNESS_FACTOR * float(line_coefficients[0])
    stiffness = np.array([k, k, k, 0.0, 0.0, 0.0])
    m_red = end_mass * body_mass / (end_mass + body_mass)
    damping = np.zeros(6)
    damping[:3] = 2.0 * math.sqrt(k * m_red)
    if connection == "clamped":
        kr = CONNECTION_STIFFNESS_FACTOR * float(np.max(line_coefficients[3:]))
        stiffness[3:] = kr
        for j in range(3):
            i_red = end_inertia[j] * body_inertia[j] / (end_inertia[j] + body_inertia[j])
            damping[3 + j] = 2.0 * math.sqrt(kr * i_red)
    return stiffness, damping


def body_rfe_row(body, sc) -> dict:
    """Per-RFE array values of a body's RFE (line hydrodynamics off: rfesim.loads.bodies acts)."""
    height = body.vertical_extent()
    c_len, ct_len = seabed_damping(sc.environment.seabed, body.mass / height)
    return dict(mass=body.mass, inertia=np.asarray(body.principal_inertia(), float), length=height,
                diameter=0.0, disp_area=0.0, cdn=0.0, cdt=0.0, can=0.0, cat=0.0,
                contact_radius=0.5 * height, seabed_c=c_len, seabed_ct=ct_len)


def body_arrays(sc, infos: list[BodyInfo]) -> dict:
    """The km.body_* arrays."""
    water = sc.environment.water
    rho = float(water.density) if water is not None else 0.0
    bodies = [sc.bodies[b.name] for b in infos]
    nb = len(bodies)
    return dict(
        body_rfe=np.asarray([b.rfe for b in infos], np.int64).reshape(nb),
        body_volume=np.asarray([b.volume for b in bodies], float).reshape(nb),
        body_height=np.asarray([b.vertical_extent() for b in bodies], float).reshape(nb),
        body_cob=np.asarray([b.centre_of_buoyancy for b in bodies], float).reshape(nb, 3),
        body_box=np.asarray([b.box_half_sizes() for b in bodies], float).reshape(nb, 3),
        body_drag=np.asarray([b.drag_cd_area() for b in bodies], float).reshape(nb, 3),
        body_added_mass=np.asarray([b.added_mass_per_axis(rho) for b in bodies], float).reshape(nb, 3),
        body_added_inertia=np.asarray([b.added_mass.inertia if b.added_mass is not None else [0.0] * 3
                                       for b in bodies], float).reshape(nb, 3),
        body_slam=np.asarray([b.slam_coefficient * b.slamming_area() for b in bodies], float).reshape(nb),
        has_bodies=nb > 0 and water is not None,
    )


def deck_arrays(sc, infos: list[BodyInfo], attachment_names: list[str]) -> dict:
    """The km.body_deck_* arrays (rfesim.loads.deck): default stiffness the body's weight over
    5 mm, damping the given fraction of critical on the body's mass."""
    g = float(sc.environment.gravity)
    nb = len(infos)
    out = dict(body_deck_att=np.full(nb, -1, np.int64), body_deck_z=np.zeros(nb),
               body_deck_corner=np.zeros((nb, 4, 3)), body_deck_k=np.zeros(nb), body_deck_c=np.zeros(nb),
               body_deck_mu=np.zeros(nb), body_deck_anchor=np.zeros((nb, 4, 3)), has_deck=False)
    for j, info in enumerate(infos):
        body = sc.bodies[info.name]
        deck = getattr(body, "deck", None)
        if deck is None:
            continue
        k = deck.stiffness if deck.stiffness is not None else max(body.mass * g, 1.0) / 0.005
        out["body_deck_att"][j] = attachment_names.index(deck.vessel)
        out["body_deck_z"][j] = deck.height
        a, b = body.deck_footprint()
        out["body_deck_corner"][j] = [[sx * 0.5 * a, sy * 0.5 * b, -0.5 * body.vertical_extent()]
                                      for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
        out["body_deck_k"][j] = k
        out["body_deck_c"][j] = 2.0 * deck.damping_ratio * math.sqrt(k * body.mass)
        out["body_deck_mu"][j] = deck.friction
        out["has_deck"] = True
    return out


DECK_SEAT = 0.01        # m: a body whose underside starts within this of its deck is seated on it
DECK_DEEP = 0.1         # m: a body whose underside starts deeper than this in its deck is refused


def deck_anchors(model, gravity: float, sc=None) -> np.ndarray:
    """(nb, 4, 3) m: the corners of each decked body's footprint at the model's initial state,
    in its deck vessel's frame at t = 0 (the statics stick anchors, rfesim.loads.deck).

    A body put on its deck (its lowest corner within DECK_SEAT of the deck plane, the
    natural input) is first seated: moved along the deck normal to the penetration its own
    weight gives, W / k + delta_0 / 2 (model.initial is changed in place). Statics then
    starts where the contact has its full stiffness; at zero penetration the smooth onset
    has none, and Newton's first step would be wild.

    A body whose underside starts more than DECK_DEEP inside its deck is refused
    (ScenarioError on its position, named as the user wrote it with ``sc``): the contact would
    throw it out with its stiffness times that depth, hundreds of times its weight at the
    default stiffness (the weight over 5 mm), and statics could not settle it."""
    from ..kinematics import rot_zyx
    from ..loads.deck import DECK_ONSET
    from ..vessel_kernel import attachment_kinematics, vessel_spec
    from .arrays import new_attachment_state
    km = model.km
    out = np.zeros((km.body_rfe.shape[0], 4, 3))
    att = new_attachment_state(len(model.attachment_names))
    attachment_kinematics(vessel_spec(model.motions), 0.0, att)
    X, q = model.initial.ref.X, model.initial.q
    for j in range(km.body_rfe.shape[0]):
        a = km.body_deck_att[j]
        if a < 0:
            continue
        i = km.body_rfe[j]
        n = att.R[a][:, 2]
        Rb = model.initial.ref.R[i] @ rot_zyx(q[i, 3], q[i, 4], q[i, 5])
        corners = X[i] + q[i, :3] + km.body_deck_corner[j] @ Rb.T
        delta = -((corners - (att.p[a] + km.body_deck_z[j] * n)) @ n)
        low = float(delta.max())
        if low > DECK_DEEP:
            _deck_too_deep(model, sc, j, low, float(km.body_deck_z[j]), float(km.rfe_mass[i]) * gravity,
                           float(km.body_deck_k[j]))
        if abs(low) < DECK_SEAT and km.body_deck_k[j] > 0.0:
            seat = km.rfe_mass[i] * gravity / km.body_deck_k[j] + 0.5 * DECK_ONSET
            X[i] -= (seat - low) * n
            corners = corners - (seat - low) * n
        out[j] = (corners - att.p[a]) @ att.R[a]
    return out


def _deck_too_deep(model, sc, j: int, depth: float, deck_z: float, weight: float, k: float) -> None:
    """Raise the ScenarioError of a body that starts ``depth`` m inside its deck."""
    from ..errors import ScenarioError
    info = next((b for b in (getattr(model, "bodies", None) or []) if b.index == j), None)
    name = info.name if info is not None else str(j)
    from ..scenario.pipelay import user_field
    field, deck_field = user_field(sc, f"bodies.{name}.position"), user_field(sc, f"bodies.{name}.deck.height")
    vessel = model.attachment_names[int(model.km.body_deck_att[j])]
    times = f" ({k * depth / weight:.3g} times its weight)" if weight > 0.0 else ""
    raise ScenarioError([(field, f"the body's underside starts {depth:.4g} m inside the deck of vessel '{vessel}' "
                                 f"({deck_field} = {deck_z:.6g} m in its frame): the deck would push it out with "
                                 f"{k * depth / 1e3:.4g} kN{times}; raise the body by {depth:.4g} m to stand on "
                                 f"the deck, or lower {deck_field}")])


def append_body(sc, name: str, index: int, line, pose, line_coefficients: np.ndarray, end_length: float,
                end_mass: float, end_inertia: np.ndarray, n_total: int, nsde_total: int, rfe: dict, sde: dict,
                plastic_rows: list, plastic_flags: list, tension_flags: list, q0_blocks: list, X0_blocks: list,
                R0_blocks: list, kinds: tuple) -> BodyInfo:
    """Append a body's RFE (index ``n_total``, right after its line's end RFE) and its
    connection SDE (index ``nsde_total``) to compile_scenario's lists."""
    body = sc.bodies[name]
    centre, R, _ = pose
    row = body_rfe_row(body, sc)
    for key in ("mass", "inertia", "length", "diameter", "disp_area", "cdn", "cdt", "can", "cat", "contact_radius",
                "seabed_c", "seabed_ct"):
        rfe[key].append(row[key])
    rfe["kind"].append(kinds[0])
    rfe["attach"].append(-1)
    rfe["attach_offset"].append(np.zeros(3))
    rfe["pin_arm"].append(np.zeros(3))
    rfe["clamp_R"].append(np.eye(3))
    stiffness, damping = connection_rows(line_coefficients, line.end_b.connection, end_mass, body.mass,
                                         end_inertia, row["inertia"])
    from .arrays import append_sde
    append_sde(sde, plastic_rows, plastic_flags, tension_flags, n_total - 1, n_total, [0.5 * end_length, 0.0, 0.0],
               np.asarray(line.end_b.position, float).tolist(), stiffness, damping, end_length)
    q0_blocks.append(np.zeros((1, 6)))
    X0_blocks.append(np.asarray(centre, float)[None, :])
    R0_blocks.append(np.asarray(R, float)[None, :, :])
    return BodyInfo(name=name, index=index, rfe=n_total, sde=nsde_total, line=line_name(sc, line), mass=body.mass,
                    volume=body.volume)


def line_name(sc, line) -> str:
    for name, ln in sc.lines.items():
        if ln is line:
            return name
    raise KeyError("line not in the scenario")


def connection_force(km, ws, info: BodyInfo, end: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Force (global) of the line on the body and its moment about the attachment point,
    from the connection SDE of an evaluated workspace (``end``: its sde_end_loads if
    already computed)."""
    out = end
    if out is None:
        from .outputs import sde_end_loads
        out = np.empty((4, 3))
        n = ws.R.shape[0]
        sde_end_loads(km, ws, info.sde, np.zeros((n, 3)), np.zeros((n, 3)), out)
    return out[2].copy(), out[3].copy()
