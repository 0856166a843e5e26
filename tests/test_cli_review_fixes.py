"""The command line after the UI/CLI review: ``demo`` gives the preset's own grades (2), errors name
the option typed, not the library's field (7), ``--replace`` needs ``--append``, one rule for
output folders, negative numbers in scientific notation (8), and ``--help`` / argument errors do
not load every command (11)."""

from __future__ import annotations

import argparse
import math
import subprocess
import sys

import pytest

from budget.cli import main as cli_main
from budget.cli.main import COMMANDS, build_parser, main
from budget.cli.option_names import name_option
from budget.errors import InputError


def _error_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    return err[-1] if err else ""


def _allan_table(path):
    """A digitised gyro ARW curve (5 deg/h at 1 s): ``noise characterize`` reads it in ~1 s."""
    rows = ["channel,tau_s,adev [deg/h]"] + [f"gyro_z,{t:g},{5 / math.sqrt(t):.6g}"
                                            for t in (0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10)]
    path.write_text("\n".join(rows) + "\n")
    return path


# --- 2. demo --preset X: X's own grades -----------------------------------------------------------

def test_demo_prints_the_presets_own_lowest_sufficient_grades(capsys):
    from budget.presets import get_preset
    from budget.recommend import lowest_sufficient_grades

    assert main(["demo", "--preset", "sas_100khz"]) == 0
    out = capsys.readouterr().out
    own = lowest_sufficient_grades(get_preset("sas_100khz"), "paper", None)  # what `check` prints
    assert own["paper"] == "navigation"  # the paper's industrial-for-Tc-1-s table said nothing of it
    assert (f"lowest sufficient grade for sas_100khz (typical, bias + noise, paper bounds): "
            f"{own.text('paper')}") in out
    assert (f"lowest sufficient grade for sas_100khz (typical, bias + noise, PGA-limited bounds): "
            f"{own.text('pga_limited')}") in out
    assert "seed 004's table (δr = 0.1 m" in out and "not sas_100khz's geometry" in out


# --- 7. errors name the option typed ---------------------------------------------------------------

@pytest.mark.parametrize("argv, option, field", [
    (["check", "--preset", "airborne_xband", "--platform-motion", "oscillation", "--manoeuvre-period", "0"],
     "--manoeuvre-period", "period_s"),
    (["check", "--preset", "airborne_xband", "--platform-motion", "oscillation", "--manoeuvre-rate", "-1"],
     "--manoeuvre-rate", "peak_rate_deg_s"),
    (["sar", "--snr-db", "-1000"], "--snr-db", "snr_db"),
    (["sar", "--window", "hamming"], "--window", "field window"),
    (["mc", "--preset", "airborne_xband", "--part", "STIM300", "--trials", "2", "--clutter-db", "nan", "-q"],
     "--clutter-db", "clutter_to_target_db"),
])
def test_a_library_refusal_names_the_option_typed(argv, option, field, capsys):
    assert main(argv) == 2
    line = _error_line(capsys)
    assert f"option {option}:" in line and field not in line, line


def test_sar_window_expectation_is_in_the_command_lines_words(capsys):
    assert main(["sar", "--window", "hamming"]) == 2
    line = _error_line(capsys)
    assert "Window" not in line and "taylor-35-4" in line, line


def test_field_to_option_mapping_in_one_place():
    """gap's --realizations/--alpha and characterize's --as-part (their errors come after a
    computation): the mapping itself, on the parsers the commands build."""
    argv = ["gap", "log.csv", "--part", "STIM300", "--report", "r.json", "--realizations", "2", "--alpha", "5"]
    parser = build_parser(argv)
    args = parser.parse_args(argv)
    for field, option in (("realizations", "--realizations"), ("alpha", "--alpha")):
        err = name_option(InputError(f"{field} bad", field=field, value=2), parser, args)
        assert str(err).startswith(f"option {option}: "), str(err)
    argv = ["noise", "characterize", "log.csv", "--as-part", "=bad"]
    parser = build_parser(argv)
    args = parser.parse_args(argv)
    err = name_option(InputError("no catalog row", field="part_id", value="=bad"), parser, args)
    assert str(err).startswith("option --as-part: ")
    # read from a file: the file and its field stay (a catalog row's part_id is the file's)
    err = name_option(InputError("bad id", file="cat.csv", field="part_id"), parser, args)
    assert str(err).startswith("cat.csv, field part_id")
    # an option not given: the field is not the option's
    argv = ["noise", "characterize", "log.csv"]
    parser = build_parser(argv)
    err = name_option(InputError("bad id", field="part_id"), parser, parser.parse_args(argv))
    assert str(err).startswith("field part_id")


# --- 8. --replace, output folders, negative numbers ------------------------------------------------

def test_replace_without_append_is_refused(tmp_path, capsys):
    table = _allan_table(tmp_path / "allan.csv")
    assert main(["noise", "characterize", str(table), "--replace", "-q"]) == 2
    line = _error_line(capsys)
    assert "option --replace" in line and "--append" in line, line


def test_append_into_a_missing_folder_is_created_and_said_as_json_is(tmp_path, capsys):
    table = _allan_table(tmp_path / "allan.csv")
    cat, js = tmp_path / "nodir2" / "user.csv", tmp_path / "nodir" / "x.json"
    assert main(["noise", "characterize", str(table), "-q", "--as-part", "ABC1", "--append", str(cat),
                 "--json", str(js)]) == 0
    err = capsys.readouterr().err
    assert cat.is_file() and js.is_file()
    assert f"created folder {tmp_path / 'nodir2'}" in err and f"created folder {tmp_path / 'nodir'}" in err
    assert "ABC1" in cat.read_text()


@pytest.mark.parametrize("text, value", [("-1.5e1", -15.0), ("-2E-3", -0.002), ("-30", -30.0), ("-.5", -0.5)])
def test_negative_numbers_in_scientific_notation_parse(text, value):
    argv = ["check", "--preset", "airborne_xband", "--platform-motion", "attitude_change",
            "--manoeuvre-angle", text]
    args = build_parser(argv).parse_args(argv)
    assert args.manoeuvre_angle == value


def test_a_word_after_an_option_is_still_an_option_error(capsys):
    with pytest.raises(SystemExit) as e:
        build_parser(["check"]).parse_args(["check", "--preset", "airborne_xband", "--manoeuvre-angle",
                                            "--json"])
    assert e.value.code == 2 and "expected one argument" in capsys.readouterr().err


# --- 11. only the command typed is loaded -----------------------------------------------------------

def _modules_after(argv: list[str]) -> set[str]:
    code = ("import sys\nfrom budget.cli.main import main\n"
            f"try:\n    main({argv!r})\nexcept SystemExit:\n    pass\n"
            "print(' '.join(sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120).stdout
    return set(out.split())


HEAVY = ("scipy", "pandas", "plotly", "numba", "statsmodels", "streamlit")


def test_top_level_help_and_a_wrong_command_load_no_command_and_no_heavy_dependency():
    for argv in (["--help"], ["bogus"]):
        loaded = _modules_after(argv)
        assert not [m for m in HEAVY if m in loaded], argv
        assert not [m for m in loaded if m.endswith("_cmd")], argv


def test_a_commands_argument_error_loads_that_command_only():
    loaded = _modules_after(["check", "--bogus"])
    assert "budget.cli.check_cmd" in loaded
    assert not {"budget.cli.mc_cmd", "budget.check", "budget.mc", "budget.sar", "pandas", "plotly",
                "numba", "statsmodels"} & loaded


def test_the_lazy_parser_lists_the_commands_the_full_parser_has():
    full, lazy = build_parser(), build_parser([])
    sub_full = next(a for a in full._actions if isinstance(a, argparse._SubParsersAction))
    sub_lazy = next(a for a in lazy._actions if isinstance(a, argparse._SubParsersAction))
    assert list(sub_full.choices) == list(sub_lazy.choices) == list(COMMANDS)
    helps = {a.dest: a.help for a in sub_full._choices_actions}
    assert helps == {name: help_ for name, (_, help_) in COMMANDS.items()}  # the modules' own help
    assert full.format_help() == lazy.format_help()
    for name, (module, _) in COMMANDS.items():  # each command's module registers it
        sub = argparse.ArgumentParser().add_subparsers()
        __import__(f"budget.cli.{module}", fromlist=["add_parser"]).add_parser(sub)
        assert name in sub.choices


def test_a_commands_parser_is_the_same_lazy_or_full():
    for words in (["check"], ["noise", "characterize"], ["sweep"]):
        lazy = build_parser(words)
        full = build_parser()
        pick = cli_main.command_in(words)
        assert pick == words[0]

        def sub_help(p):
            for w in words:
                p = next(a for a in p._actions if isinstance(a, argparse._SubParsersAction)).choices[w]
            return p.format_help()

        assert sub_help(lazy) == sub_help(full)
