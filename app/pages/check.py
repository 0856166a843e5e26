"""Page: check matrix — parts × parameters with margins, verdict, binding parameter, grade advice;
the numbers ``sar-budget check --scenario … --mode M`` gives for the same scenario (the bounds'
assumptions taken from the scenario, with the sidebar's edits), and its JSON download holds what
``check --json`` writes."""

from __future__ import annotations

import streamlit as st

from budget.catalog.io import catalog_note, user_catalog_path
from budget.catalog.schema import GRADES
from budget.check import check_parts, check_scenario_keys, rotation_line
from budget.errors import InputError
from budget.check_text import check_record
from budget.recommend import lowest_sufficient_grades
from budget.fileio import json_text
from budget.safe_text import frame_csv_text
from budget.plots.check import margin_heatmap_figure
from budget.report import build_report

import components as c
import sidebar
from page_frame import run_page
from check_view import check_frame, flagged, style_check_frame, verdict_counts
from uploads import error_text


def grade_verdicts(ctx: sidebar.Context) -> dict[str, str | None]:
    """``{mode: grade, "pga_limited": grade}`` for the sidebar's scenario, mode and edits
    (:func:`budget.recommend.lowest_sufficient_grades`, as ``sar-budget check``)."""
    return lowest_sufficient_grades(ctx.scenario, ctx.mode, c.grades().values(), ctx.assumptions())


def _recommendation(ctx: sidebar.Context, rec: dict[str, str | None]) -> None:
    left, right = st.columns(2)
    if ctx.mode == "no-autofocus":  # bounds for flying without PGA: no grade advice for a system with it
        left.caption("Grade recommendation uses the paper or derived bounds; pick one of them in the sidebar "
                     f"(the JSON download holds the no-autofocus one, {rec[ctx.mode] or 'none'}, as "
                     "`sar-budget check --json` does).")
    else:
        left.metric(f"lowest sufficient grade, {ctx.mode} bounds", rec[ctx.mode] or "none",
                    help="bias and noise terms vs. the best typical values of each grade, seed 004 Tables 3–4")
    right.metric("lowest sufficient grade, PGA-limited", rec["pga_limited"] or "none",
                 help="seed 004's bounds tightened by what PGA cannot remove: fast phase beyond its window "
                      "and attitude error × lever arm")
    # why a grade is none: the binding terms and how far the best grade misses them (as `sar-budget check`)
    why = getattr(rec, "why_none", {})
    if ctx.mode != "no-autofocus" and why.get(ctx.mode):
        left.caption(f"none: {why[ctx.mode]}")
    if why.get("pga_limited"):
        right.caption(f"none: {why['pga_limited']}")


def check_json(result, ctx: sidebar.Context, rec: dict[str, str | None], motion_kind: str | None) -> dict:
    """What ``sar-budget check --json`` writes, for this check (:func:`budget.check_text.check_record`).
    Parts uploaded on the Catalog page in this session are named under ``catalog`` and
    ``catalog_note``, as the CLI names a user catalog."""
    user = user_catalog_path(None)  # $SAR_BUDGET_CATALOG, merged into the shipped parts as the CLI does
    note = catalog_note(result.part_ids, None)
    uploaded = [pid for pid in result.part_ids if pid in c.user_parts()]
    catalog = str(user) if user else "shipped"
    if uploaded:
        catalog += " + parts uploaded on the Catalog page"
        note = "; ".join(filter(None, [note, "uploaded on the Catalog page in this session: " + ", ".join(uploaded)]))
    return check_record(result, ctx.scenario, ctx.mode, rec, catalog=catalog, catalog_note=note,
                        scenario_keys=check_scenario_keys(ctx.mode, motion_kind))


def render() -> None:
    ctx = sidebar.require_context()
    if ctx is None:
        return
    s = ctx.scenario
    st.title("Check matrix")
    grades = st.multiselect("grades", GRADES, default=list(GRADES), key="chk_grades")
    parts = [p for p in c.session_catalog().values() if p.grade in grades]
    if not parts:
        st.info("No part of the selected grades in the catalog.")
        return
    motions = {"the bounds' own (an attitude change of 1 rad)": None, "straight": "straight",
               "oscillation": "oscillation", "attitude_change": "attitude_change"}
    motion = st.selectbox("platform motion the gyro scale factor and misalignment are judged on", list(motions),
                          key="chk_platform_motion",
                          help="seed 004 assumes an attitude change of 1 rad over the aperture; a motion here "
                               "replaces it by that motion's equivalent excursion (as the Monte Carlo flies it)")
    kind = motions[motion]
    try:  # the sidebar's edits completed from the scenario by the library, as `sar-budget check` does
        result = check_parts(parts, s, ctx.mode, ctx.edits(), platform_motion={"kind": kind} if kind else None)
        rec = grade_verdicts(ctx)
    except InputError as err:  # e.g. derived bounds with platform_accel_m_s2 = 0: the CLI's refusal
        st.error(f"{ctx.mode} check of scenario {s.name} not run: {error_text(err)}", icon=":material/error:")
        return
    if ctx.mode != "paper":  # which values the bounds were computed with
        st.caption("Bounds: " + ctx.assumptions_words())
    if result.rotation:
        st.caption(rotation_line(result.rotation[0]))
    frame = check_frame(result)
    n = verdict_counts(frame)
    st.markdown(f"Scenario **{s.name}**: Tc = **{s.tc_s:.4g} s**, δr = {s.range_resolution_m:.4g} m, "
                f"**{ctx.mode}** bounds → <span id='check-summary'>**{n['pass']} pass · {n['fail']} fail · "
                f"{n['unknown']} unknown**</span>", unsafe_allow_html=True)
    if defaults := s.defaults_note(check_scenario_keys(ctx.mode, kind)):  # as `sar-budget check` states it
        st.info(defaults, icon=":material/info:")
    cols = st.columns([1, 1, 1, 2])
    cols[0].metric("pass", n["pass"])
    cols[1].metric("fail", n["fail"])
    cols[2].metric("unknown", n["unknown"], help="no error figure in the datasheet")
    with cols[3]:
        _recommendation(ctx, rec)
    flags = flagged(result)
    if flags:
        st.warning("**Seed 004's bounds and what PGA cannot remove disagree** (⚠ in the table; the Monte "
                   "Carlo page simulates it): " + "; ".join(f"**{pid}** {why}" for pid, why in flags),
                   icon=":material/warning:")
        st.markdown(f"<span id='check-flags'>{len(flags)} flagged</span>", unsafe_allow_html=True)
    # A static HTML table: every cell readable (and testable in a browser), colours and frames kept.
    st.table(style_check_frame(frame).hide(axis="index"))
    st.caption("Margin = bound / datasheet value (≥ 1 passes, green; < 1 fails, red; – not in the datasheet, "
               "never assumed). The framed, darker cell is the binding (smallest-margin) parameter. In-run "
               "bias instability is checked against the bias bounds, as seed 004 Tables 3–4 do." + _share_words(result))
    st.plotly_chart(margin_heatmap_figure(result), key="chk_heatmap", width="stretch")
    _downloads(result, frame, parts, ctx, check_json(result, ctx, rec, kind))


def _share_words(result) -> str:
    share = result.fast_phase_share[0] if result.fast_phase_share else None
    if share is None:
        return ""
    limit = result.fast_phase_limit_deg[0] if result.fast_phase_limit_deg else 1.0
    return (f" What PGA cannot remove is asked of a share of apertures, not of its rms: the PGA-limited verdict "
            f"passes a part when at least {share:g} of apertures keep it within {limit:g}° (the Monte Carlo's "
            "pass target; column 'apertures within the limit').")


def report_assumptions(ctx: sidebar.Context) -> dict:
    """The sidebar's edits of every mode's assumptions, as partial dicts: the report completes
    them from the scenario (its ``platform_accel_m_s2``) and states a mode it cannot compute
    (``platform_accel_m_s2`` = 0) beside its bounds table instead of refusing the whole report."""
    return {m: ctx.edits(m) for m in sidebar.MODES if ctx.edits(m)}


def _downloads(result, frame, parts, ctx: sidebar.Context, record: dict) -> None:
    s = ctx.scenario
    st.subheader("Export")
    a, b, c3 = st.columns(3)
    a.download_button("Check matrix (CSV)", frame_csv_text(frame), f"check_{s.name}.csv", mime="text/csv",
                      key="chk_dl_csv")
    b.download_button("Check matrix (JSON)", json_text(record), f"check_{s.name}.json", mime="application/json",
                      key="chk_dl_json", help="what `sar-budget check --json` writes for this scenario and mode")
    if c3.button("Build the report (HTML)", key="chk_build_report",
                 help="scenario, bounds, this check and figures; the Monte Carlo page adds P(pass)"):
        try:
            st.session_state["chk_report"] = (f"report_{s.name}.html", build_report(
                s, parts, mode=ctx.mode, assumptions=report_assumptions(ctx)).html())
        except InputError as err:
            st.session_state.pop("chk_report", None)
            c3.error(f"report not built: {error_text(err)}", icon=":material/error:")
    got = st.session_state.get("chk_report")
    if got is not None:
        c3.download_button("Download the report", got[1], got[0], mime="text/html", key="chk_dl_report")


run_page(render)
