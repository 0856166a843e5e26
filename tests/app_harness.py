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
