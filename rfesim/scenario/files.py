"""Data files named in a scenario (a vessel motion CSV, an RAO table): relative paths
are taken from the folder of the scenario file (or a given folder)."""
from __future__ import annotations

import copy
import os
from pathlib import Path
from typing import Any

FILE_KEYS = ("file",)


def _relative_file_refs(data: Any, out: list, path: tuple = ()) -> None:
    if isinstance(data, dict):
        for key, value in data.items():
            if key in FILE_KEYS and isinstance(value, str) and value.strip() and not os.path.isabs(value) \
                    and not value.startswith("~"):
                out.append(path + (key,))
            else:
                _relative_file_refs(value, out, path + (key,))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            _relative_file_refs(value, out, path + (i,))


def resolve_data_files(data: Any, base_dir: str | os.PathLike) -> Any:
    """``data`` with every relative ``file`` value made absolute against ``base_dir`` (a
    copy when anything changes; the input is never modified)."""
    refs: list = []
    _relative_file_refs(data, refs)
    if not refs:
        return data
    out = copy.deepcopy(data)
    base = Path(base_dir).resolve()
    for ref in refs:
        cur = out
        for k in ref[:-1]:
            cur = cur[k]
        cur[ref[-1]] = str(base / cur[ref[-1]])
    return out
