"""Compile rfesim's numba kernels in parallel processes into numba's on-disk cache.

A cold cache (a fresh install, a new NUMBA_CACHE_DIR, or kernel sources changed: see
``rfesim._kernel_cache``) costs minutes before a run's first step: numba compiles each kernel
when it is first called, one after the other, on one core. Most of that work can run side by
side. A kernel is compiled with the kernels it calls linked in, so a kernel can be compiled
as soon as its callees are in the cache, where another process loads them from.

``KERNELS`` (``rfesim/data/kernel_signatures.json``) lists the argument types of every
kernel a run of the shipped scenarios reaches (statics, dynamics with each integrator,
modes; ``python -m rfesim._precompile --record``; ``tests/test_precompile.py`` fails when
it is stale). ``precompile(processes)`` takes the recorded kernels not in the cache yet and
works on them in that many processes; each takes the next kernel whose callees are done
(claimed by an exclusive file create in a scratch folder), compiles it for its listed
signatures (numba writes the cache) and marks it done. Precompiles of one cache take turns
on a file lock. The callees of a
kernel are the rfesim kernels its code names (its globals, or attributes of a module it
names): an over-count only orders the work, an under-count only means a process compiles
a callee itself. A kernel whose signature cannot be rebuilt (another numba version) is
left to be compiled when first called, as without this module.
"""
from __future__ import annotations

import hashlib
import importlib
import json
import os
import subprocess
import sys
import tempfile
import time
import types
from typing import Callable

PACKAGE = os.path.dirname(os.path.abspath(__file__))
KERNELS = os.path.join(PACKAGE, "data", "kernel_signatures.json")
POLL = 0.02                      # s between looks at the other processes' progress


def cache_is_cold() -> bool:
    """True when the compiled kernels are not in numba's cache yet (the first run after an
    install, a new NUMBA_CACHE_DIR, kernel sources changed): a run would spend minutes
    compiling before its first step. Judged by the cache index of the time-step and statics
    kernels; False when numba's cache cannot be inspected."""
    try:
        from .solvers.jacobian import jacobian_analytic_at
        from .solvers.kernels import ga_advance

        paths = [d._cache._cache_file._index_path for d in (ga_advance, jacobian_analytic_at)]
    except Exception:  # pragma: no cover - a numba without this (private) layout
        return False
    return not all(os.path.exists(p) for p in paths)


def kernel_modules() -> list[str]:
    """The rfesim modules that define numba kernels."""
    out = []
    for folder, dirs, files in os.walk(PACKAGE):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__" and not d.startswith("."))
        for name in sorted(files):
            if not name.endswith(".py"):
                continue
            path = os.path.join(folder, name)
            with open(path, "rb") as f:
                text = f.read()
            if b"@njit" not in text:
                continue
            rel = os.path.relpath(path, os.path.dirname(PACKAGE))[:-3].replace(os.sep, ".")
            out.append(rel[:-len(".__init__")] if rel.endswith(".__init__") else rel)
    return out


def dispatchers() -> dict[str, object]:
    """'module:name' -> the numba dispatcher of every kernel rfesim defines."""
    from numba.core.registry import CPUDispatcher

    out = {}
    for modname in kernel_modules():
        mod = importlib.import_module(modname)
        for name, obj in vars(mod).items():
            if isinstance(obj, CPUDispatcher) and obj.py_func.__module__ == modname:
                out[f"{modname}:{name}"] = obj
    return out


def _names(code: types.CodeType) -> set[str]:
    out = set(code.co_names)
    for c in code.co_consts:
        if isinstance(c, types.CodeType):
            out |= _names(c)
    return out


def callees(disp, table: dict[str, object]) -> set[str]:
    """The keys (of ``table``) of the rfesim kernels ``disp``'s code names."""
    by_id = {id(d): k for k, d in table.items()}
    names = _names(disp.py_func.__code__)
    g = disp.py_func.__globals__
    out = set()
    for n in names:
        obj = g.get(n)
        if id(obj) in by_id:
            out.add(by_id[id(obj)])
        elif isinstance(obj, types.ModuleType):
            for m in names:
                sub = getattr(obj, m, None)
                if id(sub) in by_id:
                    out.add(by_id[id(sub)])
    return out


def cached_signatures(table: dict[str, object]) -> dict[str, list]:
    """key -> the argument types of each overload of the kernel in numba's on-disk cache
    (its index file: a kernel compiled as a callee of another is there too)."""
    out = {}
    for k, d in table.items():
        try:
            index = d._cache._cache_file._load_index()
        except Exception:   # no cache, or a numba with another layout
            continue
        sigs = []
        for key in index:
            if key[0] not in sigs:
                sigs.append(key[0])
        if sigs:
            out[k] = sigs
    return out


def encode(t, shared: dict | None = None) -> list:
    """A numba argument type as JSON: the kinds rfesim's kernels take (arrays, scalars,
    literals, tuples and named tuples of them); ValueError for another kind. A named tuple's
    members go once into ``shared`` (class -> members) and the type refers to them there."""
    from numba.core import types as nt

    if isinstance(t, nt.Array):
        return ["array", str(t.dtype), t.ndim, t.layout, not t.mutable]
    if isinstance(t, nt.BooleanLiteral):
        return ["bool-literal", bool(t.literal_value)]
    if isinstance(t, nt.IntegerLiteral):
        return ["int-literal", int(t.literal_value)]
    if isinstance(t, (nt.Boolean, nt.Integer, nt.Float)):
        return ["scalar", str(t)]
    if isinstance(t, nt.BaseNamedTuple):
        cls = t.instance_class
        name = f"{cls.__module__}:{cls.__qualname__}"
        members = [encode(x, shared) for x in t.types]
        if shared is None:
            return ["namedtuple", name, members]
        if shared.setdefault(name, members) == members:
            return ["namedtuple", name]
        return ["namedtuple", name, members]
    if isinstance(t, nt.BaseTuple):
        return ["tuple", [encode(x, shared) for x in t.types]]
    raise ValueError(f"a kernel argument of type {t} ({type(t).__name__}) has no JSON form here")


def decode(e: list, shared: dict | None = None):
    """The numba type ``encode`` gave ``e`` (``shared``: its named tuples' members)."""
    from numba.core import types as nt

    kind = e[0]
    if kind == "array":
        return nt.Array(getattr(nt, e[1]), e[2], e[3], readonly=e[4])
    if kind == "bool-literal":
        return nt.literal(bool(e[1]))
    if kind == "int-literal":
        return nt.literal(int(e[1]))
    if kind == "scalar":
        return getattr(nt, e[1])
    if kind == "namedtuple":
        module, qualname = e[1].split(":")
        cls = importlib.import_module(module)
        for part in qualname.split("."):
            cls = getattr(cls, part)
        members = [decode(x, shared) for x in (e[2] if len(e) > 2 else shared[e[1]])]
        if members and all(m == members[0] for m in members):
            return nt.NamedUniTuple(members[0], len(members), cls)
        return nt.NamedTuple(members, cls)
    if kind == "tuple":
        return nt.Tuple([decode(x, shared) for x in e[1]])
    raise ValueError(f"unknown kernel argument kind {kind!r}")


def record(path: str = KERNELS) -> dict[str, list]:
    """Write the signatures of every kernel in numba's on-disk cache now (JSON: the named
    tuples' members once, then one kernel a line)."""
    sigs = cached_signatures(dispatchers())
    shared: dict = {}
    lines = [json.dumps([k, [[encode(t, shared) for t in sig] for sig in v]], separators=(",", ":"))
             for k, v in sorted(sigs.items())]
    with open(path, "w") as f:
        f.write('{"namedtuples": ' + json.dumps(shared, separators=(",", ":")) + ',\n"kernels": [\n'
                + ",\n".join(lines) + "\n]}\n")
    return sigs


def recorded(path: str = KERNELS, table: dict[str, object] | None = None) -> dict[str, list]:
    """key -> signatures (tuples of numba types) of each recorded kernel that exists now and
    whose types this numba can rebuild (the others are left to be compiled when called)."""
    try:
        with open(path) as f:
            data = json.load(f)
        shared, kernels = data["namedtuples"], data["kernels"]
    except (OSError, ValueError, KeyError, TypeError):
        return {}
    table = dispatchers() if table is None else table
    out = {}
    for k, sigs in kernels:
        if k not in table:
            continue
        try:
            out[k] = [tuple(decode(t, shared) for t in sig) for sig in sigs]
        except Exception:   # a type this numba cannot rebuild, a class renamed
            continue
    return out


def order(sigs: dict[str, list], table: dict[str, object]) -> list[tuple[str, set[str]]]:
    """(key, keys it waits for) of each recorded kernel, callees first."""
    deps = {k: callees(table[k], table) & set(sigs) - {k} for k in sigs if k in table}
    out, seen = [], set()

    def visit(k, path=()):
        if k in seen or k in path:
            return
        for c in sorted(deps[k]):
            visit(c, path + (k,))
        seen.add(k)
        out.append((k, deps[k]))

    for k in sorted(deps):
        visit(k)
    # a call cycle (recursion through two kernels) would wait forever: drop the later edge
    done = set()
    for i, (k, d) in enumerate(out):
        out[i] = (k, d & done)
        done.add(k)
    return out


def _claim(folder: str, i: int) -> bool:
    """Take kernel i of the plan (an exclusive create of its claim file, holding this pid)."""
    try:
        fd = os.open(os.path.join(folder, f"{i}.claim"), os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        return False
    with os.fdopen(fd, "w") as f:
        f.write(str(os.getpid()))
    return True


def _settled(folder: str, i: int) -> bool:
    """Kernel i is compiled, or the process that took it has gone (whoever needs it then
    compiles it: numba compiles a missing callee with its caller)."""
    if os.path.exists(os.path.join(folder, f"{i}.done")):
        return True
    try:
        with open(os.path.join(folder, f"{i}.claim")) as f:
            pid = int(f.read() or 0)
    except (OSError, ValueError):
        return False                     # not taken yet, or its pid not written yet
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
        return False
    except ProcessLookupError:
        return True
    except OSError:                      # alive, another user's
        return False


def work(folder: str, only: set[str] | None = None,
         progress: Callable[[int, int], None] | None = None) -> int:
    """Compile kernels of the plan shared through ``folder`` until none is left to take;
    returns how many this process compiled. ``only``: those keys alone (and no waiting for
    others). ``progress(done, total)``: called after each kernel this process compiles and
    about once a second while it waits (``done`` counts every process's)."""
    table = dispatchers()
    sigs = recorded(table=table)
    if only is not None:
        sigs = {k: v for k, v in sigs.items() if k in only}
    plan = order(sigs, table)
    index = {k: i for i, (k, _) in enumerate(plan)}
    done: set[int] = set()
    mine = 0
    pending = list(range(len(plan)))
    said = 0.0

    def report() -> None:
        nonlocal said
        if progress is not None:
            said = time.monotonic()
            try:
                n = sum(1 for name in os.listdir(folder) if name.endswith(".done"))
            except OSError:
                return
            progress(min(n, len(plan)), len(plan))

    def settled(j: int) -> bool:        # remembered once true: the poll looks at each file once
        if j not in done and _settled(folder, j):
            done.add(j)
        return j in done

    while pending:
        ready = None
        for i in list(pending):
            k, deps = plan[i]
            if all(settled(index[d]) for d in deps):
                pending.remove(i)
                if _claim(folder, i):
                    ready = i
                    break
        if ready is None:
            if pending:
                time.sleep(POLL)
                if time.monotonic() - said > 1.0:
                    report()
            continue
        k, _ = plan[ready]
        for sig in sigs[k]:
            try:
                table[k].compile(sig)
            except Exception:      # left to be compiled when first called
                pass
        mine += 1
        done.add(ready)
        with open(os.path.join(folder, f"{ready}.done"), "w"):
            pass
        report()
    return mine


def processes_default() -> int:
    """Processes for a precompile: RFESIM_PRECOMPILE when set (0: none, kernels compile when
    first called), else the CPUs this process may use, at most 4."""
    env = os.environ.get("RFESIM_PRECOMPILE", "").strip()
    if env:
        try:
            return max(0, int(env))
        except ValueError:
            pass
    try:
        n = len(os.sched_getaffinity(0))
    except AttributeError:   # pragma: no cover - not Linux
        n = os.cpu_count() or 1
    return max(1, min(4, n))


def uncached(sigs: dict[str, list], table: dict[str, object]) -> set[str]:
    """The keys of ``sigs`` with a signature not in numba's on-disk cache yet."""
    have = cached_signatures({k: table[k] for k in sigs if k in table})
    return {k for k, v in sigs.items() if not set(v) <= set(have.get(k, ()))}


def _lock():
    """An exclusive lock for precompiling this package into this cache, held until the file
    returned is closed (or the process ends): two precompiles of one cache (the service's
    workers warming up side by side) then take turns, and the second finds the kernels
    cached. None where there is no such lock (not POSIX, a lock file not ours)."""
    try:
        import fcntl
    except ImportError:   # pragma: no cover - not POSIX
        return None
    key = hashlib.sha1(f"{PACKAGE}\0{os.environ.get('NUMBA_CACHE_DIR', '')}".encode()).hexdigest()[:16]
    try:
        f = open(os.path.join(tempfile.gettempdir(), f"rfesim-precompile-{key}.lock"), "a")
    except OSError:
        return None
    try:
        fcntl.flock(f, fcntl.LOCK_EX)
    except OSError:
        f.close()
        return None
    return f


def precompile(processes: int | None = None, only: set[str] | None = None,
               progress: Callable[[int, int], None] | None = None) -> int:
    """Compile the recorded kernels (``only``: those keys) that are not in numba's cache yet,
    in this process and ``processes - 1`` more (default ``processes_default()``); returns how
    many it compiled (0 when all are cached, no record is usable or processes is 0).
    ``progress(done, total)`` as for ``work``. Another precompile of the same cache running
    meanwhile is waited for first."""
    processes = processes_default() if processes is None else processes
    if processes <= 0:
        return 0
    table = dispatchers()
    sigs = recorded(table=table)
    if only is not None:
        sigs = {k: v for k, v in sigs.items() if k in only}
    if not sigs:
        return 0
    lock = _lock()
    try:
        wanted = uncached(sigs, table)
        if not wanted:
            return 0
        # run from the folder holding this rfesim, so that the processes compile the same
        # package into the same cache (numba names a cache folder after the source's path):
        # from a checkout with rfesim installed beside it, the checkout's copy would come first
        cmd = [sys.executable, "-c", "import sys; from rfesim._precompile import main; sys.exit(main(sys.argv[1:]))",
               "--package", PACKAGE, "--only", ",".join(sorted(wanted)), "--work"]
        with tempfile.TemporaryDirectory(prefix="rfesim-precompile-") as folder:
            env = dict(os.environ, PYTHONPATH=os.pathsep.join(
                [os.path.dirname(PACKAGE)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
            others = []
            for _ in range(min(processes, len(wanted)) - 1):
                try:
                    others.append(subprocess.Popen(cmd + [folder], env=env, stdin=subprocess.DEVNULL,
                                                   cwd=os.path.dirname(PACKAGE)))
                except OSError:        # no more processes: this one does the rest
                    break
            try:
                work(folder, wanted, progress)
            finally:
                for p in others:
                    p.wait()
            if progress is not None:     # the others' last kernels
                progress(min(len(wanted), sum(1 for name in os.listdir(folder) if name.endswith(".done"))), len(wanted))
        return len(wanted)
    finally:
        if lock is not None:
            lock.close()


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if "--package" in argv:
        i = argv.index("--package")
        if os.path.realpath(argv[i + 1]) != os.path.realpath(PACKAGE):
            print(f"rfesim._precompile: this process imported {PACKAGE}, not {argv[i + 1]}: it would fill "
                  "another cache; nothing done", file=sys.stderr)
            return 1
        argv = argv[:i] + argv[i + 2:]
    only = None
    if "--only" in argv:
        i = argv.index("--only")
        only = set(filter(None, argv[i + 1].split(",")))
        argv = argv[:i] + argv[i + 2:]
    if argv[:1] == ["--work"]:
        work(argv[1], only)
        return 0
    if argv[:1] == ["--record"]:
        # the workload in a process of its own on an empty cache: what it compiles is the record
        # (and not precompiled from the old record, which would carry its stale kernels over)
        with tempfile.TemporaryDirectory(prefix="rfesim-record-") as cache:
            env = dict(os.environ, NUMBA_CACHE_DIR=cache, RFESIM_PRECOMPILE="0")
            return subprocess.call([sys.executable, "-m", "rfesim._precompile", "--record-here"], env=env,
                                   cwd=os.path.dirname(PACKAGE))
    if argv[:1] == ["--record-here"]:
        from ._kernel_workload import run_all
        failed = run_all()
        print(f"{len(record())} kernels recorded in {KERNELS}")
        for f in failed:
            print(f"failed: {f}")
        return 1 if failed else 0
    def progress(done: int, total: int) -> None:
        print(f"{done}/{total}", file=sys.stderr, flush=True)

    show = "--progress" in argv
    argv = [a for a in argv if a != "--progress"]
    t0 = time.perf_counter()
    n = precompile(int(argv[0]) if argv else None, only, progress if show else None)
    print(f"{n} kernels compiled in {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
