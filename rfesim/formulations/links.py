"""Links of a kinematic chain: rigid bodies and beams discretised into rigid finite elements.

A link is described in its own frame {p,0}: the beam axis is the local x axis from the
joint (s = 0) to the tip (s = length). `Link.bodies` lists the bodies it compiles to:
body 0 is RFE 0 (it carries the joint with the preceding link, eq. 8.1), the others
hang on it (classical, eq. 8.9) or on each other (modified, eq. 8.38).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .transforms import FIXED, JOINT_COORDS, homogeneous, pseudo_inertia


@dataclass(frozen=True)
class BeamProperties:
    """Section properties of a straight uniform beam (SI units)."""
    EA: float | None              # N, axial stiffness (classical only)
    EIy: float                    # N*m^2, bending about the local y axis
    EIz: float                    # N*m^2, bending about the local z axis
    GJ: float                     # N*m^2, torsion
    mass_per_length: float        # kg/m
    GA: float | None = None       # N, shear stiffness (shear="kruszewski")
    shear: str = "fem"            # "fem": c = 12 EI / d^3 (eq. 8.89); "kruszewski": c = GA / d (eq. 8.88)
    rotary_inertia: float | None = None   # kg*m, section moment about a transverse axis per length
    polar_inertia: float | None = None    # kg*m, section polar moment per length
    damping: float = 0.0          # s, stiffness-proportional Kelvin-Voigt damping: d = damping * c

    def __post_init__(self):
        for name in ("EIy", "EIz", "GJ", "mass_per_length"):
            if not getattr(self, name) >= 0.0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)}")
        if self.shear not in ("fem", "kruszewski"):
            raise ValueError(f"shear must be 'fem' or 'kruszewski', got {self.shear!r}")
        if self.damping < 0.0:
            raise ValueError(f"damping must be >= 0, got {self.damping}")

    @property
    def rotary(self) -> float:
        if self.rotary_inertia is not None:
            return self.rotary_inertia
        if self.EA:
            return self.mass_per_length * 0.5 * (self.EIy + self.EIz) / self.EA   # rho I = mu I / A
        return 0.0

    @property
    def polar(self) -> float:
        return self.polar_inertia if self.polar_inertia is not None else 2.0 * self.rotary

    def element_inertia(self, length: float) -> tuple[float, np.ndarray]:
        """Mass and principal moments (Jx, Jy, Jz) about the centre of an element of a length."""
        m = self.mass_per_length * length
        Jt = m * length ** 2 / 12.0 + self.rotary * length
        return m, np.array([self.polar * length, Jt, Jt])


@dataclass
class BodySpec:
    """One body of a link. parent: index within the link (-1: the link's joint parent)."""
    parent: int
    kind: int
    axis: np.ndarray              # (3,) joint axis (revolute, prismatic)
    placement: np.ndarray         # (4, 4) C, the joint's constant placement in the parent body
    inertia: np.ndarray           # (4, 4) pseudo-inertia H in the body frame
    undeformed: np.ndarray        # (4, 4) body frame in {p,0} when all its coordinates are zero
    s_range: tuple[float, float]  # m, the part of the link axis this body carries
    locked: tuple = ()            # per coordinate: True = held at zero (not a degree of freedom)
    names: tuple = ()             # coordinate names
    stiffness: np.ndarray = field(default_factory=lambda: np.zeros(0))   # per coordinate (eq. 8.49)
    damping: np.ndarray = field(default_factory=lambda: np.zeros(0))


@dataclass
class SdeSpec:
    """A spring-damping element of the classical formulation (eq. 8.21) between two bodies."""
    left: int                     # body index within the link
    right: int
    point_left: np.ndarray        # (3,) SDE position in the left body frame
    point_right: np.ndarray       # (3,) in the right body frame
    stiffness: np.ndarray         # (6,) N/m x3, N*m/rad x3 (eq. 8.21, axes of {p,0})
    damping: np.ndarray           # (6,)


class Link:
    """Base class: a link of a chain. Subclasses build `bodies` and `sdes`."""
    formulation = "rigid"
    length: float

    def bodies(self) -> list[BodySpec]:
        raise NotImplementedError

    def sdes(self) -> list[SdeSpec]:
        return []

    def locate(self, s: float) -> int:
        """Index of the body that carries the axis point at arc length s."""
        if not -1e-12 <= s <= self.length * (1 + 1e-12):
            raise ValueError(f"arc length s={s} outside the link [0, {self.length}]")
        for i, b in enumerate(self.bodies()):
            if b.s_range[0] - 1e-12 <= s <= b.s_range[1] + 1e-12:
                return i
        raise ValueError(f"no body at s={s}")          # pragma: no cover


class RigidLink(Link):
    """A rigid link (m_p = 0): the link is RFE 0 alone (section 8.1.4)."""
    formulation = "rigid"

    def __init__(self, length: float, mass: float, centre=None, inertia=None):
        if not length >= 0.0 or not mass > 0.0:
            raise ValueError(f"rigid link needs length >= 0 and mass > 0, got {length}, {mass}")
        self.length = float(length)
        self.mass = float(mass)
        self.centre = np.array([0.5 * length, 0.0, 0.0]) if centre is None else np.asarray(centre, float)
        if inertia is None:                               # uniform slender rod along x
            Jt = mass * length ** 2 / 12.0
            inertia = np.array([1e-6 * max(Jt, mass * 1e-6), Jt, Jt])
        self.inertia = np.asarray(inertia, float)

    def bodies(self):
        return [BodySpec(parent=-1, kind=FIXED, axis=np.zeros(3), placement=np.eye(4),
                         inertia=pseudo_inertia(self.mass, self.centre, self.inertia), undeformed=np.eye(4),
                         s_range=(0.0, self.length))]


def rfe_lengths(length: float, elements: int) -> np.ndarray:
    """Secondary division (Fig. 8.2): m_p + 1 RFEs, half-length at both ends."""
    if elements < 1:
        raise ValueError(f"elements must be >= 1, got {elements}")
    d = length / elements
    ell = np.full(elements + 1, d)
    ell[0] = ell[-1] = 0.5 * d
    return ell


def sde_translational_stiffness(props: BeamProperties, d: float) -> np.ndarray:
    """c_1..c_3 of an SDE of primary length d: axial EA/d, shear 12 EI/d^3 or GA/d."""
    if props.EA is None or not props.EA > 0.0:
        raise ValueError("the classical formulation needs EA > 0")
    if props.shear == "fem":
        cy, cz = 12.0 * props.EIz / d ** 3, 12.0 * props.EIy / d ** 3
    else:
        if props.GA is None or not props.GA > 0.0:
            raise ValueError("shear='kruszewski' needs GA > 0")
        cy = cz = props.GA / d
    return np.array([props.EA / d, cy, cz])


def body_placement(x: float) -> np.ndarray:
    return homogeneous(translation=(x, 0.0, 0.0))


def check_dofs(dofs, allowed) -> tuple:
    dofs = tuple(allowed if dofs is None else dofs)
    bad = [d for d in dofs if d not in allowed]
    if bad or not dofs:
        raise ValueError(f"dofs must be a non-empty subset of {allowed}, got {dofs}")
    return dofs


def joint_coordinate_count(kind: int) -> int:
    return JOINT_COORDS[kind]
