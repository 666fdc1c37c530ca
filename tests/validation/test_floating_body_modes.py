"""Modal analysis (rfesim.modes) of bodies at the water surface against closed forms: a buoy
on a taut tether heaves on its waterplane and tether stiffness, and its tether's spin is a
zero mode, not an instability; a tall box hung at its centre, half submerged, capsizes at the
rate its wall-sided hydrostatic moment gives (rfesim.loads.bodies, rfesim.solvers.modal)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim

G, RHO = 9.81, 1025.0


def tethered_buoy(rope_mass: float) -> dict:
    """1 t, V = 2 m^3, height 2 m, ca_z = 1; an 18 m tether (EA 3.24e5 N) from an anchor 20 m
    down to 1 m below the buoy's centre."""
    return {"environment": {"gravity": G, "water": {"density": RHO, "depth": 20.0}},
            "line_types": {"rope": {"EA": 3.24e5, "EIy": 1.0, "mass_per_length": rope_mass, "tension_only": True}},
            "bodies": {"buoy": {"mass": 1000.0, "inertia": [500.0, 500.0, 500.0], "volume": 2.0, "height": 2.0,
                                "added_mass": {"ca": [0.5, 0.5, 1.0]}, "position": [0.0, 0.0, -1.0]}},
            "lines": {"tether": {"type": "rope", "length": 18.0, "elements": 6,
                                 "end_a": {"attach": "fixed", "position": [0.0, 0.0, -20.0]},
                                 "end_b": {"attach": "buoy", "position": [0.0, 0.0, -1.0]}}},
            "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}}}


@pytest.mark.parametrize("rope_mass", [1.0, 0.01])
def test_a_tethered_buoy_heaves_on_its_waterplane_and_its_tethers_spin_is_no_instability(rope_mass):
    """Heave: omega^2 = (rho g V / h + k) / (m + f ca_z rho V + m_r / 3), k = 1 / (L / EA +
    Delta / (100 EA)) the tether with the body connection, f the submerged fraction of the
    statics (0.816): 0.5153 Hz within 3e-5 (measured 1e-7 on the 0.01 kg/m rope, 1.2e-5 on the
    1 kg/m one, whose 6 lumped elements differ from m_r / 3). The taut tether spinning about its
    own axis moves no point; its omega^2 came out at -1e-15 of the scale max K_ii / M_ii
    (-2.4e-5 Hz with a 1 kg/m rope, -4.1e-4 Hz with 0.01 kg/m) and was reported as an
    unstable static state; it is a zero mode."""
    scene = tethered_buoy(rope_mass)
    st = rfesim.statics(scene)
    f0 = float(st.body("buoy").submerged_fraction[0])
    assert 0.8 < f0 < 0.83
    md = rfesim.api.modes(scene, n=6)
    assert md.unstable == 0 and "unstable" not in md.message
    assert md.frequencies_hz[0] == 0.0
    k = 1.0 / (18.0 / 3.24e5 + (18.0 / 6) / (100.0 * 3.24e5))
    heave = math.sqrt((RHO * G * 2.0 / 2.0 + k) / (1000.0 + f0 * RHO * 2.0 + rope_mass * 18.0 / 3.0)) / (2.0 * math.pi)
    assert np.min(np.abs(md.frequencies_hz - heave)) < 3e-5 * heave


@pytest.mark.parametrize("ea, elements", [(1e8, 5), (1e10, 20)])
def test_a_tall_box_hung_at_its_centre_capsizes_at_its_wall_sided_rate(ea, elements):
    """A 1 x 1 x 4 m box (V = 4 m^3, 8 t, I = 8000 kg m^2 about x and y) hung by its centre,
    half submerged: the buoyancy of the lower half acts c/2 = 1 m below the centre and the
    waterplane gives BM = a^2 / (3 c) = 0.0417 m (half-sides a = 0.5, c = 2), so GM = -0.958 m
    and omega^2 = rho g (V / 2) GM / I = -2.409 s^-2 in roll and in pitch: two unstable modes
    at -sqrt(2.409) / (2 pi) Hz, within 1e-4. Turning about its shackle, the box moves no
    point of the rope, like a spin, and on the stiff 20-element rope its omega^2 is 1e-13 of
    the scale max K_ii / M_ii: it is still reported, as its own stiffness is all hydrostatic."""
    half = {"a": 0.5, "c": 2.0}
    scene = {"environment": {"gravity": G, "water": {"density": RHO, "depth": 50.0}},
             "line_types": {"rope": {"EA": ea, "EIy": 1.0, "mass_per_length": 1.0, "tension_only": True}},
             "bodies": {"box": {"mass": 8000.0, "inertia": [8000.0, 8000.0, 1000.0], "volume": 4.0,
                                "dimensions": [1.0, 1.0, 4.0], "position": [0.0, 0.0, 0.0]}},
             "lines": {"hoist": {"type": "rope", "length": 10.0, "elements": elements,
                                 "end_a": {"attach": "fixed", "position": [0.0, 0.0, 10.0]},
                                 "end_b": {"attach": "box", "position": [0.0, 0.0, 0.0]}}},
             "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}}}
    md = rfesim.api.modes(scene, n=6)
    gm = half["a"] ** 2 / (3.0 * half["c"]) - half["c"] / 2.0
    omega2 = RHO * G * 2.0 * gm / 8000.0
    assert md.unstable == 2 and "unstable" in md.message
    np.testing.assert_allclose(md.frequencies_hz[:2], -math.sqrt(-omega2) / (2.0 * math.pi), rtol=1e-4)
    assert np.abs(md.line_shapes["hoist"][:2]).max() < 1e-6
