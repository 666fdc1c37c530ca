"""One fused kernel per evaluation of the chain equations A q'' = f (eqs. 8.34, 8.51).

Python-level work per evaluation is reduced to the base motion, the drives and the loads;
poses, composites, velocity terms, elastic forces, the mass matrix and the branch-sparse
solve run here in one numba call.
"""
from __future__ import annotations

from numba import njit

from .classical import sde_forces
from .tree import (
    composite_pass,
    forward_pass,
    generalized_bias,
    ltl_factor,
    ltl_solve,
    mass_matrix,
)


@njit(cache=True)
def evaluate_kernel(parent, kind, axis, placement, inertia, qstart, qcount, coord_stiffness, coord_damping, coord_rest,
                    sde_left, sde_right, sde_left_root, sde_right_root, sde_point_left, sde_point_right,
                    sde_stiffness, sde_damping, load_body, load_point, load_force, load_moment, gravity,
                    TA, TAd, TAdd, q, qd, qdd, with_mass,
                    T, Td, Tdd, Omega, Hc, Fc, Mc, A, h, S, f):
    """f = -e - G + Q - S (joint-force drives are added by the caller); A if with_mass.
    Returns the elastic energy."""
    forward_pass(parent, kind, axis, placement, qstart, qcount, q, qd, qdd, TA, TAd, TAdd, T, Td, Tdd, Omega)
    composite_pass(parent, inertia, T, Tdd, gravity, load_body, load_point, load_force, load_moment, Hc, Fc, Mc)
    generalized_bias(qstart, qcount, Omega, Fc, Mc, h)
    energy = 0.0
    for k in range(q.shape[0]):
        dq = q[k] - coord_rest[k]
        S[k] = coord_stiffness[k] * dq + coord_damping[k] * qd[k]            # eq. 8.49, joint springs
        energy += 0.5 * coord_stiffness[k] * dq * dq
    if sde_left.shape[0] > 0:
        energy += sde_forces(kind, placement, qstart, sde_left, sde_right, sde_left_root, sde_right_root,
                             sde_point_left, sde_point_right, sde_stiffness, sde_damping, q, qd, S)
    for k in range(q.shape[0]):
        f[k] = -h[k] - S[k]
    if with_mass:
        mass_matrix(parent, qstart, qcount, Omega, Hc, A)
    return energy


@njit(cache=True)
def solve_free(A, f, free, lam, Aff, rhs, x):
    """x = A_ff^{-1} f_f by the branch-sparse LTL^T factorisation; False if A_ff is not SPD."""
    n = free.shape[0]
    for i in range(n):
        rhs[i] = f[free[i]]
        for j in range(n):
            Aff[i, j] = A[free[i], free[j]]
    if not ltl_factor(Aff, lam):
        return False
    ltl_solve(Aff, lam, rhs, x)
    return True
