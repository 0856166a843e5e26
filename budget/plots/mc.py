"""Figures of a Monte Carlo verdict (:func:`budget.mc.run_mc`): P(pass) with intervals, metric
distributions and the worst-trial inspector (images before/after PGA, phase truth vs. estimate).

The numbers come from :class:`budget.mc.McResult` and from the ``detail`` a run keeps for its
worst trials (``keep_detail=True``, see :func:`budget.mc.chain.run_trial_errors`); these
functions only draw them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import plotly.graph_objects as go
from plotly.subplots import make_subplots

from ..mc import McResult
from ..sar.phase import remove_linear

#: Keys a worst trial's ``detail`` must hold for the inspector figures.
DETAIL_KEYS = ("image_before_db", "image_after_db", "azimuth_m", "slant_range_m",
               "phase_truth_rad", "phase_estimate_rad")

#: Per-trial metric → axis label (unit).
METRIC_LABELS: dict[str, str] = {
    "azimuth_broadening": "azimuth broadening (fraction of the ideal width)",
    "range_broadening": "range broadening (fraction of the ideal width)",
    "pslr_db": "PSLR (dB)",
    "islr_db": "ISLR (dB)",
    "peak_loss_db": "peak loss (dB)",
    "residual_phase_rms_deg": "fast residual phase rms (deg)",
    "pga_error_rms_deg": "PGA estimate − truth rms (deg)",
    "fast_phase_rms_deg": "true phase beyond PGA's window rms (deg)",
}


def has_detail(detail: Mapping) -> bool:
    """True when ``detail`` holds everything the inspector figures draw."""
    return all(k in detail for k in DETAIL_KEYS)


def pass_probability_figure(results: Mapping[str, McResult]) -> go.Figure:
    """P(pass) before and after PGA per part, with the 95 % Wilson intervals as error bars."""
    names = list(results)
    fig = go.Figure()
    for when, colour in (("before", "#9e9e9e"), ("after", "#1b7837")):
        p = np.array([getattr(results[n], f"p_pass_{when}") for n in names], float)
        ci = np.array([getattr(results[n], f"ci_{when}") for n in names], float).reshape(-1, 2)
        fig.add_trace(go.Bar(x=names, y=p, name=f"{when} PGA", marker_color=colour,
                             error_y=dict(type="data", symmetric=False, array=ci[:, 1] - p,
                                          arrayminus=p - ci[:, 0])))
    fig.update_layout(title="P(pass) with 95 % Wilson interval", barmode="group",
                      yaxis=dict(title="P(pass)", range=[0, 1.05]), xaxis_title="part",
                      template="plotly_white")
    return fig


def metric_histogram_figure(values: Mapping[str, Sequence[float]], metric: str) -> go.Figure:
    """Histogram over trials of ``metric`` after PGA, one trace per part (``{part: values}``)."""
    fig = go.Figure()
    for name, vals in values.items():
        v = np.asarray(vals, float)
        fig.add_trace(go.Histogram(x=v[np.isfinite(v)], name=name, opacity=0.7))
    fig.update_layout(title=f"{metric} after PGA over trials", barmode="overlay",
                      xaxis_title=METRIC_LABELS.get(metric, metric), yaxis_title="trials",
                      template="plotly_white")
    return fig


def trial_images_figure(detail: Mapping, *, dynamic_range_db: float = 50.0,
                        title: str | None = None) -> go.Figure:
    """Image magnitude before and after PGA side by side, dB re. each image's peak;
    x: slant range (m), y: azimuth (m). ``detail`` is a worst trial's ``TrialOutcome.detail``."""
    fig = make_subplots(rows=1, cols=2, subplot_titles=("before PGA", "after PGA"),
                        shared_yaxes=True, horizontal_spacing=0.04)
    for col, key in enumerate(("image_before_db", "image_after_db"), start=1):
        mag = np.asarray(detail[key], float)
        fig.add_trace(go.Heatmap(z=mag - np.nanmax(mag), x=detail["slant_range_m"], y=detail["azimuth_m"],
                                 zmin=-dynamic_range_db, zmax=0.0, colorscale="Gray",
                                 colorbar=dict(title="dB"), showscale=col == 2), row=1, col=col)
        fig.update_xaxes(title_text="slant range (m)", row=1, col=col)
    fig.update_yaxes(title_text="azimuth (m)", row=1, col=1)
    fig.update_layout(title=title or "image (dB re. peak)", template="plotly_white")
    return fig


def trial_phase_figure(detail: Mapping, *, title: str | None = None) -> go.Figure:
    """Phase error per azimuth bin: truth against the PGA estimate (deg), constant and linear
    terms removed (they only shift the image), over the bins where both exist."""
    truth = np.asarray(detail["phase_truth_rad"], float)
    est = np.asarray(detail["phase_estimate_rad"], float)
    mask = np.isfinite(truth) & np.isfinite(est)
    x = np.asarray(detail["azimuth_m"], float)
    fig = go.Figure()
    if mask.sum() >= 3:
        tru = np.degrees(remove_linear(truth, mask))
        est_d = np.degrees(remove_linear(est, mask))
        fig.add_trace(go.Scatter(x=x[mask], y=tru[mask], name="truth", mode="lines",
                                 line=dict(dash="dash")))
        fig.add_trace(go.Scatter(x=x[mask], y=est_d[mask], name="PGA estimate", mode="lines"))
        fig.add_trace(go.Scatter(x=x[mask], y=(est_d - tru)[mask], name="estimate − truth",
                                 mode="lines", line=dict(width=1)))
    fig.update_layout(title=title or "phase error: truth vs. PGA estimate", xaxis_title="azimuth (m)",
                      yaxis_title="phase (deg), constant and linear removed", template="plotly_white")
    return fig
