"""Page: check matrix — parts × parameters with margins, verdict, binding parameter, grade advice."""

from __future__ import annotations

import streamlit as st

from budget.catalog.schema import GRADES
from budget.check import check_parts, recommend_grade
from budget.plots.check import margin_heatmap_figure

import components as c
import sidebar
from page_frame import run_page
from check_view import check_frame, style_check_frame, verdict_counts


def _recommendation(ctx: sidebar.Context) -> None:
    s = ctx.scenario
    if ctx.mode == "no-autofocus":
        st.caption("Grade recommendation uses the paper or derived bounds; pick one of them in the sidebar.")
        return
    rec = recommend_grade([s.tc_s], s.range_resolution_m, list(c.grades().values()), mode=ctx.mode)
    note = " (default assumptions)" if ctx.mode == "derived" else ""
    st.metric(f"lowest sufficient grade, {ctx.mode} bounds{note}", rec.grade[0] or "none",
              help="bias and noise terms vs. the best typical values of each grade, seed 004 Tables 3–4")


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
    result = check_parts(parts, s, ctx.mode, ctx.assumptions())
    frame = check_frame(result)
    n = verdict_counts(frame)
    st.markdown(f"Scenario **{s.name}**: Tc = **{s.tc_s:.4g} s**, δr = {s.range_resolution_m:.4g} m, "
                f"**{ctx.mode}** bounds → <span id='check-summary'>**{n['pass']} pass · {n['fail']} fail · "
                f"{n['unknown']} unknown**</span>", unsafe_allow_html=True)
    cols = st.columns([1, 1, 1, 2])
    cols[0].metric("pass", n["pass"])
    cols[1].metric("fail", n["fail"])
    cols[2].metric("unknown", n["unknown"], help="no error figure in the datasheet")
    with cols[3]:
        _recommendation(ctx)
    # A static HTML table: every cell readable (and testable in a browser), colours and frames kept.
    st.table(style_check_frame(frame).hide(axis="index"))
    st.caption("Margin = bound / datasheet value (≥ 1 passes, green; < 1 fails, red; – not in the datasheet, "
               "never assumed). The framed, darker cell is the binding (smallest-margin) parameter. In-run "
               "bias instability is checked against the bias bounds, as seed 004 Tables 3–4 do.")
    st.plotly_chart(margin_heatmap_figure(result), key="chk_heatmap", width="stretch")


run_page(render)
