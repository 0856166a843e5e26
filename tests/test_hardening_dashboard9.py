"""Dashboard: the noise lab's catalog entry offers what its messages name — keep the spikes, the grade.

A characterisation replaces isolated spikes that would decide the short-τ Allan deviation and says
how to keep them; the dashboard says it as its own tick box (not a CLI option) and the box keeps
them. The grade of the catalog row is inferred unless the user picks one.
"""

from __future__ import annotations

import numpy as np
import pytest

from app_harness import open_app

from budget.catalog.schema import GRADES

UPLOAD = "upload a log or an Allan table"


def _spiky_log(n: int = 6000, rate: float = 100.0) -> bytes:
    """White gyro noise (1e-3 deg/s) with 6 isolated spikes of 0.5 deg/s: they carry most of the
    sample-to-sample variance, so the fit replaces them by default."""
    rng = np.random.default_rng(21)
    gyro = rng.normal(0.0, 1e-3, n)
    gyro[np.linspace(500, n - 500, 6).astype(int)] += 0.5
    accel = 9.81 + rng.normal(0.0, 1e-3, n)
    lines = "".join(f"{i / rate:.4f},{g:.6g},{a:.6g}\n" for i, (g, a) in enumerate(zip(gyro, accel)))
    return ("time_s,gyro_z_dps,accel_z_mps2\n" + lines).encode()


def _row(at, column: str) -> str:
    """A value of the catalog row the page shows (its table of column → value)."""
    rows = next(d.value for d in at.dataframe if list(d.value.columns) == ["column", "value"]
                and "gyro_arw_deg_rt_h" in set(d.value["column"]))
    return rows.set_index("column").loc[column, "value"]


def _warnings(at) -> list[str]:
    assert not at.exception, [e.value for e in at.exception]
    return [w.value for w in at.warning]


@pytest.fixture(scope="module")
def page():
    at = open_app("pages/noise_lab.py")
    at.radio(key="noise_source").set_value(UPLOAD).run()
    at.file_uploader(key="noise_upload").set_value(("spiky.csv", _spiky_log(), "text/csv")).run()
    return at


def test_the_spike_warning_names_the_tick_box_and_the_box_keeps_them(page):
    replaced = [w for w in _warnings(page) if "isolated spike" in w]
    assert replaced and "tick 'keep spikes' to keep them" in replaced[0], _warnings(page)
    assert "--keep-spikes" not in replaced[0] and "keep_spikes=True" not in replaced[0]
    arw_replaced = float(_row(page, "gyro_arw_deg_rt_h"))
    page.checkbox(key="noise_keep_spikes").check().run()
    kept = [w for w in _warnings(page) if "isolated spike" in w]
    assert kept and "kept on request" in kept[0], kept
    # the spikes carry ≈ 6·0.5²/6000 = 2.5e-4 (deg/s)² against the noise's 1e-6: kept, they
    # raise the white-noise level ≈ 16× (3× is a safe floor for the fit over octave τ)
    assert float(_row(page, "gyro_arw_deg_rt_h")) > 3 * arw_replaced
    page.checkbox(key="noise_keep_spikes").uncheck().run()




def test_the_grade_is_inferred_unless_picked(page):
    inferred = _row(page, "grade")
    assert inferred in GRADES
    other = next(g for g in GRADES if g != inferred)
    page.selectbox(key="noise_grade").set_value(other).run()
    assert _row(page, "grade") == other and not page.exception
    page.selectbox(key="noise_grade").set_value("inferred").run()
    assert _row(page, "grade") == inferred
