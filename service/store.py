"""Job records in SQLite (WAL journal, full sync): the service's memory across restarts.

One row per job. A job moves ``queued -> running -> done | failed | cancelled``; a
running job whose service stopped goes back to ``queued`` at the next start (or to
``failed`` once it has been interrupted ``max_attempts`` times). Sweeps are a row in
``sweeps`` and one job per load case.

Every thread gets its own connection; writes are short transactions.
"""
from __future__ import annotations

import json
import sqlite3
import threading
import time
from pathlib import Path
from typing import Any

TERMINAL = ("done", "failed", "cancelled")
STATUSES = ("queued", "running") + TERMINAL

SCHEMA = """
CREATE TABLE IF NOT EXISTS jobs (
    seq INTEGER PRIMARY KEY AUTOINCREMENT,
    id TEXT UNIQUE NOT NULL,
    status TEXT NOT NULL,
    name TEXT NOT NULL DEFAULT '',
    scenario TEXT NOT NULL,
    progress REAL NOT NULL DEFAULT 0,
    sim_time REAL,
    message TEXT NOT NULL DEFAULT '',
    created REAL NOT NULL,
    started REAL,
    finished REAL,
    attempts INTEGER NOT NULL DEFAULT 0,
    cancel_requested INTEGER NOT NULL DEFAULT 0,
    worker TEXT,
    worker_pid INTEGER,
    sweep_id TEXT,
    case_index INTEGER,
    case_values TEXT,
    summary TEXT,
    wall_time REAL,
    has_results INTEGER NOT NULL DEFAULT 0,
    warnings TEXT,
    compile_time REAL
);
CREATE INDEX IF NOT EXISTS jobs_status ON jobs (status, seq);
CREATE INDEX IF NOT EXISTS jobs_sweep ON jobs (sweep_id, case_index);
CREATE TABLE IF NOT EXISTS sweeps (
    seq INTEGER PRIMARY KEY AUTOINCREMENT,
    id TEXT UNIQUE NOT NULL,
    name TEXT NOT NULL DEFAULT '',
    vary TEXT NOT NULL,
    ncases INTEGER NOT NULL,
    created REAL NOT NULL
);
"""

JOB_COLUMNS = ("id", "status", "name", "progress", "sim_time", "message", "created", "started", "finished",
               "attempts", "cancel_requested", "worker", "worker_pid", "sweep_id", "case_index", "case_values",
               "summary", "wall_time", "has_results", "warnings", "compile_time")

# columns added after the first release: added to an older database when it is opened
ADDED_COLUMNS = {"warnings": "TEXT", "compile_time": "REAL"}


class QueueFull(Exception):
    """More queued jobs than the service accepts."""


class Store:
    def __init__(self, path: Path):
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._local = threading.local()
        self._write_lock = threading.Lock()
        con = self._connect()
        con.execute("PRAGMA journal_mode=WAL")
        con.executescript(SCHEMA)
        have = {r[1] for r in con.execute("PRAGMA table_info(jobs)").fetchall()}
        for name, kind in ADDED_COLUMNS.items():
            if name not in have:
                con.execute(f"ALTER TABLE jobs ADD COLUMN {name} {kind}")

    # ------------------------------------------------------------------ connections
    def _connect(self) -> sqlite3.Connection:
        con = getattr(self._local, "con", None)
        if con is None:
            con = sqlite3.connect(self.path, timeout=30.0, isolation_level=None, check_same_thread=False)
            con.row_factory = sqlite3.Row
            con.execute("PRAGMA synchronous=FULL")
            con.execute("PRAGMA busy_timeout=30000")
            self._local.con = con
        return con

    def _write(self, sql: str, params=()) -> sqlite3.Cursor:
        with self._write_lock:
            return self._connect().execute(sql, params)

    def close(self) -> None:
        con = getattr(self._local, "con", None)
        if con is not None:
            con.close()
            self._local.con = None

    # ------------------------------------------------------------------ jobs
    def insert_jobs(self, jobs: list[dict], max_queued: int | None = None, sweep: dict | None = None) -> None:
        """Insert jobs (and their sweep) in one transaction; QueueFull if the queue would
        exceed ``max_queued``."""
        now = time.time()
        with self._write_lock:
            con = self._connect()
            con.execute("BEGIN IMMEDIATE")
            try:
                if max_queued is not None:
                    queued = con.execute("SELECT COUNT(*) FROM jobs WHERE status='queued'").fetchone()[0]
                    if queued + len(jobs) > max_queued:
                        raise QueueFull(f"{queued} jobs are queued and the service takes at most {max_queued}; "
                                        f"retry when some have finished")
                if sweep is not None:
                    con.execute("INSERT INTO sweeps (id, name, vary, ncases, created) VALUES (?, ?, ?, ?, ?)",
                                (sweep["id"], sweep.get("name", ""), json.dumps(sweep["vary"]), len(jobs), now))
                for j in jobs:
                    con.execute(
                        "INSERT INTO jobs (id, status, name, scenario, created, message, sweep_id, case_index, "
                        "case_values, warnings) VALUES (?, 'queued', ?, ?, ?, 'queued', ?, ?, ?, ?)",
                        (j["id"], j.get("name", ""), j["scenario"], now, j.get("sweep_id"), j.get("case_index"),
                         json.dumps(j["case_values"]) if j.get("case_values") is not None else None,
                         json.dumps(list(j.get("warnings") or []))))
                con.execute("COMMIT")
            except BaseException:
                con.execute("ROLLBACK")
                raise

    def get(self, job_id: str) -> dict | None:
        row = self._connect().execute(f"SELECT {', '.join(JOB_COLUMNS)} FROM jobs WHERE id=?",
                                      (job_id,)).fetchone()
        return _job(row) if row is not None else None

    def scenario(self, job_id: str) -> str | None:
        row = self._connect().execute("SELECT scenario FROM jobs WHERE id=?", (job_id,)).fetchone()
        return row[0] if row else None

    def list(self, offset: int = 0, limit: int = 50, status: str | None = None) -> tuple[int, list[dict]]:
        con = self._connect()
        where, params = ("WHERE status=?", (status,)) if status else ("", ())
        total = con.execute(f"SELECT COUNT(*) FROM jobs {where}", params).fetchone()[0]
        rows = con.execute(f"SELECT {', '.join(JOB_COLUMNS)} FROM jobs {where} ORDER BY seq DESC LIMIT ? OFFSET ?",
                           params + (limit, offset)).fetchall()
        return total, [_job(r) for r in rows]

    def count(self, status: str) -> int:
        return self._connect().execute("SELECT COUNT(*) FROM jobs WHERE status=?", (status,)).fetchone()[0]

    def claim_queued(self, n: int) -> list[tuple[str, str, int]]:
        """Mark up to ``n`` of the oldest queued jobs running; ``(id, scenario, attempt)`` each."""
        if n <= 0:
            return []
        now = time.time()
        with self._write_lock:
            con = self._connect()
            con.execute("BEGIN IMMEDIATE")
            try:
                rows = con.execute("SELECT id, scenario, attempts FROM jobs WHERE status='queued' "
                                   "ORDER BY seq LIMIT ?", (n,)).fetchall()
                for r in rows:
                    con.execute("UPDATE jobs SET status='running', started=?, attempts=attempts+1, progress=0, "
                                "sim_time=NULL, worker=NULL, worker_pid=NULL WHERE id=?", (now, r[0]))
                con.execute("COMMIT")
            except BaseException:
                con.execute("ROLLBACK")
                raise
        return [(r[0], r[1], r[2] + 1) for r in rows]

    def set_running_info(self, job_id: str, message: str, worker: str | None, worker_pid: int | None) -> None:
        self._write("UPDATE jobs SET message=?, worker=?, worker_pid=? WHERE id=? AND status='running'",
                    (message, worker, worker_pid, job_id))

    def set_running_message(self, job_id: str, message: str) -> None:
        self._write("UPDATE jobs SET message=? WHERE id=? AND status='running'", (message, job_id))

    def set_progress(self, job_id: str, fraction: float, sim_time: float) -> None:
        self._write("UPDATE jobs SET progress=?, sim_time=? WHERE id=? AND status='running'",
                    (fraction, sim_time, job_id))

    def finish(self, job_id: str, status: str, message: str, *, summary: dict | None = None,
               wall_time: float | None = None, has_results: bool = False, progress: float | None = None,
               sim_time: float | None = None, warnings: list[str] | None = None,
               compile_time: float | None = None) -> None:
        """A job is over. ``warnings``: the job's whole list (those found at submit and
        those of the run), None to keep the stored one."""
        assert status in TERMINAL
        self._write("UPDATE jobs SET status=?, message=?, summary=?, wall_time=?, has_results=?, finished=?, "
                    "progress=COALESCE(?, progress), sim_time=COALESCE(?, sim_time), "
                    "warnings=COALESCE(?, warnings), compile_time=COALESCE(?, compile_time) WHERE id=?",
                    (status, message, json.dumps(summary) if summary is not None else None, wall_time,
                     int(has_results), time.time(), progress, sim_time,
                     json.dumps(list(warnings)) if warnings is not None else None, compile_time, job_id))

    def cancel_queued(self, job_id: str) -> bool:
        """Cancel a job that is still queued; False if it is not queued (any more)."""
        cur = self._write("UPDATE jobs SET status='cancelled', message='cancelled before it started', "
                          "finished=?, cancel_requested=1 WHERE id=? AND status='queued'", (time.time(), job_id))
        return cur.rowcount == 1

    def request_cancel(self, job_id: str) -> bool:
        cur = self._write("UPDATE jobs SET cancel_requested=1 WHERE id=? AND status='running'", (job_id,))
        return cur.rowcount == 1

    def requeue_one(self, job_id: str) -> None:
        """Undo a claim that could not be handed to a worker."""
        self._write("UPDATE jobs SET status='queued', attempts=MAX(0, attempts-1), started=NULL WHERE id=? "
                    "AND status='running'", (job_id,))

    def names(self, text: str) -> bool:
        """Whether some job's stored scenario contains ``text`` (a copy of an input file)."""
        return self._connect().execute("SELECT 1 FROM jobs WHERE instr(scenario, ?) > 0 LIMIT 1",
                                       (text,)).fetchone() is not None

    def delete_jobs(self, job_ids: list[str], sweep_id: str | None = None) -> bool:
        """Delete the records of jobs that are over (and the row of the sweep ``sweep_id``) in
        one transaction; False, deleting nothing, when one of them is gone or not over."""
        marks = ", ".join("?" * len(job_ids))
        with self._write_lock:
            con = self._connect()
            con.execute("BEGIN IMMEDIATE")
            try:
                if job_ids:
                    cur = con.execute(f"DELETE FROM jobs WHERE id IN ({marks}) AND status IN ('done', 'failed', "
                                      f"'cancelled')", tuple(job_ids))
                    if cur.rowcount != len(set(job_ids)):
                        con.execute("ROLLBACK")
                        return False
                if sweep_id is not None:
                    con.execute("DELETE FROM sweeps WHERE id=?", (sweep_id,))
                con.execute("COMMIT")
            except BaseException:
                con.execute("ROLLBACK")
                raise
        return True

    def running_ids(self) -> list[str]:
        return [r[0] for r in self._connect().execute("SELECT id FROM jobs WHERE status='running'").fetchall()]

    def requeue_running(self, message: str, max_attempts: int | None = None,
                        refund: bool = False) -> tuple[list[str], list[str]]:
        """After a stop: running jobs go back to the queue (or fail when interrupted too
        often, or are cancelled when a cancel was asked). ``refund``: a clean stop of the
        service, which does not count as an attempt. Returns (re-queued, failed) ids."""
        requeued, failed = [], []
        now = time.time()
        with self._write_lock:
            con = self._connect()
            con.execute("BEGIN IMMEDIATE")
            try:
                rows = con.execute("SELECT id, attempts, cancel_requested FROM jobs WHERE status='running'").fetchall()
                for job_id, attempts, cancel in rows:
                    if cancel:
                        con.execute("UPDATE jobs SET status='cancelled', message=?, finished=? WHERE id=?",
                                    ("cancelled (the service stopped while the job was being cancelled)", now,
                                     job_id))
                    elif max_attempts is not None and attempts >= max_attempts:
                        con.execute("UPDATE jobs SET status='failed', message=?, finished=? WHERE id=?",
                                    (f"interrupted {attempts} times by service stops; not re-queued again "
                                     f"(resubmit it to try again)", now, job_id))
                        failed.append(job_id)
                    else:
                        con.execute("UPDATE jobs SET status='queued', message=?, progress=0, sim_time=NULL, "
                                    "worker=NULL, worker_pid=NULL, attempts=attempts-? WHERE id=?",
                                    (message, int(refund and attempts > 0), job_id))
                        requeued.append(job_id)
                con.execute("COMMIT")
            except BaseException:
                con.execute("ROLLBACK")
                raise
        return requeued, failed

    # ------------------------------------------------------------------ sweeps
    def get_sweep(self, sweep_id: str) -> dict | None:
        con = self._connect()
        row = con.execute("SELECT id, name, vary, ncases, created FROM sweeps WHERE id=?", (sweep_id,)).fetchone()
        if row is None:
            return None
        jobs = con.execute(f"SELECT {', '.join(JOB_COLUMNS)} FROM jobs WHERE sweep_id=? ORDER BY case_index",
                           (sweep_id,)).fetchall()
        return {"id": row[0], "name": row[1], "vary": json.loads(row[2]), "ncases": row[3], "created": row[4],
                "jobs": [_job(r) for r in jobs]}

    def list_sweeps(self, offset: int = 0, limit: int = 50) -> tuple[int, list[dict]]:
        con = self._connect()
        total = con.execute("SELECT COUNT(*) FROM sweeps").fetchone()[0]
        rows = con.execute("SELECT id FROM sweeps ORDER BY seq DESC LIMIT ? OFFSET ?", (limit, offset)).fetchall()
        return total, [s for s in (self.get_sweep(r[0]) for r in rows) if s is not None]


def _job(row) -> dict[str, Any]:
    d = dict(zip(JOB_COLUMNS, tuple(row)))
    d["summary"] = json.loads(d["summary"]) if d["summary"] else None
    d["case_values"] = json.loads(d["case_values"]) if d["case_values"] else None
    d["cancel_requested"] = bool(d["cancel_requested"])
    d["has_results"] = bool(d["has_results"])
    d["warnings"] = json.loads(d["warnings"]) if d["warnings"] else []
    return d
