"""Section properties of a line type: pipe geometry or direct properties."""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Section:
    EA: float                 # N
    EIy: float                # N*m^2
    EIz: float                # N*m^2
    GJ: float                 # N*m^2
    GA: float                 # N, effective shear stiffness (shear coefficient applied)
    mass_per_length: float    # kg/m, structure and contents
    rotary_inertia: float     # kg*m, section mass moment about a transverse axis per unit length
    polar_inertia: float      # kg*m, section polar mass moment per unit length
    outer_diameter: float     # m (0: unknown; no sea loads, no contact radius)
    displaced_area: float     # m^2, outer area per unit length (buoyancy)
    steel_area: float         # m^2, wall area (stress outputs), 0 if unknown
    drag_normal: float
    drag_axial: float
    added_mass_normal: float
    added_mass_axial: float

    @property
    def EI_min(self) -> float:
        return min(self.EIy, self.EIz)


def cowper_shear_coefficient(outer_diameter: float, inner_diameter: float, poisson: float) -> float:
    """Timoshenko shear coefficient of a hollow circular section (Cowper 1966)."""
    m = inner_diameter / outer_diameter
    m2 = m * m
    num = 6.0 * (1.0 + poisson) * (1.0 + m2) ** 2
    den = (7.0 + 6.0 * poisson) * (1.0 + m2) ** 2 + (20.0 + 12.0 * poisson) * m2
    return num / den


def section_from_type(lt) -> Section:
    """Section of a scenario LineType (validated already)."""
    nu = lt.poisson_ratio
    if lt.wall_thickness is not None:
        D = lt.outer_diameter
        d = D - 2.0 * lt.wall_thickness
        A = math.pi / 4.0 * (D * D - d * d)
        I = math.pi / 64.0 * (D ** 4 - d ** 4)
        E = lt.youngs_modulus
        G = E / (2.0 * (1.0 + nu))
        k = cowper_shear_coefficient(D, d, nu)
        mass = lt.density * A + lt.contents_density * math.pi / 4.0 * d * d
        rotary = lt.density * I if lt.rotary_inertia is None else lt.rotary_inertia
        return Section(EA=E * A, EIy=E * I, EIz=E * I, GJ=G * 2.0 * I, GA=k * G * A, mass_per_length=mass,
                       rotary_inertia=rotary, polar_inertia=2.0 * rotary, outer_diameter=D,
                       displaced_area=math.pi / 4.0 * D * D, steel_area=A,
                       drag_normal=lt.drag_normal, drag_axial=lt.drag_axial,
                       added_mass_normal=lt.added_mass_normal, added_mass_axial=lt.added_mass_axial)
    EIy = lt.EIy if lt.EIy is not None else lt.EIz
    EIz = lt.EIz if lt.EIz is not None else EIy
    GJ = lt.GJ if lt.GJ is not None else 0.5 * (EIy + EIz) / (1.0 + nu)
    GA = lt.GA if lt.GA is not None else 0.5 * lt.EA / (2.0 * (1.0 + nu))
    mu = lt.mass_per_length
    if lt.rotary_inertia is not None:
        rotary = lt.rotary_inertia
    else:
        rotary = mu * 0.5 * (EIy + EIz) / lt.EA       # homogeneous section: rho I = mu I / A
    D = lt.outer_diameter or 0.0
    return Section(EA=lt.EA, EIy=EIy, EIz=EIz, GJ=GJ, GA=GA, mass_per_length=mu, rotary_inertia=rotary,
                   polar_inertia=2.0 * rotary, outer_diameter=D, displaced_area=math.pi / 4.0 * D * D,
                   steel_area=0.0, drag_normal=lt.drag_normal, drag_axial=lt.drag_axial,
                   added_mass_normal=lt.added_mass_normal, added_mass_axial=lt.added_mass_axial)
