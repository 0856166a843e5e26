"""Page: model gap — a measured log against the model it should follow: where they disagree,
which effect is missing, and the gap after adding it. Every number from ``budget.gap``."""

from __future__ import annotations

import json

import numpy as np
import streamlit as st

from budget.errors import InputError
from budget.gap import run_gap
from budget.gap.inputs import log_from_arrays
from budget.gap.plots import adev_figure, gap_figure, psd_figure
from budget.imu.generator import simulate_static_log
from budget.catalog.schema import PartSpec
from budget.imu.noise_model import NoiseModel

import components as c
from page_frame import run_page
from uploads import read_uploaded_log

MAX_UPLOAD_MB = 50
SOURCES = ("built-in example (a part with a hidden effect)", "upload a log CSV")
#: The example: 30 min at 100 Hz of the chosen part, plus a sinusoid on gyro_z the part does not
#: have (0.7 Hz, 0.02 deg/s peak), so the workflow has something to find.
EXAMPLE_RATE_HZ, EXAMPLE_SECONDS = 100.0, 1800.0
EXAMPLE_EFFECT = {"name": "sinusoid", "channel": "gyro_z",
                  "params": {"frequency_hz": 0.7, "amplitude": float(np.radians(0.02))}}


@st.cache_data(show_spinner="Simulating the example log …", max_entries=4)
def _example(part_json: str, seed: int):
    model = NoiseModel.model_validate_json(part_json).with_effect(EXAMPLE_EFFECT)
    n = int(EXAMPLE_RATE_HZ * EXAMPLE_SECONDS)
    chans = simulate_static_log(model, n, EXAMPLE_RATE_HZ, np.random.default_rng(seed))
    return log_from_arrays(chans, EXAMPLE_RATE_HZ, source="example (hidden sinusoid on gyro_z)")


@st.cache_data(show_spinner="Comparing the log with the model …", max_entries=8)
def _run(key: str, model_json: str, from_catalog: bool, seed: int, realizations: int, _log):
    model = NoiseModel.model_validate_json(model_json)
    # a catalog part is checked as a part (its datasheet rate need not be the log's rate)
    arg = PartSpec.model_validate(model.model_dump(exclude={"effects"})) if from_catalog else model
    return run_gap(_log, arg, seed=seed, realizations=realizations)


def _model() -> tuple[NoiseModel | None, bool]:
    how = st.radio("model", ("catalog part", "noise-model JSON"), horizontal=True, key="gap_model_kind")
    if how == "catalog part":
        cat = c.session_catalog()
        ids = list(cat)
        pid = st.selectbox("part", ids, index=ids.index("ADIS16405") if "ADIS16405" in ids else 0,
                           key="gap_part")
        return NoiseModel.from_part(cat[pid]), True
    up = st.file_uploader("MODEL.json (catalog-row fields, optional effects)", type=["json"], key="gap_model_upload",
                          max_upload_size=1)
    if up is None:
        st.info("Upload a noise-model JSON, or pick a catalog part.")
        return None, False
    try:
        return NoiseModel.from_dict(json.loads(up.getvalue().decode("utf-8")), source=up.name), False
    except (UnicodeDecodeError, json.JSONDecodeError) as err:
        raise InputError(f"not valid JSON: {err}", file=up.name) from None


def render() -> None:
    st.title("Model gap")
    st.caption("Compare a static log with its model, name the missing effect, show the gap shrink "
               "(Allan deviation, PSD, tails; the gap is within noise when it is below its null threshold).")
    model, from_catalog = _model()
    if model is None:
        return
    src = st.radio("measured log", SOURCES, horizontal=True, key="gap_source")
    left, mid, right = st.columns(3)
    seed = int(left.number_input("seed", min_value=0, value=0, step=1, key="gap_seed"))
    realizations = int(mid.number_input("model realizations", min_value=4, max_value=32, value=6, step=1,
                                        key="gap_realizations"))
    if src == SOURCES[0]:
        log = _example(model.model_dump_json(), seed)
        key = f"example-{seed}-{model.part_id}"
    else:
        up = st.file_uploader(f"IMU log (at most {MAX_UPLOAD_MB} MB)", type=["csv", "gz"], key="gap_upload",
                              max_upload_size=MAX_UPLOAD_MB)
        if up is None:
            st.info("Upload a static IMU log in the canonical columns, or use the example.")
            return
        data = up.getvalue()
        log = read_uploaded_log(data, up.name, 2_000_000, False)
        key = f"{up.name}-{len(data)}-{hash(data)}"
    if not right.button("Run", type="primary", key="gap_run"):
        if "gap_last" not in st.session_state:
            return
    report = _run(key, model.model_dump_json(), from_catalog, seed, realizations, log)
    st.session_state["gap_last"] = True
    a, b, c2 = st.columns(3)
    a.metric("gap before", f"{report.gap_before:.3g}")
    b.metric("gap after", f"{report.gap_after:.3g}")
    c2.metric("within-noise threshold", f"{report.threshold:.3g}")
    if report.steps:
        st.subheader("Effects named, in order")
        st.dataframe([{"effect": s.name, "channel": s.channel, "params": json.dumps(s.params),
                       "gap before": s.gap_before, "gap after": s.gap_after} for s in report.steps],
                     hide_index=True, key="gap_steps")
    else:
        st.success("No effect is missing: the log follows its model within the statistical noise.")
    st.plotly_chart(gap_figure(report), key="gap_fig")
    ch = st.selectbox("channel", list(report.channels), key="gap_channel")
    st.plotly_chart(adev_figure(report, ch), key="gap_adev")
    if report.kind == "log":
        st.plotly_chart(psd_figure(report, ch), key="gap_psd")
    st.dataframe(report.to_frame(), hide_index=True, key="gap_table")
    d1, d2 = st.columns(2)
    d1.download_button("Download REPORT.json", json.dumps(report.to_json(), indent=2), "gap_report.json",
                       mime="application/json", key="gap_dl_report")
    if report.updated_model is not None:
        d2.download_button("Download the updated model JSON", json.dumps(report.updated_model.to_dict(), indent=2),
                           "updated_model.json", mime="application/json", key="gap_dl_model")
    for note in report.notes:
        st.caption(note)


run_page(render)
