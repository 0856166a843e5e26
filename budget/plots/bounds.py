"""Figure: Tc-driven bounds vs. aperture time on log axes, over the IMU grade bands.

The curves are the bounds of seed 004 (6)–(11) (or the derived / no-autofocus variants of
:mod:`budget.bounds`) evaluated on a grid of Tc; the shaded bands are the typical error ranges
of each grade, seed 004 Tables 3–4 (``catalog/grades.csv``). Where a band lies below a curve,
that grade's typical parts meet that bound at that Tc. All values in datasheet units (the keys
of :meth:`budget.bounds.BoundsTable.datasheet`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
import plotly.graph_objects as go
from plotly.subplots import make_subplots

from ..bounds import compute_bounds
from ..catalog.schema import GRADE_RANK, GradeSpec
from ..parameters import BOUNDS, PARAMETERS

#: Datasheet key of a bound → axis label with its unit (from :data:`budget.parameters.BOUNDS`;
#: panels ordered bias, noise, scale factor, misalignment).
BOUND_LABELS: dict[str, str] = {p.bound_key: p.bound_label
                                 for fam in ("bias", "noise", "scale_factor", "misalignment")
                                 for p in BOUNDS if p.family == fam}

#: Bound key → the GradeSpec fields whose min/max give the grade's typical range (Tables 3–4);
#: misalignment has one bound for both triads, so both grade columns.
GRADE_FIELDS: dict[str, tuple[str, ...]] = {
    key: tuple(dict.fromkeys(c for p in PARAMETERS if p.bound_key == key for c in p.grade_columns))
    for key in BOUND_LABELS}

GRADE_COLORS: dict[str, str] = {
    "strategic": "#6a3d9a",
    "navigation": "#1f78b4",
    "stabilization": "#17becf",
    "tactical": "#33a02c",
    "industrial": "#ff7f00",
    "consumer": "#e31a1c",
}

_MODE_STYLE = {
    "paper": dict(color="black", dash="solid"),
    "derived": dict(color="#555555", dash="dash"),
    "no-autofocus": dict(color="#8b0000", dash="dot"),
}


def grade_band(grade: GradeSpec, key: str) -> tuple[float, float]:
    """(low, high) typical value of ``grade`` for the bound ``key``, in the bound's datasheet unit."""
    vals = [float(getattr(grade, f)) for f in GRADE_FIELDS[key]]
    return min(vals), max(vals)


def _grid(tc_range_s: tuple[float, float], n_points: int) -> np.ndarray:
    lo, hi = (float(v) for v in tc_range_s)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
        raise ValueError(f"tc_range_s must be two finite times 0 < low < high in s, got {tc_range_s}")
    return np.geomspace(lo, hi, int(n_points))


def bounds_vs_tc_figure(range_resolution_m: float, grades: Mapping[str, GradeSpec] | Sequence[GradeSpec],
                        *, modes: Sequence[str] = ("paper",), tc_range_s: tuple[float, float] = (0.1, 100.0),
                        n_points: int = 200, current_tc_s: float | None = None,
                        wavelength_m: float | None = None, assumptions: Mapping[str, object] | None = None,
                        keys: Sequence[str] = tuple(BOUND_LABELS)) -> go.Figure:
    """Bounds (one panel per key, log–log) vs. Tc in s for δr = ``range_resolution_m`` m.

    ``modes`` are drawn as curves (``no-autofocus`` needs ``wavelength_m``); ``assumptions``
    maps a mode to its assumptions model. ``current_tc_s`` adds a vertical marker.
    """
    tc = _grid(tc_range_s, n_points)
    grade_list = sorted(grades.values() if isinstance(grades, Mapping) else grades,
                        key=lambda g: GRADE_RANK[g.grade])
    assumptions = dict(assumptions or {})
    curves = {m: compute_bounds(tc, range_resolution_m, m, wavelength_m=wavelength_m,
                                assumptions=assumptions.get(m)).datasheet() for m in modes}
    at_tc = ({m: compute_bounds(np.array([current_tc_s]), range_resolution_m, m, wavelength_m=wavelength_m,
                                assumptions=assumptions.get(m)).datasheet() for m in modes}
             if current_tc_s is not None else {})

    ncols = 4
    nrows = math.ceil(len(keys) / ncols)
    fig = make_subplots(rows=nrows, cols=ncols, subplot_titles=[BOUND_LABELS[k] for k in keys],
                        horizontal_spacing=0.07, vertical_spacing=0.14)
    x_band = [tc[0], tc[-1], tc[-1], tc[0], tc[0]]
    for i, key in enumerate(keys):
        row, col = i // ncols + 1, i % ncols + 1
        first = i == 0
        ys: list[float] = []
        for g in grade_list:
            lo, hi = grade_band(g, key)
            if hi <= 0:
                continue  # a zero typical value cannot be drawn on a log axis
            lo = lo if lo > 0 else hi
            ys += [lo, hi]
            style = dict(legendgroup=g.grade, name=g.grade, showlegend=first,
                         hovertemplate=f"{g.grade}: {lo:.3g} – {hi:.3g}<extra></extra>")
            if hi > lo:
                fig.add_trace(go.Scatter(x=x_band, y=[lo, lo, hi, hi, lo], fill="toself", mode="lines",
                                         line=dict(width=0), fillcolor=GRADE_COLORS[g.grade], opacity=0.25,
                                         **style), row=row, col=col)
            else:  # a single printed value: draw it as a line
                fig.add_trace(go.Scatter(x=[tc[0], tc[-1]], y=[lo, lo], mode="lines",
                                         line=dict(color=GRADE_COLORS[g.grade], width=2, dash="dashdot"),
                                         opacity=0.7, **style), row=row, col=col)
        for m in modes:
            y = np.asarray(curves[m][key], float)
            ok = np.isfinite(y) & (y > 0)
            ys += list(y[ok])
            fig.add_trace(go.Scatter(x=tc[ok], y=y[ok], mode="lines", name=f"bound ({m})", legendgroup=m,
                                     showlegend=first, line=dict(width=2.5, **_MODE_STYLE.get(m, {})),
                                     hovertemplate=f"{m}: Tc %{{x:.3g}} s → %{{y:.3g}}<extra></extra>"),
                          row=row, col=col)
        ymin, ymax = (min(ys), max(ys)) if ys else (1e-6, 1.0)
        ylo, yhi = math.log10(ymin) - 0.3, math.log10(ymax) + 0.3
        if current_tc_s is not None:
            fig.add_trace(go.Scatter(x=[current_tc_s, current_tc_s], y=[10 ** ylo, 10 ** yhi], mode="lines",
                                     line=dict(color="black", width=1, dash="dot"), name="scenario Tc",
                                     legendgroup="tc", showlegend=first,
                                     hovertemplate=f"scenario Tc = {current_tc_s:.3g} s<extra></extra>"),
                          row=row, col=col)
            for m in modes:
                v = float(np.ravel(at_tc[m][key])[0])
                if math.isfinite(v) and v > 0:
                    fig.add_trace(go.Scatter(x=[current_tc_s], y=[v], mode="markers", legendgroup=m,
                                             showlegend=False, marker=dict(color="black", size=7),
                                             hovertemplate=f"{m} at scenario Tc: %{{y:.3g}}<extra></extra>"),
                                  row=row, col=col)
        fig.update_xaxes(type="log", title_text="Tc (s)", row=row, col=col)
        fig.update_yaxes(type="log", range=[ylo, yhi], exponentformat="power", row=row, col=col)
    for j in range(len(keys), nrows * ncols):  # hide unused panels
        fig.update_xaxes(visible=False, row=j // ncols + 1, col=j % ncols + 1)
        fig.update_yaxes(visible=False, row=j // ncols + 1, col=j % ncols + 1)
    fig.update_layout(height=330 * nrows + 80, margin=dict(l=40, r=20, t=60, b=40),
                      title=f"Maximum allowed IMU errors vs. aperture time (δr = {range_resolution_m:g} m) "
                            f"over seed 004 grade ranges",
                      legend=dict(orientation="v", x=0.78, y=0.02, xanchor="left", yanchor="bottom"))
    return fig
