"""Modal analysis about the static equilibrium: K x = omega^2 M x.

K is the block-tridiagonal Jacobian of the static residual (finite differences, symmetrised:
at an equilibrium of conservative loads it is symmetric), M the block-diagonal RFE mass
matrix with every RFE's angles re-based to zero. Fixed coordinates are removed. Small
problems use a dense symmetric solver; long lines a sparse shift-invert Lanczos solver
(scipy eigsh), which keeps the cost linear in the number of RFEs per mode.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from ..errors import SolverError
from ..model.assemble import rebase
from ..model.compile import State
from ..model.outputs import line_points
from .banded import bt_to_sparse
from .system import System

log = logging.getLogger("rfesim")

SHAPE_FLOOR = 1e-4        # line_shapes: displacements below this x (a unit coordinate's length scale) are zero
ZERO_EIGENVALUE = 1e-15   # a negative omega^2 above -this x the stiffness scale is a zero mode's round-off
# a frequency below this fraction of the stiffness-scale frequency (ModalResults.scale_hz) is a
# rigid-body (zero) mode's round-off in print (`rfesim modes`): omega^2 within 1e-16 of the scale;
# measured positive round-off 1.1e-17 (the spin of the pinned catenary riser, 7.8e-7 Hz) and 3e-20
# (the column crane's slew), real first modes at 7e-9 (catenary riser) and 4e-11 (column crane)
RIGID_BODY_FRACTION = 1e-8
# a negative omega^2 within this x the mode's own stiffness scale |v|^T |K| |v| / v^T M v
# whose mode moves no point of any line beyond round-off (a rope spinning about its own axis,
# a body's free yaw) is a zero mode's round-off too. The central-difference Jacobian leaves
# such a mode at up to 3e-15 of the global scale max K_ii / M_ii (the spin of a buoy's taut
# tether, past ZERO_EIGENVALUE), 4e-13 to 1.3e-12 of its own; a real instability that moves
# no line point (a tall box payload capsizing about its shackle at its centre) sits at 1 of
# its own, but at 1e-13 of the global scale on a stiff 20-element rope: the global scale
# cannot tell them apart
SPIN_ROUNDOFF = 1e-8


def signed_omega(w2, scale: float) -> np.ndarray:
    """Angular frequencies (rad/s) from the eigenvalues omega^2 of K x = omega^2 M x:
    sqrt(omega^2) for stable modes and -sqrt(-omega^2) for unstable ones (negative
    stiffness: the static state is unstable and the mode grows as exp(sqrt(-omega^2) t)).
    A negative omega^2 with |omega^2| <= ZERO_EIGENVALUE x scale (scale: the largest
    omega^2 or an estimate of it, max K_ii / M_ii) is the round-off of a zero mode (measured
    at 1e-17 of the scale: the spin of a pinned line) and gives 0. Small positive values
    are kept: a long riser's first mode can sit at 1e-16 of its axial frequencies."""
    w2 = np.asarray(w2, float)
    tol = ZERO_EIGENVALUE * max(float(scale), 0.0)
    w2 = np.where((w2 < 0.0) & (w2 >= -tol), 0.0, w2)
    return np.sign(w2) * np.sqrt(np.abs(w2))


def unstable_note(frequencies_hz) -> str:
    """The warning of a modal analysis with negative-stiffness modes ("" when there is none)."""
    f = np.asarray(frequencies_hz, float)
    bad = np.flatnonzero(f < 0.0)
    if bad.size == 0:
        return ""
    which = ", ".join(str(int(i) + 1) for i in bad[:10]) + (", ..." if bad.size > 10 else "")
    return (f"the static state is unstable: {bad.size} mode{'s' if bad.size > 1 else ''} with negative "
            f"stiffness (mode{'s' if bad.size > 1 else ''} {which}, shown with negative frequencies "
            f"-sqrt(-omega^2)/(2 pi): the growth rate)")


def checked_mode_count(n, available: int | None = None, *, default: int = 10) -> int:
    """The number of modes to compute: n (None: default) must be a positive integer
    (ScenarioError naming n otherwise); above the available coordinates it becomes all of them
    (the caller says so in ModalResults.message, `count_note`)."""
    from ..errors import ScenarioError
    if n is None:
        n = default
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise ScenarioError([("n", f"the number of modes must be a positive integer, got {n!r}")])
    if n < 1:
        raise ScenarioError([("n", f"the number of modes must be a positive integer (at least 1), got {n}")])
    n = int(n)
    return n if available is None else min(n, available)


def count_note(requested: int, available: int) -> str:
    return (f"{requested} modes requested but the model has only {available} moving coordinates: all "
            f"{available} modes are given" if requested > available else "")


def statics_disabled_note(sc) -> str:
    """The note of a modal analysis whose scenario has analysis.statics.enabled false: the
    modes are about the static equilibrium all the same, solved for them ("" with statics on)."""
    if sc.analysis.statics.enabled:
        return ""
    return ("analysis.statics.enabled is false, but the modes are about the static equilibrium: the statics was "
            "solved for the modal analysis (the initial shape of the scenario is not an equilibrium in general)")


def locked_payouts(sc) -> list[str]:
    """The winches and payouts (tensioners, reels) of a scenario whose mode lets them pay out
    in the time domain, but which the modal analysis holds locked (its K is the static Jacobian
    at fixed payouts): a constant-tension winch, a drum winch without a brake, a heave
    compensation on a sheave that can move (its end A neither fixed nor on a vessel, whose
    prescribed motion stands still in the modal analysis), a constant-tension tensioner or reel.
    One description each."""
    out = []
    for name, w in (sc.winches or {}).items():
        why = []
        if w.mode.kind == "tension":
            why.append("mode tension: it pays out at the set tension")
        elif w.mode.kind == "drum" and not w.mode.brake_torque > 0.0:
            why.append("mode drum without a brake: the drum turns under the rope tension")
        line = (sc.lines or {}).get(w.line)
        if w.heave_compensation is not None and line is not None and \
                line.end_a.attach != "fixed" and line.end_a.attach not in (sc.vessels or {}):
            why.append("heave_compensation: it pays out with the sheave's motion")
        if why:
            out.append(f"winch '{name}' ({'; '.join(why)})")
    for name, sup in (sc.supports or {}).items():
        payout = getattr(sup, "payout", None)
        if getattr(payout, "kind", None) == "constant-tension":
            out.append(f"{sup.kind} '{name}' (payout constant-tension: it pays out at the set tension)")
    return out


def locked_note(sc) -> str:
    """The note of a modal analysis on ``locked_payouts`` ("" when there is none)."""
    held = locked_payouts(sc)
    if not held:
        return ""
    return (f"the modal analysis holds every winch and payout locked at its static length, so these modes are "
            f"those with {', '.join(held)} held (a payout free under a set tension adds a zero-stiffness "
            f"coordinate and removes the rope's bounce mode; docs/theory.md, modal analysis)")


def statics_failed(exc: SolverError, sc) -> SolverError:
    """The SolverError of a statics solved for a modal analysis although
    analysis.statics.enabled is false: the failure, saying that the modes need it."""
    if sc.analysis.statics.enabled:
        return exc
    return SolverError("the modal analysis needs the static equilibrium (solved although analysis.statics.enabled "
                       "is false), and its statics failed: " + exc.message, time=exc.time, element=exc.element,
                       quantity=exc.quantity, results=exc.results, hint=exc.hint)


def join_notes(*notes) -> str:
    return "; ".join(x for x in notes if x)


@dataclass
class ModalResults:
    """Natural frequencies and mode shapes about the static state.

    frequencies_hz (nmodes,), ascending: an unstable mode (negative stiffness, omega^2 < 0,
    e.g. a column above its buckling load) has a NEGATIVE frequency -sqrt(-omega^2)/(2 pi)
    (its growth rate over 2 pi), listed first; `unstable` counts them and `message` says so
    (also logged as a warning by the "rfesim" logger). Zero modes (rigid-body motions,
    the spin of a pinned line) give 0.

    shapes (nmodes, ...): the mode in the formulation's own coordinates, scaled to unit
    largest coordinate: (nmodes, n, 6) RFE coordinates for absolute-coordinate lines;
    (nmodes, nq) the concatenated coordinates of every chain / line unit for the classical,
    modified and planar formulations and for chains (angles in rad and translations in m
    mixed, so compare modes through line_shapes).

    line_shapes: name -> (nmodes, npoints, 3), the same in every formulation: the
    displacement of each line's points (end A, every SDE, end B) in the global frame, scaled
    so that the largest displacement over all lines of a mode is 1. A mode whose point
    displacements are at round-off (pure torsion about the line axis, a spin) has zero
    line_shapes rather than noise scaled up to 1.
    """
    frequencies_hz: np.ndarray             # (nmodes,) Hz, negative for unstable modes
    shapes: np.ndarray                     # formulation coordinates (see above), unit max
    line_shapes: dict = field(default_factory=dict)   # name -> (nmodes, npoints, 3) point displacements
    asymmetry: float = 0.0                 # |K - K^T| / |K| before symmetrisation
    message: str = ""                      # warnings: unstable modes, fewer modes than requested
    unstable: int = 0                      # number of negative-stiffness modes
    scale_hz: float = 0.0                  # sqrt(stiffness scale) / (2 pi): max K_ii / M_ii, or the largest omega^2

    @property
    def rigid_body(self) -> np.ndarray:
        """(nmodes,) bool: the modes whose |frequency| is below RIGID_BODY_FRACTION (1e-8) of
        scale_hz, the round-off of a rigid-body (zero) mode; `rfesim modes` prints them as 0."""
        f = np.abs(np.asarray(self.frequencies_hz, float))
        return (f <= RIGID_BODY_FRACTION * float(self.scale_hz)) | (f == 0.0)

    @property
    def periods_s(self) -> np.ndarray:
        """1 / f; inf for a zero mode, NaN for an unstable (negative-frequency) mode."""
        f = np.asarray(self.frequencies_hz, float)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(f > 0.0, 1.0 / np.where(f > 0.0, f, 1.0), np.where(f == 0.0, np.inf, np.nan))

    def __repr__(self) -> str:
        f = ", ".join(f"{x:.5g}" for x in self.frequencies_hz[:10])
        return f"ModalResults(frequencies_hz=[{f}{', ...' if len(self.frequencies_hz) > 10 else ''}])"


def modal_analysis(system: System, state: State, nmodes: int) -> ModalResults:
    import scipy.linalg as sla              # imported here: 0.3 s of every start-up otherwise
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla
    st = state.copy()
    st.qd[:] = 0.0
    dummy = np.zeros_like(st.q)
    rebase(st.q, dummy, st.ref, system.km.rfe_kind, 0.0, dummy, dummy, False)
    system.set_time(st.t)
    system.ws.waves_off[0] = 1          # about the static state: still water plus current
    try:
        km = system.km
        if km.has_closures or system.has_line_leads:
            # a closing join or a rope led along a line: their off-band blocks (in ws.cl_J,
            # ws.ob_J) are added below
            K = system.static_jacobian_hybrid(st.q, st.ref).copy()
        else:
            K = system.static_jacobian_accurate(st.q, st.ref).copy()
        system.evaluate(st)
        Mblk = system.ws.Mgen.copy()
    finally:
        system.ws.waves_off[0] = 0
    mask = system.mask.ravel()
    active = np.flatnonzero(mask)
    nact = active.size
    if nact == 0:
        raise SolverError("modal analysis: the scene has no moving coordinates")
    requested = nmodes
    nmodes = min(nmodes, nact)
    Ksp = bt_to_sparse(K)
    if km.has_closures:
        n6 = 6 * system.n
        for c, s in enumerate(km.cl_sde):
            a, b = int(km.sde_left[s]), int(km.sde_right[s])
            for blk, (i, j) in enumerate(((a, b), (b, a))):
                ii, jj = np.meshgrid(np.arange(6 * i, 6 * i + 6), np.arange(6 * j, 6 * j + 6), indexing="ij")
                Ksp = Ksp + sp.csr_matrix((system.ws.cl_J[c, blk].ravel(), (ii.ravel(), jj.ravel())),
                                          shape=(n6, n6))
    if km.has_offband:
        n6 = 6 * system.n
        for c, (i, j) in enumerate(zip(km.ob_row, km.ob_col)):
            ii, jj = np.meshgrid(np.arange(6 * i, 6 * i + 6), np.arange(6 * j, 6 * j + 6), indexing="ij")
            Ksp = Ksp + sp.csr_matrix((system.ws.ob_J[c].ravel(), (ii.ravel(), jj.ravel())), shape=(n6, n6))
    Ksp = Ksp.tocsr()[active][:, active]
    n = system.n
    Msp = sp.block_diag([Mblk[i] for i in range(n)], format="csr")[active][:, active]
    Ka = (Ksp - Ksp.T)
    knorm = abs(Ksp).max()
    asym = float(abs(Ka).max() / knorm) if knorm > 0 else 0.0
    Ks = 0.5 * (Ksp + Ksp.T)
    Ms = 0.5 * (Msp + Msp.T)
    if nmodes >= nact - 1:
        w2, vec = sla.eigh(Ks.toarray(), Ms.toarray(), subset_by_index=[0, nmodes - 1])
    else:
        # Shift-invert Lanczos: the low modes come out with relative accuracy even when the
        # stiffest (axial, shear) modes are 1e10 times higher, which a dense solver cannot do.
        # The shift sits a little below zero so zero-stiffness modes do not break the factors.
        ratio = np.abs(Ks.diagonal()) / np.maximum(np.abs(Ms.diagonal()), 1e-300)
        sigma = -1e-12 * float(ratio.max())
        w2, vec = spla.eigsh(Ks.tocsc(), k=nmodes, M=Ms.tocsc(), sigma=sigma, which="LM")
        order = np.argsort(w2)
        w2, vec = w2[order], vec[:, order]
    stiff = np.abs(Ks.diagonal()) / np.maximum(np.abs(Ms.diagonal()), 1e-300)
    omega2_scale = float(stiff.max()) if stiff.size else 0.0
    freq = signed_omega(w2, omega2_scale) / (2.0 * np.pi)
    shapes = np.zeros((nmodes, n * 6))
    shapes[:, active] = vec.T
    norms = np.abs(shapes).max(axis=1)
    norms[norms == 0] = 1.0
    shapes /= norms[:, None]
    shapes = shapes.reshape(nmodes, n, 6)
    # point displacements of each line by a small perturbation along each mode
    line_shapes = {}
    ws = system.ws
    km = system.km
    base = {}
    system.evaluate(st)
    for li in system.model.lines:
        pts = np.zeros((li.elements + 2, 3))
        line_points(ws, li.rfe_start, li.rfe_stop, li.sde_start, li.sde_stop, km.rfe_length, pts)
        base[li.name] = pts
        line_shapes[li.name] = np.zeros((nmodes, li.elements + 2, 3))
    scale = 1e-6 * float(km.rfe_length.max())
    pert = st.copy()
    for m in range(nmodes):
        d = shapes[m].copy()
        d[:, 3:] *= 1e-6
        d[:, :3] *= scale
        pert.q[:] = st.q + d
        system.evaluate(pert)
        for li in system.model.lines:
            pts = np.zeros((li.elements + 2, 3))
            line_points(ws, li.rfe_start, li.rfe_stop, li.sde_start, li.sde_stop, km.rfe_length, pts)
            line_shapes[li.name][m] = pts - base[li.name]
    peak = max((np.abs(v).max(axis=(1, 2)) for v in line_shapes.values()), key=lambda a: a.max()) \
        if line_shapes else None
    if peak is not None:
        allpeak = np.max(np.stack([np.abs(v).max(axis=(1, 2)) for v in line_shapes.values()]), axis=0)
        # a spin (no line point moves) with a negative omega^2 at round-off is a zero mode
        for m in np.flatnonzero((allpeak < SHAPE_FLOOR * scale) & (freq < 0.0)):
            v = vec[:, m]
            own = float(np.abs(v) @ (abs(Ks) @ np.abs(v))) / max(float(v @ (Ms @ v)), 1e-300)
            if (2.0 * np.pi * freq[m]) ** 2 <= SPIN_ROUNDOFF * own:
                freq[m] = 0.0
        # a mode that moves no point beyond round-off (pure torsion) keeps its (near-zero)
        # size relative to SHAPE_FLOOR of a unit coordinate's displacement, not noise scaled to 1
        allpeak = np.maximum(allpeak, SHAPE_FLOOR * scale)
        for name in line_shapes:
            line_shapes[name] /= allpeak[:, None, None]
    unstable = int(np.sum(freq < 0.0))
    message = join_notes(unstable_note(freq), count_note(requested, nact))
    if unstable:
        log.warning("modal analysis: %s", unstable_note(freq))
    return ModalResults(frequencies_hz=freq, shapes=shapes, line_shapes=line_shapes, asymmetry=asym,
                        message=message, unstable=unstable,
                        scale_hz=float(np.sqrt(max(omega2_scale, 0.0)) / (2.0 * np.pi)))
