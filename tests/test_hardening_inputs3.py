"""Bad input, round 3: cases a sweep of the CLI and the library entry points found.

Each test names the input and asserts the words of the one-line error (file, field, what was
expected), not only that something was raised.
"""

from __future__ import annotations

import pytest

import budget
from budget.cli.main import main
from budget.errors import InputError
from budget.mc.runner import MAX_LOCAL_WORKERS


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert err and "Traceback" not in "\n".join(err)
    return err[-1]


# --- local worker processes -------------------------------------------------------------------

def test_run_mc_refuses_more_local_processes_than_the_limit_before_starting_any():
    # 100000 workers forked 100000 processes and hung for minutes on a 2-trial run
    with pytest.raises(InputError) as e:
        budget.run_mc("automotive_77ghz", "STIM300", trials=1, workers=100_000)
    assert e.value.field == "workers" and f"1 … {MAX_LOCAL_WORKERS}" in str(e.value)
    assert "more local worker processes" in str(e.value) and "100000" in str(e.value)
    with pytest.raises(InputError) as e:
        budget.sweep(["STIM300"], "automotive_77ghz", trials=1, workers=MAX_LOCAL_WORKERS + 1)
    assert e.value.field == "workers"


def test_cli_mc_with_too_many_workers_exits_2(capsys):
    assert main(["mc", "--preset", "automotive_77ghz", "--part", "STIM300", "--trials", "1",
                 "--workers", "100000", "-q"]) == 2
    line = _one_line(capsys)
    assert "workers" in line and f"expected 1 … {MAX_LOCAL_WORKERS}" in line


# --- an output file that is a folder, checked before the computation --------------------------

@pytest.mark.parametrize("argv", [
    ["mc", "--preset", "automotive_77ghz", "--part", "STIM300", "--trials", "1", "-q", "--json", "{d}"],
    ["report", "--preset", "automotive_77ghz", "-q", "--out", "{d}"],
    ["sweep", "--preset", "automotive_77ghz", "--part", "STIM300", "--trials", "1", "-q", "--out", "{d}"],
])
def test_an_existing_folder_as_output_file_is_refused_before_the_run(tmp_path, monkeypatch, capsys, argv):
    import budget.cli.mc_cmd as mc_cmd
    import budget.cli.report_cmd as report_cmd

    def never(*a, **k):
        raise AssertionError("the computation started")
    monkeypatch.setattr(mc_cmd, "run_mc", never)
    monkeypatch.setattr(mc_cmd, "sweep", never)
    monkeypatch.setattr(report_cmd, "build_report", never)
    assert main([a.format(d=tmp_path) for a in argv]) == 1
    line = _one_line(capsys)
    assert f"{tmp_path}: is a folder; give a file name" in line and "--" in line


def test_report_figures_that_is_a_file_is_refused_before_the_run(tmp_path, capsys):
    f = tmp_path / "figs"
    f.write_text("x")
    assert main(["report", "--preset", "automotive_77ghz", "-q", "--out", str(tmp_path / "r.html"),
                 "--figures", str(f)]) == 1
    line = _one_line(capsys)
    assert "--figures" in line and f"{f}: exists and is not a folder" in line
    assert not (tmp_path / "r.html").exists()  # refused before the report was written


# --- a folder or a device where a log, an Allan table or a phase history is expected ----------

def _readers():
    from budget.noise import read_adev_table, read_log
    from budget.noise.measurement import read_measurement
    from budget.sar.afrl import read_afrl

    return [("log", lambda p: read_log(p)), ("allan table", lambda p: read_adev_table(p, 100.0, 10_000)),
            ("measurement", lambda p: read_measurement(p)), ("afrl", lambda p: read_afrl([p]))]


@pytest.mark.parametrize("which", range(4))
def test_a_folder_or_device_is_named_as_such_not_as_missing(tmp_path, which):
    name, read = _readers()[which]
    for path, said in ((tmp_path, "is a folder, not a file"), ("/dev/null", "is not a regular file"),
                       (tmp_path / "none.csv", "file not found")):
        with pytest.raises(InputError) as e:
            read(path)
        assert str(e.value).startswith(f"{path}: {said}"), (name, str(e.value))


def test_cli_noise_and_focus_name_a_folder_given_as_input(tmp_path, capsys):
    assert main(["noise", "characterize", str(tmp_path)]) == 2
    assert f"{tmp_path}: is a folder, not a file; expected an IMU log CSV or an Allan table" in _one_line(capsys)
    assert main(["noise", "arma", str(tmp_path)]) == 2
    assert f"{tmp_path}: is a folder, not a file" in _one_line(capsys)
    assert main(["focus", str(tmp_path)]) == 2
    assert "is a folder, not a file; expected an AFRL phase-history .mat file" in _one_line(capsys)


# --- a log or an Allan table with nothing to characterise names its file ----------------------

def test_a_log_whose_every_channel_is_constant_names_the_log(tmp_path, capsys):
    f = tmp_path / "stuck.csv"
    f.write_text("time_s,gyro_x_dps,gyro_y_dps,gyro_z_dps\n"
                 + "".join(f"{k / 100:.2f},0.1,0.1,0.1\n" for k in range(2000)))
    assert main(["noise", "characterize", str(f)]) == 2
    line = _one_line(capsys)
    assert f"{f}: no channel with noise to characterise: every channel is constant" in line
    assert "expected a static IMU log with noise" in line


def test_an_allan_table_too_short_to_fit_names_the_table(tmp_path, capsys):
    f = tmp_path / "adev_short.csv"
    f.write_text("channel,tau_s,adev\ngyro_x_dps,0.01,0.2\ngyro_x_dps,0.02,0.15\n")
    assert main(["noise", "characterize", str(f), "--rate-hz", "100", "--samples", "100000"]) == 2
    line = _one_line(capsys)
    assert "adev_short.csv: no channel could be fitted: gyro_x: not fitted" in line and "usable τ" in line


# --- bounds --wavelength ------------------------------------------------------------------------

@pytest.mark.parametrize("lam", ["1e30", "1e-30", "5000"])
def test_bounds_refuses_a_wavelength_no_radar_or_sonar_has(capsys, lam):
    # 1e30 m gave bounds of 5e34 ppm, 1e-30 m bounds of 5e-26 ppm, both printed as results
    assert main(["bounds", "--tc", "1", "--range-resolution", "0.1", "--wavelength", lam,
                 "--mode", "no-autofocus"]) == 2
    line = _one_line(capsys)
    assert "option --wavelength: wavelength outside the physically plausible range" in line
    assert "expected 1e-06 … 2000 m" in line


def test_bounds_refuses_a_range_resolution_finer_than_a_quarter_wavelength(capsys):
    assert main(["bounds", "--tc", "1", "--range-resolution", "0.1", "--wavelength", "3",
                 "--mode", "lever-arm"]) == 2
    line = _one_line(capsys)
    assert "option --range-resolution" in line and "expected > λ/4 = 0.75 m" in line
    assert main(["bounds", "--tc", "1", "--range-resolution", "0.1", "--wavelength", "0.03",
                 "--mode", "lever-arm", "--json", "-"]) == 0  # a real X-band case still runs


# --- an injected smooth phase error the pulses cannot sample ------------------------------------

def test_sar_refuses_a_quadratic_phase_error_that_aliases(capsys):
    # 1e12 rad printed "metrics" of an aliased error (a negative broadening) as a result
    assert main(["sar", "--preset", "airborne_xband", "--quadratic-rad", "1e12"]) == 2
    line = _one_line(capsys)
    assert "option --quadratic-rad, --cubic-rad, --sinusoid-rad" in line
    assert "the 462 pulses cannot sample it" in line and "≤ π(n−1)/2 = 724.1 rad" in line
    assert main(["sar", "--preset", "airborne_xband", "--quadratic-rad", "300", "--sinusoid-rad", "0",
                 "--json", "-"]) == 0  # 2·300 < 724: sampled, runs


def test_phase_history_refuses_an_injected_error_that_aliases():
    from test_sar_focus_injected import _points_history

    ph = _points_history(n_pulses=40, n_freq=16)
    with pytest.raises(InputError) as e:  # 2·100 > π·39/2 = 61.3: aliased
        ph.with_smooth_phase_error(100.0, 0.0, 0.0, 1.0)
    assert e.value.field == "quadratic_rad, cubic_rad, sinusoid_rad"
    assert "the 40 pulses cannot sample it" in str(e.value) and "= 61.26 rad" in str(e.value)
    assert ph.with_smooth_phase_error(20.0, 0.0, 0.0, 1.0).injected_phase_rad.shape == (40,)


# --- options of a log given with an Allan table ----------------------------------------------------

@pytest.mark.parametrize("extra", [["--max-rows", "10"], ["--repair"], ["--mapping", "{map}"]])
def test_noise_characterize_refuses_log_options_with_an_allan_table(tmp_path, capsys, extra):
    # they were silently ignored: --max-rows 10 still fitted every row of the table
    table = tmp_path / "adev.csv"
    table.write_text("channel,tau_s,adev\n" + "".join(
        f"gyro_z_dps,{0.01 * 2 ** k:g},{0.1 / 2 ** (k / 2):.6g}\n" for k in range(12)))
    mapping = tmp_path / "map.json"
    mapping.write_text('{"columns": {"gz": "gyro_z_dps"}}')
    argv = ["noise", "characterize", str(table), "--rate-hz", "100", "--samples", "1000000",
            *[a.format(map=mapping) for a in extra]]
    assert main(argv) == 2
    line = _one_line(capsys)
    assert f"{table}, option {extra[0]}: {extra[0]} applies to an IMU log, not to an Allan table" in line
    assert f"expected no {extra[0]} with an Allan table" in line


# --- noise.check_series on a series with NaN or without noise ------------------------------------

def test_check_series_refuses_nan_and_a_constant_series():
    import numpy as np

    from budget.noise import check_series

    x = np.random.default_rng(0).normal(size=1000)
    x[5] = np.nan  # was judged 'stationary' with a K² p-value of NaN
    with pytest.raises(InputError) as e:
        check_series(x)
    assert e.value.field == "x" and "NaN or infinite" in str(e.value) and "repair the log first" in str(e.value)
    with pytest.raises(InputError) as e:
        check_series(np.ones(1000))
    assert "series is constant (no noise to check)" in str(e.value)
    assert check_series(np.random.default_rng(0).normal(size=1000)).passed


# --- a warning on the command line is one line, without the code that raised it -----------------

def test_cli_prints_a_library_warning_as_one_line(tmp_path, capsys):
    p = tmp_path / "my.csv"
    p.write_text("part_id,grade,source\nstim300,tactical,mine\n")
    assert main(["catalog", "list", "--catalog", str(p)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    # was: ".../catalog_cmd.py:52: UserWarning: …" and the source line "cat = load_catalog(…)"
    assert len(err) == 1 and err[0].startswith("sar-budget catalog: warning: ")
    assert "'stim300' differs only in case from the shipped part 'STIM300'" in err[0]
    assert "UserWarning" not in err[0] and "load_catalog" not in err[0]
