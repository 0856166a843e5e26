"""The dashboard side of the error boundary: the same one-line messages as the CLI (no
"Something went wrong", no traceback), and uploads checked like files on disk."""

from __future__ import annotations

import gzip
import sys
from pathlib import Path

APP_DIR = Path(__file__).resolve().parents[1] / "app"
if str(APP_DIR) not in sys.path:
    sys.path.insert(0, str(APP_DIR))

from budget.errors import InputError  # noqa: E402
from upload_check import check_upload  # noqa: E402
from uploads import error_text, read_uploaded_log  # noqa: E402


def test_error_text_matches_the_cli():
    err = InputError("not a number", file="my.csv", row=3, field="gyro_arw_deg_rt_h", value="x" * 10 ** 6)
    text = error_text(err)
    assert text.startswith("my.csv, row 3, field gyro_arw_deg_rt_h: not a number") and len(text) < 400
    assert "Something went wrong" not in error_text(ZeroDivisionError("boom"))
    assert "ZeroDivisionError" in error_text(ZeroDivisionError("boom"))
    assert "nested too deeply" in error_text(RecursionError())
    assert "\x1b" not in error_text(InputError("bad \x1b[31mred"))


def test_damaged_upload_names_the_users_file():
    full = gzip.compress(b"time_s,gyro_x_dps\n" + b"".join(b"%.2f,%d\n" % (i / 100, i % 97)
                                                              for i in range(5000)))
    data = full[: len(full) // 2]
    try:
        read_uploaded_log.__wrapped__(data, "my_log.csv.gz", 1000, False)
    except InputError as err:
        assert err.file == "my_log.csv.gz" and "truncated" in str(err)
    else:
        raise AssertionError("a truncated upload was read")


def test_formula_and_escape_cells_in_an_uploaded_catalog():
    data = ("part_id,grade,source,vendor\nP1,tactical,ds,=HYPERLINK(1)\n"
            "P2,tactical,ds,\x1b[2Jx\n").encode()
    res = check_upload(data, "cat.csv")
    assert not res.ok
    rows = res.error_rows()
    assert [r["row"] for r in rows] == [2, 3] and all("\x1b" not in str(r["value"]) for r in rows)
