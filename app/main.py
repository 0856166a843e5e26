"""Dashboard entry point: ``streamlit run app/main.py`` (or ``sar-budget dashboard``).

Runs the page picked in the top menu. Pages are listed in ``page_registry.py``; each is one
module in ``pages/`` that draws the shared sidebar (scenario, bounds mode, assumptions) itself.
"""

from __future__ import annotations

import sys
from pathlib import Path

APP_DIR = Path(__file__).resolve().parent
if str(APP_DIR) not in sys.path:  # page modules import the helpers beside this file
    sys.path.insert(0, str(APP_DIR))
try:
    import budget  # noqa: F401
except ImportError:  # running from a source checkout without installing the package
    sys.path.insert(0, str(APP_DIR.parent))

import streamlit as st  # noqa: E402

import page_registry  # noqa: E402

st.set_page_config(page_title="SAR IMU budget", page_icon=":material/radar:", layout="wide")
# Errors reach the browser as messages only (pages catch them; this covers the rest).
st.set_option("client.showErrorDetails", "none")

st.navigation(page_registry.pages(), position="top").run()
