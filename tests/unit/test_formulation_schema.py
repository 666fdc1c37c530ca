"""Scenario errors of the non-absolute formulations and of ``chains``: each names its field."""
from __future__ import annotations

import copy

import pytest

import rfesim
from rfesim.bench.cases import cantilever

ROD = {"rigid": True, "length": 1.0, "mass": 1.0}


def chain_scene(**changes):
    sc = {"environment": {"gravity": 9.81},
          "chains": {"c": {"links": {"a": dict(ROD), "b": dict(ROD)},
                           "joints": {"j1": {"kind": "revolute", "parent": "base", "child": "a", "axis": [0, 1, 0]},
                                      "j2": {"kind": "revolute", "parent": "a", "child": "b", "axis": [0, 1, 0]}}}},
          "analysis": {"dynamics": {"duration": 1.0, "integrator": {"kind": "rk4"}}}}
    for path, value in changes.items():
        cur = sc
        keys = path.split(".")
        for k in keys[:-1]:
            cur = cur[k]
        if value is None:
            del cur[keys[-1]]
        else:
            cur[keys[-1]] = value
    return sc


def errors_of(sc):
    with pytest.raises(rfesim.ScenarioError) as exc:
        rfesim.Scenario.model_validate(sc)
    return dict(exc.value.errors)


def line_scene(formulation="classical", **line):
    sc = cantilever(4, [])
    sc["lines"]["beam"]["formulation"] = formulation
    sc["lines"]["beam"].update(line)
    return sc


def test_valid_scenes_load():
    rfesim.Scenario.model_validate(chain_scene())
    for f in ("classical", "classical-linear", "modified", "planar"):
        assert rfesim.Scenario.model_validate(line_scene(f)).lines["beam"].formulation == f


@pytest.mark.parametrize("path, value, field, words", [
    ("chains.c.joints.j2.child", "nope", "chains.c.joints.j2.child", "unknown link 'nope'"),
    ("chains.c.joints.j2.parent", "ghost", "chains.c.joints.j2.parent", "unknown link 'ghost'"),
    ("chains.c.joints.j1.parent", "b", "chains.c.joints.j2.parent", "cycle: a -> b -> a"),
    ("chains.c.joints.j2.axis", [0, 0, 0], "chains.c.joints.j2.axis", "zero vector"),
    ("chains.c.joints.j2.axis", None, "chains.c.joints.j2.axis", "needs its axis"),
    ("chains.c.joints.j2.parent", "b", "chains.c.joints.j2.parent", "own parent"),
    ("chains.c.joints.j3", {"kind": "fixed", "child": "b"}, "chains.c.joints.j3.child", "already carried"),
    ("chains.c.base", "barge", "chains.c.base", "unknown base 'barge'"),
    ("chains.c.links.b", {"length": 1.0, "elements": 3}, "chains.c.links.b.type", "needs a line type"),
    ("chains.c.links.b", {"length": 1.0, "type": "pipe", "elements": 3}, "chains.c.links.b.type",
     "unknown line type 'pipe'"),
    ("chains.c.links.b", {"length": 1.0, "rigid": True}, "chains.c.links.b.mass", "needs its mass"),
    ("chains.c.joints.j2.at", 2.0, "chains.c.joints.j2.at", "beyond the tip"),
    ("chains.c.joints.j2.drive", {"kind": "spin"}, "chains.c.joints.j2.drive.kind", "unknown kind"),
    ("chains.c.joints.j2.kind", "fixed", "chains.c.joints.j2.axis", "has no axis"),
    ("analysis.dynamics.integrator", {"kind": "generalized-alpha"}, "analysis.dynamics.integrator.kind",
     "not available"),
])
def test_chain_errors_name_the_field(path, value, field, words):
    errs = errors_of(chain_scene(**{path: value}))
    assert field in errs, errs
    assert words in errs[field]


def test_link_without_joint_and_mixing_with_absolute_lines():
    sc = chain_scene()
    sc["chains"]["c"]["links"]["spare"] = dict(ROD)
    errs = errors_of(sc)
    assert "no joint carries" in errs["chains.c.links.spare"]
    mixed = copy.deepcopy(cantilever(4, []))
    mixed["chains"] = chain_scene()["chains"]
    rfesim.Scenario.model_validate(mixed)          # chains with absolute lines: rfesim.formulations.mixed
    mixed["analysis"]["dynamics"] = {"duration": 1.0, "integrator": {"kind": "rk4"}}
    errs = errors_of(mixed)
    assert "use 'generalized-alpha'" in errs["analysis.dynamics.integrator.kind"]
    mixed = copy.deepcopy(cantilever(4, []))
    mixed["lines"]["other"] = dict(mixed["lines"]["beam"], formulation="modified")
    errs = errors_of(mixed)
    assert "not supported yet" in errs["lines.beam.formulation"]


@pytest.mark.parametrize("formulation, change, field, words", [
    ("planar", {"loads": [{"at": "end_b", "force": [0, 5.0, -1.0]}]}, "lines.beam.loads.0.force",
     "out of the line's plane"),
    ("planar", {"loads": [{"at": "end_b", "moment": [0, 0, 3.0]}]}, "lines.beam.loads.0.moment", "plane normal"),
    ("classical", {"end_b": {"attach": "fixed", "position": [10, 0, 0]}}, "lines.beam.end_b.attach", "free end B"),
    ("modified", {"dofs": ["x"]}, "lines.beam.dofs", "subset"),
    ("classical", {"loads": [{"at": 1.0, "force": [0, 0, 1], "frame": "local"}]}, "lines.beam.loads.0.frame",
     "global"),
])
def test_line_formulation_errors_name_the_field(formulation, change, field, words):
    errs = errors_of(line_scene(formulation, **change))
    assert field in errs, errs
    assert words in errs[field]


def test_direction_needed_and_no_sea_loads():
    sc = line_scene("modified")
    del sc["lines"]["beam"]["end_a"]["direction"]
    assert "give it" in errors_of(sc)["lines.beam.end_a.direction"]
    sc = line_scene("classical")
    sc["environment"]["water"] = {"density": 1025.0, "depth": 100.0}
    assert "absolute formulation only" in errors_of(sc)["lines.beam.formulation"]
