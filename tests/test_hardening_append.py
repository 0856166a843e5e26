"""Appends to a user catalog : symlinks followed, missing folders refused,
temporary files removed, the user's columns, order, units and line endings kept."""

from __future__ import annotations

import os
import time

import pytest

from budget import fileio
from budget.catalog.io import append_part, read_parts
from budget.catalog.schema import PartSpec
from budget.errors import InputError, OutputError

NEW = PartSpec(part_id="NEW-1", grade="industrial", gyro_arw_deg_rt_h=0.3, accel_vrw_m_s_rt_h=0.06,
               source="measured")


def test_symlink_target_is_updated_and_link_kept(tmp_path):
    real = tmp_path / "real" / "cat.csv"
    real.parent.mkdir()
    real.write_text("part_id,grade,source\nP1,tactical,ds\n")
    link = tmp_path / "link.csv"
    link.symlink_to(real)
    append_part(link, NEW)
    assert link.is_symlink() and os.readlink(link) == str(real)
    assert list(read_parts(real)) == ["P1", "NEW-1"]


def test_missing_folder_is_refused(tmp_path):
    with pytest.raises(OutputError, match="does not exist"):
        append_part(tmp_path / "nope" / "cat.csv", NEW)
    assert not (tmp_path / "nope").exists()


def test_user_columns_order_units_and_bytes_are_kept(tmp_path):
    p = tmp_path / "cat.csv"
    original = ("source,part_id,grade,accel_vrw_ug_rt_hz,gyro_arw_deg_rt_h\r\n"
                "\"Acme, rev B\",P1,tactical,25.0,0.15\r\n")
    p.write_bytes(original.encode())
    append_part(p, NEW)
    text = p.read_bytes().decode()
    assert text.startswith(original)  # untouched bytes, the row appended after them
    last = text[len(original):]
    assert last.endswith("\r\n") and last.count("\r\n") == 1
    cells = last.strip().split(",")
    assert cells[:3] == ["measured", "NEW-1", "industrial"]
    back = read_parts(p)["NEW-1"]
    assert back.accel_vrw_m_s_rt_h == pytest.approx(0.06, rel=1e-12)  # via µg/√Hz and back
    assert back.gyro_arw_deg_rt_h == 0.3


def test_columns_the_file_lacks_are_added_at_the_end(tmp_path):
    p = tmp_path / "cat.csv"
    p.write_text("part_id,grade,source\nP1,tactical,ds\n")
    append_part(p, NEW)
    header = p.read_text().splitlines()[0].split(",")
    assert header[:3] == ["part_id", "grade", "source"]
    assert set(header[3:]) == {"gyro_arw_deg_rt_h", "accel_vrw_m_s_rt_h"}
    parts = read_parts(p)
    assert parts["P1"].gyro_arw_deg_rt_h is None and parts["NEW-1"].gyro_arw_deg_rt_h == 0.3


def test_replace_keeps_the_row_in_place(tmp_path):
    p = tmp_path / "cat.csv"
    p.write_text("part_id,grade,source,gyro_arw_deg_rt_h,accel_vrw_m_s_rt_h\n"
                 "NEW-1,tactical,old,1,1\nP2,tactical,ds,,\n")
    with pytest.raises(InputError, match="already"):
        append_part(p, NEW)
    append_part(p, NEW, replace=True)
    parts = read_parts(p)
    assert list(parts) == ["NEW-1", "P2"] and parts["NEW-1"].source == "measured"


def test_failed_write_leaves_no_temp_file(tmp_path, monkeypatch):
    p = tmp_path / "cat.csv"
    p.write_text("part_id,grade,source\nP1,tactical,ds\n")
    before = p.read_bytes()

    def fail(*a, **k):
        raise KeyboardInterrupt  # as a Ctrl+C / SIGTERM during the write

    monkeypatch.setattr(fileio.os, "replace", fail)
    with pytest.raises(KeyboardInterrupt):
        append_part(p, NEW)
    assert p.read_bytes() == before
    assert not [f for f in os.listdir(tmp_path) if f.endswith(".tmp")]


def test_stale_temp_files_of_a_killed_run_are_cleaned(tmp_path):
    p = tmp_path / "cat.csv"
    p.write_text("part_id,grade,source\nP1,tactical,ds\n")
    stale = tmp_path / f".cat.csv{fileio.TMP_TAG}abc123.tmp"
    fresh = tmp_path / f".cat.csv{fileio.TMP_TAG}def456.tmp"
    stale.write_text("half")
    fresh.write_text("another run, in progress")
    old = time.time() - 2 * fileio.STALE_TMP_S
    os.utime(stale, (old, old))
    append_part(p, NEW)
    assert not stale.exists() and fresh.exists()  # a running writer's file is left alone


def test_sigkill_during_appends_never_corrupts(tmp_path):
    import signal
    import subprocess
    import sys

    p = tmp_path / "cat.csv"
    p.write_text("part_id,grade,source\nP0,tactical,ds\n")
    code = ("import sys\nfrom budget.catalog.io import append_part\nfrom budget.catalog.schema import PartSpec\n"
            "for i in range(1, 100000):\n"
            "    append_part(sys.argv[1], PartSpec(part_id=f'K{i}', grade='tactical', source='s'))\n")
    proc = subprocess.Popen([sys.executable, "-c", code, str(p)])
    deadline = time.monotonic() + 30
    while p.read_text().count("\n") < 6 and time.monotonic() < deadline:
        time.sleep(0.05)  # let it append a few rows, then kill it mid-run
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    parts = read_parts(p)  # still a valid catalog
    assert "P0" in parts
    ids = list(parts)[1:]
    assert len(ids) >= 4 and ids == [f"K{i}" for i in range(1, len(ids) + 1)]  # none lost
    leftovers = [f for f in os.listdir(tmp_path) if f.endswith(".tmp")]
    assert len(leftovers) <= 1 and all(fileio.TMP_TAG in f for f in leftovers)  # recognisable
