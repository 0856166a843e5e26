"""Figure of a part's verdict on a recorded scene (:func:`budget.mc.real_scene.real_scene_verdict`):
per trial, each quantity the verdict judges against its limit — what PGA leaves beyond its window
(deg rms), the peak loss of a point at the scene centre (dB) and the peak range migration (range
cells) — passed trials in one colour, failed ones in another with their reasons on hover.

The numbers come from :class:`~budget.mc.real_scene.RealSceneVerdict` (its outcomes, limits and
options); this module only draws them.
"""

from __future__ import annotations

import plotly.graph_objects as go
from plotly.subplots import make_subplots

from ..mc.real_scene import RealSceneVerdict

PASS_COLOUR, FAIL_COLOUR, LIMIT_COLOUR = "#2ca02c", "#d62728", "#444"


def judged_keys(verdict: RealSceneVerdict) -> tuple[tuple[str, str, str], ...]:
    """(outcome key, limit key, axis label) of each judged quantity: the ``added_`` measures when
    the verdict is judged relative to the scene's floor (``scene_reference = "reference"``), the
    absolute ones otherwise."""
    added = verdict.options.scene_reference == "reference"
    pre, word = ("added_", "added ") if added else ("", "")
    return ((f"{pre}residual_beyond_window_deg", "residual_beyond_window_deg",
             f"{word}residual beyond PGA's window (deg rms)"),
            (f"{pre}peak_loss_db", "peak_loss_db", f"{word}peak loss, scene-centre point (dB)"),
            ("peak_range_cells", "range_migration_cells", "peak range migration (range cells)"))


def real_scene_trials_figure(verdict: RealSceneVerdict) -> go.Figure:
    """One panel per judged quantity: its value per trial (markers, green passed / red failed,
    the failure reasons on hover) and its limit (dashed line; none where it is not judged)."""
    keys = judged_keys(verdict)
    fig = make_subplots(rows=len(keys), cols=1, shared_xaxes=True, vertical_spacing=0.1,
                        subplot_titles=[label for _, _, label in keys])
    trials = [o["trial"] for o in verdict.outcomes]
    hover = [", ".join(o["reasons"]) or "passed" for o in verdict.outcomes]
    colours = [PASS_COLOUR if o["passed"] else FAIL_COLOUR for o in verdict.outcomes]
    for row, (key, limit_key, label) in enumerate(keys, start=1):
        fig.add_trace(go.Scatter(x=trials, y=[o.get(key) for o in verdict.outcomes], mode="markers",
                                 marker={"color": colours, "size": 9}, customdata=hover, name=label,
                                 hovertemplate="trial %{x}: %{y:.3g}<br>%{customdata}<extra></extra>",
                                 showlegend=False), row=row, col=1)
        limit = verdict.limits.get(limit_key)
        if limit is not None:
            fig.add_hline(y=limit, line={"dash": "dash", "color": LIMIT_COLOUR}, row=row, col=1,
                          annotation_text=f"limit {limit:g}", annotation_position="top left")
        fig.update_yaxes(rangemode="tozero", row=row, col=1)
    fig.update_xaxes(title_text="trial", dtick=1 if len(trials) <= 20 else None, row=len(keys), col=1)
    lo, hi = verdict.interval
    fig.update_layout(title=f"{verdict.part}: P(pass) {verdict.p_pass:.2f} [{lo:.2f}, {hi:.2f}] "
                            f"(95 % Wilson), {verdict.passed} of {verdict.trials} trials, seed {verdict.seed}",
                      template="plotly_white", height=220 * len(keys) + 80)
    return fig
