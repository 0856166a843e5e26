"""The dashboard's "run on demand, keep the last result" component (``components.run_on_demand``),
pinned on a cheap callable under ``AppTest``: it runs only when its button is pressed, keeps the
last result across reruns, says when the inputs changed since, and shows a refusal of the library
as its one-line message (never a traceback) with the last result kept. The pages that use it
(Model gap, Real SAR data, Monte Carlo, Trade study) are run against the library in their own
tests."""

from __future__ import annotations

import pytest

from app_harness import AppTest, open_app


def _script():
    """A page holding one on-demand run: x → 10·x; x < 0 is refused as the library refuses input,
    x = 13 fails to write an output. ``calls`` counts the runs."""
    import streamlit as st

    import components as c
    from budget.errors import InputError, OutputError

    x = int(st.number_input("x", value=1, step=1, key="x"))
    note = st.session_state.get("refused_prefix")

    def run():
        st.session_state["calls"] = st.session_state.get("calls", 0) + 1
        if x < 0:
            raise InputError("must be at least 0", field="x", value=x)
        if x == 13:
            raise OutputError("read-only file system", file="/proc/out.json")
        return 10 * x

    last = c.run_on_demand("demo_last", (x,), "Compute", run, button_key="demo_run",
                           prompt="Press **Compute** to compute.",
                           refused=(lambda text: f"{note}: {text}") if note else None)
    if last is not None:
        st.metric(f"result of x = {last.inputs[0]}", last.result)


def _open(**state) -> AppTest:
    at = AppTest.from_function(_script, default_timeout=30)
    for k, v in state.items():
        at.session_state[k] = v
    at.run()
    assert not at.exception, [e.value for e in at.exception]
    return at


def _shown(at: AppTest) -> dict[str, str]:
    assert not at.exception, [e.value for e in at.exception]
    return {m.label: m.value for m in at.metric}


def _infos(at: AppTest) -> list[str]:
    return [i.value for i in at.info]


def _calls(at: AppTest) -> int:
    return at.session_state["calls"] if "calls" in at.session_state else 0


def test_nothing_runs_before_the_button_and_the_prompt_says_what_to_press():
    at = _open()
    at.number_input(key="x").set_value(2).run()
    assert _shown(at) == {} and _calls(at) == 0
    assert _infos(at) == ["Press **Compute** to compute."]
    assert at.button(key="demo_run").label == "Compute"
    assert "demo_last" not in at.session_state


def test_the_button_runs_once_and_reruns_keep_the_result_without_running_again():
    at = _open()
    at.button(key="demo_run").click().run()
    assert _shown(at) == {"result of x = 1": "10"} and _calls(at) == 1
    assert _infos(at) == []  # a current result: no prompt, no note
    at.run()  # any rerun (another widget, a page switch back) shows the kept result
    at.number_input(key="x").set_value(1).run()
    assert _shown(at) == {"result of x = 1": "10"} and _calls(at) == 1
    assert at.session_state["demo_last"] == ((1,), 10)


def test_changed_inputs_keep_the_last_result_with_a_note_until_the_next_run():
    at = _open()
    at.button(key="demo_run").click().run()
    at.number_input(key="x").set_value(3).run()
    assert _shown(at) == {"result of x = 1": "10"} and _calls(at) == 1  # not re-run
    assert _infos(at) == ["The inputs changed since the last run; press **Compute** to update. "
                          "Showing the last run."]
    at.number_input(key="x").set_value(1).run()  # back to the inputs of the result: no note
    assert _infos(at) == []
    at.number_input(key="x").set_value(3).run()
    at.button(key="demo_run").click().run()
    assert _shown(at) == {"result of x = 3": "30"} and _calls(at) == 2
    assert _infos(at) == []


def test_a_refused_input_is_one_line_and_nothing_is_kept():
    at = _open()
    at.number_input(key="x").set_value(-2).run()
    at.button(key="demo_run").click().run()
    errors = [e.value for e in at.error]
    assert errors == ["field x: must be at least 0 (got -2)"], errors
    assert not at.exception and _shown(at) == {} and _calls(at) == 1
    assert _infos(at) == []  # the refusal, not the prompt
    assert "demo_last" not in at.session_state


def test_a_refusal_keeps_the_last_result_with_its_note():
    at = _open(refused_prefix="Compute of x not run")
    at.button(key="demo_run").click().run()
    at.number_input(key="x").set_value(-1).run()
    at.button(key="demo_run").click().run()
    errors = [e.value for e in at.error]
    assert errors == ["Compute of x not run: field x: must be at least 0 (got -1)"], errors
    assert "Traceback" not in errors[0] and "\n" not in errors[0]
    assert _shown(at) == {"result of x = 1": "10"}
    assert any("inputs changed" in i for i in _infos(at))
    at.run()  # the message belongs to that press only; the kept result stays
    assert not at.error and _shown(at) == {"result of x = 1": "10"} and _calls(at) == 2


def test_an_output_the_library_cannot_write_is_its_one_line():
    at = _open()
    at.number_input(key="x").set_value(13).run()
    at.button(key="demo_run").click().run()
    assert [e.value for e in at.error] == ["/proc/out.json: read-only file system"]
    assert not at.exception and _shown(at) == {}


@pytest.mark.parametrize("page, button", [("pages/model_gap.py", "gap_run"), ("pages/focus.py", None),
                                          ("pages/monte_carlo.py", "mc_run"), ("pages/sweep.py", "sw_run_grid")])
def test_the_pages_with_a_run_button_say_what_to_press_before_any_run(page, button):
    """Nothing runs when a page opens: each page draws its button and its prompt, and no result.
    (The Real SAR data page asks for its phase history first; its buttons come with it.)"""
    at = open_app(page)
    assert not at.error and not at.metric, [e.value for e in at.error]
    if button is not None:
        assert at.button(key=button).label.startswith("Run")
        assert any("press **run" in i.value.lower() for i in at.info), [i.value for i in at.info]


def test_the_real_sar_image_is_kept_when_an_input_changes(tmp_path):
    """The Real SAR data page's **Focus** (a point target, 5 m patch): the image is formed on the
    button only; a changed patch keeps it with the note instead of forming it again."""
    from test_focus_description import N, NAME, _write  # a synthetic AFRL file of N pulses

    _write(tmp_path / NAME)
    at = open_app("pages/focus.py")
    at.radio(key="focus_mode").set_value("none").run()
    for key in ("focus_range_extent", "focus_azimuth_extent"):
        at.number_input(key=key).set_value(5.0).run()
    at.text_input(key="focus_dir").set_value(str(tmp_path)).run()
    assert not at.metric and any("Press **Focus**" in i for i in _infos(at))
    at.button(key="focus_run").click().run()
    first = _shown(at)
    assert first["pulses"] == str(N) and not at.error
    assert not any("inputs changed" in i for i in _infos(at))
    at.number_input(key="focus_range_extent").set_value(6.0).run()
    assert _shown(at) == first
    assert any(i.startswith("The inputs changed") and "**Focus**" in i for i in _infos(at))


def test_the_trade_study_keeps_its_table_and_says_when_the_seed_changed():
    """The Trade study's grid (one part, one scenario, one trial) now says when it is stale."""
    at = open_app("pages/sweep.py")
    at.selectbox(key="scn_preset").set_value("automotive_77ghz").run()
    at.multiselect(key="sw_parts").set_value(["STIM300"]).run()
    at.multiselect(key="sw_scenarios").set_value(["automotive_77ghz"]).run()
    at.number_input(key="sw_trials").set_value(1).run()
    at.button(key="sw_run_grid").click().run()
    inputs, table = at.session_state["sw_grid_last"]
    assert not at.error and not any("inputs changed" in i for i in _infos(at))
    at.number_input(key="sw_seed").set_value(int(at.number_input(key="sw_seed").value) + 1).run()
    assert at.session_state["sw_grid_last"][1] is table  # kept, not re-run
    assert any(i.startswith("The inputs changed") and "**Run the sweep**" in i for i in _infos(at))
