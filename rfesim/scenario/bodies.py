"""Scenario schema of rigid bodies (top-level ``bodies``): payloads, buoys, clump weights.

A body hangs on the end B of one absolute-coordinate line (``"end_b": {"attach":
"payload", "position": [0, 0, 1.2]}``: the end's ``position`` is the attachment point in
the body frame, from the centre of mass). Its frame has the principal axes of inertia;
at t = 0 it is turned by ``orientation_deg`` (roll, pitch, yaw; ZYX) from the global frame::

    "bodies": {"payload": {"mass": 1.0e4, "inertia": [2e4, 2e4, 1.5e4],
                           "volume": 4.0, "height": 2.0,
                           "drag": {"cd": [1.0, 1.0, 1.2], "area": [4.0, 4.0, 4.0]},
                           "added_mass": {"ca": [0.6, 0.6, 1.0]},
                           "slam_coefficient": 3.14159,
                           "position": [0, 0, -20]}}

Hydrodynamics scale with the submerged fraction of the body's vertical extent
(rfesim.loads.bodies), or, for a body given as a box (``"dimensions": [a, b, c]`` along its
axes, centred on the centre of buoyancy), with the exact fraction of the box under water at
its current attitude, acting at the centroid of that part. Units SI.
"""
from __future__ import annotations

import math
from typing import Annotated

from pydantic import Field, model_validator

from .schema import (COEFFICIENT_LIMIT, INERTIA_FLOOR, INERTIA_LIMIT, LENGTH_LIMIT, MASS_FLOOR, MASS_LIMIT,
                     MAX_COEFFICIENT, MAX_INERTIA, MAX_LENGTH, MAX_MASS, MAX_STIFFNESS, MIN_INERTIA, MIN_MASS,
                     MIN_RADIUS_OF_GYRATION, STIFFNESS_LIMIT, FieldError, Vector3, _Strict, _units, upper_bound)

NumberOr3 = float | Vector3


def per_axis(value, default: float = 0.0) -> list[float]:
    """A scalar or [x, y, z] -> [x, y, z] (None -> default on every axis)."""
    if value is None:
        return [default] * 3
    if isinstance(value, (int, float)):
        return [float(value)] * 3
    return [float(v) for v in value]


def _check_non_negative(value, name: str) -> None:
    for k, v in enumerate(per_axis(value)):
        if v < 0.0:
            where = name if isinstance(value, (int, float)) else f"{name}.{k}"
            raise FieldError(where, f"must not be negative, got {v}")


def _check_at_most(value, name: str, limit: float, unit: str, why: str) -> None:
    """A number or [x, y, z] at most ``limit`` on every axis (schema.upper_bound)."""
    for k, v in enumerate(per_axis(value)):
        reason = upper_bound(v, limit, unit, why)
        if reason:
            raise FieldError(name if isinstance(value, (int, float)) else f"{name}.{k}", reason)


MAX_ADDED_MASS_COEFFICIENT = 1.0e4      # [-] on the displaced mass rho*volume
ADDED_MASS_COEFFICIENT_LIMIT = ("on the displaced mass rho*volume, even a thin plate's added mass is a few hundred "
                                "times it (for a plate, give the added mass itself: mass)")


class BodyDrag(_Strict):
    """Quadratic drag per body axis: F_k = 1/2 rho cd_k area_k |u_k| u_k (u: water velocity
    relative to the body at its centre of buoyancy, in body axes), times the submerged fraction."""

    cd: NumberOr3 = _units("1", "Drag coefficient, one value or one per body axis [x, y, z], each from 0 to 10",
                           default=1.0)
    area: NumberOr3 = _units("m^2", "Projected area normal to each body axis [x, y, z] (one value: all), not "
                                    "negative")

    @model_validator(mode="after")
    def _signs(self):
        _check_non_negative(self.cd, "cd")
        _check_non_negative(self.area, "area")
        _check_at_most(self.cd, "cd", MAX_COEFFICIENT, "1", COEFFICIENT_LIMIT)
        return self


class BodyAddedMass(_Strict):
    """Added mass of the fully submerged body per body axis: ``ca`` times the displaced
    mass rho*volume, or ``mass`` directly; it scales with the submerged fraction."""

    ca: NumberOr3 | None = _units("1", "Added-mass coefficient on rho*volume, one value or [x, y, z], each from "
                                       "0 to 1e4 (needs the body's volume)", default=None)
    mass: NumberOr3 | None = _units("kg", "Added mass, one value or [x, y, z] (instead of ca), not negative",
                                    default=None, limit=MASS_LIMIT)
    inertia: Vector3 = _units("kg*m^2", "Added rotational inertia about the body axes [x, y, z], not negative",
                              default=[0.0, 0.0, 0.0], limit=INERTIA_LIMIT)

    @model_validator(mode="after")
    def _one_of(self):
        if self.ca is not None and self.mass is not None:
            raise FieldError("mass", "give either ca or mass, not both")
        if self.ca is None and self.mass is None:
            raise FieldError("ca", "give the added-mass coefficient ca or the added mass itself (mass)")
        for name in ("ca", "mass", "inertia"):
            if getattr(self, name) is not None:
                _check_non_negative(getattr(self, name), name)
        if self.ca is not None:
            _check_at_most(self.ca, "ca", MAX_ADDED_MASS_COEFFICIENT, "1", ADDED_MASS_COEFFICIENT_LIMIT)
        if self.mass is not None:
            _check_at_most(self.mass, "mass", MAX_MASS, "kg", MASS_LIMIT)
        _check_at_most(self.inertia, "inertia", MAX_INERTIA, "kg*m^2", INERTIA_LIMIT)
        return self


class BodyDeck(_Strict):
    """The deck of a vessel the body rests on until it is lifted off (rfesim.loads.deck): a
    unilateral contact of the body's underside (half its vertical extent below its centre,
    along the deck's normal) with the deck plane, with Coulomb friction."""

    vessel: str = Field(..., min_length=1, description="The vessel whose deck carries the body (a name of "
                        "`vessels`)")
    height: float = _units("m", "Deck level: z of the deck plane in the vessel frame")
    stiffness: float | None = _units("N/m", "Contact stiffness (default: the body's weight over 5 mm)",
                                     default=None, gt=0.0, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    damping_ratio: float = _units("1", "Contact damping as a fraction of critical on the body's mass",
                                  default=0.5, ge=0.0, le=5.0)
    friction: float = _units("1", "Coulomb friction coefficient between body and deck", default=0.3, ge=0.0,
                             le=2.0)
    footprint: Annotated[list[float], Field(min_length=2, max_length=2)] | None = _units(
        "m", "Size [a, b] of the rectangle the body stands on, along its x and y axes, each greater than 0 "
        "(contact at its four corners); default: the body's box dimensions [a, b], else a square of side "
        "sqrt(volume / height), or the height without a volume", default=None)

    @model_validator(mode="after")
    def _footprint(self):
        if self.footprint is not None:
            for k, x in enumerate(self.footprint):
                if not (math.isfinite(x) and x > 0.0):
                    raise FieldError(f"footprint.{k}", f"must be a length greater than 0 m, got {x}")
        return self


class Body(_Strict):
    """A rigid body (payload, buoy, clump weight) hanging on the end B of a line: its mass and
    inertia, buoyancy, drag, added mass and slamming, and optionally the vessel deck it rests
    on before lift-off."""

    mass: float = _units("kg", "Mass", ge=MIN_MASS, le=MAX_MASS, limit=MASS_LIMIT, floor=MASS_FLOOR)
    inertia: Vector3 | None = _units("kg*m^2", "Principal moments of inertia about the centre of mass, body "
                                     "axes [Ixx, Iyy, Izz], each at least 1e-9 and none more than the sum of the "
                                     "other two", default=None, limit=INERTIA_LIMIT)
    radius_of_gyration: NumberOr3 | None = _units("m", "Radius of gyration, one value or [x, y, z] (instead of "
                                                  "inertia: I = mass * r^2), each at least 0.001", default=None,
                                                  limit=LENGTH_LIMIT)
    volume: float = _units("m^3", "Displaced volume when fully submerged (a box: at most a * b * c)", default=0.0,
                           ge=0.0)
    height: float | None = _units("m", "Vertical extent over which the body goes under water (buoyancy, drag "
                                  "and added mass scale with the submerged part of it; slamming acts, "
                                  "unscaled, while it crosses the surface); default: "
                                  "the cube root of the volume; for a box: its c (or left out)", default=None,
                                  gt=0.0)
    centre_of_buoyancy: Vector3 = _units("m", "Centre of buoyancy from the centre of mass, body axes (also the "
                                         "middle of the vertical extent, or the box's centre, and where drag "
                                         "acts when fully submerged)", default=[0.0, 0.0, 0.0])
    dimensions: Vector3 | None = _units("m", "The body as a box [a, b, c] along its axes x, y, z, each greater "
                                        "than 0, centred on the centre of buoyancy: the submerged fraction is the "
                                        "part of the box under water at the body's attitude, and buoyancy, drag "
                                        "and water inertia act at that part's centroid (a tilted box in the "
                                        "splash zone gets its "
                                        "restoring moment); c is the height (give one). The volume is spread "
                                        "uniformly over the box. Without it: the vertical extent `height`, "
                                        "whatever the attitude", default=None, limit=LENGTH_LIMIT)
    drag: BodyDrag | None = None
    added_mass: BodyAddedMass | None = None
    slam_coefficient: float = _units("1", "Slamming coefficient C_s: while the body crosses the surface moving "
                                          "down into the water, an upward force 1/2 rho C_s A_s v^2",
                                     default=math.pi, ge=0.0, le=100.0)
    slam_area: float | None = _units("m^2", "Slamming area A_s (horizontal projection; default: the drag area "
                                     "along the body z axis, else volume/height)", default=None, ge=0.0)
    position: Vector3 | None = _units("m", "Centre of mass at t = 0 (global); default: the line hangs straight "
                                      "down from its end A with the body under it", default=None)
    orientation_deg: Vector3 = _units("deg", "Roll, pitch, yaw of the body axes at t = 0 (ZYX, global)",
                                      default=[0.0, 0.0, 0.0])
    deck: BodyDeck | None = Field(None, description="A vessel deck the body rests on before lift-off "
                                  "(unilateral contact with friction)")

    @model_validator(mode="after")
    def _inertia(self):
        if self.inertia is not None and self.radius_of_gyration is not None:
            raise FieldError("radius_of_gyration", "give either inertia or radius_of_gyration, not both")
        if self.inertia is None and self.radius_of_gyration is None:
            raise FieldError("inertia", "give the principal moments of inertia [Ixx, Iyy, Izz] (kg*m^2) or a "
                                        "radius_of_gyration (m)")
        if self.radius_of_gyration is not None:
            for k, r in enumerate(per_axis(self.radius_of_gyration)):
                if not r >= MIN_RADIUS_OF_GYRATION:
                    where = "radius_of_gyration" if isinstance(self.radius_of_gyration, (int, float)) \
                        else f"radius_of_gyration.{k}"
                    raise FieldError(where, f"must be at least {MIN_RADIUS_OF_GYRATION:g} m (a millimetre), got {r}: a "
                                            f"body that does not resist turning cannot be integrated (check the units)")
            _check_at_most(self.radius_of_gyration, "radius_of_gyration", MAX_LENGTH, "m", LENGTH_LIMIT)
        else:
            I = self.inertia
            for k, v in enumerate(I):
                if not v >= MIN_INERTIA:
                    raise FieldError(f"inertia.{k}", f"must be at least {MIN_INERTIA:g} kg*m^2, got {v}: "
                                                     f"{INERTIA_FLOOR}")
            _check_at_most(I, "inertia", MAX_INERTIA, "kg*m^2", INERTIA_LIMIT)
            for k in range(3):
                if I[k] > 1.000001 * (I[(k + 1) % 3] + I[(k + 2) % 3]):
                    raise FieldError("inertia", f"I{'xyz'[k]}{'xyz'[k]} = {I[k]:.6g} kg*m^2 exceeds the sum of the "
                                                "other two: no rigid body has these principal moments")
        return self

    @model_validator(mode="after")
    def _box(self):
        if self.dimensions is None:
            return self
        for k, x in enumerate(self.dimensions):
            if not (math.isfinite(x) and x > 0.0):
                raise FieldError(f"dimensions.{k}", f"must be a length greater than 0 m, got {x}")
        _check_at_most(self.dimensions, "dimensions", MAX_LENGTH, "m", LENGTH_LIMIT)
        a, b, c = (float(x) for x in self.dimensions)
        if self.height is not None and abs(self.height - c) > 1e-9 * c:
            raise FieldError("height", f"{self.height} m differs from the box's height dimensions.2 = {c} m: give "
                                       f"one of them")
        if self.volume > a * b * c * (1.0 + 1e-9):
            raise FieldError("volume", f"{self.volume} m^3 is more than the box dimensions {a} x {b} x {c} m "
                                       f"holds ({a * b * c:.6g} m^3)")
        return self

    @model_validator(mode="after")
    def _added_mass_volume(self):
        am = self.added_mass
        if am is not None and am.ca is not None and self.volume <= 0.0 and any(c > 0.0 for c in per_axis(am.ca)):
            raise FieldError("added_mass.ca", "needs the body's volume: the added mass is ca rho volume, and "
                                              "without a volume it would be 0; give volume (m^3) or the added "
                                              "mass itself, added_mass.mass (kg)")
        return self

    def principal_inertia(self) -> list[float]:
        """[Ixx, Iyy, Izz] in kg*m^2."""
        if self.inertia is not None:
            return [float(v) for v in self.inertia]
        return [self.mass * r * r for r in per_axis(self.radius_of_gyration)]

    def deck_footprint(self) -> list[float]:
        """[a, b] m: the rectangle the body stands on (deck.footprint, or the box's [a, b], or a
        square of side sqrt(volume / height), or the height)."""
        if self.deck is not None and self.deck.footprint is not None:
            return [float(x) for x in self.deck.footprint]
        if self.dimensions is not None:
            return [float(self.dimensions[0]), float(self.dimensions[1])]
        h = self.vertical_extent()
        side = math.sqrt(self.volume / h) if self.volume > 0.0 else h
        return [side, side]

    def vertical_extent(self) -> float:
        """m: the height (or the box's c), or the cube root of the volume (1 m without a volume)."""
        if self.height is not None:
            return float(self.height)
        if self.dimensions is not None:
            return float(self.dimensions[2])
        return float(self.volume) ** (1.0 / 3.0) if self.volume > 0.0 else 1.0

    def box_half_sizes(self) -> list[float]:
        """[a/2, b/2, c/2] m of a box body, [0, 0, 0] without dimensions."""
        if self.dimensions is None:
            return [0.0, 0.0, 0.0]
        return [0.5 * float(x) for x in self.dimensions]

    def drag_cd_area(self) -> list[float]:
        """cd * area per body axis (m^2)."""
        if self.drag is None:
            return [0.0, 0.0, 0.0]
        return [c * a for c, a in zip(per_axis(self.drag.cd), per_axis(self.drag.area))]

    def added_mass_per_axis(self, water_density: float) -> list[float]:
        """kg, fully submerged."""
        am = self.added_mass
        if am is None:
            return [0.0, 0.0, 0.0]
        if am.mass is not None:
            return per_axis(am.mass)
        return [water_density * self.volume * c for c in per_axis(am.ca)]

    def slamming_area(self) -> float:
        """m^2."""
        if self.slam_area is not None:
            return float(self.slam_area)
        if self.drag is not None:
            return float(per_axis(self.drag.area)[2])
        return float(self.volume / self.vertical_extent()) if self.volume > 0.0 else 0.0


def check_body_references(sc) -> list[tuple[str, str]]:
    """Bodies hang on end B of exactly one absolute-coordinate line."""
    errors: list[tuple[str, str]] = []
    users: dict[str, list[str]] = {}
    for name in sc.bodies:
        if name in ("fixed", "free") or name in sc.vessels:
            errors.append((f"bodies.{name}", f"'{name}' is already a vessel or a reserved attachment word; "
                                             f"rename the body"))
        elif not name or any(c in name for c in "/:\\") or name.strip() != name:
            errors.append((f"bodies.{name}", f"bad name {name!r}: names must be non-empty and must not contain "
                                             f"'/', ':' or '\\' or outer spaces"))
    for lname, line in sc.lines.items():
        if line.end_a.attach in sc.bodies:
            errors.append((f"lines.{lname}.end_a.attach", f"a body hangs on a line's end B: attach body "
                                                          f"'{line.end_a.attach}' at end_b (reverse the line)"))
        if line.end_b.attach in sc.bodies:
            users.setdefault(line.end_b.attach, []).append(lname)
            if line.formulation != "absolute":
                errors.append((f"lines.{lname}.formulation", "a body can hang only on a line in the absolute "
                                                             "formulation"))
    for bname, lines in users.items():
        if len(lines) > 1:
            errors.append((f"lines.{lines[1]}.end_b.attach",
                           f"body '{bname}' already hangs on line '{lines[0]}': one line per body (more lines on "
                           f"one body would break the block-tridiagonal structure of the model)"))
    for bname, body in sc.bodies.items():
        deck = getattr(body, "deck", None)
        if deck is not None and deck.vessel not in sc.vessels:
            known = ", ".join(sc.vessels) or "none"
            errors.append((f"bodies.{bname}.deck.vessel", f"unknown vessel '{deck.vessel}' (vessels: {known})"))
    for bname in sc.bodies:
        if bname not in users:
            errors.append((f"bodies.{bname}", "not attached to any line: attach it at a line's end_b "
                                              f"(\"end_b\": {{\"attach\": \"{bname}\", \"position\": [...]}})"))
    return errors
