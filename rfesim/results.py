"""Results of a run: a plain object in the spirit of scipy's OdeResult, written to and
read from netCDF-4/HDF5 (one group per object, units and long names from one table)."""
from __future__ import annotations

import errno
import json
import os
import secrets
from dataclasses import dataclass, field

import numpy as np

# one table: every output variable's units and long name
CHANNELS: dict[str, tuple[str, str]] = {
    "time": ("s", "Simulated time"),
    "payout": ("m", "Length of line paid out by the tensioner or reel since the start (negative: reeled in)"),
    "grip_force": ("N", "Axial (reel: tangential) force with which the tensioner or reel holds the line back"),
    "position": ("m", "Position of the line points (end A, every SDE, end B) in the global frame"),
    "tension": ("N", "Effective tension (axial SDE force); a crane template's boom or legs below a table-driven "
                     "luffing cylinder's eye: the model's, whose luffing joint holds them by a moment at the hinge "
                     "(rfesim.crane_results.crane_summary gives the real frame's, the cylinders at their eye)"),
    "shear_force": ("N", "Shear force magnitude at the SDE; a crane template's boom or legs below a table-driven "
                         "luffing cylinder's eye: the model's, whose luffing joint holds them by a moment at the "
                         "hinge (rfesim.crane_results.crane_summary gives the real frame's, the cylinders at "
                         "their eye)"),
    "bend_moment": ("N*m", "Bending moment magnitude at the SDE; a crane template's boom or legs below a "
                           "table-driven luffing cylinder's eye: the model's, whose luffing joint holds them by a "
                           "moment at the hinge (rfesim.crane_results.crane_summary gives the real frame's, the "
                           "cylinders at their eye)"),
    "torque": ("N*m", "Torque (torsional moment) at the SDE"),
    "curvature": ("1/m", "Curvature at the SDE (bending rotation over the element length)"),
    "end_a_force": ("N", "Force of the line on its end-A attachment (global)"),
    "end_b_force": ("N", "Force of the line on its end-B attachment (global)"),
    "end_a_moment": ("N*m", "Moment of the line on its end-A attachment (global)"),
    "end_b_moment": ("N*m", "Moment of the line on its end-B attachment (global)"),
    "seabed_force": ("N", "Seabed normal force on each RFE"),
    "seabed_friction": ("N", "Seabed friction force on each RFE (global)"),
    "von_mises_stress": ("Pa", "Largest von Mises stress in the pipe wall (outer and inner fibre, where axial and "
                               "bending stress add and where they subtract): axial = true wall tension "
                               "T_eff + p_i A_i - p_e A_e over the steel area plus bending, Lame hoop and radial "
                               "stresses, the shear of eq. 8.97. Hydrostatic pressures only: external below the "
                               "still-water surface (no wave pressure), internal from contents at rest and open at "
                               "the line's highest point (0 for an empty pipe). Elasto-plastic pipe lines; NaN "
                               "otherwise"),
    "utilisation": ("1", "von_mises_stress over the yield stress (1 = first yield, with the hydrostatic pressure as "
                         "von_mises_stress; NaN: no yield stress)"),
    "residual_curvature": ("1/m", "Curvature the SDE would keep if unloaded to zero moment, from its plastic "
                                  "memory (reeling residual curvature; 0 for elastic lines)"),
    "touchdown_position": ("m", "Touchdown point: where seabed contact begins, seen from end B (NaN: no contact)"),
    "touchdown_arc_length": ("m", "Arc length from end A of the touchdown point (NaN: no contact)"),
    "end_a_direction": ("1", "Unit tangent of the line at end A (axis of the end RFE, global)"),
    "end_b_direction": ("1", "Unit tangent of the line at end B (axis of the end RFE, global)"),
    "arc_length": ("m", "Arc length from end A of the line points"),
    "drive_angle": ("deg", "Prescribed angle of each drive of the line's end-A join (its table, monotone cubic)"),
    "drive_torque": ("N*m", "Moment of the join on the line about each drive's current axis (global): the drive "
                            "torque"),
    "hinge_angle": ("deg", "Rotation of a hinged join (the line's end A) about its hinge axis from the start, "
                           "positive by the right-hand rule about the axis"),
    "reeving_slip": ("m", "Rope drawn over the sheave into the run toward a vessel lead since the start (the "
                          "run's growth; the hanging rope is that much shorter)"),
    "sde_arc_length": ("m", "Arc length from end A of the SDEs"),
    "vessel_position": ("m", "Position of the vessel origin (global)"),
    "vessel_rotation": ("deg", "Vessel roll, pitch, yaw of its motion (ZYX angles about its heading's axes: "
                               "R = R_heading Rz(yaw) Ry(pitch) Rx(roll); heading_deg is not included)"),
    "frequency": ("Hz", "Natural frequency about the static equilibrium (negative: an unstable mode, its growth "
                        "rate over 2 pi)"),
    "period": ("s", "Natural period 1 / frequency (inf: a zero mode; NaN: an unstable mode)"),
    "mode": ("1", "Mode number, from 1, by ascending frequency"),
    "mode_shape": ("1", "Displacement of the line points (end A, every SDE, end B) in the mode (global), scaled "
                        "so that the largest over all lines is 1"),
    "mode_coordinates": ("1", "The mode in the formulation's own coordinates (absolute lines: 6 per RFE, "
                              "translations and rotation increments; other formulations and chains: their joint "
                              "coordinates), flattened, scaled to a largest of 1"),
    "roller_reaction": ("N", "Normal contact force of the line on each roller"),
    "roller_force": ("N", "Force of the line on each roller, normal and friction (global)"),
    "roller_position": ("m", "Centre of each roller's contact line in the frame of the support's attachment"),
    "roller_axis": ("1", "Unit axis of each roller in the frame of the support's attachment"),
    "xyz": ("1", "Global axis (0: x, 1: y, 2: z)"),
    "body_position": ("m", "Centre of mass of the body (global)"),
    "body_velocity": ("m/s", "Velocity of the body's centre of mass (global)"),
    "body_acceleration": ("m/s^2", "Acceleration of the body's centre of mass (global)"),
    "body_rotation": ("deg", "Body roll, pitch, yaw (ZYX angles of the body axes, global)"),
    "body_angular_velocity": ("rad/s", "Angular velocity of the body (global)"),
    "connection_force": ("N", "Force of the line on the body at the attachment point (global)"),
    "connection_tension": ("N", "Magnitude of the line's force on the body (the rope tension at the body)"),
    "submerged_fraction": ("1", "Submerged fraction of the body's vertical extent"),
    "buoyancy": ("N", "Buoyancy force on the body (rho g V times the submerged fraction)"),
    "deck_force": ("N", "Normal force of the deck the body rests on (0: lifted off or no deck)"),
    "tugger_tension": ("N", "Tension of the tugger line (its pull on the body, along the line; negative: a "
                            "force element pushing)"),
    "tugger_length": ("m", "Length of the tugger line from its deck point to its body point"),
    "tugger_force": ("N", "Force of the tugger line on the body (global)"),
    "winch_payout": ("m", "Rope paid out by the winch since the start (negative: hauled in)"),
    "winch_speed": ("m/s", "Payout speed of the winch (negative: hauling in)"),
    "winch_tension": ("N", "Rope tension at the winch (axial force of the line's first SDE)"),
    "winch_suspended_length": ("m", "Unstretched length of the hanging rope (the line's length; a rope slipping "
                                    "over its sheave toward a vessel lead: less the slip handed over)"),
    "winch_rope_mass_suspended": ("kg", "Mass of the rope out of the winch"),
    "winch_rope_mass_drum": ("kg", "Mass of the rope left on the drum"),
    "winch_rope_mass_run": ("kg", "Mass of the rope's run from the sheave to a vessel lead (a deck winch's reeving; "
                                  "massless in the model, kept for the rope's mass balance; 0 without one)"),
    "winch_drum_radius": ("m", "Radius at which the rope leaves the drum (drum mode; grows with the rope on a "
                               "layered drum); NaN in the other modes"),
}

# chain joints (rfesim.formulations): units of the coordinates and rates by joint kind
JOINT_UNITS: dict[str, tuple[str, str]] = {"revolute": ("rad", "rad/s"), "spherical": ("rad", "rad/s"),
                                           "prismatic": ("m", "m/s"), "fixed": ("1", "1/s")}
JOINT_LONG_NAMES = {
    "coordinate": "Joint coordinate(s) of a chain joint: the rotation about its axis (revolute, rad), the slide "
                  "along it (prismatic, m) or its ZYX angles (spherical, rad)",
    "rate": "Rate(s) of the chain joint's coordinate(s) (rad/s or m/s, as the coordinates)",
}

WINCH_CHANNELS = ("payout", "speed", "tension", "suspended_length", "rope_mass_suspended", "rope_mass_drum",
                  "drum_radius", "rope_mass_run")
TUGGER_CHANNELS = ("tension", "length", "force")

BODY_CHANNELS = ("position", "velocity", "acceleration", "rotation", "angular_velocity", "connection_force",
                 "connection_tension", "submerged_fraction", "buoyancy", "deck_force")

LINE_CHANNELS = ("position", "tension", "shear_force", "bend_moment", "torque", "curvature", "end_a_force",
                 "end_b_force", "end_a_moment", "end_b_moment", "seabed_force", "end_a_direction",
                 "end_b_direction", "seabed_friction", "touchdown_position", "touchdown_arc_length",
                 "von_mises_stress", "utilisation", "residual_curvature")
# the channels along a line LineResults.range_graph takes: per point (a coordinate of the
# position), per SDE, per RFE (seabed_force)
RANGE_GRAPH_CHANNELS = ("position_x", "position_y", "position_z", "tension", "shear_force", "bend_moment",
                        "torque", "curvature", "seabed_force", "von_mises_stress", "utilisation",
                        "residual_curvature")
# channels of a line whose end A is a join with drives only (rfesim.model.joins)
DRIVE_CHANNELS = ("drive_angle", "drive_torque", "hinge_angle", "reeving_slip")


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
    residual_curvature: np.ndarray = None   # (nt, nsde) 1/m, zero-moment curvature from the plastic memory
    drive_angle: np.ndarray = None          # (nt, ndrive) deg, drives of a joined end A (rfesim.model.joins)
    drive_torque: np.ndarray = None         # (nt, ndrive) N*m, joint moment on the line about each drive axis
    drive_names: tuple = ()                 # names of those drives, in the scenario's order
    hinge_angle: np.ndarray = None          # (nt,) deg, a hinged end-A join's turn about its axis
    reeving_slip: np.ndarray = None         # (nt,) m, a rope's slip over its sheave toward a vessel lead

    @property
    def top_tension(self) -> np.ndarray:
        """Magnitude of the force at end B (N): the tension at the top of a riser."""
        return np.linalg.norm(self.end_b_force, axis=-1)

    @property
    def departure_angle(self) -> np.ndarray:
        """(nt,) deg: angle of the line at end B below the horizontal (90: vertical)."""
        d = np.asarray(self.end_b_direction)
        return np.degrees(np.arctan2(np.abs(d[:, 2]), np.hypot(d[:, 0], d[:, 1])))

    def bending_strain(self, outer_diameter: float) -> np.ndarray:
        """(nt, nsde) outer-fibre bending strain kappa D / 2 (-)."""
        return np.asarray(self.curvature) * 0.5 * outer_diameter

    def range_graph(self, channel: str, t_from: float | None = None, time: np.ndarray | None = None) -> dict:
        """Range graph of an SDE or RFE channel along the line: ``{"arc_length", "min", "max",
        "mean"}`` over time (from ``t_from`` on: give the run's ``time`` with it, a line's
        results have no time axis of their own; ``t_from`` alone is a ValueError).
        For a channel per point (``position``), give ``channel="position_z"`` etc.
        ValueError listing the channels it takes (:data:`RANGE_GRAPH_CHANNELS`) for another."""
        if t_from is not None and time is None:
            raise ValueError(f"range_graph: t_from = {t_from:g} s needs the run's time axis: "
                             f"line.range_graph(channel, t_from={t_from:g}, time=results.time)")
        if channel not in RANGE_GRAPH_CHANNELS:
            raise ValueError(f"range_graph: '{channel}' is not a channel along the line; it takes "
                             f"{', '.join(RANGE_GRAPH_CHANNELS)}")
        if channel.startswith("position_"):
            data = np.asarray(self.position)[..., "xyz".index(channel[-1])]
            s = np.asarray(self.arc_length)
        else:
            data = getattr(self, channel, None)
            data = None if data is None else np.asarray(data)
            nsde = len(self.sde_arc_length)
            if data is None or data.ndim != 2 or data.shape[1] not in (nsde, nsde + 1):
                raise ValueError(f"range_graph: line '{self.name}' has no channel {channel} in these results")
            if data.shape[1] == nsde:
                s = np.asarray(self.sde_arc_length)
            else:       # per RFE: the RFE centres, between the SDEs (and the ends)
                p = np.concatenate([[self.arc_length[0]], self.sde_arc_length, [self.arc_length[-1]]])
                s = 0.5 * (p[:-1] + p[1:])
        if t_from is not None and time is not None:
            data = data[np.asarray(time) >= t_from]
        if data.shape[0] == 0:
            raise ValueError("no results in the requested time window")
        return {"arc_length": s, "min": np.nanmin(data, axis=0), "max": np.nanmax(data, axis=0),
                "mean": np.nanmean(data, axis=0)}

    def sagbend_overbend(self, seabed_touchdown: bool = True) -> dict:
        """Largest bending moment and curvature in the sag bend (the concave-up part of the
        suspended line, above the touchdown point) and in the overbend (its concave-down
        part, further up), over the whole run. The suspended part runs from the touchdown
        point to the higher end of the line: end B for a riser or mooring line grounded at
        end A, end A for a pipe laid from a vessel (end B on the seabed), as
        ``rfesim.lay_results.lay_summary`` does.

        ``seabed_touchdown``: start the suspended part at the touchdown point
        (``touchdown_arc_length``) when the line touches the seabed; at the line's lowest
        point when it does not, or always when ``False`` (to ignore seabed contact)."""
        s = np.asarray(self.sde_arc_length)
        moment = np.asarray(self.bend_moment)
        curv = np.asarray(self.curvature)
        td = (np.asarray(self.touchdown_arc_length)
              if seabed_touchdown and self.touchdown_arc_length is not None else None)
        z = np.asarray(self.position)[..., 2]
        out = {"sagbend_moment": 0.0, "sagbend_curvature": 0.0, "overbend_moment": 0.0, "overbend_curvature": 0.0}
        pts = np.asarray(self.arc_length)
        for k in range(moment.shape[0]):
            # the sag bend is concave up, the overbend concave down: sign of z'' along the line
            zpp = np.gradient(np.gradient(z[k], pts), pts)
            zpp_sde = np.interp(s, pts, zpp)
            start = td[k] if (td is not None and np.isfinite(td[k])) else s[np.argmin(np.interp(s, pts, z[k]))]
            # towards the higher end (the solver's touchdown search runs from it too)
            suspended = (s <= start) if z[k][0] > z[k][-1] else (s >= start)
            sag = suspended & (zpp_sde > 0)
            over = suspended & (zpp_sde < 0)
            if sag.any():
                out["sagbend_moment"] = max(out["sagbend_moment"], float(moment[k][sag].max()))
                out["sagbend_curvature"] = max(out["sagbend_curvature"], float(curv[k][sag].max()))
            if over.any():
                out["overbend_moment"] = max(out["overbend_moment"], float(moment[k][over].max()))
                out["overbend_curvature"] = max(out["overbend_curvature"], float(curv[k][over].max()))
        return out

    def _truncate(self, nt: int) -> None:
        for name in LINE_CHANNELS + DRIVE_CHANNELS:
            if getattr(self, name) is not None:
                setattr(self, name, getattr(self, name)[:nt])


@dataclass
class TensionerResults:
    """Paid-out length and held force of one tensioner."""

    name: str
    line: str
    payout: np.ndarray                # (nt,) m, paid-out length (negative: reeled in)
    grip_force: np.ndarray            # (nt,) N, axial force the tensioner holds the line back with


@dataclass
class SupportResults:
    """Reactions of the rollers of one support (rollers or stinger)."""

    name: str
    line: str
    attach: str
    roller_position: np.ndarray       # (nroller, 3) m, attachment frame
    roller_axis: np.ndarray           # (nroller, 3) unit, attachment frame
    roller_reaction: np.ndarray       # (nt, nroller) N, normal force
    roller_force: np.ndarray          # (nt, nroller, 3) N, force of the line on the roller (global)

    @property
    def reaction(self) -> np.ndarray:
        """Normal force on each roller (nt, nroller), N."""
        return self.roller_reaction


@dataclass
class BodyResults:
    """Motion of a rigid body and the force of its line on it."""

    name: str
    line: str                          # the line it hangs on (at end B)
    position: np.ndarray               # (nt, 3) m, centre of mass
    velocity: np.ndarray               # (nt, 3) m/s
    acceleration: np.ndarray           # (nt, 3) m/s^2
    rotation: np.ndarray               # (nt, 3) deg: roll, pitch, yaw
    angular_velocity: np.ndarray       # (nt, 3) rad/s, global
    connection_force: np.ndarray       # (nt, 3) N, force of the line on the body (global)
    connection_tension: np.ndarray     # (nt,) N, its magnitude
    submerged_fraction: np.ndarray     # (nt,) -
    buoyancy: np.ndarray               # (nt,) N
    deck_force: np.ndarray | None = None  # (nt,) N, normal force of the deck (bodies.<b>.deck); None: files before it

    @property
    def tension(self) -> np.ndarray:
        """(nt,) N: the rope tension at the body (magnitude of the connection force)."""
        return self.connection_tension


@dataclass
class WinchResults:
    """Payout and rope tension of one winch."""

    name: str
    line: str                          # the rope line it pays out
    payout: np.ndarray                 # (nt,) m, paid out since the start (negative: hauled in)
    speed: np.ndarray                  # (nt,) m/s
    tension: np.ndarray                # (nt,) N, rope tension at the winch (first SDE of the line)
    suspended_length: np.ndarray       # (nt,) m, unstretched rope length out of the winch
    rope_mass_suspended: np.ndarray    # (nt,) kg
    rope_mass_drum: np.ndarray         # (nt,) kg
    drum_radius: np.ndarray            # (nt,) m, radius the rope leaves the drum at (drum mode; else NaN)
    rope_mass_run: np.ndarray = None   # (nt,) kg, the run from the sheave to a vessel lead (0 without one)


@dataclass
class TuggerResults:
    """Pull of one tugger line (rfesim.loads.tugger)."""

    name: str
    body: str                          # the body it pulls on ("" for a line point)
    vessel: str                        # the vessel its deck end is on
    tension: np.ndarray                # (nt,) N, negative: pushing (a "force" element, a cylinder)
    length: np.ndarray                 # (nt,) m, deck point to body point
    force: np.ndarray                  # (nt, 3) N, force of the line on the body (global)
    line: str = ""                     # the line it acts on at arc length ``at`` (instead of a body)
    at: float = float("nan")           # m from the line's end A


@dataclass
class JointResults:
    """Time history of a chain joint's coordinates and rates: rad and rad/s for a revolute
    joint (a spherical one: its three ZYX angles), m and m/s for a prismatic one; none for a
    fixed joint."""

    name: str                          # "<chain>.<joint>"
    coordinate: np.ndarray             # (nt, ncoord) rad or m
    rate: np.ndarray                   # (nt, ncoord) rad/s or m/s
    kind: str = ""                     # revolute | prismatic | spherical | fixed ("": not known)

    @property
    def velocity(self) -> np.ndarray:
        """(nt, ncoord): the rates of the coordinates (rad/s or m/s)."""
        return self.rate

    @property
    def units(self) -> str:
        """Units of ``coordinate``: rad or m (1 when the kind is not known)."""
        return JOINT_UNITS.get(self.kind, ("1", "1"))[0]


@dataclass
class VesselResults:
    name: str
    position: np.ndarray              # (nt, 3) m
    rotation: np.ndarray              # (nt, 3) deg: roll, pitch, yaw


@dataclass
class Results:
    """What a run produced. ``status`` 0: finished; 1: stopped by a SolverError (the
    arrays hold what was computed before); 2: interrupted by Ctrl-C or SIGTERM (the arrays
    hold what was computed before; rfesim.solvers.dynamics.INTERRUPTED); 3: cancelled
    through the progress callback, the HTTP service's cancel (the run raises
    ``CancelledError`` whose ``results`` hold what was recorded up to the last output step;
    rfesim.solvers.dynamics.CANCELLED)."""

    time: np.ndarray
    lines: dict[str, LineResults]
    vessels: dict[str, VesselResults] = field(default_factory=dict)
    bodies: dict = field(default_factory=dict)
    supports: dict[str, SupportResults] = field(default_factory=dict)
    tensioners: dict[str, TensionerResults] = field(default_factory=dict)
    reels: dict[str, TensionerResults] = field(default_factory=dict)   # payout and tangential grip force
    winches: dict = field(default_factory=dict)    # WinchResults by winch name
    tuggers: dict = field(default_factory=dict)    # TuggerResults by tugger name
    joints: dict = field(default_factory=dict)     # JointResults by "<chain>.<joint>" (chains only)
    status: int = 0
    message: str = ""
    counters: dict = field(default_factory=dict)
    scenario_json: str = ""
    version: str = ""
    kind: str = "dynamics"            # "statics" | "dynamics"
    modes: object = None              # ModalResults of analysis.modal (rfesim.solvers.modal), or None

    @property
    def success(self) -> bool:
        return self.status == 0

    def _named(self, group: str, what: str, name: str):
        """``self.<group>[name]``, or a KeyError that lists the names there are."""
        try:
            return getattr(self, group)[name]
        except KeyError:
            names = ", ".join(getattr(self, group)) or "none"
            raise KeyError(f"no {what} '{name}' in the results ({group}: {names})") from None

    def line(self, name: str) -> LineResults:
        return self._named("lines", "line", name)

    def body(self, name: str):
        return self._named("bodies", "body", name)

    def winch(self, name: str) -> WinchResults:
        return self._named("winches", "winch", name)

    def tugger(self, name: str) -> TuggerResults:
        return self._named("tuggers", "tugger", name)

    def support(self, name: str) -> SupportResults:
        return self._named("supports", "support", name)

    def vessel(self, name: str) -> VesselResults:
        return self._named("vessels", "vessel", name)

    def joint(self, name: str) -> JointResults:
        return self._named("joints", "joint", name)

    def __repr__(self) -> str:
        return (f"Results({self.kind}, {len(self.time)} times {self.time[0] if len(self.time) else 0:.4g}.."
                f"{self.time[-1] if len(self.time) else 0:.4g} s, lines={list(self.lines)}, status={self.status}, "
                f"message={self.message!r})")

    # ------------------------------------------------------------------ netCDF
    def to_netcdf(self, path: str | os.PathLike) -> None:
        """Write netCDF-4 (HDF5) atomically: a temporary file in the same folder, then rename.
        An OSError names ``path`` (its ``filename``) and the reason: the folder does not
        exist, is not writable, the path is a folder, ... (not the hidden temporary file)."""
        path = os.fspath(path)
        folder, base = os.path.split(os.path.abspath(path))
        shown = os.path.dirname(path) or "."         # the folder as the caller gave it
        if os.path.isdir(path):
            raise OSError(errno.EISDIR, "cannot write the results, the path is a folder", path)
        if not os.path.isdir(folder):
            raise OSError(errno.ENOENT, f"cannot write the results, the folder {shown!r} does not exist", path)
        # created like an ordinary file (mode 0o666 less the umask; mkstemp would give 0o600)
        while True:
            tmp = os.path.join(folder, f".{base}.{secrets.token_hex(6)}.tmp")
            try:
                os.close(os.open(tmp, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666))
                break
            except FileExistsError:
                continue
            except OSError as exc:      # a folder that is not writable, a full disk, ...
                raise OSError(exc.errno, f"cannot write the results in the folder {shown!r}: "
                                         f"{exc.strerror or exc}", path) from None
        try:
            _write_netcdf(self, tmp)
            os.replace(tmp, path)
        except BaseException as exc:
            if os.path.exists(tmp):
                os.unlink(tmp)
            if isinstance(exc, OSError) and tmp in (exc.filename, exc.filename2) and exc.errno is not None:
                # the hidden temporary file means nothing to the caller: name the path given
                raise OSError(exc.errno, f"cannot write the results: {exc.strerror or exc}", path) from None
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
            if lr.residual_curvature is not None:
                _var(g, "residual_curvature", ("time", "sde"), lr.residual_curvature)
            if lr.drive_angle is not None:
                g.dimensions["drive"] = len(lr.drive_names)
                g.attrs["drive_names"] = json.dumps(list(lr.drive_names))
                _var(g, "drive_angle", ("time", "drive"), lr.drive_angle)
                _var(g, "drive_torque", ("time", "drive"), lr.drive_torque)
            for ch in ("hinge_angle", "reeving_slip"):
                if getattr(lr, ch) is not None:
                    _var(g, ch, ("time",), getattr(lr, ch))
        for group, items in (("tensioners", res.tensioners), ("reels", res.reels)):
            if not items:
                continue
            tg = f.create_group(group)
            for name, tr in items.items():
                g = tg.create_group(name)
                g.attrs["line"] = tr.line
                g.dimensions = {"time": nt}
                _var(g, "time", ("time",), res.time)
                _var(g, "payout", ("time",), tr.payout)
                _var(g, "grip_force", ("time",), tr.grip_force)
        if res.supports:
            sg = f.create_group("supports")
            for name, sr in res.supports.items():
                g = sg.create_group(name)
                g.attrs["line"] = sr.line
                g.attrs["attach"] = sr.attach
                g.dimensions = {"time": nt, "roller": sr.roller_position.shape[0], "xyz": 3}
                _var(g, "time", ("time",), res.time)
                _var(g, "xyz", ("xyz",), [0, 1, 2], dtype=np.int32)
                _var(g, "roller_position", ("roller", "xyz"), sr.roller_position)
                _var(g, "roller_axis", ("roller", "xyz"), sr.roller_axis)
                _var(g, "roller_reaction", ("time", "roller"), sr.roller_reaction)
                _var(g, "roller_force", ("time", "roller", "xyz"), sr.roller_force)
        if res.bodies:
            bg = f.create_group("bodies")
            for name, br in res.bodies.items():
                g = bg.create_group(name)
                g.attrs["line"] = br.line
                g.dimensions = {"time": nt, "xyz": 3}
                _var(g, "time", ("time",), res.time)
                _var(g, "xyz", ("xyz",), [0, 1, 2], dtype=np.int32)
                for ch in BODY_CHANNELS:
                    data = getattr(br, ch)
                    if data is None:
                        continue
                    dims = ("time", "xyz") if np.ndim(data) == 2 else ("time",)
                    _var(g, ch, dims, data, ch if ch in ("connection_force", "connection_tension",
                                                         "submerged_fraction", "buoyancy", "deck_force")
                         else f"body_{ch}")
        if res.winches:
            wg = f.create_group("winches")
            for name, wr in res.winches.items():
                g = wg.create_group(name)
                g.attrs["line"] = wr.line
                g.dimensions = {"time": nt}
                _var(g, "time", ("time",), res.time)
                for ch in WINCH_CHANNELS:
                    _var(g, ch, ("time",), getattr(wr, ch), f"winch_{ch}")
        if res.tuggers:
            tg = f.create_group("tuggers")
            for name, tr in res.tuggers.items():
                g = tg.create_group(name)
                g.attrs["body"] = tr.body
                g.attrs["vessel"] = tr.vessel
                if tr.line:
                    g.attrs["line"] = tr.line
                    g.attrs["at"] = float(tr.at)
                g.dimensions = {"time": nt, "xyz": 3}
                _var(g, "time", ("time",), res.time)
                _var(g, "xyz", ("xyz",), [0, 1, 2], dtype=np.int32)
                _var(g, "tension", ("time",), tr.tension, "tugger_tension")
                _var(g, "length", ("time",), tr.length, "tugger_length")
                _var(g, "force", ("time", "xyz"), tr.force, "tugger_force")
        if res.joints:
            jg = f.create_group("joints")
            for name, jr in res.joints.items():
                g = jg.create_group(name)
                coord = np.asarray(jr.coordinate, dtype=float).reshape(nt, -1)
                rate = np.asarray(jr.rate, dtype=float).reshape(nt, -1)
                g.attrs["kind"] = jr.kind
                g.dimensions = {"time": nt, "coord": coord.shape[1]}
                _var(g, "time", ("time",), res.time)
                for ch, data, units in (("coordinate", coord, JOINT_UNITS.get(jr.kind, ("1", "1"))[0]),
                                        ("rate", rate, JOINT_UNITS.get(jr.kind, ("1", "1"))[1])):
                    v = g.create_variable(ch, ("time", "coord"), data=data)
                    v.attrs["units"] = units
                    v.attrs["long_name"] = JOINT_LONG_NAMES[ch]
        if res.modes is not None:
            _write_modes(f, res.modes)
        if res.vessels:
            vg = f.create_group("vessels")
            for name, vr in res.vessels.items():
                g = vg.create_group(name)
                g.dimensions = {"time": nt, "xyz": 3}
                _var(g, "time", ("time",), res.time)
                _var(g, "xyz", ("xyz",), [0, 1, 2], dtype=np.int32)
                _var(g, "position", ("time", "xyz"), vr.position, "vessel_position")
                _var(g, "rotation", ("time", "xyz"), vr.rotation, "vessel_rotation")


def _write_modes(f, md) -> None:
    """The group /modes of a ModalResults: frequency and period along ``mode``, the mode
    shapes in the formulation's coordinates (``coordinates``, flattened; attribute
    ``coordinate_shape`` their shape per mode), the line shapes in /modes/lines/<name>
    (``shape``: mode, point, xyz); attributes message, unstable, asymmetry, scale_hz."""
    freq = np.asarray(md.frequencies_hz, float)
    n = freq.size
    g = f.create_group("modes")
    shapes = np.asarray(md.shapes, float)
    g.dimensions = {"mode": n, "coordinate": int(np.prod(shapes.shape[1:])) if shapes.size else 0, "xyz": 3}
    g.attrs["message"] = md.message
    g.attrs["unstable"] = int(md.unstable)
    g.attrs["asymmetry"] = float(md.asymmetry)
    g.attrs["scale_hz"] = float(getattr(md, "scale_hz", 0.0))
    g.attrs["coordinate_shape"] = json.dumps([int(x) for x in shapes.shape[1:]])
    _var(g, "mode", ("mode",), np.arange(1, n + 1), dtype=np.int32)
    _var(g, "xyz", ("xyz",), [0, 1, 2], dtype=np.int32)
    _var(g, "frequency", ("mode",), freq)
    _var(g, "period", ("mode",), md.periods_s)
    _var(g, "coordinates", ("mode", "coordinate"), shapes.reshape(n, -1), "mode_coordinates")
    lg = g.create_group("lines")
    for name, ls in (md.line_shapes or {}).items():
        ls = np.asarray(ls, float)
        h = lg.create_group(name)
        h.dimensions = {"mode": n, "point": ls.shape[1], "xyz": 3}
        _var(h, "shape", ("mode", "point", "xyz"), ls, "mode_shape")


def _read_modes(g):
    """The ModalResults of a /modes group (``_write_modes``)."""
    from .solvers.modal import ModalResults

    def _s(x):
        return x.decode() if isinstance(x, bytes) else str(x)

    per_mode = tuple(json.loads(_s(g.attrs.get("coordinate_shape", "[]"))))
    freq = g["frequency"][()]
    coords = g["coordinates"][()] if "coordinates" in g else np.zeros((freq.size, 0))
    return ModalResults(frequencies_hz=freq, shapes=coords.reshape((freq.size,) + per_mode),
                        line_shapes={name: h["shape"][()] for name, h in g.get("lines", {}).items()},
                        asymmetry=float(_scalar(g.attrs.get("asymmetry", 0.0))), message=_s(g.attrs.get("message", "")),
                        unstable=int(_scalar(g.attrs.get("unstable", 0))),
                        scale_hz=float(_scalar(g.attrs.get("scale_hz", 0.0))))


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
                **{ch: g[ch][()] for ch in LINE_CHANNELS + DRIVE_CHANNELS if ch in g})
            if "drive_names" in g.attrs:
                lines[name].drive_names = tuple(json.loads(_s(g.attrs["drive_names"])))
        vessels = {}
        for name, g in f.get("vessels", {}).items():
            if not lines:
                time = g["time"][()]
            vessels[name] = VesselResults(name=name, position=g["position"][()], rotation=g["rotation"][()])
        bodies = {}
        for name, g in f.get("bodies", {}).items():
            if not lines:
                time = g["time"][()]
            bodies[name] = BodyResults(name=name, line=_s(g.attrs.get("line", "")),
                                       **{ch: g[ch][()] for ch in BODY_CHANNELS if ch in g})
        tensioners = {name: TensionerResults(name=name, line=_s(g.attrs.get("line", "")), payout=g["payout"][()],
                                             grip_force=g["grip_force"][()])
                      for name, g in f.get("tensioners", {}).items()}
        reels = {name: TensionerResults(name=name, line=_s(g.attrs.get("line", "")), payout=g["payout"][()],
                                        grip_force=g["grip_force"][()])
                 for name, g in f.get("reels", {}).items()}
        supports = {}
        for name, g in f.get("supports", {}).items():
            supports[name] = SupportResults(name=name, line=_s(g.attrs.get("line", "")),
                                            attach=_s(g.attrs.get("attach", "")),
                                            **{ch: g[ch][()] for ch in ("roller_position", "roller_axis",
                                                                         "roller_reaction", "roller_force")})
        winches = {name: WinchResults(name=name, line=_s(g.attrs.get("line", "")),
                                      **{ch: g[ch][()] if ch in g else np.full(g["payout"].shape, np.nan)
                                         for ch in WINCH_CHANNELS})      # files before drum_radius: NaN
                   for name, g in f.get("winches", {}).items()}
        tuggers = {name: TuggerResults(name=name, body=_s(g.attrs.get("body", "")), vessel=_s(g.attrs.get("vessel", "")),
                                       line=_s(g.attrs.get("line", "")), at=float(np.ravel(g.attrs.get("at", float("nan")))[0]),
                                       **{ch: g[ch][()] for ch in TUGGER_CHANNELS})
                   for name, g in f.get("tuggers", {}).items()}
        joints = {}
        for name, g in f.get("joints", {}).items():
            if not lines and not len(time):
                time = g["time"][()]
            joints[name] = JointResults(name=name, coordinate=g["coordinate"][()], rate=g["rate"][()],
                                        kind=_s(g.attrs.get("kind", "")))
        modes = _read_modes(f["modes"]) if "modes" in f else None
        return Results(time=time, lines=lines, vessels=vessels, supports=supports, bodies=bodies,
                       tensioners=tensioners, reels=reels, winches=winches, tuggers=tuggers, joints=joints,
                       modes=modes,
                       status=int(_scalar(attrs.get("status", 0))),
                       message=_s(attrs.get("message", "")), counters=json.loads(_s(attrs.get("counters", "{}"))),
                       scenario_json=_s(attrs.get("scenario", "")), version=_s(attrs.get("rfesim_version", "")),
                       kind=_s(attrs.get("kind", "dynamics")))
