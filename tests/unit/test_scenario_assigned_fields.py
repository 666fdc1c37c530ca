"""A Scenario whose fields were assigned after validation is validated again by the entry
points (rfesim.scenario.load.load_scenario, rfesim.api._scenario): pydantic does not check an
assignment, so ``sc.environment.water.density = -1025`` used to run and give a top tension
5.7 times too large, and ``length = -600`` a ZeroDivisionError from the model build."""
from __future__ import annotations

import copy
import glob
import os

import numpy as np
import pytest

import rfesim
from rfesim import ScenarioError
from scenes import RISER

SCENARIOS = os.path.join(os.path.dirname(__file__), "..", "..", "scenarios")


def _riser(**dyn):
    d = copy.deepcopy(RISER)
    d["analysis"]["dynamics"].update(dyn)
    return rfesim.load_scenario(d)


@pytest.mark.parametrize("assign, field, reason", [
    (lambda s: setattr(s.environment.water, "density", -1025.0), "environment.water.density",
     "must be greater than 0"),
    (lambda s: setattr(s.lines["riser"], "length", -600.0), "lines.riser.length", "must be greater than 0"),
    (lambda s: setattr(s.lines["riser"], "length", "abc"), "lines.riser.length", "must be a number"),
    (lambda s: setattr(s.lines["riser"], "elements", 12.7), "lines.riser.elements", "whole number"),
    (lambda s: setattr(s.lines["riser"].end_b, "connection", "Clamped"), "lines.riser.end_b.connection",
     "must be 'clamped' or 'pinned'"),
    (lambda s: setattr(s.line_types["pipe"], "wall_thickness", 0.2), "line_types.pipe.wall_thickness",
     "outer radius"),
    (lambda s: setattr(s.environment.seabed, "normal_stiffness", -1e6),
     "environment.seabed.normal_stiffness", "greater than or equal to"),
])
@pytest.mark.parametrize("entry", ["statics", "simulate", "modes", "load_scenario"])
def test_an_assigned_bad_value_is_refused_naming_the_field(assign, field, reason, entry):
    sc = _riser()
    assign(sc)
    with pytest.raises(ScenarioError) as info:
        getattr(rfesim, entry)(sc)
    text = str(info.value)
    assert text.startswith(field + ":"), text
    assert reason in text, text


def test_an_assigned_good_value_is_used_and_the_instance_is_left_alone():
    sc = _riser()
    base = rfesim.statics(sc).line("riser")
    sc.environment.water.density = 1100.0          # more buoyancy: less submerged weight
    st = rfesim.statics(sc)
    # the riser's submerged weight falls by (1100 - 1025) g A_outer per metre; its top
    # tension (to the heaving ship, about 70 % of the weight hangs from it) must fall
    assert st.line("riser").top_tension[-1] < base.top_tension[-1] - 100.0
    assert sc.environment.water.density == 1100.0
    assert rfesim.load_scenario(st.scenario_json).environment.water.density == 1100.0   # stored as run
    sc.lines["riser"].end_b.connection = "clamped"          # pinned carries no moment
    assert np.linalg.norm(base.end_b_moment[-1]) == 0.0
    assert np.linalg.norm(rfesim.statics(sc).line("riser").end_b_moment[-1]) > 1.0


def test_model_validate_then_assign_is_caught_too():
    sc = rfesim.Scenario.model_validate(copy.deepcopy(RISER))
    sc.analysis.dynamics.integrator.kind = "rk4"          # the generalized-alpha object, relabelled
    with pytest.raises(ScenarioError, match=r"analysis\.dynamics\.integrator\.rho_inf: unknown key"):
        rfesim.simulate(sc)


@pytest.mark.parametrize("path", sorted(glob.glob(os.path.join(SCENARIOS, "*.json"))),
                         ids=lambda p: os.path.basename(p))
def test_validating_a_bundled_scenario_again_gives_an_equal_one(path):
    sc = rfesim.load_scenario(path)
    again = rfesim.load_scenario(sc)
    assert again is not sc
    assert again == sc
    assert again._template_warnings == sc._template_warnings
