"""Plotly figures of the whole package, in one place (each function returns a ``go.Figure``).

This floor sits above the models and engines it draws (``bounds``, ``check``, ``sar``, ``noise``,
``motion``, ``mc``, ``gap``): it imports them, they never import it.

* :mod:`.bounds` — Tc-driven bounds vs. aperture time with the grade bands of seed 004 Tables 3–4.
* :mod:`.check` — part × parameter margins as a colour-coded heat map.
* :mod:`.sar` — SAR image in dB, IRF cuts against the ideal, PGA phase estimate against truth.
* :mod:`.focus` — recorded-data focusing: image before/after autofocus, phase estimate per pulse.
* :mod:`.noise` — Allan deviation with fit, PSD, Kalman filtering and response, ARMA criteria,
  preprocessing.
* :mod:`.motion` — APC position error, phase error and metric histograms of motion trials.
* :mod:`.mc` — Monte-Carlo pass probability and metric distributions.
* :mod:`.gap` — model-gap figures: measured vs model before/after (ADEV, PSD, gap, z).
* :mod:`.sweep` — trade-study pass maps.
* :mod:`.export` — offline HTML (plotly.js beside or embedded) and PNG/SVG export.
"""

from .bounds import BOUND_LABELS, GRADE_COLORS, bounds_vs_tc_figure, grade_band
from .check import PARAM_LABELS, margin_heatmap_figure

__all__ = ["BOUND_LABELS", "GRADE_COLORS", "bounds_vs_tc_figure", "grade_band", "PARAM_LABELS",
           "margin_heatmap_figure"]
