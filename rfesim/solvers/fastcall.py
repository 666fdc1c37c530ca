"""Repeated calls of a numba kernel from Python without numba's argument typing.

A call of a compiled kernel from Python types every argument first; for the model and
workspace NamedTuples (``KernelModel`` has over a hundred arrays) that alone costs
20-45 us a call, more than many output kernels take to run. ``FastCall`` types the
arguments once, keeps the compiled entry point of that signature and calls it directly
while the arguments keep their types: (named) tuples of the same class whose members keep
their types, arrays of the same dtype, rank, layout and writeability, scalars of the same
Python type. Any other call goes through the dispatcher as usual (and becomes the new cached
signature). Tuples used to be keyed by their identity: a state copied at every step (the
winch-controlled loop) then brought a new ``Reference`` tuple each time, and whenever its
id was new the call was typed again, 7 ms each time.
"""
from __future__ import annotations

import numpy as np


def _arg_key(a):
    if isinstance(a, np.ndarray):
        f = a.flags
        return (a.dtype.num, a.ndim, f.c_contiguous, f.f_contiguous, f.writeable)
    if isinstance(a, tuple):
        # a (named) tuple types as its class and its members: a new tuple of the same
        # structure (a state's copied Reference) takes the same compiled entry point
        return (type(a),) + tuple(_arg_key(x) for x in a)
    return type(a)


def _key(args) -> tuple:
    return tuple(_arg_key(a) for a in args)


class FastCall:
    """``FastCall(kernel)(*args)`` is ``kernel(*args)``, typed once per signature.

    The arguments of the last typed call are held; a call whose arguments are the same
    objects (or scalars of the same Python type, or arrays of the same key) skips even the
    key: that is the common case of a time loop calling with the same work arrays."""

    def __init__(self, kernel):
        self.kernel = kernel
        self._key = None
        self._entry = None
        self._held = ()
        self._args = None
        self._arg_keys = None

    def _same(self, args) -> bool:
        held = self._args
        if held is None or len(args) != len(held):
            return False
        for a, b, kb in zip(args, held, self._arg_keys):
            if a is b:
                continue
            ta = type(a)
            if ta is not type(b):
                return False
            if ta is np.ndarray or isinstance(a, tuple):
                if _arg_key(a) != kb:
                    return False
            elif not (ta is float or ta is int or ta is bool):
                return False
        return True

    def __call__(self, *args):
        if self._same(args):
            return self._entry(*args)
        key = _key(args)
        if key == self._key:
            self._args = args
            return self._entry(*args)
        out = self.kernel(*args)
        sig = tuple(self.kernel.typeof_pyval(a) for a in args)
        cres = self.kernel.overloads.get(sig)
        if cres is not None:
            self._key = key
            self._entry = cres.entry_point
            self._held = tuple(a for a in args if isinstance(a, tuple))
            self._args = args
            self._arg_keys = key
        else:
            self._args = None
        return out
