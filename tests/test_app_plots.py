"""Figures in ``budget.plots``: they draw exactly the library's bounds, grade ranges and margins."""

from __future__ import annotations

import math

import numpy as np
import pytest

from budget.bounds import compute_bounds
from budget.catalog.io import load_catalog, load_grades
from budget.check import check_parts
from budget.plots import BOUND_LABELS, bounds_vs_tc_figure, grade_band, margin_heatmap_figure
from budget.presets import get_preset


def _panel_traces(fig, key):
    i = list(BOUND_LABELS).index(key)
    axis = "x" if i == 0 else f"x{i + 1}"
    return [t for t in fig.data if (t.xaxis or "x") == axis]


@pytest.fixture(scope="module")
def grades():
    return load_grades()


def test_bound_curves_are_compute_bounds_on_the_grid(grades):
    s = get_preset("automotive_77ghz")
    fig = bounds_vs_tc_figure(0.1, grades, modes=("paper", "no-autofocus"), tc_range_s=(0.5, 50), n_points=40,
                              wavelength_m=s.wavelength_m)
    for key in BOUND_LABELS:
        for mode in ("paper", "no-autofocus"):
            curve = next(t for t in _panel_traces(fig, key) if t.name == f"bound ({mode})")
            x = np.asarray(curve.x)
            expected = compute_bounds(x, 0.1, mode, wavelength_m=s.wavelength_m).datasheet()[key]
            np.testing.assert_allclose(curve.y, expected, rtol=1e-12)
            assert x[0] == pytest.approx(0.5) and x[-1] == pytest.approx(50)
    assert all(ax.type == "log" for ax in (fig.layout.xaxis, fig.layout.yaxis, fig.layout.xaxis7, fig.layout.yaxis7))


def test_grade_bands_span_the_grade_table_ranges(grades):
    fig = bounds_vs_tc_figure(0.1, grades)
    tactical = grades["tactical"]
    band = next(t for t in _panel_traces(fig, "gyro_bias_deg_h") if t.name == "tactical")
    assert min(band.y) == tactical.gyro_bias_deg_h_min and max(band.y) == tactical.gyro_bias_deg_h_max
    noise = next(t for t in _panel_traces(fig, "accel_vrw_ug_rt_hz") if t.name == "navigation")
    assert (min(noise.y), max(noise.y)) == (grades["navigation"].accel_noise_ug_rt_hz_min,
                                            grades["navigation"].accel_noise_ug_rt_hz_max)
    assert grade_band(grades["industrial"], "gyro_arw_deg_rt_h") == (3.0, 3.0)  # one printed value


def test_scenario_marker_sits_at_tc_on_every_panel(grades):
    s = get_preset("airborne_xband")
    fig = bounds_vs_tc_figure(s.range_resolution_m, grades, current_tc_s=s.tc_s)
    markers = [t for t in fig.data if t.name == "scenario Tc"]
    assert len(markers) == len(BOUND_LABELS)
    assert all(list(t.x) == [s.tc_s, s.tc_s] for t in markers)


def test_bad_arguments_are_refused(grades):
    with pytest.raises(ValueError, match="wavelength"):
        bounds_vs_tc_figure(0.1, grades, modes=("no-autofocus",))
    with pytest.raises(ValueError, match="tc_range_s"):
        bounds_vs_tc_figure(0.1, grades, tc_range_s=(10, 1))


def test_margin_heatmap_shows_check_parts_margins():
    parts = list(load_catalog().values())
    res = check_parts(parts, get_preset("airborne_xband_long_range"))
    fig = margin_heatmap_figure(res)
    hm = fig.data[0]
    assert list(hm.y) == [p.part_id for p in parts]
    m = res.margins[:, 0, :]
    z = np.asarray(hm.z, float)
    ok = ~np.isnan(m)
    np.testing.assert_allclose(z[ok], np.clip(np.log10(m[ok]), -3, 3), rtol=1e-12)
    assert np.all(np.isnan(z[~ok]))
    text = np.asarray(hm.text)
    assert np.all(text[~ok] == "–")
    i, j = np.argwhere(ok)[0]
    assert float(text[i, j]) == pytest.approx(m[i, j], rel=1e-2)
    assert math.isclose(hm.zmid, 0.0)
