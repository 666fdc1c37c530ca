"""The element-length error of the J-lay and S-lay templates names half the collar or
tensioner; without tensioner.length that track is 10 m and at least three elements
(rfesim.scenario.pipelay._track_length), so with long elements the message said "half the
collar (147 m)" of a collar whose default is 10 m. It now says where that length came from."""
import json
from pathlib import Path

import pytest

import rfesim
from rfesim.errors import ScenarioError

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def _j_lay(**lay):
    d = json.loads((SCENARIOS / "j_lay.json").read_text())
    d["pipelay"]["lay"].update(lay)
    return d


def test_default_collar_stretched_by_long_elements_is_explained():
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(_j_lay(element_length=100.0), base_dir=SCENARIOS)
    text = str(err.value)
    assert "pipelay.lay.element_length" in text
    assert "without tensioner.length the collar is 10 m long and at least three elements" in text
    assert "stretch it to 293.4 m" in text


def test_given_collar_length_is_named_plainly():
    d = _j_lay(element_length=100.0)
    d["pipelay"]["lay"]["tensioner"] = dict(d["pipelay"]["lay"].get("tensioner") or {}, length=40.0)
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(d, base_dir=SCENARIOS)
    assert "half the collar (20 m) must" in str(err.value)


def test_reel_lay_names_each_limit_and_the_default_track_plainly():
    # the reel-lay message said "a quarter of the reel and aligner radii" without their sizes,
    # and a default 10 m tensioner that no element stretched was explained as stretched
    d = json.loads((SCENARIOS / "reel_lay.json").read_text())
    d["pipelay"]["lay"]["element_length"] = 3.0
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(d, base_dir=SCENARIOS)
    text = str(err.value)
    radius = d["pipelay"]["lay"]["aligner_radius"]
    assert "elements of 2.99 m are longer than 2.04 m" in text
    assert "half the tensioner (5 m), a quarter of the reel radius (2.04 m)" in text
    assert f"a quarter of the aligner radius ({0.25 * radius:.3g} m)" in text
    assert "stretch" not in text
