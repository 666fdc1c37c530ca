"""rfesim.precompile: the record of kernel signatures (rfesim/data/kernel_signatures.json), its
plan (callees first) and the parallel compile into an empty numba cache."""
import inspect
import json
import os
import subprocess
import sys

import pytest
from numba.core import types as nt

from rfesim import _precompile as P

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture(scope="module")
def table():
    return P.dispatchers()


def test_record_names_live_kernels_with_their_arity_and_round_trips(table):
    with open(P.KERNELS) as f:
        data = json.load(f)
    keys = [k for k, _ in data["kernels"]]
    assert len(keys) == len(set(keys)) > 100
    missing = [k for k in keys if k not in table]
    assert not missing, f"recorded kernels that no longer exist (python -m rfesim._precompile --record): {missing}"
    sigs = P.recorded(table=table)
    assert sorted(sigs) == sorted(keys)               # every type rebuilt by this numba
    shared = data["namedtuples"]
    for k, raw in data["kernels"]:
        arity = len(inspect.signature(table[k].py_func).parameters)
        for sig, enc in zip(sigs[k], raw):
            assert len(sig) == arity, k
            assert [P.encode(t) for t in sig] == [_full(e, shared) for e in enc]      # encode(decode(e)) == e
    # the kernels every run goes through are there
    for k in ("rfesim.solvers.recording:ga_run", "rfesim.solvers.residual:residual_general",
              "rfesim.solvers.jacobian:jacobian_analytic_at", "rfesim.solvers.kernels:ga_advance"):
        assert k in sigs


def _full(e, shared):
    """``e`` with each named tuple's members written out (as ``encode`` without ``shared``)."""
    if e[0] == "namedtuple":
        return ["namedtuple", e[1], [_full(x, shared) for x in (e[2] if len(e) > 2 else shared[e[1]])]]
    if e[0] == "tuple":
        return ["tuple", [_full(x, shared) for x in e[1]]]
    return e


def test_encode_decode_identity_and_refusal():
    from rfesim.sea.kernel import SeaSpec  # a named tuple the kernels take

    for t in (nt.Array(nt.float64, 2, "C"), nt.Array(nt.int64, 1, "C", readonly=True), nt.boolean, nt.float64,
              nt.int64, nt.literal(True), nt.literal(3), nt.Tuple([nt.float64, nt.int64]),
              nt.UniTuple(nt.float64, 3)):
        assert P.decode(P.encode(t)) == t
    members = [nt.boolean] + [nt.Array(nt.float64, 1, "C")] * (len(SeaSpec._fields) - 1)
    sea = nt.NamedTuple(members, SeaSpec)
    shared = {}
    e = P.encode(sea, shared)
    assert e == ["namedtuple", "rfesim.sea.kernel:SeaSpec"] and len(shared["rfesim.sea.kernel:SeaSpec"]) == len(members)
    assert P.decode(e, shared) == sea == P.decode(P.encode(sea))
    other = nt.NamedTuple([nt.int64] + members[1:], SeaSpec)          # members unlike the shared ones
    assert P.decode(P.encode(other, shared), shared) == other
    with pytest.raises(ValueError, match="unicode_type"):
        P.encode(nt.unicode_type)


def test_plan_compiles_callees_first(table):
    sigs = P.recorded(table=table)
    plan = P.order(sigs, table)
    where = {k: i for i, (k, _) in enumerate(plan)}
    assert sorted(where) == sorted(sigs)
    for i, (k, deps) in enumerate(plan):
        assert all(where[d] < i for d in deps), k
    # the time step calls the residual and the Jacobian, which call the model's evaluation
    assert where["rfesim.solvers.residual:residual_general"] < where["rfesim.solvers.kernels:ga_advance"]
    assert "rfesim.solvers.kernels:ga_advance" in P.callees(table["rfesim.solvers.recording:ga_run"], table)


def test_settled_claims(tmp_path):
    assert not P._settled(str(tmp_path), 0)                      # nobody took it
    assert P._claim(str(tmp_path), 0) and not P._claim(str(tmp_path), 0)
    assert not P._settled(str(tmp_path), 0)                      # taken by this (live) process
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    (tmp_path / "1.claim").write_text(dead.stdout.strip())
    assert P._settled(str(tmp_path), 1)                          # its process has gone
    (tmp_path / "0.done").write_text("")
    assert P._settled(str(tmp_path), 0)


def test_precompile_off(monkeypatch):
    monkeypatch.setenv("RFESIM_PRECOMPILE", "0")
    assert P.processes_default() == 0
    assert P.precompile() == 0
    monkeypatch.setenv("RFESIM_PRECOMPILE", "3")
    assert P.processes_default() == 3


# a callee and two of its callers: small kernels, so the compile takes seconds
SMALL = ("rfesim.loads.tensioner:payout_speed", "rfesim.loads.tensioner:payout_newton",
         "rfesim.loads.tensioner:solve_driven_payout")


def test_two_processes_fill_an_empty_cache(tmp_path, table):
    deps = P.callees(table[SMALL[1]], table)
    assert SMALL[0] in deps
    # run from a folder holding another package named rfesim (a checkout beside an installed
    # copy): the second process must still import this one, and fill the same cache
    decoy = tmp_path / "rfesim"
    decoy.mkdir()
    (decoy / "__init__.py").write_text(f"open({str(tmp_path / 'decoy-imported')!r}, 'w').close()\n")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    env.pop("PYTHONPATH", None)
    code = (f"import sys; sys.path.insert(0, {ROOT!r}); from rfesim._precompile import main; "
            f"sys.exit(main(['2', '--only', {','.join(SMALL)!r}, '--progress']))")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600,
                         cwd=str(tmp_path))
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("3 kernels compiled"), run.stdout
    assert not (tmp_path / "decoy-imported").exists()
    counts = [tuple(map(int, ln.split("/"))) for ln in run.stderr.split() if "/" in ln]
    assert counts[-1] == (3, 3) and all(t == 3 for _, t in counts), run.stderr     # progress: done of the plan
    assert [d for d, _ in counts] == sorted(d for d, _ in counts)
    # a new process finds every recorded signature of the three in that cache
    check = subprocess.run([sys.executable, "-c", (
        "from rfesim import _precompile as P; t = P.dispatchers(); r = P.recorded(table=t); "
        f"keys = {list(SMALL)!r}; c = P.cached_signatures({{k: t[k] for k in keys}}); "
        "print(all(set(r[k]) <= set(c.get(k, [])) for k in keys), sorted(c))")],
        capture_output=True, text=True, env=dict(env, PYTHONPATH=ROOT), timeout=300, cwd=ROOT)
    assert check.stdout.startswith("True"), (check.stdout, check.stderr)


def test_a_process_of_another_package_does_nothing(tmp_path, capsys):
    assert P.main(["--package", str(tmp_path), "--work", str(tmp_path)]) == 1
    assert "it would fill another cache; nothing done" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())                      # no claim taken


def test_record_has_what_a_run_calls():
    # the kernels a run calls from Python, with the argument types it passes, are in the record
    # (a kernel given another argument makes the record stale: python -m rfesim._precompile --record)
    code = (
        "import rfesim; from rfesim import _precompile as P; from rfesim._kernel_workload import runs\n"
        "for label, fn in runs():\n"
        "    if label.startswith(('simulate catenary', 'modes catenary', 'results')): fn()\n"
        "t = P.dispatchers(); r = P.recorded(table=t)\n"
        "print(sorted({k for k, d in t.items() for s in d.signatures if tuple(s) not in r.get(k, [])}))\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=900, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip().splitlines()[-1] == "[]", "kernels called with types the record lacks: " + run.stdout[-3000:]


def test_a_cached_kernel_is_not_compiled_again():
    # this session's cache holds the three: nothing to do, nothing reported
    seen = []
    assert P.uncached({k: P.recorded()[k] for k in SMALL}, P.dispatchers()) == set()
    assert P.precompile(2, only=set(SMALL), progress=lambda done, total: seen.append((done, total))) == 0
    assert seen == []


def test_two_precompiles_of_one_cache_take_turns(tmp_path):
    # the second waits for the first's lock and then finds the kernels cached
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=ROOT)
    cmd = [sys.executable, "-m", "rfesim._precompile", "1", "--only", ",".join(SMALL)]
    runs = [subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, cwd=ROOT)
            for _ in range(2)]
    outs = [p.communicate(timeout=600) for p in runs]
    assert [p.returncode for p in runs] == [0, 0], outs
    assert sorted(out.split(" kernels")[0] for out, _ in outs) == ["0", "3"], outs


def test_a_run_compiles_ahead_once_on_a_cold_cache(monkeypatch):
    import copy

    import rfesim
    import rfesim.api as api
    from scenes import RISER

    sc = copy.deepcopy(RISER)
    calls = []
    monkeypatch.setattr(api, "_COMPILE_CHECKED", False)
    monkeypatch.setattr(P, "cache_is_cold", lambda: True)
    monkeypatch.setattr(P, "precompile", lambda n: calls.append(n) or 0)
    monkeypatch.setenv("RFESIM_PRECOMPILE", "2")
    bad = copy.deepcopy(sc)
    bad["lines"]["riser"]["elements"] = 0
    with pytest.raises(rfesim.ScenarioError, match="elements"):
        rfesim.statics(bad)                                       # refused before any compiling
    assert calls == []
    rfesim.statics(sc)
    rfesim.modes(sc, n=2)
    assert calls == [2]                                           # once per process
    # one process would compile more than the run needs: left to the run
    monkeypatch.setattr(api, "_COMPILE_CHECKED", False)
    monkeypatch.setenv("RFESIM_PRECOMPILE", "1")
    rfesim.statics(sc)
    assert calls == [2]
