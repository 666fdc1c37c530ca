"""Joint points of a line's initial shape along a polyline (rfesim.model.compile._Curve).

``march_joints`` is the compiled form of ``_Curve._march``: from ``start``, each joint is
the point of the polyline ahead at the given straight distance from the previous joint
(the sphere-polyline intersection, moving forward), continuing straight along the
curve's last direction past its end. ``_Curve.joints`` runs it up to 42 times per line
(the secant on the closing strain), which made it most of a riser's model build in
Python.

Its arithmetic is that of the numpy code it replaces, operation for operation: a 3-vector
dot product (``d @ d``, ``np.linalg.norm``) was numpy's, i.e. OpenBLAS ``ddot``, which on
the machine the kernel was written on (OpenBLAS's Haswell kernel) runs its scalar tail
``dot += y[i] * x[i]`` from 0 compiled to fused multiply-adds: ``_dot3`` is that chain of
FMAs (llvm.fma, one rounding each; exact in software where the CPU has no FMA), and the
joints were the same to the last bit there. OpenBLAS picks its kernel by CPU, and on
others (an AMD EPYC, 2026-11-28) numpy's dot of 3-vectors rounds differently in the last
bit: the kernel keeps the fused chain on every machine, so a start shape no longer depends
on the BLAS build. Elementwise operations round separately as in numpy (no fastmath: no
contraction), and ``max``/``min`` keep Python's choice on ties and NaN. The slow readable
reference is kept in tests/unit/test_march_kernel.py (its dots are ``_dot3``, which is
checked exactly against the fused chain in rational arithmetic).
"""
from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic


@intrinsic
def _fma(typingctx, a, b, c):
    """a * b + c with one rounding (llvm.fma.f64)."""
    if not all(isinstance(t, types.Float) for t in (a, b, c)):
        return None
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        args = [context.cast(builder, v, t, types.float64) for v, t in zip(args, signature.args)]
        dbl = ir.DoubleType()
        fn = builder.module.declare_intrinsic("llvm.fma", [dbl], ir.FunctionType(dbl, [dbl, dbl, dbl]))
        return builder.call(fn, args)

    return sig, codegen


@njit(cache=True)
def _dot3(x0, x1, x2, y0, y1, y2):
    """x @ y of two 3-vectors as OpenBLAS's Haswell ddot computes it (dot = 0; dot += y[i] *
    x[i], fused), on every machine."""
    s = _fma(y0, x0, 0.0)
    s = _fma(y1, x1, s)
    return _fma(y2, x2, s)


@njit(cache=True)
def march_joints(X, start, lengths, last_dir):
    """Joints J0 = start, J1, ... with |J_{i+1} - J_i| = lengths[i], each on the polyline X
    (m, 3) at or after the segment of the previous one; past the end of X along last_dir."""
    n = lengths.shape[0]
    pts = np.empty((n + 1, 3))
    pts[0, 0] = start[0]
    pts[0, 1] = start[1]
    pts[0, 2] = start[2]
    nseg = X.shape[0] - 1
    seg = 0
    for i in range(n):
        ell = lengths[i]
        c0 = pts[i, 0]
        c1 = pts[i, 1]
        c2 = pts[i, 2]
        found = False
        while seg < nseg:
            p00 = X[seg, 0]
            p01 = X[seg, 1]
            p02 = X[seg, 2]
            p10 = X[seg + 1, 0]
            p11 = X[seg + 1, 1]
            p12 = X[seg + 1, 2]
            d0 = p10 - p00
            d1 = p11 - p01
            d2 = p12 - p02
            a = _dot3(d0, d1, d2, d0, d1, d2)
            if not a > 0.0:
                seg += 1              # a repeated point (a curve with its slack bunched up)
                continue
            e0 = p10 - c0
            e1 = p11 - c1
            e2 = p12 - c2
            if math.sqrt(_dot3(e0, e1, e2, e0, e1, e2)) >= ell:
                # solve |p0 + u d - c| = ell for the largest u in [0, 1]
                f0 = p00 - c0
                f1 = p01 - c1
                f2 = p02 - c2
                b = _dot3(2.0 * f0, 2.0 * f1, 2.0 * f2, d0, d1, d2)
                cc = _dot3(f0, f1, f2, f0, f1, f2) - ell * ell
                disc = b * b - 4.0 * a * cc
                if 0.0 > disc:        # max(disc, 0.0)
                    disc = 0.0
                u = (-b + math.sqrt(disc)) / (2.0 * a)
                if 0.0 > u:           # min(max(u, 0.0), 1.0)
                    u = 0.0
                if 1.0 < u:
                    u = 1.0
                pts[i + 1, 0] = p00 + u * d0
                pts[i + 1, 1] = p01 + u * d1
                pts[i + 1, 2] = p02 + u * d2
                found = True
                break
            seg += 1
        if not found:                 # past the end of the curve: continue straight
            pts[i + 1, 0] = c0 + ell * last_dir[0]
            pts[i + 1, 1] = c1 + ell * last_dir[1]
            pts[i + 1, 2] = c2 + ell * last_dir[2]
    return pts
