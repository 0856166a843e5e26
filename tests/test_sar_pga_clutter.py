"""PGA on scenes that look like real ones: many dominant scatterers over distributed clutter.

The test images are generated here, independently of budget.sar (no simulator, no PGA code): a
phase history on centred azimuth bins (aperture = 80 % of the band), a sinc range response,
point targets on distinct range lines, complex white Gaussian clutter band-limited to the same
2-D support, white receiver noise, and a smooth phase error multiplied onto the phase history
(image = DFT along azimuth of the phase history, the convention of budget.sar.image).

Theory for the bound (Jakowatz & Wahl, JOSA A 10(12), 1993): with lines of per-bin
signal-to-clutter ratio SCR_r the ML estimate of a common phase has a per-bin rms error
1/√(2 Σ SCR_r); for a point of peak power |a|² in a window of W samples over clutter of mean
pixel power c, SCR = |a|² E_irf / (W c) with E_irf = 1/0.8 samples (sinc of 80 % band).
"""

import numpy as np
import pytest

from budget.presets import get_preset
from budget.sar import SarGeometry, Scene
from budget.sar.pga import apply_phase_correction, pga

FRAC = 0.8  # aperture fraction of the azimuth band and range band fraction


def clutter_scene(n_az=384, n_r=128, n_targets=24, ctr_db=-25.0, snr_db=30.0, spread_db=15.0,
                  error_rms_rad=2.0, seed=0):
    """(defocused image, ideal image, aperture mask, injected error, amplitudes, clutter+noise power)."""
    rng = np.random.default_rng(seed)
    k = np.arange(n_az) - n_az // 2
    ap = np.abs(k) < FRAC * n_az / 2
    lines = rng.choice(np.arange(4, n_r - 4), n_targets, replace=False) + rng.uniform(-0.3, 0.3, n_targets)
    x = rng.uniform(0, n_az, n_targets)
    amp = 10 ** (-rng.uniform(0, spread_db, n_targets) / 20)
    amp[0] = 1.0
    amp = amp * np.exp(2j * np.pi * rng.uniform(size=n_targets))
    r = np.arange(n_r)
    hist = sum(a * (ap * np.exp(2j * np.pi * k * xi / n_az))[:, None] * np.sinc(FRAC * (r - ri))[None, :]
               for xi, ri, a in zip(x, lines, amp)) / ap.sum()
    image = np.fft.fft(np.fft.ifftshift(hist, axes=0), axis=0)
    band_r = np.fft.fftshift(np.abs(np.fft.fftfreq(n_r)) < FRAC / 2)
    spec = (rng.standard_normal((n_az, n_r)) + 1j * rng.standard_normal((n_az, n_r))) * ap[:, None] * band_r
    clutter = np.fft.fft(np.fft.ifftshift(np.fft.ifft(np.fft.ifftshift(spec, axes=1), axis=1), axes=0), axis=0)
    clutter *= np.sqrt(10 ** (ctr_db / 10) / np.mean(np.abs(clutter) ** 2))
    noise = (rng.standard_normal((n_az, n_r)) + 1j * rng.standard_normal((n_az, n_r))) * np.sqrt(0.5 * 10 ** (-snr_db / 10))
    ideal = image + clutter + noise
    u = np.where(ap, k / (FRAC * n_az / 2), 0.0)
    psi = 6 * u ** 2 + 3 * rng.uniform(-1, 1) * u ** 3 + 2 * np.sin(1.5 * np.pi * u + rng.uniform(-np.pi, np.pi))
    kk = k[ap]
    beyond = psi[ap] - np.polyval(np.polyfit(kk, psi[ap], 1), kk)
    psi = np.where(ap, psi * error_rms_rad / np.sqrt(np.mean(beyond ** 2)), 0.0)
    bad = np.fft.fft(np.fft.ifft(ideal, axis=0) * np.fft.ifftshift(np.exp(1j * psi))[:, None], axis=0)
    return bad, ideal, ap, psi, np.abs(amp), 10 ** (ctr_db / 10) + 10 ** (-snr_db / 10)


def residual_rad(out, ideal, ap):
    """rms over the aperture of the phase still on ``out`` relative to ``ideal`` (from their
    cross-spectrum summed over range), constant and linear terms removed."""
    cross = np.fft.fftshift((np.fft.ifft(out, axis=0) * np.conj(np.fft.ifft(ideal, axis=0))).sum(axis=1))
    ph = np.unwrap(np.angle(cross[ap]))
    k = np.arange(ph.size)
    ph = ph - np.polyval(np.polyfit(k, ph, 1), k)
    return float(np.sqrt(np.mean(ph ** 2)))


def ml_limit_rad(amp, clutter_power, window=8):
    """1/√(2 Σ SCR_r) for the targets whose SCR in a ``window``-sample window is ≥ 1."""
    scr = amp ** 2 * (1 / FRAC) / (window * clutter_power)
    return float(1 / np.sqrt(2 * scr[scr >= 1].sum()))


def test_apply_phase_correction_inverts_an_injected_error():
    bad, ideal, ap, psi, _, _ = clutter_scene(n_az=128, n_r=32, n_targets=4, seed=3)
    assert np.allclose(apply_phase_correction(bad, psi), ideal)
    assert residual_rad(bad, ideal, ap) == pytest.approx(2.0, rel=1e-6)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_pga_on_many_scatterers_over_minus_25_db_clutter(seed):
    """24 scatterers (15 dB amplitude spread) over −25 dB clutter, SNR 30 dB, 2 rad rms smooth
    error: the residual stays within 2.5× the ML limit of the scene (limit 0.038–0.053 rad for
    these seeds, so 0.095–0.13 rad). Measured 1.1–2.4× the limit over seeds 0–5 (seeds 0, 1, 2:
    1.7×, 2.2×, 1.1×); a first window of 1× instead of 3× the measured width gave 4.1× on seed 2
    (the blurred response's tails truncated). Seed 0 (weak targets) ends above a flat 0.1 rad;
    the bound is the theory-scaled one."""
    bad, ideal, ap, _, amp, c = clutter_scene(seed=seed)
    res = pga(bad)
    limit = ml_limit_rad(amp, c)
    assert res.usable_lines >= 5 and not res.failed
    resid = residual_rad(res.image, ideal, ap)
    assert resid < 2.5 * limit, (resid, limit, res.reason)
    # the returned image is the input with the returned estimate applied, whatever the outcome
    assert np.allclose(res.image, apply_phase_correction(bad, res.phase_error_rad))
    assert res.final_window >= 8 and res.predicted_noise_rad > 0


def test_pga_on_clutter_only_finds_no_usable_scatterers():
    bad, _, _, _, _, _ = clutter_scene(n_targets=0 + 1, ctr_db=20.0, seed=4)  # one target 20 dB under the clutter
    res = pga(bad)
    assert res.failed and res.usable_lines == 0 and not res.converged
    assert res.reason.startswith("no usable scatterers")
    assert np.array_equal(res.image, bad) and np.all(res.phase_error_rad == 0)
    assert res.to_dict()["failed"] is True


def test_realistic_scene_and_its_clutter_free_copy():
    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    a = Scene.realistic(g, rng=np.random.default_rng(5))
    b = Scene.realistic(g, rng=np.random.default_rng(5))
    assert a == b  # same seed → same scene
    f = a.to_frame()
    assert len(f) == round(g.scene_extent_m[1] / g.range_resolution_m / 3)  # one per 3 range cells
    gaps = np.diff(np.sort(f["range_m"].to_numpy()))
    assert gaps.min() >= 2 * g.range_resolution_m - 1e-9  # distinct range lines
    assert f["amplitude"].max() == 1.0 and f["amplitude"].min() >= 10 ** (-15 / 20)
    assert a.clutter_to_target_db == -25.0 and a.snr_db == 30.0
    clean = a.without_clutter()
    assert clean.targets == a.targets and clean.clutter_to_target_db is None and clean.snr_db is None
    with pytest.raises(Exception, match="n_scatterers"):
        Scene.realistic(g, rng=np.random.default_rng(5), n_scatterers=500)
    with pytest.raises(Exception, match="rng"):
        Scene.realistic(g, rng=5)


@pytest.mark.slow  # simulates the clutter echoes of the whole image (≈ 3–6 s)
def test_pga_on_the_simulated_realistic_scene():
    """Simulator end to end: Scene.realistic (20 scatterers, −25 dB clutter, SNR 30 dB) on
    airborne X-band with a smooth error of 1.6 rad rms beyond linear along the line of sight. The
    estimate matches the injected phase within 4× the ML limit of the scene (per-bin SCR of a
    target = |a|² · (n/n_ap) / (W c̄), n_ap of the n azimuth bins in the aperture, W = 8).
    Measured over five draws (seeds 2–6, 14–20 scatterers): 0.8–1.9× the limit (this draw 1.3×;
    before PGA's first window followed the lines' SCR: 1.2–3.9×, this draw 3.9×). The bound was
    set from those earlier draws with margin: it guards against regressions, it is not a theory
    result."""
    from budget.sar import form_image, los_offset_for_phase, phase_on_bins, residual_phase_rad, simulate_echoes
    from budget.sar.phase import normalised_time, residual_rms_rad, smooth_phase_error
    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    rng = np.random.default_rng(2)
    scene = Scene.realistic(g, rng=rng, n_scatterers=20)
    psi = smooth_phase_error(normalised_time(g), quadratic_rad=5.0, cubic_rad=2.0, sinusoid_rad=1.5,
                             sinusoid_cycles=1.2)
    off = los_offset_for_phase(g, psi)
    img = form_image(g, simulate_echoes(g, scene, off, rng))
    truth = phase_on_bins(img, g, residual_phase_rad(g, off))
    mask = img.aperture_mask()
    res = pga(img.data)
    amp = scene.to_frame()["amplitude"].to_numpy()
    c = 10 ** (scene.clutter_to_target_db / 10) + 10 ** (-scene.snr_db / 10)
    scr = amp ** 2 * (mask.size / mask.sum()) / (8 * c)
    limit = 1 / np.sqrt(2 * scr[scr >= 1].sum())
    resid = residual_rms_rad(res.phase_error_rad, truth, mask)
    assert res.usable_lines >= 5 and resid < 4.0 * limit, (resid, limit, res.reason)
    clean = Scene.realistic(g, rng=np.random.default_rng(2), n_scatterers=20).without_clutter()
    assert clean.targets == scene.targets


def _beyond_window_rms(estimate, truth, ap, res):
    """rms (rad) over the aperture bins of (estimate − truth) beyond the bandwidth K of PGA's
    settled window (budget.sar.residual: Legendre ≤ 3 and DCT ≤ 2K removed, unweighted)."""
    from budget.sar.residual import highpass_phase, pga_bandwidth_cycles
    k_cycles = pga_bandwidth_cycles(res.final_window, ap.size, int(ap.sum()))
    r = highpass_phase(estimate[ap] - truth[ap], k_cycles)
    return float(np.sqrt(np.mean(r ** 2))), k_cycles


@pytest.mark.parametrize("seed,ctr_db", [(0, -20.0), (1, -25.0), (2, -35.0)])
def test_no_error_on_clutter_adds_nothing_beyond_the_settled_window(seed, ctr_db):
    """Focused scene (24 scatterers over clutter, SNR 30 dB, NO phase error): whatever PGA adds
    beyond its settled window stays far below the noise an unconstrained estimator would leave
    there — the per-bin ML noise 1/√(2 Σ SCR_r) (``predicted_noise_rad``) times √(fraction of the
    aperture's degrees of freedom beyond K) — and below 1° (the Monte Carlo's residual limit).
    The former whole-line start left 2.5–12° here on the simulated scenes (wide windows at
    per-bin SCR < 1: a random walk)."""
    from budget.sar.residual import _removable_projector
    bad, _, ap, psi, _, _ = clutter_scene(ctr_db=ctr_db, error_rms_rad=0.0, seed=seed)
    assert np.all(psi == 0)
    res = pga(bad)
    assert res.converged and not res.failed, res.reason
    resid, k_cycles = _beyond_window_rms(res.phase_error_rad, np.zeros(ap.size), ap, res)
    n_ap = int(ap.sum())
    h = _removable_projector(n_ap, int(np.floor(2 * k_cycles)))
    unconstrained = res.predicted_noise_rad * np.sqrt(np.trace(h) / n_ap)
    assert resid < 0.25 * unconstrained and resid < np.radians(1.0), (resid, unconstrained, res.fast_bands)


def test_fast_sinusoid_on_clean_points_is_still_removed():
    """Clean points (clutter −80 dB, SNR 60 dB) with a 0.3 rad sinusoid of 6 cycles per aperture,
    beyond the settled window's bandwidth (K ≈ 3.2 cycles): the fast-phase stage finds it
    significant and removes ≥ 80 % of its rms; without the stage it stays (≥ 80 % left)."""
    _, ideal, ap, _, _, _ = clutter_scene(n_targets=12, ctr_db=-80.0, snr_db=60.0, error_rms_rad=0.0, seed=6)
    k = np.arange(ap.size) - ap.size // 2
    u = np.where(ap, k / (FRAC * ap.size / 2), 0.0)
    psi = np.where(ap, 0.3 * np.sin(np.pi * 6.0 * u + 0.4), 0.0)
    bad = np.fft.fft(np.fft.ifft(ideal, axis=0) * np.fft.ifftshift(np.exp(1j * psi))[:, None], axis=0)
    res = pga(bad)
    assert res.converged, res.reason
    injected, k_cycles = _beyond_window_rms(np.zeros(ap.size), psi, ap, res)
    assert k_cycles < 4.0 and injected > 0.15
    left, _ = _beyond_window_rms(res.phase_error_rad, psi, ap, res)
    assert left < 0.2 * injected, (left, injected, res.fast_bands)
    assert any(b["gain"] > 0 for b in res.fast_bands)
    assert len(res.to_dict()["fast_bands"]) == len(res.fast_bands) and res.to_dict()["fast_bands_kept"] >= 1
    off = pga(bad, fast_phase=False)
    assert _beyond_window_rms(off.phase_error_rad, psi, ap, off)[0] > 0.8 * injected


def test_first_window_follows_the_lines_scr():
    """"auto" start: the whole line (shrunk to n/2 on the first iteration) on a noise-free scene,
    a measured window on a cluttered one, where a half-line window has per-bin SCR < 1."""
    bad, _, _, _, _, _ = clutter_scene(ctr_db=-25.0, seed=1)
    clean, _, _, _, _, _ = clutter_scene(ctr_db=-80.0, snr_db=80.0, seed=1)
    n = bad.shape[0]
    assert pga(clean).history[0]["window"] == n // 2
    assert pga(bad).history[0]["window"] < n // 4
    assert pga(bad, first_window="full").history[0]["window"] == n // 2
    with pytest.raises(Exception, match="first_window"):
        pga(bad, first_window="wide")


def test_start_window_is_reported_and_the_capture_check_runs_only_after_a_clutter_limited_start():
    """``start_window``: the whole line on a noise-free scene (no capture check), narrower on
    clutter; the check runs there only with fewer usable lines than ``min_lines``, and
    ``restarts=False`` leaves it out."""
    clean, _, _, _, _, _ = clutter_scene(ctr_db=-80.0, snr_db=80.0, n_targets=4, seed=1)
    r = pga(clean)
    assert r.start_window == clean.shape[0] and r.restarts == []
    many, _, _, _, _, _ = clutter_scene(ctr_db=-25.0, n_targets=24, seed=1)
    r = pga(many)
    assert r.start_window < many.shape[0] and r.usable_lines >= 8 and r.restarts == []
    few, _, _, _, _, _ = clutter_scene(ctr_db=-25.0, n_targets=3, seed=1)
    single = pga(few, restarts=False)
    assert single.start_window < few.shape[0] and 0 < single.usable_lines < 8 and single.restarts == []
    assert "capture check" not in single.reason


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_capture_check_keeps_the_sharpest_run_and_says_so(seed):
    """The check lists every run (the first, a measured start, a slower shrink), keeps exactly one —
    the one whose corrected image is sharpest (Σ|g|⁴/(Σ|g|²)², computed here independently) — and
    says so in the reason and in ``to_dict``; when it keeps the first run the estimate is the
    single run's. (The second pass, which may follow the check, is left out: its own tests are in
    ``test_pga_second_pass.py``.)"""
    few, _, _, _, _, _ = clutter_scene(ctr_db=-25.0, n_targets=4, error_rms_rad=3.0, seed=seed)
    r, single = pga(few, second_pass_above_rad=None), pga(few, restarts=False)
    assert [row["start"] for row in r.restarts] == ["clutter-limited start", "measured start",
                                                     "slower shrink (0.7)"]
    kept = [row for row in r.restarts if row["kept"]]
    assert len(kept) == 1
    p = np.abs(r.image) ** 2
    assert kept[0]["sharpness"] == pytest.approx(np.sum(p * p) / np.sum(p) ** 2, rel=1e-9)
    assert kept[0]["sharpness"] == max(row["sharpness"] for row in r.restarts)
    assert r.restarts[0]["sharpness"] == pytest.approx(
        np.sum(np.abs(single.image) ** 4) / np.sum(np.abs(single.image) ** 2) ** 2, rel=1e-9)
    assert f"the {kept[0]['start']}" in r.reason and "capture check" in r.reason
    assert r.to_dict()["restarts"][0]["start"] == "clutter-limited start"
    if r.restarts[0]["kept"]:
        assert np.array_equal(r.phase_error_rad, single.phase_error_rad)


def test_capture_check_recovers_runs_that_settle_elsewhere_on_few_scatterers():
    """Few scatterers (5 or 8) over −25 dB clutter with a 3 rad rms smooth error, 12 draws each: a
    single run from the clutter-limited start sometimes settles on a wrong solution (residual
    > 0.5 rad: a defocused image); with the capture check fewer do, and the typical residual stays
    at the clutter-limited level (median ≤ 0.15 rad)."""
    single, checked = [], []
    for n_targets in (5, 8):
        for seed in range(12):
            bad, ideal, ap, _, _, _ = clutter_scene(ctr_db=-25.0, n_targets=n_targets, error_rms_rad=3.0, seed=seed)
            single.append(residual_rad(pga(bad, restarts=False).image, ideal, ap))
            checked.append(residual_rad(pga(bad).image, ideal, ap))
    single, checked = np.array(single), np.array(checked)
    assert np.sum(checked > 0.5) < np.sum(single > 0.5)
    assert np.median(checked) <= 0.15
