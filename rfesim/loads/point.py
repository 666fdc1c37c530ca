"""Point forces and moments on RFEs (eq. 8.93-8.94).

A force F at a point with body-frame offset ``arm`` from the RFE centre adds F to the
RFE's resultant and ``(R arm) x F`` to its moment; the generalised forces then follow
from the projection onto the RFE's coordinates (eq. 8.94 in trace form, see
``rfesim.model.assemble``). ``local`` loads are given in the RFE frame (follower loads).
"""
from __future__ import annotations

from numba import njit

from ..kinematics import cross_into, matvec_into


@njit(cache=True)
def point_loads(load_rfe, load_arm, load_force, load_moment, load_local, scale, R, F, M, tmp3):
    p = tmp3[0]
    f = tmp3[1]
    m = tmp3[2]
    c = tmp3[3]
    for j in range(load_rfe.shape[0]):
        i = load_rfe[j]
        matvec_into(R[i], load_arm[j], p)
        if load_local[j] != 0:
            matvec_into(R[i], load_force[j], f)
            matvec_into(R[i], load_moment[j], m)
        else:
            for k in range(3):
                f[k] = load_force[j, k]
                m[k] = load_moment[j, k]
        cross_into(p, f, c)
        for k in range(3):
            F[i, k] += scale * f[k]
            M[i, k] += scale * (m[k] + c[k])
