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
#: Most part × scenario cells the page's grid runs at once (at :data:`SETUP_S_PER_CELL` each,
#: 200 cells are about half an hour before any trial); the page says so above the button.
MAX_CELLS = 200
#: Time estimate of a sweep: each part × scenario cell pays a set-up before its trials, the first
#: time this server process runs it (a cell run before in the same process skips most of it), then
#: its trials. Measured on this machine (2 cores, shared with other jobs) with
#: ``budget.api.sweep(["ADIS16405", "STIM300"], ["airborne_xband", "automotive_77ghz"], T, 1)`` in
#: a fresh process and again in the same process: set-up 9–12 s per airborne_xband cell (15–19 s
#: for the first cell of a fresh process), 4–6 s per automotive_77ghz cell; then 4 (ADIS16405 on
#: airborne_xband) to 25 (automotive_77ghz) trials/s. 8 trials per cell took 37 s in all (41 s in the
#: review that asked for this), 64 trials 49 s.
SETUP_S_PER_CELL = 8.0
TRIALS_PER_S = 10.0


#: Session-state keys of the aiding-mode control: whether the user changed it on this page, and
#: the sidebar's mode it last followed.
AIDING_KEY, AIDING_OVERRIDE_KEY, AIDING_FOLLOWED_KEY = "sw_aiding_mode", "sw_aiding_override", "sw_aiding_followed"


def _aiding_changed_here() -> None:
    st.session_state[AIDING_OVERRIDE_KEY] = True


def _aiding_mode(scenario) -> str | None:
    """Aiding correction mode the sweep runs when the scenario has aiding sensors (else None): the
    sidebar scenario's ``aiding_mode``, unless the user changed this page's control (and the
    sidebar's mode has not changed since: the later edit wins). The page says which mode runs."""
    if not getattr(scenario, "aiding", None):
        st.caption("The sidebar scenario has no aiding sensors (unaided IMU, as seed 004 assumes); "
                   "load a scenario with `aiding` to compare aiding modes here.")
        return None
    try:
        from budget.aiding_spec import CORRECTION_MODES
    except ImportError:  # aiding section not typed in this version
        return None
    own = scenario.aiding_mode
    state = st.session_state
    if (AIDING_KEY not in state or state.get(AIDING_FOLLOWED_KEY) != own
            or not state.get(AIDING_OVERRIDE_KEY)):
        state[AIDING_KEY] = own  # follow the sidebar (its mode changed, or the control was not touched)
        state[AIDING_OVERRIDE_KEY] = False
    state[AIDING_FOLLOWED_KEY] = own
    mode = st.selectbox("aiding correction mode (scenarios with aiding)", CORRECTION_MODES, key=AIDING_KEY,
                        on_change=_aiding_changed_here,
                        help="follows the sidebar scenario's aiding_mode until changed here")
    if mode == own:
        st.caption(f"The sweep runs aiding mode **{mode}**, the sidebar scenario's aiding_mode.")
    else:
        st.caption(f"The sweep runs aiding mode **{mode}**, chosen here: the sidebar scenario says **{own}** "
                   "(a change of it in the sidebar is followed again). Every swept scenario with aiding "
                   f"sensors runs **{mode}**.")
    return mode


def estimate_s(cells: int, trials: int) -> float:
    """Rough time (s) of a sweep of ``cells`` part × scenario cells of ``trials`` trials each run
    for the first time in this server: set-up per cell plus the trials
    (:data:`SETUP_S_PER_CELL`, :data:`TRIALS_PER_S`)."""
    return cells * (SETUP_S_PER_CELL + trials / TRIALS_PER_S)


def estimate_words(cells: int, trials: int) -> str:
    """The estimate as the page says it, with what it rests on."""
    total = estimate_s(cells, trials)
    when = f"{total:.0f} s" if total < 120 else f"{total / 60:.0f} min"
    return (f"≈ {when} — about {SETUP_S_PER_CELL:g} s set-up per cell the first time this server runs that part "
            f"on that scenario (less for a cell run before), then about {TRIALS_PER_S:g} trials/s; both vary about "
            "2× with the part and the scenario")


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


def _mode_run(inputs: tuple) -> None:
    """Say which aiding correction mode the shown run used (from its :func:`_inputs_key`)."""
    mode = inputs[4]
    if mode is not None:
        st.caption(f"Run with aiding correction mode **{mode}** on the scenarios with aiding sensors "
                   "(column 'navigation').")


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
    st.caption(f"{n} cells × {trials} trials: {estimate_words(n, trials)}")
    if n > MAX_CELLS:
        st.warning(f"{n} part × scenario cells is more than this page runs at once ({MAX_CELLS}, about "
                   f"{n * SETUP_S_PER_CELL / 60:.0f} min of set-up alone): pick fewer parts or scenarios to "
                   "enable **Run the sweep**.", icon=":material/warning:")
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
    _mode_run(last.inputs[0])
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
    _mode_run(last.inputs[0])
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
