"""Plotly figures of the noise lab (each function returns a ``go.Figure``).

* :func:`allan_figure` — overlapping Allan deviation with confidence band and the IEEE-952 fit;
* :func:`psd_figure` — one-sided Welch PSD;
* :func:`filter_figure` — measured vs ARMA-Kalman filtered/smoothed series (seed 000 §3.2);
* :func:`response_figure` — steady-state filter/smoother frequency response;
* :func:`arma_criteria_figure` — the ARMA candidates' AIC/FPE (seed 000 §3.1, Table 1);
* :func:`preprocess_figure` — the series before/after preprocessing (seed 000 §3.1: Pauta
  outliers, trend, mean).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import plotly.graph_objects as go
from plotly.subplots import make_subplots

from ..noise import ArmaSelection, Preprocessed
from ..noise.allan import AllanResult
from ..noise.kalman import KalmanResult
from ..noise.kalman_response import FrequencyResponse
from ..noise.psd import PsdResult
from ..noise.terms import TERMS, NoiseTerms, adev_model


def allan_figure(results: Mapping[str, AllanResult] | AllanResult,
                 fits: Mapping[str, NoiseTerms] | None = None, *, show_terms: bool = False) -> go.Figure:
    """Allan deviation per channel (log-log) with confidence band and, if given, the fit."""
    if isinstance(results, AllanResult):
        results = {results.channel or "series": results}
    fig = go.Figure()
    for ch, r in results.items():
        fig.add_trace(go.Scatter(x=r.tau_s, y=r.adev, mode="markers+lines", name=f"{ch}",
                                 error_y=dict(type="data", symmetric=False, array=r.hi - r.adev,
                                              arrayminus=r.adev - r.lo)))
        fit = (fits or {}).get(ch)
        if fit is not None:
            tau = np.logspace(np.log10(r.tau_s[0]), np.log10(r.tau_s[-1]), 200)
            fig.add_trace(go.Scatter(x=tau, y=fit.model_adev(tau), mode="lines",
                                     line=dict(dash="dash"), name=f"{ch} IEEE-952 fit"))
            if show_terms:
                for t in TERMS:
                    v = fit.values[t]
                    if v:
                        fig.add_trace(go.Scatter(x=tau, y=adev_model(tau, **{t: v}), mode="lines",
                                                 line=dict(dash="dot", width=1), name=f"{ch} {t}"))
    unit = next(iter(results.values())).unit
    fig.update_layout(title="Overlapping Allan deviation", xaxis_title="τ (s)",
                      yaxis_title=f"σ(τ) ({unit})", xaxis_type="log", yaxis_type="log")
    return fig


def psd_figure(results: Mapping[str, PsdResult] | PsdResult) -> go.Figure:
    """One-sided Welch PSD per channel (log-log)."""
    if isinstance(results, PsdResult):
        results = {results.channel or "series": results}
    fig = go.Figure()
    for ch, r in results.items():
        sel = r.freq_hz > 0
        fig.add_trace(go.Scatter(x=r.freq_hz[sel], y=r.psd[sel], mode="lines", name=ch))
    unit = next(iter(results.values())).unit
    fig.update_layout(title="Power spectral density (Welch, one-sided)", xaxis_title="f (Hz)",
                      yaxis_title=f"PSD ({unit}²/Hz)", xaxis_type="log", yaxis_type="log")
    return fig


def filter_figure(z, result: KalmanResult, rate_hz: float, *, max_points: int = 20000,
                  unit: str = "") -> go.Figure:
    """Measured vs filtered/smoothed series (decimated for display, every k-th sample)."""
    z = np.asarray(z, float)
    step = max(1, z.size // max_points)
    t = np.arange(0, z.size, step) / rate_hz
    what = "smoothed" if result.smoothed else "filtered"
    fig = go.Figure([go.Scatter(x=t, y=z[::step], mode="lines", name="measured", opacity=0.6),
                     go.Scatter(x=t, y=result.signal[::step], mode="lines", name=what)])
    fig.update_layout(title=f"ARMA Kalman {what}: variance {result.variance_before:.3g} → "
                            f"{result.variance_after:.3g}", xaxis_title="t (s)",
                      yaxis_title=unit or "value")
    return fig


def response_figure(*responses: FrequencyResponse) -> go.Figure:
    """|H(f)| in dB of the steady-state filter and/or smoother: what happens to real motion."""
    fig = go.Figure()
    for r in responses:
        fig.add_trace(go.Scatter(x=r.freq_hz, y=20 * np.log10(np.maximum(r.magnitude, 1e-12)),
                                 mode="lines", name="RTS smoother" if r.smoother else "Kalman filter"))
    fig.add_hline(y=-3.0, line_dash="dot")
    fig.update_layout(title="Response to motion (steady state)", xaxis_title="f (Hz)",
                      yaxis_title="|H| (dB)")
    return fig


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
