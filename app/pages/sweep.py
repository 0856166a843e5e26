"""Page: trade study — P(pass) over parts × scenarios (heat map) and P(pass) against slant range,
speed or azimuth resolution (Tc follows), from :func:`budget.sweep`; downloads as CSV/JSON.

Runs only when its button is pressed; the last result stays until the next run
(:func:`components.run_on_demand`).
"""

from __future__ import annotations

import numpy as np
import streamlit as st

from budget.api import VARIABLE_FIELDS, load_scenarios, sweep_over
from budget.api import sweep as run_sweep
from budget.fileio import json_text
from budget.safe_text import frame_csv_text
from budget.mc.options import DEFAULT_SEED, DEFAULT_TRIALS
from budget.mc.sweep import not_simulated
from budget.plots.sweep import pass_heatmap_figure, pass_vs_figure
from budget.presets import PRESETS, get_preset

import components as c
import sidebar
from formatting import tidy
from page_frame import run_page

DEFAULT_PARTS = ("ADIS16405", "STIM300")
CURRENT = "current scenario (sidebar)"
#: Session-state keys of the last runs: (inputs, table) and (inputs, (field, table)).
GRID_KEY, LINE_KEY = "sw_grid_last", "sw_line_last"
MAX_CELLS = 200


def _aiding_mode(scenario) -> str | None:
    """Aiding correction mode to use when the scenario has aiding sensors (else None)."""
    if not getattr(scenario, "aiding", None):
        st.caption("The sidebar scenario has no aiding sensors (unaided IMU, as seed 004 assumes); "
                   "load a scenario with `aiding` to compare aiding modes here.")
        return None
    try:
        from budget.aiding_spec import CORRECTION_MODES
    except ImportError:  # aiding section not typed in this version
        return None
    return st.selectbox("aiding correction mode (scenarios with aiding)", CORRECTION_MODES,
                        index=CORRECTION_MODES.index(scenario.aiding_mode)
                        if getattr(scenario, "aiding_mode", None) in CORRECTION_MODES else 0,
                        key="sw_aiding_mode")


def _with_mode(scenarios, mode: str | None):
    if mode is None:
        return scenarios
    return [s.model_copy(update={"aiding_mode": mode}) if getattr(s, "aiding", None) else s for s in scenarios]


def _progress():
    bar = st.progress(0.0, text="0 cells")

    def cb(done: int, total: int) -> None:
        bar.progress(done / max(total, 1), text=f"{done} / {total} part × scenario cells")
    return bar, cb


def _with_progress(run):
    """``run(progress)`` with a progress bar, removed when done or refused."""
    bar, cb = _progress()
    try:
        return run(cb)
    finally:
        bar.empty()


def _on_demand(key: str, inputs: tuple, label: str, run, *, button_key: str, prompt: str, what: str,
               scenarios: list[str], parts: list, disabled: bool):
    """:func:`components.run_on_demand` of ``run(progress)`` with a progress bar; a refusal (a motion
    run beyond its memory limit, a scenario the simulator cannot form) is one line naming the
    scenario(s) and parts as the Monte Carlo page does, and the rest of the page (and the last
    result) stays."""
    return c.run_on_demand(key, inputs, label, lambda: _with_progress(run), button_key=button_key, prompt=prompt,
                           refused=lambda text: c.refused_run(what, scenarios, [p.part_id for p in parts], text),
                           disabled=disabled)


def _inputs_key(scenario, parts: list, trials: int, seed: int, mode: str | None) -> tuple:
    """What every sweep depends on: the sidebar scenario, the parts, trials, seed, aiding mode."""
    return scenario.model_dump_json(), tuple(p.model_dump_json() for p in parts), trials, seed, mode


def _sidebar_scenario(s) -> str:
    """The sidebar's scenario as a refusal names it (with where its fields came from)."""
    return c.scenario_named(s.name, st.session_state.get(sidebar.BASE_ORIGIN_KEY))


def _downloads(table, stem: str, key: str) -> None:
    a, b = st.columns(2)
    a.download_button("Download the table (CSV)", frame_csv_text(table), f"{stem}.csv", mime="text/csv",
                      key=f"{key}_csv")
    b.download_button("Download the table (JSON)", json_text(table.to_dict(orient="records")), f"{stem}.json",
                      mime="application/json", key=f"{key}_json")


def _same_preset(scenario, names: list[str]) -> str | None:
    """The preset of ``names`` that the sidebar scenario (listed as :data:`CURRENT`) equals, if any."""
    if CURRENT not in names:
        return None
    return next((n for n in names if n in PRESETS and get_preset(n) == scenario), None)


def _grid(ctx, parts: list, trials: int, seed: int, mode: str | None) -> None:
    st.subheader("P(pass) over parts × scenarios")
    names = st.multiselect("scenarios", [CURRENT, *sorted(PRESETS)], default=[CURRENT, "automotive_77ghz"],
                           key="sw_scenarios")
    same = _same_preset(ctx.scenario, names)
    n = len(parts) * (len(names) - bool(same))
    st.caption(f"{n} cells × {trials} trials (≈ {n * trials / 20:.0f} s at 20 trials/s)")
    if same:  # the library refuses a scenario given twice; here it is one row of the list
        st.caption(f"The sidebar scenario is the preset **{same}**, also picked in the list: swept once.")
    scens = [ctx.scenario if s == CURRENT else s for s in names if not (same and s == CURRENT)]
    described = [_sidebar_scenario(s) if s is ctx.scenario else s for s in scens]
    last = _on_demand(GRID_KEY, (_inputs_key(ctx.scenario, parts, trials, seed, mode), tuple(names)),
                      "Run the sweep",
                      lambda cb: run_sweep(parts, _with_mode(load_scenarios(scens), mode), trials, seed, progress=cb),
                      button_key="sw_run_grid", prompt="Pick parts and scenarios, then press **Run the sweep**.",
                      what="Sweep", scenarios=described, parts=parts,
                      disabled=not (parts and names) or n > MAX_CELLS)
    if last is None:
        return
    table = last.result
    st.markdown(f"<span id='sweep-grid-done'>{len(table)} cells</span>", unsafe_allow_html=True)
    for name, status in not_simulated(table).items():
        st.warning(f"**{name}**: {status} (its cells are empty; the analytic check still applies)")
    st.plotly_chart(pass_heatmap_figure(table), key="sw_heatmap", width="stretch")
    st.dataframe(tidy(table), hide_index=True, key="sw_table")
    _downloads(table, "sweep", "sw_grid")


def _line(ctx, parts: list, trials: int, seed: int, mode: str | None) -> None:
    st.subheader("P(pass) against one scenario quantity")
    s = ctx.scenario
    left, mid, right = st.columns([2, 2, 1])
    field = left.selectbox("vary", list(VARIABLE_FIELDS), format_func=VARIABLE_FIELDS.get, key="sw_field")
    now = float(getattr(s, field))
    lo, hi = mid.select_slider("from … to (× the current value)", options=[0.25, 0.5, 1.0, 2.0, 4.0],
                               value=(0.5, 2.0), key="sw_span")
    points = int(right.number_input("points", min_value=2, max_value=12, value=4, key="sw_points"))
    x_tc = st.checkbox("x axis: Tc instead of the varied quantity", key="sw_x_tc")
    values = np.geomspace(now * lo, now * hi, points) if lo < hi else np.array([now])
    st.caption(f"{field} = " + ", ".join(f"{v:.4g}" for v in values) + f" on scenario **{s.name}**")
    last = _on_demand(LINE_KEY, (_inputs_key(s, parts, trials, seed, mode), field, tuple(values.tolist())), "Run",
                      lambda cb: (field, sweep_over(parts, _with_mode([s], mode)[0], field, values, trials, seed,
                                                    progress=cb)),
                      button_key="sw_run_line", prompt="Press **Run** to draw P(pass) against the chosen quantity.",
                      what=f"Sweep over {field}", scenarios=[_sidebar_scenario(s)], parts=parts, disabled=not parts)
    if last is None:
        return
    f, table = last.result
    x = "tc_s" if x_tc else f
    for name, status in not_simulated(table).items():
        st.warning(f"**{name}**: {status}")
    st.plotly_chart(pass_vs_figure(table, x, x_label="Tc (s)" if x_tc else VARIABLE_FIELDS[f], log_x=True),
                    key="sw_line_plot", width="stretch")
    st.dataframe(tidy(table), hide_index=True, key="sw_line_table")
    _downloads(table, f"sweep_{f}", "sw_line")


def render() -> None:
    ctx = sidebar.require_context()
    if ctx is None:
        return
    st.title("Trade study")
    st.markdown("Monte Carlo P(pass after PGA) for several parts at once (same seed for every cell: "
                "common random numbers make the comparison between parts sharper). The current scenario "
                "comes from the sidebar.")
    catalog = c.session_catalog()
    parts = st.multiselect("parts", list(catalog), default=[p for p in DEFAULT_PARTS if p in catalog],
                           key="sw_parts")
    left, right = st.columns(2)
    trials = int(left.number_input("trials per cell", min_value=1, max_value=10_000, value=DEFAULT_TRIALS,
                                   step=64, key="sw_trials"))
    seed = int(right.number_input("seed", min_value=0, value=DEFAULT_SEED, step=1, key="sw_seed"))
    mode = _aiding_mode(ctx.scenario)
    chosen = [catalog[p] for p in parts]
    _grid(ctx, chosen, trials, seed, mode)
    _line(ctx, chosen, trials, seed, mode)


run_page(render)
