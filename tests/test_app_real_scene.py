"""The Real SAR data page's part verdict (app/pages/focus.py, section "Part verdict on this scene")
shows the library's verdict (budget.mc.real_scene.real_scene_verdict) for the same inputs and seed,
its notes, and the library's refusals as one-line errors; and the figure of the per-trial judged
quantities (budget.plots.real_scene) draws exactly the verdict's outcomes against its limits. The
page tests on the Gotcha files are skipped when ../shared is absent."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from budget.catalog.io import load_catalog
from budget.mc.real_scene import REASONS, RealSceneOptions, RealSceneVerdict, real_scene_verdict
from budget.plots.real_scene import FAIL_COLOUR, PASS_COLOUR, real_scene_trials_figure
from budget.sar.afrl import read_afrl
from budget.sar.focus import FocusOptions

APP_DIR = Path(__file__).resolve().parents[1] / "app"
PAGE = str(APP_DIR / "pages" / "focus.py")
#: A 20 m patch and 2 trials: the page's run and the library's run take a few seconds together. With
#: ADIS16405 at 150 m/s and seed 3 one trial passes and one fails (P(pass) 0.50): a mixed verdict.
PATCH_M, TRIALS, SEED, SPEED_M_S = 20.0, 2, 3, 150.0


def _page(monkeypatch):
    at_cls = pytest.importorskip("streamlit.testing.v1", reason="streamlit not installed").AppTest
    monkeypatch.syspath_prepend(str(APP_DIR))
    at = at_cls.from_file(PAGE, default_timeout=120).run()
    assert not at.exception, [e.value for e in at.exception]
    return at


def _set_verdict_inputs(at, directory, *, speed=SPEED_M_S):
    at.text_input(key="focus_dir").set_value(str(directory)).run()
    at.number_input(key="focus_verdict_trials").set_value(TRIALS).run()
    at.number_input(key="focus_verdict_seed").set_value(SEED).run()
    at.number_input(key="focus_verdict_speed").set_value(speed).run()
    at.number_input(key="focus_verdict_patch").set_value(PATCH_M).run()
    assert not at.exception, [e.value for e in at.exception]


def test_the_page_shows_the_library_verdict_of_a_user_part(gotcha, monkeypatch):
    """A part from the user's catalog (merged in the session as the Catalog page merges it), run
    on the page, against the library's verdict for the same part, inputs and seed: P(pass), its
    interval, the failure counts, each trial's judged numbers, the floor and every note."""
    shipped = load_catalog()["ADIS16405"]
    mine = shipped.model_copy(update={"part_id": "MY-IMU"})
    at = _page(monkeypatch)
    from components import USER_PARTS_KEY  # app/ is on the path once the page is open
    at.session_state[USER_PARTS_KEY] = {"MY-IMU": mine}
    _set_verdict_inputs(at, gotcha[0].parent)
    part_box = at.selectbox(key="focus_verdict_part")
    assert "MY-IMU (your catalog)" in part_box.options and "STIM300" in part_box.options  # user + shipped
    assert part_box.value == "STIM300"
    part_box.set_value("MY-IMU").run()
    at.button(key="focus_verdict_run").click().run()
    assert not at.exception, [e.value for e in at.exception]
    assert not at.error, [e.value for e in at.error]

    calls = []
    opts = RealSceneOptions(platform_speed_m_s=SPEED_M_S,
                            focus=FocusOptions(range_extent_m=PATCH_M, azimuth_extent_m=PATCH_M))
    v = real_scene_verdict(read_afrl(gotcha), mine, TRIALS, SEED, opts, progress=lambda d, t: calls.append((d, t)))
    assert calls == [(i, TRIALS) for i in range(TRIALS + 1)]  # the page's progress bar: reference, then each trial
    lo, hi = v.interval
    shown = {m.label: m.value for m in at.metric}
    assert shown["P(pass) after PGA — MY-IMU"] == f"{v.p_pass:.2f}"
    assert shown["95 % interval (Wilson)"] == f"[{lo:.2f}, {hi:.2f}]"
    assert shown["trials passed"] == f"{v.passed} / {TRIALS}"
    assert 0 < v.passed < TRIALS  # a mixed verdict: the page cannot match it by showing all or none
    # the verdict's tables in page order (the Focus section above was not run): reasons, trials, floor
    reasons, table, floor = (d.value for d in at.dataframe)
    assert list(reasons.columns) == list(REASONS)
    assert {r: int(reasons[r].iloc[0]) for r in REASONS} == {r: v.failure_counts().get(r, 0) for r in REASONS}
    assert len(table) == TRIALS
    for row, o in zip(table.to_dict("records"), v.outcomes):
        assert row["passed"] == o["passed"] and row["reasons"] == ", ".join(o["reasons"])
        for key in ("added_residual_beyond_window_deg", "added_peak_loss_db", "peak_range_cells",
                    "injected_beyond_linear_deg"):
            assert row[key] == pytest.approx(o[key], rel=1e-9, abs=1e-12), key
    ref = dict(zip(floor["quantity"], floor["value"]))
    from formatting import fmt_value  # the dashboard's one rule for numbers in tables (4 significant figures)
    assert ref == {k: fmt_value(val) for k, val in v.reference.items()}
    assert float(ref["residual_beyond_window_deg"]) > 0  # the floor is there: PGA against the recorded solution
    captions = [c_.value for c_ in at.caption]
    for note in v.notes:  # every assumption of the result, the assumed speed first
        assert note in captions, note
    assert any(f"platform speed {SPEED_M_S:g} m/s assumed" in n for n in v.notes)
    # the figure drawn is the library's figure of this verdict (same trials, same limit)
    assert len(at.get("plotly_chart")) == 1


def test_the_verdict_is_kept_until_the_next_run_and_a_change_is_said(gotcha, monkeypatch):
    at = _page(monkeypatch)
    _set_verdict_inputs(at, gotcha[0].parent)
    at.number_input(key="focus_verdict_trials").set_value(1).run()
    assert not at.metric  # nothing runs before the button is pressed
    at.button(key="focus_verdict_run").click().run()
    first = {m.label: m.value for m in at.metric}
    assert first["trials passed"].endswith("/ 1")
    at.number_input(key="focus_verdict_seed").set_value(SEED + 1).run()  # a rerun, no new run
    assert {m.label: m.value for m in at.metric} == first
    assert any("inputs changed" in i.value for i in at.info)


def test_uploaded_files_give_the_verdict_on_those_files(gotcha, monkeypatch):
    """The upload source: two of the four files uploaded (out of order: the page puts them in name
    order) give the library's verdict on those two files."""
    at = _page(monkeypatch)
    at.radio(key="focus_source").set_value(at.radio(key="focus_source").options[1]).run()
    at.file_uploader(key="focus_upload").set_value(
        [(f.name, f.read_bytes(), "application/octet-stream") for f in (gotcha[1], gotcha[0])]).run()
    at.number_input(key="focus_verdict_trials").set_value(1).run()
    at.number_input(key="focus_verdict_patch").set_value(PATCH_M).run()
    at.button(key="focus_verdict_run").click().run()
    assert not at.exception and not at.error, [e.value for e in (*at.exception, *at.error)]
    opts = RealSceneOptions(focus=FocusOptions(range_extent_m=PATCH_M, azimuth_extent_m=PATCH_M))
    v = real_scene_verdict(read_afrl(gotcha[:2]), load_catalog()["STIM300"], 1, 1, opts)
    row = at.dataframe[1].value.to_dict("records")[0]
    assert row["added_residual_beyond_window_deg"] == pytest.approx(v.outcomes[0]["added_residual_beyond_window_deg"],
                                                                    rel=1e-9)
    assert any(note == v.notes[0] for note in (c_.value for c_ in at.caption))  # Tc of the two files' track


def test_a_directory_without_files_is_one_line(tmp_path, monkeypatch):
    at = _page(monkeypatch)
    _set_verdict_inputs(at, tmp_path)
    at.button(key="focus_verdict_run").click().run()
    errors = [e.value for e in at.error]
    assert not at.exception and len(errors) == 1 and "no .mat files" in errors[0]
    assert not at.metric


def test_a_refused_speed_is_one_line_and_nothing_runs(tmp_path, monkeypatch):
    """The library refuses a speed ≤ 0 (RealSceneOptions): the page shows its message naming the
    field, draws no run button and no traceback (no data needed: nothing is read)."""
    at = _page(monkeypatch)
    _set_verdict_inputs(at, tmp_path, speed=-5.0)
    errors = [e.value for e in at.error]
    assert len(errors) == 1 and "platform_speed_m_s" in errors[0]
    assert not [b for b in at.button if b.key == "focus_verdict_run"]


# --- the figure (no data, no streamlit) ----------------------------------------------------------

def _verdict(outcomes, scene_reference="reference", migration_limit=1.0) -> RealSceneVerdict:
    opts = RealSceneOptions(scene_reference=scene_reference, max_range_migration_cells=migration_limit)
    limits = {"residual_beyond_window_deg": opts.max_residual_phase_rms_deg, "peak_loss_db": opts.max_peak_loss_db,
              "range_migration_cells": opts.max_range_migration_cells, "judged_on": "test"}
    return RealSceneVerdict(part="P", trials=len(outcomes), seed=1, passed=sum(o["passed"] for o in outcomes),
                            outcomes=outcomes, reference={}, limits=limits, scenario=None, acquisition=None,
                            options=opts)


def _outcome(i, passed, reasons=(), added=0.5, absolute=14.0, loss=0.1, cells=0.3):
    return {"trial": i, "passed": passed, "reasons": list(reasons), "added_residual_beyond_window_deg": added,
            "residual_beyond_window_deg": absolute, "added_peak_loss_db": loss, "peak_loss_db": loss + 0.2,
            "peak_range_cells": cells}


def test_the_figure_draws_each_trial_against_its_limit():
    outcomes = [_outcome(0, True), _outcome(1, False, ["residual_phase_noise"], added=1.7),
                _outcome(2, False, ["range_migration", "peak_loss"], loss=2.0, cells=1.3)]
    v = _verdict(outcomes)
    fig = real_scene_trials_figure(v)
    residual, loss, cells = fig.data
    assert list(residual.x) == [0, 1, 2]
    assert list(residual.y) == [0.5, 1.7, 0.5]  # the added residual (judged relative to the floor)
    assert list(loss.y) == [0.1, 0.1, 2.0] and list(cells.y) == [0.3, 0.3, 1.3]
    assert list(residual.marker.color) == [PASS_COLOUR, FAIL_COLOUR, FAIL_COLOUR]
    assert list(cells.customdata) == ["passed", "residual_phase_noise", "range_migration, peak_loss"]
    lines = sorted(s.y0 for s in fig.layout.shapes)
    assert lines == sorted([1.0, v.limits["peak_loss_db"], 1.0])  # 1° rms, 1.5 dB, 1 cell
    lo, hi = v.interval
    assert f"P(pass) {1 / 3:.2f} [{lo:.2f}, {hi:.2f}]" in fig.layout.title.text
    assert "added residual beyond PGA's window" in fig.layout.annotations[0].text


def test_the_figure_draws_the_absolute_residual_when_judged_without_the_floor():
    v = _verdict([_outcome(0, False, ["residual_phase_noise"])], scene_reference="none", migration_limit=None)
    fig = real_scene_trials_figure(v)
    assert list(fig.data[0].y) == [14.0] and list(fig.data[1].y) == [pytest.approx(0.3)]  # absolute measures
    assert not fig.layout.annotations[0].text.startswith("added")
    # no range-migration limit: two limit lines only
    assert len(fig.layout.shapes) == 2 and not any(math.isclose(s.y0, 1.0) and s.yref == "y3"
                                                   for s in fig.layout.shapes)
