"""Modal analysis about the static equilibrium: K x = omega^2 M x.

K is the block-tridiagonal Jacobian of the static residual (finite differences, symmetrised:
at an equilibrium of conservative loads it is symmetric), M the block-diagonal RFE mass
matrix with every RFE's angles re-based to zero. Fixed coordinates are removed. Small
problems use a dense symmetric solver; long lines a sparse shift-invert Lanczos solver
(scipy eigsh), which keeps the cost linear in the number of RFEs per mode.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import SolverError
from ..model.assemble import rebase
from ..model.compile import State
from ..model.outputs import line_points
from .banded import bt_to_sparse
from .system import System



@dataclass
class ModalResults:
    frequencies_hz: np.ndarray             # (nmodes,) Hz
    shapes: np.ndarray                     # (nmodes, n, 6) generalised-coordinate shapes (unit max)
    line_shapes: dict = field(default_factory=dict)   # name -> (nmodes, npoints, 3) point displacements
    asymmetry: float = 0.0                 # |K - K^T| / |K| before symmetrisation

    @property
    def periods_s(self) -> np.ndarray:
        with np.errstate(divide="ignore"):
            return 1.0 / self.frequencies_hz

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
        if km.has_closures:
            # a closing join: its off-band blocks (in ws.cl_J) are added below
            K = system.static_jacobian_closed(st.q, st.ref).copy()
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
    freq = np.sqrt(np.clip(w2, 0.0, None)) / (2.0 * np.pi)
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
        allpeak[allpeak == 0] = 1.0
        for name in line_shapes:
            line_shapes[name] /= allpeak[:, None, None]
    return ModalResults(frequencies_hz=freq, shapes=shapes, line_shapes=line_shapes, asymmetry=asym)
