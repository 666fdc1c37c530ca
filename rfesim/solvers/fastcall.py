"""Repeated calls of a numba kernel from Python without numba's argument typing.

A call of a compiled kernel from Python types every argument first; for the model and
workspace NamedTuples (``KernelModel`` has over a hundred arrays) that alone costs
20-45 us a call, more than many output kernels take to run. ``FastCall`` types the
arguments once, keeps the compiled entry point of that signature and calls it directly
while the arguments keep their types: the same tuple objects (held here, so their ids stay
theirs) and arrays of the same dtype, rank, layout and writeability. Any other call goes
through the dispatcher as usual (and becomes the new cached signature).
"""
from __future__ import annotations

import numpy as np


def _key(args) -> tuple:
    key = []
    for a in args:
        if isinstance(a, np.ndarray):
            f = a.flags
            key.append((a.dtype.num, a.ndim, f.c_contiguous, f.f_contiguous, f.writeable))
        elif isinstance(a, tuple):
            key.append(id(a))
        else:
            key.append(type(a))
    return tuple(key)


class FastCall:
    """``FastCall(kernel)(*args)`` is ``kernel(*args)``, typed once per signature."""

    def __init__(self, kernel):
        self.kernel = kernel
        self._key = None
        self._entry = None
        self._held = ()

    def __call__(self, *args):
        key = _key(args)
        if key == self._key:
            return self._entry(*args)
        out = self.kernel(*args)
        sig = tuple(self.kernel.typeof_pyval(a) for a in args)
        cres = self.kernel.overloads.get(sig)
        if cres is not None:
            self._key = key
            self._entry = cres.entry_point
            self._held = tuple(a for a in args if isinstance(a, tuple))
        return out
