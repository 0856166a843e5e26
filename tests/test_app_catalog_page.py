"""Catalog page through AppTest: browse/filter, upload a valid and an invalid CSV (AppTest's
``file_uploader.set_value``), merge, and see the merged parts in the check matrix."""

from __future__ import annotations

from pathlib import Path

import pytest

from budget.catalog.io import load_catalog
from budget.check import check_parts
from budget.presets import get_preset

AppTest = pytest.importorskip("streamlit.testing.v1", reason="streamlit not installed").AppTest

MAIN = str(Path(__file__).resolve().parents[1] / "app" / "main.py")

VALID = (b"part_id,grade,source,gyro_bias_instability_deg_h,gyro_arw_deg_rt_h\n"
         b"MY-IMU-1,tactical,my datasheet rev A,0.5,0.05\n"
         b"MY-IMU-2,consumer,my datasheet rev B,5000,3\n")
INVALID = (b"part_id,grade,source,gyro_arw_deg_rt_h\n"
           b"BAD-1,superb,sheet,0.1\n"
           b"GOOD-1,tactical,sheet,0.1\n"
           b"BAD-2,tactical,sheet,abc\n")


def _catalog_page() -> AppTest:
    at = AppTest.from_file(MAIN, default_timeout=60).run()
    at.switch_page("pages/catalog.py").run()
    assert not at.exception and not at.error
    return at


def test_catalog_lists_and_filters_parts():
    at = _catalog_page()
    parts = load_catalog()
    assert list(at.dataframe[0].value["part_id"]) == list(parts)
    at.multiselect(key="cat_grades").set_value(["tactical"]).run()
    shown = at.dataframe[0].value
    assert set(shown["grade"]) == {"tactical"}
    assert list(shown["part_id"]) == [p for p, s in parts.items() if s.grade == "tactical"]
    at.text_input(key="cat_search").set_value("stim").run()
    assert list(at.dataframe[0].value["part_id"]) == ["STIM300"]


def test_valid_upload_merges_only_on_request_and_reaches_the_check_matrix():
    at = _catalog_page()
    at.file_uploader(key="cat_upload").set_value(("mine.csv", VALID, "text/csv")).run()
    assert not at.exception and not at.error
    assert any("2 parts valid" in s.value for s in at.success)
    assert "MY-IMU-1" not in list(at.dataframe[0].value["part_id"])  # not merged yet
    at.button(key="cat_merge").click().run()
    table = at.dataframe[0].value.set_index("part_id")
    assert table.loc["MY-IMU-1", "origin"] == "yours"
    assert table.loc["MY-IMU-1", "gyro_arw_deg_rt_h"] == 0.05
    assert len(table) == len(load_catalog()) + 2
    assert any("merged catalog" in d.label for d in at.download_button)

    at.switch_page("pages/check.py").run()
    assert not at.exception and not at.error
    check = at.table[0].value.set_index("part_id")
    expected = {r["part_id"]: r["verdict"] for r in check_parts(
        list(at.session_state["user_parts"].values()), get_preset("airborne_xband")).to_dict()["scenarios"][0]["parts"]}
    assert check.loc["MY-IMU-1", "verdict"] == expected["MY-IMU-1"]
    assert check.loc["MY-IMU-2", "verdict"] == expected["MY-IMU-2"]


def test_invalid_upload_lists_every_bad_row_and_merges_nothing():
    at = _catalog_page()
    at.file_uploader(key="cat_upload").set_value(("bad.csv", INVALID, "text/csv")).run()
    assert not at.exception
    assert any("2 problem(s)" in e.value and "nothing was merged" in e.value for e in at.error)
    errors = at.dataframe[-1].value  # the error table is the page's last dataframe
    assert list(errors["row"]) == [2, 4]
    assert list(errors["column"]) == ["grade", "gyro_arw_deg_rt_h"]
    assert "user_parts" not in at.session_state
    assert len(at.button) == 0 or all(b.key != "cat_merge" for b in at.button)
