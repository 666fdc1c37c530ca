"""Block-tridiagonal matrices of RFE lines, factored and solved in O(n).

An SDE couples only its two RFEs, so the Jacobian of a scene of lines (RFEs numbered
back to back) is block tridiagonal with 6x6 blocks: ``J[i, 0]`` couples RFE i to i-1,
``J[i, 1]`` is the diagonal block, ``J[i, 2]`` couples i to i+1 (zero across the
boundary between two lines). Block LU (block Thomas) with explicitly inverted pivot
blocks (Gauss-Jordan with partial pivoting inside each 6x6 block).

The Jacobian itself is formed by finite differences of the residual with the RFEs
coloured by ``index mod 3`` (18 residual evaluations for any number of RFEs).
"""
from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def invert6_into(A, out, work):
    """out = A^-1 for a 6x6 block (Gauss-Jordan, partial pivoting). Returns False if singular.
    The order 6 is a constant here, so the compiler unrolls the elimination's inner loops
    (the same operations as ``invert_into``; bt_factor of the S-lay benchmark's Jacobian
    0.14 -> 0.12 ms)."""
    return _gauss_jordan(A, out, work, 6)


@njit(cache=True, _nrt=True)
def bt_factor(J, F):
    """Factor the block-tridiagonal J (n, 3, 6, 6) into F (n, 3, 6, 6):
    F[i, 0] = L_i D'_{i-1}^-1, F[i, 1] = D'_i^-1, F[i, 2] = U_i. Returns the first block
    whose pivot is singular, or -1."""
    n = J.shape[0]
    work = np.empty((6, 6))
    Dp = np.empty((6, 6))
    for i in range(n):
        for a in range(6):
            for b in range(6):
                Dp[a, b] = J[i, 1, a, b]
                F[i, 2, a, b] = J[i, 2, a, b]
        if i > 0:
            # X = L_i Dinv_{i-1}; D'_i = D_i - X U_{i-1}
            for a in range(6):
                for b in range(6):
                    s = 0.0
                    for k in range(6):
                        s += J[i, 0, a, k] * F[i - 1, 1, k, b]
                    F[i, 0, a, b] = s
            for a in range(6):
                for b in range(6):
                    s = 0.0
                    for k in range(6):
                        s += F[i, 0, a, k] * F[i - 1, 2, k, b]
                    Dp[a, b] -= s
        else:
            for a in range(6):
                for b in range(6):
                    F[i, 0, a, b] = 0.0
        if not invert6_into(Dp, F[i, 1], work):
            return i
    return -1


@njit(cache=True, _nrt=True)
def bt_solve(F, rhs, out):
    """Solve J x = rhs with the factors of bt_factor; rhs, out (n, 6) (may alias)."""
    n = F.shape[0]
    y = np.empty((n, 6))
    for i in range(n):
        for a in range(6):
            s = rhs[i, a]
            if i > 0:
                for k in range(6):
                    s -= F[i, 0, a, k] * y[i - 1, k]
            y[i, a] = s
    tmp = np.empty(6)
    for i in range(n - 1, -1, -1):
        for a in range(6):
            s = y[i, a]
            if i < n - 1:
                for k in range(6):
                    s -= F[i, 2, a, k] * out[i + 1, k]
            tmp[a] = s
        for a in range(6):
            s = 0.0
            for k in range(6):
                s += F[i, 1, a, k] * tmp[k]
            out[i, a] = s


@njit(cache=True)
def invert_into(A, out, work):
    """out = A^-1 for a small square A (Gauss-Jordan, partial pivoting). False if singular."""
    return _gauss_jordan(A, out, work, A.shape[0])


@njit(cache=True, inline="always")
def _gauss_jordan(A, out, work, m):
    """Gauss-Jordan with partial pivoting on the leading m x m of A; inlined into its callers
    so that a constant m reaches the compiler."""
    scale = 0.0
    for i in range(m):
        for j in range(m):
            work[i, j] = A[i, j]
            out[i, j] = 1.0 if i == j else 0.0
            if abs(A[i, j]) > scale:
                scale = abs(A[i, j])
    if scale == 0.0:
        return False
    for c in range(m):
        p = c
        best = abs(work[c, c])
        for r in range(c + 1, m):
            if abs(work[r, c]) > best:
                best = abs(work[r, c])
                p = r
        if best <= 1e-300 or best < 1e-15 * scale:
            return False
        if p != c:
            for j in range(m):
                tmp = work[c, j]
                work[c, j] = work[p, j]
                work[p, j] = tmp
                tmp = out[c, j]
                out[c, j] = out[p, j]
                out[p, j] = tmp
        inv = 1.0 / work[c, c]
        for j in range(m):
            work[c, j] *= inv
            out[c, j] *= inv
        for r in range(m):
            if r == c:
                continue
            f = work[r, c]
            if f != 0.0:
                for j in range(m):
                    work[r, j] -= f * work[c, j]
                    out[r, j] -= f * out[c, j]
    return True


# --------------------------------------------------------------------------- closing joins
# A closing join (rfesim.model.joins) adds an SDE between RFEs a and b that are not
# neighbours: J = B + U W^T with B the block-tridiagonal part (in J) and, per closure c,
# U's columns E_a K_ab e_k and E_b K_ba e_k, W's E_b e_k and E_a e_k (k = 0..5; K_ab =
# ws.cl_J[c, 0], K_ba = ws.cl_J[c, 1]). Woodbury: J^-1 r = y - Z S^-1 W^T y with y = B^-1 r,
# Z = B^-1 U (12 nc solves per factorisation) and S = I + W^T Z (12 nc x 12 nc).
# Further off-band blocks (a rope led along a line, rfesim.loads.reeving: km.ob_row,
# km.ob_col, ws.ob_J) follow the closures' 12 nc columns, 6 each: U's E_row K e_k, W's E_col e_k.

@njit(cache=True)
def _woodbury_node(km, idx, column):
    """The RFE of U's column (``column``) or W's row ``idx``: 12 per closure, its end a's
    6 then its end b's; a U column belongs to that end, a W row to the other one; then 6 per
    further off-band block, a U column on its row RFE, a W row on its column RFE."""
    nc12 = 12 * km.cl_sde.shape[0]
    if idx >= nc12:
        k = (idx - nc12) // 6
        return km.ob_row[k] if column else km.ob_col[k]
    s = km.cl_sde[idx // 12]
    first = (idx % 12) < 6
    if first == column:
        return km.sde_left[s]
    return km.sde_right[s]


@njit(cache=True, _nrt=True)
def bt_factor_closed(J, F, km, ws):
    """``bt_factor`` of J's band, then Z and S^-1 of the closures and further off-band
    blocks into ws (see above). Returns the first singular pivot block, n for a singular
    capacitance matrix, or -1."""
    bad = bt_factor(J, F)
    if bad >= 0 or not (km.has_closures or km.has_offband):
        return bad
    n = J.shape[0]
    m = ws.cl_Z.shape[0]
    nc12 = 12 * km.cl_sde.shape[0]
    rhs = ws.cl_rhs
    for col in range(m):
        k = col % 6
        node = _woodbury_node(km, col, True)
        for i in range(n):
            for a in range(6):
                rhs[i, a] = 0.0
        if col < nc12:
            c = col // 12
            part = (col % 12) // 6
            for a in range(6):
                rhs[node, a] = ws.cl_J[c, part, a, k]
        else:
            blk = (col - nc12) // 6
            for a in range(6):
                rhs[node, a] = ws.ob_J[blk, a, k]
        bt_solve(F, rhs, ws.cl_Z[col])
    for row in range(m):
        k = row % 6
        node = _woodbury_node(km, row, False)
        for col in range(m):
            ws.cl_work[row, col] = ws.cl_Z[col, node, k] + (1.0 if row == col else 0.0)
    S = ws.cl_work.copy()
    if not invert_into(S, ws.cl_S, ws.cl_work):
        return n
    return -1


@njit(cache=True, _nrt=False)
def bt_solve_closed(F, rhs, out, km, ws):
    """Solve J x = rhs with the factors of ``bt_factor_closed`` (rhs, out may alias). No
    allocation, no reference counting of the model and workspace tuples (docs/theory.md,
    'Reference counting off in the evaluation chain'): it runs at every Newton iteration."""
    bt_solve(F, rhs, out)
    if not (km.has_closures or km.has_offband):
        return
    m = ws.cl_Z.shape[0]
    w = ws.cl_w
    for row in range(m):
        w[row] = out[_woodbury_node(km, row, False), row % 6]
    n = out.shape[0]
    for col in range(m):
        v = 0.0
        for row in range(m):
            v += ws.cl_S[col, row] * w[row]
        if v != 0.0:
            for i in range(n):
                for a in range(6):
                    out[i, a] -= ws.cl_Z[col, i, a] * v


@njit(cache=True)
def bt_matvec(J, x, out):
    """out = J x for a block-tridiagonal J (used by tests and iterative refinement)."""
    n = J.shape[0]
    for i in range(n):
        for a in range(6):
            s = 0.0
            for k in range(6):
                s += J[i, 1, a, k] * x[i, k]
                if i > 0:
                    s += J[i, 0, a, k] * x[i - 1, k]
                if i < n - 1:
                    s += J[i, 2, a, k] * x[i + 1, k]
            out[i, a] = s


def bt_to_dense(J: np.ndarray) -> np.ndarray:
    """Dense form of a block-tridiagonal matrix (tests and small modal problems only)."""
    n = J.shape[0]
    A = np.zeros((6 * n, 6 * n))
    for i in range(n):
        A[6 * i:6 * i + 6, 6 * i:6 * i + 6] = J[i, 1]
        if i > 0:
            A[6 * i:6 * i + 6, 6 * (i - 1):6 * i] = J[i, 0]
        if i < n - 1:
            A[6 * i:6 * i + 6, 6 * (i + 1):6 * (i + 2)] = J[i, 2]
    return A


def bt_to_sparse(J: np.ndarray):
    """scipy CSR form of a block-tridiagonal matrix (modal analysis of long lines)."""
    import scipy.sparse as sp
    n = J.shape[0]
    rows, cols, vals = [], [], []
    ii, jj = np.meshgrid(np.arange(6), np.arange(6), indexing="ij")
    for slot, off in ((0, -1), (1, 0), (2, 1)):
        idx = np.arange(n)
        valid = (idx + off >= 0) & (idx + off < n)
        idx = idx[valid]
        blocks = J[idx, slot]                          # (m, 6, 6)
        rows.append((6 * idx[:, None, None] + ii[None]).ravel())
        cols.append((6 * (idx + off)[:, None, None] + jj[None]).ravel())
        vals.append(blocks.ravel())
    A = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(6 * n, 6 * n))
    A.eliminate_zeros()
    return A
