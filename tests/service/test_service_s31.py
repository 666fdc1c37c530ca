"""Defects of the service found by an audit: the sweep CSV rounded every number to 6
significant digits, partial results files of killed workers stayed in the job folders for
ever."""
from __future__ import annotations

import csv
import io
import time

from service_helpers import riser


def _wait_sweep(client, sweep_id: str, timeout: float = 120.0) -> dict:
    deadline = time.monotonic() + timeout
    while True:
        r = client.get(f"/sweeps/{sweep_id}")
        assert r.status_code == 200, r.text
        if r.json()["status"] not in ("queued", "running"):
            return r.json()
        assert time.monotonic() < deadline, r.json()
        time.sleep(0.1)


# --------------------------------------------------------------------------- 1. the sweep CSV

def test_the_sweep_csv_has_the_numbers_of_the_json_table_in_full_precision(api):
    amplitudes = [0.2000001, 0.2000004]
    r = api.client.post("/sweeps", json={"scenario": riser(),
                                         "vary": {"vessels.ship.motion.heave.amplitude": amplitudes}})
    assert r.status_code == 202, r.text
    table = _wait_sweep(api.client, r.json()["id"])
    assert table["status"] == "done", table
    r = api.client.get(f"/sweeps/{table['id']}/table.csv")
    assert r.status_code == 200, r.text
    header, *rows = list(csv.reader(io.StringIO(r.text)))
    assert header == table["columns"] and len(rows) == 2
    # the two load cases: told apart (6 digits made both 0.2)
    assert [row[1] for row in rows] == ["0.2000001", "0.2000004"]
    numbers = 0
    for row, answer in zip(rows, table["rows"]):
        for cell, column in zip(row, header):
            value = answer[column]
            if isinstance(value, float):
                assert float(cell) == value, (column, cell, value)     # read back exactly
                numbers += 1
    assert numbers >= 12
