"""Page: noise lab — an IMU log → checks, ARMA model and Kalman filter (seed 000), Allan deviation,
PSD, IEEE-952 terms, and the characterisation as a catalog row. Every number from ``budget.noise``."""

from __future__ import annotations

import hashlib
import io

import numpy as np
import pandas as pd
import streamlit as st

from budget import units as u
from budget.catalog.io import parts_to_csv_text
from budget.catalog.schema import GRADES
from budget.errors import InputError, in_words_of
from budget.fileio import json_text
from budget.safe_text import printable
from budget.noise import ImuLog, LogError, allan_deviation, characterize, fit_noise_terms, welch_psd
from budget.noise.pipeline import analyse_arma
from budget.noise.synth import imu_noise
from budget.plots.noise import (allan_figure, arma_criteria_figure, filter_figure, preprocess_figure, psd_figure,
                                response_figure)
from budget.units import channel_si_unit

from formatting import tidy, value_table
from page_frame import run_page
from upload_tables import UploadedTable, is_adev_table, upload_log_or_table, uploaded_adev
from uploads import (INTERFACE, LogLayout, layout_inputs, naming_upload, read_uploaded_log, repair_box, show_error,
                     show_log_findings)

DEFAULT_MAX_ROWS = 500_000
DEFAULT_ARMA_SAMPLES = 20_000
#: Session-state key holding the built-in example log (CSV text) currently shown.
EXAMPLE_KEY = "noise_example_csv"
SOURCES = ("built-in synthetic example", "upload a log or an Allan table")

#: The built-in example: a static 6-axis log, 200 s at 100 Hz, with known IEEE-952 terms
#: (datasheet units; the CSV is written in SI: rad/s and m/s²).
EXAMPLE_RATE_HZ = 100.0
EXAMPLE_SAMPLES = 20_000
EXAMPLE_GYRO_ARW_DEG_RT_H = 0.3
EXAMPLE_GYRO_B_DEG_H = 5.0
EXAMPLE_ACCEL_VRW_M_S_RT_H = 0.05
EXAMPLE_ACCEL_B_UG = 50.0


@st.cache_data(show_spinner=False, max_entries=4)
def example_csv(seed: int) -> str:
    """The synthetic example log as CSV text (``budget.noise.synth.imu_noise``, seeded)."""
    rng = np.random.default_rng(seed)
    n, fs = EXAMPLE_SAMPLES, EXAMPLE_RATE_HZ
    cols = {"time_s": np.arange(n) / fs}
    for ax in "xyz":
        cols[f"gyro_{ax}_rps"] = imu_noise(n, fs, rng, N=u.deg_rt_h_to_rad_s_rt_hz(EXAMPLE_GYRO_ARW_DEG_RT_H),
                                           B=u.deg_h_to_rad_s(EXAMPLE_GYRO_B_DEG_H))
    for ax in "xyz":
        cols[f"accel_{ax}_mps2"] = imu_noise(n, fs, rng, N=u.m_s_rt_h_to_m_s2_rt_hz(EXAMPLE_ACCEL_VRW_M_S_RT_H),
                                             B=u.ug_to_m_s2(EXAMPLE_ACCEL_B_UG))
    buf = io.StringIO()
    pd.DataFrame(cols).to_csv(buf, index=False, float_format="%.9g")
    return buf.getvalue()


#: The grade choice that leaves the grade to the grades table.
GRADE_INFERRED = "inferred"


@st.cache_data(show_spinner="Modelling the channel …", max_entries=8)
def _analyse(key: str, channel: str, arma_samples: int, _log: ImuLog):
    """The ARMA pipeline (:func:`budget.noise.pipeline.analyse_arma`, as ``sar-budget noise arma``)
    on the first ``arma_samples`` samples; Allan deviation, IEEE-952 fit and PSD on all of them."""
    x = _log.channels[channel]
    unit = channel_si_unit(channel)
    arma = analyse_arma(x[:arma_samples], _log.rate_hz, channel=channel, response_freq_hz="dense")
    allan = allan_deviation(x, _log.rate_hz, channel=channel, unit=unit)
    return arma, allan, fit_noise_terms(allan), welch_psd(x, _log.rate_hz, channel=channel, unit=unit)


@st.cache_data(show_spinner="Characterising …", max_entries=8)
def _characterize(key: str, part_id: str, _data, grade: str | None = None, keep_spikes: bool = False):
    return characterize(_data, part_id=part_id, grade=grade, keep_spikes=keep_spikes)


def _source() -> tuple[bytes, str] | None:
    src = st.radio("input", SOURCES, key="noise_source", horizontal=True)
    if src == SOURCES[0]:
        seed = int(st.number_input("example seed", min_value=0, value=7, step=1, key="noise_example_seed"))
        text = example_csv(seed)
        st.session_state[EXAMPLE_KEY] = text
        st.caption(f"Static 6-axis log, {EXAMPLE_SAMPLES / EXAMPLE_RATE_HZ:g} s at {EXAMPLE_RATE_HZ:g} Hz: gyro "
                   f"ARW {EXAMPLE_GYRO_ARW_DEG_RT_H} deg/√h and flicker B {EXAMPLE_GYRO_B_DEG_H} deg/h "
                   f"(Allan floor 0.664·B); accel VRW {EXAMPLE_ACCEL_VRW_M_S_RT_H} m/s/√h and B "
                   f"{EXAMPLE_ACCEL_B_UG} µg (budget.noise.synth).")
        st.download_button("Download the example log (CSV)", data=text, file_name=f"example_imu_log_{seed}.csv",
                           mime="text/csv", key="noise_example_download")
        return text.encode(), f"example_imu_log_{seed}.csv"
    st.markdown("A **log**: columns `time_s` (or a known rate), `gyro_x_dps|rps|dph` … `accel_z_mps2|g|mg`; "
                "a unit may be written in brackets (`gyro_x [deg/s]`, `time [ms]`); plain or .gz/.bz2/.xz/.zip "
                "(read in chunks, as the CLI reads it), UTF-8 or UTF-16 with its byte-order mark. Or an "
                "**Allan table**: `channel, tau_s, adev[, lci, uci]` with the unit on the channel name "
                "(`gyro_x_dps`, `accel_x_g` …) or in brackets (`adev (deg/h)`); a table of one curve "
                "(`tau [s], adev (deg/h)`) is read as the channel you pick.")
    return upload_log_or_table("noise_upload",
                               "Upload a static IMU log or an Allan table, or pick the built-in example.")


def _load(data: bytes, name: str) -> tuple[ImuLog, str] | None:
    """The uploaded log and the key of how it was read (rows, repair, mapping, rate), or None."""
    left, right = st.columns(2)
    max_rows = int(left.number_input("read at most this many rows", min_value=100, value=DEFAULT_MAX_ROWS,
                                     step=10_000, key="noise_max_rows"))
    repair = repair_box("noise_repair", right)
    # a logger's layout is the user's file's; the built-in example is canonical
    layout = layout_inputs("noise") if st.session_state.get("noise_source") == SOURCES[1] else LogLayout()
    try:
        log = read_uploaded_log(data, name, max_rows, repair, layout)
    except LogError as err:
        show_error(err)
        st.dataframe(err.report.to_frame(), hide_index=True, key="noise_log_errors")
        return None
    except InputError as err:
        show_error(err)
        return None
    st.markdown(f"<span id='noise-loaded'>**{name}**: {log.n_samples} samples at {log.rate_hz:.6g} Hz "
                f"({log.duration_s:.6g} s)</span>; channels "
                f"{', '.join(f'{c} [{log.source_units[c]}]' for c in log.channels)}", unsafe_allow_html=True)
    show_log_findings(log)
    if log.issues.issues or log.issues.repairs:
        with st.expander(f"Log report: {len(log.issues.issues)} finding(s), {len(log.issues.repairs)} repair(s)"):
            st.text(log.issues.summary())
            if log.issues.issues:
                st.dataframe(log.issues.to_frame(), hide_index=True, key="noise_log_issues")
    else:
        st.caption("Log checks: no issues found.")
    return log, f"{max_rows}:{repair}:{layout.key()}"


def _terms_table(terms, key: str) -> None:
    st.dataframe(tidy(terms.to_frame()), hide_index=True, key=key)


def _channel_sections(log: ImuLog, key: str) -> None:
    left, right = st.columns(2)
    channel = left.selectbox("channel", list(log.channels), key="noise_channel")
    n_arma = int(right.number_input("samples for ARMA/Kalman (from the start)", min_value=100,
                                    value=DEFAULT_ARMA_SAMPLES, step=1000, key="noise_arma_samples"))
    try:
        a, allan, terms, psd = _analyse(key, channel, n_arma, log)
    except InputError as err:  # the library sees an array: name the file and the channel
        raise naming_upload(err, log.source, channel) from None
    unit = a.unit

    st.subheader("Preprocessing and checks (seed 000 §3.1)")
    st.markdown(f"{a.pre.summary()}. Checks: **{a.checks.summary()}**.")
    st.dataframe(tidy(a.checks.to_frame().drop(columns=["flags"])), hide_index=True, key="noise_checks")
    st.plotly_chart(preprocess_figure(a.raw, a.pre, log.rate_hz, unit=unit), key="noise_pre_plot",
                    width="stretch")

    st.subheader("ARMA model")
    sel = a.selection
    st.metric("selected ARMA model (lowest AIC, stationary and invertible)", sel.selected.name)
    frame = a.to_frame()
    for col in ("phi", "theta", "stderr"):
        if col in frame.columns:
            frame[col] = frame[col].map(lambda v: ", ".join(f"{c:.4g}" for c in v))
    st.dataframe(tidy(frame), hide_index=True, key="noise_arma_table")
    for note in sel.notes:
        st.caption(f"note: {note}")
    st.plotly_chart(arma_criteria_figure(sel), key="noise_arma_plot", width="stretch")

    st.subheader("Kalman filter on the ARMA model")
    k = a.filtered
    cols = st.columns(3)
    cols[0].metric(f"variance before ({unit})²", f"{k.variance_before:.4g}")
    cols[1].metric(f"variance after ({unit})²", f"{k.variance_after:.4g}")
    cols[2].metric("reduction", f"÷{a.variance_reduction:.3g}")
    st.caption(a.kalman.summary())
    if a.adequacy is not None:  # the innovation tests and steady error variances, as the library words them
        st.text(a.adequacy.summary())
    st.plotly_chart(filter_figure(a.pre.x, k, log.rate_hz, unit=unit), key="noise_filter_plot", width="stretch")
    st.markdown(f"What the filter does to real motion: {a.response.summary()}")
    st.plotly_chart(response_figure(a.response), key="noise_response_plot", width="stretch")
    st.download_button("Download the ARMA result (JSON, as `sar-budget noise arma --json`)",
                       data=json_text(a.to_dict()), file_name=f"arma_{channel}.json", mime="application/json",
                       key="noise_arma_download")

    st.subheader("Allan deviation and IEEE-952 terms")
    st.plotly_chart(allan_figure(allan, {channel: terms}, show_terms=True), key="noise_allan_plot",
                    width="stretch")
    _terms_table(terms, "noise_terms_table")
    st.caption(terms.summary().splitlines()[0])
    st.subheader("Power spectral density")
    st.plotly_chart(psd_figure(psd), key="noise_psd_plot", width="stretch")


def _allan_table_sections(data: bytes, name: str) -> UploadedTable | None:
    """An uploaded Allan table: its curves, the IEEE-952 fit per channel (no ARMA: no series)."""
    st.markdown(f"**{name}** is an Allan table. The record's rate and length are not in it: give them "
                "(they fix the averaging factors and, without lci/uci, the confidence intervals), or, for a "
                "curve read off a datasheet figure, say there is none.")
    table = uploaded_adev("noise", data, name, digitised=True)
    if table is None:  # waiting for the channel of a one-curve table
        return None
    tables = table.tables
    record = ("digitised curve, no record behind it" if table.digitised
              else f"record of {table.samples} samples at {table.rate_hz:g} Hz")
    st.markdown(f"<span id='noise-loaded'>**{name}**: Allan table, {len(tables)} channel(s): "
                f"{', '.join(tables)} ({record})</span>", unsafe_allow_html=True)
    for note in table.notes:  # how the table was read, as the CLI notes it before its result
        st.info(f"{name}: {printable(in_words_of(note, INTERFACE), 600)}", icon=":material/info:")
    channel = st.selectbox("channel", list(tables), key="noise_table_channel")
    try:
        ch = _characterize(_table_key(name, table), "measured_imu", tables)
    except InputError as err:
        raise naming_upload(err, name) from None
    terms = ch.channels.get(channel)
    st.subheader("Allan deviation and IEEE-952 terms")
    st.plotly_chart(allan_figure(tables[channel], {channel: terms} if terms else None, show_terms=True),
                    key="noise_allan_plot", width="stretch")
    if terms is not None:
        _terms_table(terms, "noise_terms_table")
        st.caption(terms.summary().splitlines()[0])
    st.caption("ARMA modelling and the Kalman filter need the time series; upload the log for them.")
    return table


def _table_key(name: str, table: UploadedTable) -> str:
    return f"{name}:{table.rate_hz}:{table.samples}:{table.curve_channel}"


def _catalog_entry(data, key: str) -> None:
    st.subheader("Save the characterisation as a catalog entry")
    left, mid, right = st.columns([2, 2, 1])
    part_id = left.text_input("part id", value="measured_imu", key="noise_part_id").strip()
    grade = mid.selectbox("grade", (GRADE_INFERRED, *GRADES), key="noise_grade",
                          help="the grade of the catalog row; inferred: the best grade whose limits hold "
                               "the measured bias instability and noise (seed 004 Tables 3–4)")
    keep = right.checkbox("keep spikes", key="noise_keep_spikes", disabled=not isinstance(data, ImuLog),
                          help="fit the Allan deviation with isolated spikes kept (by default, spikes that "
                               "would decide the short-τ noise are replaced by their neighbours' mean)")
    if not part_id:
        st.info("Give the part an id.")
        return
    ch = _characterize(key, part_id, data, None if grade == GRADE_INFERRED else grade,
                       keep and isinstance(data, ImuLog))
    for warning in ch.warnings:  # e.g. the log is not one stationary regime
        st.warning(in_words_of(warning, INTERFACE))
    st.dataframe(value_table(ch.part.model_dump()), hide_index=True, key="noise_part_row")
    with st.expander("Per-channel IEEE-952 fits"):
        st.dataframe(tidy(ch.to_frame()), hide_index=True, key="noise_char_table")
        for note in ch.notes:
            st.caption(f"note: {in_words_of(note, INTERFACE)}")
    st.download_button("Download the catalog row (CSV)", data=parts_to_csv_text([ch.part]),
                       file_name=f"{part_id}.csv", mime="text/csv", key="noise_part_download")
    st.caption("Upload it on the Catalog page to check it against the scenario.")


def render() -> None:
    st.title("Noise lab")
    src = _source()
    if src is None:
        return
    data, name = src
    digest = hashlib.sha256(data).hexdigest()
    if is_adev_table(data, name):
        table = _allan_table_sections(data, name)
        if table is None:  # waiting for the channel of a one-curve table
            return
        _catalog_entry(table.tables, f"{digest}:{_table_key(name, table)}")
        return
    loaded = _load(data, name)
    if loaded is None:
        return
    log, how = loaded
    key = f"{digest}:{how}"
    _channel_sections(log, key)
    _catalog_entry(log, key)


run_page(render, sidebar=False)
