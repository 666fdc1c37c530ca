"""Pipelay templates (top-level ``pipelay``): S-lay, J-lay and reel-lay set-ups that expand
into ordinary scenario sections before the rest of the scenario is validated.

    "pipelay": {"lay1": {"method": "s-lay", "vessel": "barge", "tension": 150e3,
                         "pipe": {"outer_diameter": 0.3239, "wall_thickness": 0.0159, "grade": "X65"},
                         "stinger": {"radius": 100.0}}}

expands (:func:`expand`) into a vessel (when given inline), a line type (the pipe), the
line (end A free at the tensioner's entry, end B pinned on the seabed ``laid_length``
beyond the natural-catenary touchdown), its supports (S-lay: tensioner and stinger; J-lay:
the collar, a tensioner-kind track along the tower; reel-lay: reel, aligner, straightener and
tensioner on the ramp) and, without one, a seabed. The suspended pipe follows the natural
catenary with the horizontal lay tension H from its lift-off point (stinger tip, tower or
ramp exit) to the touchdown point (``lay_catenary``: submerged weight below the still water
surface, the weight in air above it; ``rfesim.catenary.natural_catenary`` when the lift-off
point is under water), so statics
starts next to its solution. A template that gives ``tension`` sets it as the track's
``horizontal_tension``: statics pays the pipe out (or hauls it in) through the tensioner
or collar (and turns a reel-lay reel with it) until the pipe carries H to its pinned end B
(rfesim.solvers.lay_statics); the bending stiffness leaves a little more pipe in the span
than the catenary has, so without it H would settle a few per cent low (the S-lay template:
143.6 kN for 150 kN; reel-lay 53.3 kN for 54.9 kN). A J-lay or reel-lay template given the
tower or ramp angle holds the pipe where the catenary puts it, and H settles where that
length puts it (scenarios/j_lay.json: 40.1 kN, 1.7 % below the 40.8 kN
of the 85 deg catenary). Geometry is in the vessel frame; the
pipe leaves along the vessel's x axis (turn the vessel with ``heading_deg`` to lay elsewhere).

Names made: the line ``line`` (default: the template's name), line type ``<line>_pipe``,
vessel ``<name>_vessel`` (inline vessels), supports ``<line>_tensioner``, ``<line>_stinger``,
``<line>_collar``, ``<line>_reel``, ``<line>_aligner``, ``<line>_straightener``. A name
that is already taken is refused. Units SI, angles in degrees.
"""
from __future__ import annotations

import copy
import math
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field as dc_field
from typing import Annotated, Iterator, Literal, Union

from pydantic import Field, TypeAdapter, ValidationError, model_validator

from .schema import (COEFFICIENT_LIMIT, DAMPING_LIMIT, DENSITY_LIMIT, FORCE_LIMIT, MAX_COEFFICIENT, MAX_DAMPING,
                     MAX_DENSITY, MAX_FORCE, MAX_MODULUS, MAX_STIFFNESS, MIN_SEABED_STIFFNESS, MODULUS_LIMIT,
                     SEABED_STIFFNESS_FLOOR, STIFFNESS_LIMIT, FieldError, PayoutConstantTension, PayoutTable, Vector3,
                     Vessel, _Strict, _units, DENSITY_FLOOR, MIN_DENSITY, MIN_MODULUS, MODULUS_FLOOR)

# API 5L specified minimum yield strength (Pa)
GRADE_YIELD = {"X52": 359e6, "X56": 386e6, "X60": 414e6, "X65": 448e6, "X70": 483e6, "X80": 552e6}
STEEL_E = 2.07e11
STEEL_DENSITY = 7850.0

# Lower bounds of the template's sizes, with the reasons given when a value is below them (the
# ``floor`` of _units): a value under them would reach the expanded scenario (its line, line
# type or seabed) and be refused there, under a name the user never wrote.
MIN_WALL_THICKNESS = 1.0e-3      # m
WALL_THICKNESS_FLOOR = ("a millimetre: thinner than the wall of any steel pipe or tube, whose section would have no "
                        "stiffness or mass (check the units, metres)")
MIN_ELEMENT_LENGTH = 0.01        # m
ELEMENT_LENGTH_FLOOR = ("a centimetre: a pipe hundreds of metres long in elements shorter than that has more than "
                        "the 100000 elements a line may have, and a far smaller time step (check the units, metres)")
MAX_LINE_ELEMENTS = 100000       # as Line.elements


class PipeSpec(_Strict):
    """The pipe: steel geometry and grade, optional coating and contents, sea-load coefficients."""

    outer_diameter: float = _units("m", "Steel outer diameter", gt=0.0, le=10.0,
                                   limit="pipelines are at most about 1.5 m (60 in) across (check the units, "
                                         "metres)")
    wall_thickness: float = _units("m", "Steel wall thickness, less than outer_diameter/2", ge=MIN_WALL_THICKNESS,
                                   floor=WALL_THICKNESS_FLOOR)
    grade: Literal["X52", "X56", "X60", "X65", "X70", "X80"] = Field(
        "X65", description="API 5L steel grade: the yield stress of an elastoplastic pipe (SMYS)")
    material: Literal["elastic", "elastoplastic"] | None = Field(
        None, description="Steel law: elastic, or elastoplastic (bilinear from the grade's yield stress). "
                          "Default: elastoplastic for reel-lay, elastic otherwise")
    hardening_ratio: float = _units("1", "Bilinear hardening E_t/E of an elastoplastic pipe", default=0.01,
                                    ge=0.0, lt=1.0)
    youngs_modulus: float = _units("Pa", "Young's modulus of the steel", default=STEEL_E, ge=MIN_MODULUS,
                                   le=MAX_MODULUS, limit=MODULUS_LIMIT, floor=MODULUS_FLOOR)
    density: float = _units("kg/m^3", "Steel density", default=STEEL_DENSITY, ge=MIN_DENSITY,
                            le=MAX_DENSITY, limit=DENSITY_LIMIT, floor=DENSITY_FLOOR)
    coating_thickness: float = _units("m", "Coating thickness (concrete, insulation); the hydrodynamic and "
                                      "contact diameter is outer_diameter + 2 coating_thickness", default=0.0,
                                      ge=0.0)
    coating_density: float | None = _units("kg/m^3", "Coating density (needed with a coating)", default=None,
                                           gt=0.0, le=MAX_DENSITY, limit=DENSITY_LIMIT)
    contents_density: float = _units("kg/m^3", "Density of the pipe contents", default=0.0, ge=0.0,
                                     le=MAX_DENSITY, limit=DENSITY_LIMIT)
    drag_normal: float = _units("1", "Normal drag coefficient", default=1.0, ge=0.0, le=MAX_COEFFICIENT,
                                limit=COEFFICIENT_LIMIT)
    drag_axial: float = _units("1", "Axial drag coefficient", default=0.008, ge=0.0, le=MAX_COEFFICIENT,
                               limit=COEFFICIENT_LIMIT)
    added_mass_normal: float = _units("1", "Normal added-mass coefficient", default=1.0, ge=0.0, le=MAX_COEFFICIENT,
                                      limit=COEFFICIENT_LIMIT)
    damping_ratio: float = _units("1", "Structural damping ratio of the axial and bending element modes",
                                  default=0.05, ge=0.0, le=2.0)

    @model_validator(mode="after")
    def _geometry(self):
        if self.wall_thickness >= 0.5 * self.outer_diameter:
            raise FieldError("wall_thickness", f"{self.wall_thickness} m is not less than the outer radius "
                                               f"{0.5 * self.outer_diameter} m")
        if self.coating_thickness > 0.0 and self.coating_density is None:
            raise FieldError("coating_density", "a coating (coating_thickness > 0) needs its density")
        return self


class TensionerSpec(_Strict):
    """The tensioner (S-lay, reel-lay) or the hang-off collar (J-lay): a straight track that
    holds the pipe (rfesim.loads.tensioner)."""

    length: float | None = _units("m", "Track length (default: 10 m, at least three elements). S-lay: the "
                                  "expanded tensioner's track runs half an element longer, past the exit, because "
                                  "its pads let go of the pipe over the last element", default=None, gt=0.0)
    capacity: float | None = _units("N", "Largest axial force the track holds (default: three times the top "
                                    "tension of the natural catenary, at least 1 MN)", default=None, gt=0.0,
                                    le=MAX_FORCE, limit=FORCE_LIMIT)
    lateral_stiffness: float = _units("N/m/m", "Pad stiffness holding the pipe on the axis", default=1.0e7,
                                      gt=0.0, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    grip_stiffness: float = _units("N/m/m", "Axial grip stiffness", default=1.0e7, gt=0.0,
                                   le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    payout: Annotated[Union[PayoutTable, PayoutConstantTension], Field(discriminator="kind")] | None = Field(
        None, description="Payout: a table, or the constant-tension characteristic (default: holds the pipe)")


class StingerSpec(_Strict):
    """S-lay stinger: an arc of V-roller stations from the vessel's deck line."""

    radius: float = _units("m", "Radius of the arc of roller stations", default=100.0, gt=0.0, le=1.0e4,
                           limit="a stinger arc is at most a few hundred metres in radius (check the units, "
                                 "metres)")
    length: float | None = _units("m", "Arc length (default: the tip angle equals the catenary's departure "
                                  "angle)", default=None, gt=0.0)
    start: Vector3 = _units("m", "First roller station (V bottom), vessel frame", default=[0.0, 0.0, 2.0])
    spacing: float = _units("m", "Distance between roller stations", default=6.0, gt=0.0)
    roller_radius: float = _units("m", "Roller radius", default=0.15, ge=0.0)
    roller_width: float = _units("m", "Contact length of each roller", default=0.6, gt=0.0)
    v_angle_deg: float = _units("deg", "Rise of each half of the V-rollers (0: flat rollers)", default=30.0,
                                ge=0.0, lt=80.0)
    stiffness: float = _units("N/m", "Contact stiffness of each roller", default=1.0e7, gt=0.0,
                              le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    damping: float = _units("N*s/m", "Contact damping of each roller", default=1.0e4, ge=0.0,
                            le=MAX_DAMPING, limit=DAMPING_LIMIT)
    friction: float = _units("1", "Roller friction across the pipe", default=0.1, ge=0.0, le=10.0)


class _Template(_Strict):
    """What the pipelay templates share: the pipe, its vessel, the lay tension, the laid
    length on the seabed and the element size."""

    line: str | None = Field(None, description="Name of the pipe line (default: the template's name)",
                             min_length=1, max_length=200)
    vessel: Union[str, Vessel] = Field(default_factory=Vessel, description="A vessel name of `vessels`, or a "
                                       "vessel (position, heading_deg, motion) made as <name>_vessel")
    pipe: PipeSpec
    tension: float | None = _units("N", "Horizontal lay tension H of the suspended pipe (the bottom tension): the "
                                   "start shape's catenary has it, and for s-lay and j-lay statics pays the pipe "
                                   "out or hauls it in through the tensioner (collar) until the pipe carries it "
                                   "to its pinned end B (the track's horizontal_tension; reel-lay turns the "
                                   "reel with it); greater than 0",
                                   default=None, le=1.0e9,
                                   limit="beyond any lay vessel: the largest tensioners hold about 20 MN "
                                         "(check the units, newtons)")
    laid_length: float = _units("m", "Pipe on the seabed beyond the touchdown point, to the pinned end B",
                                default=50.0, gt=0.0, le=1.0e5)
    element_length: float | None = _units("m", "Target element length (default: set by the method: s-lay a third "
                                          "of the stinger's station spacing, at most 4 m; j-lay a sixth of the "
                                          "bending boundary layer below the collar, sqrt(EI/T_top), at most 10 m; "
                                          "reel-lay 2 m; or give elements). An s-lay element longer than half the "
                                          "station spacing, a j-lay one longer than half that boundary layer, or a "
                                          "reel-lay one longer than a ninth of the aligner radius (the default 2 m "
                                          "on a 9 m aligner too) gets a warning: the roller reactions scatter, the "
                                          "hang-off moment comes out low, the overbend strain high", default=None,
                                          ge=MIN_ELEMENT_LENGTH,
                                          floor=ELEMENT_LENGTH_FLOOR)
    elements: int | None = _units("1", "Number of elements of the line (instead of element_length)", default=None,
                                  ge=4, le=100000)
    seabed_stiffness: float = _units("N/m/m", "Seabed normal stiffness, used when the scene has no seabed",
                                     default=1.0e6, ge=MIN_SEABED_STIFFNESS, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT,
                                     floor=SEABED_STIFFNESS_FLOOR)
    tensioner: TensionerSpec = Field(default_factory=TensionerSpec)

    @model_validator(mode="after")
    def _common(self):
        if self.tension is not None and not self.tension > 0.0:
            raise FieldError("tension", f"must be > 0 N, got {self.tension}")
        if self.element_length is not None and self.elements is not None:
            raise FieldError("elements", "give elements or element_length, not both")
        return self


class SLayTemplate(_Template):
    """S-lay: tensioner on deck, then over a stinger of rollers, down to the seabed."""

    method: Literal["s-lay"]
    stinger: StingerSpec = Field(default_factory=StingerSpec)

    @model_validator(mode="after")
    def _tension(self):
        if self.tension is None:
            raise FieldError("tension", "required for s-lay: the horizontal lay tension H (N)")
        return self


class JLayTemplate(_Template):
    """J-lay: the pipe hangs from a collar on a steep tower and leaves it at the tower angle."""

    method: Literal["j-lay"]
    tower_angle_deg: float | None = _units("deg", "Tower angle from the horizontal, at least 70 and below 90 (a "
                                           "vertical departure needs zero horizontal tension); default: the "
                                           "catenary's departure angle for the given tension. Given the angle, "
                                           "the collar holds the pipe where the catenary of that angle puts it "
                                           "and statics settles H where that length puts it (a little "
                                           "below w h cos/(1 - cos): the bending stiffness)",
                                           default=None)
    exit: Vector3 = _units("m", "Tower exit (the foot of the collar, where the pipe leaves), vessel frame",
                           default=[0.0, 0.0, 0.0])

    @model_validator(mode="after")
    def _angle(self):
        if self.tower_angle_deg is not None and self.tension is not None:
            raise FieldError("tension", "j-lay takes the tower angle or the tension, not both: the catenary that "
                                        "leaves the tower at its angle fixes the tension")
        if self.tower_angle_deg is None and self.tension is None:
            raise FieldError("tower_angle_deg", "give the tower angle (70 to 90 deg) or the lay tension")
        if self.tower_angle_deg is not None and not 70.0 <= self.tower_angle_deg < 90.0:
            raise FieldError("tower_angle_deg", f"must be in [70, 90) deg, got {self.tower_angle_deg} (a vertical "
                                                f"departure needs zero horizontal tension)")
        return self


class ReelSpec(_Strict):
    """Reel-lay reel (drum) and ramp."""

    radius: float = _units("m", "Drum (hub) radius the pipe is spooled on; the reel stands behind the aligner, "
                           "the pipe leaving its top horizontally", default=8.0, gt=0.0)
    back_tension: float | None = _units("N", "Back tension the reel holds on the pipe at the start (statics "
                                        "turns the drum until it does). Default: 10 % of the catenary's top "
                                        "tension", default=None, gt=0.0, le=MAX_FORCE, limit=FORCE_LIMIT)
    grip_stiffness: float = _units("N/m/m", "Tangential stiffness per unit length with which the drum holds the "
                                   "pipe: the compliance of the reel drive (hydraulic motors, torque control), "
                                   "much softer than the steel pipe so that the reel and the tensioner, both "
                                   "paying out by the same law, do not fight over millimetres of path length",
                                   default=1.0e5, gt=0.0, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    stored_length: float | None = _units("m", "Pipe wrapped on the drum at the start (from end A to the take-off "
                                         "point; the template's drum holds at most half a turn, less one element). "
                                         "Default: the path from the take-off point to the straightener exit "
                                         "plus the largest length the payout table pays out plus two elements "
                                         "(so that reeled pipe reaches past the straightener once that path is "
                                         "paid out, and the reel never empties), at least a quarter turn and at "
                                         "most half a turn less one element (the cap can leave the reeled pipe "
                                         "short of the straightener at the end of the payout); statics starts with "
                                         "end A anywhere on that half turn (checked for radii 8 to 20 m)",
                                         default=None, gt=0.0)


class ReelLayTemplate(_Template):
    """Reel-lay: from the reel over the aligner, through the straightener and the tensioner
    on the ramp, leaving at the ramp angle."""

    method: Literal["reel-lay"]
    ramp_angle_deg: float | None = _units("deg", "Ramp angle from the horizontal, at least 20 and below 90; "
                                                 "default: the catenary's departure angle for the given tension",
                                          default=None)
    exit: Vector3 = _units("m", "Ramp exit (the foot of the tensioner), vessel frame", default=[0.0, 0.0, 0.0])
    reel: ReelSpec = Field(default_factory=ReelSpec)
    aligner_radius: float = _units("m", "Radius of the aligner wheel arc at the top of the ramp", default=9.0,
                                   gt=0.0)
    straightener_offset: float = _units("m", "Set of the straightener's middle roller from the line of its two "
                                        "outer rollers (3 m apart on either side of it), towards the reel and "
                                        "aligner centres (reverse bending); negative: away from them. The roller "
                                        "line alone already bends the pipe coming off the aligner back past "
                                        "straight (at 0 the template's pipe leaves reversed, by 0.002-0.020 1/m "
                                        "with 1 m elements); moving the offset by d changes the residual "
                                        "curvature by -3 d / pitch^2 (1/3 1/m per m): a run warns "
                                        "when the pipe through the straightener keeps more than 0.005 1/m, with "
                                        "the offset that would cancel it (docs/theory.md, 'Straightener offset')",
                                        default=0.0)

    @model_validator(mode="after")
    def _angle(self):
        if self.ramp_angle_deg is not None and self.tension is not None:
            raise FieldError("tension", "reel-lay takes the ramp angle or the tension, not both")
        if self.ramp_angle_deg is None and self.tension is None:
            raise FieldError("ramp_angle_deg", "give the ramp angle (20 to 90 deg) or the lay tension")
        if self.ramp_angle_deg is not None and not 20.0 <= self.ramp_angle_deg < 90.0:
            raise FieldError("ramp_angle_deg", f"must be in [20, 90) deg, got {self.ramp_angle_deg}")
        return self


PipelayTemplate = Annotated[Union[SLayTemplate, JLayTemplate, ReelLayTemplate], Field(discriminator="method")]

_TEMPLATES = TypeAdapter(dict[str, PipelayTemplate])

DEFAULT_ELEMENT_LENGTH = {"s-lay": 4.0, "j-lay": 10.0, "reel-lay": 2.0}
# S-lay: the default element is at most this fraction of the stinger's station spacing (_s_lay)
STINGER_ELEMENTS_PER_SPACING = 3.0
# J-lay: the default element is at most this fraction of the bending boundary layer below the
# collar, sqrt(EI/T_top) (_j_lay): 1.5 m in scenarios/j_lay.json
HANG_OFF_ELEMENT_FRACTION = 1.0 / 6.0
# Reel-lay: elements longer than this fraction of the aligner radius get a warning (_reel_lay).
# The peak curvature at the aligner exit (the overbend strain) converges from above with the
# element length l: scenarios/reel_lay.json (aligner radius 9 m) 0.1356, 0.1285, 0.1249 and
# 0.1250 1/m at l = 2, 1, 0.5 and 0.25 m, 8.5 %, 2.8 %, -0.1 % off; l <= R/9 keeps it within
# about 3 %, and R/18 within 0.1 %
ALIGNER_COARSE_FRACTION = 1.0 / 9.0
ALIGNER_ELEMENT_FRACTION = 1.0 / 18.0
MAX_STINGER_STATIONS = 10000        # as the stinger support (rfesim.scenario.schema.StingerSupport)


# --------------------------------------------------------------------------- expansion

def expand(data: dict) -> dict:
    """The scenario dict with its ``pipelay`` templates expanded into ordinary sections.

    Returns a new dict (the input is not modified) without the ``pipelay`` key, or the
    input itself when it has no templates. Raises ScenarioError naming the template field
    (``pipelay.lay1.tension: ...``) for bad templates or names that clash. Deterministic:
    the same input gives the same output."""
    return expand_templates(data, "pipelay", _TEMPLATES, _expand_one)


def expand_templates(data: dict, key: str, adapter: TypeAdapter, expand_one) -> dict:
    """``data`` with its top-level map ``key`` of templates (validated by ``adapter``)
    expanded by ``expand_one(out, name, template, raw_template, environment)``, which adds
    ordinary sections to ``out`` and raises FieldError for a bad template; the errors of all
    templates are raised together as a ScenarioError prefixed ``key.name``. Shared by the
    pipelay and crane templates."""
    from ..errors import ScenarioError
    if not isinstance(data, dict) or key not in data:
        return data
    raw = data.get(key)
    if raw is None or raw == {}:
        out = dict(data)
        out.pop(key)
        return out
    from .load import arithmetic_error
    try:
        templates = adapter.validate_python(raw)
    except ValidationError as exc:
        from .load import validation_errors
        raise ScenarioError(validation_errors(exc, prefix=(key,))) from None
    except ArithmeticError as exc:
        raise ScenarioError([arithmetic_error(exc, key, ((key,), raw))]) from None
    env = _environment(data)
    out = copy.deepcopy(data)
    del out[key]
    if env is None:
        return out                 # the environment's own errors are reported by the validation
    errors: list[tuple[str, str]] = []
    for name, tpl in templates.items():
        token = _CURRENT.set(f"{key}.{name}")
        try:
            expand_one(out, name, tpl, raw[name], env)
        except FieldError as exc:
            errors.append((f"{key}.{name}.{exc.field}" if exc.field else f"{key}.{name}", exc.reason))
        except ScenarioError:
            raise
        except (ArithmeticError, ValueError) as exc:
            # a safety net: arithmetic on absurd numbers (an overflow, a root finder without a
            # root) names the template and the number far out of range, never a traceback
            errors.append(arithmetic_error(exc, f"{key}.{name}", ((key, name), raw[name]),
                                           (("environment",), data.get("environment"))))
        finally:
            _CURRENT.reset(token)
    if errors:
        raise ScenarioError(errors)
    return out


def _environment(data: dict):
    from .schema import Environment
    try:
        return Environment.model_validate(data.get("environment") or {})
    except (ValidationError, ValueError, ArithmeticError):
        return None


def _add(out: dict, group: str, key: str, value: dict, field: str, *, origin: str | None = None,
         copy_of: str | None = None, generated: tuple[str, ...] = (), keys: dict | None = None) -> None:
    """out[group][key] = value, refusing a name that is taken (the error names the template's
    ``field``). The section's origin is recorded (``record_origin``): the template field it
    stands for (``origin``, default ``field``; "" for the template as a whole) and, when
    ``value`` is a copy of the user's own entry at the template's ``copy_of``, that field, less
    the keys ``generated`` by the expansion; ``keys`` maps single keys of ``value`` to the
    template fields they are (``elements`` -> ``elements``: a value for the made key goes there)."""
    section = out.setdefault(group, {})
    if not isinstance(section, dict):
        raise FieldError(field, f"cannot add '{key}': {group} is not a mapping")
    if key in section:
        raise FieldError(field, f"the name '{key}' is already used in {group}: rename the template's "
                                f"{'line' if group == 'lines' else 'object'} (or the existing one)")
    section[key] = value
    record_origin(f"{group}.{key}", field if origin is None else origin, copy_of, generated, keys)


# --------------------------------------------------------------------------- origins of the expanded sections

@dataclass(frozen=True)
class Origin:
    """Where a section of the expanded scenario came from: its ``template`` (``cranes.crane``),
    the template ``field`` it stands for (``boom``; "" for the template as a whole), and when it
    is a copy of the user's own entry, that entry's field (``copy_of``: ``winch``) less the keys
    the expansion wrote itself (``generated``); ``keys`` maps single keys of the section to the
    template fields they copy (``normal_stiffness`` -> ``seabed_stiffness``)."""

    template: str
    field: str = ""
    copy_of: str | None = None
    generated: tuple[str, ...] = ()
    keys: dict = dc_field(default_factory=dict)


_CURRENT: ContextVar[str | None] = ContextVar("rfesim_template", default=None)
_ORIGINS: ContextVar[dict | None] = ContextVar("rfesim_template_origins", default=None)
_WARNINGS: ContextVar[list | None] = ContextVar("rfesim_template_warnings", default=None)


@contextmanager
def recording_warnings() -> Iterator[list]:
    """Collect the warnings of the templates expanded within (``template_warning``): texts
    that name the template field; rfesim.scenario.load keeps them on the Scenario
    (``_template_warnings``), and a run adds them to its statics warnings (rfesim.api)."""
    warnings: list = []
    token = _WARNINGS.set(warnings)
    try:
        yield warnings
    finally:
        _WARNINGS.reset(token)


def template_warning(field: str, text: str) -> None:
    """Record a warning about ``field`` of the template being expanded (a no-op outside
    ``recording_warnings``): "<template>.<field>: <text>"."""
    warnings, template = _WARNINGS.get(), _CURRENT.get()
    if warnings is not None:
        where = f"{template}.{field}" if template else field
        warnings.append(f"{where}: {text}")


@contextmanager
def recording_origins() -> Iterator[dict]:
    """Record the origin of every section the templates expanded within (a map of expanded
    path, e.g. ``winches.crane_winch``, to its Origin), for ``template_path``."""
    origins: dict = {}
    token = _ORIGINS.set(origins)
    try:
        yield origins
    finally:
        _ORIGINS.reset(token)


def record_origin(path: str, field: str = "", copy_of: str | None = None, generated: tuple[str, ...] = (),
                  keys: dict | None = None) -> None:
    """Record that the expanded section at ``path`` came from the template being expanded
    (a no-op outside ``recording_origins`` or a template's expansion)."""
    origins, template = _ORIGINS.get(), _CURRENT.get()
    if origins is not None and template is not None:
        origins[path] = Origin(template, field, copy_of, tuple(generated), dict(keys or {}))


def user_field(sc, path: str) -> str:
    """``path`` of the expanded scenario ``sc`` as the user wrote it (``template_path`` with the
    scenario's recorded template origins; the path itself without templates)."""
    origins = getattr(sc, "_origins", None) or {}
    return template_path(path, origins) if origins else path


def template_path(path: str, origins: dict) -> str:
    """The field the user wrote for an error at ``path`` of the expanded scenario: in a copy
    of the user's own entry, its path in the template (``winches.crane_winch.mode.rows.1`` ->
    ``cranes.crane.winch.mode.rows.1``); elsewhere in a generated section, the template field
    it came from with the expanded path (``cranes.crane.boom (expanded as
    lines.crane_boom.length)``); outside the generated sections, ``path`` itself."""
    best = max((p for p in origins if path == p or path.startswith(p + ".")), key=len, default=None)
    if best is None:
        return path
    o = origins[best]
    rest = path[len(best) + 1:]
    first = rest.split(".", 1)[0]
    if first and first in o.keys:
        return f"{o.template}.{o.keys[first]}{rest[len(first):]}"
    if o.copy_of is not None and first not in o.generated:
        return f"{o.template}.{o.copy_of}" + (f".{rest}" if rest else "")
    where = f"{o.template}.{o.field}" if o.field else o.template
    return f"{where} (expanded as {path})"


class _Pipe:
    """Section numbers of the template's pipe."""

    def __init__(self, pipe: PipeSpec, method: str, env):
        D, t = pipe.outer_diameter, pipe.wall_thickness
        d = D - 2.0 * t
        self.steel_diameter = D
        self.contact_diameter = D + 2.0 * pipe.coating_thickness
        self.area = math.pi / 4.0 * (D * D - d * d)
        self.inertia = math.pi / 64.0 * (D ** 4 - d ** 4)
        self.EA = pipe.youngs_modulus * self.area
        self.EI = pipe.youngs_modulus * self.inertia
        Dc = self.contact_diameter
        coating_area = math.pi / 4.0 * (Dc * Dc - D * D)
        self.mass = pipe.density * self.area + (pipe.coating_density or 0.0) * coating_area \
            + pipe.contents_density * math.pi / 4.0 * d * d
        g = env.gravity
        rho_w = env.water.density if env.water is not None else 0.0
        self.weight = self.mass * g                                     # N/m in air
        self.submerged_weight = self.weight - rho_w * g * math.pi / 4.0 * Dc * Dc
        self.surface_level = env.water.surface_level if env.water is not None else 0.0   # still water, z
        self.material = pipe.material or ("elastoplastic" if method == "reel-lay" else "elastic")
        self.yield_stress = GRADE_YIELD[pipe.grade]
        self.spec = pipe

    def line_type(self) -> dict:
        p = self.spec
        common = {"drag_normal": p.drag_normal, "drag_axial": p.drag_axial, "added_mass_normal": p.added_mass_normal,
                  "damping": {"axial_ratio": p.damping_ratio, "bending_ratio": p.damping_ratio}}
        if self.material == "elastoplastic":
            if p.coating_thickness > 0.0:
                raise FieldError("pipe.coating_thickness", "an elastoplastic pipe is modelled by its steel wall "
                                                           "and cannot carry a coating here (drop the coating or "
                                                           "use material: elastic)")
            material = {"kind": "elastoplastic", "law": "bilinear", "yield_stress": self.yield_stress,
                        "hardening_ratio": p.hardening_ratio}
        else:
            material = {"kind": "elastic"}
        if p.coating_thickness == 0.0:
            return {"outer_diameter": p.outer_diameter, "wall_thickness": p.wall_thickness,
                    "youngs_modulus": p.youngs_modulus, "density": p.density,
                    "contents_density": p.contents_density, "material": material, **common}
        # a coated pipe: the steel's stiffness, the coated section's mass and diameter
        from ..model.sections import cowper_shear_coefficient
        D, d = p.outer_diameter, p.outer_diameter - 2.0 * p.wall_thickness
        nu = 0.3
        G = p.youngs_modulus / (2.0 * (1.0 + nu))
        Dc = self.contact_diameter
        rotary = p.density * self.inertia + p.coating_density * math.pi / 64.0 * (Dc ** 4 - D ** 4)
        return {"outer_diameter": Dc, "steel_outer_diameter": D,
                "EA": self.EA, "EIy": self.EI, "EIz": self.EI, "GJ": 2.0 * G * self.inertia,
                "GA": cowper_shear_coefficient(D, d, nu) * G * self.area, "mass_per_length": self.mass,
                "rotary_inertia": rotary, "material": material, **common}


def _vessel_pose(out: dict, name: str, tpl, raw_tpl: dict) -> tuple[str, list, float]:
    """(vessel name, rest position, heading in rad); an inline vessel is added to ``vessels``."""
    if isinstance(tpl.vessel, str):
        vname = tpl.vessel
        vessels = out.get("vessels") or {}
        if not isinstance(vessels, dict) or vname not in vessels:
            known = ", ".join(sorted(vessels)) if isinstance(vessels, dict) and vessels else "none defined"
            raise FieldError("vessel", f"unknown vessel '{vname}' (vessels: {known})")
        try:
            v = Vessel.model_validate(vessels[vname])
        except (ValidationError, ValueError):
            v = Vessel()        # its own errors are reported by the validation of vessels
    else:
        vname = f"{name}_vessel"
        v = tpl.vessel
        _add(out, "vessels", vname, copy.deepcopy(raw_tpl.get("vessel", {})), "vessel", copy_of="vessel")
    return vname, list(v.position), math.radians(v.heading_deg)


def _to_global(position, heading, p):
    c, s = math.cos(heading), math.sin(heading)
    return [position[0] + c * p[0] - s * p[1], position[1] + s * p[0] + c * p[1], position[2] + p[2]]


def _seabed(out: dict, env, tpl) -> tuple[float, float]:
    """(seabed z, normal stiffness); adds a seabed when the scene has none."""
    if env.water is None:
        raise FieldError("", "a pipelay template needs sea water (environment.water with its depth)")
    sb = env.seabed
    if sb is None:
        if env.water.depth is None:
            raise FieldError("", "a pipelay template needs the water depth (environment.water.depth) or a seabed")
        out.setdefault("environment", {})["seabed"] = {"normal_stiffness": tpl.seabed_stiffness,
                                                       "damping_ratio": 0.2, "friction": 0.5}
        record_origin("environment.seabed", keys={"normal_stiffness": "seabed_stiffness"})
        return env.water.surface_level - env.water.depth, tpl.seabed_stiffness
    if sb.profile is not None or sb.slope_deg != 0.0:
        raise FieldError("", "the pipelay templates need a flat seabed (no slope_deg, no profile)")
    return env.seabed_z(), sb.normal_stiffness


# the template field each support stands for (the collar is J-lay's tensioner; the aligner and
# the straightener come from the template's aligner_radius and straightener_offset)
_SUPPORT_FIELDS = {"tensioner": "tensioner", "collar": "tensioner", "stinger": "stinger", "reel": "reel"}


# a laid pipe of more elements than this, longer than this many water depths, is named: it
# makes the model large and the lay does not feel it
LAID_ELEMENTS = 2000
LAID_DEPTHS = 10.0


def _element_count(tpl, length: float, default: float | None = None) -> int:
    """Elements of the line: given, or from element_length, or from ``default`` (the
    method's own default, DEFAULT_ELEMENT_LENGTH, when None; S-lay: a third of the station
    spacing, so too many of them are the spacing's fault)."""
    if tpl.elements is not None:
        return tpl.elements
    target = tpl.element_length or default or DEFAULT_ELEMENT_LENGTH[tpl.method]
    n = max(4, int(math.ceil(length / target - 1e-9)))
    if n > MAX_LINE_ELEMENTS:
        if tpl.element_length is None and default is not None and tpl.method == "s-lay":
            raise FieldError("stinger.spacing", f"the default elements, a third of the station spacing ({target:.3g} "
                                                f"m), make {n} elements on the {length:.6g} m line, more than the "
                                                f"{MAX_LINE_ELEMENTS} a line may have: give a spacing of at least "
                                                f"{3.0 * length / MAX_LINE_ELEMENTS:.3g} m, or element_length")
        raise FieldError("element_length", f"{target:g} m gives {n} elements on the {length:.6g} m line, more than "
                                           f"the {MAX_LINE_ELEMENTS} a line may have: give at least "
                                           f"{length / MAX_LINE_ELEMENTS:.3g} m")
    return n


def _track_length(tpl, length_estimate: float, default_element: float | None = None) -> float:
    """Tensioner/collar length: given, or 10 m and at least three elements."""
    if tpl.tensioner.length is not None:
        return tpl.tensioner.length
    n = _element_count(tpl, length_estimate, default_element)
    return max(10.0, 3.0 * length_estimate / n)


def _half_track(tpl, track: float, what: str) -> str:
    """'half the <what> (<m>)' for a max_element_reason, saying where a default track length
    came from: without tensioner.length the track is 10 m and at least three elements
    (_track_length), so with long elements it is longer than the 10 m default (100 m J-lay
    elements: a 292 m collar, reported as "half the collar (147 m)" without a word why)."""
    if tpl.tensioner.length is not None or track <= 10.0 * (1.0 + 1e-9):
        return f"half the {what} ({0.5 * track:.3g} m)"
    return (f"half the {what} ({0.5 * track:.3g} m; without tensioner.length the {what} is 10 m long and at "
            f"least three elements, so these elements stretch it to {track:.4g} m)")


def _payout_reach(pay) -> float:
    """The largest paid-out length a payout table reaches (0 without a table: a driven
    payout's total is not known before the run)."""
    if pay is None or pay.kind != "table":
        return 0.0
    return max(0.0, max(row[1] for row in pay.rows))


def _tensioner(tpl, line: str, vname: str, entry, axis, length: float, top_tension: float,
               static_load: float | None = None, what: str = "tensioner", upstream: float | None = None,
               horizontal_tension: float | None = None) -> dict:
    """The track's support. ``static_load``: the axial force it holds in statics (estimate,
    N): a given capacity below it is refused here (statics would fail with the pipe slipping
    through, at some element far away). ``upstream``: the pipe held upstream of the track's
    exit at the start (m): a payout table reaching beyond it is refused (the pipe's end would
    leave the track and the pipe drop). ``horizontal_tension``: the H statics pays the pipe
    out (or hauls it in) to (the template's given ``tension``; rfesim.solvers.lay_statics)."""
    spec = tpl.tensioner
    out = {"kind": "tensioner", "attach": vname, "line": line, "entry": [float(c) for c in entry],
           "axis": [float(c) for c in axis], "length": length,
           "lateral_stiffness": spec.lateral_stiffness, "grip_stiffness": spec.grip_stiffness,
           "capacity": spec.capacity if spec.capacity is not None else max(1.0e6, 3.0 * top_tension)}
    if spec.capacity is not None and static_load is not None and spec.capacity < static_load:
        raise FieldError("tensioner.capacity", f"{spec.capacity:.6g} N is below the {static_load / 1e3:.4g} kN the "
                                               f"{what} holds in statics (the catenary's top tension and the pipe "
                                               f"in the {what}): the pipe would slip through it; give a capacity "
                                               f"above {static_load:.4g} N (default: three times the top tension, "
                                               f"at least 1 MN)")
    reach = _payout_reach(spec.payout)
    if upstream is not None and reach > upstream:
        raise FieldError("tensioner.payout", f"the payout table pays out {reach:.6g} m, but the {what} holds only "
                                             f"{upstream:.6g} m of pipe up to its exit (end A of the line starts at "
                                             f"its entry): the end would leave the {what} and the pipe drop; pay out "
                                             f"at most {upstream:.6g} m, or give a longer tensioner.length")
    if spec.payout is not None:
        out["payout"] = spec.payout.model_dump(mode="json")
    if horizontal_tension is not None:
        out["horizontal_tension"] = horizontal_tension
    return out


def _expand_one(out: dict, name: str, tpl, raw_tpl: dict, env) -> None:
    line = tpl.line or name
    if any(c in line for c in "/:\\") or line.strip() != line:
        raise FieldError("line", f"bad name {line!r}: no '/', ':' or '\\', no outer spaces")
    if line in (out.get("lines") or {}):
        raise FieldError("line", f"the line '{line}' is already defined in lines: give the template another "
                                 f"line name (pipelay.{name}.line)")
    pipe = _Pipe(tpl.pipe, tpl.method, env)
    if not pipe.submerged_weight > 0.0:
        raise FieldError("pipe", f"the pipe floats (submerged weight {pipe.submerged_weight:.4g} N/m): the "
                                 f"templates lay a pipe that sinks")
    vname, vpos, heading = _vessel_pose(out, name, tpl, raw_tpl)
    seabed_z, k_bed = _seabed(out, env, tpl)
    w = pipe.submerged_weight
    radius = 0.5 * pipe.contact_diameter
    z_bed_axis = seabed_z + radius - w / k_bed       # the laid pipe's axis (sunk w/k into the seabed)
    build = {"s-lay": _s_lay, "j-lay": _j_lay, "reel-lay": _reel_lay}[tpl.method]
    geo = build(tpl, pipe, vpos, heading, z_bed_axis)
    # the line: end A free at the first track's entry, end B pinned on the seabed
    length = geo["length"]
    n = _element_count(tpl, length, geo.get("default_element"))
    if length / n > geo["max_element"]:
        raise FieldError("element_length" if tpl.elements is None else "elements",
                         f"elements of {length / n:.3g} m are longer than {geo['max_element']:.3g} m: the "
                         f"{geo['max_element_reason']}")
    # a given element_length or elements coarser than the mesh an output needs (the defaults
    # are finer): the builder's (limit, why)
    if geo.get("coarse_mesh") is not None and length / n > geo["coarse_mesh"][0]:
        template_warning("element_length" if tpl.elements is None else "elements",
                         f"elements of {length / n:.4g} m are {geo['coarse_mesh'][1]}")
    laid = tpl.laid_length * n / length         # elements on the laid pipe
    depth = env.water.surface_level - seabed_z
    if laid > LAID_ELEMENTS and tpl.laid_length > LAID_DEPTHS * depth:
        template_warning("laid_length",
                         f"{tpl.laid_length:.6g} m of pipe on the seabed ({tpl.laid_length / depth:.3g} times the "
                         f"water depth) makes about {laid:.0f} of the line's {n} elements: the lay above feels the "
                         f"laid pipe only over the length on which the seabed's friction takes up the bottom "
                         f"tension, a few water depths, while the statics and every time step grow with the "
                         f"element count (a reel-lay with 30000 m laid, 15000 elements, took 8 minutes of statics "
                         f"on a 2-core machine, with 10000 m 19 s); give a laid_length of a few water depths")
    type_name = f"{line}_pipe"
    _add(out, "line_types", type_name, pipe.line_type(), "line", origin="pipe")
    _add(out, "lines", line, {
        "type": type_name, "length": length, "elements": n,
        "end_a": {"attach": "free", "position": geo["end_a"], "direction": geo["end_a_direction"]}
        if geo["end_a"] is not None else {"attach": "free"},
        "end_b": {"attach": "fixed", "position": geo["end_b"], "connection": "pinned"}}, "line", origin="",
        keys={"elements": "elements"} if tpl.element_length is None else None)
    for key, support in geo["supports"].items():
        support = dict(support, line=line)
        if support.get("attach") is None:
            support["attach"] = vname
        _add(out, "supports", f"{line}_{key}", support, "line", origin=_SUPPORT_FIELDS.get(key, ""),
             keys={"offset": "straightener_offset"} if key == "straightener" else None)
    if not out.get("name"):
        out["name"] = f"{tpl.method} of a {tpl.pipe.outer_diameter:.4g} m pipe"


def _weight_height(pipe, h: float, z_top: float) -> tuple[float, float]:
    """(W, h_air): the pipe's weight over the height h from the laid pipe's axis up to the
    lift-off point at z_top, W = w h_water + w_air h_air (N), submerged below the still water
    surface and in air above it, with h_air = the part of h above the surface."""
    h_air = min(h, max(0.0, z_top - pipe.surface_level))
    return pipe.submerged_weight * (h - h_air) + pipe.weight * h_air, h_air


def lay_catenary(pipe, h: float, z_top: float, H: float) -> dict:
    """The natural catenary from the touchdown up to the lift-off point h above the laid
    pipe's axis (at z_top), in two pieces: submerged weight w below the still water surface,
    the weight in air w_a above it (a catenary of parameter H / w_i in each, the slope
    continuous at the surface). With sec(theta) = cosh(x / a) on a catenary, the height
    between two angles is a (sec(theta_2) - sec(theta_1)), so at the surface
    sec(theta_s) = 1 + w h_water / H and at the top sec(theta) = 1 + W / H, W = w h_water +
    w_a h_air; the lengths a (tan(theta_2) - tan(theta_1)) and spans a (asinh(tan(theta_2)) -
    asinh(tan(theta_1))) of the pieces add up. One piece (the lift-off point under water)
    is ``rfesim.catenary.natural_catenary``. Returns ``horizontal_span``, ``suspended_length``
    (m), ``top_angle_deg``, ``top_tension`` = H + W (N, the effective tension at the top)."""
    from ..catenary import natural_catenary

    W, h_air = _weight_height(pipe, h, z_top)
    if h_air <= 0.0:                    # all under water: one piece, the closed form as before
        nat = natural_catenary(pipe.submerged_weight, h, H)
        return {k: nat[k] for k in ("horizontal_span", "suspended_length", "top_angle_deg", "top_tension")}
    # tan = sqrt(sec^2 - 1) = sqrt(x (2 + x)), x = sec - 1: no cancellation for a light pipe
    # under a large tension (x of 1e-15; (1 + x)^2 - 1 rounds to 0, a flat departure)
    x_s, x_t = pipe.submerged_weight * (h - h_air) / H, W / H
    tan_s, tan_t = math.sqrt(x_s * (2.0 + x_s)), math.sqrt(x_t * (2.0 + x_t))
    a_w, a_a = H / pipe.submerged_weight, H / pipe.weight
    return {"horizontal_span": a_w * math.asinh(tan_s) + a_a * (math.asinh(tan_t) - math.asinh(tan_s)),
            "suspended_length": a_w * tan_s + a_a * (tan_t - tan_s),
            "top_angle_deg": math.degrees(math.atan(tan_t)), "top_tension": H + W}


def _catenary_h(tpl, pipe, h: float, z_top: float, angle_deg: float | None, what: str) -> tuple[float, float]:
    """(H, departure angle in deg): H given, or from the angle theta at the lift-off point h
    above the laid pipe's axis (at z_top) on the two-piece natural catenary (``lay_catenary``):
    sec(theta) = 1 + W / H, so H = W cos(theta) / (1 - cos(theta)) with W = w h_water + w_a h_air
    the pipe's weight over the height, submerged below the still water surface and in air above
    it (before, w h: the submerged weight over the whole height left H 2.8 % low for a J-lay
    tower exit 15 m above the water at 85 deg, 1.5 % for the reel-lay ramp exit 2 m up at 70 deg)."""
    if h <= 0.0:
        raise FieldError("exit", f"the {what} is {-h:.4g} m below the seabed: it must be above it")
    W, _ = _weight_height(pipe, h, z_top)
    if tpl.tension is not None:
        return tpl.tension, math.degrees(math.acos(1.0 / (1.0 + W / tpl.tension)))
    c = math.cos(math.radians(angle_deg))
    return W * c / (1.0 - c), angle_deg


def _stiff_sagbend(tpl, pipe, H: float, angle: float, field: str) -> None:
    """Warn when the natural catenary cannot describe the sagbend: its radius at the touchdown,
    H / w, is shorter than the pipe's bending boundary layer sqrt(EI / H). The lay tension the
    template takes from the departure angle (``field``), and the catenary start shape, then
    no longer hold: the pipe's stiffness shapes the sagbend (a reel-lay ramp at 89.3 deg in
    300 m failed statics; at 89.5 deg the tensioner carried 996 kN)."""
    w = pipe.submerged_weight
    if w <= 0.0 or H <= 0.0:
        return
    radius, layer = H / w, math.sqrt(pipe.EI / H)
    if layer <= radius:
        return
    given = "the lay tension" if tpl.tension is not None else f"at {angle:.4g} deg, the natural catenary's lay tension"
    fix = "give a larger tension" if tpl.tension is not None else "give a lower angle or the lay tension (tension)"
    template_warning(field, f"{given} H = {H / 1e3:.4g} kN makes a sagbend radius H/w of {radius:.4g} m, shorter "
                            f"than the pipe's bending boundary layer sqrt(EI/H) = {layer:.4g} m: the pipe's "
                            f"bending stiffness, not the catenary, shapes the sagbend, so the catenary's tension and "
                            f"start shape do not hold (statics may fail, or settle far from H); {fix}")


def _s_lay(tpl, pipe, vpos, heading, z_bed) -> dict:
    """S-lay: the tensioner on the deck line, 2 m of free pipe, the stinger arc to its tip;
    the tip angle equals the departure angle of the natural catenary from the tip (unless
    the stinger length is given). The deck line is tangent to the arc at station 0 (the
    pipe's slope is continuous there, its curvature steps from 0 to 1/R). The tensioner
    support's track reaches half an element past the tensioner's exit: the pads let go over
    the last element (rfesim.loads.tensioner), so the pipe is held up to the exit."""
    st = tpl.stinger
    w, H = pipe.submerged_weight, tpl.tension
    _stiff_sagbend(tpl, pipe, H, 0.0, "tension")
    a = H / w
    lift = (0.5 * pipe.contact_diameter + st.roller_radius) / math.cos(math.radians(st.v_angle_deg))
    Rp = st.radius + lift                 # radius of the pipe axis on the rollers
    x0, y0, z0 = st.start
    zA = z0 + lift                         # pipe axis on the deck line (vessel frame)

    def height(theta):                     # tip (pipe axis) above the laid pipe's axis
        return vpos[2] + zA - Rp * (1.0 - math.cos(theta)) - z_bed

    def departure(theta):                  # catenary angle at the tip (rad), dry above the water
        h = max(height(theta), 0.0)
        return math.radians(lay_catenary(pipe, h, z_bed + h, H)["top_angle_deg"]) if h > 0.0 else 0.0

    if height(0.0) <= 0.0:
        raise FieldError("stinger.start", "the stinger starts below the seabed")
    if st.length is not None:
        theta = st.length / st.radius
        if height(theta) <= 0.0:
            raise FieldError("stinger.length", f"{st.length} m puts the stinger tip below the seabed")
    else:
        from scipy.optimize import brentq
        hi = 0.5 * math.pi
        if height(hi) <= 0.0:              # the arc reaches the seabed first
            hi = math.acos(1.0 - (height(0.0) - 1e-6) / Rp)
        lo = 1e-9
        if not (departure(lo) - lo) * (departure(hi) - hi) <= 0.0:       # no sign change (or nan)
            raise FieldError("tension", f"{H:.6g} N on a pipe of submerged weight {w:.4g} N/m (H/w = {a:.4g} m): no "
                                        f"stinger tip angle matches the catenary's departure angle (between "
                                        f"{math.degrees(lo):.3g} and {math.degrees(hi):.3g} deg); give "
                                        f"stinger.length, or a smaller tension or a heavier pipe")
        theta = brentq(lambda th: departure(th) - th, lo, hi, xtol=1e-12)
    length_stinger = st.radius * theta
    if length_stinger < st.spacing:
        raise FieldError("stinger.spacing", f"{st.spacing} m is longer than the stinger ({length_stinger:.4g} m "
                                            f"to the tip angle {math.degrees(theta):.3g} deg)")
    stations = max(1, round(length_stinger / st.spacing))
    spacing = length_stinger / stations    # a station exactly at the tip
    h = height(theta)
    nat = lay_catenary(pipe, h, z_bed + h, H)
    gap = 2.0                              # free pipe between the tensioner and the stinger

    def geometry(track):
        tip = [x0 + Rp * math.sin(theta), y0, zA - Rp * (1.0 - math.cos(theta))]
        tip_g = _to_global(vpos, heading, tip)
        u = [math.cos(heading), math.sin(heading), 0.0]
        along = nat["horizontal_span"] + tpl.laid_length
        return {"length": track + gap + Rp * theta + nat["suspended_length"] + tpl.laid_length,
                "end_a": _to_global(vpos, heading, [x0 - gap - track, y0, zA]),
                "end_a_direction": u,
                "end_b": [tip_g[0] + along * u[0], tip_g[1] + along * u[1], z_bed]}

    # elements of at most a third of the station spacing by default: a rigid element of
    # length l lies l^2 / (8 R) inside the arc at its middle, which against the roller
    # stiffness is a large force, so with 1.5 elements per spacing (4 m elements, 6 m
    # spacing) every other station carries nothing and its neighbours twice their share;
    # at spacing / 3 the station reactions are within 1.5 % of a converged mesh
    default_element = min(DEFAULT_ELEMENT_LENGTH["s-lay"], spacing / STINGER_ELEMENTS_PER_SPACING)
    if length_stinger / spacing > MAX_STINGER_STATIONS:
        default_element = None      # the stinger support refuses the spacing itself, naming it
    track = _track_length(tpl, geometry(10.0)["length"], default_element)
    geo = geometry(track)
    # the tensioner's grip force: the string's effective tension over a frictionless path
    # (dT = w dz) from the laid pipe up to the deck line, submerged weight below the still
    # water surface and the weight in air above it
    z_top = zA + vpos[2]
    z_surface = pipe.surface_level
    top = H + w * (min(z_top, z_surface) - z_bed) + pipe.weight * max(z_top - z_surface, 0.0)
    # the pads hold an RFE by min(1, xi / l, (L - xi) / l) of its centre's place xi along the
    # track (rfesim.loads.tensioner): they let go of the pipe over the last element, and their
    # hold ends half an element before the track's exit whatever the RFEs' places; the
    # support's track reaches half an element past the tensioner's exit so that the pipe is
    # held up to it and leaves it the gap's 2 m before station 0 at any mesh (docs/theory.md,
    # "S-lay first station"; before, the free span was 2 + l/2 m and the first station's
    # reaction 20 % low at the default elements)
    half_element = 0.5 * geo["length"] / _element_count(tpl, geo["length"], default_element)
    layer = math.sqrt(pipe.EI / H)
    geo.update(
        default_element=default_element,
        coarse_mesh=(0.5 * spacing,
                     f"longer than half the stinger's roller-station spacing ({spacing:.4g} m): a rigid element "
                     f"lies l^2/(8R) inside the arc at its middle, so the stations alternate between element ends "
                     f"and middles and the roller reactions scatter (every other station unloaded, its neighbours "
                     f"doubled); give elements of at most a third of the spacing ({spacing / 3.0:.4g} m, the "
                     f"default)"),
        max_element=min(layer, 0.5 * track),
        max_element_reason=f"bending boundary layer sqrt(EI/H) = {layer:.3g} m and "
                           f"{_half_track(tpl, track, 'tensioner')} must each span at least one element",
        supports={
            "tensioner": _tensioner(tpl, "", None, [x0 - gap - track, y0, zA], [1.0, 0.0, 0.0],
                                    track + half_element, top, static_load=top, upstream=track,
                                    horizontal_tension=H),
            "stinger": {"kind": "stinger", "start": list(st.start), "direction": [1.0, 0.0, 0.0],
                        "radius": st.radius, "length": length_stinger, "spacing": spacing,
                        "roller_width": st.roller_width, "roller_radius": st.roller_radius,
                        "v_angle_deg": st.v_angle_deg, "stiffness": st.stiffness, "damping": st.damping,
                        "friction": st.friction}})
    for sup in geo["supports"].values():
        sup.pop("line", None)
        sup["attach"] = None
    return geo


def _j_lay(tpl, pipe, vpos, heading, z_bed) -> dict:
    """J-lay: the pipe hangs from the collar (a tensioner-kind track along the tower, ending
    at the tower exit) and leaves at the tower angle on the natural catenary."""
    exit_local = list(tpl.exit)
    exit_g = _to_global(vpos, heading, exit_local)
    h = exit_g[2] - z_bed
    H, angle = _catenary_h(tpl, pipe, h, exit_g[2], tpl.tower_angle_deg, "tower exit")
    _stiff_sagbend(tpl, pipe, H, angle, "tension" if tpl.tension is not None else "tower_angle_deg")
    if tpl.tension is not None and not 70.0 <= angle < 90.0:
        raise FieldError("tension", f"{tpl.tension} N leaves the tower exit {h:.4g} m above the seabed at "
                                    f"{angle:.3g} deg: a J-lay tower stands at 70 to 90 deg (give a smaller tension "
                                    f"or use s-lay)")
    th = math.radians(angle)
    axis = [math.cos(th), 0.0, -math.sin(th)]     # down the tower, leaning towards the lay direction
    nat = lay_catenary(pipe, h, exit_g[2], H)
    top = nat["top_tension"]                       # H + the pipe's weight over the height
    u = [math.cos(heading), math.sin(heading), 0.0]

    def geometry(track):
        along = nat["horizontal_span"] + tpl.laid_length
        entry = [exit_local[k] - track * axis[k] for k in range(3)]
        c, s = math.cos(heading), math.sin(heading)
        return {"length": track + nat["suspended_length"] + tpl.laid_length,
                "end_a": _to_global(vpos, heading, entry),
                "end_a_direction": [c * axis[0] - s * axis[1], s * axis[0] + c * axis[1], axis[2]],
                "end_b": [exit_g[0] + along * u[0], exit_g[1] + along * u[1], z_bed], "entry": entry}

    # the hang-off: under vessel pitch the pipe bends within sqrt(EI/T_top) below the collar
    # (9 m in scenarios/j_lay.json); elements of a sixth of it carry the moment there
    hang_off = math.sqrt(pipe.EI / top)
    default_element = min(DEFAULT_ELEMENT_LENGTH["j-lay"], HANG_OFF_ELEMENT_FRACTION * hang_off)
    track = _track_length(tpl, geometry(10.0)["length"], default_element)
    geo = geometry(track)
    layer = math.sqrt(pipe.EI / H)
    # the collar holds the catenary's top tension and the pipe in the tower (in air)
    collar = _tensioner(tpl, "", None, geo.pop("entry"), axis, track, top,
                        static_load=top + pipe.weight * track * math.sin(th), what="collar", upstream=track,
                        horizontal_tension=tpl.tension)
    collar.pop("line")
    collar["attach"] = None
    geo.update(max_element=min(layer, 0.5 * track),
               max_element_reason=f"bending boundary layer sqrt(EI/H) = {layer:.3g} m and "
                                  f"{_half_track(tpl, track, 'collar')} must each span at least one element",
               supports={"collar": collar}, default_element=default_element,
               coarse_mesh=(0.5 * hang_off,
                            f"longer than half the bending boundary layer below the collar, sqrt(EI/T_top) = "
                            f"{hang_off:.4g} m with the catenary's top tension: under vessel pitch the hang-off "
                            f"moment and the departure angle's range come out low (10 m elements: half the moment "
                            f"of a converged mesh); give elements of at most "
                            f"{HANG_OFF_ELEMENT_FRACTION * hang_off:.4g} m (the default)"))
    return geo


def _reel_payout(tpl, back_tension: float) -> dict:
    """The reel turns with the tensioner: the same payout table; under a constant-tension
    tensioner it is driven by the same characteristic (gain, speed limit) holding the back
    tension that statics settles the pipe just off the drum to (``back_tension``): the law acts
    on the drum's grip force less the offset statics fixes at that state (rfesim.loads.reel,
    rfesim.solvers.reel_statics), so the run starts in equilibrium, without a transient."""
    pay = tpl.tensioner.payout
    if pay is None:
        return {}
    if pay.kind == "table":
        return {"payout": pay.model_dump(mode="json")}
    return {"payout": {"kind": "constant-tension", "tension": back_tension,
                       "dead_band": 0.0, "gain": pay.gain, "max_speed": pay.max_speed}}


# the template's wrap window: the pipe beyond half a turn lies under the drum, where only the
# grips hold it against gravity (one layer, unilateral radial contact): statics with a longer
# wrap finds no sensible equilibrium, so the template stores at most half a turn
MAX_REEL_WRAP_DEG = 180.0


def _elastic_on_reel(pipe, reel_radius: float) -> None:
    """Warn (``pipe.material``) when an elastic pipe is bent on the reel beyond its grade's yield
    strain: reeling is plastic by design (a 12.75 in pipe on an 8 m drum is strained 2 %, some
    ten times the yield strain), so an elastic pipe there carries moments about ten times its
    first-yield moment into the aligner and straightener, and has no residual curvature."""
    spec = pipe.spec
    strain = 0.5 * spec.outer_diameter / reel_radius
    yield_strain = pipe.yield_stress / spec.youngs_modulus
    if strain <= yield_strain:
        return
    moment = pipe.EI / reel_radius
    first_yield = pipe.yield_stress * pipe.inertia / (0.5 * spec.outer_diameter)
    template_warning("pipe.material",
                     f"an elastic pipe bent on the {reel_radius:.4g} m reel (pipe axis): its bending strain D/2R = "
                     f"{100.0 * strain:.3g} % is {strain / yield_strain:.3g} times the yield strain of "
                     f"{spec.grade} ({100.0 * yield_strain:.3g} %): it carries {moment / 1e6:.4g} MN*m on the "
                     f"drum where its first-yield moment is {first_yield / 1e6:.4g} MN*m, and leaves the "
                     f"straightener with no residual curvature; give material: elastoplastic (the reel-lay "
                     f"default)")


def _reel_lay(tpl, pipe, vpos, heading, z_bed) -> dict:
    """Reel-lay, up the ramp from its exit: tensioner, 2 m, straightener, 2 m, the aligner
    arc (stinger kind, from horizontal down to the ramp angle), 2 m of horizontal pipe to
    the take-off point at the top of the reel; end A lies on the reel's wrap
    (rfesim.model.reels). The catenary leaves the exit at the ramp angle."""
    exit_local = list(tpl.exit)
    exit_g = _to_global(vpos, heading, exit_local)
    h = exit_g[2] - z_bed
    H, angle = _catenary_h(tpl, pipe, h, exit_g[2], tpl.ramp_angle_deg, "ramp exit")
    _stiff_sagbend(tpl, pipe, H, angle, "tension" if tpl.tension is not None else "ramp_angle_deg")
    if tpl.tension is not None and not 20.0 <= angle < 90.0:
        raise FieldError("tension", f"{tpl.tension} N leaves the ramp exit at {angle:.3g} deg: the ramp stands "
                                    f"at 20 to 90 deg")
    al = math.radians(angle)
    e = [math.cos(al), 0.0, -math.sin(al)]
    # the straightener's middle roller pushes the pipe towards the reel and aligner centres
    # (below the ramp's pipe line): the reverse of the reeling and aligner bend
    side = [-math.sin(al), 0.0, -math.cos(al)]
    if tpl.straightener_offset < 0.0:               # set away from the centres
        side = [-c for c in side]
    nat = lay_catenary(pipe, h, exit_g[2], H)
    top = nat["top_tension"]                       # H + the pipe's weight over the height
    u = [math.cos(heading), math.sin(heading), 0.0]
    rp = 0.5 * pipe.contact_diameter
    gap, span = 2.0, 6.0
    roller_radius = 0.15
    lift = rp + roller_radius                       # flat aligner rollers
    Rp = tpl.aligner_radius + lift
    reel_radius = tpl.reel.radius + rp               # the pipe axis on the drum
    if pipe.material == "elastic":
        _elastic_on_reel(pipe, reel_radius)
    # pipe on the drum at the start: enough for the payout and to bring reeled pipe past the
    # straightener (ReelSpec.stored_length), inside the largest wrap window
    element = min(tpl.element_length or DEFAULT_ELEMENT_LENGTH["reel-lay"], 0.25 * tpl.reel.radius,
                  0.25 * tpl.aligner_radius)
    window = reel_radius * math.radians(MAX_REEL_WRAP_DEG)
    path = gap + Rp * al + gap + span                 # take-off point to the straightener exit
    reach = _payout_reach(tpl.tensioner.payout)
    if tpl.reel.stored_length is not None:
        stored = tpl.reel.stored_length
        if stored > window - element:
            raise FieldError("reel.stored_length", f"{stored:.6g} m is more than the drum holds in its "
                                                   f"{MAX_REEL_WRAP_DEG:.0f} deg wrap window less one element "
                                                   f"({window - element:.6g} m at "
                                                   f"the pipe-axis radius {reel_radius:.6g} m): store less, or "
                                                   f"give a larger reel.radius")
    else:
        stored = min(window - element, max(0.5 * math.pi * reel_radius, path + reach + 2.0 * element))
    if reach > stored:
        given = tpl.reel.stored_length is not None
        held = "reel.stored_length" if given else f"the most its {MAX_REEL_WRAP_DEG:.0f} deg wrap window holds"
        raise FieldError("tensioner.payout", f"the payout table pays out {reach:.6g} m, but the reel stores only "
                                             f"{stored:.6g} m ({held}): the reel would empty and the pipe's end run "
                                             f"free over the aligner; pay out less, or store more "
                                             f"({'reel.stored_length, ' if given else ''}a larger reel.radius)")
    wrap_deg = MAX_REEL_WRAP_DEG

    def geometry(track):
        entry_t = [exit_local[k] - track * e[k] for k in range(3)]
        entry_s = [entry_t[k] - (gap + span) * e[k] for k in range(3)]
        arc_end = [entry_s[k] - gap * e[k] for k in range(3)]
        arc_start = [arc_end[0] - Rp * math.sin(al), arc_end[1], arc_end[2] + Rp * (1.0 - math.cos(al))]
        take_off = [arc_start[0] - gap, arc_start[1], arc_start[2]]
        along = nat["horizontal_span"] + tpl.laid_length
        return {"length": stored + gap + Rp * al + gap + span + gap + track + nat["suspended_length"]
                          + tpl.laid_length,
                "end_a": None, "end_a_direction": None,
                "end_b": [exit_g[0] + along * u[0], exit_g[1] + along * u[1], z_bed],
                "entry_t": entry_t, "entry_s": entry_s, "arc_start": arc_start, "take_off": take_off}

    track = _track_length(tpl, geometry(10.0)["length"])
    geo = geometry(track)
    layer = math.sqrt(pipe.EI / H)
    back_tension = tpl.reel.back_tension or 0.1 * top
    # the tensioner holds the catenary's top tension and the pipe on the ramp less the back tension
    # given the tension, statics pays the pipe out through the tensioner (the reel turning
    # with it) until the pipe carries H to end B (rfesim.solvers.lay_statics)
    tensioner = _tensioner(tpl, "", None, geo.pop("entry_t"), e, track, top,
                           static_load=top + pipe.weight * track * math.sin(al) - back_tension,
                           horizontal_tension=tpl.tension)
    entry_s, arc_start, take_off = geo.pop("entry_s"), geo.pop("arc_start"), geo.pop("take_off")
    arc = tpl.aligner_radius * al
    stations = max(2, round(arc / 1.0))
    coarse = ALIGNER_COARSE_FRACTION * tpl.aligner_radius
    geo.update(
        coarse_mesh=(coarse,
                     f"longer than a ninth of the aligner radius ({coarse:.4g} m): the pipe's peak curvature at "
                     f"the aligner exit, and with it the overbend strain and moment, comes out high (on a 9 m "
                     f"aligner 8.5 % high with 2 m elements, 2.8 % with 1 m, converged with 0.5 m); give elements "
                     f"of at most {ALIGNER_ELEMENT_FRACTION * tpl.aligner_radius:.4g} m (an eighteenth of the "
                     f"aligner radius)"),
        max_element=min(layer, 0.5 * track, 0.25 * reel_radius, 0.25 * tpl.aligner_radius),
        max_element_reason=f"bending boundary layer sqrt(EI/H) = {layer:.3g} m, "
                           f"{_half_track(tpl, track, 'tensioner')}, a quarter of the reel radius "
                           f"({0.25 * reel_radius:.3g} m) and a quarter of the aligner radius "
                           f"({0.25 * tpl.aligner_radius:.3g} m) must each span at least one element",
        supports={
            "reel": {"kind": "reel", "centre": [take_off[0], take_off[1], take_off[2] - reel_radius],
                     "axis": [0.0, -1.0, 0.0], "direction": [1.0, 0.0, 0.0], "radius": reel_radius,
                     "wrap_deg": wrap_deg, "stored_length": stored,
                     "capacity": max(1.0e6, 3.0 * top),
                     "back_tension": back_tension,
                     "grip_stiffness": tpl.reel.grip_stiffness, **_reel_payout(tpl, back_tension)},
            "aligner": {"kind": "stinger", "start": [arc_start[0], arc_start[1], arc_start[2] - lift],
                        "direction": [1.0, 0.0, 0.0], "radius": tpl.aligner_radius, "length": arc,
                        "spacing": arc / stations, "roller_width": 0.6, "roller_radius": roller_radius,
                        "v_angle_deg": 0.0, "stiffness": 1.0e7, "damping": 1.0e4, "friction": 0.0},
            "straightener": {"kind": "straightener", "entry": entry_s, "axis": e, "side": side, "span": span,
                             "offset": abs(tpl.straightener_offset), "rollers": 3, "roller_radius": 0.2,
                             "roller_width": 1.0, "stiffness": 1.0e7, "damping": 1.0e4},
            "tensioner": tensioner})
    for sup in geo["supports"].values():
        sup.pop("line", None)
        sup["attach"] = None
    return geo
