"""Elasto-plastic pipe material (section 8.4.2): uniaxial stress-strain laws, the fibre
model of the pipe wall (moment-curvature, cyclic), and the SDE bending law with memory
used by the RFE kernels (docs/theory.md, "Elasto-plastic SDE")."""
from .section import FibreSection, PipeWall, moment_curvature, plastic_moment, reeling, yield_curvature, yield_moment
from .sde_plastic import (PlasticSection, pack_params, pipe_stress_into, plastic_bending_into, plastic_params,
                          plastic_section)
from .stress_strain import Bilinear, RambergOsgood, TabulatedLaw, elastic_perfectly_plastic, law_from_material

__all__ = ["Bilinear", "RambergOsgood", "TabulatedLaw", "elastic_perfectly_plastic", "law_from_material",
           "PipeWall", "FibreSection", "moment_curvature", "yield_moment", "plastic_moment", "yield_curvature",
           "reeling", "PlasticSection", "plastic_section", "plastic_params", "pack_params",
           "plastic_bending_into", "pipe_stress_into"]
