"""The CLI as the README shows it: every sub-command's ``--help`` names the default of every
option that has one, and ``report --json -`` leaves stdout to the JSON alone."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import pytest

from budget.cli.main import build_parser, main


def _parsers(parser: argparse.ArgumentParser, prefix: tuple[str, ...] = ()):
    """Every (command words, parser) below ``parser``, nested ones (``noise arma``) included."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield (*prefix, name), sub
                yield from _parsers(sub, (*prefix, name))


def _has_default(value) -> bool:
    return not (value is None or value is False or value is argparse.SUPPRESS
                or (isinstance(value, str) and value == ""))


def test_every_option_with_a_default_names_it_in_help():
    """README (Quick start): "Every sub-command's --help shows its defaults". Options without a
    help text (check --mode, sar --method/--kernel/--seed, focus --autofocus, noise arma
    --replace-with) showed nothing, and a default of 0 was taken for "off"."""
    missing = []
    for words, parser in _parsers(build_parser()):
        formatter = parser._get_formatter()
        for action in parser._actions:
            if not action.option_strings or not _has_default(action.default):
                continue
            if isinstance(action, (argparse._HelpAction, argparse._VersionAction)):
                continue
            text = " ".join(formatter._format_action(action).split())
            if "default" not in text.lower():
                missing.append(f"{' '.join(words)} {action.option_strings[-1]}")
    assert not missing, missing


@pytest.mark.parametrize("argv, shown", [
    (["check"], "(default: paper)"),
    (["sar"], "(default: rda)"),
    (["sar"], "(default: 0)"),
    (["focus"], "(default: pga)"),
    (["noise", "arma"], "(default: mean)"),
])
def test_options_without_help_text_show_their_default(argv, shown, capsys):
    with pytest.raises(SystemExit):
        main([*argv, "--help"])
    assert shown in capsys.readouterr().out


def test_report_json_to_stdout_is_json_alone(tmp_path, monkeypatch, capsys):
    """``report --json -``: "also write the report's content as JSON ('-' = stdout)" — the
    summary and the "wrote" line followed the JSON on stdout, which then did not parse."""
    import budget.cli.report_cmd as report_cmd

    class _Report:  # the report itself is tested elsewhere; this is about what goes where
        figures: dict = {}

        def save(self, path):
            Path(path).write_text("<html></html>")

        def to_dict(self):
            return {"scenario": {"name": "automotive_77ghz"}}

        def summary(self):
            return "report: scenario automotive_77ghz"

    monkeypatch.setattr(report_cmd, "build_report", lambda *a, **k: _Report())
    out = tmp_path / "r.html"
    assert main(["report", "--preset", "automotive_77ghz", "--part", "STIM300", "--out", str(out),
                 "--json", "-", "--quiet"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out) == {"scenario": {"name": "automotive_77ghz"}}
    assert f"wrote {out}" in captured.err and "report: scenario automotive_77ghz" in captured.err
    assert out.is_file()
    # to a file, the summary stays on stdout as before
    assert main(["report", "--preset", "automotive_77ghz", "--part", "STIM300", "--out", str(out),
                 "--json", str(tmp_path / "r.json"), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert "report: scenario automotive_77ghz" in captured.out and captured.err == ""


def test_bounds_wavelength_help_says_what_needs_it(capsys):
    """``--wavelength`` was "needed by --mode no-autofocus"; lever-arm mode refuses to run without
    it too, and bare ``--tc`` prints no fast-phase limits without it (README, Bounds)."""
    with pytest.raises(SystemExit):
        main(["bounds", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "and lever-arm, and for the fast-phase VRW/ARW limits" in text
    assert main(["bounds", "--tc", "1", "--range-resolution", "0.1", "--mode", "lever-arm"]) == 2
    assert "--wavelength" in capsys.readouterr().err
    assert main(["bounds", "--tc", "1", "10", "--range-resolution", "0.1", "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out)["fast_phase"] is None
    assert main(["bounds", "--tc", "1", "10", "--range-resolution", "0.1", "--wavelength", "0.03"]) == 0
    assert "Tc = 10 s: VRW ≤" in capsys.readouterr().out


def test_mc_help_names_the_scene_defaults(capsys):
    with pytest.raises(SystemExit):
        main(["mc", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "receiver SNR in dB (default: 30 on the realistic scene" in text
    assert "image weighting (default auto" in text


def test_sweep_csv_to_stdout_is_csv_alone(capsys):
    """``sweep --out -`` wrote the CSV to stdout and then the cheapest-part table after it."""
    import io

    import pandas as pd

    assert main(["sweep", "--preset", "automotive_24ghz", "--part", "STIM300", "--trials", "1",
                 "--out", "-", "--quiet"]) == 0
    captured = capsys.readouterr()
    table = pd.read_csv(io.StringIO(captured.out))
    assert list(table["part_id"]) == ["STIM300"] and list(table["scenario"]) == ["automotive_24ghz"]
    assert "basis" in captured.err  # the cheapest-part table, beside the CSV


@pytest.mark.parametrize("argv", [["gap"], ["noise", "characterize"]])
def test_ci_level_names_its_default_once(argv, capsys):
    with pytest.raises(SystemExit):
        main([*argv, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "confidence level of an Allan table's lci/uci (default: 0.95)" in text
    assert "(0.95) (default: 0.95)" not in text


def test_characterize_vendor_and_model_say_they_are_catalog_columns(capsys):
    """``noise characterize --model`` is the row's model name, not a noise-model file as
    ``mc --model M.json``; it had no help text."""
    with pytest.raises(SystemExit):
        main(["noise", "characterize", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--vendor VENDOR vendor column of the catalog row" in text
    assert "--model MODEL model column of the catalog row" in text
