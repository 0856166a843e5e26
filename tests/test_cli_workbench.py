"""The CLI as people use it: progress on long runs (TTY-aware, ``--quiet``), defaults in
``--help``, ``scenario show|write|validate``, ``report`` (offline HTML), one set of MC defaults."""

from __future__ import annotations

import io
import json
import re
from pathlib import Path

import pytest

from budget.cli.main import build_parser, main
from budget.cli.progress import Progress, working
from budget.mc.options import DEFAULT_SEED, DEFAULT_TRIALS
from budget.presets import get_preset
from budget.scenario import Scenario

REPO = Path(__file__).resolve().parents[1]


class _Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_without_a_terminal_writes_few_plain_lines():
    out = io.StringIO()
    p = Progress("mc X", stream=out)
    for done in range(0, 1025, 64):
        p(done, 1024)
    lines = out.getvalue().splitlines()
    assert "\r" not in out.getvalue()  # no animation in a log file
    assert lines[0] == "mc X: started"
    assert 3 <= len(lines) <= 7  # start + every 25 %, not one line per update
    assert lines[-1].startswith("mc X: 1024/1024 trials")


def test_progress_on_a_terminal_draws_a_bar_and_quiet_draws_nothing():
    tty = _Tty()
    p = Progress("sweep", "cells", stream=tty)
    for d in range(1, 5):
        p(d, 4)
    assert "4/4" in tty.getvalue() and "\r" in tty.getvalue()
    quiet = _Tty()
    q = Progress("sweep", stream=quiet, quiet=True)
    q(4, 4)
    with working("gap", quiet=True, stream=quiet):
        pass
    assert quiet.getvalue() == ""


def test_working_reports_elapsed_time_without_a_count():
    out = io.StringIO()
    with working("gap: log.csv vs ADIS16405", stream=out, interval_s=0.05):
        import time
        time.sleep(0.2)
    text = out.getvalue()
    assert text.startswith("gap: log.csv vs ADIS16405 …")
    assert "still working" in text and re.search(r"done in \d+\.\d s", text)


@pytest.mark.parametrize("argv", [["mc"], ["sweep"], ["gap"], ["noise", "arma"], ["noise", "characterize"],
                                  ["report"]])
def test_long_commands_have_quiet(argv, capsys):
    with pytest.raises(SystemExit):
        main([*argv, "--help"])
    assert "--quiet" in capsys.readouterr().out


def test_help_shows_defaults_and_mc_defaults_are_the_shared_constants(capsys):
    with pytest.raises(SystemExit):
        main(["mc", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert f"Monte Carlo trials (default: {DEFAULT_TRIALS})" in text
    assert f"(default: {DEFAULT_SEED})" in text
    args = build_parser().parse_args(["mc", "--preset", "airborne_xband", "--part", "STIM300"])
    assert (args.trials, args.seed) == (DEFAULT_TRIALS, DEFAULT_SEED)
    args = build_parser().parse_args(["sweep", "--preset", "airborne_xband", "--out", "x.csv"])
    assert (args.trials, args.seed) == (DEFAULT_TRIALS, DEFAULT_SEED)
    # the dashboard starts from the same numbers
    for page in ("monte_carlo.py", "sweep.py"):
        src = (REPO / "app" / "pages" / page).read_text()
        assert "value=DEFAULT_TRIALS" in src and "value=DEFAULT_SEED" in src


def test_scenario_write_show_validate_round_trip(tmp_path, capsys):
    out = tmp_path / "s.yaml"
    assert main(["scenario", "write", "--preset", "missile_borne", str(out)]) == 0
    assert Scenario.load(out) == get_preset("missile_borne")
    assert main(["scenario", "write", "--preset", "missile_borne", str(out)]) == 2  # kept unless --force
    assert "--force" in capsys.readouterr().err
    assert main(["scenario", "show", "--scenario", str(out)]) == 0
    shown = capsys.readouterr().out
    assert f"tc_s                        {get_preset('missile_borne').tc_s:.6g}" in shown
    assert main(["scenario", "show", "--preset", "airborne_xband", "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out) == get_preset("airborne_xband").model_dump(mode="json")


def test_scenario_validate_lists_every_error(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"name": "x", "carrier_frequency_hz": "abc", "slant_range_m": -1.0,
                               "azimuth_resolution_m": 0.5, "range_resolution_m": 0.5,
                               "platform_speed_m_s": 0.0}))
    assert main(["scenario", "validate", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1  # one line, no traceback
    for field in ("carrier_frequency_hz", "slant_range_m", "platform_speed_m_s"):
        assert field in err
    assert "more error" in err and "(and " not in err


def test_example_scenarios_are_valid_and_match_their_presets():
    files = sorted((REPO / "examples" / "scenarios").glob("*.*"))
    assert len(files) >= 4 and {f.suffix for f in files} >= {".json", ".yaml"}
    for f in files:
        s = Scenario.load(f)
        assert s.tc_s > 0
        if s.name in {"airborne_xband", "automotive_77ghz", "automotive_24ghz", "missile_borne", "sas_100khz"}:
            assert s == get_preset(s.name), f.name


def test_report_cli_writes_offline_html_with_check_and_provenance(tmp_path, capsys):
    out, js = tmp_path / "r.html", tmp_path / "r.json"
    assert main(["report", "--preset", "airborne_xband", "--part", "ADIS16405", "STIM300", "--out", str(out),
                 "--json", str(js), "--quiet"]) == 0
    html = out.read_text()
    assert not re.search(r"<script[^>]+src=", html)  # nothing loaded from elsewhere (no CDN)
    assert "Plotly" in html and html.count("class=\"plotly-graph-div\"") >= 2  # embedded plotly.js draws
    assert "id='check'" in html and "id='provenance'" in html and "ADIS16405" in html
    data = json.loads(js.read_text())
    assert data["provenance"]["sar_imu_budget_version"]
    flagged = {r["part_id"]: r["flag"] for r in data["check"]}
    assert set(flagged) == {"ADIS16405", "STIM300"}
    assert capsys.readouterr().err == ""  # --quiet


def test_demo_prints_the_check_flag(capsys):
    from budget.check import check_parts
    from budget.catalog.io import load_catalog

    assert main(["demo"]) == 0
    text = capsys.readouterr().out
    res = check_parts(load_catalog().values(), get_preset("airborne_xband"))
    flagged = [r for r in res.to_dict()["scenarios"][0]["parts"] if r.get("flag")]
    for r in flagged:
        assert f"! {r['part_id']}: {r['flag_reason']}" in text


def test_report_figures_written_beside_for_offline_use(tmp_path):
    figs = tmp_path / "figs"
    assert main(["report", "--preset", "automotive_24ghz", "--part", "STIM300", "--out", str(tmp_path / "r.html"),
                 "--figures", str(figs), "--quiet"]) == 0
    assert {p.name for p in figs.iterdir()} == {"bounds_vs_tc.html", "check_margins.html", "plotly.min.js"}
    assert 'src="plotly.min.js"' in (figs / "check_margins.html").read_text()
