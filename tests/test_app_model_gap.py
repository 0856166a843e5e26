"""Model-gap page through ``AppTest``: it loads, runs the built-in example and shows the
library's numbers (gap before/after equal ``run_gap`` on the same log, model and seed)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from budget.catalog.io import get_part
from budget.gap import run_gap
from budget.gap.inputs import log_from_arrays
from budget.imu.generator import simulate_static_log
from budget.imu.noise_model import NoiseModel

AppTest = pytest.importorskip("streamlit.testing.v1", reason="streamlit not installed").AppTest

APP_DIR = Path(__file__).resolve().parents[1] / "app"
if str(APP_DIR) not in sys.path:
    sys.path.insert(0, str(APP_DIR))


@pytest.mark.slow
def test_model_gap_page_runs_the_example():
    at = AppTest.from_file(str(APP_DIR / "main.py"), default_timeout=300).run()
    at.switch_page("pages/model_gap.py").run()
    assert not at.exception and not at.error
    at.number_input(key="gap_realizations").set_value(4)
    at.button(key="gap_run").click().run()
    assert not at.exception, at.exception
    assert not at.error, [e.value for e in at.error]
    shown = {m.label: m.value for m in at.metric}

    # the page's example, rebuilt here from the same part, hidden effect and seed
    effect = {"name": "sinusoid", "channel": "gyro_z",
              "params": {"frequency_hz": 0.7, "amplitude": float(np.radians(0.02))}}
    model = NoiseModel.from_part(get_part("ADIS16405"))
    rate, n = 100.0, 180_000
    log = log_from_arrays(simulate_static_log(model.with_effect(effect), n, rate, np.random.default_rng(0)), rate)
    ref = run_gap(log, get_part("ADIS16405"), seed=0, realizations=4)
    assert shown["gap before (mean z²)"] == f"{ref.gap_before:.3g}"
    assert shown["gap after (mean z²)"] == f"{ref.gap_after:.3g}"
    # the page's verdict is the report's channel states: a warning names every channel not ok
    open_channels = [ch for ch in ref.channels if ref.channel_state(ch) != "ok"]
    warned = " ".join(w.value for w in at.warning)
    assert all(f"{ch} (" in warned for ch in open_channels)
    assert ("Not explained" in warned) == bool(open_channels)
    # a later input change does not re-run the workflow: the last run stays, with a note
    at.number_input(key="gap_seed").set_value(1).run()
    assert not at.exception
    assert {m.label: m.value for m in at.metric}["gap before (mean z²)"] == f"{ref.gap_before:.3g}"
    assert any("inputs changed" in i.value for i in at.info)
