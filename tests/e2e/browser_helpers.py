"""Helpers of the browser tests (imported by the test modules; not a test module)."""

from __future__ import annotations


def open_page(page, base_url: str, slug: str = "") -> None:
    """Open ``base_url/slug`` reliably. A session's first request for a page URL can reach the
    server before the app has declared its pages (``st.navigation`` runs in the script), which
    shows a "Page not found" dialog that makes the page inert; the main page first avoids it."""
    from playwright.sync_api import expect

    page.goto(base_url)
    expect(page.locator("h1").first).to_be_visible()
    if slug:
        page.goto(f"{base_url}/{slug}")
        expect(page.locator("h1").first).to_be_visible()
    page.wait_for_function(IDLE_JS)
    dialog = page.get_by_role("dialog")
    if dialog.count():  # dismiss it should it still appear: it only says the main page ran
        page.keyboard.press("Escape")
        expect(dialog).to_have_count(0)


IDLE_JS = ("() => !document.querySelector('[data-testid=\"stStatusWidget\"]') && "
           "!document.querySelector('[data-testid=\"stSkeleton\"]')")


def idle(page) -> None:
    """Wait until Streamlit has finished its run: no running-status widget, no loading skeleton."""
    page.wait_for_function(IDLE_JS)
