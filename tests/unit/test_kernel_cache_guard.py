"""rfesim._kernel_cache: numba keeps a cached kernel while its own file is unchanged, though
kernels from other files are compiled into it; after an edit of rfesim/loads/seabed.py the
cached assemble kernels ran the old seabed law (2026-11-28). The guard fingerprints the
kernels' sources and drops rfesim's cache files when they change."""
from __future__ import annotations

import os
import subprocess
import sys

from rfesim import _kernel_cache as kc


def _rel(paths):
    return {os.path.relpath(p, kc.PACKAGE).replace(os.sep, "/") for p in paths}


def test_the_fingerprint_covers_the_kernels_and_what_they_import_but_not_the_front_end():
    files = _rel(kc.kernel_sources())
    # kernels, and a kernel's callee in another file (the case that went stale)
    assert {"loads/seabed.py", "model/assemble.py", "solvers/kernels.py", "solvers/residual.py"} <= files
    # modules without numba that kernels import at their top level (constants, helpers)
    assert {"materials/section.py", "vessel.py"} <= files
    # the front end: editing it must not cost a recompile of every kernel
    assert not files & {"cli.py", "api.py", "scenario/schema.py", "sweep.py", "results.py", "_kernel_cache.py"}


def test_a_changed_kernel_source_changes_the_fingerprint():
    sources = kc._sources()
    base = kc.fingerprint(sources)
    seabed = os.path.join(kc.PACKAGE, "loads", "seabed.py")
    edited = dict(sources)
    edited[seabed] = sources[seabed] + b"\n# an edit\n"
    assert kc.fingerprint(edited) != base
    cli = os.path.join(kc.PACKAGE, "cli.py")
    edited = dict(sources)
    edited[cli] = sources[cli] + b"\n# an edit\n"
    assert kc.fingerprint(edited) == base


def _fake_caches(folders):
    made = []
    for folder in folders:
        os.makedirs(folder, exist_ok=True)
        for name in ("k.f-10.py311.nbi", "k.f-10.py311.1.nbc"):
            path = os.path.join(folder, name)
            with open(path, "wb") as f:
                f.write(b"x")
            made.append(path)
    return made


def test_the_guard_drops_rfesim_caches_once_per_change_and_nothing_else(tmp_path):
    cache = str(tmp_path)
    other = tmp_path / "otherproject_0123" / "mod.f-1.py311.nbi"      # another project's kernel
    other.parent.mkdir()
    other.write_bytes(b"x")
    made = _fake_caches(kc.cache_folders(cache))
    assert kc.guard(cache) is True                          # no stamp yet: caches of unknown sources
    assert not any(os.path.exists(p) for p in made)
    assert other.exists()
    made = _fake_caches(kc.cache_folders(cache))
    assert kc.guard(cache) is False                         # sources unchanged: kept
    assert all(os.path.exists(p) for p in made)
    stamp = [p for p in os.listdir(cache) if p.endswith("-kernels.stamp")]
    assert len(stamp) == 1
    (tmp_path / stamp[0]).write_text("an older fingerprint\n")   # as after `git pull` of a kernel
    assert kc.guard(cache) is True
    assert not any(os.path.exists(p) for p in made)
    assert other.exists()


def test_numba_puts_rfesim_kernels_where_the_guard_looks(tmp_path):
    """numba's layout under NUMBA_CACHE_DIR (a folder named after each source folder): a
    kernel compiled in a fresh process lands in one of the guard's cache folders."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    code = ("import numpy as np, rfesim.interp as i; i.bracket(np.array([0.0, 1.0, 2.0]), 0.5)")
    subprocess.run([sys.executable, "-c", code], env=env, check=True, timeout=300)
    folders = kc.cache_folders(str(tmp_path))
    found = [name for folder in folders if os.path.isdir(folder) for name in os.listdir(folder)
             if name.startswith("interp.bracket") and name.endswith(".nbi")]
    assert found


def test_a_copied_cache_marked_current_is_kept(tmp_path):
    """A cache filled by copying another (a test's, an image's) has no stamp: mark_current
    stamps it, and the guard then keeps it."""
    cache = str(tmp_path)
    made = _fake_caches(kc.cache_folders(cache))
    kc.mark_current(cache)
    assert kc.guard(cache) is False
    assert all(os.path.exists(p) for p in made)
