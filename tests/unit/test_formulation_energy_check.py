"""The energy check of the formulations scenes (chains, classical / modified / planar lines;
rfesim.formulations.energy_check): a closed unit whose mechanical energy grows past a quarter
of its scale stops the run, as the absolute-coordinate dynamics do (EnergyCheck)."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import rfesim
from rfesim.formulations import energy_check
from rfesim.formulations.scene import compile_scene
from rfesim.solvers.dynamics import ENERGY_STOP

G = 9.81


def rod(step: float, duration: float, initial: float = 0.1) -> dict:
    """A rigid 1 m, 1 kg rod pinned at its top (I = m L^2 / 3 about the pin, omega =
    sqrt(3 g / 2 L) = 3.836 rad/s: RK4 is stable up to 2.828 / omega = 0.737 s), released
    from rest at ``initial`` rad, statics off."""
    return {"environment": {"gravity": G},
            "chains": {"pendulum": {"links": {"rod": {"rigid": True, "length": 1.0, "mass": 1.0}},
                                    "joints": {"top": {"kind": "revolute", "parent": "base", "child": "rod",
                                                       "direction": [0, 0, -1], "axis": [0, 1, 0],
                                                       "initial": initial}}}},
            "analysis": {"statics": {"enabled": False},
                         "dynamics": {"duration": duration, "integrator": {"kind": "rk4", "time_step": step}}}}


def rod_energy(theta, rate):
    """Kinetic + gravity energy (J) of the rod, zero potential at the pin's level minus L/2."""
    return 0.5 * rate ** 2 / 3.0 + G * 0.5 * (1.0 - np.cos(theta))


def test_rk4_beyond_its_stability_limit_stops_on_energy_growth():
    # 0.8 s steps, past the 0.737 s limit: the swing grows each step. The run used to finish
    # its 32 s with a rod going over the top; now it stops at the first output past 25 %
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(rod(0.8, 32.0))
    err = info.value
    assert err.quantity == "energy growth" and err.element == "chains.pendulum"
    assert err.time == pytest.approx(0.8)
    assert "RK4 stability limit is about 0.7" in err.hint
    res = err.results
    assert res.status == 1 and len(res.time) == 2          # the outputs up to the one that tripped
    j = res.joint("pendulum.top")
    E = rod_energy(j.coordinate[:, 0], j.rate[:, 0])
    grown = E[-1] - E[0]
    assert grown > ENERGY_STOP * E.max()                      # scale: kinetic max + potential range
    assert f"grew by {grown:.4g} J" in err.hint


def test_stable_step_conserves_and_says_nothing():
    res = rfesim.simulate(rod(0.01, 5.0, initial=0.5))
    assert res.message == "finished: 500 steps"
    j = res.joint("pendulum.top")
    E = rod_energy(j.coordinate[:, 0], j.rate[:, 0])
    assert abs(E[-1] - E[0]) < 1e-5 * E[0]


def test_energies_against_the_rod_formula():
    sc = rfesim.load_scenario(rod(0.01, 1.0))
    unit = compile_scene(sc).chains[0]
    theta = np.array([0.1, -0.4, 1.3])
    rate = np.array([0.0, 2.0, -0.7])
    kin_el, pot, floor = energy_check.chain_energies(unit.model, np.zeros(3), theta[:, None], rate[:, None])
    # the chain's gravity potential is -m g . r_C (zero at the pin): -m g (L/2) cos theta
    assert kin_el == pytest.approx(0.5 * rate ** 2 / 3.0, rel=1e-12)
    assert pot == pytest.approx(-G * 0.5 * np.cos(theta), rel=1e-12)
    assert 0.0 < floor < 1e-8


def test_growth_ratio_follows_the_incremental_rule():
    # E = kin_el + pot; scale = running max of kin_el + running range of pot
    kin_el = np.array([0.0, 2.0, 1.0, 5.0])
    pot = np.array([1.0, -1.0, 0.5, 0.0])
    g = energy_check.growth("u", kin_el, pot, floor=0.0)
    assert g.growth.tolist() == [0.0, 0.0, 0.5, 4.0]
    assert g.scale.tolist() == [0.0, 4.0, 4.0, 7.0]
    assert g.ratio.tolist() == [0.0, 0.0, 0.125, 4.0 / 7.0]
    assert g.first_over(ENERGY_STOP) == 3 and g.first_over(0.9) is None
    bad = energy_check.growth("u", np.array([0.0, math.nan]), np.zeros(2), floor=1e-12)
    assert bad.ratio[1] == math.inf


def test_driven_and_vessel_units_are_open():
    sc = rod(0.01, 1.0)
    driven = copy.deepcopy(sc)
    driven["chains"]["pendulum"]["joints"]["top"]["drive"] = {"kind": "force", "value": 1.0}
    assert compile_scene(rfesim.load_scenario(driven)).chains[0].open == ["joint drives"]
    assert compile_scene(rfesim.load_scenario(sc)).chains[0].open == []
    for motion, expected in (({"kind": "harmonic", "heave": {"amplitude": 1.0, "period": 8.0}},
                              ["a moving vessel base"]), ({"kind": "fixed"}, [])):
        on_ship = copy.deepcopy(sc)
        on_ship["vessels"] = {"ship": {"motion": motion}}
        on_ship["chains"]["pendulum"]["base"] = "ship"
        assert compile_scene(rfesim.load_scenario(on_ship)).chains[0].open == expected
