"""Benchmark line H2 (docs/benchmarks.md): line H1 with added mass, current and waves.

H2 is the H1 riser (scenarios/h1_riser_heave.json: steel pipe OD 0.3 m, wall 0.02 m,
empty, 290 m from the seabed at (0, 0, -99.85) to a fairlead at (250, 0, -10) heaving
1 m at 8 s) with

* normal added-mass coefficient 1.0 (axial 0);
* a uniform current of 0.5 m/s flowing toward +y (``direction_deg`` 90: across the
  line's x-z plane), ramped in linearly over the first 8 s (``time_factor``
  ``[[0, 0], [8, 1]]``), so that both codes start from the still-water equilibrium;
* a regular Airy wave, height 3 m, period 9 s, travelling toward +x
  (``eta = 1.5 cos(omega t - k x)``), from t = 0 without a ramp, with Wheeler
  stretching — the kinematics MoorDyn's ``WaveKin 7`` uses (see
  :mod:`rfesim.bench.moordyn_h2`).

The measured quantities and the error are those of H1 (:mod:`rfesim.bench.h1`): the
first-harmonic amplitude of the fairlead tension at the heave frequency 0.125 Hz over
28-60 s (least squares) and the largest bending moment over the same window.
"""
from __future__ import annotations

import json

from .h1 import SCENARIO, H1Run, run_rfesim_h1

ADDED_MASS_NORMAL = 1.0                 # -
CURRENT_SPEED = 0.5                     # m/s
CURRENT_DIRECTION_DEG = 90.0            # deg, toward +y
CURRENT_RAMP = 8.0                      # s, linear ramp-in of the current
WAVE_HEIGHT = 3.0                       # m
WAVE_PERIOD = 9.0                       # s
WAVE_DIRECTION_DEG = 0.0                # deg, toward +x


def h2_data(elements: int, integrator: dict, output_interval: float = 0.05) -> dict:
    """The H2 scenario as a dict (H1's JSON with the sea of H2)."""
    data = json.loads(SCENARIO.read_text())
    data["name"] = "H2 steel catenary riser, heaving fairlead, added mass, current and waves"
    data["description"] = ("Benchmark H2: benchmark H1 with normal added mass 1.0, a uniform 0.5 m/s current "
                           "toward +y ramped in over 8 s, and a regular Airy wave H 3 m, T 9 s toward +x "
                           "(Wheeler stretching, no ramp).")
    data["lines"]["riser"]["elements"] = int(elements)
    for line_type in data["line_types"].values():
        line_type["added_mass_normal"] = ADDED_MASS_NORMAL
    water = data["environment"]["water"]
    water["current"] = {"profile": [[0.0, CURRENT_SPEED]], "direction_deg": CURRENT_DIRECTION_DEG,
                        "time_factor": [[0.0, 0.0], [CURRENT_RAMP, 1.0]]}
    water["waves"] = {"kind": "airy", "height": WAVE_HEIGHT, "period": WAVE_PERIOD,
                      "direction_deg": WAVE_DIRECTION_DEG, "stretching": "wheeler", "ramp_duration": 0.0}
    data["analysis"]["dynamics"]["integrator"] = integrator
    data["analysis"]["dynamics"]["output_interval"] = output_interval
    return data


def h2_scenario(elements: int, integrator: dict, output_interval: float = 0.05):
    """The H2 scenario (a validated ``rfesim.Scenario``)."""
    import rfesim
    return rfesim.load_scenario(h2_data(elements, integrator, output_interval))


def run_rfesim_h2(elements: int, integrator: dict, label: str, repeats: int = 1) -> H1Run:
    """One H2 run: statics, then 60 s of dynamics (timed alone, best of ``repeats``)."""
    return run_rfesim_h1(elements, integrator, label, repeats, scenario=h2_scenario)
