"""Axial and torsional vibration of a clamped-free bar, and transverse vibration of a taut
beam, against closed forms.

The RFE line of docs/theory.md ('Primary and secondary division'): n segments of length
Delta = L/n, an SDE at the middle of each, RFE 0 (Delta/2, at the clamp, held), RFEs 1..n-1
(Delta) and RFE n (Delta/2, at the free end). Along the axis and about it this is exactly
the lumped chain of n springs EA/Delta (GJ/Delta) and n masses mu Delta (the last mu Delta/2),
whose eigenvalues are known in closed form:

    omega_k = (2 c / Delta) sin((2k - 1) pi / (4 n)),   c = sqrt(EA / mu)  (sqrt(GJ / rho J)),

converging as 1/n^2 to the continuum's (2k - 1) pi c / (2 L). The polar inertia rho J is
twice the line type's rotary_inertia, but at least 2 (1 + nu) mu GJ / EA (docs/theory.md).

A beam pinned at both ends under tension T (no gravity):
    omega_k^2 = (k pi / L)^2 (T + EI (k pi / L)^2) / mu
(geometric and bending stiffness together); the RFE chain converges to it as 1/n^2.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim

L_BAR, EA, MU = 10.0, 1e9, 10.0
STIFF = 1e13                     # bending and shear: their modes lie far above the axial ones


def bar(n, GJ, rotary):
    return {"environment": {"gravity": 0.0},
            "line_types": {"bar": {"EA": EA, "EIy": STIFF, "EIz": STIFF, "GA": STIFF, "GJ": GJ,
                                   "mass_per_length": MU, "rotary_inertia": rotary}},
            "lines": {"bar": {"type": "bar", "length": L_BAR, "elements": n,
                              "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                        "connection": "clamped"},
                              "end_b": {"attach": "free"}}},
            "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}}}


def axial_and_torsion(n, GJ, rotary, modes=8):
    """(axial, torsional) frequencies in Hz, told apart by their shapes: an axial mode moves
    the line's points along x, a torsional one moves none (line_shapes zero)."""
    md = rfesim.modes(bar(n, GJ, rotary), n=modes)
    assert md.unstable == 0
    shapes = md.line_shapes["bar"]
    axial, torsion = [], []
    for f, s in zip(md.frequencies_hz, shapes):
        top = np.abs(s).max()
        if top < 1e-6:
            torsion.append(f)
        elif np.abs(s[:, 0]).max() > 0.999 * top:
            axial.append(f)
        else:
            raise AssertionError(f"a mode at {f} Hz that is neither axial nor torsional")
    return np.array(axial), np.array(torsion)


def chain_hz(c, n, k):
    """The lumped chain's frequencies (Hz) of modes k (1-based)."""
    return c / (math.pi * L_BAR / n) * np.sin((2 * k - 1) * math.pi / (4 * n))


def continuum_hz(c, k):
    return (2 * k - 1) * c / (4 * L_BAR)


@pytest.mark.parametrize("n", [10, 20, 40])
def test_axial_and_torsion_modes_are_the_lumped_chain_exactly(n):
    """GJ 5e7, rotary 1 kg m: polar 2 kg m (above the floor 1.3): c = 1e4 m/s axially and
    5000 m/s in torsion; every axial and torsional mode found equals the chain's to 1e-9."""
    axial, torsion = axial_and_torsion(n, GJ=5e7, rotary=1.0)
    assert len(axial) >= 2 and len(torsion) >= 4
    k_a, k_t = np.arange(1, len(axial) + 1), np.arange(1, len(torsion) + 1)
    np.testing.assert_allclose(axial, chain_hz(math.sqrt(EA / MU), n, k_a), rtol=1e-9)
    np.testing.assert_allclose(torsion, chain_hz(math.sqrt(5e7 / 2.0), n, k_t), rtol=1e-9)


def test_axial_and_torsion_modes_converge_to_the_continuum_as_1_over_n2():
    err = []
    for n in (10, 20, 40):
        axial, torsion = axial_and_torsion(n, GJ=5e7, rotary=1.0)
        err.append([axial[0] / continuum_hz(1e4, 1) - 1.0, axial[1] / continuum_hz(1e4, 2) - 1.0,
                    torsion[0] / continuum_hz(5000.0, 1) - 1.0])
    err = np.abs(np.array(err))
    orders = np.log2(err[:-1] / err[1:])
    assert np.all(np.abs(orders - 2.0) < 0.05), orders
    # first mode within 1e-4 at 40 elements (pi^2 / (96 n^2) = 6.4e-5)
    assert err[-1, 0] < 1e-4 and err[-1, 2] < 1e-4
    assert err[-1, 0] == pytest.approx(math.pi ** 2 / (96 * 40 ** 2), rel=1e-2)


def test_torsion_inertia_floor():
    """Polar inertia given below 2 (1 + nu) mu GJ / EA (here 2 x 0.5 against 13 kg m, nu 0.3):
    the torsional modes are those of the floor, as docs/theory.md says."""
    n = 20
    _, torsion = axial_and_torsion(n, GJ=5e8, rotary=0.5)
    polar = 2.0 * 1.3 * MU * 5e8 / EA
    k = np.arange(1, len(torsion) + 1)
    np.testing.assert_allclose(torsion, chain_hz(math.sqrt(5e8 / polar), n, k), rtol=1e-9)


# --------------------------------------------------------------------------- taut beam
L_T, EA_T, EI_T, MU_T, STRETCH = 20.0, 1e8, 2e4, 50.0, 0.002


def taut(n):
    span = L_T * (1.0 + STRETCH)
    return {"environment": {"gravity": 0.0},
            "line_types": {"s": {"EA": EA_T, "EIy": EI_T, "EIz": EI_T, "GA": 1e10, "GJ": 1e4,
                                 "mass_per_length": MU_T, "rotary_inertia": 0.0}},
            "lines": {"s": {"type": "s", "length": L_T, "elements": n, "shear_stiffness": "kruszewski",
                            "end_a": {"attach": "fixed", "position": [0, 0, 0], "connection": "pinned"},
                            "end_b": {"attach": "fixed", "position": [span, 0, 0], "connection": "pinned"}}},
            "analysis": {"statics": {"enabled": True, "tolerance": 1e-12}, "dynamics": {"enabled": False}}}


def taut_errors(n, modes=4):
    """Tension from statics (against EA x stretch) and the relative errors of the first
    ``modes`` transverse frequencies (each a pair, in y and z) against the closed form on the
    stretched span with the mass spread over it."""
    sc = taut(n)
    tension = rfesim.statics(sc).line("s").tension[0]
    T = float(np.mean(tension))
    assert np.ptp(tension) < 1e-9 * T
    md = rfesim.modes(sc, n=2 * modes + 4)
    assert md.unstable == 0
    shapes = md.line_shapes["s"]
    side = sorted(f for f, s in zip(md.frequencies_hz, shapes)
                  if f > 0.01 and np.abs(s[:, 1:]).max() > 0.99 * np.abs(s).max())
    pairs = np.array(side[:2 * modes]).reshape(modes, 2)
    np.testing.assert_allclose(pairs[:, 0], pairs[:, 1], rtol=1e-9)       # y and z alike
    span = L_T * (1.0 + STRETCH)
    kk = np.arange(1, modes + 1) * math.pi / span
    exact = kk * np.sqrt((T + EI_T * kk ** 2) / (MU_T * L_T / span)) / (2 * math.pi)
    return T, pairs[:, 0] / exact - 1.0


def test_taut_beam_transverse_modes_converge_to_the_closed_form():
    """T = EA x 0.002 = 200 kN; the bending term is 0.25 % (mode 1) to 4 % (mode 4) of the
    tension term. Errors fall as 1/n^2 (from above), mode 1 within 1e-4 at 80 elements."""
    errs = []
    for n in (20, 40, 80):
        T, e = taut_errors(n)
        assert T == pytest.approx(EA_T * STRETCH, rel=1e-9)
        errs.append(e)
    errs = np.array(errs)
    assert np.all(errs > 0)
    orders = np.log2(errs[:-1] / errs[1:])
    assert np.all(np.abs(orders - 2.0) < 0.1), orders
    assert errs[-1, 0] < 1e-4 and errs[-1, -1] < 1.1e-3
