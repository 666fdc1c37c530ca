"""Crane templates (top-level ``cranes``): a column (pedestal) crane and an A-frame that
expand into ordinary scenario sections before the rest of the scenario is validated.

    "cranes": {"crane": {"type": "column", "vessel": "supply", "position": [-20, 8, 3],
                         "pedestal": {"length": 10.0, "outer_diameter": 2.0, "wall_thickness": 0.04},
                         "boom": {"length": 30.0, "outer_diameter": 1.0, "wall_thickness": 0.025},
                         "slewing_deg": 0.0, "luffing_deg": 50.0,
                         "rope": {"length": 20.0, "diameter": 0.04},
                         "payload": {"mass": 10000, "radius_of_gyration": 1.0, "volume": 4.0},
                         "winch": {"mode": {"kind": "speed", "rows": [[0, 0], [10, 0.5]]}}}}

A crane is one serial string of absolute-coordinate lines (section 8.4) joined end to end
(``"attach": "<parent>:end_b"``, rfesim.model.compile), so the whole crane, its rope and
its payload are advanced by the compiled generalized-alpha path with a block-tridiagonal
Jacobian:

* column: pedestal (end A clamped to the deck) -> clamped joint driven by slewing (about
  the pedestal axis) then luffing (about the boom foot's horizontal axis) -> boom ->
  pinned joint (the tip sheave) -> hoist rope (tension only) -> payload (a body);
* a-frame: a deck stub (a short, stiff line under the hinge, clamped to the deck) ->
  clamped joint driven by the luffing cylinders -> legs (the two legs as one line: the
  symmetric in-plane equivalent of the portal, see docs/theory.md) -> crossbeam (a short
  line carrying the crossbeam's mass) -> pinned joint (the top sheave) -> rope -> payload;
  with ``crossbeam`` given, the closed portal: per leg a deck stub -> luffing joint -> leg
  -> crossbeam half toward mid-span, the second half closing onto the first (a closing
  join, rfesim.scenario.joins), the rope from mid-span.

Drives are angle tables (deg against s); a luffing cylinder's stroke table is turned into
the angle table by the triangle hinge - cylinder base - cylinder eye (``cylinder``), a
luffing rope's length table by the triangle hinge - gantry - eye (``luffing_rope``), and
their forces are outputs (rfesim.crane_results). The winch (``winch``) is passed to ``winches``
on the rope (rfesim.model.winches).

Names made for crane ``c``: lines ``c_pedestal``, ``c_boom`` (column) or ``c_stub``,
``c_legs``, ``c_crossbeam`` (a-frame; the portal adds ``c_stub_2``, ``c_legs_2``,
``c_crossbeam_2`` and the tugger ``c_cylinder_2``), ``c_rope``; line types ``<line>_section``; the body
``c_payload`` (inline payloads); the winch ``c_winch``; the vessel ``c_vessel`` (inline
vessels); the tugger lines ``c_<name>`` (``tuggers``, rfesim.scenario.tuggers). Geometry in
the vessel frame; SI units, angles in degrees.
"""
from __future__ import annotations

import copy
import math
from typing import Annotated, Literal, Union

import numpy as np
from pydantic import Field, TypeAdapter, ValidationError, model_validator

from .bodies import Body
from .pipelay import MIN_WALL_THICKNESS, STEEL_DENSITY, STEEL_E, WALL_THICKNESS_FLOOR, _add, _vessel_pose, \
    expand_templates
from .schema import (COEFFICIENT_LIMIT, DAMPING_LIMIT, DENSITY_LIMIT, FORCE_LIMIT, MASS_LIMIT, MASS_PER_LENGTH_FLOOR,
                     MASS_PER_LENGTH_LIMIT, MAX_COEFFICIENT, MAX_DAMPING, MAX_DENSITY, MAX_FORCE, MAX_MASS,
                     MAX_MASS_PER_LENGTH, MAX_MODULUS, MAX_SECTION_STIFFNESS, MAX_STIFFNESS, MIN_MASS_PER_LENGTH,
                     MODULUS_LIMIT, SECTION_STIFFNESS_LIMIT, STIFFNESS_LIMIT, FieldError, Vector3, Vessel, _Strict,
                     _units, DENSITY_FLOOR, MIN_DENSITY, MIN_MODULUS, MODULUS_FLOOR)
from .tuggers import TuggerElastic, TuggerTension
from .winches import TemplateWinch

# A rope's bending stiffness against a solid bar of its diameter: the strands bend nearly on
# their own (a stranded wire rope's effective EI lies between its wires' sum and the solid
# bar's). A few per cent also keeps the half-length RFE under a pinned sheave from turning
# freely: with EI = 1 N*m^2 every generalized-alpha step of the column crane halved, with
# 2 % (341 N*m^2 at 36 mm) some still did at 0.1 s, with 6 % hardly any.
ROPE_BENDING_FRACTION = 0.06

# Lower bounds of the template's sizes, with the reasons given when a value is below them (the
# ``floor`` of _units): each is far below any real crane, and a size under it would reach the
# expanded scenario as a section of no stiffness or mass, or a line shorter than its elements
# allow, reported there under a name the user never wrote.
MIN_MEMBER_LENGTH = 0.1          # m
MEMBER_LENGTH_FLOOR = ("a decimetre: pedestals, booms, legs and crossbeams are metres long, and a member shorter "
                       "than its elements can be made of cannot be integrated (check the units, metres)")
MIN_ROPE_DIAMETER = 1.0e-3       # m
ROPE_DIAMETER_FLOOR = ("a millimetre: thinner than any hoist or wire rope (they start at a few mm); the rope's default "
                       "stiffness and mass grow with its diameter squared and would vanish (check the units, metres)")
MIN_ROPE_LENGTH = 0.1            # m
ROPE_LENGTH_FLOOR = ("a decimetre between the sheave and the payload: a shorter rope cannot be divided into its "
                     "elements (check the units, metres)")

AngleProfile = Union[float, list[Annotated[list[float], Field(min_length=2, max_length=2)]]]


def _check_profile(value, field: str, lo: float, hi: float, unit: str = "deg") -> None:
    """A constant or a table of [t s, value] rows with increasing times, values in [lo, hi]."""
    if isinstance(value, (int, float)):
        if not lo <= value <= hi:
            raise FieldError(field, f"{value} {unit} is outside [{lo}, {hi}] {unit}")
        return
    if len(value) < 1:
        raise FieldError(field, "a table needs at least one row [t, value]")
    for i, (t, v) in enumerate(value):
        if not (math.isfinite(t) and math.isfinite(v)):
            raise FieldError(f"{field}.{i}", "must be finite numbers")
        if i and t <= value[i - 1][0]:
            raise FieldError(f"{field}.{i}.0", f"times must increase: {t} s after {value[i - 1][0]} s")
        if not lo <= v <= hi:
            raise FieldError(f"{field}.{i}.1", f"{v} {unit} is outside [{lo}, {hi}] {unit}")


def _initial(value) -> float:
    """The profile's value at t = 0 as its drive follows it: the cubic Hermite through the
    table with the drive's slopes (rfesim.model.supports.drive_slopes), held constant before
    the first row and after the last."""
    if isinstance(value, (int, float)):
        return float(value)
    ts = np.array([float(r[0]) for r in value])
    vs = np.array([float(r[1]) for r in value])
    if 0.0 <= ts[0]:
        return float(vs[0])
    if ts[-1] <= 0.0:
        return float(vs[-1])
    from ..loads.drives import drive_table
    from ..model.supports import drive_slopes
    return float(drive_table(ts, vs, drive_slopes(ts, vs), 0.0)[0])


def _table(value) -> list[list[float]]:
    """A drive table [[t, deg], ...]; a constant holds still (two equal rows), so every crane
    joint has its drive and its torque is an output."""
    if isinstance(value, (int, float)):
        return [[0.0, float(value)], [1.0, float(value)]]
    rows = [[float(t), float(v)] for t, v in value]
    return rows if len(rows) > 1 else rows + [[rows[0][0] + 1.0, rows[0][1]]]


class MemberSpec(_Strict):
    """A structural member as a steel tube (outer_diameter, wall_thickness), or by its direct
    section properties (EA, EI, mass_per_length; GJ defaults to EI / 1.3)."""

    length: float = _units("m", "Length of the member", ge=MIN_MEMBER_LENGTH, le=500.0, floor=MEMBER_LENGTH_FLOOR)
    elements: int | None = _units("1", "Number of SDEs (default: one per 2 m, at least 4)", default=None, ge=1,
                                  le=1000)
    outer_diameter: float | None = _units("m", "Tube outer diameter (also the wind/drag diameter)", default=None,
                                          gt=0.0, le=50.0,
                                          limit="a crane member is a slender tube, at most a few metres across "
                                                "(check the units, metres)")
    wall_thickness: float | None = _units("m", "Tube wall thickness, less than outer_diameter/2", default=None,
                                          ge=MIN_WALL_THICKNESS,
                                          floor=WALL_THICKNESS_FLOOR)
    youngs_modulus: float = _units("Pa", "Young's modulus", default=STEEL_E, ge=MIN_MODULUS,
                                   le=MAX_MODULUS, limit=MODULUS_LIMIT, floor=MODULUS_FLOOR)
    density: float = _units("kg/m^3", "Density of the steel", default=STEEL_DENSITY, ge=MIN_DENSITY,
                            le=MAX_DENSITY, limit=DENSITY_LIMIT, floor=DENSITY_FLOOR)
    EA: float | None = _units("N", "Axial stiffness (instead of a tube)", default=None, gt=0.0,
                              le=MAX_SECTION_STIFFNESS, limit=SECTION_STIFFNESS_LIMIT)
    EI: float | None = _units("N*m^2", "Bending stiffness (instead of a tube)", default=None, gt=0.0,
                              le=MAX_SECTION_STIFFNESS, limit=SECTION_STIFFNESS_LIMIT)
    GJ: float | None = _units("N*m^2", "Torsional stiffness (default EI/1.3)", default=None, gt=0.0,
                              le=MAX_SECTION_STIFFNESS, limit=SECTION_STIFFNESS_LIMIT)
    mass_per_length: float | None = _units("kg/m", "Mass per length (instead of a tube)", default=None,
                                           ge=MIN_MASS_PER_LENGTH, le=MAX_MASS_PER_LENGTH,
                                           limit=MASS_PER_LENGTH_LIMIT, floor=MASS_PER_LENGTH_FLOOR)
    damping_ratio: float = _units("1", "Structural damping ratio of the element modes", default=0.02, ge=0.0,
                                  le=2.0)

    @model_validator(mode="after")
    def _section(self):
        tube = self.outer_diameter is not None or self.wall_thickness is not None
        direct = any(v is not None for v in (self.EA, self.EI, self.mass_per_length))
        if tube and direct:
            raise FieldError("EA", "give a tube (outer_diameter, wall_thickness) or direct section properties "
                                   "(EA, EI, mass_per_length), not both")
        if tube:
            if self.outer_diameter is None or self.wall_thickness is None:
                raise FieldError("wall_thickness" if self.wall_thickness is None else "outer_diameter",
                                 "a tube needs outer_diameter and wall_thickness")
            if self.wall_thickness >= 0.5 * self.outer_diameter:
                raise FieldError("wall_thickness", f"{self.wall_thickness} m is not less than the outer radius "
                                                   f"{0.5 * self.outer_diameter} m")
        elif not direct:
            raise FieldError("outer_diameter", "give a tube (outer_diameter, wall_thickness) or direct section "
                                               "properties (EA, EI, mass_per_length)")
        else:
            for name in ("EA", "EI", "mass_per_length"):
                if getattr(self, name) is None:
                    raise FieldError(name, "direct section properties need EA, EI and mass_per_length")
        return self

    def properties(self) -> dict:
        """EA, EI, GJ (N, N*m^2) and mass per length (kg/m)."""
        if self.outer_diameter is not None:
            D, d = self.outer_diameter, self.outer_diameter - 2.0 * self.wall_thickness
            A = math.pi / 4.0 * (D * D - d * d)
            I = math.pi / 64.0 * (D ** 4 - d ** 4)
            E = self.youngs_modulus
            return {"EA": E * A, "EI": E * I, "GJ": E / 1.3 * 2.0 * I, "mass_per_length": self.density * A}
        return {"EA": self.EA, "EI": self.EI, "GJ": self.GJ or self.EI / 1.3, "mass_per_length": self.mass_per_length}

    def count(self) -> int:
        return self.elements if self.elements is not None else max(4, int(math.ceil(self.length / 2.0 - 1e-9)))


class RopeSpec(_Strict):
    """The hoist rope (tension only): from the sheave to the payload's attachment point."""

    length: float = _units("m", "Rope between the sheave and the payload at the start", ge=MIN_ROPE_LENGTH,
                           le=1.0e4, floor=ROPE_LENGTH_FLOOR)
    elements: int | None = _units("1", "Number of SDEs (default: one per 1 m, at least 10, at most 100)",
                                  default=None, ge=1, le=10000)
    diameter: float = _units("m", "Nominal rope diameter (drag, buoyancy)", default=0.04, ge=MIN_ROPE_DIAMETER,
                             le=0.5, floor=ROPE_DIAMETER_FLOOR)
    EA: float | None = _units("N", "Axial stiffness (default: a steel wire rope, 0.58 of the nominal area at "
                              "100 GPa)", default=None, gt=0.0, le=MAX_SECTION_STIFFNESS, limit=SECTION_STIFFNESS_LIMIT)
    mass_per_length: float | None = _units("kg/m", "Mass per length (default: 4000 d^2, a steel wire rope)",
                                           default=None, ge=MIN_MASS_PER_LENGTH, le=MAX_MASS_PER_LENGTH,
                                           limit=MASS_PER_LENGTH_LIMIT, floor=MASS_PER_LENGTH_FLOOR)
    bending_stiffness: float | None = _units("N*m^2", "Bending stiffness (default: 6 % of a solid steel bar of "
                                             "the rope's diameter, a stranded rope)", default=None, ge=0.0,
                                             le=MAX_SECTION_STIFFNESS, limit=SECTION_STIFFNESS_LIMIT)
    damping_ratio: float = _units("1", "Damping ratio of the rope's axial element modes", default=0.2, ge=0.0,
                                  le=2.0)
    drag_normal: float = _units("1", "Normal drag coefficient", default=1.2, ge=0.0, le=MAX_COEFFICIENT,
                                limit=COEFFICIENT_LIMIT)
    added_mass_normal: float = _units("1", "Normal added-mass coefficient", default=1.0, ge=0.0, le=MAX_COEFFICIENT,
                                      limit=COEFFICIENT_LIMIT)
    breaking_load: float | None = _units("N", "Minimum breaking load (MBL) of the rope: a run whose rope tension "
                                              "exceeds it says so (the rope's line type breaking_load); omit for "
                                              "no check", default=None, gt=0.0, le=1e12)

    def count(self) -> int:
        return self.elements if self.elements is not None else min(100, max(10, int(math.ceil(self.length))))

    def line_type(self) -> dict:
        d = self.diameter
        EA = self.EA if self.EA is not None else 0.58 * math.pi / 4.0 * d * d * 1.0e11
        mass = self.mass_per_length if self.mass_per_length is not None else 4000.0 * d * d
        EI = self.bending_stiffness if self.bending_stiffness is not None else \
            ROPE_BENDING_FRACTION * STEEL_E * math.pi / 64.0 * d ** 4
        return {"EA": EA, "EIy": EI, "mass_per_length": mass, "outer_diameter": d,
                "tension_only": True, "breaking_load": self.breaking_load,
                "drag_normal": self.drag_normal, "added_mass_normal": self.added_mass_normal,
                "damping": {"axial_ratio": self.damping_ratio, "bending_ratio": self.damping_ratio}}


class CylinderSpec(_Strict):
    """Luffing cylinder(s) between a base point and an eye on the boom / legs, in the plane of
    luffing: x toward the boom's outreach (the A-frame's outboard side), z up, from the hinge."""

    base: Annotated[list[float], Field(min_length=2, max_length=2)] = _units(
        "m", "Cylinder base [x, z] from the hinge in the luffing plane")
    eye: float = _units("m", "Distance of the cylinder eye from the hinge along the boom / leg (with force: at "
                             "most the legs' length)", gt=0.0)
    count: int = _units("1", "Number of cylinders sharing the load", default=1, ge=1, le=8)
    stroke: list[Annotated[list[float], Field(min_length=2, max_length=2)]] | None = _units(
        "s, m", "Cylinder length table [[t, length], ...], times strictly increasing, lengths 0.001 to 1000 that "
                "the cylinder can reach within the boom's (legs') range: drives the luffing instead of an angle "
                "table", default=None)
    force: AngleProfile | None = _units(
        "N (s, N)", "A-frame: force per cylinder (positive pushing), or a table [[t, force], ...] with times "
        "strictly increasing; within +-1e9: the legs turn freely on their hinge under it and their weights "
        "(tilt_deg is then the starting tilt, a constant; statics finds the tilt the force at t = 0 holds)",
        default=None)
    length_min: float | None = _units("m", "With force: the cylinder's shortest length, an end stop (default: none)",
                                      default=None, gt=0.0)
    length_max: float | None = _units("m", "With force: the cylinder's longest length, an end stop, longer than "
                                           "length_min (default: none)", default=None, gt=0.0)
    stop_stiffness: float = _units("N/m", "With force: stiffness of each cylinder's end stops", default=1.0e9,
                                   gt=0.0, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)


class CraneTugger(_Strict):
    """A tugger line from a deck point to the crane's payload (rfesim.scenario.tuggers)."""

    deck_point: Vector3 = _units("m", "The line's deck end (winch or fairlead) in the vessel's frame")
    body_point: Vector3 = _units("m", "The line's end on the payload, in its body frame (default: the centre)",
                                 default=[0.0, 0.0, 0.0])
    vessel: str | None = Field(None, description="The vessel whose deck carries the tugger (default: the "
                               "crane's vessel)")
    mode: Annotated[Union[TuggerTension, TuggerElastic], Field(discriminator="kind")]


class LuffingRopeSpec(_Strict):
    """A luffing rope (topping lift) between a gantry point and an eye on the boom, in the
    plane of luffing (x toward the boom's outreach, z up, from the boom hinge): its length
    table drives the boom angle through the triangle hinge - gantry - eye."""

    gantry: Annotated[list[float], Field(min_length=2, max_length=2)] = _units(
        "m", "Gantry point [x, z] from the boom hinge in the luffing plane (behind and above it)")
    eye: float | None = _units("m", "Distance of the rope's eye from the hinge along the boom, at most the boom's "
                                    "length (default: the tip)", default=None, gt=0.0)
    falls: int = _units("1", "Parts of line between the gantry and the eye (the pull on the boom is falls times "
                             "the rope tension)", default=1, ge=1, le=24)
    length: list[Annotated[list[float], Field(min_length=2, max_length=2)]] = _units(
        "s, m", "Distance gantry - eye against time [[t, length], ...], times strictly increasing, lengths 0.001 "
                "to 1000 that put the boom within -10 to 85 deg (the winch pays out falls times its change)")


class _Crane(_Strict):
    vessel: Union[str, Vessel] = Field(default_factory=Vessel, description="A vessel name of `vessels`, or a "
                                       "vessel (position, heading_deg, motion) made as <name>_vessel")
    position: Vector3 = _units("m", "Deck point of the pedestal base / A-frame hinge (vessel frame)")
    rope: RopeSpec
    payload: Union[str, Body] = Field(..., description="A body name of `bodies`, or a body (made as "
                                      "<name>_payload, hanging under the sheave)")
    payload_attachment: Vector3 | None = _units("m", "Rope's attachment point on the payload (body frame; "
                                                "default: the top of the body's vertical extent)", default=None)
    winch: TemplateWinch | None = Field(None, description="The winch on the rope (a `winches` entry without "
                                        "`line`): mode, heave_compensation, shock_absorber")
    tuggers: dict[str, CraneTugger] = Field(default_factory=dict, description="Tugger lines steadying the "
                                            "payload, made as top-level `tuggers` <crane>_<name> "
                                            "(rfesim.scenario.tuggers)")
    reeving: Union[Literal["boom"], Vector3, None] = _units(
        "m", 'The hoist rope\'s run from the sheave to its winch: "boom" (along the boom, or the legs, to its '
             'foot: the winch on the crane), or the deck point [x, y, z] of the winch or its guide sheave (vessel '
             'frame); the sheave is pulled toward it by the rope tension (rfesim.loads.reeving). Default: left '
             'out (the winch pays out at the sheave)', default=None)


class SlewingMotor(_Strict):
    """The slewing drive as a torque-limited servo motor (rfesim.loads.drives.motor_forces):
    it follows ``slewing_deg`` through the servo gains and never gives more than
    ``max_torque``; the pedestal's top TURRET_LENGTH is then a turret on the slewing ring."""

    max_torque: float = _units("N*m", "Largest slewing torque (both directions)", gt=0.0,
                               le=MAX_FORCE, limit=FORCE_LIMIT)
    stiffness: float | None = _units("N*m/rad", "Servo gain on the angle error (default: the crane's inertia "
                                     "about the pedestal axis times (2 pi 0.5 Hz)^2)", default=None, gt=0.0,
                                     le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    damping: float | None = _units("N*m*s/rad", "Servo gain on the rate error (default: critical for that "
                                   "stiffness and inertia)", default=None, ge=0.0, le=MAX_DAMPING, limit=DAMPING_LIMIT)


TURRET_LENGTH = 1.0         # m, top of the pedestal turned by a slewing motor (at most a quarter of the pedestal)
SERVO_FREQUENCY = 0.5       # Hz, default natural frequency of the slewing servo on the crane's inertia


class ColumnCrane(_Crane):
    """Column (pedestal) crane: pedestal, slewing and luffing joint, boom, tip sheave, rope."""

    type: Literal["column"]
    pedestal: MemberSpec
    boom: MemberSpec
    slewing_deg: AngleProfile = _units("deg (s, deg)", "Slewing angle about the pedestal axis from the vessel's "
                                                       "x axis, within +-3600, or a table [[t, angle], ...] with "
                                                       "times strictly increasing", default=0.0)
    luffing_deg: AngleProfile | None = _units("deg (s, deg)", "Boom angle above the horizontal, -10 to 85, or a "
                                                              "table [[t, angle], ...] with times strictly "
                                                              "increasing (or give cylinder.stroke, or "
                                                              "luffing_rope.length)", default=None)
    cylinder: CylinderSpec | None = None
    luffing_rope: LuffingRopeSpec | None = Field(None, description="Luffing by a rope from a gantry: its length "
                                                 "table drives the boom angle (instead of luffing_deg)")
    slewing_motor: SlewingMotor | None = Field(None, description="Slewing by a torque-limited servo motor "
                                               "following slewing_deg (default: slewing_deg is imposed exactly)")

    @model_validator(mode="after")
    def _drives(self):
        _check_profile(self.slewing_deg, "slewing_deg", -3600.0, 3600.0)
        if self.cylinder is not None and self.cylinder.force is not None:
            raise FieldError("cylinder.force", "a force-driven cylinder luffs the A-frame only; for the column "
                                               "crane give luffing_deg or cylinder.stroke")
        _luffing(self, "luffing_deg", -10.0, 85.0)
        return self


class AFrame(_Crane):
    """A-frame: two legs pinned to the deck, a crossbeam with the top sheave, luffed by
    hydraulic cylinders."""

    type: Literal["a-frame"]
    legs: MemberSpec
    leg_spacing: float = _units("m", "Distance between the two legs (across the vessel)", default=6.0, gt=0.0)
    crossbeam_mass: float = _units("kg", "Without `crossbeam`: the mass of the whole crossbeam with its sheave "
                                         "block, carried at the legs' top (the equivalent frame's short top line); "
                                         "with a `crossbeam` member: only what its tube leaves out, the sheave block "
                                         "and fittings, spread over its span on top of the tube's own mass (from "
                                         "its section)", default=0.0, ge=0.0, le=MAX_MASS, limit=MASS_LIMIT)
    outboard_deg: float = _units("deg", "Direction of the outboard side in the vessel frame (180: over the "
                                 "stern, -x)", default=180.0, ge=-360.0, le=360.0)
    tilt_deg: AngleProfile | None = _units("deg (s, deg)", "Leg angle from the vertical, positive outboard, -80 to "
                                                           "80, or a table [[t, angle], ...] with times strictly "
                                                           "increasing (or give cylinder.stroke); a constant with "
                                                           "cylinder.force", default=None)
    cylinder: CylinderSpec | None = None
    crossbeam: MemberSpec | None = Field(None, description="The crossbeam as a member (its length is "
                                         "leg_spacing): the frame is then the closed portal -- two legs, each on "
                                         "its own hinge with half the cylinders, and the crossbeam between their "
                                         "tops with the sheave at mid-span (crossbeam_mass: the sheave block, "
                                         "spread over it). Without it, the symmetric in-plane equivalent: one line "
                                         "for both legs (docs/theory.md, 'Crane templates')")

    @model_validator(mode="after")
    def _drives(self):
        if self.crossbeam is not None and abs(self.crossbeam.length - self.leg_spacing) > 1e-9 * self.leg_spacing:
            raise FieldError("crossbeam.length", f"{self.crossbeam.length} m: the crossbeam spans the legs, so its "
                                                 f"length must equal leg_spacing ({self.leg_spacing} m): give both "
                                                 f"the same value")
        if self.cylinder is not None and self.cylinder.force is not None:
            force = self.cylinder.force
            if self.cylinder.stroke is not None:
                raise FieldError("cylinder.stroke", "give cylinder.stroke or cylinder.force, not both")
            if self.tilt_deg is None or not isinstance(self.tilt_deg, (int, float)):
                raise FieldError("tilt_deg", "with cylinder.force give the starting tilt as a constant (deg)")
            _check_profile(self.tilt_deg, "tilt_deg", -80.0, 80.0)
            _check_profile(force, "cylinder.force", -1e9, 1e9, "N")
            return self
        _luffing(self, "tilt_deg", -80.0, 80.0)
        return self


def _luffing(tpl, field: str, lo: float, hi: float) -> None:
    value = getattr(tpl, field)
    stroke = tpl.cylinder.stroke if tpl.cylinder is not None else None
    rope = getattr(tpl, "luffing_rope", None)
    given = [name for name, v in ((field, value), ("cylinder.stroke", stroke), ("luffing_rope", rope))
             if v is not None]
    if not given:
        raise FieldError(field, "give the angle (a constant or a table), or cylinder.stroke"
                                + (", or luffing_rope" if hasattr(tpl, "luffing_rope") else ""))
    if len(given) > 1:
        raise FieldError(given[1], f"give one of {' or '.join(given)}, not both")
    if value is not None:
        _check_profile(value, field, lo, hi)
    elif stroke is not None:
        _check_profile(stroke, "cylinder.stroke", 1e-3, 1e3, "m")
    else:
        _check_profile(rope.length, "luffing_rope.length", 1e-3, 1e3, "m")
        if rope.eye is not None and rope.eye > tpl.boom.length:
            raise FieldError("luffing_rope.eye", f"{rope.eye} m is beyond the boom's {tpl.boom.length} m")


CraneTemplate = Annotated[Union[ColumnCrane, AFrame], Field(discriminator="type")]
_TEMPLATES = TypeAdapter(dict[str, CraneTemplate])


# ============================================================================ geometry
def cylinder_angle(cyl: CylinderSpec, length: float, span: tuple[float, float] | None = None,
                   through: float | None = None) -> float:
    """Boom angle (rad, from the luffing plane's x axis toward z) at which the cylinder
    between ``cyl.base`` and the eye at ``cyl.eye`` along the boom has ``length``: the
    branch on which the cylinder lengthens as the angle grows; with ``span`` (lo, hi rad),
    the branch whose angle lies in it. The two branches meet where the boom points at the
    base (the shortest cylinder) or away from it (the longest), and a cylinder cannot drive
    the boom through either; ``through`` (rad) is an angle the mechanism works through: of
    two branches in span, the one between those dead points that holds it (an A-frame's legs
    work through upright, pi/2: from an inboard base the cylinder lengthens as they tilt
    outboard, toward smaller plane angles, even when the base is above the hinge and the
    mirror branch, tilted inboard past the base, lies in span too). Raises FieldError when
    the triangle cannot close, or neither branch lies in span."""
    bx, bz = cyl.base
    rho = math.hypot(bx, bz)
    b = cyl.eye
    c = (b * b + rho * rho - length * length) / (2.0 * b * rho)
    if not -1.0 <= c <= 1.0:
        lo, hi = abs(b - rho), b + rho
        raise FieldError("cylinder.stroke", f"a cylinder of {length:.4g} m cannot reach: with this base and eye "
                                            f"its length lies in [{lo:.4g}, {hi:.4g}] m")
    phi = math.atan2(bz, bx)
    first = phi + math.acos(c)
    if span is None:
        return first
    branches = (first, phi - math.acos(c))
    if through is not None and math.sin(through - phi) < 0.0:
        branches = branches[::-1]       # ``through`` lies on the branch below the base direction
    for a in branches:
        a = math.atan2(math.sin(a), math.cos(a))
        if span[0] <= a <= span[1]:
            return a
    raise FieldError("cylinder.stroke", f"a cylinder of {length:.4g} m puts the boom / legs outside their range "
                                        f"({math.degrees(span[0]):.4g} to {math.degrees(span[1]):.4g} deg in the "
                                        f"luffing plane)")


def cylinder_lever(cyl: CylinderSpec, angle: float) -> tuple[float, float]:
    """(cylinder length m, lever arm m about the hinge) at the boom angle ``angle`` (rad,
    in the luffing plane from x toward z). The lever arm is positive when a pushing
    cylinder turns the boom toward larger angles."""
    bx, bz = cyl.base
    px, pz = cyl.eye * math.cos(angle), cyl.eye * math.sin(angle)
    dx, dz = px - bx, pz - bz
    L = math.hypot(dx, dz)
    ux, uz = dx / L, dz / L
    return L, px * uz - pz * ux


def luffing_rope_angle(rope: LuffingRopeSpec, eye: float, length: float) -> float:
    """Boom angle (rad, in the luffing plane from x toward z) at which the luffing rope from
    ``rope.gantry`` to the eye at ``eye`` along the boom has ``length``: the branch below the
    gantry's direction, on which the rope lengthens as the boom is lowered. Raises
    FieldError when the triangle cannot close."""
    gx, gz = rope.gantry
    rho = math.hypot(gx, gz)
    c = (eye * eye + rho * rho - length * length) / (2.0 * eye * rho)
    if not -1.0 <= c <= 1.0:
        lo, hi = abs(eye - rho), eye + rho
        raise FieldError("luffing_rope.length", f"a luffing rope of {length:.4g} m cannot reach: with this gantry "
                                                f"and eye its length lies in [{lo:.4g}, {hi:.4g}] m")
    return math.atan2(gz, gx) - math.acos(c)


def luffing_rope_lever(rope: LuffingRopeSpec, eye: float, angle: float) -> tuple[float, float]:
    """(rope length m, lever arm m about the hinge) at the boom angle ``angle`` (rad): the
    moment of a unit pull toward the gantry on the eye, positive toward larger angles."""
    gx, gz = rope.gantry
    px, pz = eye * math.cos(angle), eye * math.sin(angle)
    dx, dz = gx - px, gz - pz
    L = math.hypot(dx, dz)
    return L, (px * dz - pz * dx) / L


def _angle_profile(tpl, field: str, to_plane) -> tuple[float, list | None]:
    """(initial angle deg, table [[t, deg]] or None) of the luffing drive in the template's
    own convention; a stroke table is converted through the cylinder triangle, a luffing
    rope's length table through the gantry triangle (``to_plane`` maps the template angle to
    the luffing-plane angle and back)."""
    value = getattr(tpl, field)
    if value is not None:
        return _initial(value), _table(value)
    rope = getattr(tpl, "luffing_rope", None)
    if rope is not None:
        eye = rope.eye if rope.eye is not None else tpl.boom.length
        rows = []
        for i, (t, length) in enumerate(rope.length):
            try:
                a = luffing_rope_angle(rope, eye, length)
            except FieldError as exc:
                raise FieldError(f"luffing_rope.length.{i}.1", exc.reason) from None
            if not -10.0 <= math.degrees(a) <= 85.0:
                raise FieldError(f"luffing_rope.length.{i}.1", f"{length:.4g} m puts the boom at "
                                                               f"{math.degrees(a):.4g} deg, outside [-10, 85] deg")
            rows.append([float(t), math.degrees(to_plane(a, inverse=True))])
        return _initial(rows), _table(rows)
    rows = []
    # the luffing plane angles the template allows (column: the boom angle; A-frame: 90 - tilt)
    span = (math.radians(10.0), math.radians(170.0)) if tpl.type == "a-frame" else \
        (math.radians(-10.0), math.radians(85.0))
    through = math.pi / 2.0 if tpl.type == "a-frame" else None       # the legs work through upright
    for i, (t, length) in enumerate(tpl.cylinder.stroke):
        try:
            a = cylinder_angle(tpl.cylinder, length, span, through)
        except FieldError as exc:
            raise FieldError(f"cylinder.stroke.{i}.1", exc.reason) from None
        rows.append([float(t), math.degrees(to_plane(a, inverse=True))])
    return _initial(rows), _table(rows)


class _Deck:
    """The vessel's frame at t = 0, where the template places the crane: its rest position and
    heading with its motion at t = 0 (a heel, a heave), so that the crane starts as built on
    the deck. Lines and drives given in global directions at t = 0 (the boom's and legs'
    directions, drive and hinge axes, the payload under the tip) are turned with it, as the
    pedestal and stubs clamped to the deck are."""

    def __init__(self, p, R):
        self.p = np.asarray(p, float)
        self.R = np.asarray(R, float)

    def rot(self, v) -> list[float]:
        """A direction of the vessel frame, global at t = 0."""
        return [float(c) for c in self.R @ np.asarray(v, float)]

    def point(self, v) -> list[float]:
        """A point of the vessel frame, global at t = 0."""
        return [float(c) for c in self.p + self.R @ np.asarray(v, float)]


def _deck(out: dict, vname: str, vpos, heading, env) -> _Deck:
    """The vessel ``vname``'s frame at t = 0 (its motion there; level at its rest position and
    heading when the motion cannot be made: its own errors are reported by the validation)."""
    from ..vessel import make_vessel_motion
    try:
        k = make_vessel_motion(Vessel.model_validate((out.get("vessels") or {})[vname]), env).kinematics(0.0)
        return _Deck(k.p, k.R)
    except (ValidationError, ValueError, ArithmeticError, KeyError, OSError):
        c, s = math.cos(heading), math.sin(heading)
        return _Deck(vpos, [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _member_type(m: MemberSpec, stiff: float = 1.0) -> dict:
    p = m.properties()
    out = {"EA": stiff * p["EA"], "EIy": stiff * p["EI"], "EIz": stiff * p["EI"], "GJ": stiff * p["GJ"],
           "mass_per_length": p["mass_per_length"],
           "damping": {"axial_ratio": m.damping_ratio, "bending_ratio": m.damping_ratio}}
    if m.outer_diameter is not None:
        out["outer_diameter"] = m.outer_diameter
    return out


def _drive(name: str, axis, table) -> dict:
    return {"name": name, "axis": [float(c) for c in axis],
            "angle": [[t, a] for t, a in table]}


def _payload(out: dict, name: str, tpl, raw: dict, tip, rope_length: float) -> tuple[str, list]:
    """(body name, attachment point in the body frame); an inline payload hangs straight
    under the sheave."""
    if isinstance(tpl.payload, str):
        bodies = out.get("bodies") or {}
        if not isinstance(bodies, dict) or tpl.payload not in bodies:
            known = ", ".join(sorted(bodies)) if isinstance(bodies, dict) and bodies else "none defined"
            raise FieldError("payload", f"unknown body '{tpl.payload}' (bodies: {known})")
        try:
            body = Body.model_validate(bodies[tpl.payload])
        except (ValidationError, ValueError):
            body = None
        top = 0.5 * body.vertical_extent() if body is not None else 0.0
        attach = list(tpl.payload_attachment) if tpl.payload_attachment is not None else [0.0, 0.0, top]
        return tpl.payload, attach
    body = copy.deepcopy(raw["payload"])
    top = 0.5 * tpl.payload.vertical_extent()
    attach = list(tpl.payload_attachment) if tpl.payload_attachment is not None else [0.0, 0.0, top]
    generated = ()
    if body.get("position") is not None:
        _off_lead(tpl, tip, attach)
    if body.get("position") is None:
        # the attachment is in the body frame: turn it by the payload's orientation_deg (the
        # same ZYX rotation the model gives the body, rfesim.model.bodies.body_rotation) so
        # the hook point starts straight under the sheave, the rope vertical
        from ..model.bodies import body_rotation
        arm = body_rotation(tpl.payload) @ np.asarray(attach, float)
        body["position"] = [float(tip[0] - arm[0]), float(tip[1] - arm[1]), float(tip[2] - rope_length - arm[2])]
        generated = ("position",)
    bname = f"{name}_payload"
    _add(out, "bodies", bname, body, "payload", copy_of="payload", generated=generated)
    return bname, attach


OFF_LEAD_DEG = 5.0      # a rope starting further than this from the vertical under its sheave is warned


def _off_lead(tpl, tip, attach) -> None:
    """A template warning when an inline payload placed by the user hangs its rope's end more
    than ``OFF_LEAD_DEG`` off the vertical under the sheave at the start (``tip``): the lift
    begins with a side pull, and the payload swings out under the sheave as it leaves the
    deck or the water. Lifts keep the rope within a few degrees of vertical; the payload's
    default position is straight under the sheave. The column crane lift-off luffed to 38.5
    deg (55 shipped) without moving its payload starts 12 deg off lead: the rope's slack bight
    then folded through itself at 13.8 s (before the rope's axial contact; now it runs, with
    61.5 % of its steps in substeps)."""
    from ..model.bodies import body_rotation
    hook = np.asarray(tpl.payload.position, float) + body_rotation(tpl.payload) @ np.asarray(attach, float)
    tip = np.asarray(tip, float)
    aside = float(np.hypot(hook[0] - tip[0], hook[1] - tip[1]))
    drop = float(tip[2] - hook[2])
    if drop <= 0.0:
        return
    angle = math.degrees(math.atan2(aside, drop))
    if angle > OFF_LEAD_DEG:
        from .pipelay import template_warning
        template_warning("payload.position",
                         f"the rope's end on the payload starts {aside:.3g} m aside of the vertical under the "
                         f"sheave, {angle:.3g} deg off lead over its {drop:.4g} m drop: the lift begins with a side "
                         f"pull and the payload swings out under the sheave as it lifts (lifts keep the rope within "
                         f"a few degrees of vertical); leave the position out to hang the payload straight under "
                         f"the sheave, or place it there")


def _rope_and_winch(out: dict, name: str, tpl, raw: dict, parent: str, tip, vname: str, foot: str) -> None:
    rope = f"{name}_rope"
    _add(out, "line_types", f"{rope}_section", tpl.rope.line_type(), "rope")
    body, attach = _payload(out, name, tpl, raw, tip, tpl.rope.length)
    end_a = {"attach": f"{parent}:end_b", "connection": "pinned", "direction": [0.0, 0.0, -1.0]}
    if tpl.reeving == "boom":
        end_a["reeving"] = {"lead": f"{foot}:end_a"}
    elif tpl.reeving is not None:
        end_a["reeving"] = {"lead": vname, "point": [float(c) for c in tpl.reeving]}
    _add(out, "lines", rope, {
        "type": f"{rope}_section", "length": tpl.rope.length, "elements": tpl.rope.count(),
        "end_a": end_a, "end_b": {"attach": body, "position": attach}}, "rope", keys={"length": "rope.length"})
    for tname, tug in tpl.tuggers.items():
        vessel = tug.vessel if tug.vessel is not None else vname
        if vessel not in (out.get("vessels") or {}):
            known = ", ".join(sorted(out.get("vessels") or {})) or "none defined"
            raise FieldError(f"tuggers.{tname}.vessel", f"unknown vessel '{vessel}' (vessels: {known})")
        _add(out, "tuggers", f"{name}_{tname}", {
            "body": body, "vessel": vessel, "deck_point": list(tug.deck_point), "body_point": list(tug.body_point),
            "mode": copy.deepcopy(raw["tuggers"][tname]["mode"])}, f"tuggers.{tname}", copy_of=f"tuggers.{tname}",
             generated=("body",) + (() if tug.vessel is not None else ("vessel",)))
    if tpl.winch is not None:
        # the user's own winch (validated with the template, rfesim.scenario.winches.TemplateWinch) on the rope
        winch = copy.deepcopy(raw["winch"])
        winch["line"] = rope
        _add(out, "winches", f"{name}_winch", winch, "winch", copy_of="winch", generated=("line",))


def _column(out: dict, name: str, tpl: ColumnCrane, raw: dict, vname: str, deck: _Deck) -> None:
    ped, boom = f"{name}_pedestal", f"{name}_boom"
    slew0 = math.radians(_initial(tpl.slewing_deg))
    # luffing plane: x along the boom's horizontal projection, z up; the boom angle is the plane angle
    luff0_deg, luff_table = _angle_profile(tpl, "luffing_deg", lambda a, inverse=False: a)
    luff0 = math.radians(luff0_deg)
    base = list(tpl.position)
    top = [base[0], base[1], base[2] + tpl.pedestal.length]
    d_local = [math.cos(luff0) * math.cos(slew0), math.cos(luff0) * math.sin(slew0), math.sin(luff0)]
    tip_local = [top[k] + tpl.boom.length * d_local[k] for k in range(3)]
    tip = deck.point(tip_local)
    _add(out, "line_types", f"{ped}_section", _member_type(tpl.pedestal), "pedestal")
    _add(out, "line_types", f"{boom}_section", _member_type(tpl.boom), "boom")
    luffing = _drive("luffing", deck.rot([math.sin(slew0), -math.cos(slew0), 0.0]), luff_table)
    motor = tpl.slewing_motor
    if motor is None:
        _add(out, "lines", ped, {
            "type": f"{ped}_section", "length": tpl.pedestal.length, "elements": tpl.pedestal.count(),
            "end_a": {"attach": vname, "position": base, "direction": [0.0, 0.0, 1.0], "connection": "clamped"},
            "end_b": {"attach": "free"}}, "pedestal")
        drives = [_drive("slewing", deck.rot([0.0, 0.0, 1.0]), _table(tpl.slewing_deg)), luffing]
        parent = ped
    else:
        # the pedestal's top is a turret on the slewing ring, turned by the servo motor about the
        # pedestal axis (rfesim.loads.drives.motor_forces); the boom's joint keeps the luffing drive
        turret = f"{name}_turret"
        t_len = min(TURRET_LENGTH, 0.25 * tpl.pedestal.length)
        _add(out, "lines", ped, {
            "type": f"{ped}_section", "length": tpl.pedestal.length - t_len,
            "elements": max(1, tpl.pedestal.count() - 1),
            "end_a": {"attach": vname, "position": base, "direction": [0.0, 0.0, 1.0], "connection": "clamped"},
            "end_b": {"attach": "free"}}, "pedestal")
        stiffness, damping = _servo_gains(tpl, raw, luff0)
        _add(out, "lines", turret, {
            "type": f"{ped}_section", "length": t_len, "elements": 1,
            "end_a": {"attach": f"{ped}:end_b", "connection": "clamped", "direction": deck.rot([0, 0, 1]),
                      "motor": {"name": "slewing", "angle": _table(tpl.slewing_deg), "max_torque": motor.max_torque,
                                "stiffness": motor.stiffness or stiffness,
                                "damping": motor.damping if motor.damping is not None else damping}},
            "end_b": {"attach": "free"}}, "slewing_motor", origin="")
        drives = [luffing]
        parent = turret
    end_a = {"attach": f"{parent}:end_b", "connection": "clamped", "direction": deck.rot(d_local),
             "drives": drives}
    _add(out, "lines", boom, {"type": f"{boom}_section", "length": tpl.boom.length,
                              "elements": tpl.boom.count(), "end_a": end_a, "end_b": {"attach": "free"}}, "boom")
    _rope_and_winch(out, name, tpl, raw, boom, tip, vname, boom)


def _servo_gains(tpl: ColumnCrane, raw: dict, luff0: float) -> tuple[float, float]:
    """Default slewing servo gains (N*m/rad, N*m*s/rad): natural frequency SERVO_FREQUENCY,
    critically damped, on the crane's inertia about the pedestal axis (the boom as a uniform
    bar, the payload's mass at the tip, a payload given by name counted by its mass only)."""
    reach = tpl.boom.length * math.cos(luff0)
    boom_mass = tpl.boom.properties()["mass_per_length"] * tpl.boom.length
    payload_mass = tpl.payload.mass if isinstance(tpl.payload, Body) else \
        float(((raw.get("bodies") or {}).get(tpl.payload) or {}).get("mass", 0.0))
    inertia = max(boom_mass / 3.0 * reach * reach + payload_mass * reach * reach, 1.0)
    w = 2.0 * math.pi * SERVO_FREQUENCY
    return inertia * w * w, 2.0 * inertia * w


def _a_frame(out: dict, name: str, tpl: AFrame, raw: dict, vname: str, deck: _Deck) -> None:
    stub, legs, beam = f"{name}_stub", f"{name}_legs", f"{name}_crossbeam"
    ob = math.radians(tpl.outboard_deg)
    xo = [math.cos(ob), math.sin(ob), 0.0]           # outboard, vessel frame
    # luffing plane: x outboard, z up; the plane angle is 90 deg - tilt
    tilt0_deg, tilt_table = _angle_profile(tpl, "tilt_deg",
                                           lambda a, inverse=False: math.pi / 2.0 - a)
    tilt0 = math.radians(tilt0_deg)
    d_local = [math.sin(tilt0) * xo[0], math.sin(tilt0) * xo[1], math.cos(tilt0)]
    # luffing axis: turning the legs outboard (tilt up) is a rotation about z x outboard
    across = [-xo[1], xo[0], 0.0]
    axis = deck.rot(across)
    p = tpl.legs.properties()
    damping = {"axial_ratio": tpl.legs.damping_ratio, "bending_ratio": tpl.legs.damping_ratio}
    if tpl.crossbeam is not None:
        _a_frame_portal(out, name, tpl, raw, vname, deck, xo, across, axis, d_local, tilt0_deg, tilt_table)
        return
    hinge = list(tpl.position)
    # the sheave at the legs' top, legs.length from the hinge (as the portal's): the top
    # beam_len of it is the crossbeam's short stiff line carrying its mass, the legs' line the
    # rest (it was legs.length long with the crossbeam beyond, the sheave 0.5 m too far out)
    beam_len = min(0.5, 0.1 * tpl.legs.length)
    legs_len = tpl.legs.length - beam_len
    tip_local = [hinge[k] + tpl.legs.length * d_local[k] for k in range(3)]
    tip = deck.point(tip_local)
    # the two legs as one line: twice the axial and in-plane bending stiffness and mass; out of
    # plane the portal is stiffer (the legs' parallel-axis term at half the spacing)
    EI_out = 2.0 * p["EI"] + 2.0 * p["EA"] * (0.5 * tpl.leg_spacing) ** 2
    leg_type = {"EA": 2.0 * p["EA"], "EIy": 2.0 * p["EI"], "EIz": EI_out, "GJ": 2.0 * p["GJ"],
                "mass_per_length": 2.0 * p["mass_per_length"], "damping": damping}
    stub_type = {k: (10.0 * v if k in ("EA", "EIy", "EIz", "GJ") else v) for k, v in leg_type.items()}
    stub_type["mass_per_length"] = 1.0
    # the crossbeam's line stands for the legs' top too: their mass over it, plus the crossbeam's
    beam_type = dict(stub_type, mass_per_length=max(1.0, tpl.crossbeam_mass / beam_len + leg_type["mass_per_length"]))
    _add(out, "line_types", f"{legs}_section", leg_type, "legs")
    _add(out, "line_types", f"{stub}_section", stub_type, "legs")
    _add(out, "line_types", f"{beam}_section", beam_type, "crossbeam_mass", origin="")
    _a_frame_leg(out, name, tpl, vname, deck, stub, legs, hinge, xo, axis, d_local, tilt0_deg, tilt_table,
                 1.0, f"{name}_cylinder", length=legs_len, top=beam)
    _add(out, "lines", beam, {"type": f"{beam}_section", "length": beam_len, "elements": 1,
                              "end_a": {"attach": f"{legs}:end_b", "connection": "clamped",
                                        "direction": deck.rot(d_local)},
                              "end_b": {"attach": "free"}}, "crossbeam_mass", origin="")
    _rope_and_winch(out, name, tpl, raw, beam, tip, vname, legs)


def _a_frame_leg(out: dict, name: str, tpl: AFrame, vname: str, deck: _Deck, stub: str, legs: str, hinge: list,
                 xo: list, axis: list, d_local: list, tilt0_deg: float, tilt_table, share: float,
                 cylinder: str, length: float | None = None, top: str | None = None) -> None:
    """A deck stub under the hinge and a leg line on it, luffed by its joint's drive (stroke or
    tilt table) or hinged and pushed by a force tugger (``cylinder``) for ``share`` of the
    cylinders. ``length``: the leg line's (default legs.length); an eye beyond it sits on the
    line ``top`` clamped on the leg's top (the equivalent frame's crossbeam)."""
    length = float(tpl.legs.length if length is None else length)
    tilt0 = math.radians(tilt0_deg)
    stub_len = 1.0
    _add(out, "lines", stub, {
        "type": f"{name}_stub_section", "length": stub_len, "elements": 1,
        "end_a": {"attach": vname, "position": [hinge[0], hinge[1], hinge[2] - stub_len],
                  "direction": [0.0, 0.0, 1.0], "connection": "clamped"},
        "end_b": {"attach": "free"}}, "legs")
    end_a = {"attach": f"{stub}:end_b", "connection": "clamped", "direction": deck.rot(d_local)}
    cyl = tpl.cylinder
    if cyl is not None and cyl.force is not None:
        # force-driven: the legs turn freely about the luffing axis (a hinged join) and the
        # cylinders push between their base on the deck and their eye on the legs
        end_a["hinge_axis"] = axis
        bx, bz = cyl.base
        deck = [hinge[0] + bx * xo[0], hinge[1] + bx * xo[1], hinge[2] + bz]
        rows = [[0.0, float(cyl.force)]] if isinstance(cyl.force, (int, float)) else cyl.force
        if cyl.eye > tpl.legs.length:
            raise FieldError("cylinder.eye", f"{cyl.eye} m is beyond the legs' {tpl.legs.length} m")
        mode = {"kind": "force", "force": [[float(t), share * cyl.count * float(f)] for t, f in rows]}
        start = cylinder_lever(cyl, math.pi / 2.0 - tilt0)[0]
        if cyl.length_min is not None and cyl.length_max is not None and not cyl.length_min < cyl.length_max:
            raise FieldError("cylinder.length_max", f"{cyl.length_max} m is not longer than length_min "
                                                    f"{cyl.length_min} m")
        for field, value, beyond in (("length_min", cyl.length_min, start < (cyl.length_min or 0.0)),
                                     ("length_max", cyl.length_max, cyl.length_max is not None
                                      and start > cyl.length_max)):
            if value is not None:
                if beyond:
                    raise FieldError(f"cylinder.{field}", f"the starting tilt {tilt0_deg:g} deg puts the cylinder at "
                                                          f"{start:.4g} m, beyond its {field} {value} m")
                mode[field] = float(value)
                mode["stop_stiffness"] = share * cyl.count * cyl.stop_stiffness
        on, at = (legs, cyl.eye) if cyl.eye <= length or top is None else (top, cyl.eye - length)
        _add(out, "tuggers", cylinder, {
            "line": on, "at": at, "vessel": vname, "deck_point": deck, "mode": mode}, "cylinder")
    else:
        end_a["drives"] = [_drive("luffing", axis, tilt_table)]
    _add(out, "lines", legs, {"type": f"{name}_legs_section", "length": length,
                              "elements": tpl.legs.count(), "end_a": end_a, "end_b": {"attach": "free"}}, "legs")


def _a_frame_portal(out: dict, name: str, tpl: AFrame, raw: dict, vname: str, deck: _Deck, xo: list,
                    across: list, axis: list, d_local: list, tilt0_deg: float, tilt_table) -> None:
    """The A-frame as the closed portal it is: two legs on their own hinges ``leg_spacing``
    apart, each with half the cylinders, and the crossbeam in two halves from the legs' tops to
    mid-span, the second closing onto the first (a closing join, rfesim.scenario.joins); the
    rope hangs from mid-span (the sheave). Lines: ``c_stub``, ``c_legs``, ``c_crossbeam`` (leg
    1 side, the sheave at its end B) and ``c_stub_2``, ``c_legs_2``, ``c_crossbeam_2``."""
    half = 0.5 * tpl.leg_spacing
    p = tpl.legs.properties()
    damping = {"axial_ratio": tpl.legs.damping_ratio, "bending_ratio": tpl.legs.damping_ratio}
    leg_type = {"EA": p["EA"], "EIy": p["EI"], "EIz": p["EI"], "GJ": p["GJ"],
                "mass_per_length": p["mass_per_length"], "damping": damping}
    stub_type = {k: (10.0 * v if k in ("EA", "EIy", "EIz", "GJ") else v) for k, v in leg_type.items()}
    stub_type["mass_per_length"] = 1.0
    b = tpl.crossbeam.properties()
    beam_type = {"EA": b["EA"], "EIy": b["EI"], "EIz": b["EI"], "GJ": b["GJ"],
                 "mass_per_length": b["mass_per_length"] + tpl.crossbeam_mass / tpl.leg_spacing,
                 "damping": {"axial_ratio": tpl.crossbeam.damping_ratio,
                             "bending_ratio": tpl.crossbeam.damping_ratio}}
    _add(out, "line_types", f"{name}_legs_section", leg_type, "legs")
    _add(out, "line_types", f"{name}_stub_section", stub_type, "legs")
    _add(out, "line_types", f"{name}_crossbeam_section", beam_type, "crossbeam")
    centre = list(tpl.position)
    mid_local = [centre[k] + tpl.legs.length * d_local[k] for k in range(3)]
    nbeam = max(1, int(math.ceil(tpl.crossbeam.count() / 2.0)))
    for j, (side, suffix) in enumerate(((-1.0, ""), (1.0, "_2"))):
        hinge = [centre[k] + side * half * across[k] for k in range(3)]
        legs = f"{name}_legs{suffix}"
        _a_frame_leg(out, name, tpl, vname, deck, f"{name}_stub{suffix}", legs, hinge, xo, axis, d_local,
                     tilt0_deg, tilt_table, 0.5, f"{name}_cylinder{suffix}")
        beam = {"type": f"{name}_crossbeam_section", "length": half, "elements": nbeam,
                "end_a": {"attach": f"{legs}:end_b", "connection": "clamped",
                          "direction": deck.rot([-side * c for c in across])},
                "end_b": {"attach": "free"}}
        if j == 1:
            beam["end_b"] = {"attach": f"{name}_crossbeam:end_b", "connection": "clamped"}
        _add(out, "lines", f"{name}_crossbeam{suffix}", beam, "crossbeam")
    _rope_and_winch(out, name, tpl, raw, f"{name}_crossbeam", deck.point(mid_local), vname,
                    f"{name}_legs")


def expand(data: dict) -> dict:
    """The scenario dict with its ``cranes`` templates expanded into ordinary sections
    (a new dict without ``cranes``; the input itself when it has none). Raises
    ScenarioError naming the template field (``cranes.crane.boom.length: ...``)."""
    return expand_templates(data, "cranes", _TEMPLATES, _expand_one)


def _expand_one(out: dict, name: str, tpl, raw: dict, env) -> None:
    if any(c in name for c in "/:\\") or name.strip() != name:
        raise FieldError("", f"bad crane name {name!r}: no '/', ':' or '\\', no outer spaces")
    vname, vpos, heading = _vessel_pose(out, name, tpl, raw)
    deck = _deck(out, vname, vpos, heading, env)
    (_column if tpl.type == "column" else _a_frame)(out, name, tpl, raw, vname, deck)
    if not out.get("name"):
        out["name"] = f"crane: {name} ({tpl.type})"
