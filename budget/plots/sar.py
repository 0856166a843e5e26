"""SAR figures (plotly): image in dB, IRF cuts against the ideal, PGA phase estimate against truth."""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go
from plotly.subplots import make_subplots

from ..sar.geometry import SarGeometry
from ..sar.image import SarImage
from ..sar.metrics import irf_cuts
from ..sar.pga import PgaResult
from ..sar.phase import remove_linear
from ..sar.scene import Scene


def image_figure(image: SarImage, *, dynamic_range_db: float = 50.0, title: str | None = None) -> go.Figure:
    """Magnitude in dB re. the image peak; x: slant-range offset (m), y: azimuth (m)."""
    mag = image.magnitude_db()
    mag = mag - mag.max()
    fig = go.Figure(go.Heatmap(z=mag, x=image.range_offset_m, y=image.azimuth_m, zmin=-dynamic_range_db,
                               zmax=0, colorscale="Gray", colorbar={"title": "dB"}))
    fig.update_layout(title=title or f"SAR image ({image.method})", xaxis_title="slant-range offset (m)",
                      yaxis_title="azimuth (m)", template="plotly_white")
    return fig


def irf_cuts_figure(image: SarImage, geom: SarGeometry, scene: Scene, index: int = 0,
                    *, span_cells: float = 10.0) -> go.Figure:
    """Azimuth and range cuts through target ``index`` with the window's ideal response."""
    c = irf_cuts(image, geom, scene, index)
    fig = make_subplots(rows=1, cols=2, subplot_titles=("azimuth cut", "range cut"))
    for col, (ax, win) in enumerate((("azimuth", geom.window_azimuth), ("range", geom.window_range)), start=1):
        x, y, cell = c[f"{ax}_offset_m"], c[f"{ax}_db"], float(c[f"{ax}_cell_m"])
        keep = np.abs(x) <= span_cells * cell
        order = np.argsort(x[keep])
        fig.add_trace(go.Scatter(x=x[keep][order], y=y[keep][order], name=f"{ax} measured",
                                 mode="lines"), row=1, col=col)
        xi = np.linspace(-span_cells, span_cells, 2001)
        ideal = 20 * np.log10(np.maximum(np.abs(win.impulse_response(xi)), 1e-6))
        fig.add_trace(go.Scatter(x=xi * cell, y=ideal, name=f"{ax} ideal ({win.label})",
                                 line={"dash": "dot"}), row=1, col=col)
        fig.update_xaxes(title_text="offset from peak (m)", row=1, col=col)
    fig.update_yaxes(title_text="dB re. target amplitude", range=[-60, 3])
    fig.update_layout(title=f"impulse response, target {index}", template="plotly_white")
    return fig


def phase_error_figure(result: PgaResult, image: SarImage, truth_rad=None) -> go.Figure:
    """PGA's estimate (constant and linear terms removed) against slow time, with the truth
    (per bin, e.g. from :func:`budget.sar.phase.phase_on_bins`) and their difference."""
    t = image.slow_time_of_bins_s()
    mask = result.estimated_bins & image.aperture_mask()
    est = remove_linear(result.phase_error_rad, mask)
    fig = go.Figure(go.Scatter(x=t[mask], y=est[mask], name="PGA estimate", mode="lines"))
    if truth_rad is not None:
        tru = remove_linear(np.asarray(truth_rad, dtype=float), mask)
        fig.add_trace(go.Scatter(x=t[mask], y=tru[mask], name="truth", line={"dash": "dash"}))
        fig.add_trace(go.Scatter(x=t[mask], y=(est - tru)[mask] - np.nanmean((est - tru)[mask]),
                                 name="estimate − truth"))
    fig.update_layout(title=f"phase error ({result.reason})", xaxis_title="slow time (s)",
                      yaxis_title="phase (rad), constant and linear terms removed", template="plotly_white")
    return fig
