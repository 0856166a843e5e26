"""Phase gradient autofocus: what it fixes, what it cannot fix, and how it says so."""

import numpy as np
import pytest

from budget.errors import InputError
from budget.plots.sar import phase_error_figure
from budget.presets import get_preset
from budget.sar import (PointTarget, SarGeometry, Scene, evaluate, form_image, los_offset_for_phase,
                        measure_targets, pga, phase_on_bins, residual_phase_rad, residual_rms_rad,
                        simulate_echoes, smooth_phase_error)
from budget.sar.pga import apply_phase_correction
from budget.sar.phase import normalised_time


@pytest.fixture(scope="module")
def defocused():
    """Default scene, smooth error of several radians (6 u² + 3 u³ + 2 sin(1.5πu)) along the LOS."""
    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    scene = Scene.default(g)
    psi = smooth_phase_error(normalised_time(g), quadratic_rad=6.0, cubic_rad=3.0, sinusoid_rad=2.0,
                             sinusoid_cycles=1.5)
    off = los_offset_for_phase(g, psi)
    img = form_image(g, simulate_echoes(g, scene, off, np.random.default_rng(7)))
    truth = phase_on_bins(img, g, residual_phase_rad(g, off))
    return g, scene, img, truth


@pytest.mark.parametrize("kernel", ["ml", "lumv"])
def test_pga_removes_a_smooth_phase_error(defocused, kernel):
    g, scene, img, truth = defocused
    before = measure_targets(img, g, scene)
    assert not evaluate(before).passed and before.to_frame()["azimuth_broadening"].min() > 0.3
    res = pga(img.data, kernel=kernel)
    assert res.converged, res.reason
    assert res.usable_lines >= 5
    mask = img.aperture_mask() & res.estimated_bins
    assert mask.sum() > 0.9 * img.aperture_mask().sum()
    assert residual_rms_rad(res.phase_error_rad, truth, mask) < 0.05
    after = measure_targets(img.with_data(res.image), g, scene)
    f = after.to_frame()
    assert np.all(np.abs(f["azimuth_broadening"]) < 0.02) and np.all(np.abs(f["range_broadening"]) < 0.02)
    assert np.all(f["peak_loss_db"] < 0.2)
    assert evaluate(after).passed
    assert res.to_dict()["converged"] and len(res.to_frame()) == img.data.shape[0]
    assert len(phase_error_figure(res, img, truth).data) == 3


@pytest.mark.slow  # simulates clutter echoes (≈ 5 s)
def test_pga_works_among_moderate_clutter():
    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    scene = Scene.default(g).model_copy(update={"clutter_to_target_db": -40.0})
    psi = smooth_phase_error(normalised_time(g), quadratic_rad=5.0, cubic_rad=2.0)
    off = los_offset_for_phase(g, psi)
    img = form_image(g, simulate_echoes(g, scene, off, np.random.default_rng(8)))
    res = pga(img.data)
    assert res.converged, res.reason
    truth = phase_on_bins(img, g, residual_phase_rad(g, off))
    assert residual_rms_rad(res.phase_error_rad, truth, img.aperture_mask() & res.estimated_bins) < 0.1
    # clutter fills every line, so judge sidelobes over ±10 cells rather than the whole line
    f = measure_targets(img.with_data(res.image), g, scene, islr_extent_cells=10).to_frame()
    assert np.all(np.abs(f["azimuth_broadening"]) < 0.05)


def test_pga_does_not_fix_range_migration():
    """A line-of-sight drift of 3 range cells over the aperture smears targets across range cells:
    an azimuth phase correction cannot gather them back."""
    g = SarGeometry.from_scenario(get_preset("airborne_xband"), oversample=2.0)  # keep the drift's Doppler unaliased
    scene = Scene.default(g)
    u = normalised_time(g)
    drift_m = 3.0 * g.range_cell_m * (0.5 * u + 0.5 * u ** 2)  # 3 cells end to end, partly quadratic
    psi = -4 * np.pi * drift_m / g.wavelength_m
    img = form_image(g, simulate_echoes(g, scene, los_offset_for_phase(g, psi), np.random.default_rng(9)))
    res = pga(img.data)
    after = measure_targets(img.with_data(res.image), g, scene)
    f = after.to_frame()
    assert not evaluate(after).passed
    assert f["range_broadening"].max() > 0.3 or f["peak_loss_db"].min() > 3.0


@pytest.mark.slow  # simulates clutter echoes (≈ 5 s); a fast phase-history version is in test_sar_pga_clutter.py
def test_pga_fails_gracefully_on_clutter_only():
    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    scene = Scene(clutter_to_target_db=0.0, snr_db=40.0)
    psi = smooth_phase_error(normalised_time(g), quadratic_rad=6.0)
    img = form_image(g, simulate_echoes(g, scene, los_offset_for_phase(g, psi), np.random.default_rng(10)))
    res = pga(img.data)
    assert not res.converged and res.usable_lines == 0
    assert res.reason.startswith("no usable scatterers")
    assert np.array_equal(res.image, img.data)  # the input back, not a wrong image
    assert np.all(res.phase_error_rad == 0)


def test_pga_reports_non_convergence_and_still_applies_its_estimate(defocused):
    """Two iterations cannot settle the window: the flag and the reason say so, and the image is
    the input corrected with the estimate so far (closer to the truth than the input)."""
    _, _, img, truth = defocused
    res = pga(img.data, max_iter=2)
    assert not res.converged and res.reason.startswith("did not converge") and res.iterations == 2
    assert res.usable_lines > 0 and not res.failed
    assert np.allclose(res.image, apply_phase_correction(img.data, res.phase_error_rad))
    mask = img.aperture_mask()
    assert residual_rms_rad(res.phase_error_rad, truth, mask) < 0.5 * residual_rms_rad(0 * truth, truth, mask)
    d = res.to_dict()
    assert d["converged"] is False and d["final_window"] == res.final_window and len(d["history"]) == 2


def test_pga_on_a_focused_image_changes_nothing():
    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    scene = Scene(targets=[PointTarget(azimuth_m=0.0, range_m=0.0), PointTarget(azimuth_m=5.0, range_m=6.0)])
    img = form_image(g, simulate_echoes(g, scene, None))
    res = pga(img.data, kernel="lumv")
    assert res.converged
    mask = img.aperture_mask() & res.estimated_bins
    assert residual_rms_rad(res.phase_error_rad, np.zeros_like(res.phase_error_rad), mask) < 0.03


def test_pga_bad_input():
    good = np.ones((64, 8), complex)
    bad = good.copy()
    bad[3, 3] = np.nan
    with pytest.raises(InputError, match="NaN"):
        pga(bad)
    with pytest.raises(InputError, match="kernel"):
        pga(good, kernel="eigen")
    with pytest.raises(InputError):
        pga(np.ones(64))
    with pytest.raises(InputError):
        pga(good, max_iter=0)


def test_pga_without_the_corrected_image_gives_the_same_estimate(defocused):
    """corrected_image=False skips only the final correction: same estimate, input image returned,
    and applying the estimate reproduces the corrected image."""
    _, _, img, _ = defocused
    full, lean = pga(img.data), pga(img.data, corrected_image=False)
    np.testing.assert_array_equal(full.phase_error_rad, lean.phase_error_rad)
    assert lean.image is img.data or np.array_equal(lean.image, img.data)
    np.testing.assert_allclose(apply_phase_correction(img.data, lean.phase_error_rad), full.image, atol=1e-12)


def test_phase_on_bins_holds_the_track_ends_outside_the_band_when_asked(defocused):
    """On the aperture band the held phase is the band's (NaN outside by default); beyond it, ψ
    at the track's nearer end (the bins there hold the band's edge pulses' leakage, so a
    correction must carry their phase, not zero); an unknown choice is refused by name."""
    g, _, img, truth = defocused
    psi = residual_phase_rad(g, los_offset_for_phase(g, smooth_phase_error(
        normalised_time(g), quadratic_rad=6.0, cubic_rad=3.0, sinusoid_rad=2.0, sinusoid_cycles=1.5)))
    held = phase_on_bins(img, g, psi, outside="hold")
    band = img.aperture_mask()
    assert np.isnan(truth[~band]).all() and np.isfinite(held).all()
    np.testing.assert_array_equal(held[band], truth[band])
    t = img.slow_time_of_bins_s()
    assert np.all(held[~band & (t < 0)] == psi[0]) and np.all(held[~band & (t > 0)] == psi[-1])
    with pytest.raises(InputError, match="outside"):
        phase_on_bins(img, g, psi, outside="zero")
