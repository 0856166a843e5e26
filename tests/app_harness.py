"""The dashboard under streamlit's headless ``AppTest``: its entry script, and ``app/`` on the
import path so that tests can call the pages' helpers. Importing this module skips the importing
test module when streamlit is not installed."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

AppTest = pytest.importorskip("streamlit.testing.v1", reason="streamlit not installed").AppTest

REPO = Path(__file__).resolve().parents[1]
APP_DIR = REPO / "app"
MAIN = str(APP_DIR / "main.py")
if str(APP_DIR) not in sys.path:
    sys.path.insert(0, str(APP_DIR))


def open_app(page: str | None = None) -> AppTest:
    """The dashboard run once, switched to ``page`` (``pages/<name>.py``) if given; no exception."""
    at = AppTest.from_file(MAIN, default_timeout=120).run()
    if page is not None:
        at.switch_page(page).run()
    assert not at.exception, [e.value for e in at.exception]
    return at


def page_errors(at: AppTest) -> list[str]:
    """The error messages the page shows (and no exception)."""
    assert not at.exception, [e.value for e in at.exception]
    return [e.value for e in at.error]
