"""Figure: margins (bound / spec) of catalog parts, parts × parameters, colour-coded.

Colour is log10(margin): green where the part meets the bound (margin ≥ 1), red where it does
not, blank where the datasheet gives no value (never assumed). Margins come from
:func:`budget.check.check_parts`; the figure only draws them.
"""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go

from ..check import CheckResult
from ..parameters import PARAMETERS

#: Check parameter (part column) → short label with the datasheet unit (from the parameter table).
PARAM_LABELS: dict[str, str] = {p.column: p.label for p in PARAMETERS}

#: Colour scale over log10(margin) ∈ [−3, 3]: red below 0 (fail), green above (pass).
_SCALE = [[0.0, "#b2182b"], [0.45, "#f4a582"], [0.5, "#f7f7f7"], [0.55, "#a6dba0"], [1.0, "#1b7837"]]


def margin_heatmap_figure(result: CheckResult, scenario_index: int = 0, *, clip_decades: float = 3.0) -> go.Figure:
    """Heat map of log10(margin) for scenario ``scenario_index`` of ``result`` (parts top to bottom)."""
    m = np.asarray(result.margins[:, scenario_index, :], float)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.clip(np.log10(m), -clip_decades, clip_decades)
    text = np.where(np.isnan(m), "–", np.vectorize(lambda v: f"{v:.3g}")(np.nan_to_num(m, nan=0.0)))
    labels = [PARAM_LABELS.get(p, p) for p in result.params]
    fig = go.Figure(go.Heatmap(
        z=z, x=labels, y=list(result.part_ids), text=text, texttemplate="%{text}",
        colorscale=_SCALE, zmin=-clip_decades, zmax=clip_decades, zmid=0.0,
        colorbar=dict(title="log10 margin", tickvals=[-3, -2, -1, 0, 1, 2, 3]),
        hovertemplate="%{y} · %{x}<br>margin bound/spec = %{text}<extra></extra>", xgap=1, ygap=1))
    tc = float(np.ravel(result.tc_s)[scenario_index])
    fig.update_layout(
        title=f"Margin bound/spec at Tc = {tc:.3g} s (≥ 1 passes; – = not in the datasheet)",
        yaxis=dict(autorange="reversed"), height=max(300, 26 * len(result.part_ids) + 140),
        margin=dict(l=10, r=10, t=50, b=10), plot_bgcolor="#dddddd")
    return fig
