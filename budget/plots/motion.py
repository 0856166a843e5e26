"""Figures of a :class:`~budget.motion.result.MotionResult` (plotly)."""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go
from plotly.subplots import make_subplots

from ..motion.result import MotionResult

_AXES = ("x along-track", "y cross-track", "z up")


def _need_series(result: MotionResult) -> None:
    if result.position_error_m is None or result.range_error_m is None:
        raise ValueError("this figure needs the series: simulate_motion(..., keep_series=True)")


def plot_position_error(result: MotionResult, trials: int = 5) -> go.Figure:
    """APC position error (true − measured, mm) of the first ``trials`` trials, one panel per axis."""
    _need_series(result)
    fig = make_subplots(rows=3, cols=1, shared_xaxes=True, subplot_titles=_AXES)
    for i in range(min(trials, result.n_trials)):
        for ax in range(3):
            fig.add_trace(go.Scatter(x=result.time_s, y=1e3 * result.position_error_m[i, :, ax],
                                     mode="lines", name=f"trial {i}", legendgroup=str(i),
                                     showlegend=ax == 0), row=ax + 1, col=1)
    fig.update_yaxes(title_text="mm")
    fig.update_xaxes(title_text="time in aperture (s)", row=3, col=1)
    fig.update_layout(title=f"APC position error — {result.model_label}, {result.scenario.name}")
    return fig


def plot_phase_error(result: MotionResult, trials: int = 5, target: int = 0) -> go.Figure:
    """Phase error 4πΔr/λ (deg) over the aperture for the first ``trials`` trials."""
    _need_series(result)
    phase = np.degrees(result.phase_error_rad()[:, target])
    fig = go.Figure()
    for i in range(min(trials, result.n_trials)):
        fig.add_trace(go.Scatter(x=result.time_s, y=phase[i], mode="lines", name=f"trial {i}"))
    fig.update_layout(title=f"Phase error to scene point {target} — {result.model_label}",
                      xaxis_title="time in aperture (s)", yaxis_title="phase error (deg)")
    return fig


def plot_metric_histograms(result: MotionResult, target: int = 0) -> go.Figure:
    """Histograms over trials of |quadratic|, |cubic| edge phase (rad), residual rms (deg) and
    peak range error (range cells)."""
    panels = (("quadratic_edge_rad", "|quadratic edge| (rad)"), ("cubic_edge_rad", "|cubic edge| (rad)"),
              ("residual_rms_deg", "residual rms (deg)"), ("peak_range_cells", "peak range error (cells)"))
    fig = make_subplots(rows=2, cols=2, subplot_titles=[p[1] for p in panels])
    for k, (name, _) in enumerate(panels):
        fig.add_trace(go.Histogram(x=np.abs(getattr(result, name)[:, target]), showlegend=False),
                      row=k // 2 + 1, col=k % 2 + 1)
    fig.update_layout(title=f"{result.n_trials} trials — {result.model_label}, {result.scenario.name}")
    return fig
