"""Held-out inputs of a user's own: catalog CSVs as spreadsheets write them (blank rows, a comment
line, a byte-order mark, alternative-unit columns), scenario values written with their unit, a
sonar flown at aircraft speed, and the filled datasheet values a sweep and a report must state.

Every expected number is computed here from its definition, not read from the library.
"""

from __future__ import annotations

import json
import math
import warnings

import pytest

from budget.catalog.io import append_part, read_parts
from budget.catalog.schema import PART_COLUMNS, PartSpec
from budget.catalog.validate import collect_errors
from budget.errors import InputError
from budget.scenario import Scenario

HEADER = ",".join(PART_COLUMNS)
G0 = 9.80665


def _row(part_id: str, arw: str = "0.1", vrw: str = "0.05", rep_g: str = "", rep_a: str = "") -> str:
    """One parts.csv row in the canonical column order."""
    cells = dict.fromkeys(PART_COLUMNS, "")
    cells.update(part_id=part_id, vendor="Me", model="M", grade="tactical", rate_hz="200",
                 gyro_bias_instability_deg_h="1", gyro_bias_repeatability_deg_h=rep_g,
                 gyro_arw_deg_rt_h=arw, gyro_scale_factor_ppm="100", gyro_misalignment_mrad="0.5",
                 accel_bias_instability_ug="50", accel_bias_repeatability_ug=rep_a,
                 accel_vrw_m_s_rt_h=vrw, accel_scale_factor_ppm="300", accel_misalignment_mrad="0.5",
                 source="my datasheet rev A")
    return ",".join(cells[c] for c in PART_COLUMNS)


# --- catalog: units and limits of alternative-unit columns ------------------------------------

def test_an_alternative_unit_column_is_named_with_its_own_unit_and_limit(tmp_path):
    header = HEADER.replace("gyro_arw_deg_rt_h", "gyro_arw_deg_s_rt_hz")
    p = tmp_path / "alt.csv"
    p.write_text(f"{header}\n{_row('U1', arw='50')}\n")  # 50 deg/s/√Hz = 3000 deg/√h > 1000
    with pytest.raises(InputError) as e:
        read_parts(p)
    text = str(e.value)
    assert e.value.row == 2 and e.value.field == "gyro_arw_deg_s_rt_hz"
    # the limit 1000 deg/√h written in the column's unit: 1000 / 60 = 16.67 deg/s/√Hz
    assert f"{1000 / 60:.4g} deg/s/√Hz" in text and "(= 1000 deg/√h)" in text
    assert "in hz" not in text  # formerly the last word of the column name, and the limit in deg/√h

    p.write_text(f"{header}\n{_row('U1', arw='abc')}\n")
    with pytest.raises(InputError, match="a number in deg/s/√Hz"):
        read_parts(p)

    header = HEADER.replace("accel_vrw_m_s_rt_h", "accel_vrw_ug_rt_hz")
    p.write_text(f"{header}\n{_row('U1', vrw='1e6')}\n")
    with pytest.raises(InputError) as e:
        read_parts(p)
    limit_ug = 100 / 60 / (1e-6 * G0)  # 100 m/s/√h in µg/√Hz
    assert f"{limit_ug:.4g} µg/√Hz" in str(e.value) and "(= 100 m/s/√h)" in str(e.value)
    # a value within the limit is read and converted: 50 µg/√Hz → m/s/√h
    p.write_text(f"{header}\n{_row('U1', vrw='50')}\n")
    assert read_parts(p)["U1"].accel_vrw_m_s_rt_h == pytest.approx(50e-6 * G0 * 60, rel=1e-12)


# --- catalog: spreadsheet rows ------------------------------------------------------------------

def test_row_numbers_count_blank_rows_as_a_spreadsheet_does(tmp_path):
    p = tmp_path / "blank.csv"
    empty_row = "," * (len(PART_COLUMNS) - 1)
    lines = [HEADER, "", _row("C1"), "", empty_row, _row("C2", arw="abc")]
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError) as e:
        read_parts(p)
    assert e.value.row == 6 == lines.index(_row("C2", arw="abc")) + 1  # the line a spreadsheet shows
    assert [err.row for err in collect_errors(p)] == [6]
    # a duplicate id is named at its own row too
    p.write_text("\n".join([HEADER, "", _row("C1"), "", _row("C1")]) + "\n")
    with pytest.raises(InputError, match="duplicate part_id") as e:
        read_parts(p)
    assert e.value.row == 5


def test_row_numbers_of_a_large_file_with_a_blank_row(tmp_path):
    """Large files are parsed by pandas' C reader; a blank row must not shift its row numbers."""
    from budget.catalog.validate import FAST_PATH_CHARS

    rows = [_row(f"P{i}") for i in range(14_000)]
    rows[10_000] = _row("P10000", arw="2000")  # above 1000 deg/√h
    lines = [HEADER, ""] + rows
    p = tmp_path / "big.csv"
    p.write_text("\n".join(lines) + "\n")
    assert p.stat().st_size > FAST_PATH_CHARS
    with pytest.raises(InputError) as e:
        read_parts(p)
    assert e.value.row == lines.index(rows[10_000]) + 1 == 10_003
    p.write_text("\n".join([HEADER] + rows) + "\n")  # no blank row: the fast path, same numbering
    with pytest.raises(InputError) as e:
        read_parts(p)
    assert e.value.row == 10_002


def test_a_comment_line_is_named_as_one(tmp_path, capsys):
    from budget.cli.main import main

    p = tmp_path / "c.csv"
    p.write_text(f"{HEADER}\n{_row('C1')}\n# parts added in 2024\n{_row('C2')}\n")
    with pytest.raises(InputError) as e:
        read_parts(p)
    assert e.value.row == 3 and "comment line" in str(e.value) and "notes column" in str(e.value)
    p.write_text(f"# my parts\n{HEADER}\n{_row('C1')}\n")
    with pytest.raises(InputError) as e:
        read_parts(p)
    assert e.value.row == 1 and "comment line" in str(e.value)
    assert main(["catalog", "validate", str(p)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "c.csv, row 1" in err and "comment line" in err
    # the file an append is refused on is left as it was
    before = p.read_bytes()
    with pytest.raises(InputError, match="comment line"):
        append_part(p, PartSpec(part_id="NEW", grade="tactical", source="s"))
    assert p.read_bytes() == before


def test_append_keeps_the_byte_order_mark_and_line_endings(tmp_path):
    p = tmp_path / "excel.csv"
    original = ("\ufeff" + HEADER + "\r\n" + _row("B1") + "\r\n").encode("utf-8")
    p.write_bytes(original)
    append_part(p, PartSpec(part_id="NEW1", grade="tactical", source="s", gyro_arw_deg_rt_h=0.15))
    data = p.read_bytes()
    assert data.startswith(original)  # the user's bytes, BOM included, then one CRLF line
    assert data[len(original):].endswith(b"\r\n") and data.count(b"\r\n") == 3
    append_part(p, PartSpec(part_id="B1", grade="tactical", source="s2", gyro_arw_deg_rt_h=0.2),
                replace=True)
    data = p.read_bytes()
    assert data.startswith(b"\xef\xbb\xbf" + HEADER.encode() + b"\r\n")
    parts = read_parts(p)
    assert list(parts) == ["B1", "NEW1"] and parts["B1"].gyro_arw_deg_rt_h == 0.2


# --- scenario values -----------------------------------------------------------------------------

def _scenario(**changes) -> dict:
    data = {"name": "ku uav", "carrier_frequency_hz": 16.7e9, "slant_range_m": 3000,
            "azimuth_resolution_m": 0.3, "range_resolution_m": 0.3, "platform_speed_m_s": 40}
    data.update(changes)
    return data


@pytest.mark.parametrize("key, text, number", [
    ("carrier_frequency_hz", "16.7 GHz", 16.7e9),
    ("platform_speed_m_s", "90 km/h", 90 / 3.6),
    ("platform_speed_m_s", "97 kn", 97 * 1852 / 3600),
    ("slant_range_m", "3 km", 3000.0),
    ("depression_deg", "0.35 rad", math.degrees(0.35)),
])
def test_a_value_written_with_its_unit_says_which_number_to_write(tmp_path, key, text, number):
    p = tmp_path / "s.yaml"
    p.write_text("\n".join(f"{k}: {v}" for k, v in _scenario(**{key: text}).items()) + "\n")
    with pytest.raises(InputError) as e:
        Scenario.load(p)
    msg = str(e.value)
    assert e.value.field == key and str(p) in msg and "unit is in the key's name" in msg
    assert f"{number:.6g} for {text}" in msg


def test_several_values_with_units_are_each_named():
    with pytest.raises(InputError) as e:
        Scenario.from_dict(_scenario(slant_range_m="3 km", azimuth_resolution_m="30 cm",
                                     lever_arm_m=["0.5 m", 0, 0]))
    msg = str(e.value)
    assert "3000 for 3 km" in msg and "0.3 for 30 cm" in msg and "0.5 for 0.5 m" in msg
    assert "field azimuth_resolution_m" in msg and "field lever_arm_m.0" in msg


@pytest.mark.parametrize("text, words", [("50 Hz", "'Hz' is not a unit of m/s"),
                                         ("1,000", "a plain number in m/s"),
                                         ("fifty", "a plain number in m/s")])
def test_text_that_is_no_speed_says_the_keys_unit(text, words):
    with pytest.raises(InputError, match=words) as e:
        Scenario.from_dict(_scenario(platform_speed_m_s=text))
    assert e.value.field == "platform_speed_m_s"


def test_numbers_as_plain_strings_still_read():
    s = Scenario.from_dict(_scenario(slant_range_m="3000", platform_speed_m_s=" 4.0E+1 "))
    lam = 299_792_458.0 / 16.7e9
    assert s.tc_s == pytest.approx(lam * 3000 / (2 * 0.3 * 40), rel=1e-12)


# --- a sonar flown at aircraft speed ------------------------------------------------------------

def test_a_sonar_crossing_its_aperture_while_a_ping_travels_is_warned(capsys, tmp_path):
    data = {"name": "fast sonar", "medium": "sonar", "carrier_frequency_hz": 100e3,
            "slant_range_m": 100.0, "azimuth_resolution_m": 0.05, "range_resolution_m": 0.05,
            "platform_speed_m_s": 200.0}
    lam = 1500.0 / 100e3
    tc = lam * 100.0 / (2 * 0.05 * 200.0)          # 0.075 s
    delay = 2 * 100.0 / 1500.0                       # 0.133 s > Tc
    v_max = lam * 1500.0 / (4 * 0.05)                # Tc = 2R/c at this speed: 112.5 m/s
    with pytest.warns(UserWarning) as w:
        s = Scenario.from_dict(data)
    text = str(w[0].message)
    assert s.tc_s == pytest.approx(tc)
    assert f"2R/c = {delay:.3g} s" in text and f"Tc = {tc:.3g} s" in text
    assert f"< {v_max:.3g} m/s" in text and "stop-and-go" in text
    assert s.notes() == [text]  # what a page lists beside its results, from the scenario itself
    with warnings.catch_warnings():  # the presets and a sonar below that speed are quiet
        warnings.simplefilter("error")
        Scenario.from_dict({**data, "platform_speed_m_s": 2.0})
        from budget.presets import PRESETS
        assert all(p.tc_s > 2 * p.slant_range_m / p.c_m_s and p.notes() == [] for p in PRESETS.values())
    from budget.cli.main import main
    f = tmp_path / "fast.json"
    f.write_text(json.dumps(data))
    assert main(["scenario", "show", "--scenario", str(f)]) == 0
    err = capsys.readouterr().err.strip()
    assert err.startswith("sar-budget scenario: warning: fast sonar: the echo delay") and "\n" not in err


# --- filled datasheet values stated where P(pass) is shown --------------------------------------

def _typical(grade: str, lo_col: str, hi_col: str) -> float:
    """The grade's typical value from the shipped grades.csv: geometric mean of its range."""
    import csv

    from budget.catalog.io import shipped_catalog_dir
    with open(shipped_catalog_dir() / "grades.csv", newline="", encoding="utf-8") as fh:
        row = next(r for r in csv.DictReader(fh) if r["grade"] == grade)
    return math.sqrt(float(row[lo_col]) * float(row[hi_col]))


def test_a_sweep_row_states_the_values_it_filled(tmp_path):
    from budget.mc.sweep import sweep
    from budget.presets import get_preset

    part = read_parts(_user_catalog(tmp_path))["MINE"]  # repeatabilities and RRW left empty
    table = sweep([part], [get_preset("automotive_24ghz")], 2, 1)
    text = table.loc[0, "unspecified_terms"]
    g = _typical("tactical", "gyro_bias_deg_h_min", "gyro_bias_deg_h_max")
    a = _typical("tactical", "accel_bias_ug_min", "accel_bias_ug_max")
    assert f"gyro_bias_repeatability_deg_h = {g:.4g} deg/h" in text
    assert f"accel_bias_repeatability_ug = {a:.4g} µg" in text
    assert "simulated as 0: gyro_rrw_deg_h_rt_h" in text


def _user_catalog(tmp_path):
    p = tmp_path / "mine.csv"
    p.write_text(f"{HEADER}\n{_row('MINE')}\n")
    return p


def test_the_report_states_the_values_the_monte_carlo_filled(tmp_path):
    from budget.cli.main import main

    out = tmp_path / "r.html"
    assert main(["report", "--preset", "automotive_24ghz", "--catalog", str(_user_catalog(tmp_path)),
                 "--part", "MINE", "--mc-part", "MINE", "--trials", "2", "--out", str(out),
                 "--quiet"]) == 0
    text = out.read_text()
    g = _typical("tactical", "gyro_bias_deg_h_min", "gyro_bias_deg_h_max")
    assert "data-key='unspecified'><small><b>MINE</b>: unspecified datasheet terms" in text
    assert f"gyro_bias_repeatability_deg_h = {g:.4g} deg/h" in text
    assert "data-key='imu_rate'><small><b>MINE</b>: IMU simulated at the scenario" in text


def test_a_part_whose_figures_contradict_its_grade_is_noted_where_fills_are_stated():
    """HG9900's figures labelled consumer: the consumer grade's fills (10 mrad misalignment …)
    would then be simulated for a navigation-grade sensor. The resolution, and the Monte Carlo
    summary that states the fills, say so; no shipped part (whose figures sit within a rank of
    their grade in the coarse seed 004 tables) gets the note. A figure written as 0 is named."""
    from budget.catalog.fill import resolve_unspecified
    from budget.catalog.io import get_part, load_catalog
    from budget.mc import run_mc
    from budget.presets import get_preset
    odd = get_part("HG9900").model_copy(update={"grade": "consumer", "part_id": "NAV-AS-CONSUMER"})
    notes = list(resolve_unspecified(odd).warnings)
    mismatch = [n for n in notes if "navigation-grade part" in n]
    assert len(mismatch) == 1 and "gyro_arw_deg_rt_h = 0.002 deg/√h (navigation)" in mismatch[0]
    # the other note names the single figures that lie > 100× beyond the consumer row's best
    assert [n for n in notes if n not in mismatch] == [n for n in notes if "often typed in another unit" in n]
    assert mismatch[0] in run_mc(get_preset("automotive_24ghz"), odd, 2, 1).summary()
    assert not [pid for pid, p in load_catalog().items() if resolve_unspecified(p).warnings]
    zero = get_part("STIM300").model_copy(update={"gyro_arw_deg_rt_h": 0.0})
    assert any(n.startswith("given as 0") and "gyro_arw_deg_rt_h" in n
               for n in resolve_unspecified(zero).warnings)
