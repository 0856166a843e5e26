"""Page: Monte Carlo verdict — P(pass) before/after PGA per part, failure reasons, metric
distributions and the worst trials (images and phase error), all from :func:`budget.mc.run_mc`."""

from __future__ import annotations

import math
from typing import NamedTuple

import pandas as pd
import streamlit as st

from budget.catalog.schema import PartSpec
from budget.errors import InputError
from budget.mc import REASONS, TRIAL_METRICS, McOptions, McResult, run_mc
from budget.check import check_parts
from budget.fileio import json_text
from budget.safe_text import frame_csv_text
from budget.mc.notes import SIMULATION_NOTES
from budget.mc.options import DEFAULT_SEED, DEFAULT_TRIALS, PREFILTERS
from budget.nav.manoeuvre import KINDS
from budget.plots.mc import (METRIC_LABELS, has_detail, metric_histogram_figure, pass_probability_figure,
                             trial_images_figure, trial_phase_figure)
from budget.report import build_report, check_vs_mc, mc_dict
from budget.scenario import Scenario

import components as c
import sidebar
from formatting import tidy
from page_frame import run_page
from uploads import error_text

DEFAULT_PART = "ADIS16405"
#: Platform motions the page offers (a custom disturbance needs a file: CLI or API).
PLATFORM_MOTIONS = tuple(k for k in KINDS if k != "custom")
MAX_TRIALS = 100_000
#: Scenes the page offers, the library's default first (budget.mc.McOptions.scene).
SCENES = (McOptions().scene, *(k for k in ("realistic", "points") if k != McOptions().scene))
#: Session-state key of the last run: (request, McRun) (:func:`components.run_on_demand`).
RUN_KEY = "mc_last_run"
#: Session-state key of the last built report: (inputs key, HTML text).
REPORT_KEY = "mc_report"


@st.cache_data(show_spinner=False, max_entries=16)
def _run(scenario_json: str, part_json: str, trials: int, seed: int, prefilter: str = "none",
         platform_motion: str = "straight", scene: str = SCENES[0]) -> McResult:
    """One part's verdict, cached on scenario, part, trials, seed and options (worst trials with images)."""
    part = PartSpec.model_validate_json(part_json)
    bar = st.progress(0.0, text=f"{part.part_id}: 0 / {trials} trials")

    def progress(done: int, total: int) -> None:
        bar.progress(done / total, text=f"{part.part_id}: {done} / {total} trials")

    try:  # a refused run (e.g. beyond the motion engine's memory limit) leaves no stale bar
        return run_mc(Scenario.model_validate_json(scenario_json), part, trials, seed,
                      options=McOptions(prefilter=prefilter, platform_motion={"kind": platform_motion},
                                        scene=scene),
                      progress=progress, keep_detail=True)
    finally:
        bar.empty()


class McRun(NamedTuple):
    """One press of **Run Monte Carlo**: the scenario and seed run, each part's result, and one
    line per distinct refusal (naming the scenario and the parts it hit)."""

    scenario: Scenario
    seed: int
    results: dict[str, McResult]
    refusals: list[str]


def _run_all(scenario: Scenario, parts: list[PartSpec], trials: int, seed: int, prefilter: str, motion: str,
             origin: str | None, scene: str = SCENES[0]) -> McRun:
    """Every part's verdict; a part the library refuses is left out and its message kept."""
    scenario_json = scenario.model_dump_json()
    results: dict[str, McResult] = {}
    failed: dict[str, list[str]] = {}  # one message per distinct error, with the parts it hit
    for part in parts:
        try:
            results[part.part_id] = _run(scenario_json, part.model_dump_json(), trials, seed, prefilter, motion,
                                         scene)
        except InputError as err:
            failed.setdefault(error_text(err), []).append(part.part_id)
    return McRun(scenario, seed, results,
                 [run_error(scenario.name, origin, pids, text) for text, pids in failed.items()])


def _inputs(catalog: dict[str, PartSpec]) -> tuple[list[str], int, int, str, str, str]:
    ids = list(catalog)
    default = [DEFAULT_PART] if DEFAULT_PART in catalog else ids[:1]
    parts = st.multiselect("parts", ids, default=default, key="mc_parts")
    left, mid, right, far, last = st.columns([1, 1, 1, 1, 1])
    trials = left.number_input("trials", min_value=1, max_value=MAX_TRIALS, value=DEFAULT_TRIALS, step=64,
                               key="mc_trials", help="a run of 64 trials takes about 10 s per part")
    seed = mid.number_input("seed", min_value=0, value=DEFAULT_SEED, step=1, key="mc_seed",
                            help="same seed → same trials, same result")
    prefilter = right.selectbox("IMU pre-filter", PREFILTERS, key="mc_prefilter",
                                help="seed 000's ARMA-Kalman filtering of the IMU output before "
                                     "navigation: does it change the verdict?")
    motion = far.selectbox("platform motion", PLATFORM_MOTIONS, key="mc_platform_motion",
                           help="straight: level, unrotated flight (gyro scale factor and misalignment "
                                "have no effect); oscillation: roll/pitch/yaw at the scenario's platform "
                                "rate, 10 s period; attitude_change: a roll through 1 rad over the aperture "
                                "(the gyro-scale-factor bound's manoeuvre)")
    scene = last.selectbox("scene", SCENES, key="mc_scene",
                           help="realistic: clutter, receiver noise and 16 dominant scatterers — what PGA "
                                "meets in practice; points: five noise-free points, PGA's best case")
    return parts, int(trials), int(seed), prefilter, motion, scene


def summary_frame(results: dict[str, McResult]) -> pd.DataFrame:
    """One row per part: trials, P(pass) before/after PGA with the 95 % Wilson interval."""
    return pd.DataFrame([{
        "part_id": pid, "trials": r.trials,
        "P(pass) before PGA": r.p_pass_before, "CI95 before low": r.ci_before[0], "CI95 before high": r.ci_before[1],
        "P(pass) after PGA": r.p_pass_after, "CI95 after low": r.ci_after[0], "CI95 after high": r.ci_after[1],
        "cancelled": r.cancelled} for pid, r in results.items()])


def _summary(results: dict[str, McResult], scenario: Scenario, seed: int) -> None:
    st.subheader("P(pass)")
    scene = next(iter(results.values())).judged_on.get("scene", "")
    st.caption(f"scenario **{scenario.name}** (Tc = {scenario.tc_s:.4g} s) · scene **{scene}** · seed {seed} · "
               "95 % Wilson intervals. Pass = image acceptance after PGA, range migration ≤ 1 cell, "
               "fast residual phase ≤ 1° rms (seed 004).")
    if len(results) == 1:
        (pid, r), = results.items()
        cols = st.columns(2)
        cols[0].metric(f"P(pass) before PGA — {pid}", f"{r.p_pass_before:.3f}",
                       help=f"95 % CI [{r.ci_before[0]:.3f}, {r.ci_before[1]:.3f}]")
        cols[1].metric(f"P(pass) after PGA — {pid}", f"{r.p_pass_after:.3f}",
                       help=f"95 % CI [{r.ci_after[0]:.3f}, {r.ci_after[1]:.3f}]")
    fmt = {k: "{:.3f}" for k in summary_frame(results).columns if k.startswith(("P(", "CI"))}
    st.dataframe(summary_frame(results).style.format(fmt), hide_index=True, key="mc_summary")
    first = next(iter(results.values()))
    for key in ("platform_motion", *SIMULATION_NOTES):
        if first.judged_on.get(key):  # what the simulation assumed that the user did not set
            st.caption(first.judged_on[key][:1].upper() + first.judged_on[key][1:] + ".")
    fills = [f"**{pid}** — {r.unspecified_summary()}" for pid, r in results.items() if r.unspecified_summary()]
    if fills:  # no silent zeros: say which datasheet terms were filled or taken as 0
        st.caption("  \n".join(fills))
    st.plotly_chart(pass_probability_figure(results), key="mc_pass_plot", width="stretch")
    st.subheader("Failure reasons (trials failing for each reason, after PGA)")
    st.dataframe(pd.DataFrame([{"part_id": pid, **r.agg.failure_reasons()} for pid, r in results.items()],
                              columns=["part_id", *REASONS]), hide_index=True, key="mc_reasons")


def _check_vs_mc(results: dict[str, McResult], scenario: Scenario, catalog: dict, ctx: sidebar.Context) -> None:
    """The analytic check of the same parts next to the Monte Carlo, in the Check page's mode with
    its assumptions (the sidebar's bounds mode; the scenario's acceleration level with the
    sidebar's edits, as ``sar-budget check --mode M``); the mode is said, and so is a disagreement."""
    st.subheader("Analytic check vs. Monte Carlo")
    parts = [catalog[p] for p in results if p in catalog]
    if not parts:
        return
    opts = next(iter(results.values())).options
    motion = opts.rotation_for_check if opts is not None else None
    try:
        checked = check_parts(parts, scenario, ctx.mode, ctx.edits(), platform_motion=motion)
        words = ctx.assumptions_words(scenario=scenario) if ctx.mode != "paper" else ""
    except InputError as err:  # e.g. derived bounds with platform_accel_m_s2 = 0: the CLI's refusal
        st.error(f"{ctx.mode} check of scenario {scenario.name} not run: {error_text(err)}", icon=":material/error:")
        return
    st.caption(f"Check verdict: **{ctx.mode}** bounds (the sidebar's bounds mode, as on the Check matrix)"
               + (f"; {words}" if words else "") + ". The Monte Carlo is compared with the verdict named in "
               "'compared verdict' (the PGA-limited check where it is known: seed 004's bounds tightened by what "
               "PGA cannot remove, `budget.report.check_vs_mc`).")
    recs = {r["part_id"]: r for r in checked.to_dict()["scenarios"][0]["parts"]}
    rows = []
    for pid, r in results.items():
        cmp_ = check_vs_mc(recs.get(pid, {"part_id": pid, "verdict": "not checked"}), r)
        rows.append(cmp_)
        if cmp_["agree"] is False:
            st.warning(f"**{pid}: the check and the Monte Carlo disagree.** {cmp_['reason']}",
                       icon=":material/warning:")
    frame = pd.DataFrame([{"part_id": x["part_id"],
                           f"check verdict ({ctx.mode})": x.get("seed004_verdict", x["check_verdict"]),
                           "compared verdict": f"{x['check_verdict']} ({x.get('check_basis', 'analytic check')})",
                           "MC P(pass) after PGA": x["mc_p_pass_after"], "MC verdict": x["mc_verdict"],
                           "agree": {True: "yes", False: "NO", None: "n/a"}[x["agree"]]} for x in rows])
    st.dataframe(tidy(frame), hide_index=True, key="mc_check_vs_mc")
    st.caption(f"MC verdict: pass when the 95 % interval of P(pass after PGA) lies at or above "
               f"{rows[0]['target']:g}, fail when below, undecided otherwise.")


def _downloads(results: dict[str, McResult], scenario: Scenario, catalog: dict, ctx: sidebar.Context,
               request: tuple) -> None:
    st.subheader("Export")
    a, b, c3 = st.columns(3)
    a.download_button("P(pass) table (CSV)", frame_csv_text(summary_frame(results)),
                      f"mc_{scenario.name}.csv", mime="text/csv", key="mc_dl_csv")
    b.download_button("Full results (JSON)", json_text({pid: mc_dict(r) for pid, r in results.items()}),
                      f"mc_{scenario.name}.json", mime="application/json", key="mc_dl_json")
    parts = [catalog[p] for p in results if p in catalog]
    key = (request, ctx.mode, repr(ctx.edits("derived")), repr(ctx.edits("no-autofocus")))
    if c3.button("Build the report (HTML)", key="mc_build_report",
                 help="scenario, bounds, check, these P(pass) with intervals, figures, provenance"):
        try:  # the check in the sidebar's mode, every mode's bounds with the scenario's assumptions and the edits
            assumed = {m: ctx.edits(m) for m in sidebar.MODES if ctx.edits(m)}  # completed from the scenario
            rep = build_report(scenario, parts, mode=ctx.mode, assumptions=assumed, mc_results=results)
            st.session_state[REPORT_KEY] = (key, rep.html())
        except InputError as err:
            c3.error(f"report not built: {error_text(err)}", icon=":material/error:")
    got = st.session_state.get(REPORT_KEY)
    if got is not None and got[0] == key:
        c3.download_button("Download the report (opens offline)", got[1], f"report_{scenario.name}.html",
                           mime="text/html", key="mc_dl_report", type="primary")


def run_error(scenario: str, origin: str | None, parts: list[str], text: str) -> str:
    """One line for a Monte Carlo the library refused: the scenario (and where its fields came
    from), the parts it was asked for, and the library's message."""
    return c.refused_run("Monte Carlo", [c.scenario_named(scenario, origin)], parts, text)


#: The trial metric that is a different quantity before and after PGA (:mod:`budget.mc.chain`):
#: after PGA the residual (estimate − truth) beyond PGA's settled window, before PGA the whole
#: phase error, constant and linear removed. The library has one label for it
#: (:data:`budget.plots.mc.METRIC_LABELS`, the after-PGA one); its before-PGA values get their own.
PHASE_METRIC = "residual_phase_rms_deg"
PHASE_BEFORE_LABEL = "whole phase error rms, constant and linear removed (deg) — before PGA"


def phase_after_label() -> str:
    return f"{METRIC_LABELS.get(PHASE_METRIC, PHASE_METRIC)} — after PGA"


def labelled_metrics(frame: pd.DataFrame, before: list[str], after: list[str]) -> pd.DataFrame:
    """``frame`` (one row per metric key in ``metric``; ``before`` and ``after`` its columns before
    and after PGA) with each metric's label; :data:`PHASE_METRIC`, not the same quantity before
    and after PGA, is two rows, each holding only the columns its label names."""
    rows = []
    for rec in frame.to_dict("records"):
        m = rec["metric"]
        if m == PHASE_METRIC:
            rows.append({**rec, "metric": PHASE_BEFORE_LABEL, **{col: math.nan for col in after}})
            rows.append({**rec, "metric": phase_after_label(), **{col: math.nan for col in before}})
        else:
            rows.append({**rec, "metric": METRIC_LABELS.get(m, m)})
    return pd.DataFrame(rows, columns=frame.columns)


def _percentiles(results: dict[str, McResult]) -> None:
    st.subheader("Metric percentiles (worst target per trial)")
    tabs = st.tabs(list(results))
    for tab, (pid, r) in zip(tabs, results.items()):
        frame = labelled_metrics(r.to_frame(), ["p50_before", "p95_before"], ["p50_after", "p95_after"])
        tab.dataframe(tidy(frame), hide_index=True, key=f"mc_pct_{pid}")


def _distribution(results: dict[str, McResult]) -> None:
    st.subheader("Metric distribution over trials (after PGA)")
    metric = st.selectbox("metric", TRIAL_METRICS, index=TRIAL_METRICS.index("residual_phase_rms_deg"),
                          format_func=lambda m: METRIC_LABELS.get(m, m), key="mc_metric")
    values = {pid: mc_dict(r).get("metrics_after", {}).get(metric, []) for pid, r in results.items()}
    st.plotly_chart(metric_histogram_figure(values, metric), key="mc_hist", width="stretch")


def _inspector(results: dict[str, McResult]) -> None:
    st.subheader("Worst trials")
    left, right = st.columns(2)
    pid = left.selectbox("part", list(results), key="mc_worst_part")
    worst = results[pid].worst_trials()
    if not worst:
        st.info("No trial kept for inspection.")
        return
    labels = {o.trial: f"trial {o.trial} — {', '.join(o.reasons) or 'passed'}" for o in worst}
    trial = right.selectbox("trial (worst first)", list(labels), format_func=labels.get, key="mc_worst_trial")
    o = next(w for w in worst if w.trial == trial)
    metrics = pd.DataFrame([{"metric": m, "before PGA": o.before.get(m), "after PGA": o.after.get(m)}
                            for m in TRIAL_METRICS])
    st.dataframe(tidy(labelled_metrics(metrics, ["before PGA"], ["after PGA"])), hide_index=True,
                 key="mc_worst_metrics")
    st.caption(f"peak range migration {o.peak_range_cells:.3g} range cells · PGA "
               f"{'converged' if o.pga_converged else 'did not converge'} ({o.pga_reason})")
    if not has_detail(o.detail):
        st.info("This run kept no images for its worst trials.")
        return
    st.plotly_chart(trial_images_figure(o.detail, title=f"{pid}, trial {o.trial}: image (dB re. peak)"),
                    key="mc_worst_images", width="stretch")
    st.plotly_chart(trial_phase_figure(o.detail, title=f"{pid}, trial {o.trial}: phase error, truth vs. PGA"),
                    key="mc_worst_phase", width="stretch")


def render() -> None:
    ctx = sidebar.require_context()
    if ctx is None:
        return
    s = ctx.scenario
    st.title("Monte Carlo verdict")
    st.markdown("Each trial draws the part's IMU errors, propagates them to the antenna phase centre, "
                "forms the image with the IMU-measured track and runs PGA autofocus. Does autofocus "
                "absorb what the IMU leaves? The scenario comes from the sidebar.")
    catalog = c.session_catalog()
    parts, trials, seed, prefilter, motion, scene = _inputs(catalog)
    chosen = [catalog[p] for p in parts]
    request = (s.model_dump_json(), tuple(p.model_dump_json() for p in chosen), trials, seed, prefilter, motion,
               scene)
    origin = st.session_state.get(sidebar.BASE_ORIGIN_KEY)
    last = c.run_on_demand(RUN_KEY, request, "Run Monte Carlo",
                           lambda: _run_all(s, chosen, trials, seed, prefilter, motion, origin, scene),
                           button_key="mc_run",
                           prompt="Pick parts, trials and seed, then press **Run Monte Carlo**.", disabled=not parts)
    if last is None:
        return
    run = last.result
    for text in run.refusals:
        st.error(text, icon=":material/error:")
    results = run.results
    if not results:
        return
    _summary(results, run.scenario, run.seed)
    _check_vs_mc(results, run.scenario, catalog, ctx)
    _downloads(results, run.scenario, catalog, ctx, last.inputs)
    _percentiles(results)
    _distribution(results)
    _inspector(results)


run_page(render)
