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
from budget.errors import InputError
from budget.noise import (ArmaKalman, ImuLog, LogError, allan_deviation, characterize, check_series,
                          fit_noise_terms, frequency_response, preprocess, select_arma, welch_psd)
from budget.noise.plots import allan_figure, filter_figure, psd_figure, response_figure
from budget.noise.synth import imu_noise
from budget.plots.noise import arma_criteria_figure, preprocess_figure

from page_frame import run_page
from uploads import read_uploaded_log

MAX_UPLOAD_MB = 50
DEFAULT_MAX_ROWS = 500_000
DEFAULT_ARMA_SAMPLES = 20_000
#: Session-state key holding the built-in example log (CSV text) currently shown.
EXAMPLE_KEY = "noise_example_csv"
SOURCES = ("built-in synthetic example", "upload a log CSV")

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


def _unit(channel: str) -> str:
    return "rad/s" if channel.startswith("gyro") else "m/s^2"


@st.cache_data(show_spinner="Modelling the channel …", max_entries=8)
def _analyse(key: str, channel: str, arma_samples: int, _log: ImuLog) -> dict:
    """Preprocessing, checks, ARMA selection, Kalman filter and response, Allan, PSD of one channel."""
    x = _log.channels[channel]
    pre = preprocess(x[:arma_samples])
    sel = select_arma(pre.x, method="ls")
    kf = ArmaKalman(sel.selected)
    allan = allan_deviation(x, _log.rate_hz, channel=channel, unit=_unit(channel))
    return {"raw": x[:arma_samples], "pre": pre, "checks": check_series(pre.x), "selection": sel,
            "kalman": kf.filter(pre.x), "kalman_summary": kf.summary(),
            "response": frequency_response(kf, _log.rate_hz), "allan": allan,
            "terms": fit_noise_terms(allan),
            "psd": welch_psd(x, _log.rate_hz, channel=channel, unit=_unit(channel))}


@st.cache_data(show_spinner="Characterising the log …", max_entries=8)
def _characterize(key: str, part_id: str, _log: ImuLog):
    return characterize(_log, part_id=part_id)


def _source() -> tuple[bytes, str] | None:
    src = st.radio("log", SOURCES, key="noise_source", horizontal=True)
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
    st.markdown("Columns `time_s` (or a known rate), `gyro_x_dps|rps|dph` … `accel_z_mps2|g|mg`; "
                "plain or .gz/.bz2/.xz/.zip.")
    up = st.file_uploader(f"IMU log (at most {MAX_UPLOAD_MB} MB)", type=["csv", "gz", "bz2", "xz", "zip"],
                          key="noise_upload", max_upload_size=MAX_UPLOAD_MB)
    if up is None:
        st.info("Upload a static IMU log, or pick the built-in example.")
        return None
    data = up.getvalue()
    if len(data) > MAX_UPLOAD_MB * 1_000_000:
        raise InputError(f"file is {len(data) / 1e6:.1f} MB", file=up.name, expected=f"at most {MAX_UPLOAD_MB} MB")
    return data, up.name


def _load(data: bytes, name: str) -> ImuLog | None:
    left, right = st.columns(2)
    max_rows = int(left.number_input("read at most this many rows", min_value=100, value=DEFAULT_MAX_ROWS,
                                     step=10_000, key="noise_max_rows"))
    repair = right.checkbox("repair the log (drop duplicate/out-of-order rows, interpolate gaps)",
                            key="noise_repair")
    try:
        log = read_uploaded_log(data, name, max_rows, repair)
    except LogError as err:
        st.error(str(err), icon=":material/error:")
        st.dataframe(err.report.to_frame(), hide_index=True, key="noise_log_errors")
        return None
    except InputError as err:
        st.error(str(err), icon=":material/error:")
        return None
    st.markdown(f"**{name}**: {log.n_samples} samples at {log.rate_hz:.6g} Hz ({log.duration_s:.6g} s); "
                f"channels {', '.join(f'{c} [{log.source_units[c]}]' for c in log.channels)}")
    if log.issues.issues or log.issues.repairs:
        with st.expander(f"Log report: {len(log.issues.issues)} finding(s), {len(log.issues.repairs)} repair(s)"):
            st.text(log.issues.summary())
            if log.issues.issues:
                st.dataframe(log.issues.to_frame(), hide_index=True, key="noise_log_issues")
    else:
        st.caption("Log checks: no issues found.")
    return log


def _channel_sections(log: ImuLog, key: str) -> None:
    left, right = st.columns(2)
    channel = left.selectbox("channel", list(log.channels), key="noise_channel")
    n_arma = int(right.number_input("samples for ARMA/Kalman (from the start)", min_value=100,
                                    value=DEFAULT_ARMA_SAMPLES, step=1000, key="noise_arma_samples"))
    a = _analyse(key, channel, n_arma, log)
    unit = _unit(channel)

    st.subheader("Preprocessing and checks (seed 000 §3.1)")
    st.markdown(f"{a['pre'].summary()}. Checks: **{a['checks'].summary()}**.")
    st.dataframe(a["checks"].to_frame().drop(columns=["flags"]), hide_index=True, key="noise_checks")
    st.plotly_chart(preprocess_figure(a["raw"], a["pre"], log.rate_hz, unit=unit), key="noise_pre_plot",
                    width="stretch")

    st.subheader("ARMA model")
    sel = a["selection"]
    st.metric("selected ARMA model (lowest AIC, stationary and invertible)", sel.selected.name)
    frame = sel.to_frame()
    frame["phi"] = frame["phi"].map(lambda v: ", ".join(f"{c:.4g}" for c in v))
    frame["theta"] = frame["theta"].map(lambda v: ", ".join(f"{c:.4g}" for c in v))
    st.dataframe(frame, hide_index=True, key="noise_arma_table")
    for note in sel.notes:
        st.caption(f"note: {note}")
    st.plotly_chart(arma_criteria_figure(sel), key="noise_arma_plot", width="stretch")

    st.subheader("Kalman filter on the ARMA model")
    k = a["kalman"]
    cols = st.columns(3)
    cols[0].metric(f"variance before ({unit})²", f"{k.variance_before:.4g}")
    cols[1].metric(f"variance after ({unit})²", f"{k.variance_after:.4g}")
    cols[2].metric("reduction", f"÷{k.variance_before / k.variance_after:.3g}")
    st.caption(a["kalman_summary"])
    st.plotly_chart(filter_figure(a["pre"].x, k, log.rate_hz, unit=unit), key="noise_filter_plot", width="stretch")
    st.markdown(f"What the filter does to real motion: {a['response'].summary()}")
    st.plotly_chart(response_figure(a["response"]), key="noise_response_plot", width="stretch")

    st.subheader("Allan deviation and IEEE-952 terms")
    st.plotly_chart(allan_figure(a["allan"], {channel: a["terms"]}, show_terms=True), key="noise_allan_plot",
                    width="stretch")
    st.dataframe(a["terms"].to_frame(), hide_index=True, key="noise_terms_table")
    st.caption(a["terms"].summary().splitlines()[0])
    st.subheader("Power spectral density")
    st.plotly_chart(psd_figure(a["psd"]), key="noise_psd_plot", width="stretch")


def _catalog_entry(log: ImuLog, key: str) -> None:
    st.subheader("Save the characterisation as a catalog entry")
    part_id = st.text_input("part id", value="measured_imu", key="noise_part_id").strip()
    if not part_id:
        st.info("Give the part an id.")
        return
    ch = _characterize(key, part_id, log)
    row = {k: v for k, v in ch.part.model_dump().items() if v not in (None, "")}
    st.dataframe(pd.DataFrame({"column": list(row), "value": [str(v) for v in row.values()]}),
                 hide_index=True, key="noise_part_row")
    with st.expander("Per-channel IEEE-952 fits"):
        st.dataframe(ch.to_frame(), hide_index=True, key="noise_char_table")
        for note in ch.notes:
            st.caption(f"note: {note}")
    st.download_button("Download the catalog row (CSV)", data=parts_to_csv_text([ch.part]),
                       file_name=f"{part_id}.csv", mime="text/csv", key="noise_part_download")
    st.caption("Upload it on the Catalog page to check it against the scenario.")


def render() -> None:
    st.title("Noise lab")
    src = _source()
    if src is None:
        return
    data, name = src
    log = _load(data, name)
    if log is None:
        return
    key = f"{hashlib.sha256(data).hexdigest()}:{st.session_state['noise_max_rows']}:{st.session_state['noise_repair']}"
    _channel_sections(log, key)
    _catalog_entry(log, key)


run_page(render)
