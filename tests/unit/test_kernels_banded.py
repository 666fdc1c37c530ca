"""rfesim.solvers.banded (block-tridiagonal factor/solve) against dense numpy."""
from __future__ import annotations

import numpy as np
import pytest

import reference_impl as ref
from rfesim.solvers.banded import bt_factor, bt_matvec, bt_solve, bt_to_dense, bt_to_sparse, invert6_into, invert_into

SIZES = [1, 2, 7, 50]
SEEDS = [0, 1, 2]
ROUNDOFF = 1e-12


def random_block_tridiagonal(rng, n):
    """Well-conditioned (block diagonally dominant) random blocks; the unused first
    sub-diagonal and last super-diagonal blocks hold garbage that must be ignored."""
    J = rng.normal(size=(n, 3, 6, 6))
    J[:, 1] += 12.0 * np.eye(6)
    J[0, 0] = rng.normal(scale=1e3, size=(6, 6))
    J[n - 1, 2] = rng.normal(scale=1e3, size=(6, 6))
    return J


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("n", SIZES)
def test_dense_form(seed, n):
    J = random_block_tridiagonal(np.random.default_rng(seed), n)
    np.testing.assert_array_equal(bt_to_dense(J), ref.block_tridiagonal_dense(J))


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("n", SIZES)
def test_sparse_form_equals_dense(seed, n):
    J = random_block_tridiagonal(np.random.default_rng(seed), n)
    J[n // 2, 1, 2, 3] = 0.0                       # explicit zeros are dropped, not kept
    sparse = bt_to_sparse(J)
    np.testing.assert_array_equal(sparse.toarray(), ref.block_tridiagonal_dense(J))
    assert sparse.nnz == np.count_nonzero(ref.block_tridiagonal_dense(J))


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("n", SIZES)
def test_factor_and_solve(seed, n):
    rng = np.random.default_rng(seed)
    J = random_block_tridiagonal(rng, n)
    dense = ref.block_tridiagonal_dense(J)
    rhs = rng.normal(size=(n, 6))
    factors = np.zeros((n, 3, 6, 6))
    assert bt_factor(J, factors) == -1
    out = np.zeros((n, 6))
    bt_solve(factors, rhs, out)
    expected = np.linalg.solve(dense, rhs.ravel()).reshape(n, 6)
    tolerance = ROUNDOFF * np.linalg.cond(dense) * np.abs(expected).max()
    np.testing.assert_allclose(out, expected, rtol=0, atol=tolerance)
    aliased = rhs.copy()                           # rhs and out may be the same array
    bt_solve(factors, aliased, aliased)
    np.testing.assert_allclose(aliased, expected, rtol=0, atol=tolerance)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("n", SIZES)
def test_matvec(seed, n):
    rng = np.random.default_rng(seed)
    J = random_block_tridiagonal(rng, n)
    x = rng.normal(size=(n, 6))
    out = np.zeros((n, 6))
    bt_matvec(J, x, out)
    expected = (ref.block_tridiagonal_dense(J) @ x.ravel()).reshape(n, 6)
    np.testing.assert_allclose(out, expected, rtol=0, atol=ROUNDOFF * np.abs(expected).max())


@pytest.mark.parametrize("seed", SEEDS)
def test_invert6(seed):
    rng = np.random.default_rng(seed)
    out = np.zeros((6, 6))
    work = np.zeros((6, 6))
    for _ in range(10):
        A = rng.normal(size=(6, 6))
        assert invert6_into(A, out, work)
        np.testing.assert_allclose(out, np.linalg.inv(A), rtol=0,
                                   atol=ROUNDOFF * np.linalg.cond(A) * np.abs(np.linalg.inv(A)).max())
    # a pivot search is needed: zero on the diagonal
    P = np.eye(6)[[1, 0, 3, 2, 5, 4]] * rng.uniform(1.0, 2.0, size=6)
    assert invert6_into(P, out, work)
    np.testing.assert_allclose(out, np.linalg.inv(P), rtol=0, atol=ROUNDOFF)


@pytest.mark.parametrize("seed", SEEDS)
def test_invert6_is_the_general_inverse_to_the_bit(seed):
    """invert6_into is Gauss-Jordan with the order fixed at 6 (unrolled by the compiler):
    the same operations in the same order as invert_into, so the same bits, pivoting and
    singular verdicts included."""
    rng = np.random.default_rng(seed)
    out6, out, work = np.zeros((6, 6)), np.zeros((6, 6)), np.zeros((6, 6))
    for _ in range(20):
        A = rng.normal(size=(6, 6)) * rng.uniform(1e-3, 1e3, size=(6, 1))
        A[rng.integers(6)] = 0.0 if rng.uniform() < 0.2 else A[rng.integers(6)]   # singular now and then
        ok6 = invert6_into(A, out6, work)
        ok = invert_into(A, out, work)
        assert ok6 == ok
        if ok:
            np.testing.assert_array_equal(out6, out)


def test_invert6_reports_singular_blocks():
    rng = np.random.default_rng(5)
    out = np.zeros((6, 6))
    work = np.zeros((6, 6))
    assert not invert6_into(np.zeros((6, 6)), out, work)
    A = rng.normal(size=(6, 6))
    A[4] = 2.0 * A[1] - A[2]                       # rank 5
    assert not invert6_into(A, out, work)
    B = rng.normal(size=(6, 6))
    B[:, 3] = 0.0                                   # a zero column
    assert not invert6_into(B, out, work)


@pytest.mark.parametrize("n", [2, 7])
def test_factor_reports_the_first_singular_pivot(n):
    rng = np.random.default_rng(3)
    J = random_block_tridiagonal(rng, n)
    J[n - 1, 1] = 0.0
    J[n - 1, 0] = 0.0                               # last pivot D_n - L_n ... = 0
    factors = np.zeros((n, 3, 6, 6))
    assert bt_factor(J, factors) == n - 1
