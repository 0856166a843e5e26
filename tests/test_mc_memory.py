"""Memory bounds of the Monte Carlo chain: an image too large to simulate is refused by name, a
formation batch is cut for large images without changing a number, and the chain keeps only the
motion series it uses."""

from __future__ import annotations

import math

import numpy as np
import pytest

import budget.mc.chain as chain
from budget.catalog.fill import resolve_unspecified
from budget.catalog.io import get_part
from budget.errors import InputError
from budget.mc import McOptions
from budget.mc.chain import ChainSetup, formation_batch, run_chunk
from budget.motion import simulate_motion
from budget.presets import get_preset
from budget.sar import SarGeometry
from budget.sar.geometry import MAX_PIXELS
from budget.scenario import Scenario

#: An L-band radar at walking speed: Tc = 505 s, 10560 pulses × 1152 range bins (12 M pixels).
SLOW_LBAND = {"name": "slow_lband", "carrier_frequency_hz": 1.4857e9, "slant_range_m": 3581.0,
              "azimuth_resolution_m": 0.208, "range_resolution_m": 0.2584, "platform_speed_m_s": 3.44,
              "depression_deg": 28.7, "imu_rate_hz": 400.0}


def test_an_image_beyond_the_pixel_limit_is_refused_with_its_size():
    scen = Scenario.model_validate(SLOW_LBAND)
    with pytest.raises(InputError) as e:
        SarGeometry.from_scenario(scen)
    assert e.value.field == "azimuth_resolution_m"
    assert "M pixels" in str(e.value) and f"{MAX_PIXELS / 1e6:.3g} M pixels" in str(e.value)
    # a coarser azimuth resolution brings it within the limit
    ok = SarGeometry.from_scenario(scen.model_copy(update={"azimuth_resolution_m": 0.5}))
    assert ok.n_pulses * ok.n_range <= MAX_PIXELS


@pytest.mark.slow
@pytest.mark.parametrize("scene", ["points", "realistic"])
def test_a_cut_formation_batch_gives_the_same_trials(scene, monkeypatch):
    scen = get_preset("airborne_xband")
    setup = ChainSetup.build(scen, McOptions(scene=scene))
    model = resolve_unspecified(get_part("ADIS16405"), "fill_grade_typical").model
    full = run_chunk(setup, model, 3, 0, 16)
    n_a, n_r = chain.chain_plan(setup).template.data.shape
    # room for three trials' images: batches of 3, 3, 2 inside each aligned batch of 8
    monkeypatch.setattr(chain, "FORMATION_BYTES", 3 * 16 * n_a * n_r * chain.IMAGE_COPIES + 1)
    assert formation_batch(setup) == 3
    cut = run_chunk(setup, model, 3, 0, 16)
    assert [o.trial for o in cut] == list(range(16))
    for a, b in zip(full, cut):
        assert (a.passed_before, a.passed_after, a.reasons, a.pga_reason) == \
               (b.passed_before, b.passed_after, b.reasons, b.pga_reason)
        for k in a.after:
            assert a.after[k] == b.after[k] or (math.isnan(a.after[k]) and math.isnan(b.after[k])), k


def test_position_only_series():
    scen = get_preset("airborne_xband")
    model = get_part("STIM300")
    both = simulate_motion(scen, model, 4, 1)
    pos = simulate_motion(scen, model, 4, 1, keep_series="position")
    assert pos.range_error_m is None and np.array_equal(pos.position_error_m, both.position_error_m)
    assert np.array_equal(pos.peak_range_cells, both.peak_range_cells)
    with pytest.raises(InputError, match="keep_series"):
        simulate_motion(scen, model, 4, 1, keep_series="range")


def test_a_clutter_scene_too_costly_to_simulate_is_refused_before_the_work():
    """80 GHz at 26 km and 6 m/s: 16,000 pulses over 1.3 M clutter cells (≈ 70 min of clutter)."""
    scen = Scenario.model_validate({"name": "slow_w_band", "carrier_frequency_hz": 80.2e9, "slant_range_m": 26064.0,
                                    "azimuth_resolution_m": 0.0618, "range_resolution_m": 0.322,
                                    "platform_speed_m_s": 6.24, "depression_deg": 9.0})
    with pytest.raises(InputError) as e:
        ChainSetup.build(scen, McOptions(scene="realistic"))
    assert e.value.field == "scene" and "phase evaluations" in str(e.value) and "points scene" in str(e.value)


def test_point_target_echoes_in_groups_equal_the_whole_envelope(monkeypatch):
    import budget.sar.echoes as echoes
    from budget.sar import Scene, simulate_echoes

    geom = SarGeometry.from_scenario(get_preset("airborne_xband"))
    scene = Scene.default(geom, snr_db=None)
    whole = simulate_echoes(geom, scene, None, None)
    monkeypatch.setattr(echoes, "ENVELOPE_ELEMENTS", 2 * geom.n_pulses * geom.band_bins)  # 2 targets a group
    grouped = simulate_echoes(geom, scene, None, None)
    assert np.max(np.abs(grouped - whole)) <= 1e-12 * np.max(np.abs(whole))
