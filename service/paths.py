"""File-system safety and the bundled example scenarios.

No scenario field may make the service read or write outside its data directory. The
scenario schema has file fields (``file`` of a ``csv`` or ``rao`` vessel motion) and may
get more (a spectrum table): :func:`check_scenario_paths` checks every string value of a
path-like key, which must name a file inside ``<data_dir>/files`` once resolved
(symbolic links followed), and must not be a URL. The one exception is a bundled example
submitted by name: the data files that example itself names (``scenarios/data/...``,
resolved against the bundled scenarios folder) are passed in ``allowed`` and accepted,
those exact files and nothing else.
"""
from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any, Collection

# keys that name files: "file", "path", "time_series_file", "rao_path", "filename", "directory", ...
PATH_KEY = re.compile(r"(^|_)(file|files|path|paths|filename|filenames|dir|directory|folder|url|uri)$", re.I)
URL = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*://")
SAFE_NAME = re.compile(r"^[A-Za-z0-9_-]{1,100}$")


class UnsafePath(ValueError):
    """A path that would leave the data directory."""


def files_dir(data_dir: Path) -> Path:
    """Where scenarios may reference input files (time series, tables)."""
    return Path(data_dir).resolve() / "files"


def resolve_data_path(value: str, data_dir: Path, allowed: Collection[Path] = ()) -> Path:
    """The absolute path of a scenario's file reference, or UnsafePath.

    Relative paths are taken from ``<data_dir>/files``; the result, with symbolic links
    resolved, must lie inside that folder or be one of the ``allowed`` files (resolved
    absolute paths: the data files of a bundled example).
    """
    if not isinstance(value, str) or not value.strip():
        raise UnsafePath("must be a non-empty file name")
    if "\x00" in value:
        raise UnsafePath("must not contain a NUL character")
    if URL.match(value):
        raise UnsafePath("must be a file in the service's data directory, not a URL")
    base = files_dir(data_dir)
    candidate = Path(value).expanduser() if value.startswith("~") else Path(value)
    if not candidate.is_absolute():
        candidate = base / candidate
    try:
        resolved = Path(os.path.realpath(candidate))
    except (OSError, ValueError) as exc:
        raise UnsafePath(f"is not a usable path ({exc})") from None
    if resolved in allowed:
        return resolved
    if resolved != base and base not in resolved.parents:
        raise UnsafePath(f"must name a file inside the service's data directory ({base}), "
                         f"not {value!r}")
    return resolved


def check_scenario_paths(data: Any, data_dir: Path, _prefix: str = "",
                         allowed: Collection[Path] = ()) -> list[tuple[str, str]]:
    """``(dotted.path, reason)`` for every path-like field of a raw scenario that points
    outside the data directory and is not one of the ``allowed`` files (an empty list
    when all are safe)."""
    errors: list[tuple[str, str]] = []
    if isinstance(data, dict):
        items = data.items()
    elif isinstance(data, list):
        items = ((str(i), v) for i, v in enumerate(data))
    else:
        return errors
    for key, value in items:
        path = f"{_prefix}.{key}" if _prefix else str(key)
        if isinstance(value, str) and PATH_KEY.search(str(key)):
            try:
                resolve_data_path(value, data_dir, allowed)
            except UnsafePath as exc:
                errors.append((path, str(exc)))
        elif isinstance(value, list) and PATH_KEY.search(str(key)):
            for i, item in enumerate(value):
                if isinstance(item, str):
                    try:
                        resolve_data_path(item, data_dir, allowed)
                    except UnsafePath as exc:
                        errors.append((f"{path}.{i}", str(exc)))
                else:
                    errors += check_scenario_paths(item, data_dir, f"{path}.{i}", allowed)
        else:
            errors += check_scenario_paths(value, data_dir, path, allowed)
    return errors


def find_scenarios_dir(configured: Path | None = None) -> Path | None:
    """The folder of the bundled example scenarios.

    In order: the configured folder (``RFESIM_SCENARIOS_DIR``); ``scenarios/`` next to the
    installed ``rfesim`` package (a source checkout or an editable install); ``scenarios/``
    in the current directory; ``<prefix>/share/rfesim/scenarios``.
    """
    import sys

    import rfesim

    candidates = []
    if configured is not None:
        candidates.append(Path(configured))
    package = Path(rfesim.__file__).resolve().parent
    candidates += [package.parent / "scenarios", package / "data" / "scenarios", Path.cwd() / "scenarios",
                   Path(sys.prefix) / "share" / "rfesim" / "scenarios"]
    for c in candidates:
        if c.is_dir() and any(c.glob("*.json")):
            return c.resolve()
    return None
