"""Page: scenario and bounds — Tc, aperture length, the bounds table in every mode, bounds vs. Tc."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import streamlit as st

from budget import units as u
from budget.bounds import (BOUND_FIELDS, DerivedAssumptions, NoAutofocusAssumptions, compute_bounds,
                           fast_phase_limits, scenario_keys)
from budget.recommend import recommend_grade
from budget.sar.windows import verdict_window
from budget.plots.bounds import BOUND_LABELS, bounds_vs_tc_figure

import components as c
import sidebar
from page_frame import run_page

#: Tc choices (s) for the plot's range slider (log-spaced).
TC_CHOICES = (0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0)


def bounds_tables(ctx: sidebar.Context) -> dict:
    """The library's bounds table of each mode at the scenario's Tc (as ``sar-budget bounds``)."""
    s = ctx.scenario
    return {mode: compute_bounds(np.array([s.tc_s]), s.range_resolution_m, mode, wavelength_m=s.wavelength_m,
                                 assumptions=ctx.assumptions(mode))
            for mode in sidebar.MODES}


def bounds_frame(ctx: sidebar.Context, tables: dict | None = None) -> pd.DataFrame:
    """One row per bound (datasheet unit in the label), one column per mode, at the scenario's Tc."""
    tables = tables or bounds_tables(ctx)
    data = {"parameter": [BOUND_LABELS[k] for k in BOUND_FIELDS], "key": list(BOUND_FIELDS)}
    for mode, table in tables.items():
        ds = table.datasheet()
        data[mode] = [float(np.ravel(ds[k])[0]) for k in BOUND_FIELDS]
    return pd.DataFrame(data)


def limit_notes(tables: dict) -> list[str]:
    """Where a bound stops constraining (:meth:`budget.bounds.BoundsTable.limit_notes`), per mode."""
    return [f"{mode}: {note}" for mode, table in tables.items() for note in table.limit_notes()]


def defaults_note(s) -> str:
    """The scenario keys the bounds use that its file (or preset) left out, with the defaults
    taken (:meth:`budget.scenario.Scenario.defaults_note`, as ``sar-budget bounds`` prints it)."""
    keys = tuple(dict.fromkeys(k for mode in sidebar.MODES for k in scenario_keys(mode)))
    return s.defaults_note(keys)


@st.cache_data(show_spinner="Drawing bounds vs. Tc …", max_entries=64)
def _figure(dr: float, modes: tuple[str, ...], lo: float, hi: float, tc: float, lam: float,
            derived_json: str, noaf_json: str):
    return bounds_vs_tc_figure(
        dr, c.grades(), modes=modes, tc_range_s=(lo, hi), current_tc_s=tc, wavelength_m=lam,
        assumptions={"derived": DerivedAssumptions.model_validate_json(derived_json),
                     "no-autofocus": NoAutofocusAssumptions.model_validate_json(noaf_json)})


def _metrics(s) -> None:
    cols = st.columns(4)
    cols[0].metric("Tc, synthetic-aperture time", f"{s.tc_s:.4g} s",
                   help="a_w λ R / (2 δℓ V sin θ), seed 004 (5)")
    cols[1].metric("aperture length V·Tc", f"{s.aperture_length_m:.4g} m")
    cols[2].metric("wavelength λ = c/f0", f"{s.wavelength_m:.4g} m")
    cols[3].metric("range resolution δr", f"{s.range_resolution_m:.4g} m")


def _recommendation(ctx: sidebar.Context) -> None:
    s = ctx.scenario
    grades = list(c.grades().values())
    rec = {m: recommend_grade([s.tc_s], s.range_resolution_m, grades, mode=m).grade[0]
           for m in ("paper", "derived")}
    cols = st.columns(2)
    cols[0].metric("lowest sufficient grade (paper bounds)", rec["paper"] or "none")
    cols[1].metric("lowest sufficient grade (derived, default assumptions)", rec["derived"] or "none")
    st.caption("Bias and noise terms against the best typical values of each grade (seed 004 Tables 3–4); "
               "scale factor and misalignment are left to calibration, as the paper says.")


def _fast_phase(s) -> None:
    fp = fast_phase_limits(s.wavelength_m, [s.tc_s], aperture_window=verdict_window(s).kind)  # as the check
    st.markdown(f"**What autofocus cannot remove.** {fp.summary()}")
    st.dataframe(pd.DataFrame({
        "limit at the scenario Tc": ["accel VRW (µg/√Hz)", "gyro ARW (deg/√h)"],
        "value": [float(u.m_s2_rt_hz_to_ug_rt_hz(fp.vrw_m_s2_rt_hz[0])),
                  float(u.rad_s_rt_hz_to_deg_rt_h(fp.arw_rad_s_rt_hz[0]))],
    }).style.format({"value": "{:.4g}"}), hide_index=True, key="scn_fast_table")


def _plot(ctx: sidebar.Context) -> None:
    s = ctx.scenario
    left, right = st.columns([2, 1])
    lo, hi = left.select_slider("Tc range of the plot (s)", options=TC_CHOICES, value=(0.1, 100.0),
                                key="scn_plot_range")
    modes = right.multiselect("curves", sidebar.MODES, default=list(sidebar.MODES), key="scn_plot_modes")
    lo, hi = min(lo, s.tc_s / 2), max(hi, s.tc_s * 2)  # keep the scenario's Tc in view
    if lo >= hi:
        st.info("Pick a Tc range with two different ends.")
        return
    fig = _figure(s.range_resolution_m, tuple(modes), float(lo), float(hi), s.tc_s, s.wavelength_m,
                  ctx.derived.model_dump_json(), ctx.no_autofocus.model_dump_json())
    st.plotly_chart(fig, key="scn_plot", width="stretch")
    st.caption("Shaded: typical ranges per grade (seed 004 Tables 3–4; dash-dot where the paper prints one "
               "value). A grade whose band lies below a curve meets that bound. Dotted vertical: this scenario.")


def render() -> None:
    ctx = sidebar.require_context()
    if ctx is None:
        return
    s = ctx.scenario
    st.title("Scenario & bounds")
    st.caption(f"scenario **{s.name}** · {s.medium} · {s.carrier_frequency_hz:.4g} Hz · "
               f"R = {s.slant_range_m:.4g} m · V = {s.platform_speed_m_s:.4g} m/s — edit it in the sidebar")
    _metrics(s)
    st.subheader("Maximum allowed IMU errors at this Tc")
    tables = bounds_tables(ctx)
    df = bounds_frame(ctx, tables)
    st.dataframe(df.style.format({m: "{:.4g}" for m in sidebar.MODES}), hide_index=True,
                 column_config={"key": st.column_config.TextColumn("key (JSON/CLI)")}, key="scn_bounds_table")
    st.caption("paper: seed 004 (6)–(11); derived: the same from physics with the sidebar's assumptions; "
               "no-autofocus: phase limits without PGA. Each source alone within one range cell.")
    for note in limit_notes(tables):  # a bound that does not constrain must not read as a limit
        st.warning(note, icon=":material/warning:")
    if note := defaults_note(s):
        st.info(note, icon=":material/info:")
    _recommendation(ctx)
    _fast_phase(s)
    st.subheader("Bounds vs. aperture time")
    _plot(ctx)
    st.download_button("Download scenario (JSON)", data=json.dumps(s.model_dump(mode="json"), indent=2) + "\n",
                       file_name=f"{s.name}.json", mime="application/json", key="scn_download")


run_page(render)
