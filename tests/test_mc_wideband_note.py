"""The Monte Carlo result states what image-domain PGA leaves across a wide range band."""

from __future__ import annotations

import math

import numpy as np

from budget.mc.notes import WIDEBAND_NOTE_FRACTION, wideband_note
from budget.presets import get_preset
from budget.sar import SarGeometry


def _sas(f0_hz: float):
    return get_preset("sas_100khz").model_copy(update={"name": f"sas_{f0_hz:g}", "carrier_frequency_hz": f0_hz,
                                                       "azimuth_resolution_m": 0.1})


def test_note_rms_matches_the_simulated_band():
    # 15 kHz band at 30 kHz: b = 0.5. The note's b/√12 against the rms of f/f0 − 1 over the
    # geometry's own in-band frequencies (a discrete, nearly uniform band): within 2 %.
    geom = SarGeometry.from_scenario(_sas(30e3))
    scen = _sas(30e3)
    b = geom.range_bandwidth_hz / geom.carrier_frequency_hz
    assert abs(b - scen.c_m_s / (2 * scen.range_resolution_m * 30e3)) < 0.005  # ≈ 0.5; the band is a whole number of range bins
    f = geom.range_band_freqs_hz
    rms = float(np.sqrt(np.mean((f / geom.carrier_frequency_hz) ** 2)))
    note = wideband_note(geom)
    assert "fractional bandwidth 50 %" in note
    stated = float(note.split("leaves ")[1].split(" %")[0]) / 100
    assert abs(stated - b / math.sqrt(12)) < 1e-3
    assert abs(stated / rms - 1) < 0.02


def test_no_note_for_narrowband_radar():
    for name in ("airborne_xband", "automotive_77ghz"):
        geom = SarGeometry.from_scenario(get_preset(name))
        assert geom.range_bandwidth_hz / geom.carrier_frequency_hz <= WIDEBAND_NOTE_FRACTION
        assert wideband_note(geom) == ""


def test_summary_carries_the_note():
    from budget.catalog.io import get_part
    from budget.mc import run_mc

    r = run_mc(_sas(30e3), get_part("HG9900"), 2, 1)
    assert abs(r.judged_on["fractional_bandwidth"] - 0.5) < 0.01
    assert "wavenumber-domain autofocus" in r.summary()
    assert "wavenumber-domain autofocus" in r.to_dict()["judged_on"]["wideband_note"]
