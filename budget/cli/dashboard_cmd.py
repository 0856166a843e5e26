"""``sar-budget dashboard``: start the Streamlit dashboard headless and print its URL.

The app lives in ``app/`` at the repository root (found there for a source checkout or an
editable install) or, in a wheel, in ``budget/_app``. The server runs in a child process; this
command prints the URL once the server answers its health check and stops it on Ctrl+C.
"""

from __future__ import annotations

import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

from ..errors import InputError

DEFAULT_PORT = 8501
DEFAULT_ADDRESS = "127.0.0.1"
#: Upload limit in MB: the server's ``--server.maxUploadSize`` and the limit every log/Allan-table
#: widget of the dashboard states and enforces (one constant; a real 10⁶-row log is ≈ 8 MB
#: gzipped, ≈ 70 MB as plain CSV). The catalog page has its own smaller limit for parts CSVs.
MAX_UPLOAD_MB = 200
READY_TIMEOUT_S = 90.0


def find_app() -> Path:
    """Path of the dashboard's ``main.py`` (installed copy first, then the source tree)."""
    pkg = Path(__file__).resolve().parent.parent
    for cand in (pkg / "_app" / "main.py", pkg.parent / "app" / "main.py"):
        if cand.is_file():
            return cand
    raise InputError("dashboard app not found", file=str(pkg.parent / "app" / "main.py"),
                     expected="app/main.py in the source tree or budget/_app when installed")


def port_is_free(address: str, port: int) -> bool:
    """True if a server could listen on ``address:port`` now (ports in TIME_WAIT count as free,
    as servers bind with SO_REUSEADDR)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind((address, port))
        except OSError:
            return False
    return True


def free_port(address: str = DEFAULT_ADDRESS) -> int:
    """A port the OS says is free right now on ``address``."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind((address, 0))
        return int(s.getsockname()[1])


def build_command(app: Path, port: int, address: str = DEFAULT_ADDRESS) -> list[str]:
    """``streamlit run`` command line: headless, no usage statistics, uploads ≤ :data:`MAX_UPLOAD_MB`,
    no tracebacks."""
    return [sys.executable, "-m", "streamlit", "run", str(app),
            "--server.headless=true", f"--server.port={port}", f"--server.address={address}",
            "--browser.gatherUsageStats=false", f"--server.maxUploadSize={MAX_UPLOAD_MB}",
            "--client.showErrorDetails=none", "--client.toolbarMode=viewer",
            "--server.fileWatcherType=none", "--global.developmentMode=false"]


def wait_ready(url: str, proc: subprocess.Popen, timeout_s: float = READY_TIMEOUT_S) -> bool:
    """Poll ``url/_stcore/health`` until it answers ``ok``; False if the server died or timed out."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            return False
        try:
            with urllib.request.urlopen(f"{url}/_stcore/health", timeout=2) as r:
                if r.status == 200:
                    return True
        except (urllib.error.URLError, ConnectionError, TimeoutError, OSError):
            pass
        time.sleep(0.3)
    return False


def _raise_interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


def add_parser(sub) -> None:
    p = sub.add_parser("dashboard", help="start the interactive dashboard and print its URL",
                       description="Start the Streamlit dashboard (headless) and print its URL.")
    p.add_argument("--port", type=int, default=None, metavar="P",
                   help=f"port (default {DEFAULT_PORT}, or a free one if that is taken)")
    p.add_argument("--address", default=DEFAULT_ADDRESS,
                   help=f"address to listen on (default {DEFAULT_ADDRESS}; 0.0.0.0 for other machines)")
    p.set_defaults(func=run)


def run(args) -> int:
    app = find_app()
    address = args.address
    if args.port is None:
        port = DEFAULT_PORT if port_is_free(address, DEFAULT_PORT) else free_port(address)
    else:
        port = int(args.port)
        if not 1 <= port <= 65535:
            raise InputError("port out of range", field="--port", value=port, expected="1 … 65535")
        if not port_is_free(address, port):
            raise InputError("port is already in use", field="--port", value=port,
                             expected="a free port (or omit --port)")
    host = "localhost" if address in ("127.0.0.1", "localhost") else address
    url = f"http://{host}:{port}"
    proc = subprocess.Popen(build_command(app, port, address), stdout=subprocess.DEVNULL)
    # A plain `kill` must stop the server too, not orphan it: turn SIGTERM into the Ctrl+C path.
    previous = signal.signal(signal.SIGTERM, _raise_interrupt)
    try:
        if not wait_ready(f"http://127.0.0.1:{port}" if address in ("0.0.0.0", "::") else url, proc):
            proc.terminate()
            proc.wait(timeout=10)
            print(f"sar-budget dashboard: the server did not start (exit code {proc.returncode}); "
                  "see the messages above", file=sys.stderr)
            return 1
        print(f"Dashboard running at {url}  (Ctrl+C to stop)", flush=True)
        return proc.wait()
    except KeyboardInterrupt:
        print("stopping the dashboard", file=sys.stderr)
        return 0
    finally:
        signal.signal(signal.SIGTERM, previous)
        if proc.poll() is None:
            proc.terminate()
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
