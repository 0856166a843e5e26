"""Figures of the aiding results (plotly)."""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go

from .chain import AidedResult

_FIELDS = {"position": ("position_error_m", 0, "m"), "velocity": ("velocity_error_m_s", 3, "m/s"),
           "attitude": ("attitude_error_rad", 6, "rad")}


def plot_error_history(result: AidedResult, quantity: str = "position", axis: int = 0,
                       trials: int = 5) -> go.Figure:
    """A few trials' errors of one axis with the predicted ±1σ envelope."""
    name, off, unit = _FIELDS[quantity]
    err = getattr(result, name)[:, :, axis]
    t = result.time_s
    fig = go.Figure()
    for i in range(min(trials, err.shape[0])):
        fig.add_scatter(x=t, y=err[i], mode="lines", name=f"trial {i}", line={"width": 1})
    sig = result.sigma[:, off + axis]
    fig.add_scatter(x=t, y=sig, mode="lines", name="+1σ", line={"dash": "dash", "color": "black"})
    fig.add_scatter(x=t, y=-sig, mode="lines", name="−1σ", line={"dash": "dash", "color": "black"})
    fig.update_layout(title=f"{quantity} error, axis {'xyz'[axis]} ({result.method})",
                      xaxis_title="time (s)", yaxis_title=f"{quantity} error ({unit})")
    return fig


def plot_rms_comparison(results: dict[str, AidedResult], quantity: str = "attitude",
                        axis: int = 2) -> go.Figure:
    """RMS over trials versus time of one axis for several estimators (e.g. KF vs RTS)."""
    name, _, unit = _FIELDS[quantity]
    fig = go.Figure()
    for label, res in results.items():
        rms = np.sqrt(np.mean(getattr(res, name)[:, :, axis] ** 2, axis=0))
        fig.add_scatter(x=res.time_s, y=rms, mode="lines", name=label)
    fig.update_layout(title=f"RMS {quantity} error, axis {'xyz'[axis]}", xaxis_title="time (s)",
                      yaxis_title=f"RMS ({unit})", yaxis_type="log")
    return fig
