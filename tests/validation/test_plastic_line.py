"""The elasto-plastic SDE inside a line (section 8.4.2): a pipe bent by an end moment past
yield follows the section's moment-curvature; unloaded, it keeps the residual curvature
kappa - M/EI (elastic unloading); committed history carries from one solve to the next."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.materials.section import PipeWall, moment_curvature, plastic_moment
from rfesim.materials.stress_strain import Bilinear
from rfesim.model.compile import compile_scenario
from rfesim.solvers.statics import solve_statics
from rfesim.solvers.system import System

D, T, E, SY = 0.3239, 0.0159, 2.07e11, 448e6
EI = E * np.pi / 64 * (D ** 4 - (D - 2 * T) ** 4)


def bent_pipe(moment, hardening=0.02, elements=10):
    return rfesim.Scenario.model_validate({
        "environment": {"gravity": 0.0},
        "line_types": {"x65": {"outer_diameter": D, "wall_thickness": T, "youngs_modulus": E, "density": 7850.0,
                               "material": {"kind": "elastoplastic", "yield_stress": SY,
                                            "hardening_ratio": hardening}}},
        "lines": {"pipe": {"type": "x65", "length": 2.0, "elements": elements,
                           "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                     "connection": "clamped"},
                           "end_b": {"attach": "free"},
                           "loads": [{"at": "end_b", "moment": [0.0, 0.0, moment]}]}},
        "analysis": {"dynamics": {"enabled": False}, "statics": {"load_steps": 4}},
    })


def test_bent_past_yield_then_released_keeps_the_residual_curvature():
    law = Bilinear(E, SY, 0.02)
    wall = PipeWall(D, T, E)
    mp = plastic_moment(Bilinear(E, SY, 0.0), wall)
    m_load = 1.04 * mp
    # loading: the curvature of every SDE is where the section's curve reaches the moment
    sc = bent_pipe(m_load)
    system = System(compile_scenario(sc))
    state, _ = solve_statics(system, load_steps=4)
    system.evaluate(state)
    kappa = system.ws.eps[:, 5] / system.km.sde_length
    assert np.ptp(kappa) < 1e-4 * kappa.mean()                        # uniform moment, uniform curvature
    assert float(moment_curvature(law, wall, kappa.mean())) == pytest.approx(m_load, rel=2e-3)
    assert kappa.mean() > 4.0 * SY / E / (0.5 * D)                     # well past yield
    # unloading: the same line without the moment, from the loaded state and its history
    unloaded = System(compile_scenario(bent_pipe(0.0)))
    unloaded.set_history(system.history())
    state2, _ = solve_statics(unloaded, state)
    unloaded.evaluate(state2)
    residual = unloaded.ws.eps[:, 5] / unloaded.km.sde_length
    assert residual.mean() == pytest.approx(kappa.mean() - m_load / EI, rel=2e-3)
    assert np.abs(unloaded.ws.sigma[:, 5]).max() < 1e-6 * mp           # no moment left
    # an elastic pipe under the same moment springs back straight
    el = rfesim.statics(bent_pipe(0.0))
    assert np.abs(el.line("pipe").curvature[0]).max() < 1e-12


def test_elastic_below_yield_equals_the_elastic_line():
    """Below the yield moment the plastic SDE is the elastic one (to the law's round-off)."""
    m = 0.5 * 506.01e3
    res = rfesim.statics(bent_pipe(m))
    kappa = res.line("pipe").curvature[0]
    assert kappa == pytest.approx(np.full_like(kappa, m / EI), rel=1e-9)


def test_stress_outputs_of_a_bent_pipe():
    """Pure bending below yield: von Mises at the outer fibre = M r_o / I, utilisation over 448 MPa."""
    m = 0.5 * 506.01e3
    res = rfesim.statics(bent_pipe(m))
    line = res.line("pipe")
    inertia = np.pi / 64 * (D ** 4 - (D - 2 * T) ** 4)
    assert line.von_mises_stress[0] == pytest.approx(np.full(10, m * 0.5 * D / inertia), rel=1e-6)
    assert line.utilisation[0] == pytest.approx(line.von_mises_stress[0] / SY, rel=1e-12)
    assert line.utilisation[0].max() == pytest.approx(0.5, rel=1e-3)       # half the yield moment
