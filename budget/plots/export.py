"""Writing figures to files that work offline: HTML with plotly.js, and PNG/SVG where possible.

* :func:`write_html` — standalone HTML. ``plotlyjs="inline"`` embeds plotly.js in the file
  (≈ 4.6 MB, one file that opens anywhere); ``"beside"`` writes ``plotly.min.js`` once next to
  the HTML files and points to it (a folder of many figures stays small). Never a CDN link: the
  figures open on a machine without a network.
* :func:`write_image` — PNG or SVG through plotly's static-image engine (kaleido, which drives a
  local Chromium/Chrome). :func:`static_export_available` says whether it can run here; when it
  cannot, :func:`write_image` raises an :class:`~budget.errors.InputError` saying what to install.
"""

from __future__ import annotations

import functools
import os
import tempfile
from pathlib import Path

from ..errors import InputError
from ..fileio import atomic_write_text

PLOTLY_JS_NAME = "plotly.min.js"
IMAGE_FORMATS = ("png", "svg")


def plotly_js() -> str:
    """The plotly.js bundle shipped with the installed ``plotly`` package (no network)."""
    from plotly.offline import get_plotlyjs

    return get_plotlyjs()


def figure_html(fig, *, plotlyjs: str = "inline", full_html: bool = True) -> str:
    """HTML text of ``fig``; ``plotlyjs`` is ``inline`` (embedded) or ``beside`` (a relative
    ``plotly.min.js`` script tag; see :func:`write_html`)."""
    if plotlyjs == "inline":
        return fig.to_html(include_plotlyjs=True, full_html=full_html)
    if plotlyjs == "beside":
        return fig.to_html(include_plotlyjs="directory", full_html=full_html)
    raise InputError("unknown plotly.js mode", field="plotlyjs", value=plotlyjs, expected="inline or beside")


def write_html(fig, path: str | Path, *, plotlyjs: str = "inline") -> Path:
    """Write ``fig`` as standalone HTML (atomically) that opens offline; returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if plotlyjs == "beside":
        js = path.parent / PLOTLY_JS_NAME
        if not js.is_file():
            atomic_write_text(js, plotly_js())
    atomic_write_text(path, figure_html(fig, plotlyjs=plotlyjs))
    return path


def atomic_write_bytes(path: Path, data: bytes) -> None:
    """Bytes through a temporary file in the same folder and ``os.replace`` (never half-written)."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


@functools.lru_cache(maxsize=1)
def static_export_available() -> tuple[bool, str]:
    """(True, "") when PNG/SVG export works here, else (False, the reason and what to install)."""
    try:
        import kaleido  # noqa: F401
    except ImportError:
        return False, "static image export needs kaleido (pip install 'sar-imu-budget[images]') and Chromium"
    import plotly.graph_objects as go

    try:
        go.Figure(go.Scatter(x=[0, 1], y=[0, 1])).to_image(format="svg", width=50, height=50)
    except Exception as err:  # noqa: BLE001 — kaleido reports a missing browser in several ways
        return False, f"static image export is not available ({type(err).__name__}: {err}); kaleido needs a Chromium or Chrome"
    return True, ""


def figure_image(fig, fmt: str = "png", *, width: int = 1000, height: int = 600) -> bytes:
    """PNG or SVG bytes of ``fig`` (kaleido); InputError when the engine is not available."""
    if fmt not in IMAGE_FORMATS:
        raise InputError("unknown image format", field="format", value=fmt, expected="png or svg")
    ok, why = static_export_available()
    if not ok:
        raise InputError(why, field="format", value=fmt, expected="HTML export (always available)")
    return fig.to_image(format=fmt, width=width, height=height)


def write_image(fig, path: str | Path, *, width: int = 1000, height: int = 600) -> Path:
    """Write ``fig`` as PNG or SVG (by the suffix of ``path``), atomically; returns the path."""
    path = Path(path)
    data = figure_image(fig, path.suffix.lstrip(".").lower(), width=width, height=height)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(path, data)
    return path
