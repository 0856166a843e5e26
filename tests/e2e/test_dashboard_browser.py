"""The dashboard in a real browser: open it, change a scenario field, see the check table follow."""

from __future__ import annotations

import time
from pathlib import Path

import pytest

from budget.catalog.io import load_catalog
from budget.check import check_parts
from budget.presets import get_preset
from budget.scenario import Scenario

from browser_helpers import idle, open_page

pytestmark = pytest.mark.e2e

REPO = Path(__file__).resolve().parents[2]
ARTIFACTS = REPO / "test-artifacts"  # gitignored; the page fixture creates it


def _expected(scenario: Scenario) -> tuple[list[tuple[str, str]], str]:
    recs = check_parts(list(load_catalog().values()), scenario, "paper").to_dict()["scenarios"][0]["parts"]
    n = {v: sum(r["verdict"] == v for r in recs) for v in ("pass", "fail", "unknown")}
    return ([(r["part_id"], r["verdict"]) for r in recs],
            f"{n['pass']} pass · {n['fail']} fail · {n['unknown']} unknown")


def _table_verdicts(page) -> list[tuple[str, str]]:
    rows = page.get_by_test_id("stTable").locator("tbody tr")
    out = []
    for i in range(rows.count()):
        cells = rows.nth(i).locator("td").all_inner_texts()
        out.append((cells[0].strip(), cells[2].strip()))
    return out


def _wait_for_table(page, expected: list[tuple[str, str]], timeout_s: float = 180.0) -> list[tuple[str, str]]:
    """Read the check table until it shows ``expected`` (the page re-renders asynchronously)."""
    deadline = time.monotonic() + timeout_s
    shown = _table_verdicts(page)
    while shown != expected and time.monotonic() < deadline:
        page.wait_for_timeout(250)
        shown = _table_verdicts(page)
    return shown


def test_scenario_page_draws_bounds_and_plot(page, dashboard_url):
    from playwright.sync_api import expect

    open_page(page, dashboard_url)
    s = get_preset("airborne_xband")
    expect(page.get_by_text(f"{s.tc_s:.4g} s", exact=True)).to_be_visible()
    page.locator(".js-plotly-plot .main-svg").first.wait_for()  # plotly has drawn
    idle(page)
    page.screenshot(path=str(ARTIFACTS / "dashboard_scenario.png"))  # README pictures: the per-page test


@pytest.mark.slow  # CI's second step: 33 s on a fresh clone (fast suite under 10 min on 2 cores)
def test_editing_slant_range_updates_the_check_table(page, dashboard_url):
    from playwright.sync_api import expect

    open_page(page, dashboard_url, "check")
    summary = page.locator("#check-summary")
    before, before_text = _expected(get_preset("airborne_xband"))
    expect(summary).to_have_text(before_text)
    assert _wait_for_table(page, before) == before

    edited = Scenario(**{**get_preset("airborne_xband").model_dump(), "slant_range_m": 50_000.0})
    after, after_text = _expected(edited)
    assert after_text != before_text  # the edit must change the outcome for the test to mean anything
    box = page.get_by_label("slant range (m)")
    box.fill("50000")
    box.press("Enter")
    expect(summary).to_have_text(after_text)
    expect(page.get_by_text(f"Tc = {edited.tc_s:.4g} s")).to_be_visible()
    assert _wait_for_table(page, after) == after
    page.screenshot(path=str(ARTIFACTS / "dashboard_check_after_edit.png"))
