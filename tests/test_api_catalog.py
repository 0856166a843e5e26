"""A user's catalog in the Python API (``catalog=`` of budget.run_mc, sweep, check_parts,
sweep_over, build_report, load_part(s)): the user's parts are found, ``parts=None`` is the whole
merged catalog as on the CLI (``--catalog``), the same seed gives the same numbers through the API
and the CLI, an overridden shipped id behaves as on the CLI, and a bad catalog argument is an
InputError naming the file, row or field."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pandas as pd
import pytest

import budget
from budget.catalog.io import part_origins, shipped_catalog_dir
from budget.cli.main import main
from budget.errors import InputError

from budget.mc import McOptions

#: The scene does not matter to these tests (what a result says, which part a catalog gives):
#: PGA's best case, the five noise-free points, keeps them fast.
POINTS = McOptions(scene="points")

SHIPPED_CSV = shipped_catalog_dir() / "parts.csv"
BASE_ID = "ADIS16405"  # a shipped row with gyro and accel noise figures
SCEN = "automotive_77ghz"  # where BASE_ID passes every trial (few trials: fast)


@pytest.fixture(autouse=True)
def _no_catalog_from_the_environment(monkeypatch):
    monkeypatch.delenv("SAR_BUDGET_CATALOG", raising=False)


def _shipped_row(part_id: str = BASE_ID) -> tuple[list[str], dict[str, str]]:
    with SHIPPED_CSV.open(newline="", encoding="utf-8") as f:
        reader = csv.DictReader(f)
        rows = {r["part_id"]: r for r in reader}
        return list(reader.fieldnames), rows[part_id]


def _write(path: Path, header: list[str], rows: list[dict[str, str]]) -> Path:
    with path.open("w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=header)
        w.writeheader()
        w.writerows(rows)
    return path


def _user_csv(tmp_path: Path, part_id: str = "MY-ADIS", arw: str = "3.0", name: str = "mine.csv") -> Path:
    """The shipped header and BASE_ID's row, with another id and another gyro ARW."""
    header, row = _shipped_row()
    return _write(tmp_path / name, header, [{**row, "part_id": part_id, "gyro_arw_deg_rt_h": arw}])


def _ten_times_worse(tmp_path: Path) -> Path:
    """BASE_ID's row with every gyro/accel error figure × 10, as part WORSE."""
    header, row = _shipped_row()
    worse = {k: (f"{10 * float(v):g}" if k.startswith(("gyro_", "accel_")) and v.strip() else v)
             for k, v in row.items()}
    assert any(worse[k] != row[k] for k in row)  # the row has noise figures to scale
    return _write(tmp_path / "worse.csv", header, [{**worse, "part_id": "WORSE"}])


def test_user_part_is_found_by_every_api_function(tmp_path):
    path = _user_csv(tmp_path)
    part = budget.load_part("MY-ADIS", catalog=path)
    assert part.gyro_arw_deg_rt_h == 3.0  # the value written above, not the shipped 2.0
    assert budget.load_part("MY-ADIS", catalog=str(path)) == part
    assert budget.load_part("MY-ADIS", catalog=budget.load_catalog(path)) == part
    assert [p.part_id for p in budget.load_parts(["MY-ADIS", "STIM300"], path)] == ["MY-ADIS", "STIM300"]

    r = budget.run_mc(SCEN, "MY-ADIS", trials=4, seed=2, catalog=path, options=POINTS)
    assert r.model_label == "MY-ADIS" and r.trials == 4

    table = budget.sweep(["MY-ADIS", "STIM300"], SCEN, trials=4, seed=2, catalog=path, options=POINTS)
    assert list(table["part_id"]) == ["MY-ADIS", "STIM300"]
    row = table.set_index("part_id").loc["MY-ADIS"]
    assert row["p_pass_after"] == r.p_pass_after and row["ci_after_lo"] == r.ci_after[0]

    check = budget.check_parts(["MY-ADIS"], SCEN, catalog=path)
    assert check.part_ids == ("MY-ADIS",)
    everything = budget.check_parts(None, SCEN, catalog=path)  # the whole merged catalog
    assert "MY-ADIS" in everything.part_ids and "STIM300" in everything.part_ids

    over = budget.sweep_over(["MY-ADIS"], SCEN, "slant_range_m", [300.0], trials=4, seed=2, catalog=path)
    assert list(over["part_id"]) == ["MY-ADIS"] and list(over["slant_range_m"]) == [300.0]

    rep = budget.build_report(SCEN, ["MY-ADIS"], catalog=path)
    assert rep.check.part_ids == ("MY-ADIS",)

    with pytest.raises(InputError, match="unknown part 'MY-ADIS'"):  # not in the shipped catalog
        budget.run_mc(SCEN, "MY-ADIS", trials=4, options=POINTS)


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_sweep_of_the_whole_user_catalog_matches_the_cli(tmp_path):
    path = _user_csv(tmp_path)
    api = budget.sweep(None, SCEN, trials=4, seed=5, catalog=path, options=POINTS)
    out = tmp_path / "cli.csv"
    assert main(["sweep", "--scene", "points", "--preset", SCEN, "--catalog", str(path), "--trials", "4", "--seed", "5",
                 "--out", str(out), "--quiet"]) == 0
    cli = pd.read_csv(out)
    with_noise = [p.part_id for p in budget.load_catalog(path).values()
                  if p.gyro_arw_deg_rt_h is not None or p.accel_vrw_m_s_rt_h is not None]
    assert "MY-ADIS" in with_noise and "ADIS16445" not in with_noise  # a part without noise figures
    assert list(api["part_id"]) == list(cli["part_id"]) == with_noise
    for col in ("p_pass_before", "p_pass_after", "ci_after_lo", "ci_after_hi"):
        assert api[col].tolist() == pytest.approx(cli[col].tolist(), rel=1e-12, abs=0), col


def test_run_mc_matches_the_cli_mc_for_a_user_part(tmp_path):
    path = _user_csv(tmp_path)
    r = budget.run_mc(SCEN, "MY-ADIS", trials=6, seed=11, catalog=path, options=POINTS)
    out = tmp_path / "mc.json"
    assert main(["mc", "--scene", "points", "--preset", SCEN, "--part", "MY-ADIS", "--catalog", str(path), "--trials", "6",
                 "--seed", "11", "--json", str(out), "--quiet"]) == 0
    cli = json.loads(out.read_text())
    assert cli["model"] == "MY-ADIS"
    assert cli["p_pass_after"] == pytest.approx(r.p_pass_after, abs=0)
    assert cli["p_pass_before"] == pytest.approx(r.p_pass_before, abs=0)


def test_ten_times_worse_user_part_never_passes_more_often(tmp_path):
    path = _ten_times_worse(tmp_path)
    table = budget.sweep([BASE_ID, "WORSE"], [SCEN, "airborne_xband"], trials=8, seed=3, catalog=path, options=POINTS)
    for scen, rows in table.groupby("scenario"):
        by = rows.set_index("part_id")
        assert by.loc["WORSE", "ci_after_lo"] <= by.loc[BASE_ID, "ci_after_lo"], scen
        assert by.loc["WORSE", "p_pass_after"] <= by.loc[BASE_ID, "p_pass_after"], scen
    # where the shipped part passes every trial, ten times its noise is seen to fail
    auto = table[table["scenario"] == SCEN].set_index("part_id")
    assert auto.loc[BASE_ID, "p_pass_after"] == 1.0 and auto.loc["WORSE", "p_pass_after"] < 1.0


def test_a_user_row_with_a_shipped_id_replaces_it_in_the_api_as_on_the_cli(tmp_path, capsys):
    path = _user_csv(tmp_path, part_id="STIM300", arw="1.5")
    assert part_origins(path)["STIM300"] == "user, replaces shipped"
    assert budget.load_part("STIM300", catalog=path).gyro_arw_deg_rt_h == 1.5  # the user's row
    assert budget.load_part("STIM300").gyro_arw_deg_rt_h != 1.5
    table = budget.sweep(["STIM300"], SCEN, trials=4, seed=7, catalog=path, options=POINTS)
    assert table["grade"].iloc[0] == _shipped_row()[1]["grade"]  # the copied row's grade
    out = tmp_path / "mc.json"
    assert main(["mc", "--scene", "points", "--preset", SCEN, "--part", "STIM300", "--catalog", str(path), "--trials", "4",
                 "--seed", "7", "--json", str(out), "--quiet"]) == 0
    assert json.loads(out.read_text())["p_pass_after"] == table["p_pass_after"].iloc[0]
    capsys.readouterr()
    # an id differing from a shipped one only in case stays separate, with the same warning
    twin = _user_csv(tmp_path, part_id="stim300", name="twin.csv")
    with pytest.warns(UserWarning, match="differs only in case"):
        parts = budget.load_parts(None, twin)
    assert {"stim300", "STIM300"} <= {p.part_id for p in parts}
    assert main(["check", "--preset", SCEN, "--catalog", str(twin), "--part", "stim300"]) == 0
    assert "differs only in case" in capsys.readouterr().err


def test_unknown_id_names_the_user_catalog_searched(tmp_path):
    path = _user_csv(tmp_path)
    for call in (lambda: budget.run_mc(SCEN, "MY-ADIZ", trials=4, catalog=path, options=POINTS),
                 lambda: budget.sweep(["MY-ADIZ"], SCEN, trials=4, catalog=path, options=POINTS),
                 lambda: budget.check_parts(["MY-ADIZ"], SCEN, catalog=path),
                 lambda: budget.sweep_over(["MY-ADIZ"], SCEN, "slant_range_m", [300.0], trials=4, catalog=path)):
        with pytest.raises(InputError) as err:
            call()
        text = str(err.value)
        assert text.startswith(str(path)) and "unknown part 'MY-ADIZ'" in text
        assert str(SHIPPED_CSV) in text and "MY-ADIS" in text.split("closest:")[1]
    with pytest.raises(InputError) as err:  # the shipped catalog alone: its file is named
        budget.load_part("MY-ADIZ")
    assert str(SHIPPED_CSV) in str(err.value)


def test_missing_and_malformed_catalog_files_are_named(tmp_path, capsys):
    missing = tmp_path / "none.csv"
    for call in (lambda c: budget.run_mc(SCEN, "STIM300", trials=4, catalog=c, options=POINTS),
                 lambda c: budget.sweep(None, SCEN, trials=4, catalog=c, options=POINTS),
                 lambda c: budget.check_parts(None, SCEN, catalog=c)):
        with pytest.raises(InputError, match="file not found") as err:
            call(missing)
        assert err.value.file == str(missing)
    header, row = _shipped_row()
    bad = _write(tmp_path / "bad.csv", header, [{**row, "part_id": "OK-1"},
                                                 {**row, "part_id": "BAD-1", "accel_vrw_m_s_rt_h": "fast"}])
    with pytest.raises(InputError) as err:
        budget.sweep(["OK-1"], SCEN, trials=4, catalog=bad, options=POINTS)
    e = err.value
    assert (e.file, e.row, e.field, e.value) == (str(bad), 3, "accel_vrw_m_s_rt_h", "fast")
    assert "number" in e.expected
    # the CLI says the same in one line, exit status 2
    assert main(["sweep", "--preset", SCEN, "--catalog", str(bad), "--trials", "4",
                 "--out", str(tmp_path / "t.csv"), "--quiet"]) == 2
    cli_err = capsys.readouterr().err
    assert "bad.csv" in cli_err and "row 3" in cli_err and "Traceback" not in cli_err


@pytest.mark.parametrize("bad", [5, 2.5, True, ["mine.csv"], b"mine.csv", ""])
def test_a_catalog_argument_of_a_wrong_type_is_an_input_error(bad):
    for call in (lambda: budget.run_mc(SCEN, "STIM300", trials=4, catalog=bad, options=POINTS),
                 lambda: budget.sweep(["STIM300"], SCEN, trials=4, catalog=bad, options=POINTS),
                 lambda: budget.sweep(None, SCEN, trials=4, catalog=bad, options=POINTS),
                 lambda: budget.check_parts(["STIM300"], SCEN, catalog=bad),
                 lambda: budget.load_part(budget.load_part("STIM300"), catalog=bad)):
        with pytest.raises(InputError) as err:
            call()
        assert err.value.field == "catalog" and "user parts CSV" in err.value.expected


def test_a_mapping_of_something_else_than_parts_is_refused():
    with pytest.raises(InputError, match="'X' is not a part") as err:
        budget.sweep(["X"], SCEN, trials=4, catalog={"X": {"gyro_arw_deg_rt_h": 1.0}}, options=POINTS)
    assert err.value.field == "catalog"
    # a plain dict of parts (e.g. a filtered catalog) is accepted
    cat = {k: v for k, v in budget.load_catalog().items() if k == "STIM300"}
    assert [p.part_id for p in budget.load_parts(None, cat)] == ["STIM300"]


def test_no_catalog_argument_takes_the_environment_catalog_as_the_cli_does(tmp_path, monkeypatch):
    path = _user_csv(tmp_path)
    monkeypatch.setenv("SAR_BUDGET_CATALOG", str(path))
    assert budget.load_part("MY-ADIS").gyro_arw_deg_rt_h == 3.0
    assert "MY-ADIS" in [p.part_id for p in budget.load_parts(None)]
    with pytest.raises(InputError) as err:
        budget.check_parts(["MY-ADIZ"], SCEN)
    assert err.value.file == str(path)
