"""The top-tension plot draws the force at the end held on board (the rule of the run summary,
rfesim.sweep.line_top_tension), not end B whatever the line's orientation."""
import json
from pathlib import Path

import numpy as np
import pytest

import rfesim

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def _riser(reverse: bool):
    d = json.loads((SCENARIOS / "catenary_riser.json").read_text())
    line = d["lines"]["riser"]
    line["elements"] = 30
    if reverse:      # the vessel holds end A, the anchor end B
        line["end_a"], line["end_b"] = line["end_b"], line["end_a"]
    d["analysis"]["dynamics"]["enabled"] = False
    return rfesim.simulate(d)


@pytest.mark.parametrize("reverse", [False, True])
def test_top_tension_plot_is_the_vessel_end(reverse):
    from rfesim.plot import plot_top_tension

    res = _riser(reverse)
    lr = res.line("riser")
    on_board = lr.end_a_force if reverse else lr.end_b_force
    anchor = lr.end_b_force if reverse else lr.end_a_force
    ax = plot_top_tension(res, "riser")
    (curve,) = ax.get_lines()
    drawn = np.asarray(curve.get_ydata()) * 1e3
    np.testing.assert_allclose(drawn, np.linalg.norm(on_board, axis=-1), rtol=1e-12)
    # the two ends differ by the hanging weight, so the wrong end would fail the check above
    assert np.linalg.norm(on_board, axis=-1)[0] > 1.5 * np.linalg.norm(anchor, axis=-1)[0]
    assert curve.get_label() == ("riser (end A)" if reverse else "riser (end B)")
