"""Results files as JSON: channel selection and decimation, read straight from HDF5.

A channel is ``<group>/<object>/<variable>`` as in the file: ``lines/riser/tension``,
``lines/riser/position``, ``vessels/fpso/rotation``; a variable of a group itself is
``<group>/<variable>``: ``modes/frequency``, ``modes/period`` (the modal analysis of
``analysis.modal``). Variables along time are
decimated with ``every`` (every n-th output time, the first one included); the others
(``arc_length``, ``sde_arc_length``) are returned whole.

An answer is checked first (:func:`plan_results`: unknown channels, size) and then
streamed (:func:`stream_results`), a block of output times at a time: the web process
never builds the whole answer (a 14-million-value answer is about 270 MB of JSON text).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator

import numpy as np

SKIP = ("time", "xyz", "mode")
FIRST_GROUPS = ("lines", "vessels", "bodies")

# values json-encoded at a time when an answer is streamed (about 1 MB of text), so the web
# process never holds a whole answer (hundreds of MB) and its event loop gets the GIL between
# blocks (a /health probe waits at most one block, not the whole answer)
BLOCK_VALUES = 50_000


class UnknownChannels(ValueError):
    def __init__(self, unknown: list[str], available: list[str]):
        self.unknown = unknown
        self.available = available
        super().__init__(f"unknown channel{'s' if len(unknown) > 1 else ''} {', '.join(repr(u) for u in unknown)} "
                         f"(available: {', '.join(available)})")


class TooLarge(ValueError):
    pass


def _text(x) -> str:
    return x.decode() if isinstance(x, bytes) else str(x)


def _dims(ds) -> list[str | None]:
    """The dimension names of a netCDF variable (None where unknown)."""
    out = []
    for d in ds.dims:
        try:
            scales = [s.name.rsplit("/", 1)[-1] for s in d.values()]
        except (RuntimeError, KeyError, ValueError):
            scales = []
        out.append(scales[0] if scales else None)
    return out


def channel_index(f) -> dict[str, Any]:
    """``{name: dataset}`` of every channel in an open h5py file: every variable with units
    of every object of every top-level group the file has (lines, vessels, bodies,
    supports, winches, tuggers, tensioners, reels, and whatever a later rfesim adds)."""
    import h5py

    out = {}
    # lines, vessels and bodies first, as before the other groups were listed (h5py lists
    # groups by name), so that the answer without ?channels= keeps its order
    names = sorted(f, key=lambda g: FIRST_GROUPS.index(g) if g in FIRST_GROUPS else len(FIRST_GROUPS))
    for group in names:
        g = f[group]
        if not isinstance(g, h5py.Group):
            continue
        for obj_name, obj in g.items():
            if isinstance(obj, h5py.Dataset):
                # a variable of the group itself (/modes: frequency, period along the modes)
                if obj_name not in SKIP and "units" in obj.attrs:
                    out[f"{group}/{obj_name}"] = obj
                continue
            if not isinstance(obj, h5py.Group):
                continue
            for var, ds in obj.items():
                if isinstance(ds, h5py.Dataset) and var not in SKIP and "units" in ds.attrs:
                    out[f"{group}/{obj_name}/{var}"] = ds
    return out


def list_channels(path: Path) -> list[str]:
    import h5py

    with h5py.File(path, "r") as f:
        return sorted(channel_index(f))


def to_list(a: np.ndarray) -> list:
    """A JSON-ready nested list; NaN and infinities become null."""
    a = np.asarray(a)
    if a.dtype.kind == "f":
        bad = ~np.isfinite(a)
        if bad.any():
            o = a.astype(object)
            o[bad] = None
            return o.tolist()
    return a.tolist()


def _dumps(value: Any) -> str:
    return json.dumps(value, separators=(",", ":"), allow_nan=False)


@dataclass
class _Channel:
    name: str
    dataset: str              # its path in the file
    decimate: bool            # along time: every n-th row
    shape: tuple[int, ...]    # of the answer
    dims: list[str | None]
    units: str
    long_name: str


@dataclass
class Plan:
    """What one answer holds, checked (channels known, size within the limit) before the
    first byte is sent: once a streamed answer has started, its status cannot change."""
    path: Path
    every: int
    time: str | None          # "<group>/<object>/time" of the output times, None if the file has none
    nt: int                   # output times in the file
    channels: list[_Channel] = field(default_factory=list)


def plan_results(path: Path, channels: list[str] | None, every: int, max_values: int) -> Plan:
    """Check a request for the results of ``path``: :class:`UnknownChannels` or
    :class:`TooLarge` (over ``max_values`` values), else the :class:`Plan` to stream."""
    import h5py

    with h5py.File(path, "r") as f:
        index = channel_index(f)
        names = list(index) if not channels else list(dict.fromkeys(channels))
        unknown = [c for c in names if c not in index]
        if unknown:
            raise UnknownChannels(unknown, sorted(index))
        # the output times: those of the first selected channel's object, else any object's
        time_ds = None
        for ds in [index[n] for n in names] + list(index.values()):
            if "time" in ds.parent:
                time_ds = ds.parent["time"]
                break
        if time_ds is None:
            for g in f.values():
                for obj in (g.values() if isinstance(g, h5py.Group) else ()):
                    if isinstance(obj, h5py.Group) and "time" in obj:
                        time_ds = obj["time"]
                        break
                if time_ds is not None:
                    break
        nt = time_ds.shape[0] if time_ds is not None else 0
        plan = Plan(Path(path), every, time_ds.name if time_ds is not None else None, nt)
        total = len(range(0, nt, every))
        for name in names:
            ds = index[name]
            dims = _dims(ds)
            decimate = bool(dims) and dims[0] == "time"
            shape = (len(range(0, ds.shape[0], every)),) + ds.shape[1:] if decimate else ds.shape
            total += int(np.prod(shape))
            plan.channels.append(_Channel(name, ds.name, decimate, tuple(int(n) for n in shape), dims,
                                          _text(ds.attrs.get("units", "")), _text(ds.attrs.get("long_name", ""))))
        if total > max_values:
            raise TooLarge(f"the answer would hold {total} values (this service sends at most {max_values}): "
                           f"select channels with ?channels=a,b or decimate with ?every=n "
                           f"(or download the netCDF file from results.nc)")
        return plan


def _rows(ds, every: int, decimate: bool) -> Iterator[str]:
    """The JSON text of a dataset's data, in pieces: the rows along its first dimension
    a block at a time (every n-th row when decimated), as ``json.dumps`` of the whole
    nested list would write them."""
    if not decimate or ds.ndim == 0:
        yield _dumps(to_list(ds[()]))
        return
    n = len(range(0, ds.shape[0], every))
    per_row = max(1, int(np.prod(ds.shape[1:])))
    block = max(1, BLOCK_VALUES // per_row)
    yield "["
    for k0 in range(0, n, block):
        k1 = min(n, k0 + block)
        text = _dumps(to_list(ds[k0 * every:(k1 - 1) * every + 1:every]))
        yield ("," if k0 else "") + text[1:-1]          # the rows without the block's brackets
    yield "]"


def stream_results(plan: Plan, head: dict[str, Any]) -> Iterator[bytes]:
    """The answer as JSON text in pieces: ``head`` (id, status, message) first, then
    ``time``, ``every`` and ``channels`` as documented, byte for byte what ``json.dumps``
    (compact separators) of the whole answer would be."""
    import h5py

    def pieces() -> Iterator[str]:
        with h5py.File(plan.path, "r") as f:
            yield _dumps(head)[:-1] + ("," if head else "")     # the head's members, the object left open
            yield '"time":'
            if plan.time is not None:
                yield from _rows(f[plan.time], plan.every, True)
            else:
                yield "[]"
            yield f',"every":{_dumps(plan.every)},"channels":{{'
            for i, ch in enumerate(plan.channels):
                meta = _dumps({"units": ch.units, "long_name": ch.long_name, "dims": ch.dims,
                               "shape": list(ch.shape)})
                yield f'{"," if i else ""}{_dumps(ch.name)}:{meta[:-1]},"data":'
                yield from _rows(f[ch.dataset], plan.every, ch.decimate)
                yield "}"
            yield "}}"

    # join small pieces so that each chunk sent is a useful size
    buf: list[str] = []
    size = 0
    for piece in pieces():
        buf.append(piece)
        size += len(piece)
        if size >= 1 << 20:
            yield "".join(buf).encode()
            buf, size = [], 0
    if buf:
        yield "".join(buf).encode()


def read_results(path: Path, channels: list[str] | None, every: int, max_values: int) -> dict[str, Any]:
    """``{"time": [...], "every": n, "channels": {name: {"units", "long_name", "dims", "shape",
    "data"}}}`` as Python data (the service streams the same as text: :func:`stream_results`)."""
    plan = plan_results(path, channels, every, max_values)
    return json.loads(b"".join(stream_results(plan, {})))
