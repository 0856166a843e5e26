"""The top-level Python API (``budget.sweep``, ``budget.run_mc``, ``budget.check_parts`` …): names
accepted where objects are expected, clear errors otherwise, the same numbers as the modules;
the README's worked trade study (``examples/trade_study.py``) runs; figures export offline."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import budget
from budget.catalog.io import load_catalog
from budget.check import check_parts as check_module
from budget.errors import InputError
from budget.presets import get_preset
from example_loader import load_example

REPO = Path(__file__).resolve().parents[1]


def test_top_level_names_are_the_functions_not_modules():
    for name in ("sweep", "run_mc", "check_parts", "load_scenario", "load_catalog", "cheapest_passing",
                 "sweep_over", "build_report"):
        assert callable(getattr(budget, name)), name
    assert budget.DEFAULT_TRIALS == 64 and budget.DEFAULT_SEED == 1
    with pytest.raises(AttributeError):
        budget.no_such_thing  # noqa: B018


def test_preset_name_accepted_wherever_a_scenario_is_expected(tmp_path):
    s = get_preset("airborne_xband")
    assert budget.load_scenario("airborne_xband") == s
    path = tmp_path / "s.json"
    s.save(path)
    assert budget.load_scenario(path) == s and budget.load_scenario(str(path)) == s
    assert budget.load_scenario(s.model_dump()) == s
    res = budget.check_parts(["ADIS16405", "STIM300"], "airborne_xband")
    ref = check_module([load_catalog()[p] for p in ("ADIS16405", "STIM300")], s)
    np.testing.assert_array_equal(res.margins, ref.margins)
    # a Scenario object and a single PartSpec are one item each, not iterated
    one = budget.check_parts(load_catalog()["STIM300"], s)
    assert one.part_ids == ("STIM300",) and one.scenario_names == (s.name,)


@pytest.mark.parametrize("bad", [42, "no_such_preset", ["airborne_xband", 3.0]])
def test_wrong_scenario_is_a_clear_input_error(bad):
    with pytest.raises(InputError, match="scenario|preset"):
        budget.check_parts(["STIM300"], bad)


def test_wrong_part_is_a_clear_input_error():
    with pytest.raises(InputError, match="part"):
        budget.run_mc("airborne_xband", "NOT-A-PART", trials=1)
    with pytest.raises(InputError, match="part"):
        budget.run_mc("airborne_xband", 3.5, trials=1)


def test_vary_scenario_follows_tc_and_names_each_copy():
    scens = budget.vary_scenario("automotive_77ghz", "slant_range_m", [250.0, 1000.0])
    base = get_preset("automotive_77ghz")
    assert [s.name for s in scens] == ["automotive_77ghz@slant_range_m=250", "automotive_77ghz@slant_range_m=1000"]
    # Tc ∝ R (seed 004 (5)), everything else unchanged
    assert scens[1].tc_s / scens[0].tc_s == pytest.approx(4.0, rel=1e-12)
    assert scens[0].model_dump(exclude={"name", "slant_range_m"}) == base.model_dump(exclude={"name", "slant_range_m"})
    with pytest.raises(InputError, match="cannot vary"):
        budget.vary_scenario(base, "medium", [1])


def _trade_study():
    return load_example("trade_study")


@pytest.mark.slow
def test_worked_trade_study_runs_and_its_table_is_the_sweep(tmp_path, capsys):
    """examples/trade_study.py with one trial per cell (the README shows it with 64)."""
    mod = _trade_study()
    out = mod.main(["--trials", "1", "--out", str(tmp_path / "ts.html"), "--ranges", "250", "500"])
    table = out["table"]
    assert isinstance(table, pd.DataFrame)
    assert set(table["part_id"]) == set(mod.PARTS) and set(table["scenario"]) == set(mod.SCENARIOS)
    assert len(table) == len(mod.PARTS) * len(mod.SCENARIOS)
    assert table["p_pass_after"].between(0, 1).all()
    assert (table["ci_after_lo"] <= table["p_pass_after"]).all() and (table["p_pass_after"] <= table["ci_after_hi"]).all()
    # one cell equals run_mc with the same seed (the sweep is the same trials)
    one = budget.run_mc("automotive_77ghz", "STIM300", trials=1, seed=budget.DEFAULT_SEED)
    row = table[(table["part_id"] == "STIM300") & (table["scenario"] == "automotive_77ghz")].iloc[0]
    assert row["p_pass_after"] == one.p_pass_after
    assert list(out["vs_range"]["slant_range_m"].unique()) == [250.0, 500.0]
    html = (tmp_path / "ts.html").read_text()
    assert not re.search(r"<script[^>]+src=", html)  # plotly.js embedded: opens offline
    assert (tmp_path / "ts_vs_range.html").is_file()


def test_gap_figures_are_written_for_offline_use(tmp_path):
    import plotly.graph_objects as go

    from budget.plots.export import PLOTLY_JS_NAME, write_html

    fig = go.Figure(go.Scatter(x=[1, 2], y=[3, 4]))
    a = write_html(fig, tmp_path / "a.html", plotlyjs="beside")
    write_html(fig, tmp_path / "b.html", plotlyjs="beside")
    assert (tmp_path / PLOTLY_JS_NAME).stat().st_size > 1_000_000  # the real bundle, written once
    text = a.read_text()
    assert f'src="{PLOTLY_JS_NAME}"' in text and "cdn" not in re.findall(r"<script[^>]*>", text)[0]
    src = (REPO / "budget" / "plots" / "gap.py").read_text()
    assert 'include_plotlyjs="cdn"' not in src and 'plotlyjs="beside"' in src


@pytest.mark.slow  # kaleido starts a headless Chromium per image (≈ 5 s each under load)
def test_png_and_svg_export_where_the_engine_is_installed(tmp_path):
    import plotly.graph_objects as go

    from budget.plots.export import static_export_available, write_image

    ok, why = static_export_available()
    if not ok:
        pytest.skip(why)
    fig = go.Figure(go.Scatter(x=[1, 2], y=[3, 4]))
    png = write_image(fig, tmp_path / "f.png", width=300, height=200)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    svg = write_image(fig, tmp_path / "f.svg", width=300, height=200)
    assert "<svg" in svg.read_text()[:500]
    with pytest.raises(InputError, match="png or svg"):
        write_image(fig, tmp_path / "f.gif")
