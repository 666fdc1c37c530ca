"""An elasto-plastic line type outside the absolute formulation is refused, naming the field.

The plastic SDE law (section 8.4.2) lives in the absolute formulation's SDE only; the
classical, modified and planar SDEs and flexible chain links use the elastic section
stiffness. Before this check such a scenario ran elastic without a word (a bilinear X65
cantilever gave M/EI = 0.01722 1/m at the root instead of the fibre model's 0.02824 1/m
and no residual curvature).
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest

import rfesim

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
X65 = {"kind": "elastoplastic", "law": "bilinear", "yield_stress": 448e6, "hardening_ratio": 0.01}


def pipe_scene(formulation):
    sc = json.loads((SCENARIOS / "cantilever_pipe.json").read_text())
    sc["analysis"] = {"statics": {"enabled": True}}
    lt = sc["line_types"]["pipe12"]
    lt["material"] = dict(X65)
    lt.pop("damping")                       # ratios are absolute-only (a separate error)
    ln = sc["lines"]["pipe"]
    ln["formulation"] = formulation
    if formulation != "absolute":
        ln.pop("shear_stiffness")
    return sc


def errors_of(sc):
    with pytest.raises(rfesim.ScenarioError) as exc:
        rfesim.Scenario.model_validate(sc)
    return dict(exc.value.errors)


def test_absolute_line_keeps_its_plastic_material():
    sc = rfesim.Scenario.model_validate(pipe_scene("absolute"))
    assert sc.line_types["pipe12"].material.kind == "elastoplastic"


@pytest.mark.parametrize("formulation", ["classical", "classical-linear", "modified", "planar"])
def test_other_formulations_refuse_an_elastoplastic_line_type(formulation):
    errs = errors_of(pipe_scene(formulation))
    assert list(errs) == ["lines.pipe.formulation"]
    msg = errs["lines.pipe.formulation"]
    for words in ("line_types.pipe12.material", "8.4.2", "absolute formulation only", formulation):
        assert words in msg, (words, msg)


def test_the_same_line_elastic_is_accepted():
    sc = pipe_scene("modified")
    sc["line_types"]["pipe12"]["material"] = {"kind": "elastic"}
    assert rfesim.Scenario.model_validate(sc).lines["pipe"].formulation == "modified"


def test_flexible_chain_link_refuses_an_elastoplastic_line_type():
    sc = pipe_scene("absolute")
    del sc["lines"]
    sc["environment"] = {"gravity": 9.81}
    sc["chains"] = {"c": {"links": {"a": {"rigid": True, "length": 1.0, "mass": 1.0},
                                    "b": {"type": "pipe12", "length": 10.0, "elements": 4}},
                          "joints": {"j1": {"kind": "revolute", "parent": "base", "child": "a", "axis": [0, 1, 0]},
                                     "j2": {"kind": "fixed", "parent": "a", "child": "b"}}}}
    errs = errors_of(sc)
    assert "chains.c.links.b.type" in errs, errs
    msg = errs["chains.c.links.b.type"]
    assert "line_types.pipe12.material" in msg and "8.4.2" in msg
    # a rigid link only takes its mass from the type: no plastic law to lose, accepted
    sc["chains"]["c"]["links"]["b"] = {"rigid": True, "type": "pipe12", "length": 10.0}
    rfesim.Scenario.model_validate(sc)
