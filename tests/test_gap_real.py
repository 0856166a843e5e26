"""Model-gap workflow on the real ADIS16405 recordings in ``../shared/data`` (skipped if absent).

What the recordings show against the catalog row (see the README's model-gap section): a tone
near 20 Hz on gyro_z and a 0.56 Hz line on the accelerometers, neither in the datasheet model.
The tone wanders between about 19 and 22 Hz over the recording. The fast test uses the first
60 000 rows (10 min) and two channels; the slow ones the whole logs and the published Allan
table.
"""

from __future__ import annotations

import pytest

from budget.gap import run_gap

pytestmark = pytest.mark.shared_data


def _log(shared_data, i: int):
    path = shared_data / "logs" / f"adis16405_static_{i}.csv.gz"
    if not path.is_file():
        pytest.skip(f"{path} not found")
    return path


def _named(report, name: str, channel: str):
    return [s for s in report.steps if (s.name, s.channel) == (name, channel)]


def test_short_real_log_names_the_tones(shared_data):
    rep = run_gap(_log(shared_data, 1), "ADIS16405", seed=0, max_rows=60_000,
                  channels=["gyro_z", "accel_x"], max_steps=4)
    tone = _named(rep, "sinusoid", "gyro_z")
    assert tone and 18.5 < tone[0].params["frequency_hz"] < 22.5, rep.summary()
    line = _named(rep, "sinusoid", "accel_x")
    assert line and abs(line[0].params["frequency_hz"] - 0.562) < 0.03, rep.summary()
    assert rep.gap_after < rep.gap_before / 3
    assert any("output rate" in n for n in rep.notes)  # catalog 819.2 Hz vs log 100 Hz


@pytest.mark.slow
@pytest.mark.parametrize("i", [1, 2])
def test_full_real_logs(shared_data, i):
    rep = run_gap(_log(shared_data, i), "ADIS16405", seed=0)
    assert rep.gap_after < rep.gap_before / 3
    assert _named(rep, "sinusoid", "gyro_z"), rep.summary()
    assert not rep.within_noise  # the datasheet model plus the vocabulary does not explain it all


@pytest.mark.slow
def test_real_allan_table(shared_data):
    table = shared_data / "adev" / "adis16405.csv"
    if not table.is_file():
        pytest.skip(f"{table} not found")
    rep = run_gap(table, "ADIS16405", seed=0, rate_hz=100.0, samples=1_000_000)
    assert rep.kind == "adev_table"
    assert rep.gap_after < rep.gap_before / 3
    # from the Allan deviation alone a tone above ~10 Hz is seen only through its τ = 0.02 s
    # point, so its frequency is not pinned down (the log gives 19–22 Hz)
    tone = _named(rep, "sinusoid", "gyro_z")
    assert tone and 10.0 < tone[0].params["frequency_hz"] < 50.0, rep.summary()
