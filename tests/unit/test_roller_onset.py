"""Smooth onset of the roller contact (rfesim.loads.rollers.contact_law) and what it is for:
an S-lay over a stinger that steps without halving its time step."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import rollers_reference as rref
from rfesim.loads.rollers import CONTACT_ONSET, contact_law
from test_rollers import make_case, run_kernel

ROOT = Path(__file__).resolve().parents[2]


def test_contact_law_force_and_tangent_are_continuous():
    k, c, d0 = 1e7, 1e4, 2e-3
    # quadratic part: k delta^2 / (2 delta_0), tangent k delta / delta_0
    assert contact_law(0.5 * d0, 0.0, k, c, d0) == pytest.approx(k * (0.5 * d0) ** 2 / (2 * d0), rel=1e-14)
    # linear part: k (delta - delta_0 / 2)
    assert contact_law(3 * d0, 0.0, k, c, d0) == pytest.approx(k * 2.5 * d0, rel=1e-14)
    # at first touch the force and its tangent start from 0 (the sharp law jumps to k)
    e = 1e-9 * d0
    assert contact_law(e, 0.0, k, c, d0) < 1e-8 * k * e
    # at the onset depth force and tangent agree from both sides
    lo, hi = contact_law(d0 - e, 0.0, k, c, d0), contact_law(d0 + e, 0.0, k, c, d0)
    assert hi - lo == pytest.approx(2 * e * k, rel=1e-5)
    slope_lo = (contact_law(d0 - e, 0.0, k, c, d0) - contact_law(d0 - 3 * e, 0.0, k, c, d0)) / (2 * e)
    slope_hi = (contact_law(d0 + 3 * e, 0.0, k, c, d0) - contact_law(d0 + e, 0.0, k, c, d0)) / (2 * e)
    assert slope_lo == pytest.approx(k, rel=1e-4) and slope_hi == pytest.approx(k, rel=1e-4)
    # damping ramps in with the same factor: no jump of c v at first touch
    assert contact_law(0.25 * d0, -0.1, k, c, d0) == pytest.approx(k * (0.25 * d0) ** 2 / (2 * d0) + 0.25 * c * 0.1,
                                                                   rel=1e-14)
    assert contact_law(e, -1.0, k, c, d0) < 1e-6 * c
    # it never pulls
    assert contact_law(0.5 * d0, 10.0, k, c, d0) == 0.0
    # onset 0 is the sharp law max(0, k delta - c v)
    assert contact_law(1e-3, -0.1, k, c, 0.0) == pytest.approx(k * 1e-3 + c * 0.1, rel=1e-14)


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_kernel_matches_reference_inside_the_onset(seed):
    """Onset depths of the order of the penetrations (up to 5 cm in these cases), so that
    contacts fall on both sides of them; the kernel against the numpy reference."""
    rng, args = make_case(seed)
    nr = args[0].shape[0]
    onset = rng.uniform(0.0, 0.06, size=nr)
    onset[0] = 0.0                                    # a sharp one too
    anchor = rng.uniform(-0.3, 0.3, size=nr)
    anchored = rng.integers(0, 2, size=nr).astype(np.int64)
    hint = np.full(nr, -1, np.int64)
    F, M, force, normal, at, adt = run_kernel(args, hint, anchor, anchored, 0, onset=onset)
    (attach, point, axis, hw, rho, k, c, mu, kt, lo, hi, length, radius, att, R, r, v, w) = args
    Fr, Mr, force_r, normal_r, at_r, adt_r = rref.roller_forces(
        attach, point, axis, hw, rho, k, c, mu, kt, lo, hi, length, radius, *att, R, r, v, w, anchor, anchored, 0,
        roller_onset=onset)
    assert (normal_r > 0).sum() >= 3
    scale = max(np.abs(Fr).max(), 1.0)
    np.testing.assert_allclose(F, Fr, rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(M, Mr, rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(normal, normal_r, rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(at[adt == 1], at_r[adt_r == 1], rtol=0, atol=1e-12)


def test_default_onset_is_a_fraction_of_pipe_and_roller_radius():
    import rfesim
    from rfesim.model.compile import compile_scenario
    sc = rfesim.load_scenario(ROOT / "scenarios" / "s_lay.json")
    km = compile_scenario(sc).km
    assert km.roller_onset == pytest.approx(CONTACT_ONSET * (0.3239 / 2 + 0.15), rel=1e-12)
    data = json.loads((ROOT / "scenarios" / "s_lay.json").read_text())
    data["supports"]["stinger"]["contact_onset"] = 0.0
    assert np.all(compile_scenario(rfesim.load_scenario(data)).km.roller_onset == 0.0)
    data["supports"]["stinger"]["contact_onset"] = -1.0
    with pytest.raises(rfesim.ScenarioError, match="contact_onset"):
        rfesim.load_scenario(data)
