"""Ramberg-Osgood laws with a large exponent (steels close to perfectly plastic): the
stress inverse and the tangent no longer form yield_stress**n, which overflowed for
n > 35 (an OverflowError from deep inside, "internal error", exit code 4)."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.materials.stress_strain import RambergOsgood


@pytest.mark.parametrize("n", [20.0, 36.0, 60.0, 200.0])
def test_stress_inverts_strain_and_the_tangent_is_its_slope(n):
    law = RambergOsgood(youngs_modulus=207e9, yield_stress=448e6, exponent=n)
    s = np.array([1e6, 200e6, 440e6, 448e6, 455e6, 470e6])
    e = law.strain(s)
    np.testing.assert_allclose(law.stress(e), s, rtol=1e-12)
    np.testing.assert_allclose(law.stress(-e), -s, rtol=1e-12)
    de = 1e-7 * e
    slope = (law.strain(s + 1e-6 * s) - law.strain(s - 1e-6 * s)) / (2e-6 * s)
    np.testing.assert_allclose(law.tangent(e), 1.0 / slope, rtol=1e-6)
    assert np.all(np.isfinite(law.tangent(e + de)))


def test_a_pipe_of_exponent_40_runs():
    from test_cli import CANTILEVER      # pytest puts tests/ on sys.path
    import copy
    sc = copy.deepcopy(CANTILEVER)
    sc["line_types"]["beam"] = {"outer_diameter": 0.3239, "wall_thickness": 0.0159, "youngs_modulus": 207e9, "density": 7850.0,
                                "material": {"kind": "elastoplastic", "law": "ramberg-osgood",
                                             "yield_stress": 448e6, "ro_n": 40.0}}
    sc["lines"]["pipe"]["loads"][0]["force"] = [0.0, 0.0, -50e3]
    sc["analysis"].pop("dynamics")
    res = rfesim.statics(sc)
    assert res.status == 0
    M = float(np.asarray(res.line("pipe").bend_moment)[0].max())
    assert M == pytest.approx(50e3 * 10.0, rel=0.06)          # the root moment of the tip load
