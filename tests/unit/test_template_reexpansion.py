"""A scenario made from pipelay / crane templates keeps its input with the templates: a change
on the loaded scenario (an override, an assignment, a sweep from it) expands the templates
again, as from the file; a value for an entry a template makes goes onto the template field
it copies, or is refused naming the template field (rfesim.scenario.load.template_route)."""
from __future__ import annotations

import os

import pytest

import rfesim
from rfesim import ScenarioError
from rfesim.sweep import build_cases

HERE = os.path.dirname(__file__)
S_LAY = os.path.join(HERE, "..", "..", "scenarios", "s_lay_template.json")
J_LAY = os.path.join(HERE, "..", "..", "scenarios", "j_lay.json")
CRANE = os.path.join(HERE, "..", "..", "scenarios", "column_crane.json")


def _end_b_z(sc) -> float:
    return sc.lines["lay"].end_b.position[2]


def test_the_base_lays_the_pipe_on_its_seabed():
    sc = rfesim.load_scenario(S_LAY)
    assert sc.environment.water.depth == 130.0
    assert _end_b_z(sc) == pytest.approx(-129.838, abs=1e-3)


def test_an_override_on_a_loaded_scenario_expands_the_template_again():
    # was: end B kept at z -129.84 m, 30 m above the 160 m seabed
    from_file = rfesim.load_scenario(S_LAY, overrides={"environment.water.depth": 160.0})
    loaded = rfesim.load_scenario(rfesim.load_scenario(S_LAY), overrides={"environment.water.depth": 160.0})
    assert _end_b_z(from_file) == pytest.approx(-159.838, abs=1e-3)
    assert _end_b_z(loaded) == pytest.approx(-159.838, abs=1e-3)
    assert loaded == from_file
    assert loaded.lines["lay"].length == pytest.approx(500.95, abs=0.01)     # was 453.70


def test_an_assignment_on_a_loaded_scenario_expands_the_template_again():
    sc = rfesim.load_scenario(S_LAY)
    sc.environment.water.depth = 160.0
    again = rfesim.load_scenario(sc)
    assert _end_b_z(again) == pytest.approx(-159.838, abs=1e-3)
    assert again == rfesim.load_scenario(S_LAY, overrides={"environment.water.depth": 160.0})


def test_statics_of_an_assigned_depth_lays_the_pipe_on_the_new_seabed():
    # was: top tension 200.02 kN, no touchdown, "converged"; from the file 207.97 kN
    sc = rfesim.load_scenario(S_LAY)
    sc.analysis.dynamics.enabled = False
    sc.environment.water.depth = 160.0
    st = rfesim.statics(sc)
    assert st.tensioners["lay_tensioner"].grip_force[0] == pytest.approx(207968.6, rel=1e-4)
    assert st.line("lay").touchdown_arc_length[0] == pytest.approx(465.0, abs=0.5)


def test_a_sweep_from_a_loaded_scenario_expands_the_template_in_every_case():
    cases = build_cases(rfesim.load_scenario(S_LAY), {"environment.water.depth": [130.0, 160.0]})
    z = [_end_b_z(rfesim.load_scenario(data)) for _, data in cases]
    assert z == pytest.approx([-129.838, -159.838], abs=1e-3)        # was -129.838 twice


def test_template_fields_are_taken_as_overrides_on_a_loaded_scenario():
    loaded = rfesim.load_scenario(rfesim.load_scenario(CRANE), overrides={"cranes.crane.payload.mass": 20000.0})
    assert loaded.bodies["crane_payload"].mass == 20000.0
    tension = rfesim.load_scenario(rfesim.load_scenario(S_LAY), overrides={"pipelay.lay.tension": 120000.0})
    assert tension.supports["lay_tensioner"].horizontal_tension == 120000.0


@pytest.mark.parametrize("source", ["file", "loaded"])
def test_a_made_entry_path_goes_onto_the_template_field_it_copies(source):
    # was (from the file): "the name 'crane_payload' is already used in bodies"
    base = CRANE if source == "file" else rfesim.load_scenario(CRANE)
    made = rfesim.load_scenario(base, overrides={"bodies.crane_payload.mass": 20000.0})
    assert made == rfesim.load_scenario(CRANE, overrides={"cranes.crane.payload.mass": 20000.0})
    assert made.bodies["crane_payload"].mass == 20000.0
    rope = rfesim.load_scenario(base, overrides={"lines.crane_rope.length": 40.0})
    assert rope == rfesim.load_scenario(CRANE, overrides={"cranes.crane.rope.length": 40.0})


def test_an_assigned_made_field_goes_onto_the_template_and_survives_a_later_change():
    sc = rfesim.load_scenario(CRANE)
    sc.bodies["crane_payload"].mass = 20000.0
    again = rfesim.load_scenario(sc)
    assert again == rfesim.load_scenario(CRANE, overrides={"cranes.crane.payload.mass": 20000.0})
    again.analysis.dynamics.enabled = not again.analysis.dynamics.enabled
    assert rfesim.load_scenario(again).bodies["crane_payload"].mass == 20000.0


def test_a_made_entry_without_a_template_field_is_refused_naming_the_template_field():
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(CRANE, overrides={"line_types.crane_rope_section.breaking_load": 1e5})
    (field, reason), = err.value.errors
    assert field == "line_types.crane_rope_section.breaking_load"
    assert "cranes.crane.rope" in reason and "already used" not in reason


def test_an_assigned_made_field_without_a_template_field_is_kept_with_a_warning():
    # was kept silently; now kept over the template's section, with a warning naming the template,
    # and again after a later change expands the templates again
    sc = rfesim.load_scenario(CRANE)
    sc.lines["crane_boom"].length = 20.0
    again = rfesim.load_scenario(sc)
    assert again.lines["crane_boom"].length == 20.0
    (warning,) = again._template_warnings
    assert warning.startswith("lines.crane_boom was changed after the template cranes.crane made it "
                              "(lines.crane_boom.length)") and "cranes.crane.boom" in warning
    again.bodies["crane_payload"].mass = 20000.0
    third = rfesim.load_scenario(again)
    assert third.lines["crane_boom"].length == 20.0 and third.bodies["crane_payload"].mass == 20000.0
    assert third._template_warnings == [warning]


def test_a_made_field_without_a_template_field_is_refused_as_an_override_on_a_loaded_scenario():
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(rfesim.load_scenario(CRANE), overrides={"lines.crane_boom.length": 20.0})
    (field, reason), = err.value.errors
    assert field == "lines.crane_boom.length" and "cranes.crane.boom" in reason


def test_varied_made_entries_from_the_docs_run():
    # docs/service.md: entries the templates make can be varied (were all refused)
    (values, data), = build_cases(J_LAY, {"vessels.lay_vessel.motion.heave.amplitude": [1.0]})
    assert values == {"vessels.lay_vessel.motion.heave.amplitude": 1.0}
    assert rfesim.load_scenario(data).vessels["lay_vessel"].motion.heave.amplitude == 1.0
    cases = build_cases(S_LAY, {"lines.lay.elements": [60, 80]})
    assert [rfesim.load_scenario(d).lines["lay"].elements for _, d in cases] == [60, 80]
    (_, data), = build_cases(rfesim.load_scenario(CRANE), {"bodies.crane_payload.mass": [20000.0]})
    assert rfesim.load_scenario(data).bodies["crane_payload"].mass == 20000.0


def test_the_templates_warnings_are_made_again_not_kept_stale():
    reel = os.path.join(HERE, "..", "..", "scenarios", "reel_lay.json")
    sc = rfesim.load_scenario(reel)
    (warning,) = sc._template_warnings
    assert warning.startswith("pipelay.lay.element_length: elements of 1.999 m")
    sc.analysis.dynamics.enabled = not sc.analysis.dynamics.enabled
    assert rfesim.load_scenario(sc)._template_warnings == [warning]
    finer = rfesim.load_scenario(rfesim.load_scenario(reel), overrides={"pipelay.lay.element_length": 0.5})
    assert finer._template_warnings == []


def test_a_sweep_from_a_scenario_with_an_assignment_kept_over_a_template_is_refused():
    sc = rfesim.load_scenario(CRANE)
    sc.lines["crane_boom"].length = 20.0
    with pytest.raises(ScenarioError) as err:
        build_cases(sc, {"cranes.crane.payload.mass": [20000.0]})
    (field, reason), = err.value.errors
    assert field == "lines.crane_boom.length" and "sweep makes again" in reason




def test_a_made_section_changed_in_place_stays_so_through_copies_and_later_changes():
    # the reel-lay tensioner put on a table, the reel left driven (tests/unit/test_reel_driven.py):
    # the constant-tension keys the assignment removed stay removed
    import copy
    import pickle

    from pydantic import TypeAdapter

    reel = os.path.join(HERE, "..", "..", "scenarios", "reel_lay.json")
    sc = rfesim.load_scenario(reel, overrides={"pipelay.lay.tensioner.payout": {
        "kind": "constant-tension", "tension": 5.0e4, "dead_band": 0.0, "gain": 2.0e4, "max_speed": 0.5}})
    tens = sc.supports["lay_tensioner"]
    tens.payout = TypeAdapter(type(tens).model_fields["payout"].annotation).validate_python(
        {"kind": "table", "rows": [[0.0, 0.0], [10.0, 1.0]]})
    first = rfesim.load_scenario(sc)
    again = pickle.loads(pickle.dumps(copy.deepcopy(first)))
    again.analysis.dynamics.enabled = not again.analysis.dynamics.enabled
    second = rfesim.load_scenario(again)
    for s in (first, second):
        assert s.supports["lay_tensioner"].payout.kind == "table"
        assert s.supports["lay_tensioner"].payout.rows == [[0.0, 0.0], [10.0, 1.0]]
        assert s.supports["lay_reel"].payout.kind == "constant-tension"
        assert any(w.startswith("supports.lay_tensioner was changed after the template pipelay.lay made it")
                   for w in s._template_warnings)
