"""The scenario schema: the user's words, one pydantic v2 model.

Every model forbids unknown keys and NaN/inf. SI units throughout (m, s, kg, N, Pa),
angles in degrees where the field name says ``_deg``, z up, still water at
``environment.water.surface_level`` (0 by default). Units are written into the JSON
Schema (``units`` key of each property) so the HTTP service and the docs show them.

Cross-references (a line's ``type``, an end's ``attach``) are checked after the
field-level validation by :func:`rfesim.scenario.check_references`.
"""
from __future__ import annotations

import math
import types
import typing
from typing import Annotated, Any, Literal, Union

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, field_validator, model_validator


class FieldError(ValueError):
    """A validation error raised inside a model validator that names a sub-field.

    The scenario loader appends ``field`` to the location pydantic reports, so the
    user sees ``line_types.pipe12.wall_thickness: ...`` rather than only the parent.
    """

    def __init__(self, field: str, reason: str):
        self.field = field
        self.reason = reason
        super().__init__(f"{field}: {reason}")


def _units(u: str, description: str, **kw):
    """A pydantic Field with its SI unit in the JSON Schema."""
    return Field(description=f"{description} [{u}]", json_schema_extra={"units": u}, **kw)


def _allows_bool(annotation) -> bool:
    """True when a field's type accepts a boolean (bool itself, or a union with bool)."""
    if annotation is bool:
        return True
    origin = typing.get_origin(annotation)
    if origin is Annotated:
        return _allows_bool(typing.get_args(annotation)[0])
    if origin in (Union, types.UnionType):
        return any(_allows_bool(a) for a in typing.get_args(annotation))
    return annotation is Any


def _show(value: Any) -> str:
    """A short repr of a user value for error messages."""
    if isinstance(value, dict):
        return "a mapping"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, validate_default=True,
                              populate_by_name=True)

    @model_validator(mode="before")
    @classmethod
    def _no_bool_for_numbers(cls, data):
        # pydantic's lax mode reads true/false as 1/0 for numbers: that is silent garbage
        # in a scenario (``elements: true``), so a boolean is accepted only where the
        # field is a boolean.
        if isinstance(data, dict):
            for name, value in data.items():
                field = cls.model_fields.get(name) if isinstance(name, str) else None
                if field is None or not isinstance(value, bool) or _allows_bool(field.annotation):
                    continue
                word = "true" if value else "false"
                if _is_numeric(field.annotation):
                    raise FieldError(name, f"must be a number, not the boolean {word}")
                raise FieldError(name, f"the boolean {word} is not allowed here")
        return data


def _is_numeric(annotation) -> bool:
    """True when a field's type is (optionally) int or float."""
    if annotation in (int, float):
        return True
    origin = typing.get_origin(annotation)
    if origin is Annotated:
        return _is_numeric(typing.get_args(annotation)[0])
    if origin in (Union, types.UnionType):
        return any(_is_numeric(a) for a in typing.get_args(annotation))
    return False


def _fixed_length_numbers(n: int, what: str):
    """A before-validator for a list of exactly ``n`` numbers (clear message, no booleans)."""

    def check(value):
        if isinstance(value, (list, tuple)):
            if len(value) != n:
                raise ValueError(f"must have exactly {n} numbers {what}, got {len(value)}")
            for i, v in enumerate(value):
                if isinstance(v, bool):
                    raise FieldError(str(i), f"must be a number, not the boolean {'true' if v else 'false'}")
        return value

    return BeforeValidator(check)


Vector3 = Annotated[list[float], _fixed_length_numbers(3, "[x, y, z]"), Field(min_length=3, max_length=3)]
TableRow = Annotated[list[float], _fixed_length_numbers(7, "[t, surge, sway, heave, roll, pitch, yaw]"),
                     Field(min_length=7, max_length=7)]

PositiveFloat = Annotated[float, Field(gt=0.0)]
NonNegativeFloat = Annotated[float, Field(ge=0.0)]


# --------------------------------------------------------------------------- environment

class Water(_Strict):
    """Sea water: density, depth and still-water level."""

    density: float = _units("kg/m^3", "Mass density of sea water", default=1025.0, gt=0.0)
    depth: float | None = _units("m", "Water depth below the still surface (seabed at surface_level - depth)",
                                 default=None, gt=0.0)
    surface_level: float = _units("m", "z of the still water surface", default=0.0)


class Seabed(_Strict):
    """Flat horizontal seabed: a normal spring-damper per unit length of line."""

    z: float | None = _units("m", "z of the seabed plane (default: surface_level - water.depth)", default=None)
    normal_stiffness: float = _units("N/m/m", "Normal contact stiffness per unit length of line",
                                     default=1.0e5, gt=0.0)
    damping_ratio: float = Field(0.2, ge=0.0, le=10.0,
                                 description="Normal contact damping as a fraction of critical for the line's "
                                             "mass per length on the seabed spring [-]",
                                 json_schema_extra={"units": "1"})
    friction: float = Field(0.0, ge=0.0, le=5.0,
                            description="Coulomb friction coefficient (axial and lateral) [-]",
                            json_schema_extra={"units": "1"})


class Environment(_Strict):
    gravity: float = _units("m/s^2", "Acceleration of gravity (acts along -z)", default=9.81, ge=0.0, le=100.0)
    water: Water | None = Field(None, description="Sea water; omit for a scene in air")
    seabed: Seabed | None = Field(None, description="Seabed contact; omit for no seabed")

    @model_validator(mode="after")
    def _seabed_level(self):
        if self.seabed is not None and self.seabed.z is None:
            if self.water is None or self.water.depth is None:
                raise FieldError("seabed.z", "give the seabed level z or a water depth")
        if self.seabed is not None and self.seabed.z is not None and self.water is not None \
                and self.water.depth is not None:
            expected = self.water.surface_level - self.water.depth
            if abs(self.seabed.z - expected) > 1e-6 * max(1.0, self.water.depth):
                raise FieldError("seabed.z", f"{self.seabed.z} m does not match the water depth "
                                             f"{self.water.depth} m (seabed at z = {expected} m); give one of them")
        if self.seabed is not None and self.water is not None and self.seabed_z() >= self.water.surface_level:
            raise FieldError("seabed.z", "the seabed must lie below the water surface")
        return self

    def seabed_z(self) -> float | None:
        """The z of the seabed plane, or None without a seabed."""
        if self.seabed is None:
            return None
        if self.seabed.z is not None:
            return self.seabed.z
        return self.water.surface_level - self.water.depth


# --------------------------------------------------------------------------- vessels

DOF_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")


class HarmonicDof(_Strict):
    amplitude: float = Field(..., ge=0.0, description="Amplitude [m for surge/sway/heave, deg for roll/pitch/yaw]")
    period: float = _units("s", "Period", gt=0.0)
    phase_deg: float = _units("deg", "Phase: displacement = amplitude*sin(2*pi*t/period + phase)", default=0.0)


class FixedMotion(_Strict):
    kind: Literal["fixed"] = "fixed"


class HarmonicMotion(_Strict):
    """Sum of sines per degree of freedom about the vessel's rest position."""

    kind: Literal["harmonic"]
    surge: HarmonicDof | None = None
    sway: HarmonicDof | None = None
    heave: HarmonicDof | None = None
    roll: HarmonicDof | None = None
    pitch: HarmonicDof | None = None
    yaw: HarmonicDof | None = None
    ramp_duration: float = _units("s", "The motion is ramped in with 0.5*(1-cos(pi*t/T)) over this time",
                                  default=0.0, ge=0.0)


class TableMotion(_Strict):
    """A table of time vs the six displacements [t, surge, sway, heave, roll, pitch, yaw]."""

    kind: Literal["table"]
    rows: list[TableRow] = Field(
        ..., min_length=2,
        description="Rows [t (s), surge (m), sway (m), heave (m), roll (deg), pitch (deg), yaw (deg)]")
    interpolation: Literal["cubic", "linear"] = "cubic"
    ramp_duration: float = _units("s", "Ramp-in time of the motion", default=0.0, ge=0.0)

    @model_validator(mode="after")
    def _times_increase(self):
        times = [r[0] for r in self.rows]
        for i in range(1, len(times)):
            if not times[i] > times[i - 1]:
                raise FieldError(f"rows.{i}", f"time {times[i]} s does not increase (previous {times[i - 1]} s)")
        if self.interpolation == "cubic" and len(times) < 4:
            raise FieldError("rows", "cubic interpolation needs at least 4 rows (or use interpolation 'linear')")
        return self


VesselMotion = Annotated[Union[FixedMotion, HarmonicMotion, TableMotion], Field(discriminator="kind")]


class Vessel(_Strict):
    """A vessel with prescribed motion. Its frame has its origin at `position` at rest,
    x forward, z up, turned by `heading_deg` about z. Motions are displacements of the
    vessel origin; rotations are ZYX (yaw, pitch, roll) about the vessel origin."""

    position: Vector3 = _units("m", "Rest position of the vessel origin", default=[0.0, 0.0, 0.0])
    heading_deg: float = _units("deg", "Heading of the vessel x axis from global x, about z", default=0.0)
    motion: VesselMotion = Field(default_factory=FixedMotion)


# --------------------------------------------------------------------------- line types

class ElasticMaterial(_Strict):
    kind: Literal["elastic"] = "elastic"


Material = Annotated[Union[ElasticMaterial], Field(discriminator="kind")]


class StructuralDamping(_Strict):
    """Kelvin-Voigt damping of the SDEs: either damping ratios of the element-level
    axial/bending modes, or explicit coefficients (per unit length, like EA and EI)."""

    axial_ratio: float | None = Field(None, ge=0.0, le=2.0, description="Damping ratio of the axial and shear "
                                      "element modes [-]")
    bending_ratio: float | None = Field(None, ge=0.0, le=2.0, description="Damping ratio of the bending and "
                                        "torsion element modes [-]")
    axial: float | None = _units("N*s", "Axial damping coefficient (stress-rate analogue of EA)", default=None, ge=0.0)
    shear: float | None = _units("N*s", "Shear damping coefficient", default=None, ge=0.0)
    bending: float | None = _units("N*m^2*s", "Bending damping coefficient (analogue of EI)", default=None, ge=0.0)
    torsion: float | None = _units("N*m^2*s", "Torsion damping coefficient (analogue of GJ)", default=None, ge=0.0)

    @model_validator(mode="after")
    def _one_way(self):
        ratios = self.axial_ratio is not None or self.bending_ratio is not None
        explicit = any(v is not None for v in (self.axial, self.shear, self.bending, self.torsion))
        if ratios and explicit:
            raise FieldError("axial_ratio", "give damping either as ratios or as explicit coefficients, not both")
        return self


class LineType(_Strict):
    """Section of a line: a pipe geometry (outer_diameter, wall_thickness, youngs_modulus,
    density) or direct section properties (EA, EIy, EIz, GJ, mass_per_length, GA)."""

    outer_diameter: float | None = _units("m", "Outer diameter (hydrodynamic, buoyancy and contact diameter)",
                                          default=None, gt=0.0)
    wall_thickness: float | None = _units("m", "Wall thickness of a pipe", default=None, gt=0.0)
    youngs_modulus: float | None = _units("Pa", "Young's modulus", default=None, gt=0.0)
    poisson_ratio: float = Field(0.3, gt=-1.0, lt=0.5, description="Poisson's ratio [-]")
    density: float | None = _units("kg/m^3", "Material density of the pipe wall", default=None, gt=0.0)
    contents_density: float = _units("kg/m^3", "Density of the pipe contents (internal fluid)", default=0.0, ge=0.0)

    EA: float | None = _units("N", "Axial stiffness", default=None, gt=0.0)
    EIy: float | None = _units("N*m^2", "Bending stiffness about the local y axis", default=None, ge=0.0)
    EIz: float | None = _units("N*m^2", "Bending stiffness about the local z axis", default=None, ge=0.0)
    GJ: float | None = _units("N*m^2", "Torsional stiffness", default=None, ge=0.0)
    GA: float | None = _units("N", "Effective shear stiffness (kappa already applied)", default=None, gt=0.0)
    mass_per_length: float | None = _units("kg/m", "Mass per unit length (structure and contents)",
                                           default=None, gt=0.0)
    rotary_inertia: float | None = _units("kg*m", "Mass moment of inertia of the section about a transverse "
                                          "axis per unit length (polar: twice this)", default=None, ge=0.0)

    drag_normal: float = Field(0.0, ge=0.0, le=10.0, description="Normal drag coefficient (on outer_diameter) [-]")
    drag_axial: float = Field(0.0, ge=0.0, le=10.0, description="Axial drag coefficient (on pi*outer_diameter) [-]")
    added_mass_normal: float = Field(0.0, ge=0.0, le=10.0, description="Normal added-mass coefficient [-]")
    added_mass_axial: float = Field(0.0, ge=0.0, le=10.0, description="Axial added-mass coefficient [-]")
    material: Material = Field(default_factory=ElasticMaterial)
    damping: StructuralDamping | None = None

    @model_validator(mode="after")
    def _section(self):
        pipe = self.wall_thickness is not None
        if not pipe and self.EA is None and (self.youngs_modulus is not None or self.density is not None):
            raise FieldError("wall_thickness", "a pipe geometry needs wall_thickness (with outer_diameter, "
                                               "youngs_modulus and density); or give direct section properties "
                                               "EA, EIy and mass_per_length")
        if pipe:
            for name in ("outer_diameter", "youngs_modulus", "density"):
                if getattr(self, name) is None:
                    raise FieldError(name, "a pipe geometry (wall_thickness given) needs outer_diameter, "
                                           "wall_thickness, youngs_modulus and density")
            if self.wall_thickness >= 0.5 * self.outer_diameter:
                raise FieldError("wall_thickness", f"{self.wall_thickness} m is not less than the outer radius "
                                                   f"{0.5 * self.outer_diameter} m (outer_diameter/2): impossible "
                                                   f"pipe section (for a solid rod give direct section properties)")
            for name in ("EA", "EIy", "EIz", "GJ", "mass_per_length"):
                if getattr(self, name) is not None:
                    raise FieldError(name, "give either a pipe geometry or direct section properties, not both")
            D = self.outer_diameter
            d = D - 2.0 * self.wall_thickness
            area = math.pi / 4.0 * (D * D - d * d)
            inertia = math.pi / 64.0 * (D ** 4 - d ** 4)
            for name, value in (("EA", self.youngs_modulus * area), ("EI", self.youngs_modulus * inertia)):
                if not (math.isfinite(value) and value > 0.0):
                    raise FieldError("youngs_modulus", f"{self.youngs_modulus} Pa with this pipe geometry gives "
                                                       f"{name} = {value:.6g}: not a usable section stiffness")
            mass = self.density * area + self.contents_density * math.pi / 4.0 * d * d
            if not (math.isfinite(mass) and mass > 0.0):
                raise FieldError("density", f"{self.density} kg/m^3 with this pipe geometry gives a mass per "
                                            f"length of {mass:.6g} kg/m: not a usable section")
        else:
            missing = [n for n in ("EA", "mass_per_length") if getattr(self, n) is None]
            if missing:
                raise FieldError(missing[0], "direct section properties need EA and mass_per_length "
                                             "(or give a pipe geometry: outer_diameter, wall_thickness, "
                                             "youngs_modulus, density)")
            if self.EIy is None and self.EIz is None:
                raise FieldError("EIy", "direct section properties need a bending stiffness EIy (and EIz, "
                                        "which defaults to EIy); use 0 for a flexible cable")
            if self.contents_density > 0.0:
                raise FieldError("contents_density", "only used with a pipe geometry; with direct section "
                                                     "properties include the contents in mass_per_length")
        if self.damping is not None and (self.damping.axial_ratio or self.damping.bending_ratio) is not None:
            pass
        return self


# --------------------------------------------------------------------------- lines

class LineEnd(_Strict):
    attach: str = Field("free", description='"fixed" (global frame), "free", or a vessel name')
    position: Vector3 | None = _units("m", "Position of the end: global for fixed and free ends, in the vessel "
                                      "frame for a vessel", default=None)
    direction: Vector3 | None = Field(None, description="Unit tangent of the line at this end, pointing from "
                                      "end A toward end B (global, or vessel frame for a vessel)")
    connection: Literal["clamped", "pinned"] = Field("pinned", description="clamped: position and orientation "
                                                     "follow the attachment; pinned: position only")

    @model_validator(mode="after")
    def _direction(self):
        if self.direction is not None:
            n = math.sqrt(sum(c * c for c in self.direction))
            if n < 1e-12:
                raise FieldError("direction", "must not be the zero vector")
        return self


class PointLoad(_Strict):
    at: Union[Literal["end_a", "end_b"], float] = Field(..., description='"end_a", "end_b", or the arc length '
                                                        'from end A [m]')
    force: Vector3 = _units("N", "Force", default=[0.0, 0.0, 0.0])
    moment: Vector3 = _units("N*m", "Moment", default=[0.0, 0.0, 0.0])
    frame: Literal["global", "local"] = Field("global", description="global: dead load; local: follows the "
                                              "element (x along the line)")

    @field_validator("at", mode="before")
    @classmethod
    def _at(cls, value):
        if isinstance(value, str):
            if value in ("end_a", "end_b"):
                return value
            try:
                return float(value)
            except ValueError:
                pass
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            return value
        raise ValueError(f"must be 'end_a', 'end_b' or an arc length from end A in m, got {_show(value)}")


MIN_SEGMENT = 1.0e-6      # m, shortest SDE spacing length/elements (the SDE stiffness goes as 1/dx^3)


class Line(_Strict):
    type: str = Field(..., description="Name of a line type")
    length: float = _units("m", "Unstretched length", gt=0.0, le=1.0e7)
    elements: int = Field(..., ge=1, le=100000, description="Number of SDEs (primary division into equal segments)")
    formulation: Literal["absolute"] = Field("absolute", description="RFE formulation (section 8.4 absolute "
                                             "coordinates)")
    shear_stiffness: Literal["fem", "kruszewski"] | None = Field(
        None, description='"fem" (eq. 8.89, default) or "kruszewski" (eq. 8.88). By default a nearly flexible '
                          'line (12EI/dx^3 < 1e-6 GA/dx) uses kruszewski so its elements stay connected')
    end_a: LineEnd = Field(default_factory=LineEnd)
    end_b: LineEnd = Field(default_factory=LineEnd)
    loads: list[PointLoad] = Field(default_factory=list)

    @model_validator(mode="after")
    def _ends(self):
        dx = self.length / self.elements
        if dx < MIN_SEGMENT:
            if self.length < MIN_SEGMENT:
                raise FieldError("length", f"{self.length} m is too short (at least {MIN_SEGMENT} m)")
            raise FieldError("elements", f"{self.elements} elements on {self.length} m make segments of "
                                         f"{dx:.3g} m, shorter than {MIN_SEGMENT} m: use fewer elements")
        if self.end_a.attach == "free" and self.end_b.attach == "free":
            pass  # a free-floating line is allowed in dynamics (statics will be singular and says so)
        if self.end_a.position is None and self.end_a.attach != "free":
            raise FieldError("end_a.position", f"an end attached to '{self.end_a.attach}' needs a position")
        if self.end_b.position is None and self.end_b.attach != "free":
            raise FieldError("end_b.position", f"an end attached to '{self.end_b.attach}' needs a position")
        for i, load in enumerate(self.loads):
            if not isinstance(load.at, str) and not (0.0 <= load.at <= self.length):
                raise FieldError(f"loads.{i}.at", f"arc length {load.at} m is outside the line [0, {self.length}] m")
        return self


# --------------------------------------------------------------------------- analysis

class StaticsSettings(_Strict):
    enabled: bool = True
    tolerance: float = Field(1e-8, gt=0.0, lt=1.0, description="Convergence: largest residual force relative to "
                                                                "the largest applied force [-]")
    max_iterations: int = Field(400, ge=1, le=100000, description="Newton iterations over all load steps")
    load_steps: int = Field(1, ge=1, le=1000, description="Initial number of load steps (halved adaptively "
                                                          "when Newton fails)")
    start: Literal["auto", "straight", "catenary"] = Field(
        "auto", description="Initial shape: auto = catenary for lines with both ends placed and slack, "
                            "straight otherwise")


class RK4Settings(_Strict):
    kind: Literal["rk4"]
    time_step: float | None = _units("s", "Fixed step (default: estimated from the stiffest SDE)",
                                     default=None, gt=0.0)
    safety: float = Field(0.8, gt=0.0, le=1.0, description="Fraction of the estimated stability limit used for "
                                                           "the default step [-]")


class AdaptiveSettings(_Strict):
    kind: Literal["adaptive"]
    rtol: float = Field(1e-6, gt=0.0, lt=1.0)
    atol: float = Field(1e-8, gt=0.0)
    max_step: float | None = _units("s", "Largest step", default=None, gt=0.0)
    first_step: float | None = _units("s", "First step (default: estimated)", default=None, gt=0.0)


class GeneralizedAlphaSettings(_Strict):
    kind: Literal["generalized-alpha"]
    time_step: float = _units("s", "Time step", default=0.01, gt=0.0)
    rho_inf: float = Field(0.8, ge=0.0, le=1.0, description="Spectral radius at infinite frequency "
                                                            "(1: no numerical damping) [-]")
    tolerance: float = Field(1e-6, gt=0.0, lt=1.0, description="Newton tolerance: largest residual force "
                                                               "relative to the largest element weight or point "
                                                               "load [-]")
    max_iterations: int = Field(12, ge=1, le=200)
    jacobian_reuse: bool = Field(True, description="Modified Newton: keep the factorised Jacobian while "
                                                   "Newton converges fast")
    jacobian: Literal["analytic", "finite-difference"] = Field(
        "analytic", description="Jacobian of the SDEs: analytic tangent (fast) or coloured finite differences "
                                "(the reference)")


Integrator = Annotated[Union[RK4Settings, AdaptiveSettings, GeneralizedAlphaSettings], Field(discriminator="kind")]


class DynamicsSettings(_Strict):
    enabled: bool = True
    duration: float = _units("s", "Simulated time", default=0.0, ge=0.0, le=1.0e7)
    integrator: Integrator = Field(default_factory=lambda: GeneralizedAlphaSettings(kind="generalized-alpha"))
    output_interval: float | None = _units("s", "Interval between stored results (default: every step for "
                                           "fixed-step integrators, duration/1000 for adaptive)",
                                           default=None, gt=0.0)


class ModalSettings(_Strict):
    modes: int = Field(10, ge=1, le=10000, description="Number of modes (lowest frequencies)")


class Analysis(_Strict):
    statics: StaticsSettings = Field(default_factory=StaticsSettings)
    dynamics: DynamicsSettings = Field(default_factory=DynamicsSettings)
    modal: ModalSettings | None = None


# --------------------------------------------------------------------------- scenario

class Scenario(_Strict):
    """A complete scene: environment, vessels, line types, lines and analysis settings."""

    schema_version: Literal[1] = 1
    name: str = Field("unnamed", max_length=200)
    description: str = Field("", max_length=10000)
    environment: Environment = Field(default_factory=Environment)
    vessels: dict[str, Vessel] = Field(default_factory=dict)
    line_types: dict[str, LineType] = Field(default_factory=dict)
    lines: dict[str, Line] = Field(default_factory=dict)
    analysis: Analysis = Field(default_factory=Analysis)

    @classmethod
    def model_validate(cls, obj, *args, **kwargs):  # noqa: D102 - converts errors to ScenarioError
        from .load import validate_dict
        if isinstance(obj, cls):
            return obj
        return validate_dict(obj, _raw=lambda o: super(Scenario, cls).model_validate(o, *args, **kwargs))

    @classmethod
    def model_validate_json(cls, data, *args, **kwargs):  # noqa: D102
        from .load import parse_text
        return cls.model_validate(parse_text(data, "json"))
