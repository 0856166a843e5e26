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
    out = run_json(capsys, ["bounds", "--tc", "1", "10", "25", "50", "100", "--range-resolution", "0.1",
                            "--json", "-"])
    assert [r["tc_s"] for r in out] == [1, 10, 25, 50, 100]
    assert set(out[0]) == KEYS
    assert out[0]["accel_bias_ug"] == pytest.approx(14000) and out[4]["gyro_arw_deg_rt_h"] == pytest.approx(7.84e-4)


@pytest.mark.parametrize("mode", ["paper", "derived", "no-autofocus"])
def test_bounds_scenario_json(tmp_path, capsys, mode):
    s = get_preset("automotive_77ghz")
    path = tmp_path / "s.json"
    s.save(path)
    out = run_json(capsys, ["bounds", "--scenario", str(path), "--mode", mode, "--json", "-"])
    assert len(out) == 1 and out[0]["tc_s"] == pytest.approx(s.tc_s) and set(out[0]) == KEYS


def test_check_json(tmp_path, capsys):
    path = tmp_path / "s.json"
    get_preset("automotive_24ghz").save(path)
    out = run_json(capsys, ["check", "--scenario", str(path), "--json", "-"])
    assert out and {"part_id", "grade", "verdict", "binding", "margins"} <= set(out[0])
    assert all(r["verdict"] in ("pass", "fail", "unknown") for r in out)


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
