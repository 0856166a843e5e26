"""Page: real SAR data — focus a recorded phase history (AFRL format) on a ground grid, autofocus
it, and show the image before/after, the estimated vs recorded phase error and what the data are
(band, aperture, resolutions: ``FocusResult.acquisition``); and a catalog part's verdict on the
scene (its motion error injected into the recorded data, P(pass) after PGA with its interval,
per-trial outcomes, the floor and the assumptions). Every number from ``budget.sar.focus_pga`` and
``budget.mc.real_scene``; this page only collects the inputs and draws."""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path

import pandas as pd
import streamlit as st

from budget.catalog.schema import PartSpec
from budget.errors import InputError
from budget.fileio import json_safe
from budget.mc.real_scene import (DEFAULT_EXTENT_M, DEFAULT_SPEED_M_S, DEFAULT_SPEED_REASON, REASONS,
                                  RealSceneOptions, RealSceneVerdict, real_scene_verdict)
from budget.plots.focus import image_pair_figure, phase_figure
from budget.plots.real_scene import real_scene_trials_figure
from budget.sar.afrl import name_order, read_afrl
from budget.sar.focus import FocusOptions
from budget.sar.focus_pga import AUTOFOCUS_MODES, focus

import components as c
from formatting import fmt_value, tidy
from page_frame import run_page
from uploads import error_text

SOURCES = ("directory of .mat files", "upload .mat files")
MAX_UPLOAD_MB = 50
#: Environment variable naming a default directory of phase-history files.
DATA_ENV = "SAR_BUDGET_SAR_DATA"
#: The part the verdict section starts with (present in the shipped catalog).
DEFAULT_VERDICT_PART = "STIM300"
#: Trials the verdict section starts with: one backprojection each, so few.
DEFAULT_VERDICT_TRIALS = 8
MAX_VERDICT_TRIALS = 1000
#: Session-state keys of the image and of the verdict shown: (inputs, FocusResult) and (inputs,
#: RealSceneVerdict), each kept until the next run of its button (:func:`components.run_on_demand`).
FOCUS_KEY, VERDICT_KEY = "focus_image_last", "focus_verdict_last"


def _files_in(directory: str) -> list[Path]:
    d = Path(directory).expanduser()
    if not d.is_dir():
        raise InputError("directory not found", file=d, expected="a directory holding AFRL .mat files")
    files = name_order(d.glob("*.mat"))
    if not files:
        raise InputError("no .mat files", file=d, expected="AFRL phase-history .mat files")
    return files


def _with_injection(ph, inject: tuple[float, float, float, float] | None):
    return ph if inject is None else ph.with_smooth_phase_error(*inject)


@st.cache_data(show_spinner="Backprojecting and autofocusing …", max_entries=4)
def _run_paths(paths: tuple[str, ...], options_json: str, autofocus: str,
               inject: tuple[float, float, float, float] | None = None):
    return focus(_with_injection(read_afrl(list(paths)), inject), FocusOptions.model_validate_json(options_json),
                 autofocus)


def _read_uploads(blobs: tuple[tuple[str, bytes], ...]):
    """The phase history of uploaded files (written to a private temporary copy, read as the CLI
    reads files; errors name the uploaded file)."""
    with tempfile.TemporaryDirectory() as tmp:
        paths = []
        for name, data in blobs:
            path = Path(tmp) / Path(name).name
            with open(path, "wb") as fh:
                fh.write(data)
            paths.append(str(path))
        try:
            return read_afrl(paths)
        except InputError as err:
            if err.file and tmp in err.file:
                err.rename_file(err.file.replace(tmp + os.sep, ""))
            raise


@st.cache_data(show_spinner="Backprojecting and autofocusing …", max_entries=2)
def _run_uploads(blobs: tuple[tuple[str, bytes], ...], options_json: str, autofocus: str,
                 inject: tuple[float, float, float, float] | None = None):
    return focus(_with_injection(_read_uploads(blobs), inject), FocusOptions.model_validate_json(options_json),
                 autofocus)


def _verdict(ph, part_json: str, trials: int, seed: int, options_json: str) -> RealSceneVerdict:
    """The part's verdict on ``ph`` with a progress bar (removed when done, or refused)."""
    part = PartSpec.model_validate_json(part_json)
    bar = st.progress(0.0, text=f"{part.part_id}: reference run (no injection) …")

    def progress(done: int, total: int) -> None:
        bar.progress(done / total, text=f"{part.part_id}: {done} / {total} trials")

    try:
        return real_scene_verdict(ph, part, trials, seed, RealSceneOptions.model_validate_json(options_json),
                                  progress=progress)
    finally:
        bar.empty()


@st.cache_data(show_spinner=False, max_entries=8)
def _verdict_paths(paths: tuple[str, ...], part_json: str, trials: int, seed: int,
                   options_json: str) -> RealSceneVerdict:
    return _verdict(read_afrl(list(paths)), part_json, trials, seed, options_json)


@st.cache_data(show_spinner=False, max_entries=2)
def _verdict_uploads(blobs: tuple[tuple[str, bytes], ...], part_json: str, trials: int, seed: int,
                     options_json: str) -> RealSceneVerdict:
    return _verdict(_read_uploads(blobs), part_json, trials, seed, options_json)


def _injection() -> tuple[float, float, float, float] | None:
    """A known smooth phase error to multiply into the phase history (to see what PGA recovers)."""
    if not st.checkbox("inject a known phase error q u² + c u³ + s sin(Nπu) (u = −1 … 1 over the pulses)",
                       key="focus_inject"):
        return None
    a, b, c2, d = st.columns(4)
    return (a.number_input("q (rad)", -50.0, 50.0, 4.0, 0.5, key="focus_inject_q"),
            b.number_input("c (rad)", -50.0, 50.0, 2.0, 0.5, key="focus_inject_c"),
            c2.number_input("s (rad)", -50.0, 50.0, 1.5, 0.5, key="focus_inject_s"),
            d.number_input("N (cycles)", 0.0, 50.0, 1.5, 0.5, key="focus_inject_n"))


def _comparison_rows(comparison: dict) -> list[dict]:
    """One row per number; the comparison with the known error (recorded + injected) prefixed."""
    rows = []
    for k, v in comparison.items():
        if isinstance(v, dict):
            ref = v.get("reference", "known")
            rows += [{"quantity": f"against {ref}: {kk}", "value": vv} for kk, vv in v.items() if kk != "reference"]
        else:
            rows.append({"quantity": k, "value": v})
    return rows


def _options() -> FocusOptions:
    a, b, c2, d = st.columns(4)
    rng = a.number_input("ground-range extent (m)", 5.0, 1000.0, 100.0, 5.0, key="focus_range_extent")
    az = b.number_input("cross-range extent (m)", 5.0, 1000.0, 100.0, 5.0, key="focus_azimuth_extent")
    sp = c2.number_input("pixel spacing (m)", 0.05, 5.0, 0.25, 0.05, key="focus_spacing")
    win = d.selectbox("window (range and azimuth)", ("taylor-35-4", "rect", "taylor-25-3"), key="focus_window")
    return FocusOptions.build(range_extent_m=rng, azimuth_extent_m=az, spacing_m=sp, range_window=win,
                              azimuth_window=win)


def _source(src: str) -> tuple[str, object] | None:
    """Where the phase history comes from: ("paths", directory) or ("uploads", ((name, bytes), …)),
    or None after telling the user what to give."""
    if src == SOURCES[0]:
        directory = st.text_input("directory (all its .mat files, in name order, form one aperture)",
                                  os.environ.get(DATA_ENV, ""), key="focus_dir")
        if not directory:
            st.info(f"Name a directory of AFRL .mat files (or set {DATA_ENV}), or upload files.")
            return None
        return "paths", directory
    ups = st.file_uploader(f"AFRL .mat files (at most {MAX_UPLOAD_MB} MB each)", type=["mat"],
                           accept_multiple_files=True, key="focus_upload", max_upload_size=MAX_UPLOAD_MB)
    if not ups:
        st.info("Upload one or more AFRL .mat files (they are concatenated in name order, az2 before az10).")
        return None
    by_name = {u.name: u for u in ups}
    return "uploads", tuple((n, by_name[n].getvalue()) for n in name_order(by_name))


def _identity(source: tuple[str, object]) -> tuple:
    """What identifies the phase history in a run's inputs: the directory, or each uploaded file's
    name and content digest (files of one pass often share their size)."""
    kind, value = source
    if kind == "paths":
        return kind, value
    return kind, tuple((n, hashlib.sha256(b).hexdigest()) for n, b in value)


def _focus(source: tuple[str, object], options: FocusOptions, autofocus: str, inject):
    kind, value = source
    if kind == "paths":
        return _run_paths(tuple(str(p) for p in _files_in(value)), options.model_dump_json(), autofocus, inject)
    return _run_uploads(value, options.model_dump_json(), autofocus, inject)


def _focus_section(source: tuple[str, object], identity: tuple, options: FocusOptions, autofocus: str,
                   inject) -> None:
    """The image before/after autofocus; runs when **Focus** is pressed and keeps that result until
    the next run."""
    inputs = (identity, options.model_dump_json(), autofocus, inject)
    last = c.run_on_demand(FOCUS_KEY, inputs, "Focus", lambda: _focus(source, options, autofocus, inject),
                           button_key="focus_run",
                           prompt="Press **Focus** to backproject and autofocus the phase history.")
    if last is None:
        return
    result = last.result
    s = result.scalars()
    m1, m2, m3, m4 = st.columns(4)
    m1.metric("pulses", s["pulses"])
    m2.metric("entropy before", f"{s['entropy_before']:.5g}")
    m3.metric("entropy after", f"{s['entropy_after']:.5g}", delta=f"{s['entropy_after'] - s['entropy_before']:+.3g}",
              delta_color="inverse")
    diff = s["recorded_af_rms_diff_rad"]
    m4.metric("rms diff. from recorded (rad)", "—" if diff is None else f"{diff:.3g}")
    known = result.comparison.get("known")
    if known:
        k1, k2, _, _ = st.columns(4)
        k1.metric(f"known error ({known['reference']}), rms (rad)", f"{known['recorded_beyond_linear_rms_rad']:.3g}")
        k2.metric("rms diff. from known (rad)", f"{known['rms_diff_rad']:.3g}")
    st.plotly_chart(image_pair_figure(result), key="focus_images")
    st.plotly_chart(phase_figure(result), key="focus_phase")
    if result.comparison:
        st.dataframe(_comparison_rows(result.comparison), hide_index=True, key="focus_comparison")
    st.subheader("What the data are")
    st.caption("Band and aperture from the files' own fields; resolutions and unambiguous extents in closed "
               "form (c/(2B), c/(2B cos ψ), λ/(2Δθ); c/(2Δf), λ/(2δθ)) beside the image's pixel spacing.")
    st.dataframe(result.acquisition.to_frame()[["quantity", "shown"]], hide_index=True, key="focus_acquisition")
    for note in result.acquisition.notes:
        st.warning(note)
    if result.pga:
        st.caption(f"PGA: {result.pga.get('reason')}")
    for note in result.notes:
        st.caption(note)
    st.download_button("Download FOCUS.json", json.dumps(json_safe(result.to_dict()), indent=2), "focus.json",
                       mime="application/json", key="focus_dl")


def _verdict_inputs(options: FocusOptions) -> tuple[PartSpec, int, int, RealSceneOptions | None]:
    """Part (shipped + user catalog), trials, seed, assumed speed, patch; the options built by the
    library (None after showing its refusal)."""
    catalog = c.session_catalog()
    ids, user = list(catalog), set(c.user_parts())
    a, b, c2, d, e = st.columns([2, 1, 1, 1, 1])
    pid = a.selectbox("part (shipped catalog and your uploaded parts)", ids,
                      index=ids.index(DEFAULT_VERDICT_PART) if DEFAULT_VERDICT_PART in ids else 0,
                      format_func=lambda p: f"{p} (your catalog)" if p in user else p, key="focus_verdict_part")
    trials = b.number_input("trials", min_value=1, max_value=MAX_VERDICT_TRIALS, value=DEFAULT_VERDICT_TRIALS,
                            step=1, key="focus_verdict_trials",
                            help=f"one backprojection and PGA per trial: ≈ 1 s per trial for the "
                                 f"{DEFAULT_EXTENT_M:g} m patch on 2 threads (the time grows with the patch's "
                                 "area), plus one reference run")
    seed = c2.number_input("seed", min_value=0, value=1, step=1, key="focus_verdict_seed",
                           help="same seed → same draws of the part's errors, same verdict")
    speed = d.number_input("assumed platform speed (m/s)", value=DEFAULT_SPEED_M_S, step=10.0, format="%g",
                           key="focus_verdict_speed", help=f"default {DEFAULT_SPEED_M_S:g} m/s: {DEFAULT_SPEED_REASON}")
    patch = e.number_input("patch, square (m)", 5.0, 1000.0, DEFAULT_EXTENT_M, 5.0, key="focus_verdict_patch",
                           help="ground range × cross range imaged per trial; pixel spacing and window as above")
    try:
        opts = RealSceneOptions.build(platform_speed_m_s=speed, focus=FocusOptions.build(
            **{**options.model_dump(), "range_extent_m": patch, "azimuth_extent_m": patch}))
    except InputError as err:
        st.error(error_text(err), icon=":material/error:")
        return catalog[pid], int(trials), int(seed), None
    return catalog[pid], int(trials), int(seed), opts


def _show_verdict(v: RealSceneVerdict) -> None:
    lo, hi = v.interval
    m1, m2, m3, m4 = st.columns(4)
    m1.metric(f"P(pass) after PGA — {v.part}", f"{v.p_pass:.2f}", help=f"95 % Wilson interval [{lo:.2f}, {hi:.2f}]")
    m2.metric("95 % interval (Wilson)", f"[{lo:.2f}, {hi:.2f}]")
    m3.metric("trials passed", f"{v.passed} / {v.trials}")
    m4.metric("time per trial (s)", f"{v.timings_s.get('per_trial', float('nan')):.2f}",
              help=f"{v.timings_s.get('total', float('nan')):.1f} s in all, with the reference run")
    lim = v.limits
    migration = (f", range migration ≤ {lim['range_migration_cells']:g} cells"
                 if lim.get("range_migration_cells") is not None else "")
    st.caption(f"seed {v.seed} · assumed speed {v.options.platform_speed_m_s:g} m/s · Tc {v.scenario.tc_s:.3g} s · "
               f"patch {v.options.focus.range_extent_m:g} m × {v.options.focus.azimuth_extent_m:g} m at "
               f"{v.options.focus.spacing_m:g} m. Judged: {lim['judged_on']}. Limits: beyond PGA's window ≤ "
               f"{lim['residual_beyond_window_deg']:g}° rms, peak loss ≤ {lim['peak_loss_db']:g} dB{migration}.")
    st.markdown("**Failure reasons** (trials failing for each)")
    counts = v.failure_counts()
    st.dataframe(pd.DataFrame([{r: counts.get(r, 0) for r in REASONS}]), hide_index=True,
                 key="focus_verdict_reasons")
    st.plotly_chart(real_scene_trials_figure(v), key="focus_verdict_plot", width="stretch")
    st.markdown("**Per trial**")
    st.dataframe(tidy(v.to_frame().reset_index()), hide_index=True, key="focus_verdict_trials_table")
    st.markdown("**The floor: the reference run** (no injection; PGA against the recorded solution)")
    st.dataframe([{"quantity": k, "value": fmt_value(val)} for k, val in v.reference.items()],
                 hide_index=True, key="focus_verdict_reference")
    st.markdown("**Assumptions and notes**")
    for note in v.notes:
        st.caption(note)
    with st.expander("Summary (as `sar-budget focus --part` prints it)"):
        st.code(v.summary(), language=None)
    st.download_button("Download VERDICT.json", json.dumps(json_safe(v.to_dict()), indent=2), "verdict.json",
                       mime="application/json", key="focus_verdict_dl")


def _run_verdict(source: tuple[str, object], part: PartSpec, trials: int, seed: int,
                 opts: RealSceneOptions) -> RealSceneVerdict:
    kind, value = source
    args = (part.model_dump_json(), trials, seed, opts.model_dump_json())
    if kind == "paths":
        return _verdict_paths(tuple(str(p) for p in _files_in(value)), *args)
    return _verdict_uploads(value, *args)


def _verdict_section(source: tuple[str, object], identity: tuple, options: FocusOptions) -> None:
    """A catalog part's motion error injected into these data, focused, PGA, judged (the library's
    :func:`budget.mc.real_scene.real_scene_verdict`); runs when its button is pressed and keeps that
    result until the next run."""
    st.subheader("Part verdict on this scene")
    st.caption("Each trial draws the part's IMU errors (the Monte Carlo's motion engine), injects their "
               "line-of-sight range error into the recorded phase history exactly, backprojects, runs PGA "
               "and judges what PGA adds to the scene's own floor; the data as recorded (no known phase "
               f"error injected). Cost: ≈ 1 s per trial for the {DEFAULT_EXTENT_M:g} m patch on 2 threads "
               "(growing with the patch's area), plus one reference run.")
    part, trials, seed, opts = _verdict_inputs(options)
    if opts is None:
        return
    inputs = (identity, part.model_dump_json(), trials, seed, opts.model_dump_json())
    last = c.run_on_demand(VERDICT_KEY, inputs, "Run the verdict",
                           lambda: _run_verdict(source, part, trials, seed, opts), button_key="focus_verdict_run",
                           prompt="Pick a part, trials, seed, speed and patch, then press **Run the verdict**.")
    if last is not None:
        _show_verdict(last.result)


def render() -> None:
    st.title("Real SAR data")
    st.caption("Backprojection of a recorded phase history onto a ground grid, phase gradient autofocus on "
               "the real image, and the comparison with the data provider's own autofocus solution.")
    src = st.radio("phase history", SOURCES, horizontal=True, key="focus_source")
    autofocus = st.radio("autofocus", AUTOFOCUS_MODES, horizontal=True, key="focus_mode")
    options = _options()
    inject = _injection()
    source = _source(src)
    if source is None:
        return
    identity = _identity(source)
    _focus_section(source, identity, options, autofocus, inject)
    _verdict_section(source, identity, options)


run_page(render, sidebar=False)  # the phase history carries its own geometry
