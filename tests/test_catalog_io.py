"""Catalog CSV validation: every bad row gives a clear error; nothing is ever half-written."""

import hashlib

import numpy as np
import pytest
from pydantic import ValidationError

from budget.catalog.io import (ALT_UNIT_COLUMNS, append_part, load_catalog, part_origins, parts_to_csv_text,
                               read_grades, read_parts, shipped_catalog_dir, write_parts)
from budget.catalog.schema import PART_COLUMNS, GradeSpec, PartSpec
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
    origin = part_origins(user)
    assert list(origin) == list(merged)
    assert origin[pid] == "user, replaces shipped" and origin["MINE-1"] == "user"
    assert {origin[k] for k in shipped if k != pid} == {"shipped"}


def test_catalog_list_and_show_mark_a_replaced_shipped_row(tmp_path, capsys, monkeypatch):
    import json
    monkeypatch.delenv("SAR_BUDGET_CATALOG", raising=False)

    from budget.cli.main import main
    pid = next(iter(read_parts(shipped_catalog_dir() / "parts.csv")))
    user = tmp_path / "u.csv"
    write_parts(user, [PartSpec(part_id=pid, grade="consumer", gyro_arw_deg_rt_h=9.0, source="mine")])
    assert main(["catalog", "list", "--catalog", str(user)]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith(pid + " "))
    assert line.rstrip().endswith("user, replaces shipped")
    assert main(["catalog", "show", pid, "--catalog", str(user), "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out)["origin"] == "user, replaces shipped"
    assert main(["catalog", "list", "--json", "-"]) == 0
    assert {r["origin"] for r in json.loads(capsys.readouterr().out)} == {"shipped"}


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


# --- writers re-validate; booleans; InputError at the API; ids differing only in case --------

def _stim300():
    return read_parts(shipped_catalog_dir() / "parts.csv")["STIM300"]


def test_append_of_an_unvalidated_model_copy_is_refused_and_the_file_kept(tmp_path):
    """The tester's case: model_copy(update=…) skips validation; the row must not be written."""
    p = tmp_path / "g2.csv"
    good = _stim300()
    append_part(p, good)
    before = p.read_bytes()
    bad = good.model_copy(update={"gyro_arw_deg_rt_h": -5.0})
    with pytest.raises(InputError) as e:
        append_part(p, bad, replace=True)
    msg = str(e.value)
    assert "g2.csv" in msg and "STIM300" in msg and "field gyro_arw_deg_rt_h" in msg and "-5.0" in msg
    assert "\n" not in msg
    assert p.read_bytes() == before  # byte-identical
    assert not list(tmp_path.glob(".*.tmp"))
    assert read_parts(p)["STIM300"].gyro_arw_deg_rt_h == good.gyro_arw_deg_rt_h
    # a file that does not exist yet is not created
    fresh = tmp_path / "fresh.csv"
    with pytest.raises(InputError, match="gyro_arw_deg_rt_h"):
        append_part(fresh, bad)
    assert not fresh.exists()


@pytest.mark.parametrize("update,field,words", [
    ({"notes": "red \x1b[31m text"}, "notes", "control characters"),  # the schema allows it, the reader not
    ({"vendor": "x" * 20_000}, "vendor", "characters"),
    ({"grade": "superb"}, "grade", "strategic"),
    ({"colour": "red"}, "colour", "Extra inputs"),
])
def test_append_refuses_rows_a_later_read_would_refuse(tmp_path, update, field, words):
    p = write(tmp_path, f"{HEADER}\n{GOOD}\n")
    before = p.read_bytes()
    part = PartSpec(part_id="P7", grade="tactical", source="ds").model_copy(update=update)
    with pytest.raises(InputError) as e:
        append_part(p, part)
    msg = str(e.value)
    assert "P7" in msg and f"field {field}" in msg and words in msg
    assert p.read_bytes() == before
    assert list(read_parts(p)) == ["P1"]


def test_write_parts_refuses_what_read_parts_would_refuse(tmp_path):
    p = tmp_path / "w.csv"
    a = PartSpec(part_id="A1", grade="tactical", source="ds")
    with pytest.raises(InputError, match="duplicate part_id"):
        write_parts(p, [a, a])
    with pytest.raises(InputError, match="field mass_g"):
        write_parts(p, [a.model_copy(update={"mass_g": float("nan")})])
    assert not p.exists()


@pytest.mark.parametrize("value", [True, False, np.True_, np.False_])
def test_number_fields_refuse_booleans(value):
    with pytest.raises(ValidationError, match="true/false"):
        PartSpec(part_id="B1", grade="tactical", source="ds", gyro_arw_deg_rt_h=value)
    with pytest.raises(ValidationError, match="true/false"):
        PartSpec(part_id="B1", grade="tactical", source="ds", rate_hz=value)
    grade = next(iter(read_grades(shipped_catalog_dir() / "grades.csv").values()))
    with pytest.raises(ValidationError, match="true/false"):
        GradeSpec.model_validate({**grade.model_dump(), "rank": value})


def test_booleans_refused_alike_by_the_model_and_the_csv_reader(tmp_path):
    with pytest.raises(InputError, match="not a number"):
        read_parts(write(tmp_path, f"{HEADER}\nP2,Acme,X2,tactical,true,0.07,ds\n"))
    with pytest.raises(InputError, match="true/false"):
        append_part(tmp_path / "b.csv", {"part_id": "P2", "grade": "tactical", "source": "ds",
                                         "gyro_arw_deg_rt_h": True})
    assert not (tmp_path / "b.csv").exists()
    # numbers (numpy ones included) are still taken
    p = PartSpec(part_id="P3", grade="tactical", source="ds", gyro_arw_deg_rt_h=np.float64(0.2),
                 rate_hz=np.int64(200))
    assert p.gyro_arw_deg_rt_h == 0.2 and p.rate_hz == 200.0


@pytest.mark.parametrize("call", [
    lambda p: append_part(p, {"part_id": "D1", "source": "ds"}),                     # no grade
    lambda p: append_part(p, {"part_id": "D1", "grade": "tactical", "source": "ds",
                              "gyro_arw_deg_rt_h": -1}),
    lambda p: append_part(p, {"part_id": "bad id", "grade": "tactical", "source": "ds"}),
    lambda p: append_part(p, "STIM300"),                                              # not a part
    lambda p: write_parts(p, [{"part_id": "D1", "grade": "tactical", "source": ""}]),
    lambda p: write_parts(p, [PartSpec.model_construct(part_id="D1", grade="tactical",
                                                       source="ds", mass_g=-3.0)]),
    lambda p: p.write_text(parts_to_csv_text([{"part_id": "D1", "grade": "tactical",
                                               "source": "ds", "mass_g": True}])),
])
def test_bad_parts_through_the_api_are_input_errors_of_one_line(tmp_path, call):
    p = tmp_path / "api.csv"
    with pytest.raises(InputError) as e:  # not a raw pydantic ValidationError
        call(p)
    assert not isinstance(e.value, ValidationError)
    assert "\n" not in str(e.value) and "errors.pydantic.dev" not in str(e.value)
    assert not p.exists()


def test_append_of_an_id_differing_only_in_case_from_a_shipped_one_is_refused(tmp_path):
    p = write(tmp_path, f"{HEADER}\n{GOOD}\n")
    before = p.read_bytes()
    twin = _stim300().model_copy(update={"part_id": "stim300"})
    for replace in (False, True):
        with pytest.raises(InputError) as e:
            append_part(p, twin, replace=replace)
        msg = str(e.value)
        assert "'stim300'" in msg and "'STIM300'" in msg and "field part_id" in msg
        assert p.read_bytes() == before
    append_part(p, _stim300())  # the exact shipped id overrides it, as before
    assert load_catalog(p)["STIM300"].source == _stim300().source


def test_append_of_an_id_differing_only_in_case_from_one_in_the_file(tmp_path):
    p = write(tmp_path, f"{HEADER}\n{GOOD}\n")
    before = p.read_bytes()
    new = PartSpec(part_id="p1", grade="industrial", gyro_arw_deg_rt_h=2.0, source="ds")
    with pytest.raises(InputError) as e:
        append_part(p, new)
    assert "'P1'" in str(e.value) and "--replace" in str(e.value)
    assert p.read_bytes() == before
    append_part(p, new, replace=True)  # replaces that row where it stands
    parts = read_parts(p)
    assert list(parts) == ["p1"] and parts["p1"].gyro_arw_deg_rt_h == 2.0


def test_loading_a_user_id_differing_only_in_case_from_a_shipped_one_warns(tmp_path):
    p = write(tmp_path, "part_id,grade,source\nstim300,tactical,mine\n")
    with pytest.warns(UserWarning, match=r"my\.csv.*'stim300'.*'STIM300'"):
        merged = load_catalog(p)
    assert merged["stim300"].source == "mine" and merged["STIM300"].source == _stim300().source
