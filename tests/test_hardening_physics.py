"""No silent absurdity: physically impossible scenarios are refused with the
reason; log integrity: absurd samples named with their row, repairs that would keep too little
refused, a mostly-NaN channel never interpolated into a constant, a misread time unit named."""

from __future__ import annotations

import numpy as np
import pytest

from budget.cli.main import main
from budget.errors import InputError
from budget.noise import LogError, read_log
from budget.noise.log_checks import MIN_KEPT_FRACTION
from budget.presets import PRESETS, get_preset
from budget.scenario import PLAUSIBLE_TC_S, Scenario

BASE = dict(carrier_frequency_hz=9.6e9, slant_range_m=5000.0, azimuth_resolution_m=0.5,
            range_resolution_m=0.5, platform_speed_m_s=50.0)


def test_presets_are_plausible():
    for name in PRESETS:
        s = get_preset(name)
        assert PLAUSIBLE_TC_S[0] <= s.tc_s <= PLAUSIBLE_TC_S[1]


@pytest.mark.parametrize("update,field,words", [
    (dict(carrier_frequency_hz=1e300), "carrier_frequency_hz", "Hz"),
    (dict(carrier_frequency_hz=2e13), "carrier_frequency_hz", "radar"),
    (dict(medium="sonar", carrier_frequency_hz=1.0), "carrier_frequency_hz", "sonar"),
    (dict(platform_speed_m_s=1e-300), "platform_speed_m_s", "orbit"),
    (dict(slant_range_m=1e300), "slant_range_m", "km"),
    (dict(azimuth_resolution_m=1e-30), "azimuth_resolution_m", "µm"),
    (dict(propagation_speed_m_s=1e12), "propagation_speed_m_s", "light"),
    # each input plausible on its own, together Tc = 5e19 s
    (dict(medium="sonar", carrier_frequency_hz=100.0, slant_range_m=1e9, azimuth_resolution_m=5.0,
          range_resolution_m=5.0, platform_speed_m_s=1e-3), "tc_s", "Tc"),
])
def test_implausible_scenarios_are_refused_with_reason(update, field, words):
    with pytest.raises(InputError) as e:
        Scenario.from_dict({**BASE, **update}, source="s.json")
    msg = str(e.value)
    assert "s.json" in msg and field in msg and words in msg


def test_bounds_refuses_absurd_tc(capsys):
    assert main(["bounds", "--tc", "5e19", "--range-resolution", "0.1"]) == 2
    assert main(["bounds", "--tc", "5e-290", "--range-resolution", "0.1"]) == 2
    assert "plausible" in capsys.readouterr().err


def _log(path, t, gyro, header="time_s,gyro_x_dps,accel_z_mps2"):
    rows = "\n".join(f"{a:.9g},{b:.9g},9.81" for a, b in zip(t, gyro))
    path.write_text(f"{header}\n{rows}\n")
    return path


def test_single_absurd_sample_is_named_with_its_row(tmp_path):
    rng = np.random.default_rng(1)
    g = rng.normal(0.0, 0.01, 3000)
    g[1234] = 1e300
    p = _log(tmp_path / "spike.csv", np.arange(3000) / 100.0, g)
    with pytest.raises(LogError, match="implausible") as e:
        read_log(p)
    assert "1236" in str(e.value)  # data index 1234 = spreadsheet row 1236
    log = read_log(p, repair=True)  # one corrupt sample: treated as missing, interpolated, listed
    assert np.all(np.abs(log.channels["gyro_x"]) < 1.0)
    assert any("implausible" in r for r in log.issues.repairs)


def test_repair_keeping_too_little_is_refused(tmp_path):
    n = 19_830
    block = np.arange(n) // 76  # a gap after every 76 samples: the longest stretch is 0.4 %
    t = np.arange(n) / 100.0 + block * 5.0
    g = np.random.default_rng(2).normal(0, 0.01, n)
    with pytest.raises(LogError, match="keep only 76 of 19,830") as e:
        read_log(_log(tmp_path / "gaps.csv", t, g), repair=True)
    assert f"{100 * MIN_KEPT_FRACTION:.0f} %" in str(e.value)


def test_mostly_nan_channel_is_not_interpolated(tmp_path):
    n = 10_000
    g = np.full(n, np.nan)
    g[5] = 0.01
    p = _log(tmp_path / "nan.csv", np.arange(n) / 100.0, g)
    with pytest.raises(LogError, match="interpolated"):
        read_log(p, repair=True)


def test_time_in_ns_read_as_seconds_is_named(tmp_path):
    t = np.arange(500) * 1e7  # ns stamps of a 100 Hz log in a column called time_s
    with pytest.raises(InputError, match="time_ns") as e:
        read_log(_log(tmp_path / "ns.csv", t, np.zeros(500) + 0.01))
    assert "ns.csv" in str(e.value)


def test_duplicate_column_names_are_named(tmp_path):
    p = _log(tmp_path / "dup.csv", np.arange(50) / 100.0, np.zeros(50),
             header="time_s,gyro_x_dps,gyro_x_dps")
    with pytest.raises(InputError, match="more than once") as e:
        read_log(p)
    assert "gyro_x_dps" in str(e.value) and ".1" not in str(e.value)


@pytest.mark.parametrize("effect, params, words", [
    ("rate_ramp", {"R": 1e300}, "rate_ramp.R must be within ±1e+06"),
    ("lowpass", {"cutoff_hz": 1e-300}, "lowpass.cutoff_hz must be ≥ 1e-06 Hz"),
    ("sinusoid", {"frequency_hz": 5.0, "amplitude": 1e300}, "sinusoid.amplitude must be at most"),
])
def test_absurd_effect_parameters_are_refused_with_their_name(tmp_path, capsys, effect, params, words):
    import json

    from budget.cli.main import main

    model = {"part_id": "X", "grade": "tactical", "source": "test", "gyro_arw_deg_rt_h": 0.1,
             "effects": [{"name": effect, "channel": "gyro_x", "params": params}]}
    path = tmp_path / "model.json"
    path.write_text(json.dumps(model), encoding="utf-8")
    assert main(["mc", "--preset", "automotive_77ghz", "--model", str(path), "--trials", "4", "-q"]) == 2
    err = capsys.readouterr().err
    assert words in err and "model.json" in err and "Traceback" not in err
