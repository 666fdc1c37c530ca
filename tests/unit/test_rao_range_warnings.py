"""RAO tables that do not cover the sea (audit 7, suspicion): beyond its frequencies an RAO
table holds its end rows, so with the default spectrum (out to 10 omega_p) short waves move
the vessel with the last row's RAOs instead of real RAOs falling off. The run warns
(rfesim.sea.rao.rao_range_warnings, a dynamics warning in the results' message) when the
components outside the table carry more than 1 % of the sea's m0 and the held row moves the
vessel with them; the motions themselves are unchanged.

The shares are checked against the closed form of the Pierson-Moskowitz spectrum's
cumulative energy, F(omega) = Hs^2/16 exp(-5/4 (omega_p/omega)^4), on a sea whose geometric
frequency bins have edges at the table's end frequencies (each component carries exactly
its bin's energy, so the share of the components beyond an edge is that of the spectrum)."""
from __future__ import annotations

import copy
import math

import pytest

import rfesim
from rfesim.api import DYNAMICS_WARNING
from rfesim.sea.rao import RAO_RANGE_ENERGY, rao_range_warnings

HS, TP = 2.0, 8.0
W_LO, W_HI, N = 0.4, 6.4, 200          # geometric bins: edges 0.4 * 16**(i / 200); i = 50: 0.8, i = 100: 1.6


def table(upper_row=1.0, lower_row=1.0, frequencies=(0.8, 1.6)):
    """A symmetric heave-only RAO table at two frequencies (rows ascending)."""
    return {"frequencies": list(frequencies), "headings_deg": [0.0, 90.0, 180.0], "symmetric": True,
            "heave": {"amplitude": [[lower_row] * 3, [upper_row] * 3], "phase_deg": [[0.0] * 3, [0.0] * 3]}}


def scene(raos, waves=None, duration=0.0):
    waves = waves or {"kind": "pierson-moskowitz", "hs": HS, "tp": TP, "omega_min": W_LO, "omega_max": W_HI,
                      "components": N, "direction_deg": 90.0, "seed": 3}
    data = {"environment": {"water": {"density": 1025.0, "depth": 100.0, "waves": waves}},
            "vessels": {"barge": {"position": [0.0, 0.0, 0.0], "motion": {"kind": "rao", "raos": raos}}},
            "line_types": {"rope": {"outer_diameter": 0.1, "wall_thickness": 0.01, "youngs_modulus": 2e11,
                                    "density": 7850.0}},
            "lines": {"hang": {"type": "rope", "length": 10.0, "elements": 4,
                               "end_a": {"attach": "barge", "position": [0.0, 0.0, -2.0]},
                               "end_b": {"attach": "free", "position": [0.0, 0.0, -12.0]}}},
            "analysis": {"statics": {"enabled": True}}}
    if duration > 0.0:
        data["analysis"]["dynamics"] = {"duration": duration, "output_interval": 0.1,
                                        "integrator": {"kind": "generalized-alpha", "time_step": 0.05}}
    return data


def pm_cumulative(w):
    wp = 2.0 * math.pi / TP
    return HS ** 2 / 16.0 * math.exp(-1.25 * (wp / w) ** 4)


M0 = pm_cumulative(W_HI) - pm_cumulative(W_LO)
ABOVE = (pm_cumulative(W_HI) - pm_cumulative(1.6)) / M0        # 6.97 % of m0 above 1.6 rad/s
BELOW = (pm_cumulative(0.8) - pm_cumulative(W_LO)) / M0        # 31.3 % below 0.8 rad/s


def test_the_shares_beyond_the_table_are_the_spectrum_s():
    above, below = rao_range_warnings(rfesim.load_scenario(scene(table())))
    assert f"{100 * ABOVE:.3g} % of the sea's energy (m0) lies above the RAO table's highest frequency, " \
           f"1.6 rad/s (3.93 s), out to " in above
    assert above.startswith("vessel 'barge' (vessels.barge.motion.raos): ")
    assert "(up to heave 1 m/m)" in above and "extend the table to shorter periods, or set " \
                                              "environment.water.waves.omega_max to 1.6 rad/s" in above
    assert f"{100 * BELOW:.3g} % of the sea's energy (m0) lies below the RAO table's lowest frequency, " \
           f"0.8 rad/s (7.85 s)" in below
    assert "extend the table to longer periods, or set environment.water.waves.omega_min to 0.8 rad/s" in below


def test_a_row_of_zeros_held_beyond_the_table_is_no_warning():
    """Holding zeros is the RAO tapering to zero: those components do not move the vessel."""
    warnings = rao_range_warnings(rfesim.load_scenario(scene(table(upper_row=0.0))))
    assert len(warnings) == 1 and "lies below" in warnings[0]
    assert rao_range_warnings(rfesim.load_scenario(scene(table(upper_row=0.0, lower_row=0.0)))) == []


def test_the_threshold_is_one_percent_of_m0():
    # table up to 2.8 rad/s: between 0.72 % and 0.76 % of m0 lies above (the bin with 2.8 in it
    # counts or not as its random frequency falls), under the 1 %; up to 2.4 rad/s: 1.34 % to
    # 1.41 %, over
    wp = 2.0 * math.pi / TP
    for top, warned in ((2.8, False), (2.4, True)):
        share = (pm_cumulative(W_HI) - pm_cumulative(top)) / M0
        assert (share > RAO_RANGE_ENERGY) == warned
        out = rao_range_warnings(rfesim.load_scenario(scene(table(frequencies=(0.3 * wp, top)))))
        assert any("lies above" in w for w in out) == warned, (top, share, out)


def test_regular_waves_outside_the_table_move_the_vessel_with_the_held_row():
    short = rao_range_warnings(rfesim.load_scenario(scene(table(), {"kind": "airy", "height": 1.0, "period": 3.0})))
    assert len(short) == 1 and "100 % of the sea's energy (m0) lies above" in short[0]
    assert short[0].endswith("extend the table to shorter periods")      # an Airy wave has no omega_max
    assert rao_range_warnings(rfesim.load_scenario(scene(table(), {"kind": "airy", "height": 1.0,
                                                                   "period": 5.0}))) == []


def test_the_run_s_message_carries_the_warning_and_the_motions_are_unchanged():
    data = scene(table(), duration=0.2)
    res = rfesim.simulate(data)
    above, below = rao_range_warnings(rfesim.load_scenario(data))
    assert res.message.endswith(f"{DYNAMICS_WARNING}{above}{DYNAMICS_WARNING}{below}")
    # statics alone does not move the vessel: no warning
    statics_only = copy.deepcopy(data)
    del statics_only["analysis"]["dynamics"]
    assert DYNAMICS_WARNING not in rfesim.simulate(statics_only).message


@pytest.mark.parametrize("name, warned", [
    ("column_crane", 1), ("column_crane_slewing_motor", 1), ("column_crane_liftoff", 2), ("a_frame", 0),
    ("a_frame_deck_winch", 0), ("reel_lay", 0), ("riser_irregular_sea", 0), ("s_lay_template", 0)])
def test_bundled_scenarios(name, warned):
    """The barge table stops at 4 s (1.571 rad/s); 7.75 % of the cranes' JONSWAP (Hs 2 m,
    Tp 8 s) lies above it. Its 4 s row is zero in head and following seas (the a-frame,
    pipelay and riser scenarios), not in the beam (90 deg) and 165 deg seas of the crane
    scenarios."""
    from pathlib import Path
    path = Path(__file__).resolve().parents[2] / "scenarios" / f"{name}.json"
    out = rao_range_warnings(rfesim.load_scenario(str(path)))
    assert len(out) == warned
    for w in out:
        assert "7.75 % of the sea's energy (m0) lies above the RAO table's highest frequency, 1.571 rad/s (4 s)" in w
