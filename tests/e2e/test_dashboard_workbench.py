"""The dashboard in a real browser as an engineer uses it: the real ADIS16405 log uploaded on the
Noise lab and Model gap pages, the trade-study page driven, the HTML report downloaded and opened
with the network cut off. Every wait is on what the page shows (Playwright ``expect`` /
``wait_for`` with generous timeouts), never a fixed sleep."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from browser_helpers import idle, open_page

pytestmark = pytest.mark.e2e

REPO = Path(__file__).resolve().parents[2]
ARTIFACTS = REPO / "test-artifacts"
DOCS = REPO / "docs"
REAL_LOG = REPO.parent / "shared" / "data" / "logs" / "adis16405_static_1.csv.gz"


def _real_log() -> Path:
    if not REAL_LOG.is_file():
        pytest.skip(f"real ADIS16405 log not found at {REAL_LOG} (clone without ../shared)")
    return REAL_LOG


def _idle(page) -> None:
    idle(page)


def _upload(page, path: Path) -> None:
    page.locator("input[type=file]").first.set_input_files(str(path))


def _set_number(page, label: str, value) -> None:
    box = page.get_by_role("spinbutton", name=label, exact=True)
    box.fill(str(value))
    box.press("Enter")
    _idle(page)


@pytest.mark.slow
def test_real_log_on_noise_lab(page, dashboard_url):
    from playwright.sync_api import expect

    log = _real_log()
    open_page(page, dashboard_url, "noise-lab")
    page.get_by_text("upload a log or an Allan table").click()
    from budget.cli.dashboard_cmd import MAX_UPLOAD_MB  # the server's limit, stated on the widget

    expect(page.get_by_text(f"at most {MAX_UPLOAD_MB} MB", exact=False).first).to_be_visible()
    _upload(page, log)
    loaded = page.locator("#noise-loaded")
    expect(loaded).to_contain_text("adis16405_static_1.csv.gz")
    expect(loaded).to_contain_text("samples at 100 Hz")
    expect(page.get_by_text("selected ARMA model", exact=False)).to_be_visible()
    expect(page.get_by_text("Allan deviation and IEEE-952 terms")).to_be_visible()
    page.locator(".js-plotly-plot").first.wait_for()
    _idle(page)
    page.screenshot(path=str(ARTIFACTS / "noise_lab_real_log.png"), full_page=True)


@pytest.mark.slow  # the model-gap workflow on 2·10⁵ real samples: 1–7 min on 2 cores
def test_real_log_on_model_gap(page, dashboard_url):
    from playwright.sync_api import expect

    log = _real_log()
    open_page(page, dashboard_url, "model-gap")
    page.get_by_text("upload a log or an Allan table").click()
    expect(page.get_by_text("Upload a static IMU log or an Allan table", exact=False)).to_be_visible()
    _idle(page)  # the radio's rerun ends before the file is set (see test_allan_table_on_noise_lab)
    _upload(page, log)
    expect(page.get_by_text("adis16405_static_1.csv.gz: 1000000 samples", exact=False)).to_be_visible()
    # 2·10⁵ samples (33 min) keep the browser test short; the CLI test runs the whole log
    _set_number(page, "read at most this many rows", 200_000)
    _set_number(page, "model realizations", 4)
    expect(page.get_by_text("200000 samples at 100 Hz", exact=False)).to_be_visible()
    page.get_by_role("button", name="Run").click()
    result = page.locator("#gap-result")
    expect(result).to_contain_text("effect(s) named", timeout=600_000)
    expect(page.get_by_text("gap before (mean z²)", exact=True)).to_be_visible()
    _idle(page)
    page.screenshot(path=str(ARTIFACTS / "model_gap_real_log.png"), full_page=True)


@pytest.mark.slow
def test_sweep_page_then_report_download_opens_offline(page, dashboard_url, tmp_path):
    from playwright.sync_api import expect

    open_page(page, dashboard_url, "sweep")
    expect(page.get_by_role("heading", name="Trade study")).to_be_visible()
    _set_number(page, "trials per cell", 1)
    page.get_by_role("button", name="Run the sweep").click()
    expect(page.locator("#sweep-grid-done")).to_contain_text("cells")
    page.locator(".js-plotly-plot").first.wait_for()
    _idle(page)
    page.screenshot(path=str(ARTIFACTS / "sweep_page.png"), full_page=True)

    open_page(page, dashboard_url, "monte-carlo")
    _set_number(page, "trials", 1)
    page.get_by_role("button", name="Run Monte Carlo").click()
    page.get_by_role("button", name="Build the report (HTML)").click()
    link = page.get_by_role("button", name="Download the report (opens offline)")
    expect(link).to_be_visible()
    with page.expect_download() as info:
        link.click()
    report = tmp_path / info.value.suggested_filename
    info.value.save_as(str(report))
    assert report.suffix == ".html" and report.stat().st_size > 1_000_000

    offline = page.context.browser.new_context()
    offline.set_offline(True)  # no network at all: plotly.js must come from the file itself
    requests: list[str] = []
    view = offline.new_page()
    view.on("request", lambda r: requests.append(r.url))
    view.goto(report.as_uri())
    expect(view.locator("#check")).to_be_visible()
    expect(view.locator("#provenance")).to_contain_text("sar_imu_budget_version")
    view.locator(".js-plotly-plot .main-svg").first.wait_for()  # drawn by the embedded plotly.js
    assert [u for u in requests if not u.startswith(("file:", "data:", "blob:"))] == []
    view.screenshot(path=str(ARTIFACTS / "report_offline.png"))
    offline.close()


@pytest.mark.parametrize("slug", ["", "catalog", "check", "monte-carlo", "sweep", "noise-lab", "model-gap",
                                  "focus"])
def test_every_page_renders_and_the_menu_shows_them_all(browser, dashboard_url, slug):
    """Each page in a wide window (the top menu lists every page); pictures for the README when
    ``SAR_BUDGET_UPDATE_SCREENSHOT=1``."""
    from playwright.sync_api import expect

    ctx = browser.new_context(viewport={"width": 1900, "height": 1200})
    pg = ctx.new_page()
    pg.set_default_timeout(180_000)
    open_page(pg, dashboard_url, slug)
    _idle(pg)
    expect(pg.get_by_text("Something went wrong")).to_have_count(0)
    for title in ("Scenario & bounds", "Monte Carlo", "Trade study", "Noise lab", "Model gap", "Real SAR data"):
        expect(pg.get_by_role("link", name=title).first).to_be_visible(timeout=30_000)
    name = slug or "scenario"
    ARTIFACTS.mkdir(exist_ok=True)
    pg.screenshot(path=str(ARTIFACTS / f"page_{name}.png"))
    if os.environ.get("SAR_BUDGET_UPDATE_SCREENSHOT") == "1":
        (DOCS / "screenshots").mkdir(parents=True, exist_ok=True)
        pg.screenshot(path=str(DOCS / "screenshots" / f"{name}.png"))
    ctx.close()


@pytest.mark.slow  # CI's second step: 20 s on a fresh clone (fast suite under 10 min on 2 cores)
def test_allan_table_on_noise_lab(page, dashboard_url):
    """A published Allan table (the CLI's second input form) is accepted on the dashboard too."""
    from playwright.sync_api import expect

    table = REPO.parent / "shared" / "data" / "adev" / "adis16405.csv"
    if not table.is_file():
        pytest.skip(f"Allan table not found at {table} (clone without ../shared)")
    open_page(page, dashboard_url, "noise-lab")
    page.get_by_text("upload a log or an Allan table").click()
    # the radio's rerun must end before the file is set: an uploader replaced by a rerun still in
    # flight drops it (the page then waits for an upload that never comes)
    expect(page.get_by_text("Upload a static IMU log or an Allan table", exact=False)).to_be_visible()
    _idle(page)
    _upload(page, table)
    expect(page.locator("#noise-loaded")).to_contain_text("Allan table, 6 channel(s)")
    expect(page.get_by_text("Allan deviation and IEEE-952 terms")).to_be_visible()
    expect(page.get_by_text("Download the catalog row (CSV)")).to_be_visible()
    page.locator(".js-plotly-plot .main-svg").first.wait_for()
    _idle(page)
    page.screenshot(path=str(ARTIFACTS / "noise_lab_allan_table.png"), full_page=True)
