"""Reel-lay elements too coarse for the overbend: the peak curvature at the aligner exit
converges from above with the element length (scenarios/reel_lay.json, 9 m aligner: 0.1356,
0.1285, 0.1249, 0.1250 1/m at 2, 1, 0.5, 0.25 m), so elements longer than a ninth of the
aligner radius (rfesim.scenario.pipelay.ALIGNER_COARSE_FRACTION) get a template warning
naming the field and the element length to give, as S-lay and J-lay templates do."""
import json
from pathlib import Path

import pytest

import rfesim

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def _reel_lay(**lay):
    d = json.loads((SCENARIOS / "reel_lay.json").read_text())
    d["pipelay"]["lay"].pop("element_length", None)
    d["pipelay"]["lay"].update(lay)
    return rfesim.load_scenario(d, base_dir=SCENARIOS)


@pytest.mark.parametrize("lay", [{}, {"element_length": 2.0}, {"element_length": 1.5}])
def test_coarse_elements_over_the_aligner_are_warned_about(lay):
    """The default 2 m (8.5 % high on the 9 m aligner) and a given 1.5 m."""
    (warning,) = _reel_lay(**lay)._template_warnings
    assert "element_length" in warning and "aligner radius (1 m)" in warning
    assert "at most 0.5 m" in warning


def test_warning_names_elements_when_given_as_a_count():
    (warning,) = _reel_lay(elements=300)._template_warnings       # 1.73 m on the 520 m line
    assert "pipelay.lay.elements" in warning and "elements of 1.733 m" in warning


def test_fine_elements_and_a_larger_aligner_are_not_warned_about():
    assert _reel_lay(element_length=1.0)._template_warnings == []          # 2.8 % high
    assert _reel_lay(element_length=0.5)._template_warnings == []
    # a 20 m aligner takes 2 m elements (a tenth of its radius)
    assert _reel_lay(element_length=2.0, aligner_radius=20.0)._template_warnings == []
