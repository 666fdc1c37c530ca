"""Lines sunk into the seabed: a result the contact model does not describe.

The seabed is a spring per unit length under the pipe's underside (rfesim.loads.seabed): it
holds a line at a penetration p = w / k under its own submerged weight w (a few mm to cm
for a pipe on a real seabed). A line that sinks deeper than its own diameter (at least
MIN_DEPTH) is in ground the model does not know: a seabed given far too soft, or elements
too long to follow it (a 290 m riser given one element is two rigid halves whose hinge
must go 60 m below the seabed to span its ends; the seabed then carries 5e7 N and the run
'finishes' with 7e7 N of compression). Each such line is named once, at its deepest point
over the results' times.
"""
from __future__ import annotations

import numpy as np

MIN_DEPTH = 0.1      # m: the penetration warned about, at least (thin lines, cables)


def _seabed_z(km, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Seabed height under (x, y) and the slope along the profile (rfesim.loads.seabed.
    seabed_height, vectorised): linear between the profile's points, continued with the end
    slopes."""
    s = x * km.bed_dir[0] + y * km.bed_dir[1]
    bs, bz = np.asarray(km.bed_s, float), np.asarray(km.bed_z, float)
    j = np.clip(np.searchsorted(bs, s, side="left") - 1, 0, bs.shape[0] - 2)
    g = (bz[j + 1] - bz[j]) / (bs[j + 1] - bs[j])
    return bz[j] + g * (s - bs[j]), g


def seabed_penetration_warnings(model, sc, results) -> list[str]:
    """One message per line whose underside goes deeper into the seabed than its diameter (at
    least MIN_DEPTH) at any output point and time of ``results``: the depth, where and when,
    the depth its submerged weight alone gives on the seabed's stiffness, and the fields."""
    from .scenario.pipelay import user_field
    found = _lines_on_seabed(model, sc)
    if found is None or not getattr(results, "lines", None):
        return []
    k, lines = found
    km = model.km
    out = []
    for li, a, w in lines:
        if li.name not in results.lines:
            continue
        pos = np.asarray(results.line(li.name).position, float)        # (nt, npoints, 3)
        if pos.size == 0 or not np.isfinite(pos).all():
            continue
        zb, slope = _seabed_z(km, pos[..., 0], pos[..., 1])
        depth = a - (pos[..., 2] - zb) / np.sqrt(1.0 + slope * slope)
        limit = max(2.0 * a, MIN_DEPTH)
        t, j = np.unravel_index(int(np.argmax(depth)), depth.shape)
        deepest = float(depth[t, j])
        if deepest <= limit:
            continue
        arc = float(np.asarray(results.line(li.name).arc_length)[j])
        elements = user_field(sc, f"lines.{li.name}.elements")
        if w / k > limit:
            why = (f"its submerged weight ({w / 1e3:.4g} kN/m) alone sinks it {w / k:.3g} m into the seabed's "
                   f"normal_stiffness ({k:.4g} N/m/m): the seabed is too soft for the line (give "
                   f"environment.seabed.normal_stiffness for the soil; soft clays give 1e4 to 1e6 N/m/m)")
        else:
            own = (f"its submerged weight ({w / 1e3:.4g} kN/m) alone sinks it only {w / k:.3g} m"
                   if w > 0.0 else "it floats")
            why = (f"on the seabed's normal_stiffness ({k:.4g} N/m/m) {own}, so the line is pushed in: by its "
                   f"ends, or because its elements ({li.elements} of {li.dx:.4g} m) are too long to follow the "
                   f"seabed ({elements})")
        out.append(f"line '{li.name}' sinks {deepest:.3g} m into the seabed (its underside, {arc:.4g} m from end A "
                   f"at t = {float(results.time[t]):.6g} s), deeper than its diameter ({2.0 * a:.3g} m; at least "
                   f"{MIN_DEPTH:g} m), where the seabed model, a spring under the pipe, does not describe it: {why}")
    return out


def soft_seabed_hint(model, sc) -> str | None:
    """A failed statics' hint (rfesim.api._statics_hint): the first line whose submerged weight
    w alone sinks it deeper than its diameter (at least MIN_DEPTH) into the seabed's normal
    stiffness k, and how many more; None if none does."""
    found = _lines_on_seabed(model, sc)
    if found is None:
        return None
    k, lines = found
    soft = [(li.name, w / k, 2.0 * a) for li, a, w in lines if w > 0.0 and w / k > max(2.0 * a, MIN_DEPTH)]
    if not soft:
        return None
    name, sink, diameter = soft[0]
    more = f" (and {len(soft) - 1} more)" if len(soft) > 1 else ""
    return (f"the seabed's normal_stiffness ({k:.4g} N/m/m) lets line '{name}'{more} sink {sink:.3g} m under its "
            f"own submerged weight, more than its diameter ({diameter:.3g} m): where it lies it has no equilibrium "
            f"the seabed model (a spring under the pipe) describes; give environment.seabed.normal_stiffness for "
            f"the soil (soft clays give 1e4 to 1e6 N/m/m; the default is 1e5)")


def _lines_on_seabed(model, sc):
    """(the seabed's normal stiffness k, [(LineInfo, contact radius a, submerged weight per
    length w)]) of the compiled ``model``'s lines, or None without a seabed."""
    seabed = sc.environment.seabed if sc is not None else None
    if seabed is None or model is None:
        return None
    water = sc.environment.water
    rho = float(water.density) if water is not None else 0.0
    g = float(sc.environment.gravity)
    return float(seabed.normal_stiffness), [
        (li, float(model.km.rfe_contact_radius[li.rfe_start]),
         (li.section.mass_per_length - rho * li.section.displaced_area) * g) for li in model.lines]


def below_bottom_warnings(sc, results) -> list[str]:
    """One message per line and body that goes below the sea floor, z = surface_level -
    depth, in a scene with water of a given depth and no seabed (nothing there stops it): how
    deep, where and when. The water's kinematics there are no water's (an Airy wave's cosh
    grows again below the bottom) and a real payload or line would rest on the floor. A line
    counts once its whole section (its axis plus its radius) is more than MIN_DEPTH below the
    floor, so an end anchored with its axis on the floor is not named; a body counts from its
    centre."""
    env = getattr(sc, "environment", None)
    water = getattr(env, "water", None) if env is not None else None
    if water is None or getattr(water, "depth", None) is None or getattr(env, "seabed", None) is not None:
        return []
    bottom = float(water.surface_level) - float(water.depth)
    time = np.asarray(getattr(results, "time", []), float)
    out = []
    for name in (getattr(results, "lines", None) or {}):
        pos = np.asarray(results.line(name).position, float)
        if pos.ndim != 3 or pos.size == 0 or not np.isfinite(pos).all():
            continue
        line = (sc.lines or {}).get(name)
        lt = (sc.line_types or {}).get(line.type) if line is not None else None
        radius = 0.5 * float(getattr(lt, "outer_diameter", None) or 0.0) if lt is not None else 0.0
        z = pos[..., 2]
        t, j = np.unravel_index(int(np.argmin(z)), z.shape)
        if z[t, j] < bottom - radius - MIN_DEPTH:       # (an end anchored on the floor is not below it)
            arc = np.asarray(results.line(name).arc_length, float)
            where = f" at arc length {float(arc[j]):.4g} m" if arc.size == z.shape[1] else ""
            when = f" at t = {float(time[t]):.6g} s" if time.size == z.shape[0] and time.size > 1 else ""
            out.append(_below(f"line '{name}'", bottom - float(z[t, j]) - radius, where + when, water.depth, bottom))
    for name in (getattr(results, "bodies", None) or {}):
        pos = np.asarray(results.bodies[name].position, float)
        if pos.ndim != 2 or pos.size == 0 or not np.isfinite(pos).all():
            continue
        t = int(np.argmin(pos[:, 2]))
        if pos[t, 2] < bottom - MIN_DEPTH:
            when = f" at t = {float(time[t]):.6g} s" if time.size == pos.shape[0] and time.size > 1 else ""
            out.append(_below(f"body '{name}'", bottom - float(pos[t, 2]), when, water.depth, bottom))
    return out


def _below(what: str, depth: float, where: str, water_depth: float, bottom: float) -> str:
    return (f"{what} goes {depth:.4g} m below the sea floor{where} (environment.water.depth {water_depth:.6g} m, "
            f"the floor at z = {bottom:.6g} m; the scene has no seabed, so nothing stops it there): below the "
            f"floor the waves' kinematics are no water's and a real line or payload would rest on it; give "
            f"environment.seabed for contact, the real water depth, or a shorter line or rope")
