"""Page: model gap — a measured log (or Allan table) against the model it should follow: where
they disagree, which effect is missing, and the gap after adding it. Every number from ``budget.gap``.

The workflow runs only when **Run** is pressed; its result is kept in the session and shown
until the next run (a later change of an input says so instead of silently re-running).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import streamlit as st

from budget.api import load_part
from budget.catalog.schema import PartSpec
from budget.fileio import json_text
from budget.gap import run_gap
from budget.gap.inputs import log_from_arrays
from budget.imu.generator import simulate_static_log
from budget.imu.noise_model import NoiseModel
from budget.noise import ImuLog
from budget.units import CHANNELS
from budget.plots.gap import adev_figure, gap_figure, psd_figure

import components as c
from formatting import fmt_value, tidy
from page_frame import run_page
from upload_tables import is_adev_table, upload_log_or_table, uploaded_adev
from uploads import layout_inputs, read_uploaded_log, read_via_temp_copy, repair_box, show_log_findings

SOURCES = ("built-in example (a part with a hidden effect)", "upload a log or an Allan table")
#: The example: 30 min at 100 Hz of the chosen part, plus a sinusoid on gyro_z the part does not
#: have (0.7 Hz, 0.02 deg/s peak), so the workflow has something to find.
EXAMPLE_RATE_HZ, EXAMPLE_SECONDS = 100.0, 1800.0
EXAMPLE_EFFECT = {"name": "sinusoid", "channel": "gyro_z",
                  "params": {"frequency_hz": 0.7, "amplitude": float(np.radians(0.02))}}
#: Rows read from an uploaded log by default (10⁶ = a real ADIS16405 log at 100 Hz, whole).
DEFAULT_MAX_ROWS = 1_000_000
#: Session-state key of the last run: (request tuple, GapReport) (:func:`components.run_on_demand`).
RESULT_KEY = "gap_result"
#: The choice of the measurement's channels the workflow compares (``run_gap(channels=)``); the
#: library's messages name it (``budget.errors.GAP_CHANNELS_WAY``).
CHANNELS_LABEL = "channels compared"


@st.cache_data(show_spinner="Simulating the example log …", max_entries=4)
def _example(part_json: str, seed: int):
    model = NoiseModel.model_validate_json(part_json).with_effect(EXAMPLE_EFFECT)
    n = int(EXAMPLE_RATE_HZ * EXAMPLE_SECONDS)
    chans = simulate_static_log(model, n, EXAMPLE_RATE_HZ, np.random.default_rng(seed))
    return log_from_arrays(chans, EXAMPLE_RATE_HZ, source="example (hidden sinusoid on gyro_z)")


def _run(model_json: str, from_catalog: bool, seed: int, realizations: int, measured, rate_hz=None,
         samples=None, channels=None):
    model = NoiseModel.model_validate_json(model_json)
    # a catalog part is checked as a part (its datasheet rate need not be the log's rate)
    arg = PartSpec.model_validate(model.model_dump(exclude={"effects"})) if from_catalog else model
    with st.spinner("Comparing the measurement with the model …"):
        return run_gap(measured, arg, seed=seed, realizations=realizations, rate_hz=rate_hz, samples=samples,
                       channels=channels)


def silent_channels(model: NoiseModel, channels) -> list[str]:
    """Channels of ``channels`` for which ``model`` gives no noise term at all (no ARW/VRW, bias
    instability, rate random walk or effect): a model of a constant signal, which no log can be
    compared with (the workflow's whitening would divide by zero)."""
    si = model.to_si()
    return [ch for ch in channels if ch in CHANNELS and not si.channel_effects(ch)]


def _refuse_silent(model: NoiseModel, origin: str, channels, what: str) -> bool:
    """Show why ``model`` cannot be compared on ``channels`` (True) or nothing (False)."""
    silent = silent_channels(model, channels)
    if not silent:
        return False
    st.error(f"{origin}: the model gives no noise term for {', '.join(silent)}; expected for a gyro "
             "gyro_arw_deg_rt_h, gyro_bias_instability_deg_h or gyro_rrw_deg_h_rt_h, for an accelerometer "
             "accel_vrw_m_s_rt_h or accel_bias_instability_ug, or an effect on that channel — "
             f"{what}.", icon=":material/error:")
    return True


def _model() -> tuple[NoiseModel | None, bool]:
    how = st.radio("model", ("catalog part", "noise-model JSON"), horizontal=True, key="gap_model_kind")
    if how == "catalog part":
        cat = c.session_catalog()
        ids = list(cat)
        pid = st.selectbox("part", ids, index=ids.index("ADIS16405") if "ADIS16405" in ids else 0,
                           key="gap_part")
        return NoiseModel.from_part(cat[pid]), True
    up = st.file_uploader("MODEL.json (catalog-row fields, optional effects; at most 1 MB)", type=["json"],
                          key="gap_model_upload", max_upload_size=1)
    if up is None:
        st.info("Upload a noise-model JSON, or pick a catalog part.")
        return None, False
    # read as the CLI reads --model: errors name the uploaded file and the field
    return read_via_temp_copy(up.getvalue(), up.name, lambda path: load_part(Path(path))), False


def _origin(model: NoiseModel) -> str:
    """Where the model comes from, for messages: the uploaded file or the catalog part."""
    if st.session_state.get("gap_model_kind") == "noise-model JSON":
        up = st.session_state.get("gap_model_upload")
        return up.name if up is not None else "the model"
    return f"part {model.part_id}"


def _measured(model: NoiseModel, seed: int):
    """(request key, measured object, rate_hz, samples, its name) or None while nothing is uploaded."""
    src = st.radio("measured", SOURCES, horizontal=True, key="gap_source")
    if src == SOURCES[0]:
        if _refuse_silent(model, _origin(model), CHANNELS, "the example log would hold constant channels"):
            return None
        return f"example-{seed}-{model.part_id}", _example(model.model_dump_json(), seed), None, None, \
            "the example log"
    st.markdown("A static **log** (canonical columns, a unit in brackets read too: `gyro_x [deg/s]`; plain or "
                ".gz/.bz2/.xz/.zip, read in chunks as the CLI reads it; UTF-8 or UTF-16 with its byte-order "
                "mark) or an **Allan table** `channel, tau_s, adev[, lci, uci]`; a table of one curve "
                "(`tau [s], adev (deg/h)`) is read as the channel you pick.")
    upload = upload_log_or_table("gap_upload", "Upload a static IMU log or an Allan table, or use the example.")
    if upload is None:
        return None
    data, name = upload
    digest = hashlib.sha256(data).hexdigest()[:16]
    if is_adev_table(data, name):
        table = uploaded_adev("gap", data, name, digitised=True)  # "not known": the library refuses it
        if table is None:  # waiting for the channel of a one-curve table
            return None
        st.caption(f"{name}: Allan table, channels {', '.join(table.tables)} (compared by ADEV only).")
        return (f"{name}-{digest}-{table.rate_hz}-{table.samples}-{table.curve_channel}", table.tables,
                None, None, name)
    left, right = st.columns(2)
    max_rows = int(left.number_input("read at most this many rows", min_value=4096, value=DEFAULT_MAX_ROWS,
                                     step=100_000, key="gap_max_rows"))
    repair = repair_box("gap_repair", right)  # the library's repair= of the log (run_gap reads it repaired)
    layout = layout_inputs("gap")
    log = read_uploaded_log(data, name, max_rows, repair, layout)
    st.caption(f"{name}: {log.n_samples} samples at {log.rate_hz:.6g} Hz ({log.duration_s:.6g} s).")
    show_log_findings(log)
    return f"{name}-{digest}-{max_rows}-{repair}-{layout.key()}", log, None, None, name


def _compared(model: NoiseModel, measured, name: str) -> list[str] | None:
    """The measurement's channels the user compares (all by default), or None (with the reason)
    when none is picked or a picked one has no noise term in the model."""
    have = list(measured.channels if isinstance(measured, ImuLog) else measured)
    picked = st.multiselect(CHANNELS_LABEL, have, default=have, key=f"gap_channels_{'-'.join(have)}",
                            help="the workflow compares these channels of the measurement with the model")
    if not picked:
        st.info(f"Pick at least one channel of {name} to compare.", icon=":material/info:")
        return None
    if _refuse_silent(model, _origin(model), picked,
                      f"nothing to compare {name} with there; leave them out of '{CHANNELS_LABEL}'"):
        return None
    return picked


def _show(report) -> None:
    a, b, c2 = st.columns(3)
    a.metric("gap before (mean z²)", fmt_value(report.gap_before, 3),
             help="mean over channels of the mean squared standardised difference; ≈ 1 when the "
                  "log follows its model")
    b.metric("gap after (mean z²)", fmt_value(report.gap_after, 3))
    c2.metric("within-noise threshold (mean z²)", fmt_value(report.threshold, 3))
    st.markdown(f"<span id='gap-result'>{len(report.steps)} effect(s) named</span>", unsafe_allow_html=True)
    if report.steps:
        st.subheader("Effects named, in order")
        st.dataframe(tidy(_steps_frame(report)), hide_index=True, key="gap_steps")
    open_channels = {ch: report.channel_state(ch) for ch in report.channels if report.channel_state(ch) != "ok"}
    if open_channels:
        st.warning("Not explained: " + ", ".join(f"{ch} ({state})" for ch, state in open_channels.items())
                   + f". GAP: beyond the channel's null threshold; MISFIT: within it, but a misfit beyond "
                     f"the tolerance remains. Stop: {report.stop_reason}")
    elif not report.steps:
        st.success("No effect is missing: the log follows its model within the statistical noise.")
    else:
        st.caption(f"Stop: {report.stop_reason}")
    st.plotly_chart(gap_figure(report), key="gap_fig")
    ch = st.selectbox("channel", list(report.channels), key="gap_channel")
    st.plotly_chart(adev_figure(report, ch), key="gap_adev")
    if report.kind == "log":
        st.plotly_chart(psd_figure(report, ch), key="gap_psd")
    st.dataframe(tidy(report.to_frame()), hide_index=True, key="gap_table")
    d1, d2 = st.columns(2)
    d1.download_button("Download REPORT.json", json_text(report.to_dict()), "gap_report.json",
                       mime="application/json", key="gap_dl_report")
    if report.updated_model is not None:
        d2.download_button("Download the updated model JSON", json_text(report.updated_model.to_dict()),
                           "updated_model.json", mime="application/json", key="gap_dl_model")
    for note in report.notes:
        st.caption(note)


def _steps_frame(report):
    import pandas as pd

    return pd.DataFrame([{"effect": s.name, "channel": s.channel,
                          "parameters (SI)": ", ".join(f"{k} = {fmt_value(v)}" for k, v in s.params.items()),
                          "channel gap before (mean z²)": s.gap_before,
                          "channel gap after (mean z²)": s.gap_after,
                          "not told apart from": ", ".join(a["name"] for a in s.alternatives) or "-"}
                         for s in report.steps])


def render() -> None:
    st.title("Model gap")
    st.caption("Compare a static log (or Allan table) with its model, name the missing effect, show the "
               "gap shrink (Allan deviation, PSD, tails; the gap is within noise when it is below its null "
               "threshold).")
    model, from_catalog = _model()
    if model is None:
        return
    left, mid, right = st.columns(3)
    seed = int(left.number_input("seed", min_value=0, value=0, step=1, key="gap_seed"))
    realizations = int(mid.number_input("model realizations", min_value=4, max_value=32, value=6, step=1,
                                        key="gap_realizations"))
    got = _measured(model, seed)
    if got is None:
        return
    key, measured, rate_hz, samples, name = got
    channels = _compared(model, measured, name)
    if channels is None:
        return
    request = (key, model.model_dump_json(), from_catalog, seed, realizations, tuple(channels))
    last = c.run_on_demand(RESULT_KEY, request, "Run",
                           lambda: _run(model.model_dump_json(), from_catalog, seed, realizations, measured,
                                        rate_hz, samples, channels),
                           button_key="gap_run", prompt="Press **Run** to compare.", container=right)
    if last is not None:
        _show(last.result)


run_page(render, sidebar=False)
