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
    sc.lines["riser"].length = 0.0
    with pytest.raises(ScenarioError, match=r"^lines\.riser\.length: must be greater than 0"):
        rfesim.simulate(sc)


def test_an_assignment_is_put_into_the_input_as_an_override_would():
    """Relabelling the generalized-alpha settings as rk4 changes the input's kind only: the
    settings the input did not give (rho_inf, tolerance, ...) are not carried over, as with
    load_scenario(..., overrides={"analysis.dynamics.integrator.kind": "rk4"})."""
    sc = rfesim.Scenario.model_validate(copy.deepcopy(RISER))
    sc.analysis.dynamics.integrator.kind = "rk4"
    again = rfesim.load_scenario(sc)
    same = rfesim.load_scenario(copy.deepcopy(RISER), overrides={"analysis.dynamics.integrator.kind": "rk4"})
    assert again == same
    assert again.analysis.dynamics.integrator.kind == "rk4" and again.analysis.dynamics.integrator.time_step == 0.05


@pytest.mark.parametrize("path", sorted(glob.glob(os.path.join(SCENARIOS, "*.json"))),
                         ids=lambda p: os.path.basename(p))
def test_a_bundled_scenario_unchanged_is_taken_as_it_is_and_a_change_is_validated(path):
    sc = rfesim.load_scenario(path)
    assert rfesim.load_scenario(sc) is sc
    sc.name = "changed"
    again = rfesim.load_scenario(sc)
    assert again is not sc and again.name == "changed"
    assert again.model_dump() == sc.model_dump()
    assert again._template_warnings == sc._template_warnings


def test_a_line_tugger_without_body_point_stays_valid():
    """A tugger on a line refuses body_point when it is given; a default filled in must not
    count as given when the scenario is validated again (review of this change)."""
    d = copy.deepcopy(RISER)
    d["tuggers"] = {"t1": {"line": "riser", "at": 50.0, "vessel": "ship", "deck_point": [0.0, 0.0, 0.0],
                           "mode": {"kind": "tension", "tension": 1000.0}}}
    sc = rfesim.load_scenario(d)
    sc.tuggers["t1"].mode.tension = 2000.0
    again = rfesim.load_scenario(sc)
    assert again.tuggers["t1"].mode.tension == 2000.0
    assert again.tuggers["t1"].body_point == sc.tuggers["t1"].body_point


def test_values_a_validator_filled_in_do_not_count_as_given():
    """A bilinear law fills in hardening_ratio 0; changing the law by assignment must not
    find that filled value "given" for a law that does not use it."""
    d = copy.deepcopy(RISER)
    d["line_types"]["pipe"]["material"] = {"kind": "elastoplastic", "law": "bilinear", "yield_stress": 450e6}
    sc = rfesim.load_scenario(d)
    assert sc.line_types["pipe"].material.hardening_ratio == 0.0
    sc.line_types["pipe"].material.law = "ramberg-osgood"
    sc.line_types["pipe"].material.ro_n = 15.0
    again = rfesim.load_scenario(sc)
    assert again.line_types["pipe"].material.law == "ramberg-osgood"


def test_numpy_values_assigned_by_a_script_are_taken_as_numbers():
    sc = _riser()
    sc.lines["riser"].elements = np.int64(20)
    sc.environment.water.density = np.float32(1030.0)
    sc.lines["riser"].end_a.position = np.array([-70.0, 0.0, -49.9])
    again = rfesim.load_scenario(sc)
    assert again.lines["riser"].elements == 20 and type(again.lines["riser"].elements) is int
    assert again.environment.water.density == pytest.approx(1030.0)
    assert list(again.lines["riser"].end_a.position) == [-70.0, 0.0, -49.9]


def test_an_entry_added_or_removed_by_assignment_is_validated():
    sc = _riser()
    sc.lines["riser2"] = sc.lines["riser"].model_copy(update={"length": -1.0})
    with pytest.raises(ScenarioError, match=r"^lines\.riser2\.length: must be greater than 0"):
        rfesim.load_scenario(sc)
    del sc.lines["riser2"]
    del sc.line_types["pipe"]
    with pytest.raises(ScenarioError, match="pipe"):
        rfesim.load_scenario(sc)


def test_a_field_assigned_in_a_section_the_input_left_out_gets_only_that_field():
    d = copy.deepcopy(RISER)
    del d["analysis"]["statics"]                    # the defaults
    sc = rfesim.load_scenario(d)
    sc.analysis.statics.max_iterations = 77
    again = rfesim.load_scenario(sc)
    assert again.analysis.statics.max_iterations == 77
    assert again.analysis.statics.model_fields_set == {"max_iterations"}
