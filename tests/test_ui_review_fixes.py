"""The dashboard after the UI review: the Scenario page for long apertures (1, 6), scenario notes
once with the edited name (10), the check matrix's margin columns (3), catalog merges that
accumulate (4) and the user catalog read when it changes (5)."""

from __future__ import annotations

import os

import pytest

from app_harness import open_app, page_errors

from budget.bounds import max_bounds_tc_s
from budget.catalog.schema import PART_COLUMNS
from budget.check import check_parts
from budget.catalog.io import load_catalog
from budget.plots.check import PARAM_LABELS
from budget.presets import get_preset

GRADE_METRICS = ("lowest sufficient grade (paper bounds)", "lowest sufficient grade (derived bounds)",
                 "lowest sufficient grade (PGA-limited, binding)")


def _metrics(at) -> dict[str, str]:
    return {m.label: m.value for m in at.metric}


def _downloads(at) -> list[str]:
    return [d.proto.label for d in at.get("download_button")]


# --- 1. Tc between 1500 and 3000 s: the plot stops at the library's limit, nothing disappears --------

def test_a_valid_long_aperture_keeps_the_plot_and_the_download():
    at = open_app()
    at.number_input(key="scn_slant_range_m").set_value(2.5e6).run()  # Tc = 1561 s, valid
    assert _metrics(at)["Tc, synthetic-aperture time"] == "1561 s"
    errors = page_errors(at)
    assert not [e for e in errors if "3123" in e or "beyond the bounds" in e], errors  # 2·Tc was plotted
    assert len(at.get("plotly_chart")) == 1
    assert "Download scenario (JSON)" in _downloads(at)
    assert any(f"stops at Tc = {max_bounds_tc_s():g} s" in c.value for c in at.caption)


# --- 6 (and 1). every bounds mode refused: "–" and why, and the rest of the page stays ---------------

def test_grades_not_computed_read_dash_with_the_reason_and_the_page_goes_on():
    at = open_app()
    at.number_input(key="scn_slant_range_m").set_value(1e7).run()  # Tc = 6246 s: no bound computed
    metrics = _metrics(at)
    assert [metrics[k] for k in GRADE_METRICS] == ["–", "–", "–"], metrics  # not "none": nothing computed
    reasons = [c.value for c in at.caption if c.value.startswith("not computed:")]
    assert len(reasons) == 3 and all("6246" in r for r in reasons), reasons
    assert "Download scenario (JSON)" in _downloads(at)
    assert len(at.get("plotly_chart")) == 1  # the grade bands up to the limit
    assert any("beyond the longest Tc" in i.value for i in at.info)


def test_a_grade_none_is_still_none_with_its_reason():
    from formatting import grade_text

    assert grade_text({"paper": None}, "paper") == "none"
    assert grade_text({}, "paper") == "–"
    assert grade_text({"paper": "tactical"}, "paper") == "tactical"


# --- 10. the scenario's notes: once, with the edited name ---------------------------------------------

def test_scenario_notes_are_shown_once_with_the_edited_name():
    at = open_app()
    at.number_input(key="scn_lever_arm_m__0").set_value(30.0).run()  # > 20 m: a unit note
    assert not at.exception
    notes = [w.value for w in at.warning if "lever arm" in w.value and "20 m" in w.value]
    assert len(notes) == 1, [w.value for w in at.warning]
    assert notes[0].startswith("airborne_xband_edited:"), notes[0]


# --- 3. the check matrix holds margins, and says so ---------------------------------------------------

def test_check_frame_labels_margins_as_margins_with_four_significant_figures():
    from check_view import MARGIN_LABELS, WITHIN_LIMIT, check_frame, style_check_frame

    res = check_parts(list(load_catalog().values()), get_preset("airborne_xband"))
    frame = check_frame(res)
    assert not set(PARAM_LABELS.values()) & set(frame.columns)  # "gyro bias (deg/h)" held a ratio
    assert "gyro bias margin (bound/spec)" in frame.columns
    stim = frame.set_index("part_id").loc["STIM300"]
    rec = next(r for r in res.to_dict()["scenarios"][0]["parts"] if r["part_id"] == "STIM300")
    assert stim[MARGIN_LABELS["gyro_bias_instability_deg_h"]] == rec["margins"]["gyro_bias_instability_deg_h"]
    assert stim["binding"] in {label.split(" margin")[0] for label in MARGIN_LABELS.values()}

    html = style_check_frame(frame).to_html()
    share = frame.set_index("part_id").loc["ADIS16405", WITHIN_LIMIT]
    assert 0 < share < 1e-3  # 9.3e-5 in the README
    assert f"{share:.4g}" in html and ">0.000<" not in html
    margin = stim[MARGIN_LABELS["gyro_bias_instability_deg_h"]]
    assert f">{margin:.4g}<" in html  # 4 significant figures, as the README says (was 3)


def test_check_page_names_margins():
    at = open_app("pages/check.py")  # the CSV export is written from the same frame
    assert not page_errors(at)
    columns = list(at.table[0].value.columns)
    assert "gyro ARW margin (bound/spec)" in columns and "gyro ARW (deg/√h)" not in columns


# --- 4. a second merge adds to the first ---------------------------------------------------------------

def _row(part_id: str, grade: str, arw: float) -> bytes:
    values = {"part_id": part_id, "grade": grade, "gyro_arw_deg_rt_h": arw, "source": "test datasheet"}
    header = ",".join(PART_COLUMNS)
    return (header + "\n" + ",".join(str(values.get(c, "")) for c in PART_COLUMNS) + "\n").encode()


def test_merges_accumulate_and_a_part_merged_again_is_replaced_and_said():
    at = open_app("pages/catalog.py")
    for name, data in (("a.csv", _row("AAA1", "tactical", 0.1)), ("b.csv", _row("BBB2", "industrial", 0.5))):
        at.file_uploader(key="cat_upload").set_value((name, data, "text/csv")).run()
        at.button(key="cat_merge").click().run()
    assert not at.exception
    user = at.session_state["user_parts"]
    assert set(user) == {"AAA1", "BBB2"}  # the second merge used to drop AAA1
    at.file_uploader(key="cat_upload").set_value(("a2.csv", _row("AAA1", "tactical", 0.2), "text/csv")).run()
    at.button(key="cat_merge").click().run()
    user = at.session_state["user_parts"]
    assert set(user) == {"AAA1", "BBB2"} and user["AAA1"].gyro_arw_deg_rt_h == 0.2
    assert any("replaced" in s.value and "AAA1" in s.value for s in at.success), [s.value for s in at.success]


# --- 5. $SAR_BUDGET_CATALOG edited while the server runs --------------------------------------------

def test_the_cached_catalog_follows_an_edit_of_the_user_catalog(tmp_path, monkeypatch):
    import components

    user = tmp_path / "mine.csv"
    user.write_bytes(_row("MINE-1", "tactical", 0.1))
    monkeypatch.setenv("SAR_BUDGET_CATALOG", str(user))
    assert "MINE-1" in components.shipped_catalog()
    text = user.read_bytes() + _row("MINE-2", "industrial", 0.3).split(b"\n", 1)[1]
    user.write_bytes(text)
    os.utime(user, ns=(user.stat().st_atime_ns, user.stat().st_mtime_ns + 1_000_000))  # a later mtime
    parts = components.shipped_catalog()
    assert {"MINE-1", "MINE-2"} <= set(parts)  # the cache kept the first file for the server's life
    monkeypatch.delenv("SAR_BUDGET_CATALOG")
    assert "MINE-1" not in components.shipped_catalog()


def test_the_catalog_cache_key_is_path_mtime_and_size(tmp_path, monkeypatch):
    import components

    user = tmp_path / "mine.csv"
    user.write_bytes(_row("MINE-1", "tactical", 0.1))
    monkeypatch.setenv("SAR_BUDGET_CATALOG", str(user))
    key = components.catalog_files_key()
    info = user.stat()
    assert key[-1] == (str(user), info.st_mtime_ns, info.st_size)
    monkeypatch.setenv("SAR_BUDGET_CATALOG", str(tmp_path / "gone.csv"))
    assert components.catalog_files_key()[-1] == (str(tmp_path / "gone.csv"), None, None)


@pytest.mark.parametrize("page", ["pages/scenario.py", "pages/check.py"])
def test_pages_still_draw_on_the_default_preset(page):
    at = open_app(page)
    assert not page_errors(at)
