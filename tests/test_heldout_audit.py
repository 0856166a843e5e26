"""Held-out audit: scenarios the tool was not tuned on, derived by hand, and what a user gets wrong.

The expected values here come from closed forms written out in each test (not from the tool's
output): Tc = λR/(2 δℓ V) at broadside with an unweighted aperture, λ = c/f0.
"""

from __future__ import annotations

import warnings

import pytest

from budget.scenario import Scenario

#: A small synthetic-aperture sonar (held out: not a preset): 100 kHz, 1.5 m/s, 50 m, 3 cm cells.
SAS_50M = {"name": "sas_50m", "medium": "sonar", "carrier_frequency_hz": 100e3, "slant_range_m": 50.0,
           "azimuth_resolution_m": 0.03, "range_resolution_m": 0.03, "platform_speed_m_s": 1.5,
           "depression_deg": 10.0, "lever_arm_m": [0.1, 0.0, 0.0], "platform_rate_deg_s": 0.5,
           "imu_rate_hz": 100.0}


def test_a_sonar_carrier_in_khz_that_the_resolution_checks_let_through_is_noted():
    """100 (kHz) written into carrier_frequency_hz is a 100 Hz sonar: λ = 1500/100 = 15 m. With
    5 m cells the range resolution needs only c/(2δr) = 150 Hz of bandwidth (< 2·f0) and δℓ ≥ λ/4,
    so no refusal fires and Tc = λR/(2δℓV) = 15·50/(2·5·1.5) = 50 s instead of the 100 kHz
    sonar's 0.05 s — the unit slip must be said, with the reading that puts it in band."""
    data = {**SAS_50M, "carrier_frequency_hz": 100.0, "azimuth_resolution_m": 5.0, "range_resolution_m": 5.0}
    with pytest.warns(UserWarning) as w:
        s = Scenario.from_dict(data)
    assert s.tc_s == pytest.approx(15.0 * 50.0 / (2 * 5.0 * 1.5), rel=1e-12)
    carrier = [str(x.message) for x in w if "carrier" in str(x.message)]
    assert len(carrier) == 1, [str(x.message) for x in w]
    assert "carrier_frequency_hz" in carrier[0] and "1e+05 Hz if it was in kHz" in carrier[0]
    assert carrier[0] in s.notes()


def test_carriers_inside_their_bands_carry_no_carrier_note():
    """The held-out sonar at 100 kHz and radars from L (1.3 GHz) to W band (94 GHz) are quiet."""
    radar = {"name": "r", "medium": "radar", "slant_range_m": 5000.0, "azimuth_resolution_m": 0.3,
             "range_resolution_m": 0.3, "platform_speed_m_s": 100.0}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert Scenario.from_dict(SAS_50M).notes() == []
        for f0 in (1.3e9, 5.3e9, 16e9, 94e9):
            assert Scenario.from_dict({**radar, "carrier_frequency_hz": f0}).notes() == []
