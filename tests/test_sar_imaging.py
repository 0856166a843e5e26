"""Echo simulation, motion compensation and image formation (range-Doppler vs backprojection)."""

import numpy as np
import pytest

from budget.plots.sar import image_figure, irf_cuts_figure
from budget.presets import get_preset
from budget.sar import (Acceptance, PointTarget, SarGeometry, Scene, evaluate, form_image, measure_targets,
                        simulate_echoes)
from budget.sar.metrics import irf_cuts


@pytest.fixture(scope="module")
def ideal():
    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    scene = Scene.default(g, snr_db=None)
    data = simulate_echoes(g, scene, None)
    return g, scene, data, form_image(g, data)


def _sway(g, amp_m=0.6):
    """Smooth cross-track and vertical APC motion of ``amp_m`` (many wavelengths, ~1 range cell)."""
    u = 2 * g.pulse_times_s / g.aperture_time_s
    off = np.zeros((g.n_pulses, 3))
    off[:, 1] = amp_m * np.sin(2.1 * u + 0.4)
    off[:, 2] = 0.5 * amp_m * u ** 2
    off[:, 0] = 0.05 * u
    return off


def test_ideal_rda_image_reproduces_unweighted_theory(ideal):
    g, scene, _, img = ideal
    f = measure_targets(img, g, scene).to_frame()
    for ax in ("azimuth", "range"):
        assert np.allclose(f[f"{ax}_pslr_db"], -13.26, atol=0.15)
        assert np.all(np.abs(f[f"{ax}_broadening"]) < 0.005)  # 3 dB width 0.886 cells
        assert np.all(np.abs(f[f"{ax}_peak_shift_m"]) < 0.01 * f[f"{ax}_cell_m"].iloc[0] * 2)
        # whole-line ISLR; the azimuth cut of a wide aperture loses a little far-sidelobe energy to
        # neighbouring range lines (the 2-D spectrum is a sector of an annulus), hence 0.3 dB
        assert np.allclose(f[f"{ax}_islr_db"], -9.68, atol=0.3)
    assert np.all(np.abs(f["peak_loss_db"]) < 0.03)
    assert evaluate(measure_targets(img, g, scene)).passed


def test_rda_agrees_with_backprojection(ideal):
    g, scene, data, img = ideal
    bp = form_image(g, data, method="backprojection")
    ia = np.searchsorted(img.azimuth_m, bp.azimuth_m - 1e-9)
    ja = np.searchsorted(img.slant_range_m, bp.slant_range_m - 1e-9)
    assert np.allclose(img.azimuth_m[ia], bp.azimuth_m) and np.allclose(img.slant_range_m[ja], bp.slant_range_m)
    sub = img.data[np.ix_(ia, ja)]
    assert np.linalg.norm(sub - bp.data) / np.linalg.norm(bp.data) < 0.03  # complex, phase included
    fr, fb = measure_targets(img, g, scene).to_frame(), measure_targets(bp, g, scene).to_frame()
    assert np.allclose(fr["peak_amplitude"], fb["peak_amplitude"], rtol=0.003)
    for ax in ("azimuth", "range"):
        assert np.allclose(fr[f"{ax}_width_3db_m"], fb[f"{ax}_width_3db_m"], rtol=0.005)
        assert np.allclose(fr[f"{ax}_pslr_db"], fb[f"{ax}_pslr_db"], atol=0.2)


def test_taylor_window_image():
    g = SarGeometry.from_scenario(get_preset("airborne_xband"), window="taylor")
    scene = Scene(targets=[PointTarget(azimuth_m=0.0, range_m=0.0)])
    img = form_image(g, simulate_echoes(g, scene, None))
    m = measure_targets(img, g, scene)[0]
    for ax in (m.azimuth, m.range):
        assert ax.pslr_db == pytest.approx(-35.2, abs=0.5)
        assert abs(ax.broadening) < 0.005  # window-aware: relative to Taylor's own 1.18 × 0.886 cells
        assert ax.width_3db_m / ax.cell_m == pytest.approx(1.184, abs=0.01)


def test_motion_compensation_with_the_true_trajectory_restores_the_image(ideal):
    g, scene, _, _ = ideal
    off = _sway(g)
    data = simulate_echoes(g, scene, off)
    bad = evaluate(measure_targets(form_image(g, data, None), g, scene))
    assert not bad.passed
    # RDA: first/second-order mocomp to the scene centre line leaves a small space-variant residual
    good = measure_targets(form_image(g, data, off), g, scene)
    assert evaluate(good, Acceptance(max_broadening=0.03, pslr_margin_db=1.0)).passed
    # residual true − measured enters like a real error: half the sway left uncompensated fails
    assert not evaluate(measure_targets(form_image(g, data, 0.5 * off), g, scene)).passed
    # backprojection with the measured (= true) trajectory is exact
    bp = form_image(g, data, off, method="backprojection")
    fb = measure_targets(bp, g, scene).to_frame()
    assert np.all(np.abs(fb["azimuth_broadening"]) < 0.005) and np.all(np.abs(fb["peak_loss_db"]) < 0.05)


def test_position_error_larger_than_a_cell_migrates_through_range_cells(ideal):
    g, _, _, _ = ideal
    scene = Scene(targets=[PointTarget(azimuth_m=0.0, range_m=0.0)])
    shift = 3.0 * g.range_cell_m
    off = np.zeros((g.n_pulses, 3))
    off[:, 1] = -shift / np.cos(g.depression_rad)  # move away horizontally: range grows ≈ shift
    d0 = np.abs(simulate_echoes(g, scene, None))
    d1 = np.abs(simulate_echoes(g, scene, off))
    mid = g.n_pulses // 2
    moved = (np.argmax(d1[mid]) - np.argmax(d0[mid])) * g.range_bin_m
    assert moved == pytest.approx(shift, abs=g.range_bin_m)  # the echo left its range cell


def test_sonar_medium_and_clutter():
    g = SarGeometry.from_scenario(get_preset("sas_100khz"))
    assert g.medium == "sonar" and g.wavelength_m == pytest.approx(0.015)
    scene = Scene.default(g, snr_db=60)
    img = form_image(g, simulate_echoes(g, scene, None, np.random.default_rng(3)))
    assert evaluate(measure_targets(img, g, scene)).passed
    # clutter level: mean pixel power over the scene ≈ CTR × the strongest target's peak power
    cl = Scene(clutter_to_target_db=-20.0)
    img_c = form_image(g, simulate_echoes(g, cl, None, np.random.default_rng(4)))
    inner = (np.abs(img_c.azimuth_m) < 0.35 * g.scene_extent_m[0])[:, None] & \
        (np.abs(img_c.range_offset_m) < 0.35 * g.scene_extent_m[1])[None, :]
    level = np.mean(np.abs(img_c.data[inner]) ** 2)
    assert 10 * np.log10(level) == pytest.approx(-20.0, abs=1.0)


def test_image_results_and_figures(ideal):
    g, scene, _, img = ideal
    s = img.to_dict()
    assert s["method"] == "rda" and s["peak"] == pytest.approx(1.0, abs=0.1)
    assert img.summary().startswith("rda image")
    assert img.to_frame().shape == img.data.shape
    cuts = irf_cuts(img, g, scene, 2)
    assert cuts["azimuth_db"].max() == pytest.approx(0.0, abs=0.05)
    assert len(image_figure(img).data) == 1 and len(irf_cuts_figure(img, g, scene, 2).data) == 4
