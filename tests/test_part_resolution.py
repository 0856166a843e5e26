"""One resolution of "a catalog part or a noise-model file" (budget.api.load_part) for the API,
the CLI commands and the dashboard; the CLI options that expose library settings."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from budget.api import load_part
from budget.catalog.io import get_part, load_catalog, load_grades
from budget.catalog.schema import PartSpec
from budget.recommend import recommend_grade
from budget.cli.main import main
from budget.errors import InputError
from budget.imu.noise_model import NoiseModel
from budget.presets import get_preset


def _model_file(tmp_path: Path, part_id: str = "STIM300", name: str = "model.json") -> Path:
    path = tmp_path / name
    NoiseModel.from_part(get_part(part_id)).save(path)
    return path


def test_part_id_gives_the_catalog_row_and_a_file_gives_the_noise_model(tmp_path):
    part = load_part("STIM300")
    assert isinstance(part, PartSpec) and not isinstance(part, NoiseModel)
    assert part == load_catalog()["STIM300"]
    path = _model_file(tmp_path)
    for source in (path, str(path)):
        model = load_part(source)
        assert isinstance(model, NoiseModel)
        assert model.gyro_arw_deg_rt_h == part.gyro_arw_deg_rt_h and model.part_id == "STIM300"
    assert load_part(part) is part


def test_unknown_part_lists_the_closest_ids():
    with pytest.raises(InputError) as err:
        load_part("STIM30")
    text = str(err.value)
    assert "unknown part 'STIM30'" in text and "STIM300" in text.split("closest:")[1]
    with pytest.raises(InputError, match="ADIS16405"):
        load_part("adis16405")  # ids are exact; the message offers the right spelling


def test_bad_model_files_name_the_file_and_the_field(tmp_path):
    missing = tmp_path / "none.json"
    with pytest.raises(InputError, match="file not found") as err:
        load_part(missing)
    assert str(missing) in str(err.value)
    broken = tmp_path / "broken.json"
    broken.write_text('{"part_id": "X", ')
    with pytest.raises(InputError, match="not valid JSON") as err:
        load_part(broken)
    assert "broken.json" in str(err.value)
    bad_field = tmp_path / "field.json"
    bad_field.write_text(json.dumps({"part_id": "X", "gyro_arw_deg_rt_h": -1.0}))
    with pytest.raises(InputError) as err:
        load_part(bad_field)
    assert "field.json" in str(err.value) and "gyro_arw_deg_rt_h" in str(err.value)
    binary = tmp_path / "nul.json"
    binary.write_bytes(b'{"part_id": "X"}\x00')
    with pytest.raises(InputError, match="NUL") as err:
        load_part(binary)
    assert "nul.json" in str(err.value)


@pytest.mark.parametrize("command", ["mc", "motion"])
def test_commands_report_an_unknown_part_and_a_bad_model_in_one_line(tmp_path, capsys, command):
    assert main([command, "--preset", "airborne_xband", "--part", "STIM30"]) == 2
    err = capsys.readouterr().err
    assert "unknown part 'STIM30'" in err and "STIM300" in err and "Traceback" not in err
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    assert main([command, "--preset", "airborne_xband", "--model", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "bad.json" in err and "Traceback" not in err


def test_motion_gives_the_same_numbers_for_a_part_and_its_model_file(tmp_path):
    path = _model_file(tmp_path)
    out = {}
    for how, src in (("part", ["--part", "STIM300"]), ("model", ["--model", str(path)])):
        dest = tmp_path / f"out_{how}.json"  # not model.json: that is the input
        assert main(["motion", "--preset", "airborne_xband", *src, "--trials", "4", "--seed", "3",
                     "--json", str(dest)]) == 0
        out[how] = json.loads(dest.read_text())
    assert out["part"] == out["model"]


def test_mc_unspecified_policy_reaches_the_library(tmp_path, capsys):
    sparse = tmp_path / "sparse.json"
    sparse.write_text(json.dumps({"part_id": "SPARSE", "grade": "tactical", "gyro_arw_deg_rt_h": 0.15}))
    assert main(["mc", "--preset", "airborne_xband", "--model", str(sparse), "--trials", "1",
                 "--unspecified", "refuse"]) == 2
    err = capsys.readouterr().err
    assert "unspecified" in err and "accel_vrw_m_s_rt_h" in err
    from budget.cli import mc_cmd
    import argparse

    parser = argparse.ArgumentParser()
    mc_cmd.add_parser(parser.add_subparsers())
    for policy in ("zero", "fill_grade_typical", "refuse"):
        args = parser.parse_args(["mc", "--preset", "airborne_xband", "--part", "STIM300", "--unspecified", policy])
        assert mc_cmd._options(args).unspecified == policy
        args = parser.parse_args(["sweep", "--preset", "airborne_xband", "--out", "x.csv", "--unspecified", policy])
        assert mc_cmd._options(args).unspecified == policy
    with pytest.raises(SystemExit):
        parser.parse_args(["mc", "--preset", "airborne_xband", "--part", "STIM300", "--unspecified", "typical"])


@pytest.mark.parametrize("mode", ["paper", "derived", "no-autofocus"])
def test_check_recommends_the_grade_of_its_mode(capsys, mode):
    s = get_preset("airborne_xband")
    assert main(["check", "--preset", "airborne_xband", "--mode", mode, "--part", "STIM300"]) == 0
    line = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("lowest sufficient grade")][0]
    want = recommend_grade([s.tc_s], s.range_resolution_m, list(load_grades().values()), mode=mode,
                           wavelength_m=s.wavelength_m).grade[0]
    assert line.endswith(f"{mode} bounds): {want or 'none'}")


def test_an_uploaded_model_is_read_as_the_cli_reads_it(tmp_path):
    """The dashboard's model upload goes through the same resolver; errors name the upload."""
    import sys

    app_dir = Path(__file__).resolve().parents[1] / "app"
    if str(app_dir) not in sys.path:
        sys.path.insert(0, str(app_dir))
    from uploads import read_via_temp_copy

    def read(data: bytes, name: str):
        return read_via_temp_copy(data, name, lambda path: load_part(Path(path)))

    good = _model_file(tmp_path).read_bytes()
    assert read(good, "mine.json") == load_part(_model_file(tmp_path, name="again.json"))
    with pytest.raises(InputError) as err:
        read(b'{"part_id": "X", "gyro_arw_deg_rt_h": "fast"}', "mine.json")
    assert "mine.json" in str(err.value) and "gyro_arw_deg_rt_h" in str(err.value)
    assert err.value.file == "mine.json"  # not the temporary copy


def test_mc_runs_on_a_full_noise_model_json(tmp_path, capsys):
    """A model JSON with both ARW and VRW (and an effect) runs through ``mc``: the analytic
    check beside the verdict is for catalog parts only (a NoiseModel is a PartSpec too; its
    ``to_si`` adds the effects, which the check once read as the part's SI errors and crashed)."""
    model = tmp_path / "m.json"
    model.write_text(json.dumps({"rate_hz": 200.0, "gyro_arw_deg_rt_h": 0.15, "gyro_bias_instability_deg_h": 0.5,
                                 "accel_vrw_m_s_rt_h": 0.03, "accel_bias_instability_ug": 20.0,
                                 "effects": [{"name": "warmup_transient", "channel": "accel_z",
                                              "params": {"amplitude": 1e-3, "tau_s": 600.0}}]}))
    assert main(["mc", "--preset", "airborne_xband", "--model", str(model), "--trials", "2", "-q"]) == 0
    out = capsys.readouterr().out
    assert "P(pass)" in out and "check vs Monte Carlo" not in out


def test_check_of_a_noise_model_is_that_of_its_catalog_row():
    from budget.check import check_parts

    part, scen = get_part("STIM300"), get_preset("airborne_xband")
    model = NoiseModel.from_part(part).with_effect({"name": "rate_ramp", "channel": "gyro_x", "params": {"R": 1e-7}})
    a = check_parts([part], scen).to_dict()["scenarios"][0]["parts"][0]
    b = check_parts([model], scen).to_dict()["scenarios"][0]["parts"][0]
    # the analytic check reads the catalog row only: every field the same, the fast-phase
    # residual included (the term that read the SI errors)
    assert a == b and a["fast_phase_residual_deg"] > 0
