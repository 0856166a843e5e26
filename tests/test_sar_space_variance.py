"""Space variance of a motion error in the point-target simulator, and what one PGA phase leaves.

PGA estimates one azimuth phase for the whole image. A line-of-sight error Δr(t) along the LOS to
the scene centre is one phase for every target only to first order: targets away from the centre
see it slightly differently, and the single correction fits the centre. These tests measure it on
the noise-free five points of the 77 GHz preset (Taylor −35 dB window), with the error written by
this test (a cubic LOS displacement), not drawn from an IMU model."""

from __future__ import annotations

import numpy as np

from budget.mc import McOptions
from budget.presets import get_preset
from budget.sar import SarGeometry, Scene, form_image, measure_targets, simulate_echoes
from budget.sar.pga import pga


def _after_pga(peak_to_peak_cells: float):
    scen = get_preset("automotive_77ghz")
    geom = SarGeometry.from_scenario(scen, window=McOptions().window_for(scen))
    scene = Scene.default(geom, snr_db=None)
    los = geom.nominal_apc_m() - geom.scene_centre_m[None, :]
    los /= np.linalg.norm(los, axis=1, keepdims=True)
    u = 2.0 * geom.pulse_times_s / geom.aperture_time_s
    d = peak_to_peak_cells * scen.range_resolution_m * u ** 3 / np.ptp(u ** 3)
    img = form_image(geom, simulate_echoes(geom, scene, d[:, None] * los), np.zeros((geom.n_pulses, 3)))
    res = pga(img.data)
    table = measure_targets(img.with_data(res.image), geom, scene, azimuth_search_cells=30).to_frame()
    offset = np.array([np.hypot(t.azimuth_m, t.range_m) for t in scene.targets])
    return res, table, offset


def test_without_error_every_target_has_the_window_sidelobes():
    res, t, _ = _after_pga(0.0)
    assert np.all(np.abs(t["azimuth_pslr_db"] - t["azimuth_ideal_pslr_db"]) < 0.3)


def test_one_pga_phase_focuses_the_centre_and_leaves_off_centre_targets_a_residual():
    """Cubic LOS error of 0.15 range cells peak to peak (≈ 48 rad of phase at 77 GHz): PGA
    converges and the centre target keeps its Taylor sidelobes within 0.5 dB, while both targets
    2√2 m off centre are ≥ 3 dB above them (measured −28.8 / −29.2 dB against −35.2 dB: the
    verdict's +3 dB PSLR allowance fails there, whatever the IMU that caused the error)."""
    res, t, off = _after_pga(0.15)
    assert res.converged
    excess = (t["azimuth_pslr_db"] - t["azimuth_ideal_pslr_db"]).to_numpy()
    centre, corners = int(np.argmin(off)), np.flatnonzero(off > 2.5)
    assert excess[centre] < 0.5
    assert corners.size == 2 and np.all(excess[corners] > 3.0)
    # the excess grows with the distance from the centre (the five targets at 0, √2 and 2√2 m)
    order = np.argsort(off)
    assert np.all(np.diff(excess[order][[0, 2, 4]]) > 0)


def test_the_residual_grows_with_the_error():
    """Off-centre excess at 0.05 cells is smaller than at 0.15 (measured ≈ 2.5 vs 6.0–6.4 dB)."""
    _, small, off = _after_pga(0.05)
    _, large, _ = _after_pga(0.15)
    corners = off > 2.5
    ex = lambda t: (t["azimuth_pslr_db"] - t["azimuth_ideal_pslr_db"]).to_numpy()[corners]  # noqa: E731
    assert np.all(ex(large) > ex(small) + 1.0)
