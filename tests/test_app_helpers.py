"""Dashboard helpers without Streamlit: upload validation, check table layout, labels, registry."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pandas as pd
import pytest

from budget.catalog.io import load_catalog, read_parts
from budget.check import check_parts
from budget.errors import InputError
from budget.presets import get_preset
from budget.scenario import Scenario

APP_DIR = Path(__file__).resolve().parents[1] / "app"
if str(APP_DIR) not in sys.path:
    sys.path.insert(0, str(APP_DIR))

import page_registry  # noqa: E402
from check_view import check_frame, style_check_frame, verdict_counts  # noqa: E402
from components import field_label  # noqa: E402
from sidebar import MAIN_FIELDS, MORE_FIELDS  # noqa: E402
from upload_check import MAX_REPORTED_ERRORS, check_upload  # noqa: E402

HEADER = b"part_id,grade,source,gyro_arw_deg_rt_h,accel_bias_instability_ug\n"


def test_valid_upload_gives_the_parts_read_parts_gives(tmp_path):
    data = HEADER + b"A-1,tactical,sheet rev 1,0.1,50\nB-2,industrial,sheet rev 2,,200\n"
    res = check_upload(data, "../../etc/mine.csv")
    assert res.ok and res.filename == "mine.csv"  # only the base name is ever shown
    f = tmp_path / "x.csv"
    f.write_bytes(data)
    assert res.parts == read_parts(f)


def test_every_bad_row_is_reported_with_its_row_and_column(tmp_path):
    data = (HEADER + b"A-1,tactical,s,0.1,50\n"      # row 2 fine
            b"B-2,tactical,s,abc,50\n"                # row 3: not a number
            b"\n"                                      # row 4: blank, skipped but counted
            b"C-3,tactical,s,0.1,-5\n"                 # row 5: negative
            b"D-4,tactical,s,0.1\n")                   # row 6: missing cell
    res = check_upload(data, "bad.csv")
    assert not res.ok and res.parts is None
    # rows as a spreadsheet or an editor numbers them: the blank line is a row too
    assert [(e.row, e.field) for e in res.errors] == [(3, "gyro_arw_deg_rt_h"), (5, "accel_bias_instability_ug"),
                                                      (6, None)]
    f = tmp_path / "bad.csv"
    f.write_bytes(data)
    with pytest.raises(InputError) as first:  # read_parts' own (first-found) error is listed
        read_parts(f)
    assert (first.value.row, first.value.field, first.value.reason) in [(e.row, e.field, e.reason) for e in res.errors]
    assert all(e.file == "bad.csv" for e in res.errors)
    rows = res.error_rows()
    assert rows[0]["value"] == "abc" and rows[0]["column"] == "gyro_arw_deg_rt_h"


def test_duplicate_ids_and_header_errors_are_single_messages():
    dup = check_upload(HEADER + b"A-1,tactical,s,0.1,50\nA-1,tactical,s,0.2,50\n", "d.csv")
    assert [(e.row, e.field) for e in dup.errors] == [(3, "part_id")]
    head = check_upload(b"part_id,grade,source,warp_factor\nA,tactical,s,9\n", "h.csv")
    assert [(e.row, e.field) for e in head.errors] == [(1, "warp_factor")]


@pytest.mark.parametrize("data, reason", [(b"", "empty"), (b"\xff\xfe\x00bin", "UTF-8"),
                                          (b"x" * 101, "bytes")])
def test_empty_binary_and_oversized_uploads_are_refused(data, reason):
    res = check_upload(data, "f.csv", max_bytes=100)
    assert not res.ok and reason in str(res.errors[0])


def test_error_listing_is_capped():
    data = HEADER + b"".join(b"P-%d,tactical,s,abc,1\n" % i for i in range(MAX_REPORTED_ERRORS + 20))
    res = check_upload(data, "many.csv")
    assert len(res.errors) == MAX_REPORTED_ERRORS and res.truncated


def test_check_frame_carries_check_parts_records():
    parts = list(load_catalog().values())
    res = check_parts(parts, get_preset("airborne_xband_long_range"))
    frame = check_frame(res)
    recs = res.to_dict()["scenarios"][0]["parts"]
    assert list(frame["verdict"]) == [r["verdict"] for r in recs]
    counts = verdict_counts(frame)
    assert counts == {v: sum(r["verdict"] == v for r in recs) for v in ("pass", "fail", "unknown")}
    for row, rec in zip(frame.to_dict("records"), recs):
        if rec["margins"]:
            assert row["min margin"] == pytest.approx(min(rec["margins"].values()), rel=1e-12)
        else:
            assert math.isnan(row["min margin"]) and pd.isna(row["binding"])
        assert row["beyond PGA (° rms)"] == pytest.approx(rec["fast_phase_residual_deg"], nan_ok=True)
        assert row["apertures within the limit"] == pytest.approx(rec["fast_phase_p_within_limit"], nan_ok=True)
    style_check_frame(frame).to_html()  # the styling renders


def test_field_labels_carry_units():
    assert field_label("slant_range_m") == "slant range (m)"
    assert field_label("platform_accel_m_s2") == "platform accel (m/s²)"
    assert field_label("platform_speed_m_s") == "platform speed (m/s)"
    assert field_label("carrier_frequency_hz") == "carrier frequency (Hz)"
    assert field_label("window_broadening") == "window broadening"


def test_sidebar_shows_every_scenario_field_once():
    assert sorted(MAIN_FIELDS + MORE_FIELDS) == sorted(Scenario.model_fields)


def test_registry_lists_existing_page_modules_with_unique_urls():
    avail = page_registry.available()
    assert [p.url_path for p in avail][:3] == ["scenario", "catalog", "check"]
    assert len({p.url_path for p in page_registry.PAGES}) == len(page_registry.PAGES)
    assert sum(p.default for p in avail) == 1


def test_tidy_tables_with_empty_cells_convert_to_arrow_as_streamlit_sends_them():
    """A number column with an empty cell is shown as text throughout ("–" for the empty cell),
    so the table converts to Arrow without Streamlit's logged fallback; full columns stay
    numbers (sortable)."""
    import pyarrow as pa

    from formatting import EMPTY, tidy

    frame = pd.DataFrame({"part": ["A", "B", "C"], "p_pass": [0.5, float("nan"), 0.123456],
                          "trials": [64, 64, 128], "margin": [1.0, 2.0, 3.0]})
    shown = tidy(frame).data
    table = pa.Table.from_pandas(shown)            # raises ArrowInvalid on a mixed column
    assert table.column("p_pass").to_pylist() == ["0.5", EMPTY, "0.1235"]
    assert pd.api.types.is_numeric_dtype(shown["margin"])
    assert pd.api.types.is_numeric_dtype(shown["trials"])
