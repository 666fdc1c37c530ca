"""Von Mises stress and utilisation of elasto-plastic pipe with hydrostatic pressure
(docs/theory.md, "Elasto-plastic SDE", stresses): the SDE axial force is the effective
tension, the wall carries T = T_eff + p_i A_i - p_e A_e, and the hoop and radial stresses
are Lame's.

X65 12.75" x 0.625" (D = 0.3239 m, t = 0.0159 m, sigma_y = 448 MPa), steel 7850 kg/m^3,
sea water 1025 kg/m^3, g = 9.81 m/s^2, hanging vertically from a pin with a free lower end.
Hand numbers (r_o = 0.16195 m, r_i = 0.14605 m):
A_s = pi (r_o^2 - r_i^2) = 0.0153850 m^2, A_e = pi r_o^2 = 0.0823971 m^2,
A_i = pi r_i^2 = 0.0670121 m^2, r_o^2 / (r_o^2 - r_i^2) = A_e / A_s = 5.355673.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim

D, T, SY = 0.3239, 0.0159, 448e6
RHO_S, RHO_W, G = 7850.0, 1025.0, 9.81
RO, RI = 0.5 * D, 0.5 * D - T
AS, AE, AI = math.pi * (RO ** 2 - RI ** 2), math.pi * RO ** 2, math.pi * RI ** 2


def hanging(top_z: float, length: float, elements: int, contents: float = 0.0):
    return rfesim.Scenario.model_validate({
        "environment": {"gravity": G, "water": {"density": RHO_W, "depth": 1600.0}},
        "line_types": {"p": {"outer_diameter": D, "wall_thickness": T, "youngs_modulus": 2.07e11,
                             "density": RHO_S, "contents_density": contents,
                             "material": {"kind": "elastoplastic", "yield_stress": SY, "hardening_ratio": 0.0}}},
        "lines": {"p": {"type": "p", "length": length, "elements": elements,
                        "end_a": {"attach": "fixed", "position": [0, 0, top_z], "connection": "pinned"},
                        "end_b": {"attach": "free"}}},
        "analysis": {"statics": {"enabled": True}, "dynamics": {"duration": 0.1}},
    })


@pytest.fixture(scope="module")
def air_filled():
    """Top 10 m above the surface, 1510 m long, 151 SDEs 10 m apart: the first SDE is at
    z = +5 m (dry), the last at z = -1495 m (+ the stretch, 0.13 m)."""
    return rfesim.statics(hanging(10.0, 1510.0, 151)).line("p")


def test_deep_end_of_an_air_filled_pipe(air_filled):
    """Bottom SDE, 5 m above the free end, z = -1495 m:
    T_eff = 5 m x (7850 A_s - 1025 A_e) g = 5 x 356.25 N/m = 1781.3 N,
    p_e = 1025 x 9.81 x 1495 = 15.0326 MPa, p_i = 0;
    sigma_x = (T_eff - p_e A_e) / A_s = 0.116 - 80.510 = -80.394 MPa (true wall);
    Lame at the inner fibre: sigma_h = -2 p_e r_o^2 / (r_o^2 - r_i^2) = -161.019 MPa,
    sigma_r = 0; von Mises sqrt(sx^2 + sh^2 - sx sh) = 139.447 MPa, the largest (outer
    fibre: sigma_h = -p_e (r_o^2 + r_i^2)/(r_o^2 - r_i^2) = -146.0, sigma_r = -15.03,
    von Mises 113.4 MPa); utilisation 139.447 / 448 = 0.31127.
    (Before the pressure terms the output was T_eff / A_s = 0.116 MPa.)"""
    line = air_filled
    t_eff = 5.0 * (RHO_S * AS - RHO_W * AE) * G
    assert line.tension[-1][-1] == pytest.approx(t_eff, rel=2e-3)
    pe = RHO_W * G * 1495.0
    sx = (t_eff - pe * AE) / AS
    sh = -2.0 * pe * RO ** 2 / (RO ** 2 - RI ** 2)
    vm = math.sqrt(sx * sx + sh * sh - sx * sh)
    assert sx / 1e6 == pytest.approx(-80.394, abs=1e-3)
    assert vm / 1e6 == pytest.approx(139.447, abs=1e-3)
    assert line.von_mises_stress[-1][-1] == pytest.approx(vm, rel=1e-3)      # stretch: z is 0.13 m deeper
    assert line.utilisation[-1][-1] == pytest.approx(0.31127, rel=1e-3)
    # deeper down, more stress: von Mises grows from the surface to the free end below it
    vm_wet = line.von_mises_stress[-1][1:]
    assert np.all(np.diff(vm_wet[-100:]) > 0.0)


def test_dry_top_of_the_pipe_is_tension_over_area(air_filled):
    """Top SDE at z = +5 m, above the surface: no pressure, von Mises = T / A_s
    (T ~ 1505 m x 356 N/m + 5 m of dry pipe ~ 0.54 MN, ~35 MPa)."""
    line = air_filled
    assert line.position[-1][1][2] > 0.0
    t = line.tension[-1][0]
    assert t / AS / 1e6 == pytest.approx(35.0, rel=0.02)
    assert line.von_mises_stress[-1][0] == pytest.approx(t / AS, rel=1e-12)
    assert line.utilisation[-1][0] == pytest.approx(t / AS / SY, rel=1e-12)


def test_flooded_pipe_von_mises_is_the_effective_tension_stress():
    """Flooded (contents 1025 kg/m^3) with its top at the surface: p_i = p_e = p at every SDE,
    so T_true = T_eff - p A_s, sigma_x = T_eff/A_s - p, sigma_h = sigma_r = -p: the
    pressure cancels from the deviator and von Mises = T_eff / A_s (no bending).
    T_eff = (7850 - 1025) A_s g x (length below), so von Mises = 6825 x 9.81 x (length
    below) = 66.953 kPa/m: 100.09 MPa at the top SDE (1495 m below), 0.335 MPa at the bottom one.
    The air-filled pipe of the same length has 139.4 MPa at the bottom."""
    line = rfesim.statics(hanging(0.0, 1500.0, 150, contents=RHO_W)).line("p")
    t = line.tension[-1]
    vm = line.von_mises_stress[-1]
    np.testing.assert_allclose(vm, np.abs(t) / AS, rtol=1e-9)
    below = 1500.0 - 10.0 * np.arange(150) - 5.0
    np.testing.assert_allclose(vm, (RHO_S - RHO_W) * G * below, rtol=2e-3)
    assert vm[0] / 1e6 == pytest.approx(100.09, rel=1e-3)
    np.testing.assert_allclose(line.utilisation[-1], vm / SY, rtol=1e-12)


def test_dynamics_records_the_same_stresses():
    """The dynamic run's recording (a short one from the static state) gives the statics'
    von Mises stresses (a shorter pipe: 300 m, top 10 m above the surface)."""
    sc = hanging(10.0, 310.0, 31)
    st = rfesim.statics(sc).line("p")
    dyn = rfesim.simulate(sc).line("p")
    np.testing.assert_allclose(dyn.von_mises_stress[0], st.von_mises_stress[-1], rtol=1e-6)
    np.testing.assert_allclose(dyn.von_mises_stress[-1], st.von_mises_stress[-1], rtol=1e-3)
    # bottom SDE at z = -295 m: p_e = 2.9663 MPa, sigma_x ~ -p_e A_e/A_s, sigma_h(r_i) = 2 sigma_x
    pe = RHO_W * G * 295.0
    sh = -2.0 * pe * RO ** 2 / (RO ** 2 - RI ** 2)
    assert dyn.von_mises_stress[-1][-1] == pytest.approx(0.5 * math.sqrt(3.0) * abs(sh), rel=2e-3)
