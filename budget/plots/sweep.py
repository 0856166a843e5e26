"""Figures of a trade study (a :func:`budget.sweep` table): P(pass) heat map parts × scenarios, and
P(pass) against one varied scenario quantity with its 95 % Wilson interval."""

from __future__ import annotations

import numpy as np
import pandas as pd
import plotly.graph_objects as go

from ..errors import InputError

P_COL, LO_COL, HI_COL = "p_pass_after", "ci_after_lo", "ci_after_hi"


def _need(table: pd.DataFrame, cols) -> None:
    missing = [c for c in cols if c not in table.columns]
    if missing:
        raise InputError(f"sweep table lacks column(s) {', '.join(missing)}", field="table",
                         expected="a table from budget.sweep")


def pass_heatmap_figure(table: pd.DataFrame, *, value: str = P_COL) -> go.Figure:
    """P(pass after PGA) per part (rows) × scenario (columns), the interval in the hover text."""
    _need(table, ("part_id", "scenario", value, LO_COL, HI_COL))
    parts = list(dict.fromkeys(table["part_id"]))
    scens = list(dict.fromkeys(table["scenario"]))
    z = np.full((len(parts), len(scens)), np.nan)
    text = np.full(z.shape, "", dtype=object)
    for _, r in table.iterrows():
        i, j = parts.index(r["part_id"]), scens.index(r["scenario"])
        z[i, j] = r[value]
        text[i, j] = (f"{r[value]:.2f} [{r[LO_COL]:.2f}, {r[HI_COL]:.2f}]" if np.isfinite(r[value])
                      else "not simulated")  # the table's status column says why
    fig = go.Figure(go.Heatmap(z=z, x=scens, y=parts, zmin=0, zmax=1, colorscale="RdYlGn", text=text,
                               texttemplate="%{text}", hovertemplate="%{y} on %{x}: %{text}<extra></extra>",
                               colorbar=dict(title="P(pass)")))
    fig.update_layout(title="P(pass after PGA) [95 % Wilson interval]", xaxis_title="scenario",
                      yaxis_title="part", yaxis_autorange="reversed", template="plotly_white",
                      height=max(300, 60 * len(parts) + 160))
    return fig


def pass_vs_figure(table: pd.DataFrame, x: str, *, x_label: str | None = None, log_x: bool = False) -> go.Figure:
    """P(pass after PGA) against column ``x`` (e.g. ``slant_range_m`` or ``tc_s``), one line per
    part, the 95 % interval as error bars."""
    _need(table, ("part_id", x, P_COL, LO_COL, HI_COL))
    fig = go.Figure()
    for pid, g in table.groupby("part_id", sort=False):
        g = g.sort_values(x)
        fig.add_trace(go.Scatter(x=g[x], y=g[P_COL], mode="lines+markers", name=str(pid),
                                 error_y=dict(type="data", symmetric=False, array=g[HI_COL] - g[P_COL],
                                              arrayminus=g[P_COL] - g[LO_COL])))
    fig.update_layout(title=f"P(pass after PGA) vs {x_label or x}", xaxis_title=x_label or x,
                      yaxis_title="P(pass after PGA)", yaxis_range=[-0.03, 1.03], template="plotly_white",
                      xaxis_type="log" if log_x else "linear")
    return fig
