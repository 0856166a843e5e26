"""Page: scenario and bounds — Tc, aperture length, the bounds table in every mode (paper, derived,
no-autofocus and lever-arm, as ``sar-budget bounds --scenario`` computes them), the lowest
sufficient grades (the PGA-limited one beside seed 004's), bounds vs. Tc."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import streamlit as st

from budget import units as u
from budget.api import compute_bounds as scenario_bounds
from budget.bounds import MODES as BOUND_MODES
from budget.bounds import (BOUND_FIELDS, DerivedAssumptions, LeverArmAssumptions, NoAutofocusAssumptions,
                           fast_phase_limits, max_bounds_tc_s, scenario_keys)
from budget.errors import InputError
from budget.recommend import SufficientGrades, lowest_sufficient_grades
from budget.sar.windows import verdict_window
from budget.plots.bounds import BOUND_LABELS, bounds_vs_tc_figure

import components as c
import sidebar
from formatting import grade_text
from page_frame import run_page
from uploads import error_text

#: Tc choices (s) for the plot's range slider (log-spaced).
TC_CHOICES = (0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0)


def bounds_tables(ctx: sidebar.Context) -> tuple[dict, dict]:
    """The library's bounds table of each mode (:data:`budget.bounds.MODES`: paper, derived,
    no-autofocus, lever-arm) at the scenario's Tc, as ``sar-budget bounds --scenario … --mode M``
    computes them (:func:`budget.api.compute_bounds`: the scenario's ``platform_accel_m_s2``, lever
    arm and turn rate), with the sidebar's assumption edits. → (tables, refusals): a mode the
    library refuses (e.g. derived with ``platform_accel_m_s2`` = 0) is in ``refusals`` with the
    library's one-line message, not computed with some other value."""
    s = ctx.scenario
    tables, refused = {}, {}
    for mode in BOUND_MODES:
        try:
            tables[mode] = scenario_bounds(s, mode, ctx.edits(mode))
        except InputError as err:
            refused[mode] = error_text(err)
    return tables, refused


def bounds_frame(ctx: sidebar.Context, tables: dict | None = None) -> pd.DataFrame:
    """One row per bound (datasheet unit in the label), one column per mode, at the scenario's Tc;
    a mode the library refused is a column of NaN (shown "–")."""
    tables = tables if tables is not None else bounds_tables(ctx)[0]
    data = {"parameter": [BOUND_LABELS[k] for k in BOUND_FIELDS], "key": list(BOUND_FIELDS)}
    for mode in BOUND_MODES:
        ds = tables[mode].datasheet() if mode in tables else None
        data[mode] = [float(np.ravel(ds[k])[0]) if ds is not None else np.nan for k in BOUND_FIELDS]
    return pd.DataFrame(data)


def limit_notes(tables: dict) -> list[str]:
    """Where a bound stops constraining (:meth:`budget.bounds.BoundsTable.limit_notes`), per mode."""
    return [f"{mode}: {note}" for mode, table in tables.items() for note in table.limit_notes()]


def defaults_note(s) -> str:
    """The scenario keys the bounds use that its file (or preset) left out, with the defaults
    taken (:meth:`budget.scenario.Scenario.defaults_note`, as ``sar-budget bounds`` prints it)."""
    keys = tuple(dict.fromkeys(k for mode in BOUND_MODES for k in scenario_keys(mode)))
    return s.defaults_note(keys)


@st.cache_data(show_spinner="Drawing bounds vs. Tc …", max_entries=64)
def _figure(dr: float, modes: tuple[str, ...], lo: float, hi: float, tc: float | None, lam: float,
            assumptions_json: tuple[tuple[str, str], ...]):
    classes = {"derived": DerivedAssumptions, "no-autofocus": NoAutofocusAssumptions,
               "lever-arm": LeverArmAssumptions}
    return bounds_vs_tc_figure(
        dr, c.grades(), modes=modes, tc_range_s=(lo, hi), current_tc_s=tc, wavelength_m=lam,
        assumptions={m: classes[m].model_validate_json(a) for m, a in assumptions_json})


def _metrics(s) -> None:
    cols = st.columns(4)
    cols[0].metric("Tc, synthetic-aperture time", f"{s.tc_s:.4g} s",
                   help="a_w λ R / (2 δℓ V sin θ), seed 004 (5)")
    cols[1].metric("aperture length V·Tc", f"{s.aperture_length_m:.4g} m")
    cols[2].metric("wavelength λ = c/f0", f"{s.wavelength_m:.4g} m")
    cols[3].metric("range resolution δr", f"{s.range_resolution_m:.4g} m")


def grade_verdicts(ctx: sidebar.Context) -> dict[str, str | None]:
    """Lowest sufficient grade (bias and noise terms vs. the best typical values of each grade)
    against the paper bounds, the derived bounds (the scenario's assumptions with the sidebar's
    edits, as ``sar-budget check --mode derived`` computes it) and the PGA-limited bounds (seed
    004's tightened by what PGA cannot remove and attitude error × lever arm,
    :func:`budget.bounds.lever_arm.pga_limited_bounds`, as the Check page and ``sar-budget check``
    give it). None where no grade suffices; a verdict the library refuses is left out (its
    refusal: :func:`grade_refusals`)."""
    return _grade_verdicts(ctx)[0]


def grade_refusals(ctx: sidebar.Context) -> dict[str, str]:
    """``{key: the library's one-line refusal}`` of each grade verdict not computed (e.g. a Tc
    beyond the bounds' navigation model, :func:`budget.bounds.check_bounds_tc`)."""
    return _grade_verdicts(ctx)[1]


def _grade_verdicts(ctx: sidebar.Context) -> tuple[dict[str, str | None], dict[str, str]]:
    """(grades, refusals): :func:`budget.recommend.lowest_sufficient_grades` — the call the Check page
    and ``sar-budget check`` make — for the paper and the derived bounds; the PGA-limited grade with
    the paper one. ``grades`` carries ``why_none``."""
    s = ctx.scenario
    grades = list(c.grades().values())
    out = SufficientGrades({}, {})
    refused: dict[str, str] = {}
    for mode, keys in (("paper", ("paper", "pga_limited")), ("derived", ("derived",))):
        try:
            rec = lowest_sufficient_grades(s, mode, grades, ctx.edits(mode))
        except InputError as err:  # e.g. a Tc beyond the bounds' navigation model: nothing computed
            refused.update({k: error_text(err) for k in keys})
            continue
        for k in keys:
            out[k] = rec[k]
            if rec.why_none.get(k):
                out.why_none[k] = rec.why_none[k]
    return out, refused


#: Keys of :func:`grade_verdicts` → the metric's label.
GRADE_LABELS = {"paper": "lowest sufficient grade (paper bounds)",
                "derived": "lowest sufficient grade (derived bounds)",
                "pga_limited": "lowest sufficient grade (PGA-limited, binding)"}


def _recommendation(ctx: sidebar.Context) -> None:
    rec, refused = _grade_verdicts(ctx)
    helps = {"derived": "the scenario's acceleration level and the sidebar's assumptions, as above",
             "pga_limited": "seed 004's bounds tightened by what PGA cannot remove: fast phase beyond its window "
                            "and attitude error × lever arm — the verdict the Monte Carlo's after-PGA pass rule "
                            "follows"}
    cols = st.columns(3)
    for col, key in zip(cols, GRADE_LABELS):
        col.metric(GRADE_LABELS[key], grade_text(rec, key), help=helps.get(key))
        if key in refused:  # "–": not computed, and why (never "none", which is a verdict)
            col.caption(f"not computed: {refused[key]}")
        elif rec.why_none.get(key):  # none: the binding terms and how far the best grade misses them
            col.caption(f"none: {rec.why_none[key]}")
    st.caption("Bias and noise terms against the best typical values of each grade (seed 004 Tables 3–4); "
               "scale factor and misalignment are left to calibration, as the paper says. The paper and "
               "derived grades are seed 004's verdict; the **PGA-limited** one is the binding verdict (the "
               "Check matrix's 'PGA-limited' column, `sar-budget check`'s second grade line): a part of a "
               "lower grade may pass seed 004's bounds and still fail the Monte Carlo.")


def _fast_phase(s) -> None:
    fp = fast_phase_limits(s.wavelength_m, [s.tc_s], aperture_window=verdict_window(s).kind)  # as the check
    st.markdown(f"**What autofocus cannot remove.** {fp.summary()}")
    st.dataframe(pd.DataFrame({
        "limit at the scenario Tc": ["accel VRW (µg/√Hz)", "gyro ARW (deg/√h)"],
        "value": [float(u.m_s2_rt_hz_to_ug_rt_hz(fp.vrw_m_s2_rt_hz[0])),
                  float(u.rad_s_rt_hz_to_deg_rt_h(fp.arw_rad_s_rt_hz[0]))],
    }).style.format({"value": "{:.4g}"}), hide_index=True, key="scn_fast_table")


def _plot(ctx: sidebar.Context, refused: dict) -> None:
    s = ctx.scenario
    left, right = st.columns([2, 1])
    lo, hi = left.select_slider("Tc range of the plot (s)", options=TC_CHOICES, value=(0.1, 100.0),
                                key="scn_plot_range")
    offered = [m for m in BOUND_MODES if m not in refused]  # a refused mode has no curve
    modes = right.multiselect("curves", offered, default=[m for m in sidebar.MODES if m in offered],
                              key="scn_plot_modes")
    # keep the scenario's Tc in view, up to the longest Tc the bounds are computed for (beyond it
    # the library refuses every bound: the curves stop there, and so does the plot)
    limit = max_bounds_tc_s()
    lo, hi = min(lo, s.tc_s / 2), min(max(hi, s.tc_s * 2), limit)
    if lo >= hi:
        st.info("Pick a Tc range with two different ends.")
        return
    tc = s.tc_s if s.tc_s <= limit else None
    if tc is None:
        st.info(f"This scenario's Tc = {s.tc_s:.4g} s is beyond the longest Tc the bounds are computed for "
                f"({limit:g} s): the plot stops there, without the scenario's marker.", icon=":material/info:")
    elif hi < s.tc_s * 2:
        st.caption(f"The plot stops at Tc = {limit:g} s, the longest Tc the bounds are computed for.")
    used = tuple((m, ctx.assumptions(m).model_dump_json()) for m in modes if m != "paper")
    fig = _figure(s.range_resolution_m, tuple(modes), float(lo), float(hi), tc, s.wavelength_m, used)
    st.plotly_chart(fig, key="scn_plot", width="stretch")
    st.caption("Shaded: typical ranges per grade (seed 004 Tables 3–4; dash-dot where the paper prints one "
               "value). A grade whose band lies below a curve meets that bound. Dotted vertical: this scenario. "
               "The curves use the same assumptions as the table above.")


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
    tables, refused = bounds_tables(ctx)
    for mode, text in refused.items():  # the library's refusal, as `sar-budget bounds --mode M` gives it
        st.error(f"{mode} bounds not computed: {text}", icon=":material/error:")
    df = bounds_frame(ctx, tables)
    st.dataframe(df.style.format({m: "{:.4g}" for m in BOUND_MODES}, na_rep="–"), hide_index=True,
                 column_config={"key": st.column_config.TextColumn("key (JSON/CLI)")}, key="scn_bounds_table")
    st.caption("paper: seed 004 (6)–(11); derived: the same from physics; no-autofocus: phase limits without "
               "PGA; lever-arm: seed 004's bounds together with attitude error × lever arm (the range "
               "migration it makes and what PGA cannot remove of it) — where it is below paper, it binds. "
               "Each source alone within one range cell. As `sar-budget bounds --scenario … --mode M` computes "
               "them, with:")
    st.markdown("\n".join(f"- {ctx.assumptions_words(m)}" for m in BOUND_MODES if m in tables and m != "paper"))
    for note in limit_notes(tables):  # a bound that does not constrain must not read as a limit
        st.warning(note, icon=":material/warning:")
    if note := defaults_note(s):
        st.info(note, icon=":material/info:")
    # each panel on its own: one the library refuses is its message, and the others still show
    c.guarded(lambda: _recommendation(ctx))
    c.guarded(lambda: _fast_phase(s))
    st.subheader("Bounds vs. aperture time")
    c.guarded(lambda: _plot(ctx, refused))
    st.download_button("Download scenario (JSON)", data=json.dumps(s.model_dump(mode="json"), indent=2) + "\n",
                       file_name=f"{s.name}.json", mime="application/json", key="scn_download")


run_page(render)
