"""The dashboard's pages: one module under ``pages/`` each, listed here in menu order.

To add a page: write ``pages/<name>.py`` whose body calls
``page_frame.run_page(render)``, and add one :class:`PageEntry` below. A listed page whose
module does not exist yet is left out of the menu.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import streamlit as st

APP_DIR = Path(__file__).resolve().parent


@dataclass(frozen=True)
class PageEntry:
    path: str  # relative to the app directory
    title: str
    icon: str
    url_path: str
    default: bool = False


PAGES: tuple[PageEntry, ...] = (
    PageEntry("pages/scenario.py", "Scenario & bounds", ":material/radar:", "scenario", default=True),
    PageEntry("pages/catalog.py", "Catalog", ":material/inventory_2:", "catalog"),
    PageEntry("pages/check.py", "Check matrix", ":material/fact_check:", "check"),
    PageEntry("pages/monte_carlo.py", "Monte Carlo", ":material/casino:", "monte-carlo"),
    PageEntry("pages/sweep.py", "Trade study", ":material/grid_on:", "sweep"),
    PageEntry("pages/noise_lab.py", "Noise lab", ":material/ssid_chart:", "noise-lab"),
    PageEntry("pages/model_gap.py", "Model gap", ":material/compare_arrows:", "model-gap"),
    PageEntry("pages/focus.py", "Real SAR data", ":material/satellite_alt:", "focus"),
)


def available() -> list[PageEntry]:
    """Entries whose page module exists."""
    return [p for p in PAGES if (APP_DIR / p.path).is_file()]


def pages() -> list:
    """``st.Page`` objects for :func:`st.navigation`."""
    return [st.Page(APP_DIR / p.path, title=p.title, icon=p.icon, url_path=p.url_path, default=p.default)
            for p in available()]
