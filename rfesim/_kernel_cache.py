"""Drop numba's cached kernels when the kernels' sources changed (run at ``import rfesim``).

numba keeps a compiled kernel on disk and takes it again while the kernel's own file is
unchanged (its modification time and size); a kernel calls others from other files, and
their code is compiled into it, so after an edit of ``rfesim/loads/seabed.py`` the cached
``rfesim.model.assemble`` kernels still ran the old seabed law. That happens to a source
checkout after ``git pull`` (only the changed files get new times) and to anyone editing a
kernel: silently old physics. A ``pip install`` rewrites every file, so numba notices there.

So the sources that compiled kernels depend on (the modules that use numba and the rfesim
modules they import at their top level) are fingerprinted by content; when the fingerprint
differs from the one stored beside the cache, rfesim's cache files are deleted and numba
compiles afresh (minutes, once). Only rfesim's own cache files are touched: the
``__pycache__`` folders of the package, or, with ``NUMBA_CACHE_DIR``, the folders numba
names after the package's folders there. Anything unexpected (a read-only install, a numba
whose cache layout differs) leaves the cache as it is.
"""
from __future__ import annotations

import hashlib
import os
import re

PACKAGE = os.path.dirname(os.path.abspath(__file__))
STAMP = "rfesim-kernels.stamp"
_USES_NUMBA = re.compile(rb"^(from numba[ .]|import numba)", re.MULTILINE)
_IMPORT = re.compile(r"^from (\.+)([\w.]*) import ([^\n(]+|\([^)]*\))", re.MULTILINE)


def _sources() -> dict[str, bytes]:
    out = {}
    for folder, dirs, files in os.walk(PACKAGE):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__" and not d.startswith("."))
        for name in sorted(files):
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                with open(path, "rb") as f:
                    out[path] = f.read()
    return out


def _targets(path: str, text: str, sources: dict[str, bytes]) -> list[str]:
    """The rfesim files that ``path`` imports at its top level (relative imports)."""
    out = []
    for dots, module, names in _IMPORT.findall(text):
        base = os.path.dirname(path)
        for _ in range(len(dots) - 1):
            base = os.path.dirname(base)
        target = os.path.join(base, *module.split(".")) if module else base
        if target + ".py" in sources:
            out.append(target + ".py")
        elif os.path.join(target, "__init__.py") in sources:
            out.append(os.path.join(target, "__init__.py"))
            for name in re.findall(r"\w+", names):
                if os.path.join(target, name + ".py") in sources:
                    out.append(os.path.join(target, name + ".py"))
    return out


def kernel_sources(sources: dict[str, bytes] | None = None) -> list[str]:
    """The files compiled kernels depend on: modules using numba, and what they import."""
    sources = _sources() if sources is None else sources
    pending = [p for p, b in sources.items() if _USES_NUMBA.search(b) and p != os.path.abspath(__file__)]
    seen = set(pending)
    while pending:
        path = pending.pop()
        for target in _targets(path, sources[path].decode("utf-8", "replace"), sources):
            if target not in seen:
                seen.add(target)
                pending.append(target)
    return sorted(seen)


def fingerprint(sources: dict[str, bytes] | None = None) -> str:
    sources = _sources() if sources is None else sources
    h = hashlib.sha256()
    for path in kernel_sources(sources):
        h.update(os.path.relpath(path, PACKAGE).encode())
        h.update(b"\0")
        h.update(sources[path])
        h.update(b"\0")
    return h.hexdigest()


def cache_folders(cache_dir: str | None) -> list[str]:
    """Where numba keeps rfesim's kernels: each package folder's __pycache__, or under a
    NUMBA_CACHE_DIR the folder numba names after it (numba's own naming)."""
    folders = []
    for folder, dirs, _ in os.walk(PACKAGE):
        dirs[:] = [d for d in dirs if d != "__pycache__" and not d.startswith(".")]
        if cache_dir is None:
            folders.append(os.path.join(folder, "__pycache__"))
        else:
            from numba.core.caching import _CacheLocator
            folders.append(os.path.join(cache_dir, _CacheLocator.get_suitable_cache_subpath(
                os.path.join(folder, "__init__.py"))))
    return folders


def stamp_path(cache_dir: str | None = None) -> str:
    """The file holding the fingerprint of the sources the cache in ``cache_dir`` was compiled
    from (None: numba's default, next to the sources)."""
    if cache_dir is None:
        return os.path.join(PACKAGE, "__pycache__", STAMP)
    return os.path.join(cache_dir, f"rfesim-{hashlib.sha1(PACKAGE.encode()).hexdigest()[:16]}-kernels.stamp")


def mark_current(cache_dir: str | None = None) -> None:
    """Stamp ``cache_dir`` as compiled from the present sources: for a cache filled by copying
    another one (a test's, an image's), which the guard would otherwise take for one of unknown
    sources and drop."""
    _write_stamp(stamp_path(cache_dir), fingerprint())


def _write_stamp(stamp: str, fingerprint_now: str) -> None:
    os.makedirs(os.path.dirname(stamp), exist_ok=True)
    tmp = f"{stamp}.{os.getpid()}.tmp"
    with open(tmp, "w") as f:
        f.write(fingerprint_now + "\n")
    os.replace(tmp, stamp)


def guard(cache_dir: str | None = None) -> bool:
    """Delete rfesim's cached kernels if the kernel sources changed since they were
    compiled (or the cache has no stamp: sources unknown); True when it deleted some.
    ``cache_dir``: NUMBA_CACHE_DIR (None: numba's default, next to the sources)."""
    try:
        stamp = stamp_path(cache_dir)
        now = fingerprint()
        try:
            with open(stamp) as f:
                if f.read().strip() == now:
                    return False
        except OSError:
            pass
        removed = False
        for folder in cache_folders(cache_dir):
            try:
                names = os.listdir(folder)
            except OSError:
                continue
            for name in names:
                if name.endswith((".nbi", ".nbc")):
                    try:
                        os.unlink(os.path.join(folder, name))
                        removed = True
                    except OSError:
                        pass
        _write_stamp(stamp, now)
        return removed
    except Exception:       # never stop an import over the cache: numba then works as it always did
        return False
