"""Catalog validation after review: unit-safe column suggestions, every problem of a file in one
pass, ids differing only in case, an unquoted decimal comma.

The expected numbers are written from the units' definitions here (1 deg/s/√Hz = 60 deg/√h,
1 rad = 180/π deg), not from the library's tables.
"""

from __future__ import annotations

import math
import re

import pytest

from budget.catalog.io import append_part, load_catalog, read_parts
from budget.catalog.validate import (ALT_UNIT_COLUMNS, FAST_PATH_CHARS, QUANTITY_COLUMNS, collect_errors,
                                     validate_parts_table)
from budget.cli.main import main
from budget.errors import InputError

DEG_S_RT_HZ_IN_DEG_RT_H = 60.0          # 1 deg/s/√Hz = 60 deg/√h
RAD_IN_DEG = 180.0 / math.pi


def _one_column_file(tmp_path, header: str, value: str = "0.007"):
    p = tmp_path / "mine.csv"
    p.write_text(f"part_id,vendor,model,grade,rate_hz,{header},source\n"
                 f"MTi-630,Xsens,MTi-630,industrial,400,{value},Xsens datasheet\n", encoding="utf-8")
    return p


def _refusal(path) -> InputError:
    with pytest.raises(InputError) as e:
        read_parts(path)
    assert e.value.row == 1
    return e.value


def _suggested(err: InputError) -> str | None:
    m = re.search(r"did you mean '([^']+)'", err.reason)
    return m.group(1) if m else None


# --- 1. a suggested column has the unit of the header it replaces --------------------------------

def test_dps_noise_density_header_suggests_the_deg_s_column_not_rad_s(tmp_path):
    err = _refusal(_one_column_file(tmp_path, "gyro_arw_dps_rt_hz"))
    assert err.field == "gyro_arw_dps_rt_hz"
    assert _suggested(err) == "gyro_arw_deg_s_rt_hz"
    # following the suggestion reads the figure as written: 0.007 deg/s/√Hz = 0.42 deg/√h
    fixed = _one_column_file(tmp_path, _suggested(err))
    assert read_parts(fixed)["MTi-630"].gyro_arw_deg_rt_h == pytest.approx(0.007 * DEG_S_RT_HZ_IN_DEG_RT_H)


def test_a_bias_in_dps_still_gets_the_deg_s_column(tmp_path):
    err = _refusal(_one_column_file(tmp_path, "gyro_bias_instability_dps", "0.0022"))
    assert _suggested(err) == "gyro_bias_instability_deg_s"


def test_a_unit_without_a_column_is_named_with_its_factor_and_no_column_is_guessed(tmp_path):
    err = _refusal(_one_column_file(tmp_path, "gyro_arw_mdeg_s_rt_hz", "7"))
    assert _suggested(err) is None
    assert "mdeg/s/√Hz is not a catalog unit: divide by 1000 and use gyro_arw_deg_s_rt_hz" in err.reason
    # the other accepted columns with their factors: 1 mdeg/s/√Hz = 0.06 deg/√h
    assert "multiply by 0.06 for gyro_arw_deg_rt_h" in err.reason
    # doing what it says gives the figure's true value: 7 mdeg/s/√Hz = 0.42 deg/√h
    fixed = _one_column_file(tmp_path, "gyro_arw_deg_s_rt_hz", str(7 / 1000))
    assert read_parts(fixed)["MTi-630"].gyro_arw_deg_rt_h == pytest.approx(0.42)


def test_a_unit_of_another_dimension_lists_the_accepted_columns_and_picks_none(tmp_path):
    # deg/√Hz is no ARW unit (deg/√h is, and so is deg/s/√Hz): which was meant is the user's call
    err = _refusal(_one_column_file(tmp_path, "gyro_arw_deg_rt_hz", "0.42"))
    assert _suggested(err) is None
    assert "deg/√Hz is not a unit of gyro_arw" in err.reason
    for col in ("gyro_arw_deg_rt_h", "gyro_arw_deg_s_rt_hz", "gyro_arw_rad_s_rt_hz"):
        assert col in err.expected


def test_rad_s_bias_is_named_with_the_factor_to_deg_s(tmp_path):
    err = _refusal(_one_column_file(tmp_path, "gyro_bias_instability_rad_s", "1e-5"))
    assert _suggested(err) is None
    m = re.search(r"multiply by ([0-9.e+]+) and use gyro_bias_instability_deg_s", err.reason)
    assert m and float(m.group(1)) == pytest.approx(RAD_IN_DEG, rel=1e-3)


# every accepted numeric column respelt the ways datasheets write units: the suggestion is that
# very column (never one in another unit)
_RESPELLINGS = (("deg_s", "dps"), ("deg_h", "dph"), ("rad_s", "rps"), ("_rt_h", "_sqrt_hr"),
                ("_rt_hz", "_rthz"), ("ug", "µg"), ("pct", "percent"), ("deg_", "deg_per_"),
                ("rate_hz", "rate_sps"), ("_mrad", "_milliradian"), ("_deg", "_degrees"))


def _respelt(col: str):
    for a, b in _RESPELLINGS:
        if a in col:
            yield col.replace(a, b, 1)


_ACCEPTED = sorted({c.name for cols in QUANTITY_COLUMNS.values() for c in cols})


@pytest.mark.parametrize("column, variant", [(c, v) for c in _ACCEPTED for v in _respelt(c) if v != c])
def test_every_respelt_accepted_column_is_suggested_as_itself(tmp_path, column, variant):
    err = _refusal(_one_column_file(tmp_path, variant, "1"))
    assert _suggested(err) == column, err.reason


def test_the_unit_vocabulary_agrees_with_the_column_table():
    # reading each accepted column's unit with the vocabulary gives the table's own conversion
    from budget.catalog.header_units import read_unit, unit_token

    for quantity, cols in QUANTITY_COLUMNS.items():
        canon = cols[0]
        assert canon.to_canonical == 1.0
        for col in cols[1:]:
            assert col.name in ALT_UNIT_COLUMNS
            mine = [r for r in read_unit(unit_token(col.label))]
            ref = [r for r in read_unit(unit_token(canon.label))]
            ratios = {round(a.si / b.si / col.to_canonical, 9) for a in mine for b in ref if a.dims == b.dims}
            assert ratios == {1.0}, (quantity, col.name)


def test_the_cli_names_the_unit_safe_suggestion(tmp_path, capsys):
    p = _one_column_file(tmp_path, "gyro_arw_dps_rt_hz")
    assert main(["catalog", "validate", str(p)]) == 2
    err = capsys.readouterr().err
    assert "did you mean 'gyro_arw_deg_s_rt_hz'" in err and "rad_s" not in err.split("expected")[0]
    assert "Traceback" not in err


# --- 2. every problem of a file in one pass -------------------------------------------------------

_HEAD = "part_id,grade,gyro_arw_deg_rt_h,gyro_bias_repeatability_deg_h,source,bias_instability_convention"


def test_duplicate_ids_and_the_convention_rule_are_reported_with_the_bad_cells(tmp_path, capsys):
    p = tmp_path / "many.csv"
    p.write_text("\n".join([
        _HEAD,
        "A-1,tactical,0.1,,sheet,adev_min",        # 2 fine
        "A-2,tactical,abc,,sheet,adev_min",        # 3 bad cell
        "A-1,tactical,0.1,,sheet,adev_min",        # 4 duplicate of row 2
        "A-4,tactical,0.1,5,sheet,total_1sigma",   # 5 repeatability with a constant bias
        "A-5,tactical,-1,,sheet,adev_min",         # 6 bad cell
    ]) + "\n", encoding="utf-8")
    errors = collect_errors(p)
    assert [(e.row, e.field) for e in errors] == [(3, "gyro_arw_deg_rt_h"), (4, "part_id"),
                                                  (5, "bias_instability_convention"),
                                                  (6, "gyro_arw_deg_rt_h")]
    assert "duplicate part_id" in errors[1].reason and "row 2" in errors[1].reason
    assert main(["catalog", "validate", str(p)]) == 2
    lines = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(lines) == 4 and lines[-1].endswith("4 bad cell(s) in all")


def test_a_duplicate_of_a_row_with_a_bad_cell_is_still_found(tmp_path):
    p = tmp_path / "dup.csv"
    p.write_text(f"{_HEAD}\nB-1,tactical,xyz,,sheet,adev_min\nB-1,tactical,0.1,,sheet,adev_min\n",
                 encoding="utf-8")
    assert [(e.row, e.field) for e in collect_errors(p)] == [(2, "gyro_arw_deg_rt_h"), (3, "part_id")]


# --- 3. ids differing only in case ----------------------------------------------------------------

def _twin_file(tmp_path):
    p = tmp_path / "twins.csv"
    p.write_text("part_id,grade,gyro_arw_deg_rt_h,source\nBMI088,consumer,0.84,sheet\n"
                 "X-2,tactical,0.1,sheet\nbmi088,industrial,0.42,sheet\n", encoding="utf-8")
    return p


def test_ids_differing_only_in_case_are_refused_naming_both_rows(tmp_path):
    p = _twin_file(tmp_path)
    with pytest.raises(InputError) as e:
        read_parts(p)
    assert e.value.row == 4 and e.value.field == "part_id" and e.value.value == "bmi088"
    assert "differs only in case from 'BMI088' (row 2)" in e.value.reason
    assert "rows 2 and 4" in e.value.expected
    with pytest.raises(InputError, match="differs only in case"):
        load_catalog(p)  # what check, mc and the dashboard read
    assert [e.row for e in collect_errors(p)] == [4]


def test_the_reader_refuses_a_case_twin_in_append_parts_words(tmp_path):
    one = tmp_path / "one.csv"
    one.write_text("part_id,grade,gyro_arw_deg_rt_h,source\nBMI088,consumer,0.84,sheet\n", encoding="utf-8")
    with pytest.raises(InputError) as appended:
        append_part(one, {"part_id": "bmi088", "grade": "industrial", "source": "sheet"})
    with pytest.raises(InputError) as read:
        read_parts(_twin_file(tmp_path))
    assert appended.value.reason == "part_id differs only in case from 'BMI088', already in the catalog"
    assert read.value.reason == appended.value.reason.replace("'BMI088'", "'BMI088' (row 2)")


def test_a_large_file_refuses_a_case_twin_at_its_row(tmp_path):
    rows = [f"P{i},tactical,0.1,sheet" for i in range(FAST_PATH_CHARS // 20)]
    rows[-3] = "p7,tactical,0.1,sheet"
    p = tmp_path / "big.csv"
    p.write_text("part_id,grade,gyro_arw_deg_rt_h,source\n" + "\n".join(rows) + "\n", encoding="utf-8")
    assert p.stat().st_size >= FAST_PATH_CHARS
    with pytest.raises(InputError, match=r"differs only in case from 'P7' \(row 9\)") as e:
        validate_parts_table(p)
    assert e.value.row == len(rows) - 3 + 2


# --- 4. an unquoted decimal comma -----------------------------------------------------------------

_ROW_HEAD = ("part_id,vendor,model,grade,rate_hz,gyro_bias_instability_deg_h,gyro_arw_deg_rt_h,"
             "accel_bias_instability_ug,accel_vrw_m_s_rt_h,source")


def test_an_unquoted_decimal_comma_is_named_with_its_cells_and_column(tmp_path):
    p = tmp_path / "comma.csv"
    p.write_text(f"{_ROW_HEAD}\nA-1,Acme,A,consumer,2000,,0.84,,0.103,sheet\n"
                 "A-2,Acme,B,industrial,400,8,0,42,10,0.0353,sheet\n", encoding="utf-8")
    with pytest.raises(InputError) as e:
        read_parts(p)
    err = e.value
    assert err.row == 3 and err.field == "gyro_arw_deg_rt_h" and err.value == "0,42"
    assert "has 11 cells but the header has 10" in err.reason
    assert "cells 7 and 8 ('0' and '42') as 0.42 in gyro_arw_deg_rt_h" in err.reason
    assert "write 0.42 with a decimal point" in err.expected
    # written as it says, the row is read
    p.write_text(p.read_text().replace("8,0,42,10", "8,0.42,10"))
    assert read_parts(p)["A-2"].gyro_arw_deg_rt_h == 0.42


def test_an_extra_text_cell_gets_no_decimal_comma_hint(tmp_path):
    p = tmp_path / "extra.csv"
    p.write_text(f"{_ROW_HEAD}\nA-1,Acme,A,consumer,2000,,0.84,,0.103,sheet,note\n", encoding="utf-8")
    with pytest.raises(InputError) as e:
        read_parts(p)
    assert e.value.reason == "has 11 cells but the header has 10" and e.value.field is None


def test_an_ambiguous_decimal_comma_names_every_fit_and_no_single_column(tmp_path):
    p = tmp_path / "two.csv"
    p.write_text("part_id,grade,source,gyro_arw_deg_rt_h,accel_vrw_m_s_rt_h\nA-1,tactical,x,1,5,2\n",
                 encoding="utf-8")
    with pytest.raises(InputError) as e:
        read_parts(p)
    assert e.value.field is None
    assert "cells 4 and 5 ('1' and '5') as 1.5 in gyro_arw_deg_rt_h" in e.value.reason
    assert "cells 5 and 6 ('5' and '2') as 5.2 in accel_vrw_m_s_rt_h" in e.value.reason
