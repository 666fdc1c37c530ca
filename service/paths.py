"""File-system safety and the bundled example scenarios.

No scenario field may make the service read or write outside its data directory. The
scenario schema has file fields (``file`` of a ``csv`` or ``rao`` vessel motion) and may
get more (a spectrum table): :func:`check_scenario_paths` checks every string value of a
path-like key, which must name a file inside ``<data_dir>/files`` once resolved
(symbolic links followed), and must not be a URL. The one exception is a bundled example
submitted by name: the data files that example itself names (``scenarios/data/...``,
resolved against the bundled scenarios folder) are passed in ``allowed`` and accepted,
those exact files and nothing else.

A job runs on the data files as they were when it was submitted: :func:`snapshot_data_files`
copies each file a scenario names, at submit and before it is checked, to
``<data_dir>/inputs/<sha256 of its content>/<its name>`` (written once, never changed) and
the stored scenario names the copy. Those copies are readable by the path guard too, so a
job's stored scenario (``GET /jobs/{id}/scenario``) can be submitted again. A copy stays
while a job's stored scenario names it: :func:`input_copies_in` and :func:`copy_reference`
let the service remove the others (a purged job's, ``service.jobs.JobManager.purge``).
"""
from __future__ import annotations

import copy
import hashlib
import json
import os
import re
import secrets
from pathlib import Path
from typing import Any, Collection

# keys that name files: "file", "path", "time_series_file", "rao_path", "filename", "directory", ...
PATH_KEY = re.compile(r"(^|_)(file|files|path|paths|filename|filenames|dir|directory|folder|url|uri)$", re.I)
URL = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*://")
SAFE_NAME = re.compile(r"^[A-Za-z0-9_-]{1,100}$")
# a copy made at a submit: .../inputs/<sha256 of the content>/<file name>
INPUT_COPY = re.compile(r"[\\/]inputs[\\/]([0-9a-f]{64})[\\/]([^\\/]+)$")


class UnsafePath(ValueError):
    """A path that would leave the data directory."""


def files_dir(data_dir: Path) -> Path:
    """Where scenarios may reference input files (time series, tables)."""
    return Path(data_dir).resolve() / "files"


def inputs_dir(data_dir: Path) -> Path:
    """Where the service keeps the copies of the data files jobs were submitted with."""
    return Path(data_dir).resolve() / "inputs"


def resolve_data_path(value: str, data_dir: Path, allowed: Collection[Path] = ()) -> Path:
    """The absolute path of a scenario's file reference, or UnsafePath.

    Relative paths are taken from ``<data_dir>/files``; the result, with symbolic links
    resolved, must lie inside that folder or be one of the ``allowed`` files (resolved
    absolute paths: the data files of a bundled example), or be a copy made at a submit
    (``<data_dir>/inputs``, :func:`snapshot_data_files`).
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
    if resolved in allowed or inputs_dir(data_dir) in resolved.parents:
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


def snapshot_data_files(data: Any, data_dir: Path, copies: dict[str, str] | None = None) -> Any:
    """``data`` (a raw scenario whose ``file`` values are absolute: checked by
    :func:`check_scenario_paths`, made absolute by ``resolve_data_files``) with every ``file``
    value replaced by a copy of that file as it is now (a copy of ``data`` when anything
    changes; the input is never modified).

    A queued job read its RAO table or motion CSV only when a worker ran it: a file replaced
    meanwhile changed the job's results (172.6 kN instead of 118.0 kN of top tension for the
    same submitted body), and the submit's checks had been made on the old file. The copy is
    ``<data_dir>/inputs/<sha256 of the content>/<file name>``: the file is read once, its
    bytes hashed and written (a temporary file then a rename, so a copy is complete or
    absent), and an identical content is kept once, however many jobs or load cases name it.
    The submit checks the scenario with the copies, so what is checked is what runs.
    ``copies`` (file value -> copy) makes the load cases of one sweep read each file once.
    A file that cannot be read is left as it is: loading the scenario names the field and
    the reason."""
    from rfesim.scenario.files import FILE_KEYS

    copies = {} if copies is None else copies
    refs: list[tuple] = []
    _file_refs(data, FILE_KEYS, refs)
    if not refs:
        return data
    out = copy.deepcopy(data)
    for ref in refs:
        cur = out
        for k in ref[:-1]:
            cur = cur[k]
        value = cur[ref[-1]]
        if value not in copies:
            copies[value] = _copy_of(value, data_dir)
        cur[ref[-1]] = copies[value]
    return out


def _file_refs(data: Any, keys, out: list, path: tuple = ()) -> None:
    if isinstance(data, dict):
        for key, value in data.items():
            if key in keys and isinstance(value, str) and os.path.isabs(value):
                out.append(path + (key,))
            else:
                _file_refs(value, keys, out, path + (key,))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            _file_refs(value, keys, out, path + (i,))


def _copy_of(value: str, data_dir: Path) -> str:
    """The path of the copy of the file ``value`` (absolute) in ``<data_dir>/inputs``, or
    ``value`` itself when it cannot be read."""
    try:
        with open(value, "rb") as f:
            content = f.read()
    except (OSError, ValueError):
        return value
    name = os.path.basename(value) or "data"
    folder = inputs_dir(data_dir) / hashlib.sha256(content).hexdigest()
    target = folder / name
    if target.is_file():
        return str(target)
    folder.mkdir(parents=True, exist_ok=True)
    tmp = folder / f".{name}.{secrets.token_hex(6)}.tmp"
    try:
        tmp.write_bytes(content)
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return str(target)


def input_copies_in(data: Any, data_dir: Path) -> set[Path]:
    """The copies in ``<data_dir>/inputs`` that a stored scenario names: every string value
    ending ``inputs/<sha256>/<name>``, as the file of that name in this data directory's
    ``inputs`` folder (also when the data directory was moved since the submit)."""
    out: set[Path] = set()
    stack = [data]
    while stack:
        item = stack.pop()
        if isinstance(item, dict):
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)
        elif isinstance(item, str):
            m = INPUT_COPY.search(item)
            if m and m.group(2) not in (".", ".."):
                out.add(inputs_dir(data_dir) / m.group(1) / m.group(2))
    return out


def copy_reference(copy_path: Path) -> str:
    """What a stored scenario (compact JSON, ``json.dumps``) that names the copy
    ``copy_path`` contains, whatever the data directory's path: ``<sha256>/<name>"``
    spelled as in JSON text, with the string's closing quote (so ``m.csv`` is not found in
    ``m.csv2``)."""
    copy_path = Path(copy_path)
    return json.dumps(os.path.join(copy_path.parent.name, copy_path.name))[1:]


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
