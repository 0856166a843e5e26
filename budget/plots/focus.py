"""Pictures of a :class:`~budget.sar.focus_pga.FocusResult`: the ground image before/after
autofocus (Plotly, or an 8-bit greyscale array for PNG) and the phase estimate per pulse against
the recorded solution. Ground range u runs left to right (radar to the right), cross range v
bottom to top; magnitudes in dB re. each image's own peak."""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go
from plotly.subplots import make_subplots

from ..sar.focus_pga import FocusResult
from ..sar.png import db_to_gray, write_png

_GAP_PX = 6


def before_after_gray(result: FocusResult, dynamic_range_db: float = 40.0) -> np.ndarray:
    """Before | after, side by side, as uint8 rows top to bottom (v decreasing)."""
    left = db_to_gray(result.before.magnitude_db(), dynamic_range_db)[::-1]
    right = db_to_gray(result.after.magnitude_db(), dynamic_range_db)[::-1]
    gap = np.full((left.shape[0], _GAP_PX), 255, np.uint8)
    return np.concatenate([left, gap, right], axis=1)


def write_before_after_png(result: FocusResult, path, dynamic_range_db: float = 40.0) -> None:
    """PNG (pure zlib writer) of :func:`before_after_gray`."""
    write_png(path, before_after_gray(result, dynamic_range_db))


def image_pair_figure(result: FocusResult, dynamic_range_db: float = 40.0, max_pixels: int = 400) -> go.Figure:
    """Two heatmaps (dB re. own peak), decimated to at most ``max_pixels`` per axis for display."""
    g = result.before.grid
    step = max(1, int(np.ceil(max(g.u_m.size, g.v_m.size) / max_pixels)))
    fig = make_subplots(rows=1, cols=2, shared_yaxes=True, horizontal_spacing=0.04,
                        subplot_titles=(f"before ({result.before.label}), entropy {result.entropy_before:.4g}",
                                        f"after ({result.after.label}), entropy {result.entropy_after:.4g}"))
    for col, img in ((1, result.before), (2, result.after)):
        fig.add_trace(go.Heatmap(z=img.magnitude_db()[::step, ::step], x=g.u_m[::step], y=g.v_m[::step],
                                 zmin=-dynamic_range_db, zmax=0, colorscale="Gray", showscale=col == 2,
                                 colorbar={"title": "dB"}), row=1, col=col)
        fig.update_xaxes(title_text="ground range u (m)", scaleanchor=f"y{'' if col == 1 else col}",
                         row=1, col=col)
    fig.update_yaxes(title_text="cross range v (m)", row=1, col=1)
    fig.update_layout(template="plotly_white", height=520)
    return fig


def phase_figure(result: FocusResult) -> go.Figure:
    """Estimated phase error per pulse against the recorded solution and, after an injection, the
    known error (recorded + injected) (all beyond linear, rad)."""
    n = np.arange(result.pulses)
    fig = go.Figure()
    if result.recorded_phase_error_rad is not None:
        fig.add_trace(go.Scatter(x=n, y=result.recorded_phase_error_rad, mode="lines", name="recorded solution",
                                 line={"width": 1, "color": "#999"}))
    if result.known_phase_error_rad is not None:
        ref = result.comparison.get("known", {}).get("reference", "known")
        fig.add_trace(go.Scatter(x=n, y=result.known_phase_error_rad, mode="lines", name=f"known error ({ref})",
                                 line={"width": 1.5, "color": "#1f77b4", "dash": "dash"}))
    est = np.where(result.estimated_pulses, result.phase_estimate_rad, np.nan)
    fig.add_trace(go.Scatter(x=n, y=est, mode="lines", name=f"estimate ({result.autofocus})",
                             line={"width": 2, "color": "#d62728"}))
    diff = result.recorded_af_rms_diff_rad
    title = "phase error per pulse (constant and linear removed)"
    if diff is not None:
        title += f": rms difference {diff:.3g} rad"
    fig.update_layout(template="plotly_white", title=title, xaxis_title="pulse", yaxis_title="phase error (rad)",
                      height=380)
    return fig
