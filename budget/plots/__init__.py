"""Plotly figures shared by the dashboard and notebooks (each function returns a ``go.Figure``).

* :mod:`.bounds` — Tc-driven bounds vs. aperture time with the grade bands of seed 004 Tables 3–4.
* :mod:`.check` — part × parameter margins as a colour-coded heat map.
"""

from .bounds import BOUND_LABELS, GRADE_COLORS, bounds_vs_tc_figure, grade_band
from .check import PARAM_LABELS, margin_heatmap_figure

__all__ = ["BOUND_LABELS", "GRADE_COLORS", "bounds_vs_tc_figure", "grade_band", "PARAM_LABELS",
           "margin_heatmap_figure"]
