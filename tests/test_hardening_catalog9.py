"""User catalog edits and a trade study on parts added from datasheets: units as the datasheets
print them (ft/s/√h, mg/√Hz, deg/h/√Hz beside the older alternative columns), the check's
verdict on such a part against seed 004's bound computed here, where a result says its catalog
came from, a read-only catalog left alone, spreadsheet-exported cells named with what to write,
and written alternative-unit cells without float noise.

Expected values are computed here from the identities (1 ft = 0.3048 m, g = 9.80665 m/s²,
1 deg/√h = 1/60 deg/s/√Hz, 1 m/s/√h = 1/60 m/s²/√Hz) and seed 004 (5)–(6), not read from the code.
"""

from __future__ import annotations

import json
import math
import os

import pandas as pd
import pytest

from budget.catalog.io import append_part, load_catalog, read_parts, write_parts
from budget.catalog.schema import PartSpec
from budget.check import check_parts
from budget.cli.common import check_output_path
from budget.cli.main import main
from budget.errors import InputError, OutputError
from budget.presets import get_preset

G = 9.80665
DEG = math.pi / 180.0


def _csv(tmp_path, text: str, name: str = "mine.csv"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


# datasheet figure as printed → (header, cell, SI attribute of to_si(), expected SI value)
DATASHEET_UNITS = [
    # Honeywell HG1700: VRW 0.065 ft/s/√h (the README's 3.302e-4 m/s^1.5)
    ("accel_vrw_ft_s_rt_h", "0.065", "accel_vrw_m_s2_rt_hz", 0.065 * 0.3048 / 60.0),
    # VectorNav VN-100/VN-200: accel noise density 0.14 mg/√Hz
    ("accel_vrw_mg_rt_hz", "0.14", "accel_vrw_m_s2_rt_hz", 0.14e-3 * G),
    # KVH 1750: ARW 0.7 deg/h/√Hz (≈ 0.012 deg/√h)
    ("gyro_arw_deg_h_rt_hz", "0.7", "gyro_arw_rad_s_rt_hz", 0.7 / 3600.0 * DEG),
    # Xsens MTi-630: gyro noise density 0.007 deg/s/√Hz, accel 60 µg/√Hz, in-run bias 10 µg = 0.01 mg
    ("gyro_arw_deg_s_rt_hz", "0.007", "gyro_arw_rad_s_rt_hz", 0.007 * DEG),
    ("accel_vrw_ug_rt_hz", "60", "accel_vrw_m_s2_rt_hz", 60e-6 * G),
    ("accel_bias_instability_mg", "0.01", "accel_bias_instability_adev_m_s2", 10e-6 * G),
    # Bosch BMI088: gyro sensitivity tolerance 1 %
    ("gyro_scale_factor_pct", "1", "gyro_scale_factor", 0.01),
]


@pytest.mark.parametrize("column, cell, attr, si", DATASHEET_UNITS)
def test_datasheet_units_convert_to_si(tmp_path, column, cell, attr, si):
    p = _csv(tmp_path, f"part_id,grade,source,{column}\nP1,tactical,datasheet,{cell}\n")
    got = getattr(read_parts(p)["P1"].to_si(), attr)
    assert got == pytest.approx(si, rel=1e-12)


def test_one_vrw_column_per_file(tmp_path):
    p = _csv(tmp_path, "part_id,grade,source,accel_vrw_ft_s_rt_h,accel_vrw_mg_rt_hz\nP1,tactical,ds,0.065,\n")
    with pytest.raises(InputError, match="gives accel_vrw_m_s_rt_h twice") as e:
        read_parts(p)
    assert e.value.row == 1 and e.value.field == "accel_vrw_mg_rt_hz"


def test_bmi088_fails_the_gyro_scale_factor_bound_by_the_papers_numbers(tmp_path):
    # airborne_xband: λ = c/9.6 GHz, R = 5 km, δℓ = δr = 0.5 m, V = 50 m/s, broadside, a_w = 1
    lam = 299_792_458.0 / 9.6e9
    tc = lam * 5000.0 / (2 * 0.5 * 50.0)                     # seed 004 (5): 3.1228 s
    gamma_max = 0.1 * 0.5 / tc ** 2                          # seed 004 (6) as printed: 5127 ppm
    p = _csv(tmp_path, "part_id,grade,source,gyro_scale_factor_pct,gyro_arw_deg_s_rt_hz\n"
                       "BMI088,consumer,Bosch BMI088 datasheet,1,0.014\n")
    part = read_parts(p)["BMI088"]
    res = check_parts([part], get_preset("airborne_xband"))
    rec = res.to_dict()["scenarios"][0]["parts"][0]
    assert rec["margins"]["gyro_scale_factor_ppm"] == pytest.approx(gamma_max / 0.01, rel=1e-9)
    assert rec["verdict"] == "fail" and rec["binding"] == "gyro_scale_factor_ppm"


def test_check_frame_has_no_binding_term_where_nothing_is_specified():
    # ADIS16375's shipped row has every error column empty: verdict unknown, nothing binds
    res = check_parts([read_parts_shipped("ADIS16375"), read_parts_shipped("STIM300")],
                      get_preset("airborne_xband"))
    frame = res.to_frame().set_index("part_id")
    records = {r["part_id"]: r for r in res.to_dict()["scenarios"][0]["parts"]}
    assert frame.loc["ADIS16375", "verdict"] == "unknown"
    assert pd.isna(frame.loc["ADIS16375", "binding"]) and records["ADIS16375"]["binding"] is None
    assert frame.loc["STIM300", "binding"] == records["STIM300"]["binding"] == "accel_bias_instability_ug"


def read_parts_shipped(part_id: str) -> PartSpec:
    return load_catalog()[part_id]


def test_check_json_names_the_catalog_from_the_environment(tmp_path, monkeypatch, capsys):
    p = _csv(tmp_path, "part_id,grade,source,gyro_arw_deg_rt_h\nMTi-630,industrial,Xsens datasheet,0.42\n")
    monkeypatch.setenv("SAR_BUDGET_CATALOG", str(p))
    assert main(["check", "--preset", "airborne_xband", "--part", "MTi-630", "--json", "-"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["catalog"] == str(p)  # was "shipped", though MTi-630 is the user's part
    assert [r["part_id"] for r in out["parts"]] == ["MTi-630"]
    monkeypatch.delenv("SAR_BUDGET_CATALOG")
    assert main(["check", "--preset", "airborne_xband", "--part", "STIM300", "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out)["catalog"] == "shipped"


NEW = PartSpec(part_id="LN-200", grade="tactical", gyro_bias_instability_deg_h=1.0, gyro_arw_deg_rt_h=0.07,
               accel_bias_instability_ug=300.0, accel_vrw_m_s_rt_h=50e-6 * G * 60.0,
               source="Northrop Grumman LN-200 datasheet", bias_instability_convention="turn_on_1sigma")


def test_a_read_only_catalog_is_not_replaced(tmp_path):
    p = _csv(tmp_path, "part_id,grade,source\nP1,tactical,ds\n", "team.csv")
    os.chmod(p, 0o444)
    before = p.read_bytes()
    for write in (lambda: append_part(p, NEW), lambda: write_parts(p, [NEW])):
        with pytest.raises(OutputError, match="read-only") as e:
            write()
        assert e.value.file == str(p)
    assert p.read_bytes() == before and oct(p.stat().st_mode & 0o777) == oct(0o444)
    assert [f.name for f in tmp_path.iterdir()] == ["team.csv"]  # no temporary file left
    with pytest.raises(OutputError, match="read-only"):  # the CLI's check before computing
        check_output_path(p, "--append", must_exist_dir=True)
    os.chmod(p, 0o644)
    append_part(p, NEW)
    assert list(read_parts(p)) == ["P1", "LN-200"]


def test_appended_alternative_unit_cells_are_written_without_float_noise(tmp_path):
    p = _csv(tmp_path, "part_id,grade,source,accel_vrw_ug_rt_hz,gyro_arw_deg_s_rt_hz\nP1,tactical,ds,25,0.002\n")
    append_part(p, NEW)
    last = p.read_text().splitlines()[-1].split(",")
    assert last[3] == "50.0"                                 # 50 µg/√Hz, not 50.00000000000001
    back = read_parts(p)["LN-200"]
    assert back.accel_vrw_m_s_rt_h == NEW.accel_vrw_m_s_rt_h  # exact round trip
    assert back.gyro_arw_deg_rt_h == NEW.gyro_arw_deg_rt_h    # 0.07/60 needs 17 digits: kept


@pytest.mark.parametrize("cell, written", [("0,4", "0.4"), ("1,000", "1.000")])
def test_a_decimal_comma_is_named_with_what_to_write(tmp_path, cell, written):
    p = _csv(tmp_path, f'part_id,grade,source,gyro_arw_deg_rt_h\nP1,tactical,ds,"{cell}"\n')
    with pytest.raises(InputError, match="decimal comma") as e:
        read_parts(p)
    assert (e.value.row, e.value.field, e.value.value) == (2, "gyro_arw_deg_rt_h", cell)
    assert f"e.g. {written}" in e.value.expected and "deg/√h" in e.value.expected


def test_spreadsheet_trailing_empty_columns_are_named(tmp_path):
    p = _csv(tmp_path, "part_id,grade,source,gyro_arw_deg_rt_h,,\nP1,tactical,ds,0.4,,\n")
    with pytest.raises(InputError, match=r"column 5 of 6") as e:
        read_parts(p)
    assert e.value.row == 1 and "delete them" in e.value.expected


def test_semicolon_export_names_delimiter_and_decimal_point(tmp_path):
    p = tmp_path / "excel.csv"
    p.write_bytes(b"\xef\xbb\xbfpart_id;grade;source;gyro_arw_deg_rt_h\r\nP1;tactical;ds;0,4\r\n")
    with pytest.raises(InputError, match="';' as its delimiter") as e:
        read_parts(p)
    assert e.value.row == 1 and "decimal points" in e.value.expected
