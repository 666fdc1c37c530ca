"""The tests' root: pytest puts this folder on sys.path (the default "prepend" import mode,
no __init__.py), so every test module, in any subfolder, imports the shared small scenes as
``import scenes`` (tests/scenes.py)."""


def pytest_sessionstart(session):
    """A cold numba cache (a fresh clone, CI): compile the kernels the shipped scenarios reach
    ahead, in parallel processes (rfesim.precompile) rather than one by one as tests first
    call them; a warm cache costs nothing here."""
    from rfesim.cli import numba_cache_is_cold

    if numba_cache_is_cold():
        import time

        import rfesim

        t0 = time.perf_counter()
        n = rfesim.precompile()
        print(f"\nrfesim: {n} numba kernels compiled ahead in {time.perf_counter() - t0:.0f} s")
