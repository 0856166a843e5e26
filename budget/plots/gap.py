"""Figures of the model-gap workflow (plotly): measured vs model, before and after.

* :func:`adev_figure` — measured Allan deviation with its ±1σ band (from the EDF) against the
  mean of the simulated realizations of the base and of the updated model;
* :func:`psd_figure` — measured Welch PSD against the same two models;
* :func:`gap_figure` — gap per channel before/after with the null threshold;
* :func:`z_figure` — the standardized differences of one channel's statistics;
* :func:`write_figures` — all of them as HTML files in a directory.
Units: rad/s (gyro) and m/s² (accelerometer); PSD in unit²/Hz.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import plotly.graph_objects as go

from ..gap.metric import adev_variance
from ..gap.report import GapReport
from ..units import channel_si_unit
from .export import write_html

MEASURED = "#1f1f1f"
BEFORE = "#d62728"
AFTER = "#2ca02c"


def _unit(channel: str) -> str:
    return channel_si_unit(channel)


def adev_figure(report: GapReport, channel: str) -> go.Figure:
    c = report.channels[channel]
    tau = c.grid.tau_s
    meas = np.sqrt(c.measured.avar)
    v = 0.5 / c.measured.edf if c.measured.edf is not None else adev_variance(c.model_before, c.grid)
    fig = go.Figure()
    fig.add_trace(go.Scatter(x=np.concatenate([tau, tau[::-1]]),
                             y=np.concatenate([meas * np.exp(np.sqrt(v)), (meas * np.exp(-np.sqrt(v)))[::-1]]),
                             fill="toself", line=dict(width=0), fillcolor="rgba(0,0,0,0.12)",
                             name="measured ±1σ", hoverinfo="skip"))
    fig.add_trace(go.Scatter(x=tau, y=meas, mode="lines+markers", name="measured",
                             line=dict(color=MEASURED)))
    fig.add_trace(go.Scatter(x=tau, y=np.exp(c.model_before.ln_adev), mode="lines", name="model before",
                             line=dict(color=BEFORE, dash="dash")))
    if report.steps:
        fig.add_trace(go.Scatter(x=tau, y=np.exp(c.model_after.ln_adev), mode="lines", name="model after",
                                 line=dict(color=AFTER)))
    fig.update_layout(title=f"{channel}: Allan deviation, gap {c.gap_before:.3g} → {c.gap_after:.3g}",
                      xaxis=dict(type="log", title="τ (s)"),
                      yaxis=dict(type="log", title=f"σ(τ) ({_unit(channel)})"), template="plotly_white")
    return fig


def psd_figure(report: GapReport, channel: str) -> go.Figure:
    c = report.channels[channel]
    fig = go.Figure()
    if c.measured.psd is None:
        fig.update_layout(title=f"{channel}: no PSD (Allan-table input)")
        return fig
    f = c.grid.freq_hz
    sel = slice(1, None)
    fig.add_trace(go.Scatter(x=f[sel], y=c.measured.psd[sel], mode="lines", name="measured",
                             line=dict(color=MEASURED, width=1)))
    fig.add_trace(go.Scatter(x=f[sel], y=c.model_before.psd[sel], mode="lines", name="model before",
                             line=dict(color=BEFORE, dash="dash")))
    if report.steps:
        fig.add_trace(go.Scatter(x=f[sel], y=c.model_after.psd[sel], mode="lines", name="model after",
                                 line=dict(color=AFTER)))
    fig.update_layout(title=f"{channel}: Welch PSD (one-sided)", xaxis=dict(type="log", title="f (Hz)"),
                      yaxis=dict(type="log", title=f"S(f) (({_unit(channel)})²/Hz)"), template="plotly_white")
    return fig


def gap_figure(report: GapReport) -> go.Figure:
    chans = list(report.channels)
    fig = go.Figure()
    fig.add_trace(go.Bar(x=chans, y=[report.channels[c].gap_before for c in chans], name="before",
                         marker_color=BEFORE))
    fig.add_trace(go.Bar(x=chans, y=[report.channels[c].gap_after for c in chans], name="after",
                         marker_color=AFTER))
    thr = [report.null_after.channel_threshold(c) for c in chans]
    fig.add_trace(go.Scatter(x=chans, y=thr, mode="markers", name="null threshold",
                             marker=dict(symbol="line-ew-open", size=30, color="black")))
    fig.update_layout(title=f"gap per channel: overall {report.gap_before:.3g} → {report.gap_after:.3g}",
                      yaxis=dict(type="log", title="gap (mean z²)"), barmode="group", template="plotly_white")
    return fig


def z_figure(report: GapReport, channel: str) -> go.Figure:
    c = report.channels[channel]
    labels = [f"{k}: {w}" for k, w in zip(c.terms_before.kind, c.terms_before.where)]
    fig = go.Figure()
    fig.add_trace(go.Bar(x=labels, y=c.terms_before.z, name="before", marker_color=BEFORE))
    fig.add_trace(go.Bar(x=labels, y=c.terms_after.z, name="after", marker_color=AFTER))
    fig.add_hline(y=3, line_dash="dot")
    fig.add_hline(y=-3, line_dash="dot")
    fig.update_layout(title=f"{channel}: standardized differences z (measured − model)",
                      yaxis_title="z", barmode="group", template="plotly_white")
    return fig


def write_figures(report: GapReport, directory: Path) -> list[Path]:
    """Write gap, ADEV, PSD and z figures as standalone HTML files; returns the paths."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    figs = {"gap.html": gap_figure(report)}
    for ch in report.channels:
        figs[f"{ch}_adev.html"] = adev_figure(report, ch)
        figs[f"{ch}_psd.html"] = psd_figure(report, ch)
        figs[f"{ch}_z.html"] = z_figure(report, ch)
    out = []
    for name, fig in figs.items():
        path = directory / name
        # offline: plotly.min.js written once beside the figures, never loaded from a CDN
        write_html(fig, path, plotlyjs="beside")
        out.append(path)
    return out
