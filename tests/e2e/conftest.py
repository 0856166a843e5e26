"""Browser tests of the dashboard: a real ``sar-budget dashboard`` server driven by headless
Chromium (Debian's ``chromium`` package) through Playwright. Skipped, with the reason, when
either is missing. Screenshots go to ``test-artifacts/`` (gitignored)."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
ARTIFACTS = REPO / "test-artifacts"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync"]
#: Runs ``sar-budget dashboard`` (whether or not the CLI's command list includes it yet).
LAUNCH = ("import argparse, sys\n"
          "from budget.cli import dashboard_cmd as d\n"
          "p = argparse.ArgumentParser(); d.add_parser(p.add_subparsers())\n"
          "a = p.parse_args(['dashboard'] + sys.argv[1:])\n"
          "sys.exit(a.func(a))\n")


def pytest_configure(config):
    config.addinivalue_line("markers", "e2e: drives the dashboard in a headless browser (needs chromium, playwright)")


def chromium_path() -> str | None:
    for cand in (shutil.which("chromium"), "/usr/bin/chromium"):
        if cand and Path(cand).is_file():
            return cand
    return None


@pytest.fixture(scope="session")
def browser():
    exe = chromium_path()
    if exe is None:
        pytest.skip("Debian's chromium is not installed (apt-get install -y chromium)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed (pip install playwright)")
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS)
        yield b
        b.close()


@pytest.fixture(scope="session")
def dashboard_url():
    """URL of a dashboard started with the real command on a free localhost port."""
    from budget.cli.dashboard_cmd import free_port

    port = free_port()
    env = {**os.environ, "PYTHONPATH": str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.Popen([sys.executable, "-c", LAUNCH, "--port", str(port)], cwd=REPO, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        line = proc.stdout.readline()
        if not line.startswith("Dashboard running at "):
            pytest.fail(f"dashboard did not start: {line!r}")
        yield line.split()[3]
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=30)


#: Generous waits: the browser tests wait on what the page shows, never on fixed sleeps, and a
#: loaded 2-core machine (other jobs, the Monte Carlo itself) may take minutes for a real log.
WAIT_MS = 180_000


@pytest.fixture
def page(browser):
    from playwright.sync_api import expect

    ARTIFACTS.mkdir(exist_ok=True)
    expect.set_options(timeout=WAIT_MS)  # Playwright's default for expect() is 5 s
    ctx = browser.new_context(viewport={"width": 1500, "height": 2000}, accept_downloads=True)
    pg = ctx.new_page()
    pg.set_default_timeout(WAIT_MS)
    yield pg
    ctx.close()

