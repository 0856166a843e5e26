"""One error boundary: every failure is one line on stderr with exit status
2 (bad input) or 1 (environment, unexpected); output paths are checked before the computation;
--debug / SAR_BUDGET_DEBUG show the traceback of unexpected errors only."""

from __future__ import annotations

import pytest

from budget.cli import common
from budget.cli.main import main
from budget.errors import InputError, OutputError, describe_error


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err, err
    return err


@pytest.mark.parametrize("argv", [
    ["bounds", "--preset", "airborne_xband", "--json", "/proc/x.json"],
    ["catalog", "list", "--json", "/proc/sys/x.json"],
    ["noise", "characterize", "README.md", "--as-part", "X1", "--append", "/proc/version"],
])
def test_unwritable_output_exits_1_before_work(argv, capsys):
    assert main(argv) == 1
    err = _one_line(capsys)
    assert "/proc" in err and "error:" in err


def test_output_checked_before_the_computation(tmp_path, monkeypatch, capsys):
    # gap would run for seconds; the report folder is not writable, so it must never start
    import budget.cli.gap_cmd as gap_cmd

    def boom(*a, **k):
        raise AssertionError("the computation ran before the output check")

    monkeypatch.setattr(gap_cmd, "run_gap", boom)
    log = tmp_path / "log.csv"
    log.write_text("time_s,gyro_x_dps\n0,0\n")
    code = main(["gap", str(log), "--part", "STIM300", "--report", "/proc/none/r.json", "-q"])
    assert code == 1 and "--report" in _one_line(capsys)


def test_missing_folder_for_append_is_not_an_output_error(tmp_path, capsys):
    # one rule for every output (README, "Bad input"): a missing folder of --append is created when
    # the row is written, as for --json; the two-row log is refused as input (2), and before that
    # nothing is created (tests/test_cli_review_fixes.py: the folder created and said)
    log = tmp_path / "log.csv"
    log.write_text("time_s,gyro_x_dps\n0,0\n")
    code = main(["noise", "characterize", str(log), "--as-part", "X1",
                 "--append", str(tmp_path / "missing" / "cat.csv")])
    assert code == 2 and "does not exist" not in _one_line(capsys)
    assert not (tmp_path / "missing").exists()


def test_folder_given_as_output_file(tmp_path, capsys):
    assert main(["catalog", "list", "--json", str(tmp_path)]) == 1
    assert "folder" in _one_line(capsys)


def test_check_output_path_accepts_stdout_and_new_files(tmp_path):
    assert common.check_output_path("-", "--json") is None
    assert common.check_output_path(tmp_path / "new" / "deeper" / "r.json", "--report") is not None
    with pytest.raises(OutputError):
        common.check_output_path(tmp_path / "no" / "cat.csv", "--append", must_exist_dir=True)
    assert not list(tmp_path.glob(".sar-budget-probe-*"))  # the probe file is removed


def test_bad_input_exits_2(tmp_path, capsys):
    s = tmp_path / "deep.json"
    s.write_text("[" * 50_000 + "]" * 50_000)
    assert main(["bounds", "--scenario", str(s)]) == 2
    assert "deep.json" in _one_line(capsys)
    assert main(["bounds", "--scenario", str(tmp_path)]) == 2
    _one_line(capsys)


def test_unexpected_error_is_one_line_with_hint(monkeypatch, capsys):
    import budget.bounds  # bounds_cmd imports it when it runs (budget.cli.main loads commands lazily)

    def broken(*a, **k):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(budget.bounds, "compute_bounds", broken)
    monkeypatch.delenv("SAR_BUDGET_DEBUG", raising=False)
    assert main(["bounds", "--preset", "airborne_xband"]) == 1
    err = _one_line(capsys)
    assert "ZeroDivisionError" in err and "--debug" in err
    assert main(["--debug", "bounds", "--preset", "airborne_xband"]) == 1
    assert "Traceback" in capsys.readouterr().err
    monkeypatch.setenv("SAR_BUDGET_DEBUG", "1")
    assert main(["bounds", "--preset", "airborne_xband"]) == 1
    assert "Traceback" in capsys.readouterr().err


def test_describe_error_classes():
    assert describe_error(InputError("bad", file="f.csv")).exit_code == 2
    assert describe_error(RecursionError()).exit_code == 2
    assert describe_error(OutputError("read-only", file="x")).exit_code == 1
    assert describe_error(PermissionError(13, "Permission denied", "/x")).text == "Permission denied: /x"
    assert describe_error(MemoryError()).exit_code == 1
    assert describe_error(KeyboardInterrupt()).exit_code == 130
    msg = describe_error(RuntimeError("x" * 10_000))
    assert msg.exit_code == 1 and len(msg.text) < 400


def test_bad_option_is_one_line_with_where_to_look(capsys):
    """argparse's own errors (wrong type, unknown option) are one line, exit 2, like every other
    input error, not the usage block."""
    for argv in (["mc", "--preset", "airborne_xband", "--part", "STIM300", "--trials", "2.5"],
                 ["bounds", "--preset", "airborne_xband", "--bogus"]):
        with pytest.raises(SystemExit) as e:
            main(argv)
        err = capsys.readouterr().err
        assert e.value.code == 2 and len(err.strip().splitlines()) == 1 and "--help" in err, err
