"""Bad input, round 4: cases a new user's session with odd scenarios and huge runs found.

Each test names the input and asserts the words of the one-line error (field, what was
expected), not only that something was raised.
"""

from __future__ import annotations

import numpy as np
import pytest

import budget
from budget.cli.main import main
from budget.errors import InputError
from budget.mc.runner import MAX_TRIALS


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert err and "Traceback" not in "\n".join(err)
    return err[-1]


# --- a trial count no run can finish ----------------------------------------------------------

def test_run_mc_and_sweep_refuse_more_trials_than_one_run_takes_before_starting():
    # 10¹² trials built a task list of 1.6·10¹⁰ entries and filled 22 GB before the first trial
    with pytest.raises(InputError) as e:
        budget.run_mc("automotive_24ghz", "STIM300", trials=10 ** 12)
    assert e.value.field == "trials" and f"1 … {MAX_TRIALS:,}" in str(e.value)
    assert "1000000000000" in str(e.value)
    with pytest.raises(InputError) as e:
        budget.sweep(["STIM300"], "automotive_24ghz", trials=MAX_TRIALS + 1)
    assert e.value.field == "trials"


def test_cli_mc_with_a_huge_trial_count_exits_2(capsys):
    assert main(["mc", "--preset", "automotive_24ghz", "--part", "STIM300", "--trials", str(10 ** 12),
                 "-q"]) == 2
    line = _one_line(capsys)
    assert "trials" in line and f"expected 1 … {MAX_TRIALS:,}" in line and "other seeds" in line


# --- sar-budget motion: empty datasheet terms and defaults stated -----------------------------

def test_cli_motion_fills_empty_terms_as_mc_does_and_says_so(tmp_path, capsys):
    # HG9900's catalog row leaves the VRW empty. `motion` ran it as 0 — 55× quieter than `mc`,
    # which fills the navigation grade's typical VRW — and said nothing.
    import json
    from budget.catalog.fill import resolve_unspecified
    from budget.catalog.io import load_catalog
    from budget.motion import simulate_motion
    from budget.presets import PRESETS

    part = load_catalog()["HG9900"]
    assert part.accel_vrw_m_s_rt_h is None
    out = tmp_path / "m.json"
    assert main(["motion", "--preset", "automotive_24ghz", "--part", "HG9900", "--trials", "8",
                 "-q", "--json", str(out)]) == 0
    cli = json.loads(out.read_text())
    filled = resolve_unspecified(part, "fill_grade_typical")
    assert "accel_vrw_m_s_rt_h" in [f.column for f in filled.filled]
    assert "accel_vrw_m_s_rt_h" in cli["notes"]["unspecified"] and "filled" in cli["notes"]["unspecified"]
    # the same numbers as the engine given the filled row at the same (mc's) default seed
    ref = simulate_motion(PRESETS["automotive_24ghz"], filled.model, 8, 1, keep_series=False)
    assert cli["seed"] == 1
    assert cli["residual_rms_deg"] == pytest.approx(ref.residual_rms_deg[:, 0].tolist(), rel=1e-12)
    # the engine's own default is the terms given, and it says which it took as 0
    bare = simulate_motion(PRESETS["automotive_24ghz"], part, 8, 1, keep_series=False)
    assert "taken as 0" in bare.notes["unspecified"] and "accel_vrw_m_s_rt_h" in bare.notes["unspecified"]
    assert np.median(bare.residual_rms_deg[:, 0]) < np.median(ref.residual_rms_deg[:, 0])
    # the text states the defaults a user did not set
    assert main(["motion", "--preset", "automotive_24ghz", "--part", "HG9900", "--trials", "2", "-q"]) == 0
    text = capsys.readouterr().out
    for words in ("lever arm IMU → antenna", "imu_rate_hz", "straight, level", "unspecified datasheet terms"):
        assert words in text, words


def test_cli_motion_refuses_empty_terms_when_asked(capsys):
    assert main(["motion", "--preset", "automotive_24ghz", "--part", "HG9900", "--trials", "2", "-q",
                 "--unspecified", "refuse"]) == 2
    line = _one_line(capsys)
    assert "accel_vrw_m_s_rt_h" in line and "unspecified" in line


# --- an Allan table of one row -----------------------------------------------------------------

def test_gap_names_a_one_row_allan_table_for_what_it_is(tmp_path, capsys):
    # it read "log too short … (got 1000000); expected at least 9071 samples": the τ-range check
    # ran before the table's own count of τ
    table = tmp_path / "one.csv"
    table.write_text("channel,tau_s,adev\ngyro_x_dps,0.02,0.257\n")
    assert main(["gap", str(table), "--rate-hz", "100", "--samples", "1000000", "--part", "ADIS16405",
                 "--report", str(tmp_path / "r.json"), "-q"]) == 2
    line = _one_line(capsys)
    assert "one.csv" in line and "gyro_x" in line and "1 τ" in line and "at least 6 τ" in line


# --- an output that is an input, another output, or the shipped catalog -----------------------

def test_an_output_that_is_an_input_file_is_refused_and_the_input_kept(tmp_path, capsys):
    # check --catalog mine.csv --json mine.csv exited 0 with the catalog replaced by JSON
    from budget.catalog.io import shipped_catalog_dir

    mine = tmp_path / "mine.csv"
    shipped = shipped_catalog_dir() / "parts.csv"
    mine.write_bytes(shipped.read_bytes())
    before = mine.read_bytes()
    assert main(["check", "--preset", "airborne_xband", "--catalog", str(mine), "--json", str(mine)]) == 1
    line = _one_line(capsys)
    assert "--json" in line and "mine.csv" in line and "is also the input --catalog" in line
    assert mine.read_bytes() == before
    scen = tmp_path / "s.json"
    assert main(["scenario", "write", "--preset", "airborne_xband", str(scen)]) == 0
    kept = scen.read_bytes()
    assert main(["bounds", "--scenario", str(scen), "--json", str(scen)]) == 1
    assert "is also the input --scenario" in _one_line(capsys) and scen.read_bytes() == kept


def test_two_outputs_on_one_file_and_the_shipped_catalog_are_refused(tmp_path, capsys):
    from budget.catalog.io import shipped_catalog_dir

    same = tmp_path / "same.html"
    assert main(["report", "--preset", "airborne_xband", "-q", "--out", str(same), "--json", str(same)]) == 1
    assert "one would overwrite the other" in _one_line(capsys) and not same.exists()
    shipped = shipped_catalog_dir() / "parts.csv"
    before = shipped.read_bytes()
    assert main(["check", "--preset", "airborne_xband", "--json", str(shipped)]) == 1
    assert "shipped catalog" in _one_line(capsys) and shipped.read_bytes() == before


# --- a scenario name that would act on the terminal ------------------------------------------

def test_a_scenario_name_with_control_characters_or_blank_is_refused(tmp_path, capsys):
    # scenario write --name $'\x1b[31mX' was accepted, and show, bounds and check printed the
    # escape raw; --name "" was silently ignored
    for name in ("\x1b[31mX", "two\nlines", ""):
        assert main(["scenario", "write", "--preset", "sas_100khz", "--name", name, str(tmp_path / "e.json")]) == 2
        line = _one_line(capsys)
        assert "field name" in line and "\x1b" not in line
        assert not (tmp_path / "e.json").exists()
    from budget.scenario import Scenario
    with pytest.raises(InputError) as e:
        Scenario.from_dict({"name": "a\x07b", "carrier_frequency_hz": 1e10, "slant_range_m": 1e3,
                            "azimuth_resolution_m": 1.0, "range_resolution_m": 1.0, "platform_speed_m_s": 50.0})
    assert e.value.field == "name" and "control characters" in str(e.value)


# --- numbers read as other numbers -------------------------------------------------------------

@pytest.mark.parametrize("cell,why", [("1_0", "an underscore"), ("1e-400", "it underflows to 0")])
def test_a_catalog_cell_python_reads_as_another_number_is_refused(tmp_path, capsys, cell, why):
    # float() reads 1_0 as 10 and 1e-400 as 0.0 (a "perfect" term): both validated
    from budget.catalog.io import shipped_catalog_dir

    lines = (shipped_catalog_dir() / "parts.csv").read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    row = next(r for r in lines[1:] if r.startswith("STIM300,")).split(",")
    row[0] = "MYSTIM"
    row[header.index("gyro_arw_deg_rt_h")] = cell
    path = tmp_path / "mine.csv"
    path.write_text(lines[0] + "\n" + ",".join(row) + "\n", encoding="utf-8")
    assert main(["catalog", "validate", str(path)]) == 2
    line = _one_line(capsys)
    assert "row 2" in line and "gyro_arw_deg_rt_h" in line and why in line and cell in line


@pytest.mark.parametrize("value", ["1:40", "0x64", "1_000", "012"])
def test_a_yaml_number_yaml_1_1_reads_as_another_value_is_refused(tmp_path, capsys, value):
    # YAML 1.1 reads 1:40 as 100 (base 60), 0x64 as 100, 1_000 as 1000 and 012 as 10
    path = tmp_path / "s.yaml"
    assert main(["scenario", "write", "--preset", "airborne_xband", str(path)]) == 0
    text = path.read_text(encoding="utf-8")
    lines = [f"slant_range_m: {value}" if ln.startswith("slant_range_m:") else ln for ln in text.splitlines()]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    capsys.readouterr()
    assert main(["scenario", "validate", str(path)]) == 2
    line = _one_line(capsys)
    assert "s.yaml" in line and value in line and "plain decimal number" in line
    assert f"line {lines.index(f'slant_range_m: {value}') + 1}" in line


# --- a row's own warnings in the part check ----------------------------------------------------

def test_check_states_a_term_given_as_zero(tmp_path, capsys):
    # STIM300's row with gyro_arw_deg_rt_h = 0 passed 8/8 with no word that the ARW is "perfect"
    import json
    from budget.catalog.io import shipped_catalog_dir

    lines = (shipped_catalog_dir() / "parts.csv").read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    row = next(r for r in lines[1:] if r.startswith("STIM300,")).split(",")
    row[0] = "MYSTIM"
    row[header.index("gyro_arw_deg_rt_h")] = "0"
    path = tmp_path / "mine.csv"
    path.write_text(lines[0] + "\n" + ",".join(row) + "\n", encoding="utf-8")
    assert main(["check", "--preset", "airborne_xband", "--catalog", str(path), "--part", "MYSTIM"]) == 0
    text = capsys.readouterr().out
    assert "row note, MYSTIM: given as 0" in text and "gyro_arw_deg_rt_h" in text
    out = tmp_path / "c.json"
    assert main(["check", "--preset", "airborne_xband", "--catalog", str(path), "--part", "MYSTIM",
                 "--json", str(out)]) == 0
    rec = json.loads(out.read_text())["parts"][0]
    assert rec["part_id"] == "MYSTIM" and any("gyro_arw_deg_rt_h" in n for n in rec["row_notes"])
    # the shipped STIM300 has no such note
    assert main(["check", "--preset", "airborne_xband", "--part", "STIM300"]) == 0
    assert "row note" not in capsys.readouterr().out


# --- an aperture of few IMU samples --------------------------------------------------------------

def test_an_aperture_of_few_imu_samples_says_its_fast_phase_is_low():
    # missile-like Tc = 0.043 s at 400 Hz: 18 samples; the analytic note read "0.000 of apertures
    # … the most the fast phase lets pass" beside a simulated P(pass) of 0.44: the sampled error
    # carries about half the continuous-time phase beyond PGA's window (measured on the missile
    # case, ADIS16405, 32 trials: rms 0.82° at 200 Hz against 1.67° at 2 kHz, analytic 1.87°).
    from budget.mc.notes import fast_phase_note
    from budget.mc.options import McOptions
    from budget.motion.notes import FEW_SAMPLES, imu_rate_note
    from budget.presets import PRESETS

    short = PRESETS["airborne_xband"].model_copy(update={"imu_rate_hz": 5.0})  # Tc 3.12 s: 17 samples
    assert "only 17 IMU samples span the aperture" in imu_rate_note(short, None)
    assert "raise imu_rate_hz" in imu_rate_note(short, None)
    assert "IMU samples" not in imu_rate_note(PRESETS["airborne_xband"], None)  # 626 samples
    assert FEW_SAMPLES <= 626
    model = budget.load_part("ADIS16405")
    assert "the simulation's 17 IMU samples" in fast_phase_note(short, McOptions(), model)
    assert "IMU samples" not in fast_phase_note(PRESETS["airborne_xband"], McOptions(), model)


# --- a user catalog too large to check ----------------------------------------------------------

def test_check_refuses_more_parts_than_it_can_check_in_reasonable_time(monkeypatch):
    # a valid 200,000-row user catalog ran `check` for hours (≈ 0.13 s per part) with nothing said
    import budget.check as check
    from budget.catalog.io import load_catalog
    from budget.presets import PRESETS

    monkeypatch.setattr(check, "MAX_CHECKS", 10)
    base = load_catalog()["STIM300"]
    parts = [base.model_copy(update={"part_id": f"P{i}"}) for i in range(11)]
    with pytest.raises(InputError) as e:
        check.check_parts(parts, [PRESETS["airborne_xband"]])
    assert e.value.field == "parts" and "11 parts × 1 scenario" in str(e.value) and "--part" in str(e.value)
    assert check.check_parts(parts[:10], [PRESETS["automotive_77ghz"]]).part_ids[-1] == "P9"


def test_a_yaml_syntax_error_names_its_line_and_column(tmp_path, capsys):
    # it named the construct only ("while scanning for the next token")
    path = tmp_path / "t.yaml"
    path.write_text("name: x\n\tcarrier_frequency_hz: 1e10\n", encoding="utf-8")
    assert main(["scenario", "validate", str(path)]) == 2
    line = _one_line(capsys)
    assert "t.yaml" in line and "line 2, column 1" in line and "'\\t'" in line


def test_catalog_validate_reads_the_grades_table_as_one(tmp_path, capsys):
    # it read grades.csv as a parts file: "field rank: unknown column"
    from budget.catalog.io import shipped_catalog_dir

    grades = shipped_catalog_dir() / "grades.csv"
    assert main(["catalog", "validate", str(grades)]) == 0
    from budget.catalog.io import load_grades
    assert f"grades table, {len(load_grades())} grades valid" in capsys.readouterr().out
    lines = grades.read_text(encoding="utf-8").splitlines()
    cells = lines[2].split(",")
    cells[1] = "x"  # the rank of the second grade
    bad = tmp_path / "g.csv"
    bad.write_text("\n".join([lines[0], lines[1], ",".join(cells), *lines[3:]]) + "\n", encoding="utf-8")
    assert main(["catalog", "validate", str(bad)]) == 2
    line = _one_line(capsys)
    assert "g.csv" in line and "row 3" in line and "field rank" in line


def test_focus_refuses_an_image_name_that_is_not_png(tmp_path, capsys):
    # --image out.txt wrote a PNG into a .txt file; refused before the phase history is read
    assert main(["focus", str(tmp_path / "missing.mat"), "--image", str(tmp_path / "out.txt")]) == 2
    line = _one_line(capsys)
    assert "--image" in line and "out.txt" in line and ".png" in line
    assert not (tmp_path / "out.txt").exists()


# --- a Taylor window out of its range ----------------------------------------------------------

def test_a_taylor_window_out_of_range_says_which_number_is_wrong():
    # taylor-10-4 read "unknown window": its sidelobe level must be ≤ −13.5 dB
    from budget.sar.windows import Window
    with pytest.raises(InputError) as e:
        Window.parse("taylor-10-4")
    assert e.value.field == "window" and "sidelobe_db is out of range" in str(e.value)
    assert "13.5–80 dB" in str(e.value)
    with pytest.raises(InputError) as e:
        Window.parse("taylor-35-20")
    assert "nbar is out of range" in str(e.value)
    with pytest.raises(InputError) as e:
        Window.parse("hann")
    assert "unknown window" in str(e.value)
