"""Noise-lab figures not in :mod:`budget.noise.plots`: the ARMA candidates' AIC/FPE and the
series before/after preprocessing (seed 000 §3.1: Pauta outliers, trend, mean).

Allan deviation with the IEEE-952 fit, PSD, Kalman filtering and the filter's frequency
response are drawn by :mod:`budget.noise.plots` (``allan_figure``, ``psd_figure``,
``filter_figure``, ``response_figure``).
"""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go
from plotly.subplots import make_subplots

from ..noise import ArmaSelection, Preprocessed


def arma_criteria_figure(selection: ArmaSelection) -> go.Figure:
    """AIC and FPE of every ARMA candidate (seed 000 §3.1, Table 1); the selected one highlighted."""
    names = [c.name for c in selection.candidates]
    colours = ["#1b7837" if c is selection.selected else "#9e9e9e" for c in selection.candidates]
    fig = make_subplots(rows=1, cols=2, subplot_titles=("AIC (selects)", "FPE"))
    fig.add_trace(go.Bar(x=names, y=[c.aic for c in selection.candidates], marker_color=colours,
                         showlegend=False), row=1, col=1)
    fig.add_trace(go.Bar(x=names, y=[c.fpe for c in selection.candidates], marker_color=colours,
                         showlegend=False), row=1, col=2)
    fig.update_layout(title=f"ARMA candidates — selected {selection.selected.name} (green)",
                      template="plotly_white")
    return fig


def preprocess_figure(raw, pre: Preprocessed, rate_hz: float, *, max_points: int = 20000,
                      unit: str = "") -> go.Figure:
    """Raw series and the preprocessed one against time (every k-th sample shown), outliers
    replaced by the Pauta criterion marked on the raw series."""
    raw = np.asarray(raw, float)
    step = max(1, raw.size // max_points)
    t = np.arange(raw.size) / float(rate_hz)
    fig = go.Figure([
        go.Scatter(x=t[::step], y=raw[::step], mode="lines", name="raw", opacity=0.6),
        go.Scatter(x=t[::step], y=pre.x[::step], mode="lines", name="preprocessed"),
    ])
    if pre.outliers.size:
        fig.add_trace(go.Scatter(x=t[pre.outliers], y=raw[pre.outliers], mode="markers",
                                 name=f"outliers ({pre.outliers.size})", marker=dict(color="red")))
    fig.update_layout(title="Series before and after preprocessing", xaxis_title="t (s)",
                      yaxis_title=unit or "value", template="plotly_white")
    return fig
