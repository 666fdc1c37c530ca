"""Scenario schema of kinematic chains (top-level ``chains``) and the checks of lines in the
non-absolute formulations (``formulation``: classical, classical-linear, modified, planar).

A chain is a tree of links on a base (``"fixed"`` or a vessel) joined by joints::

    "chains": {"crane": {
        "base": "fixed", "position": [0, 0, 0],
        "links": {"pedestal": {"rigid": true, "length": 5.0, "mass": 2.0e4},
                  "boom": {"type": "boom_section", "length": 30.0, "elements": 10,
                           "formulation": "modified"}},
        "joints": {"slew": {"kind": "revolute", "parent": "base", "child": "pedestal",
                            "direction": [0, 0, 1], "axis": [0, 0, 1],
                            "drive": {"kind": "prescribed", "motion": {"kind": "harmonic",
                                      "amplitude": 0.3, "period": 20.0}}},
                   "luff": {"kind": "revolute", "parent": "pedestal", "child": "boom",
                            "axis": [0, 1, 0], "direction": [1, 0, 0]}}}}

Frames: a link's axis is its local x from the joint (s = 0) to the tip (s = length). A
joint sits at arc length ``at`` of its parent link (default: the tip) plus ``position``
(parent link axes; for ``parent: "base"``, the base frame: global, or the vessel frame);
``direction`` is the child's axis in the parent's axes at zero joint coordinate, and its
local y axis is horizontal (perpendicular to ``direction`` and the parent's z), z = x * y.
``axis`` (revolute, prismatic) is given in the parent's axes too. Joint coordinates: rad
or m; a spherical joint has the ZYX angles (phi_x, phi_y, phi_z).

Units are SI; angles of joint coordinates in rad (they are generalised coordinates).
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field, model_validator

from .schema import (DAMPING_LIMIT, INERTIA_LIMIT, MASS_FLOOR, MASS_LIMIT, MAX_DAMPING, MAX_INERTIA, MAX_MASS,
                     MAX_STIFFNESS, MIN_MASS, STIFFNESS_LIMIT, FieldError, PointLoad, Vector3, _nonzero, _Strict,
                     _units, upper_bound)

# --------------------------------------------------------------------------- drive motions


class HarmonicProfile(_Strict):
    """q(t) = mean + amplitude sin(2 pi t / period + phase)."""
    kind: Literal["harmonic"]
    amplitude: float = _units("rad or m", "Amplitude of the joint coordinate")
    period: float = _units("s", "Period", gt=0.0)
    phase_deg: float = _units("deg", "Phase", default=0.0)
    mean: float = _units("rad or m", "Mean value", default=0.0)


class SpinUpProfile(_Strict):
    """Rate rising smoothly from 0 to ``rate`` over ``ramp_time`` (Kane, Ryan & Banerjee 1987),
    then constant: q = start + ...; continuous acceleration."""
    kind: Literal["spin-up"]
    rate: float = _units("rad/s or m/s", "Final rate")
    ramp_time: float = _units("s", "Duration of the smooth ramp", gt=0.0)
    start: float = _units("rad or m", "Value at t = 0", default=0.0)


TableRow2 = Annotated[list[float], Field(min_length=2, max_length=2)]


class TableProfile(_Strict):
    """Rows [t, q], cubic spline (natural): continuous rate and acceleration. Held outside."""
    kind: Literal["table"]
    rows: list[TableRow2] = _units("s, rad or m", "Rows [time, value], times strictly increasing", min_length=4)

    @model_validator(mode="after")
    def _increasing(self):
        for i in range(1, len(self.rows)):
            if not self.rows[i][0] > self.rows[i - 1][0]:
                raise FieldError(f"rows.{i}", f"time {self.rows[i][0]} s does not increase "
                                              f"(previous {self.rows[i - 1][0]} s)")
        return self


Profile = Annotated[Union[HarmonicProfile, SpinUpProfile, TableProfile], Field(discriminator="kind")]


class FreeDrive(_Strict):
    """No drive: the joint coordinate moves freely under the loads, its spring and damper."""
    kind: Literal["free"]


class PrescribedDrive(_Strict):
    """The joint coordinate follows a time function (rate and acceleration included)."""
    kind: Literal["prescribed"]
    motion: Profile


class ForceDrive(_Strict):
    """A free joint coordinate loaded by a generalised force or torque, ramped in with a
    half cosine over ``ramp_time``."""
    kind: Literal["force"]
    value: float = _units("N or N*m", "Force (prismatic) or torque (revolute) on the joint coordinate")
    ramp_time: float = _units("s", "Ramp-in duration (0: applied at once)", default=0.0, ge=0.0)


Drive = Annotated[Union[FreeDrive, PrescribedDrive, ForceDrive], Field(discriminator="kind")]


# --------------------------------------------------------------------------- links and joints

CHAIN_FORMULATIONS = ("classical", "classical-linear", "modified")
CLASSICAL_DOFS = ("x", "y", "z", "rx", "ry", "rz")
MODIFIED_DOFS = ("rx", "ry", "rz")


class ChainLink(_Strict):
    """A rigid link (``rigid: true``: one body, ``mass``, ``centre``, ``inertia``) or a
    flexible beam of a line type in the classical or modified RFE formulation."""
    length: float = _units("m", "Length of the link axis (joint to tip)", gt=0.0, le=1.0e5)
    rigid: bool = Field(False, description="A rigid link (m_p = 0, section 8.1.4)")
    type: str | None = Field(None, description="Line type of a flexible link (or of a rigid one, for its mass)")
    elements: int | None = _units("1", "Number of SDEs of a flexible link", default=None, ge=1, le=10000)
    formulation: Literal["classical", "classical-linear", "modified"] = Field(
        "modified", description="RFE formulation of a flexible link (sections 8.1, 8.2)")
    dofs: list[str] | None = Field(None, description="Free RFE coordinates of a flexible link (classical: x, y, "
                                                     "z, rx, ry, rz; modified: rx, ry, rz); default all")
    mass: float | None = _units("kg", "Mass of a rigid link (default: mass_per_length of its type times length)",
                                default=None, ge=MIN_MASS, le=MAX_MASS, limit=MASS_LIMIT, floor=MASS_FLOOR)
    centre: Vector3 | None = _units("m", "Centre of mass of a rigid link in its axes (default: mid-length)",
                                    default=None)
    inertia: Vector3 | None = _units("kg*m^2", "Principal moments of inertia of a rigid link about its centre "
                                     "along its axes (default: a slender rod), not negative", default=None,
                                     limit=INERTIA_LIMIT)
    loads: list[PointLoad] = Field(default_factory=list, description="Dead point loads (global frame); "
                                   "'at': arc length, 'end_a' (joint) or 'end_b' (tip)")

    @model_validator(mode="after")
    def _kind(self):
        if self.rigid:
            for name in ("elements", "dofs"):
                if getattr(self, name) is not None:
                    raise FieldError(name, "a rigid link has no elements (remove it or set rigid: false)")
            if self.mass is None and self.type is None:
                raise FieldError("mass", "a rigid link needs its mass (or a line type for mass_per_length)")
            if self.inertia is not None and any(v < 0.0 for v in self.inertia):
                raise FieldError("inertia", "principal moments of inertia must be >= 0")
            for k, v in enumerate(self.inertia or []):
                why = upper_bound(v, MAX_INERTIA, "kg*m^2", INERTIA_LIMIT)
                if why:
                    raise FieldError(f"inertia.{k}", why)
        else:
            if self.type is None:
                raise FieldError("type", "a flexible link needs a line type (or set rigid: true)")
            if self.elements is None:
                raise FieldError("elements", "a flexible link needs its number of elements (SDEs)")
            for name in ("mass", "centre", "inertia"):
                if getattr(self, name) is not None:
                    raise FieldError(name, "only for rigid links (a flexible link's mass comes from its type)")
            if self.dofs is not None:
                allowed = MODIFIED_DOFS if self.formulation == "modified" else CLASSICAL_DOFS
                bad = [d for d in self.dofs if d not in allowed]
                if bad or not self.dofs:
                    raise FieldError("dofs", f"must be a non-empty subset of {list(allowed)} for the "
                                             f"{self.formulation} formulation, got {self.dofs}")
        for i, load in enumerate(self.loads):
            if load.frame != "global":
                raise FieldError(f"loads.{i}.frame", "only global (dead) loads on chain links")
            if not isinstance(load.at, str) and not 0.0 <= load.at <= self.length:
                raise FieldError(f"loads.{i}.at", f"arc length {load.at} m is outside the link [0, {self.length}] m")
        return self


class ChainJoint(_Strict):
    """A joint between a parent (the base or a link) and a child link."""
    kind: Literal["revolute", "prismatic", "spherical", "fixed"]
    parent: str = Field("base", description='"base" or the name of a link')
    child: str = Field(..., description="Name of the link this joint carries")
    at: float | None = _units("m", "Arc length on the parent link, at most its length (default: its tip); not "
                                   "for the base", default=None, ge=0.0)
    position: Vector3 = _units("m", "Offset of the joint in the parent's axes (base: global or vessel frame)",
                               default=[0.0, 0.0, 0.0])
    direction: Vector3 = _units("1", "Child link axis at zero joint coordinate, in the parent's axes (any length, "
                                     "not zero)", default=[1.0, 0.0, 0.0])
    axis: Vector3 | None = _units("1", "Joint axis of a revolute or prismatic joint (required there, not for the "
                                       "others), parent's axes (any length, not zero)", default=None)
    drive: Drive = Field(default_factory=lambda: FreeDrive(kind="free"))
    stiffness: float = _units("N/m or N*m/rad", "Spring on the joint coordinates", default=0.0, ge=0.0,
                              le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    damping: float = _units("N*s/m or N*m*s/rad", "Damper on the joint coordinates", default=0.0, ge=0.0,
                            le=MAX_DAMPING, limit=DAMPING_LIMIT)
    rest: float = _units("m or rad", "Unloaded value of the joint spring", default=0.0)
    initial: float | list[float] = _units("m or rad", "Initial joint coordinate(s): one per coordinate of the "
                                                      "joint (spherical: a list of 3 ZYX angles)", default=0.0)
    initial_rate: float | list[float] = _units("m/s or rad/s", "Initial rate(s), one per coordinate of the joint",
                                               default=0.0)

    @model_validator(mode="after")
    def _joint(self):
        _nonzero(self.direction, "direction")
        if self.kind in ("revolute", "prismatic"):
            if self.axis is None:
                raise FieldError("axis", f"a {self.kind} joint needs its axis")
            _nonzero(self.axis, "axis")
        elif self.axis is not None:
            raise FieldError("axis", f"a {self.kind} joint has no axis")
        if self.kind == "fixed" and self.drive.kind != "free":
            raise FieldError("drive", "a fixed joint cannot be driven")
        if self.kind == "spherical" and self.drive.kind != "free":
            raise FieldError("drive", "drives on spherical joints are not supported yet (use three revolute joints)")
        n = {"revolute": 1, "prismatic": 1, "spherical": 3, "fixed": 0}[self.kind]
        for name in ("initial", "initial_rate"):
            v = getattr(self, name)
            if isinstance(v, list) and len(v) != n:
                raise FieldError(name, f"a {self.kind} joint has {n} coordinate(s), got {len(v)} values")
            if n != 1 and not isinstance(v, list) and v != 0.0:
                raise FieldError(name, f"a {self.kind} joint has {n} coordinates: give a list of {n}")
        if self.parent == "base" and self.at is not None:
            raise FieldError("at", "only for a joint on a parent link (use position for the base)")
        return self


class ChainSpec(_Strict):
    """A kinematic chain (or tree) of links on a base (sections 8.1.4, 8.2, 5.4)."""
    base: str = Field("fixed", description='"fixed" (global frame) or a vessel name')
    position: Vector3 = _units("m", "Origin of the base frame: global, or in the vessel frame",
                               default=[0.0, 0.0, 0.0])
    links: dict[str, ChainLink] = Field(..., min_length=1)
    joints: dict[str, ChainJoint] = Field(..., min_length=1)

    @model_validator(mode="after")
    def _tree(self):
        carried = {}
        for jname, j in self.joints.items():
            if j.child not in self.links:
                raise FieldError(f"joints.{jname}.child", f"unknown link '{j.child}' (links: "
                                                          f"{', '.join(self.links)})")
            if j.parent != "base" and j.parent not in self.links:
                raise FieldError(f"joints.{jname}.parent", f"unknown link '{j.parent}' (use 'base' or one of: "
                                                           f"{', '.join(self.links)})")
            if j.child == j.parent:
                raise FieldError(f"joints.{jname}.parent", "a link cannot be its own parent")
            if j.child in carried:
                raise FieldError(f"joints.{jname}.child", f"link '{j.child}' is already carried by joint "
                                                          f"'{carried[j.child]}' (closed loops are not supported)")
            carried[j.child] = jname
            if j.at is not None and j.at > self.links[j.parent].length:
                raise FieldError(f"joints.{jname}.at", f"{j.at} m is beyond the tip of link '{j.parent}' "
                                                       f"({self.links[j.parent].length} m)")
        for lname in self.links:
            if lname not in carried:
                raise FieldError(f"links.{lname}", "no joint carries this link (give a joint with child "
                                                   f"'{lname}')")
        for lname in self.links:            # every link must reach the base: no cycles
            seen = [lname]
            cur = lname
            while True:
                parent = self.joints[carried[cur]].parent
                if parent == "base":
                    break
                if parent in seen:
                    raise FieldError(f"joints.{carried[cur]}.parent", "the joints form a cycle: "
                                                                      + " -> ".join(seen + [parent]))
                seen.append(parent)
                cur = parent
        return self

    def order(self) -> list[str]:
        """Joint names, parents before children."""
        out, placed = [], {"base"}
        pending = dict(self.joints)
        while pending:
            for name, j in list(pending.items()):
                if j.parent in placed:
                    out.append(name)
                    placed.add(j.child)
                    del pending[name]
        return out


# --------------------------------------------------------------------------- scenario checks

NON_ABSOLUTE = ("classical", "classical-linear", "modified", "planar")


def line_frame(direction):
    """(3, 3) rotation whose columns are the link axes: x along ``direction``, y horizontal
    (perpendicular to x and the global z), z = x * y."""
    import numpy as np
    x = np.asarray(direction, float)
    x = x / np.linalg.norm(x)
    y = np.cross([0.0, 0.0, 1.0], x)
    if np.linalg.norm(y) < 1e-9:
        y = np.array([0.0, 1.0, 0.0])
    y /= np.linalg.norm(y)
    return np.column_stack([x, y, np.cross(x, y)])


def planar_axes(direction):
    """(e1, normal): the horizontal in-plane unit vector and the plane normal of a planar line
    starting along ``direction`` (vertical start: the global x-z plane). Planar x = e1,
    planar y = global z."""
    import numpy as np
    d = np.asarray(direction, float)
    h = np.array([d[0], d[1], 0.0])
    e1 = h / np.linalg.norm(h) if np.linalg.norm(h) > 1e-9 * np.linalg.norm(d) else np.array([1.0, 0.0, 0.0])
    return e1, np.cross(e1, [0.0, 0.0, 1.0])


def chain_point(sc, attach):
    """(chain name, link name) of a line attachment "<chain>.<link>" (a point of a chain
    link, rfesim.formulations.mixed), or None."""
    if not isinstance(attach, str) or "." not in attach or attach in getattr(sc, "vessels", {}):
        return None
    chains = getattr(sc, "chains", None) or {}
    for i, c in enumerate(attach):
        if c == "." and attach[:i] in chains and attach[i + 1:] in chains[attach[:i]].links:
            return attach[:i], attach[i + 1:]
    return None


def _check_chain_ends(sc) -> None:
    """Line ends on chain links: "attach": "<chain>.<link>", ``at`` on the link."""
    special = set(getattr(sc, "vessels", {})) | set(getattr(sc, "bodies", {})) | {"fixed", "free"}
    chains = getattr(sc, "chains", None) or {}
    for name, ln in sc.lines.items():
        for end_name in ("end_a", "end_b"):
            end = getattr(ln, end_name)
            base = f"lines.{name}.{end_name}"
            if ":" in end.attach:           # a line-to-line join, checked by rfesim.scenario.joins
                if end.at is not None:
                    raise FieldError(f"{base}.at", "only for an end attached to a chain link "
                                                   "(attach: '<chain>.<link>')")
                continue
            cp = chain_point(sc, end.attach)
            if cp is None:
                if end.at is not None:
                    raise FieldError(f"{base}.at", "only for an end attached to a chain link "
                                                   "(attach: '<chain>.<link>')")
                if "." in end.attach and end.attach not in special:
                    cname, _, lname = end.attach.partition(".")
                    if cname in chains:
                        raise FieldError(f"{base}.attach", f"chain '{cname}' has no link '{lname}' (links: "
                                                           f"{', '.join(chains[cname].links)})")
                    raise FieldError(f"{base}.attach", f"unknown attachment '{end.attach}': no chain '{cname}' "
                                                       f"(chains: {', '.join(chains) or 'none defined'}) and no "
                                                       f"vessel of that name")
                if end.position is None and end.attach not in ("free",) and end.attach not in getattr(sc, "bodies", {}):
                    raise FieldError(f"{base}.position", f"an end attached to '{end.attach}' needs a position")
                continue
            cname, lname = cp
            if ln.formulation != "absolute":
                raise FieldError(f"{base}.attach", f"only absolute-coordinate lines attach to chain links (this "
                                                   f"line is in the {ln.formulation} formulation: make it a link of "
                                                   f"chain '{cname}' instead)")
            length = chains[cname].links[lname].length
            if end.at is not None and end.at > length * (1 + 1e-12):
                raise FieldError(f"{base}.at", f"{end.at} m is beyond the tip of link '{lname}' of chain "
                                               f"'{cname}' ({length} m)")


def check_formulations(sc) -> None:
    """Cross-field checks of chains and non-absolute lines; raise FieldError naming the field."""
    import numpy as np
    from .joins import check_join_formulations
    check_join_formulations(sc)
    others = {n: ln for n, ln in sc.lines.items() if ln.formulation != "absolute"}
    absolute = [n for n, ln in sc.lines.items() if ln.formulation == "absolute"]
    if absolute and others:
        o = next(iter(others))
        raise FieldError(f"lines.{absolute[0]}.formulation",
                         f"this scene has line '{o}' in the {others[o].formulation} formulation; mixing it with "
                         f"absolute-coordinate lines is not supported yet (make it a link of a chain: chains and "
                         f"absolute lines are advanced by one integrator)")
    _check_chain_ends(sc)
    if not (others or sc.chains):
        return
    mixed = bool(absolute)              # chains + absolute lines: rfesim.formulations.mixed
    if getattr(sc, "supports", None):
        raise FieldError("supports", "supports act on absolute-coordinate lines only; not with chains or other "
                                     "formulations yet")
    env = sc.environment
    dyn = sc.analysis.dynamics
    if mixed and env.seabed is not None:
        raise FieldError("environment.seabed", "a scene mixing chains with absolute-coordinate lines does not "
                                               "support the seabed yet")
    needs_chain = bool(sc.chains) or any(ln.formulation != "planar" for ln in others.values())
    if mixed and dyn.enabled and dyn.duration > 0 and dyn.integrator.kind != "generalized-alpha":
        raise FieldError("analysis.dynamics.integrator.kind",
                         "a scene mixing chains with absolute-coordinate lines is advanced by one implicit "
                         "integrator over both coordinate sets: use 'generalized-alpha'")
    if not mixed and needs_chain and dyn.enabled and dyn.duration > 0 and \
            dyn.integrator.kind == "generalized-alpha":
        raise FieldError("analysis.dynamics.integrator.kind",
                         "generalized-alpha is not available for classical/modified lines and chains yet (only "
                         "for chains together with absolute-coordinate lines); use 'rk4' or 'adaptive'")
    for name, ln in others.items():
        base = f"lines.{name}"
        lt = sc.line_types.get(ln.type)
        if lt is None:
            continue                                   # reported by check_references
        if env.water is not None or env.seabed is not None:
            raise FieldError(f"{base}.formulation", f"sea and seabed loads are implemented for the absolute "
                                                    f"formulation only; the {ln.formulation} formulation needs a "
                                                    f"scene without environment.water and environment.seabed")
        if ln.end_b.attach != "free":
            raise FieldError(f"{base}.end_b.attach", f"a line in the {ln.formulation} formulation must have a free "
                                                     f"end B (closed loops are not supported yet)")
        if ln.end_a.attach == "free":
            raise FieldError(f"{base}.end_a.attach", f"a line in the {ln.formulation} formulation hangs from end A: "
                                                     f"attach it to 'fixed' or a vessel")
        if ln.formulation == "planar" and ln.end_a.attach != "fixed":
            raise FieldError(f"{base}.end_a.attach", "a planar line starts from a fixed point (vessel motion as "
                                                     "the planar base, eq. 8.69, is not wired to scenarios yet)")
        if ln.end_a.direction is None:
            raise FieldError(f"{base}.end_a.direction", f"a line in the {ln.formulation} formulation starts "
                                                        f"straight along end_a.direction: give it")
        if ln.dofs is not None:
            allowed = CLASSICAL_DOFS if ln.formulation.startswith("classical") else (
                MODIFIED_DOFS if ln.formulation == "modified" else ())
            bad = [d for d in ln.dofs if d not in allowed]
            if not allowed or bad or not ln.dofs:
                raise FieldError(f"{base}.dofs", f"must be a non-empty subset of {list(allowed)} for the "
                                                 f"{ln.formulation} formulation, got {ln.dofs}"
                                 if allowed else "the planar formulation has no dofs selection")
        if lt.material.kind != "elastic":
            # the classical, modified and planar SDEs (eqs. 8.7-8.8, 8.2, 8.3) take the section's elastic
            # stiffness; only the absolute formulation's SDE carries the plastic bending law (8.4.2), so
            # this line would otherwise run elastic without a word
            raise FieldError(f"{base}.formulation",
                             f"line type '{ln.type}' has an elastoplastic material (line_types.{ln.type}.material, "
                             f"law '{lt.material.law}'), but the elasto-plastic SDE law (section 8.4.2) is "
                             f"implemented in the absolute formulation only: the {ln.formulation} formulation "
                             f"would run it elastic (use formulation 'absolute', or an elastic material)")
        if lt.damping is not None and (lt.damping.axial_ratio is not None or lt.damping.bending_ratio is not None):
            raise FieldError(f"line_types.{ln.type}.damping", f"damping ratios are not supported by the "
                                                               f"{ln.formulation} formulation: give the bending "
                                                               f"coefficient (N*m^2*s)")
        for i, load in enumerate(ln.loads):
            if load.frame != "global":
                raise FieldError(f"{base}.loads.{i}.frame", f"only global (dead) loads in the {ln.formulation} "
                                                            f"formulation")
        if ln.formulation == "planar":
            e1, normal = planar_axes(ln.end_a.direction)
            d = np.asarray(ln.end_a.direction, float)
            if abs(d @ normal) > 1e-9 * np.linalg.norm(d):    # pragma: no cover - by construction
                raise FieldError(f"{base}.end_a.direction", "not in the line's vertical plane")
            for i, load in enumerate(ln.loads):
                F = np.asarray(load.force, float)
                M = np.asarray(load.moment, float)
                if abs(F @ normal) > 1e-9 * max(np.linalg.norm(F), 1e-300):
                    raise FieldError(f"{base}.loads.{i}.force",
                                     f"has a component {F @ normal:.6g} N out of the line's plane (the vertical "
                                     f"plane through end_a.direction, normal {np.round(normal, 6).tolist()}): a "
                                     f"planar line (section 8.3) stays in its plane")
                if np.linalg.norm(M - (M @ normal) * normal) > 1e-9 * max(np.linalg.norm(M), 1e-300):
                    raise FieldError(f"{base}.loads.{i}.moment",
                                     f"must be about the plane normal {np.round(normal, 6).tolist()} of a planar "
                                     f"line (section 8.3)")
    vessels = set(sc.vessels)
    for cname, ch in sc.chains.items():
        base = f"chains.{cname}"
        if ch.base != "fixed" and ch.base not in vessels:
            raise FieldError(f"{base}.base", f"unknown base '{ch.base}' (use 'fixed' or one of: "
                                             f"{', '.join(sorted(vessels)) or 'no vessels defined'})")
        for lname, link in ch.links.items():
            if link.type is not None and link.type not in sc.line_types:
                raise FieldError(f"{base}.links.{lname}.type", f"unknown line type '{link.type}' (line_types: "
                                                               f"{', '.join(sorted(sc.line_types)) or 'none'})")
            if link.type is not None and not link.rigid:
                lt = sc.line_types[link.type]
                if lt.material.kind != "elastic":
                    raise FieldError(f"{base}.links.{lname}.type",
                                     f"line type '{link.type}' has an elastoplastic material (line_types."
                                     f"{link.type}.material, law '{lt.material.law}'), but the elasto-plastic SDE "
                                     f"law (section 8.4.2) is implemented in the absolute formulation only: a "
                                     f"flexible chain link ({link.formulation} formulation) would run it elastic "
                                     f"(use an elastic material, or an absolute-formulation line)")
                if lt.damping is not None and (lt.damping.axial_ratio is not None
                                               or lt.damping.bending_ratio is not None):
                    raise FieldError(f"line_types.{link.type}.damping", "damping ratios are not supported on chain "
                                                                        "links: give the bending coefficient")
