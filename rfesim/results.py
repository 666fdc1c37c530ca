"""Results of a run: a plain object in the spirit of scipy's OdeResult, written to and
read from netCDF-4/HDF5 (one group per object, units and long names from one table)."""
from __future__ import annotations

import json
import os
import secrets
from dataclasses import dataclass, field

import numpy as np

# one table: every output variable's units and long name
CHANNELS: dict[str, tuple[str, str]] = {
    "time": ("s", "Simulated time"),
    "position": ("m", "Position of the line points (end A, every SDE, end B) in the global frame"),
    "tension": ("N", "Effective tension (axial SDE force)"),
    "shear_force": ("N", "Shear force magnitude at the SDE"),
    "bend_moment": ("N*m", "Bending moment magnitude at the SDE"),
    "torque": ("N*m", "Torque (torsional moment) at the SDE"),
    "curvature": ("1/m", "Curvature at the SDE (bending rotation over the element length)"),
    "end_a_force": ("N", "Force of the line on its end-A attachment (global)"),
    "end_b_force": ("N", "Force of the line on its end-B attachment (global)"),
    "end_a_moment": ("N*m", "Moment of the line on its end-A attachment (global)"),
    "end_b_moment": ("N*m", "Moment of the line on its end-B attachment (global)"),
    "seabed_force": ("N", "Seabed normal force on each RFE"),
    "seabed_friction": ("N", "Seabed friction force on each RFE (global)"),
    "von_mises_stress": ("Pa", "Equivalent (von Mises) stress at the outer fibre where axial and bending stress add "
                               "(eqs. 8.97-8.98; elasto-plastic pipe lines, NaN otherwise)"),
    "utilisation": ("1", "von_mises_stress over the yield stress (eq. 8.98; 1 = yielding; NaN: no yield stress)"),
    "touchdown_position": ("m", "Touchdown point: where seabed contact begins, seen from end B (NaN: no contact)"),
    "touchdown_arc_length": ("m", "Arc length from end A of the touchdown point (NaN: no contact)"),
    "end_a_direction": ("1", "Unit tangent of the line at end A (axis of the end RFE, global)"),
    "end_b_direction": ("1", "Unit tangent of the line at end B (axis of the end RFE, global)"),
    "arc_length": ("m", "Arc length from end A of the line points"),
    "sde_arc_length": ("m", "Arc length from end A of the SDEs"),
    "vessel_position": ("m", "Position of the vessel origin (global)"),
    "vessel_rotation": ("deg", "Vessel roll, pitch, yaw (ZYX angles)"),
    "frequency": ("Hz", "Natural frequency"),
    "xyz": ("1", "Global axis (0: x, 1: y, 2: z)"),
}

LINE_CHANNELS = ("position", "tension", "shear_force", "bend_moment", "torque", "curvature", "end_a_force",
                 "end_b_force", "end_a_moment", "end_b_moment", "seabed_force", "end_a_direction",
                 "end_b_direction", "seabed_friction", "touchdown_position", "touchdown_arc_length",
                 "von_mises_stress", "utilisation")


@dataclass
class LineResults:
    name: str
    arc_length: np.ndarray            # (npoints,) m
    sde_arc_length: np.ndarray        # (nsde,) m
    position: np.ndarray              # (nt, npoints, 3) m
    tension: np.ndarray               # (nt, nsde) N
    shear_force: np.ndarray           # (nt, nsde) N
    bend_moment: np.ndarray           # (nt, nsde) N*m
    torque: np.ndarray                # (nt, nsde) N*m
    curvature: np.ndarray             # (nt, nsde) 1/m
    end_a_force: np.ndarray           # (nt, 3) N
    end_b_force: np.ndarray           # (nt, 3) N
    end_a_moment: np.ndarray          # (nt, 3) N*m
    end_b_moment: np.ndarray          # (nt, 3) N*m
    seabed_force: np.ndarray          # (nt, nrfe) N
    end_a_direction: np.ndarray       # (nt, 3) unit tangent at end A
    end_b_direction: np.ndarray       # (nt, 3) unit tangent at end B
    seabed_friction: np.ndarray = None      # (nt, nrfe, 3) N
    touchdown_position: np.ndarray = None   # (nt, 3) m, NaN without contact
    touchdown_arc_length: np.ndarray = None  # (nt,) m, NaN without contact
    von_mises_stress: np.ndarray = None     # (nt, nsde) Pa, NaN for lines without a yield stress
    utilisation: np.ndarray = None          # (nt, nsde) -, NaN for lines without a yield stress

    @property
    def top_tension(self) -> np.ndarray:
        """Magnitude of the force at end B (N): the tension at the top of a riser."""
        return np.linalg.norm(self.end_b_force, axis=-1)

    def _truncate(self, nt: int) -> None:
        for name in LINE_CHANNELS:
            setattr(self, name, getattr(self, name)[:nt])


@dataclass
class VesselResults:
    name: str
    position: np.ndarray              # (nt, 3) m
    rotation: np.ndarray              # (nt, 3) deg: roll, pitch, yaw


@dataclass
class Results:
    """What a run produced. ``status`` 0: finished; 1: stopped by a SolverError (the
    arrays hold what was computed before); 2: cancelled."""

    time: np.ndarray
    lines: dict[str, LineResults]
    vessels: dict[str, VesselResults] = field(default_factory=dict)
    bodies: dict = field(default_factory=dict)
    status: int = 0
    message: str = ""
    counters: dict = field(default_factory=dict)
    scenario_json: str = ""
    version: str = ""
    kind: str = "dynamics"            # "statics" | "dynamics"

    @property
    def success(self) -> bool:
        return self.status == 0

    def line(self, name: str) -> LineResults:
        try:
            return self.lines[name]
        except KeyError:
            raise KeyError(f"no line '{name}' in the results (lines: {', '.join(self.lines)})") from None

    def body(self, name: str):
        try:
            return self.bodies[name]
        except KeyError:
            raise KeyError(f"no body '{name}' in the results (bodies: {', '.join(self.bodies) or 'none'})") from None

    def vessel(self, name: str) -> VesselResults:
        return self.vessels[name]

    def __repr__(self) -> str:
        return (f"Results({self.kind}, {len(self.time)} times {self.time[0] if len(self.time) else 0:.4g}.."
                f"{self.time[-1] if len(self.time) else 0:.4g} s, lines={list(self.lines)}, status={self.status}, "
                f"message={self.message!r})")

    # ------------------------------------------------------------------ netCDF
    def to_netcdf(self, path: str | os.PathLike) -> None:
        """Write netCDF-4 (HDF5) atomically: a temporary file in the same folder, then rename."""
        path = os.fspath(path)
        folder, base = os.path.split(os.path.abspath(path))
        # created like an ordinary file (mode 0o666 less the umask; mkstemp would give 0o600)
        while True:
            tmp = os.path.join(folder, f".{base}.{secrets.token_hex(6)}.tmp")
            try:
                os.close(os.open(tmp, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666))
                break
            except FileExistsError:
                continue
        try:
            _write_netcdf(self, tmp)
            os.replace(tmp, path)
        except BaseException:
            if os.path.exists(tmp):
                os.unlink(tmp)
            raise


def _var(group, name, dims, data, channel=None, dtype=float):
    units, long_name = CHANNELS[channel or name]
    v = group.create_variable(name, dims, data=np.asarray(data, dtype=dtype))
    v.attrs["units"] = units
    v.attrs["long_name"] = long_name
    return v


def _json_scalar(x):
    """numpy scalars and arrays in the counters -> plain JSON values."""
    if isinstance(x, (np.generic, np.ndarray)):
        return x.tolist()
    raise TypeError(f"{type(x).__name__} is not JSON serialisable")


def _scalar(x):
    """An attribute as a Python scalar (h5netcdf stores numbers as 1-element arrays)."""
    if isinstance(x, bytes):
        return x.decode()
    arr = np.asarray(x)
    return arr.reshape(-1)[0].item() if arr.size == 1 and arr.dtype.kind in "iufb" else x


def _write_netcdf(res: Results, path: str) -> None:
    import h5netcdf

    with h5netcdf.File(path, "w") as f:
        f.attrs["title"] = "rfesim results"
        f.attrs["rfesim_version"] = res.version
        f.attrs["scenario"] = res.scenario_json
        f.attrs["status"] = int(res.status)
        f.attrs["message"] = res.message
        f.attrs["kind"] = res.kind
        f.attrs["counters"] = json.dumps(res.counters, default=_json_scalar)
        nt = len(res.time)
        lines = f.create_group("lines")
        for name, lr in res.lines.items():
            g = lines.create_group(name)
            g.dimensions = {"time": nt, "point": lr.arc_length.shape[0], "sde": lr.sde_arc_length.shape[0],
                            "xyz": 3, "rfe": lr.seabed_force.shape[1]}
            _var(g, "time", ("time",), res.time)
            _var(g, "arc_length", ("point",), lr.arc_length)
            _var(g, "sde_arc_length", ("sde",), lr.sde_arc_length)
            _var(g, "xyz", ("xyz",), [0, 1, 2], dtype=np.int32)
            _var(g, "position", ("time", "point", "xyz"), lr.position)
            for ch in ("tension", "shear_force", "bend_moment", "torque", "curvature"):
                _var(g, ch, ("time", "sde"), getattr(lr, ch))
            for ch in ("end_a_force", "end_b_force", "end_a_moment", "end_b_moment", "end_a_direction",
                       "end_b_direction"):
                _var(g, ch, ("time", "xyz"), getattr(lr, ch))
            _var(g, "seabed_force", ("time", "rfe"), lr.seabed_force)
            _var(g, "seabed_friction", ("time", "rfe", "xyz"), lr.seabed_friction)
            _var(g, "touchdown_position", ("time", "xyz"), lr.touchdown_position)
            _var(g, "touchdown_arc_length", ("time",), lr.touchdown_arc_length)
            _var(g, "von_mises_stress", ("time", "sde"), lr.von_mises_stress)
            _var(g, "utilisation", ("time", "sde"), lr.utilisation)
        if res.vessels:
            vg = f.create_group("vessels")
            for name, vr in res.vessels.items():
                g = vg.create_group(name)
                g.dimensions = {"time": nt, "xyz": 3}
                _var(g, "time", ("time",), res.time)
                _var(g, "xyz", ("xyz",), [0, 1, 2], dtype=np.int32)
                _var(g, "position", ("time", "xyz"), vr.position, "vessel_position")
                _var(g, "rotation", ("time", "xyz"), vr.rotation, "vessel_rotation")


def open_results(path: str | os.PathLike) -> Results:
    """Read a results file written by ``Results.to_netcdf``."""
    import h5py

    with h5py.File(path, "r") as f:
        attrs = f.attrs

        def _s(x):
            return x.decode() if isinstance(x, bytes) else str(x)

        lines = {}
        time = np.zeros(0)
        for name, g in f.get("lines", {}).items():
            time = g["time"][()]
            lines[name] = LineResults(
                name=name, arc_length=g["arc_length"][()], sde_arc_length=g["sde_arc_length"][()],
                **{ch: g[ch][()] for ch in LINE_CHANNELS if ch in g})
        vessels = {}
        for name, g in f.get("vessels", {}).items():
            if not lines:
                time = g["time"][()]
            vessels[name] = VesselResults(name=name, position=g["position"][()], rotation=g["rotation"][()])
        return Results(time=time, lines=lines, vessels=vessels, status=int(_scalar(attrs.get("status", 0))),
                       message=_s(attrs.get("message", "")), counters=json.loads(_s(attrs.get("counters", "{}"))),
                       scenario_json=_s(attrs.get("scenario", "")), version=_s(attrs.get("rfesim_version", "")),
                       kind=_s(attrs.get("kind", "dynamics")))
