"""Errors in template input (``cranes: {...}``, ``pipelay: {...}``) name the field the user
wrote, not the expanded section the template made (input audit 7, D6).

* the crane template's ``winch`` is validated with the template
  (rfesim.scenario.winches.TemplateWinch): ``cranes.crane.winch.mode.rows.1``, not
  ``winches.crane_winch.mode.rows.1``;
* template sizes have documented lower bounds (rope diameter and length, member length and
  wall thickness, pipe wall thickness, element_length, seabed_stiffness), refused under the
  template field with the reason;
* an error found in the expanded scenario is translated back
  (rfesim.scenario.pipelay.template_path): in a copy of the user's own entry (the winch, an
  inline payload or vessel) to its template path, elsewhere prefixed with the template field
  it came from (``pipelay.lay.stinger (expanded as supports.lay_stinger.spacing)``);
* a scenario without templates keeps its messages.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest

import rfesim
from rfesim import ScenarioError

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def example(name: str) -> dict:
    return json.loads((SCENARIOS / f"{name}.json").read_text())


def errors_of(name: str, overrides: dict) -> dict[str, str]:
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(example(name), overrides=overrides, base_dir=SCENARIOS)
    return dict(info.value.errors)


REVERSED_ROWS = [[74.0, 0.0], [72.0, 0.3], [14.0, 0.3], [12.0, 0.0], [0.0, 0.0]]
SPEED = {"kind": "speed", "rows": [[0.0, 0.0], [12.0, 0.0], [14.0, 0.3], [72.0, 0.3], [74.0, 0.0]]}

# (scenario, overrides, the field named, what the reason says, the expanded path no longer named)
CASES = [
    # the audit's repro cases (/tmp/audit7_input/cases/*.json are these mutations of the bundled scenarios)
    ("column_crane", {"cranes.crane.winch.mode.rows": REVERSED_ROWS},              # crane_winch_rows_rev
     "cranes.crane.winch.mode.rows.1", ["time 72.0 s does not increase"], "winches.crane_winch"),
    ("column_crane", {"cranes.crane.winch": {"modee": SPEED}},                      # crane_winch_typo
     "cranes.crane.winch.modee", ["unknown key", "did you mean 'mode'"], "winches.crane_winch"),
    ("column_crane", {"cranes.crane.rope.diameter": 1e-300},                        # crane_rope_diam_tiny
     "cranes.crane.rope.diameter", ["greater than or equal to 0.001 m (got 1e-300)", "rope"],
     "line_types.crane_rope_section"),
    ("column_crane", {"cranes.crane.boom.length": 1e-9},                            # crane_boom_len_tiny
     "cranes.crane.boom.length", ["greater than or equal to 0.1 m (got 1e-09)", "boom"], "lines.crane_boom"),
    ("j_lay", {"pipelay.lay.element_length": 1e-6},                                 # lay_elem_len_tiny
     "pipelay.lay.element_length", ["greater than or equal to 0.01 m (got 1e-06)", "100000 elements"],
     "lines.lay"),
    # the payload's deck on an unknown vessel (found by the reference checks of the expanded bodies)
    ("column_crane_liftoff", {"cranes.crane.payload.deck.vessel": "x"},
     "cranes.crane.payload.deck.vessel", ["unknown vessel 'x'"], "bodies.crane_payload"),
    # a seabed the template makes, softer than the environment's floor of 1 N/m/m
    ("s_lay_template", {"environment.seabed": None, "pipelay.lay.seabed_stiffness": 1e-3},
     "pipelay.lay.seabed_stiffness", ["greater than or equal to 1 N/m/m (got 0.001)", "soft clays"],
     "environment.seabed"),
    # more sizes of the templates
    ("column_crane", {"cranes.crane.rope.length": 1e-9},
     "cranes.crane.rope.length", ["greater than or equal to 0.1 m (got 1e-09)"], "lines.crane_rope"),
    ("column_crane", {"cranes.crane.boom.wall_thickness": 1e-300},
     "cranes.crane.boom.wall_thickness", ["greater than or equal to 0.001 m (got 1e-300)", "steel pipe or tube"],
     "line_types.crane_boom_section"),
    ("column_crane", {"cranes.crane.rope.mass_per_length": 1e-30},
     "cranes.crane.rope.mass_per_length", ["greater than or equal to 0.0001 kg/m (got 1e-30)", "fishing line"],
     "line_types.crane_rope_section"),
    ("a_frame", {"cranes.aframe.legs.length": 0.05},
     "cranes.aframe.legs.length", ["greater than or equal to 0.1 m (got 0.05)"], "lines.aframe_legs"),
    ("s_lay_template", {"pipelay.lay.pipe.wall_thickness": 1e-9},
     "pipelay.lay.pipe.wall_thickness", ["greater than or equal to 0.001 m (got 1e-09)", "steel pipe"],
     "line_types.lay_pipe"),
    # above the floor, but more elements than a line may have on the 1369 m J-lay line
    ("j_lay", {"pipelay.lay.element_length": 0.011},
     "pipelay.lay.element_length", ["0.011 m gives 124491 elements", "more than the 100000", "at least 0.0137 m"],
     "lines.lay"),
    # the winch's own fields, and the winch's payout checked against its drum in the expanded scenario
    ("column_crane", {"cranes.crane.winch.stored": 1e300},
     "cranes.crane.winch.stored", ["less than or equal to 10000000 m (got 1e+300)"], "winches.crane_winch"),
    ("column_crane", {"cranes.crane.winch.stored": 1.0},
     "cranes.crane.winch.mode.rows", ["more than the 1 m stored on the drum"], "winches.crane_winch"),
    ("column_crane", {"cranes.crane.winch.line": "crane_rope"},
     "cranes.crane.winch.line", ["the template's winch acts on its own rope: leave out line"], "winches.crane_winch"),
]


@pytest.mark.parametrize("name, overrides, field, reasons, expanded", CASES,
                         ids=[f"{c[0]}:{c[2]}" for c in CASES])
def test_template_error_names_the_field_the_user_wrote(name, overrides, field, reasons, expanded):
    errors = errors_of(name, overrides)
    assert field in errors, errors
    for reason in reasons:
        assert reason in errors[field], errors[field]
    assert not any(expanded in f for f in errors), errors


def test_an_error_without_one_template_field_names_the_template_and_the_expanded_path():
    # the stinger support's spacing is the template's, adjusted to the arc: no one-to-one field
    errors = errors_of("s_lay_template", {"pipelay.lay.stinger.spacing": 1e-6})
    field = "pipelay.lay.stinger (expanded as supports.lay_stinger.spacing)"
    assert field in errors, errors
    assert "makes more than 10000 stations" in errors[field]


def test_template_path_maps_copies_and_prefixes_the_rest():
    from rfesim.scenario.pipelay import Origin, template_path
    origins = {"winches.crane_winch": Origin("cranes.crane", "winch", "winch", ("line",)),
               "bodies.crane_payload": Origin("cranes.crane", "payload", "payload", ("position",)),
               "lines.crane_boom": Origin("cranes.crane", "boom"),
               "lines.lay": Origin("pipelay.lay"),
               "environment.seabed": Origin("pipelay.lay", keys={"normal_stiffness": "seabed_stiffness"})}
    assert template_path("winches.crane_winch.mode.rows.1", origins) == "cranes.crane.winch.mode.rows.1"
    assert template_path("winches.crane_winch", origins) == "cranes.crane.winch"
    assert template_path("winches.crane_winch.line", origins) == \
        "cranes.crane.winch (expanded as winches.crane_winch.line)"
    assert template_path("bodies.crane_payload.deck.vessel", origins) == "cranes.crane.payload.deck.vessel"
    assert template_path("bodies.crane_payload.position.2", origins) == \
        "cranes.crane.payload (expanded as bodies.crane_payload.position.2)"
    assert template_path("lines.crane_boom.length", origins) == \
        "cranes.crane.boom (expanded as lines.crane_boom.length)"
    assert template_path("lines.lay.elements", origins) == "pipelay.lay (expanded as lines.lay.elements)"
    assert template_path("environment.seabed.normal_stiffness", origins) == "pipelay.lay.seabed_stiffness"
    assert template_path("environment.seabed.friction", origins) == \
        "pipelay.lay (expanded as environment.seabed.friction)"
    # sections the user wrote, and names that only begin like a generated one, are left alone
    assert template_path("lines.crane_boom_2.length", origins) == "lines.crane_boom_2.length"
    assert template_path("lines.layer.length", origins) == "lines.layer.length"
    assert template_path("environment.gravity", origins) == "environment.gravity"


def test_user_written_sections_beside_a_template_keep_their_paths():
    # the winch of a line the user wrote, in a scene with a crane template: its own path
    data = example("column_crane")
    data["line_types"] = {"wire": {"EA": 1e8, "EIy": 10.0, "mass_per_length": 5.0, "tension_only": True}}
    data["lines"] = {"tag": {"type": "wire", "length": 10.0, "elements": 10,
                             "end_a": {"attach": "fixed", "position": [50.0, 0.0, 0.0]},
                             "end_b": {"attach": "free"}}}
    data["winches"] = {"tag_winch": {"line": "tag", "modee": SPEED}}
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data, base_dir=SCENARIOS)
    errors = dict(info.value.errors)
    assert "winches.tag_winch.modee" in errors, errors


def test_messages_of_scenarios_without_templates_are_unchanged():
    errors = errors_of("catenary_riser", {"lines.riser.length": 1e-9})
    assert errors == {"lines.riser.length": "1e-09 m is too short (at least 1e-06 m)"}, errors


@pytest.mark.parametrize("name, overrides", [
    ("column_crane", {"cranes.crane.rope.diameter": 0.001, "cranes.crane.boom.wall_thickness": 0.001}),
    ("column_crane", {"cranes.crane.rope.length": 0.5}),
    ("j_lay", {"pipelay.lay.element_length": 0.0137}),
    ("s_lay_template", {"environment.seabed": None, "pipelay.lay.seabed_stiffness": 1.0e4}),
])
def test_values_at_and_above_the_floors_pass(name, overrides):
    assert rfesim.load_scenario(example(name), overrides=overrides, base_dir=SCENARIOS) is not None
