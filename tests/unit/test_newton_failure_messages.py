"""A Newton failure with no slack rope to blame names where the last iterate's residual was
largest and what helps (rfesim.solvers.dynamics.NEWTON_HINT), and a run that fails after
the input was warned of a jolt (waves with no ramp) says so in the error, not only in the
results' message (rfesim.api.simulate)."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

import rfesim
from rfesim.solvers.dynamics import NEWTON_HINT

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def s_lay(**lines) -> dict:
    d = json.loads((SCENARIOS / "s_lay.json").read_text())
    d["lines"]["pipe"].update(lines)
    d["analysis"]["dynamics"]["duration"] = 20.0
    return d


def test_newton_failure_without_slack_ropes_names_the_element_and_the_remedies():
    """The S-lay pipe given one element (870 m: two rigid halves over the stinger's rollers)
    fails at 8.59 s; the error said only 'the run diverged at t = 8.58574 s (Newton iteration
    did not converge)'."""
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(rfesim.load_scenario(s_lay(elements=1), base_dir=SCENARIOS))
    exc = info.value
    assert exc.quantity == "Newton iteration did not converge"
    assert exc.element == "line 'pipe', RFE 1 (arc length 435 m)"
    assert exc.hint == NEWTON_HINT
    assert "time_step" in exc.hint and "rho_inf" in exc.hint
    assert exc.results is not None and exc.results.message.endswith(NEWTON_HINT)


def test_a_failure_after_a_warned_jolt_names_the_warning():
    """Airy waves 6.6 m, 10 s with no ramp on the A-frame: the slack rope hint, and after it
    the warning the input had (ramp_duration), which before only the results' message kept."""
    d = json.loads((SCENARIOS / "a_frame.json").read_text())
    d["environment"]["water"]["waves"] = {"kind": "airy", "height": 6.6, "period": 10.0}
    d["analysis"]["dynamics"]["duration"] = 5.0
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(rfesim.load_scenario(d, base_dir=SCENARIOS))
    text = str(info.value)
    assert "slack rope elements at the last iterate" in text
    assert "; before the run the scenario was warned: environment.water.waves.ramp_duration: 0 s, so the airy " \
           "waves start at full height" in text
