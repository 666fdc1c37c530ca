"""Vessel motion from a CSV time series of the six displacements.

Format: comma-, semicolon- or whitespace-separated columns t [s], surge, sway, heave [m],
roll, pitch, yaw [deg] (the same as the ``table`` motion); blank lines and lines starting
with ``#`` are skipped; an optional first row of names (``t`` or ``time``, then the six
degrees of freedom in any order, units in brackets allowed: ``heave [m]``) says which
column is which. Times must increase. The result is the ordinary table motion
(:class:`rfesim.vessel.TableVessel`): cubic spline or linear, first/last row held.
"""
from __future__ import annotations

import re
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from .rao import read_input_file

COLUMNS = ("t", "surge", "sway", "heave", "roll", "pitch", "yaw")
UNITS = ("s", "m", "m", "m", "deg", "deg", "deg")


def _cells(line: str) -> list[str]:
    """The cells of a line: comma-, semicolon- or whitespace-separated; empty cells at the
    end of the line (a trailing separator, as spreadsheets write) are dropped."""
    if ";" in line:
        if "," in line:
            raise ValueError("semicolon-separated with commas in the numbers (a decimal comma, as a spreadsheet "
                             "in some locales writes): write the numbers with a decimal point")
        cells = [c.strip() for c in line.split(";")]
    elif "," in line:
        cells = [c.strip() for c in line.split(",")]
    else:
        return line.split()
    while cells and not cells[-1]:
        cells.pop()
    return cells


def _column_name(cell: str) -> str:
    name = re.sub(r"[\[(].*?[\])]", "", cell).strip().lower()
    return "t" if name == "time" else name


def read_motion_csv(path) -> np.ndarray:
    """(n, 7) array [t, surge, sway, heave, roll, pitch, yaw] (m, deg) from a CSV file;
    ValueError with the file name and line for anything wrong, values beyond the bounds an
    inline ``table`` motion has too (rfesim.scenario.schema.UNIT_BOUNDS: its units) included."""
    if not str(path).strip():
        raise ValueError("the file name is empty: give the path of the CSV file of the vessel motion")
    path = Path(path)
    text = read_input_file(path, "a CSV file", "utf-8-sig")
    order = list(range(7))
    rows: list[list[float]] = []
    linenos: list[int] = []
    header_seen = False
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        try:
            cells = _cells(line)
        except ValueError as exc:
            raise ValueError(f"{path}, line {lineno}: {exc}") from None
        try:
            values = [float(c) for c in cells]
        except ValueError:
            if rows or header_seen:
                bad = next(c for c in cells if not _is_number(c))
                raise ValueError(f"{path}, line {lineno}: {bad!r} is not a number") from None
            header_seen = True
            names = [_column_name(c) for c in cells]
            unknown = [c for c, n in zip(cells, names) if n not in COLUMNS]
            if unknown:
                raise ValueError(f"{path}, line {lineno}: unknown column {unknown[0]!r} (columns are "
                                 f"{', '.join(COLUMNS)})") from None
            missing = [n for n in COLUMNS if n not in names]
            if missing or len(names) != 7:
                what = f"missing {', '.join(missing)}" if missing else "a column is given twice"
                raise ValueError(f"{path}, line {lineno}: the header must name the 7 columns "
                                 f"{', '.join(COLUMNS)} ({what})") from None
            order = [names.index(n) for n in COLUMNS]
            continue
        if len(values) != 7:
            raise ValueError(f"{path}, line {lineno}: {len(values)} columns, expected 7 "
                             f"({', '.join(COLUMNS)})")
        if not all(np.isfinite(values)):
            raise ValueError(f"{path}, line {lineno}: values must be finite numbers")
        rows.append([values[k] for k in order])
        linenos.append(lineno)
        _check_bounds(path, lineno, rows[-1], rows[-2] if len(rows) > 1 else None)
    if len(rows) < 2:
        raise ValueError(f"{path}: needs at least 2 rows of data, got {len(rows)}")
    data = np.asarray(rows, dtype=float)
    steps = np.diff(data[:, 0])
    if np.any(steps <= 0.0):
        i = int(np.argmax(steps <= 0.0)) + 1
        raise ValueError(f"{path}, line {linenos[i]}: time {data[i, 0]} s in data row {i + 1} does not increase "
                         f"(previous {data[i - 1, 0]} s)")
    return data


def _check_bounds(path: Path, lineno: int, row: list[float], previous: list[float] | None) -> None:
    """The bounds of the inline table motion on a row of the file (ValueError naming the file,
    the line and the column): each value within the bound of its column's unit, and the time
    at least MIN_TIME after the row before."""
    from ..scenario.schema import MIN_TIME, MIN_TIME_LIMIT, UNIT_BOUNDS, upper_bound
    for name, unit, v in zip(COLUMNS, UNITS, row):
        limit, reason = UNIT_BOUNDS[unit]
        why = upper_bound(v, limit, unit, reason, signed=True)
        if why:
            raise ValueError(f"{path}, line {lineno}, column {name}: {why}")
    if previous is not None:
        dt = row[0] - previous[0]
        if 0.0 < dt < MIN_TIME * (1.0 - 1e-6):          # as the inline table (rfesim.scenario.schema._check_table)
            raise ValueError(f"{path}, line {lineno}, column t: {row[0]:.17g} s is {dt:.3g} s after the row "
                             f"before: rows closer than {MIN_TIME:g} s, {MIN_TIME_LIMIT}")


def _is_number(cell: str) -> bool:
    try:
        float(cell)
        return True
    except ValueError:
        return False


def csv_vessel(vessel):
    """The :class:`rfesim.vessel.TableVessel` of a vessel with a ``csv`` motion."""
    from ..vessel import TableVessel
    m = vessel.motion
    spec = SimpleNamespace(rows=m.rows(), interpolation=m.interpolation, ramp_duration=m.ramp_duration,
                           start_time=m.start_time)
    return TableVessel(vessel.position, vessel.heading_deg, spec)
