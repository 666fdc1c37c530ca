"""Service workers clean up after workers that died: a warm-up folder left by a worker
killed while warming up is removed by the next worker's warm-up (they stayed in /tmp for
good), and a worker's watcher whose worker died first neither says "the service is gone"
of a healthy service nor SIGKILLs the dead pid."""
from __future__ import annotations

import multiprocessing
import os
import subprocess
import sys
import tempfile

from service import worker


def _dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def test_warm_up_folders_of_dead_workers_are_removed(tmp_path, monkeypatch):
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    dead = tmp_path / f"{worker.WARMUP_PREFIX}{_dead_pid()}-abc"
    mine = tmp_path / f"{worker.WARMUP_PREFIX}{os.getpid()}-def"
    alive = tmp_path / f"{worker.WARMUP_PREFIX}{os.getppid()}-ghi"
    other = tmp_path / f"{worker.WARMUP_PREFIX}old_style"
    unrelated = tmp_path / "something-else-123-x"
    for folder in (dead, mine, alive, other, unrelated):
        folder.mkdir()
        (folder / ".warmup.nc.0a1b.tmp").write_bytes(b"")
    worker._remove_stale_warmups()
    assert not dead.exists()
    assert mine.exists() and alive.exists() and other.exists() and unrelated.exists()


def test_the_watcher_of_a_dead_worker_says_nothing_and_kills_nothing(capfd, monkeypatch):
    """The service closed the sentinel after its worker died (the watcher was re-parented)."""
    receive, send = multiprocessing.Pipe(duplex=False)
    send.close()                                   # the sentinel reads end-of-file at once
    killed = []
    monkeypatch.setattr(worker.os, "kill", lambda pid, sig: killed.append((pid, sig)))
    gone_worker = _dead_pid()                      # not our parent: "we were re-parented"
    worker._watch(gone_worker, os.getppid(), receive, 0.01, True)
    assert killed == []
    assert "is gone" not in capfd.readouterr().err
