"""Statics of lines cut into many short elements (rfesim.solvers.statics, MU_MIN): the softest
mode of a line of n elements sits at about 1/n^4 of its stiffest, and a Levenberg damping above
it had turned Newton into a slow linear iteration (the 10 m cantilever of
scenarios/cantilever_pipe.json: 29 iterations on 300 elements, no convergence on 1000)."""
from __future__ import annotations

import math

import pytest

import rfesim

D, T_WALL, E, RHO, G = 0.3239, 0.0159, 2.07e11, 7850.0, 9.81


@pytest.mark.parametrize("elements", [300, 1000])
def test_a_cantilever_of_many_elements_converges_to_beam_theory(elements):
    """Tip deflection of the 10 m clamped pipe under its weight q and the 1 kN tip load P:
    P L^3 / 3EI + q L^4 / 8EI = 4.7909 cm (Euler-Bernoulli), within 2e-4; in a few iterations."""
    sc = rfesim.load_scenario("scenarios/cantilever_pipe.json",
                              overrides={"lines.pipe.elements": elements, "analysis.dynamics.enabled": False,
                                         "analysis.modal": None})
    res = rfesim.statics(sc)
    EI = E * math.pi / 64.0 * (D ** 4 - (D - 2 * T_WALL) ** 4)
    q = RHO * math.pi / 4.0 * (D ** 2 - (D - 2 * T_WALL) ** 2) * G
    expected = 1000.0 * 10.0 ** 3 / (3 * EI) + q * 10.0 ** 4 / (8 * EI)
    assert -res.line("pipe").position[0][-1][2] == pytest.approx(expected, rel=2e-4)
    assert res.counters["newton_iterations"] <= 10
