"""``sar-budget dashboard``: finds the app, builds a safe command line, starts a server that
answers, prints its URL, and stops the server when it is stopped."""

from __future__ import annotations

import argparse
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

from budget.cli import dashboard_cmd
from budget.errors import InputError

REPO = Path(__file__).resolve().parents[1]

#: Runs the sub-command as the CLI would, whether or not main.py lists it yet.
LAUNCH = ("import argparse, sys\n"
          "from budget.cli import dashboard_cmd as d\n"
          "p = argparse.ArgumentParser(); d.add_parser(p.add_subparsers())\n"
          "a = p.parse_args(['dashboard'] + sys.argv[1:])\n"
          "sys.exit(a.func(a))\n")


def _args(**kw):
    p = argparse.ArgumentParser()
    dashboard_cmd.add_parser(p.add_subparsers())
    argv = ["dashboard"] + [x for k, v in kw.items() for x in (f"--{k}", str(v))]
    return p.parse_args(argv)


def test_find_app_is_the_source_tree_app():
    assert dashboard_cmd.find_app() == REPO / "app" / "main.py"


def test_command_is_headless_local_and_limits_uploads():
    cmd = dashboard_cmd.build_command(REPO / "app" / "main.py", 8765)
    assert cmd[:4] == [sys.executable, "-m", "streamlit", "run"]
    for flag in ("--server.headless=true", "--server.port=8765", "--server.address=127.0.0.1",
                 "--browser.gatherUsageStats=false", f"--server.maxUploadSize={dashboard_cmd.MAX_UPLOAD_MB}",
                 "--client.showErrorDetails=none"):
        assert flag in cmd


def test_upload_limit_is_one_constant_shown_by_the_widgets():
    """The server flag and the widgets' stated and enforced limit are the same number (≥ 64 MB,
    enough for a real 10⁶-row log as plain CSV)."""
    if str(REPO / "app") not in sys.path:
        sys.path.insert(0, str(REPO / "app"))
    import upload_tables

    assert dashboard_cmd.MAX_UPLOAD_MB >= 64
    assert upload_tables.UPLOAD_LIMIT_MB == dashboard_cmd.MAX_UPLOAD_MB
    assert f"at most {dashboard_cmd.MAX_UPLOAD_MB} MB" in upload_tables.upload_label("IMU log")
    # one upload widget for logs and Allan tables, used by both pages, enforcing the one limit
    assert "max_upload_size=UPLOAD_LIMIT_MB" in (REPO / "app" / "upload_tables.py").read_text()
    for page in ("noise_lab.py", "model_gap.py"):
        text = (REPO / "app" / "pages" / page).read_text()
        assert "upload_log_or_table(" in text and "MAX_UPLOAD_MB = " not in text


@pytest.mark.parametrize("port", [0, 70000])
def test_port_out_of_range_is_an_input_error(port):
    with pytest.raises(InputError, match="--port"):
        dashboard_cmd.run(_args(port=port))


def test_busy_port_is_an_input_error():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        with pytest.raises(InputError, match="already in use"):
            dashboard_cmd.run(_args(port=s.getsockname()[1]))


def test_dashboard_starts_prints_its_url_and_stops_with_its_server():
    port = dashboard_cmd.free_port()
    env = {**os.environ, "PYTHONPATH": str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.Popen([sys.executable, "-c", LAUNCH, "--port", str(port)], cwd=REPO, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        line = proc.stdout.readline()  # printed only once the server answers its health check
        url = f"http://localhost:{port}"
        assert line.startswith(f"Dashboard running at {url}"), line
        with urllib.request.urlopen(url, timeout=10) as r:
            assert r.status == 200 and b"<html" in r.read().lower()
    finally:
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=30) == 0
    deadline = time.monotonic() + 15  # the streamlit child went with it
    while time.monotonic() < deadline and not dashboard_cmd.port_is_free("127.0.0.1", port):
        time.sleep(0.2)
    assert dashboard_cmd.port_is_free("127.0.0.1", port)
