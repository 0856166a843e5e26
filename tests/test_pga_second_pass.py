"""PGA's second pass after a large correction (``budget.sar.pga``, module docstring "Second pass").

The images come from this suite's own clutter generator (``test_sar_pga_clutter.clutter_scene``:
point scatterers over band-limited complex Gaussian clutter and receiver noise, a smooth error
multiplied onto the phase history), not from the simulator, and the residual is measured against
the error-free image (``residual_rad``), not against PGA's own estimate.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from budget.errors import InputError
from budget.sar.pga import SECOND_PASS_ABOVE_RAD, correction_rms_rad, pga
from budget.sar.sharpness import image_sharpness

from test_sar_pga_clutter import clutter_scene, residual_rad


def test_after_a_large_correction_the_second_pass_leaves_less_and_never_more():
    """24 scatterers over −25 dB clutter, SNR 30 dB, 6 and 10 rad rms of smooth error, seeds 0–7:
    the pass runs on every image, and against the error-free image it leaves less on most
    (measured 10 of 16 by more than 1 mrad) and more on at most one (measured none)."""
    better = worse = 0
    for error in (6.0, 10.0):
        for seed in range(8):
            bad, ideal, ap, _, _, _ = clutter_scene(ctr_db=-25.0, n_targets=24, error_rms_rad=error, seed=seed)
            one, two = pga(bad, second_pass_above_rad=None), pga(bad)
            assert two.second_pass and two.second_pass["correction_rms_rad"] > SECOND_PASS_ABOVE_RAD
            r1, r2 = residual_rad(one.image, ideal, ap), residual_rad(two.image, ideal, ap)
            better += r2 < r1 - 1e-3
            worse += r2 > r1 + 1e-3
    assert better >= 8, (better, worse)
    assert worse <= 1, (better, worse)


@pytest.mark.parametrize("seed", [0, 1])
def test_the_pass_is_kept_only_when_the_image_is_sharper_and_says_so(seed):
    """The record, the reason and the estimate agree: kept → the estimate is the first pass's plus
    the second's and the returned image is the sharper one (sharpness computed here); not kept →
    the single pass's estimate, unchanged."""
    bad, _, _, _, _, _ = clutter_scene(ctr_db=-25.0, n_targets=24, error_rms_rad=10.0, seed=seed)
    one, two = pga(bad, second_pass_above_rad=None), pga(bad)
    rec = two.second_pass
    assert rec["correction_rms_rad"] == pytest.approx(correction_rms_rad(one), rel=1e-12)
    assert rec["above_rad"] == SECOND_PASS_ABOVE_RAD
    assert "second pass after a correction of" in two.reason
    assert rec["sharpness_before"] == pytest.approx(image_sharpness(one.image), rel=1e-9)
    if rec["kept"]:
        assert rec["sharpness_after"] > rec["sharpness_before"]
        assert image_sharpness(two.image) == pytest.approx(rec["sharpness_after"], rel=1e-9)
        assert two.iterations == one.iterations + rec["iterations"]
        assert "kept: the image is sharper" in two.reason
    else:
        assert np.array_equal(two.phase_error_rad, one.phase_error_rad)
        assert "not kept" in two.reason
    d = two.to_dict()
    assert d["second_pass"]["correction_rms_rad"] == pytest.approx(rec["correction_rms_rad"])
    json.dumps(d)  # JSON-safe


def test_no_second_pass_after_a_small_correction_on_a_clean_image_or_when_asked_not_to():
    """It does not run after a correction below the threshold (1 rad rms of error), on a clean
    image (the first window is the whole line: no window schedule to outrun), with
    ``restarts=False`` (one run) or with ``second_pass_above_rad=None``; there the result is the
    single pass's, bit for bit."""
    small, _, _, _, _, _ = clutter_scene(ctr_db=-25.0, n_targets=24, error_rms_rad=1.0, seed=0)
    r_small = pga(small)
    assert correction_rms_rad(r_small) < SECOND_PASS_ABOVE_RAD and r_small.second_pass == {}
    assert "second pass" not in r_small.reason
    clean, _, _, _, _, _ = clutter_scene(ctr_db=-80.0, snr_db=80.0, n_targets=8, error_rms_rad=10.0, seed=0)
    r = pga(clean)
    assert r.start_window == clean.shape[0] and correction_rms_rad(r) > SECOND_PASS_ABOVE_RAD
    assert r.second_pass == {}
    big, _, _, _, _, _ = clutter_scene(ctr_db=-25.0, n_targets=24, error_rms_rad=10.0, seed=0)
    off = pga(big, second_pass_above_rad=None)
    assert off.second_pass == {} and pga(big, restarts=False).second_pass == {}
    assert np.array_equal(r_small.phase_error_rad, pga(small, second_pass_above_rad=None).phase_error_rad)


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), float("inf"), "pi", True])
def test_a_bad_threshold_is_refused_naming_the_field(bad):
    img, _, _, _, _, _ = clutter_scene(n_az=128, n_r=32, n_targets=4, seed=3)
    with pytest.raises(InputError) as err:
        pga(img, second_pass_above_rad=bad)
    assert err.value.field == "second_pass_above_rad" and "positive" in str(err.value)


def test_after_the_capture_check_the_pass_reuses_its_image_and_gives_the_same_result(monkeypatch):
    """Four scatterers (fewer usable lines than ``min_lines``: the capture check runs) and 8 rad rms:
    both the capture check and the second pass run. The pass starts from the capture check's
    corrected image and phase history instead of forming them again; the estimate and the image
    are bit-identical to a pass that forms its own."""
    import importlib
    passes = importlib.import_module("budget.sar.pga_passes")
    pga_module = importlib.import_module("budget.sar.pga")
    bad, _, _, _, _, _ = clutter_scene(ctr_db=-25.0, n_targets=4, error_rms_rad=8.0, seed=0)
    shared = pga(bad)
    assert shared.restarts and shared.second_pass, "the case must run both"
    own = passes._second_pass
    monkeypatch.setattr(pga_module, "_second_pass",
                        lambda g, first, size, above, again, g1=None, hist=None: own(g, first, size, above, again))
    formed = pga(bad)
    assert formed.second_pass == shared.second_pass
    assert np.array_equal(formed.phase_error_rad, shared.phase_error_rad)
    assert np.array_equal(formed.image, shared.image)
