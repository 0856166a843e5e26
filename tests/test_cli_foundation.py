"""CLI contract of the foundation: bounds, check, catalog; bad input → one line, exit 2."""

import json
import subprocess
import sys

import pytest

from budget.cli.main import main
from budget.presets import get_preset

KEYS = {"tc_s", "accel_scale_factor_ppm", "gyro_scale_factor_ppm", "misalignment_mrad",
        "accel_bias_ug", "gyro_bias_deg_h", "accel_vrw_ug_rt_hz", "gyro_arw_deg_rt_h"}


def run_json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_bounds_tc_json(capsys):
    """The JSON carries what the bounds were computed with (mode, Tc, δr, λ) beside the rows."""
    out = run_json(capsys, ["bounds", "--tc", "1", "10", "25", "50", "100", "--range-resolution", "0.1",
                            "--json", "-"])
    rows = out["bounds"]["rows"]
    assert out["mode"] == "paper" and out["tc_s"] == [1, 10, 25, 50, 100] and out["range_resolution_m"] == 0.1
    assert out["scenario"] is None and out["wavelength_m"] is None and out["fast_phase"] is None
    assert [r["tc_s"] for r in rows] == [1, 10, 25, 50, 100]
    assert set(rows[0]) == KEYS
    assert rows[0]["accel_bias_ug"] == pytest.approx(14000) and rows[4]["gyro_arw_deg_rt_h"] == pytest.approx(7.84e-4)


@pytest.mark.parametrize("mode", ["paper", "derived", "no-autofocus"])
def test_bounds_scenario_json(tmp_path, capsys, mode):
    s = get_preset("automotive_77ghz")
    path = tmp_path / "s.json"
    s.save(path)
    out = run_json(capsys, ["bounds", "--scenario", str(path), "--mode", mode, "--json", "-"])
    rows = out["bounds"]["rows"]
    assert len(rows) == 1 and rows[0]["tc_s"] == pytest.approx(s.tc_s) and set(rows[0]) == KEYS
    assert out["mode"] == mode and out["scenario"]["name"] == s.name
    assert out["fast_phase"]["rows"][0]["tc_s"] == pytest.approx(s.tc_s)


def test_bounds_with_a_scenario_refuse_options_it_would_ignore(capsys):
    for option in (["--range-resolution", "0.1"], ["--wavelength", "5"]):
        assert main(["bounds", "--preset", "airborne_xband", *option]) == 2
        assert "is used only with --tc" in capsys.readouterr().err


def test_bounds_print_the_fast_phase_vrw_arw_limits_at_the_scenario_tc(capsys):
    """The fast-phase limits at the scenario's Tc, in datasheet units (README: ≈ 0.097 m/s/√h and
    ≈ 4.09 deg/√h on airborne X band, unweighted, K = 2, 0.9 of apertures within 1°; the Taylor
    window the verdict images with weights the aperture's ends less and allows a little more)."""
    assert main(["bounds", "--preset", "airborne_xband"]) == 0
    line = [ln for ln in capsys.readouterr().out.splitlines() if ln.strip().startswith("Tc =")][0]
    vrw = float(line.split("VRW ≤ ")[1].split()[0])
    arw = float(line.split("ARW ≤ ")[1].split()[0])
    assert 0.0968 <= vrw <= 0.0968 * 1.15 and 4.09 <= arw <= 4.09 * 1.25


def test_derived_bounds_take_the_scenario_acceleration_level(tmp_path, capsys):
    """Scale factor and misalignment bounds ∝ 1/a (seed 004 (6)–(8) with a = the specific force):
    a scenario at 2 g gets half the scale-factor bound of one at g; 0 is refused."""
    s = get_preset("airborne_xband")
    out = {}
    for a in (9.80665, 2 * 9.80665):
        path = tmp_path / f"s{a:.0f}.json"
        s.model_copy(update={"platform_accel_m_s2": a}).save(path)
        out[a] = run_json(capsys, ["bounds", "--scenario", str(path), "--mode", "derived", "--json", "-"])
    r1, r2 = (out[a]["bounds"]["rows"][0] for a in sorted(out))
    assert r2["accel_scale_factor_ppm"] == pytest.approx(r1["accel_scale_factor_ppm"] / 2, rel=1e-12)
    assert r2["accel_bias_ug"] == pytest.approx(r1["accel_bias_ug"], rel=1e-12)
    path = tmp_path / "s0.json"
    s.model_copy(update={"platform_accel_m_s2": 0.0}).save(path)
    assert main(["bounds", "--scenario", str(path), "--mode", "derived"]) == 2
    assert "platform_accel_m_s2" in capsys.readouterr().err


def test_check_json(tmp_path, capsys):
    path = tmp_path / "s.json"
    get_preset("automotive_24ghz").save(path)
    out = run_json(capsys, ["check", "--scenario", str(path), "--json", "-"])
    # what the verdicts were computed with, beside the records
    assert out["mode"] == "paper" and out["scenario"]["name"] == "automotive_24ghz" and out["catalog"] == "shipped"
    assert set(out["lowest_sufficient_grade"]) == {"paper", "pga_limited"}
    parts = out["parts"]
    assert parts and {"part_id", "grade", "verdict", "binding", "margins"} <= set(parts[0])
    assert all(r["verdict"] in ("pass", "fail", "unknown") for r in parts)


def test_catalog_commands(capsys):
    assert main(["catalog", "validate"]) == 0
    assert "parts valid" in capsys.readouterr().out
    parts = run_json(capsys, ["catalog", "list", "--json", "-"])
    pid = parts[0]["part_id"]
    shown = run_json(capsys, ["catalog", "show", pid, "--json", "-"])
    assert shown["part_id"] == pid


@pytest.mark.parametrize("argv,words", [
    (["bounds", "--tc", "1"], "--range-resolution"),
    (["bounds", "--tc", "0", "--range-resolution", "0.1"], "Tc"),
    (["check", "--scenario", "missing.json"], "not found"),
    (["catalog", "show", "NO-SUCH-PART"], "unknown part"),
    (["catalog", "validate", "missing.csv"], "not found"),
])
def test_bad_input_one_line_exit_2(capsys, argv, words):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1 and "Traceback" not in err


def test_no_traceback_in_a_real_process(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("part_id,grade,source\nX,tactical,ds\nX,tactical,ds\n")
    r = subprocess.run([sys.executable, "-m", "budget.cli.main", "catalog", "validate", str(bad)],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "duplicate part_id" in r.stderr and "Traceback" not in r.stderr
