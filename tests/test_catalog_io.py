"""Catalog CSV validation: every bad row gives a clear error; nothing is ever half-written."""

import hashlib

import pytest

from budget.catalog.io import (ALT_UNIT_COLUMNS, append_part, load_catalog, read_parts,
                               shipped_catalog_dir, write_parts)
from budget.catalog.schema import PART_COLUMNS, PartSpec
from budget.errors import InputError

HEADER = "part_id,vendor,model,grade,gyro_arw_deg_rt_h,accel_vrw_m_s_rt_h,source"
GOOD = "P1,Acme,X1,tactical,0.15,0.07,Acme X1 datasheet Rev. A"


def write(tmp_path, text, name="my.csv", encoding="utf-8"):
    p = tmp_path / name
    p.write_bytes(text.encode(encoding))
    return p


def test_good_file(tmp_path):
    parts = read_parts(write(tmp_path, f"{HEADER}\n{GOOD}\n"))
    p = parts["P1"]
    assert p.gyro_arw_deg_rt_h == 0.15 and p.accel_bias_instability_ug is None
    assert p.to_si().gyro_arw_rad_s_rt_hz == pytest.approx(0.15 * 3.141592653589793 / 180 / 60)


@pytest.mark.parametrize("row,field,words", [
    ("P2,Acme,X2,tactical,abc,0.07,ds", "gyro_arw_deg_rt_h", "not a number"),
    ("P2,Acme,X2,tactical,-1,0.07,ds", "gyro_arw_deg_rt_h", "greater than or equal"),
    ("P2,Acme,X2,tactical,nan,0.07,ds", "gyro_arw_deg_rt_h", "finite"),
    ("P2,Acme,X2,tactical,inf,0.07,ds", "gyro_arw_deg_rt_h", "finite"),
    ("P2,Acme,X2,superb,0.1,0.07,ds", "grade", "strategic"),
    ("P1,Acme,X2,tactical,0.1,0.07,ds", "part_id", "duplicate"),
    ("P2,=HYPERLINK(\"x\"),X2,tactical,0.1,0.07,ds", "vendor", "formula"),
    ("P2,Acme,X2,tactical,0.1,0.07,", "source", "datasheet"),
    ("P2,Acme,X2,tactical,0.1,0.07", None, "cells"),
    ("P 2,Acme,X2,tactical,0.1,0.07,ds", "part_id", "letters"),
])
def test_bad_rows_name_file_row_column(tmp_path, row, field, words):
    p = write(tmp_path, f"{HEADER}\n{GOOD}\n{row}\n")
    with pytest.raises(InputError) as e:
        read_parts(p)
    msg = str(e.value)
    assert "my.csv" in msg and "row 3" in msg and words in msg
    if field:
        assert f"field {field}" in msg


@pytest.mark.parametrize("text,words", [
    ("", "empty"),
    (f"{HEADER}\n", "no parts"),
    (f"{HEADER},colour\n{GOOD},red\n", "unknown column"),
    (f"{HEADER},gyro_arw_deg_rt_h\n{GOOD},0.1\n", "duplicate column"),
    (f"{HEADER},gyro_arw_deg_s_rt_hz\n{GOOD},0.1\n", "twice"),
    ("vendor,model\nAcme,X\n", "missing required"),
])
def test_bad_files(tmp_path, text, words):
    with pytest.raises(InputError, match=words):
        read_parts(write(tmp_path, text))


def test_wrong_encoding(tmp_path):
    p = write(tmp_path, f"{HEADER}\nP1,Müller,X1,tactical,0.15,0.07,ds\n", encoding="latin-1")
    with pytest.raises(InputError, match="UTF-8"):
        read_parts(p)


def test_alternative_unit_headers(tmp_path):
    # µg/√Hz and deg/s/√Hz columns are converted to the canonical m/s/√h and deg/√h
    text = ("part_id,grade,accel_vrw_ug_rt_hz,gyro_arw_deg_s_rt_hz,accel_bias_instability_mg,source\n"
            "P1,tactical,1699.53,0.0025,0.05,ds\n")
    p = read_parts(write(tmp_path, text))["P1"]
    assert p.accel_vrw_m_s_rt_h == pytest.approx(1.0, rel=1e-4)
    assert p.gyro_arw_deg_rt_h == pytest.approx(0.15)
    assert p.accel_bias_instability_ug == pytest.approx(50.0)
    assert all(canon in PART_COLUMNS for canon, _ in ALT_UNIT_COLUMNS.values())


def test_roundtrip_and_atomic_append(tmp_path):
    p = write(tmp_path, f"{HEADER}\n{GOOD}\n")
    new = PartSpec(part_id="P9", grade="industrial", gyro_arw_deg_rt_h=2.0, source="ds")
    append_part(p, new)
    parts = read_parts(p)
    assert list(parts) == ["P1", "P9"]
    before = p.read_bytes()
    with pytest.raises(InputError, match="already"):
        append_part(p, new)
    assert p.read_bytes() == before  # failed update leaves the file untouched
    assert not list(tmp_path.glob(".*.tmp"))


def test_failed_user_update_never_touches_shipped(tmp_path, monkeypatch):
    shipped = shipped_catalog_dir() / "parts.csv"
    if not shipped.exists():
        pytest.skip("shipped catalog not present yet")
    digest = hashlib.sha256(shipped.read_bytes()).hexdigest()
    bad = write(tmp_path, f"{HEADER}\n{GOOD}\nP2,Acme,X2,tactical,oops,0.07,ds\n")
    with pytest.raises(InputError):
        load_catalog(bad)
    monkeypatch.setenv("SAR_BUDGET_CATALOG", str(bad))
    with pytest.raises(InputError):
        load_catalog()
    with pytest.raises(InputError, match="shipped"):
        append_part(shipped, PartSpec(part_id="ZZ", grade="consumer", source="x"))
    assert hashlib.sha256(shipped.read_bytes()).hexdigest() == digest


def test_user_rows_override_shipped(tmp_path):
    shipped = read_parts(shipped_catalog_dir() / "parts.csv")
    pid = next(iter(shipped))
    user = tmp_path / "u.csv"
    write_parts(user, [PartSpec(part_id=pid, grade="consumer", gyro_arw_deg_rt_h=9.0, source="mine"),
                       PartSpec(part_id="MINE-1", grade="tactical", source="mine")])
    merged = load_catalog(user)
    assert merged[pid].source == "mine" and "MINE-1" in merged
    assert len(merged) == len(shipped) + 1


def test_atomic_write_gives_ordinary_permissions(tmp_path):
    """A new file gets 0666 & ~umask (not mkstemp's 0600); an existing file keeps its mode."""
    import os
    import stat

    from budget.fileio import _umask, atomic_write_text

    new = tmp_path / "new.csv"
    atomic_write_text(new, "a\n")
    assert stat.S_IMODE(new.stat().st_mode) == 0o666 & ~_umask()
    old = tmp_path / "old.csv"
    old.write_text("x\n")
    os.chmod(old, 0o640)
    atomic_write_text(old, "y\n")
    assert stat.S_IMODE(old.stat().st_mode) == 0o640 and old.read_text() == "y\n"


def test_bad_verified_value_names_the_field(tmp_path):
    p = write(tmp_path, "part_id,grade,source,verified\nP1,tactical,ds,datasheet\nP2,tactical,ds,maybe\n")
    with pytest.raises(InputError) as e:
        read_parts(p)
    msg = str(e.value)
    assert "row 3" in msg and "field verified" in msg and "second_hand" in msg


def test_shipped_rows_state_convention_and_verification():
    parts = read_parts(shipped_catalog_dir() / "parts.csv")
    assert all(p.verified is not None for p in parts.values())
    assert parts["HG1700AG58"].bias_instability_convention == "total_1sigma"
    assert parts["STIM300"].bias_instability_convention == "adev_min"
