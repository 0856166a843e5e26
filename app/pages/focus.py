"""Page: real SAR data — focus a recorded phase history (AFRL format) on a ground grid, autofocus
it, and show the image before/after, the estimated vs recorded phase error and what the data are
(band, aperture, resolutions: ``FocusResult.acquisition``). Every number from
``budget.sar.focus_pga``; this page only collects the inputs and draws."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

import streamlit as st

from budget.errors import InputError
from budget.fileio import json_safe
from budget.plots.focus import image_pair_figure, phase_figure
from budget.sar.afrl import name_order, read_afrl
from budget.sar.focus import FocusOptions
from budget.sar.focus_pga import AUTOFOCUS_MODES, focus

from page_frame import run_page

SOURCES = ("directory of .mat files", "upload .mat files")
MAX_UPLOAD_MB = 50
#: Environment variable naming a default directory of phase-history files.
DATA_ENV = "SAR_BUDGET_SAR_DATA"


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


@st.cache_data(show_spinner="Backprojecting and autofocusing …", max_entries=2)
def _run_uploads(blobs: tuple[tuple[str, bytes], ...], options_json: str, autofocus: str,
                 inject: tuple[float, float, float, float] | None = None):
    with tempfile.TemporaryDirectory() as tmp:
        paths = []
        for name, data in blobs:
            path = Path(tmp) / Path(name).name
            with open(path, "wb") as fh:
                fh.write(data)
            paths.append(str(path))
        try:
            ph = read_afrl(paths)
        except InputError as err:
            if err.file and tmp in err.file:
                err.rename_file(err.file.replace(tmp + os.sep, ""))
            raise
    return focus(_with_injection(ph, inject), FocusOptions.model_validate_json(options_json), autofocus)


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


def render() -> None:
    st.title("Real SAR data")
    st.caption("Backprojection of a recorded phase history onto a ground grid, phase gradient autofocus on "
               "the real image, and the comparison with the data provider's own autofocus solution.")
    src = st.radio("phase history", SOURCES, horizontal=True, key="focus_source")
    autofocus = st.radio("autofocus", AUTOFOCUS_MODES, horizontal=True, key="focus_mode")
    options = _options()
    inject = _injection()
    if src == SOURCES[0]:
        directory = st.text_input("directory (all its .mat files, in name order, form one aperture)",
                                  os.environ.get(DATA_ENV, ""), key="focus_dir")
        if not directory:
            st.info(f"Name a directory of AFRL .mat files (or set {DATA_ENV}), or upload files.")
            return
        run = st.button("Focus", type="primary", key="focus_run")
        if not run and "focus_last" not in st.session_state:
            return
        result = _run_paths(tuple(str(p) for p in _files_in(directory)), options.model_dump_json(), autofocus,
                            inject)
    else:
        ups = st.file_uploader(f"AFRL .mat files (at most {MAX_UPLOAD_MB} MB each)", type=["mat"],
                               accept_multiple_files=True, key="focus_upload", max_upload_size=MAX_UPLOAD_MB)
        if not ups:
            st.info("Upload one or more AFRL .mat files (they are concatenated in name order, az2 before az10).")
            return
        run = st.button("Focus", type="primary", key="focus_run")
        if not run and "focus_last" not in st.session_state:
            return
        by_name = {u.name: u for u in ups}
        blobs = tuple((n, by_name[n].getvalue()) for n in name_order(by_name))
        result = _run_uploads(blobs, options.model_dump_json(), autofocus, inject)
    st.session_state["focus_last"] = True
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


run_page(render, sidebar=False)  # the phase history carries its own geometry
