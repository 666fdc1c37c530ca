"""The reel-lay template warns when its pipe is elastic: reeling bends a pipe far past yield
(a 12.75 in pipe on an 8 m drum: 2 % strain, 9 times X65's yield strain), so an elastic pipe
carries about nine times its first-yield moment into the aligner and straightener and has no
residual curvature (audit: 5.19 MN*m overbend moment, no word)."""
from __future__ import annotations

import copy
import json
import math
from pathlib import Path

import pytest

import rfesim

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def _reel_lay(material):
    sc = json.loads((SCENARIOS / "reel_lay.json").read_text())
    sc["vessels"]["reeler"]["motion"]["file"] = str(SCENARIOS / "data" / "barge_100m_raos.json")
    sc["pipelay"]["lay"]["pipe"]["material"] = material
    return sc


def _warnings(sc):
    return [w for w in rfesim.load_scenario(copy.deepcopy(sc))._template_warnings if ".pipe.material:" in w]


def test_an_elastic_pipe_on_the_reel_is_warned_about_with_the_numbers():
    sc = _reel_lay("elastic")
    (w,) = _warnings(sc)
    D, t = 0.3239, 0.0159
    radius = sc["pipelay"]["lay"].get("reel", {}).get("radius", 8.0) + 0.5 * D      # the pipe axis
    strain, yield_strain = 0.5 * D / radius, 448e6 / 207e9
    inertia = math.pi / 64.0 * (D ** 4 - (D - 2 * t) ** 4)
    assert w.startswith("pipelay.lay.pipe.material: an elastic pipe bent on the 8.162 m reel")
    assert f"{100 * strain:.3g} %" in w and f"{strain / yield_strain:.3g} times the yield strain of X65" in w
    assert f"{207e9 * inertia / radius / 1e6:.4g} MN*m" in w
    assert f"{448e6 * inertia / (0.5 * D) / 1e6:.4g} MN*m" in w
    assert strain / yield_strain == pytest.approx(9.17, abs=0.01)


def test_the_elastoplastic_default_is_not_warned_about():
    assert _warnings(_reel_lay("elastoplastic")) == []
