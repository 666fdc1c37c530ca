"""Results files as JSON: channel selection and decimation, read straight from HDF5.

A channel is ``<group>/<object>/<variable>`` as in the file: ``lines/riser/tension``,
``lines/riser/position``, ``vessels/fpso/rotation``. Variables along time are
decimated with ``every`` (every n-th output time, the first one included); the others
(``arc_length``, ``sde_arc_length``) are returned whole.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

SKIP = ("time", "xyz")
GROUPS = ("lines", "vessels", "bodies")


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
    """``{name: dataset}`` of every channel in an open h5py file."""
    import h5py

    out = {}
    for group in GROUPS:
        g = f.get(group)
        if not isinstance(g, h5py.Group):
            continue
        for obj_name, obj in g.items():
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


def read_results(path: Path, channels: list[str] | None, every: int, max_values: int) -> dict[str, Any]:
    """``{"time": [...], "channels": {name: {"units", "long_name", "shape", "data"}}}``."""
    import h5py

    with h5py.File(path, "r") as f:
        index = channel_index(f)
        names = list(index) if not channels else list(dict.fromkeys(channels))
        unknown = [c for c in names if c not in index]
        if unknown:
            raise UnknownChannels(unknown, sorted(index))
        time_ds = None
        for name in names or list(index):
            group = index[name].parent
            if "time" in group:
                time_ds = group["time"]
                break
        if time_ds is None:
            for group in GROUPS:
                for obj in (f.get(group) or {}).values():
                    if "time" in obj:
                        time_ds = obj["time"]
                        break
                if time_ds is not None:
                    break
        nt = time_ds.shape[0] if time_ds is not None else 0
        kept = len(range(0, nt, every))
        total = kept
        selected = []
        for name in names:
            ds = index[name]
            dims = _dims(ds)
            decimate = bool(dims) and dims[0] == "time"
            shape = (len(range(0, ds.shape[0], every)),) + ds.shape[1:] if decimate else ds.shape
            total += int(np.prod(shape))
            selected.append((name, ds, decimate, shape, dims))
        if total > max_values:
            raise TooLarge(f"the answer would hold {total} values (this service sends at most {max_values}): "
                           f"select channels with ?channels=a,b or decimate with ?every=n "
                           f"(or download the netCDF file from results.nc)")
        out: dict[str, Any] = {"time": to_list(time_ds[::every]) if time_ds is not None else [],
                               "every": every, "channels": {}}
        for name, ds, decimate, shape, dims in selected:
            data = ds[::every] if decimate else ds[()]
            out["channels"][name] = {"units": _text(ds.attrs.get("units", "")),
                                     "long_name": _text(ds.attrs.get("long_name", "")),
                                     "dims": dims,
                                     "shape": list(shape), "data": to_list(data)}
        return out
