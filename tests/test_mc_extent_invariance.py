"""The Monte Carlo verdict judges the IMU, not the simulated scene's size.

``SarGeometry.from_scenario``'s ``scene_extent_cells`` (the simulated scene's width in resolution
cells) sets the image's azimuth samples and the PRF, a simulation choice the user never makes.
On ``automotive_77ghz`` (lever arm 0, points scene) a gyro bias at 0.2× its paper bound gave
P(pass) 0.84 at 48 cells, 0.16 at 80 and 0.28 at 96, 0.84 again at 112–192 (32 trials, seed 1):
the noise-free image's phase history holds an isolated spectral line outside the aperture band
whose level (−29 to −34 dB at 80–128 cells, by image size and PRF) crossed PGA's 30 dB "bins with
signal" level at 80–96 cells, and the fast-phase stage's cut-back then fitted its basis over bins
up to 42 beyond the aperture band, leaving 27–32° at the aperture's ends. The stage now counts a
bin as signal only when it is joined to the peak by bins at most 10 dB below that level
(:func:`budget.sar.pga_fast._joined_to_peak`).

Accel VRW at 0.05× passed 0.50 / 0.09 / 0.03 at 48 / 96 / 192 cells: PGA's smallest window was 8
samples, so its bandwidth K = W·n_ap/(2n) fell from 2.05 to 1.47 cycles per aperture as the image
was sampled more finely. The chain now gives PGA a floor of 4 resolution cells (K = 2;
:func:`budget.mc.chain.pga_min_window`): 0.50 / 0.56 / 0.62.

The VRW case then still read 17/32 at 48 cells against 24/32 at 96, and over 256 trials 0.62 to
0.87 across eight image lengths. Not the image: with the exact phase correction the image is the
same at 48 and 96 cells (tested below). Not PGA's iterations: with the fast-phase stage off, PGA's
result is the same at both (tested below). It was the stage's handover: the cut-back keeps the
estimate up to K over the aperture, the bands were re-estimated above ⌊W·span/n⌋ over the 10 dB
span, a shorter interval, and what the cut-back took had a part below that index over the span
that no band gave back (0.2–0.5° at 1–4 cycles per aperture, enough to lift a −35 dB sidelobe to
the PSLR limit). A handover band now estimates that part (docs/monte-carlo.md, "The verdict and
the simulated scene's size", 4).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import budget.mc.chain as chain
from budget.mc.chain import (PGA_MIN_WINDOW_CELLS, ChainSetup, chain_plan, pga_min_window, run_chunk, run_trials,
                             settled_window)
from budget.mc.consistency import single_term_model
from budget.mc.options import McOptions
from budget.mc.runner import resolve_unspecified
from budget.mc.stats import wilson_interval
from budget.motion import simulate_motion
from budget.presets import PRESETS
from budget.sar import SarGeometry, phase_on_bins, residual_phase_rad
from budget.sar.acceptance import failed_checks
from budget.sar.pga import DEFAULT_MIN_WINDOW, PgaResult
from budget.sar.pga_fast import _BAND_GAP_DB, _joined_to_peak
from budget.sar.residual import pga_bandwidth_cycles

TRIALS = 32
SEED = 1


def _single_term(monkeypatch, extent_cells: float, scale: float, term: str):
    """(scenario, resolved model, setup) of the single-term model ``term`` at ``scale`` × its
    paper bound on automotive_77ghz with lever arm 0, points scene, the simulated scene
    ``extent_cells`` wide."""
    original = SarGeometry.from_scenario.__func__

    def sized(cls, scenario, **kw):
        kw.setdefault("scene_extent_cells", extent_cells)
        return original(cls, scenario, **kw)

    monkeypatch.setattr(SarGeometry, "from_scenario", classmethod(sized))
    scen = PRESETS["automotive_77ghz"].model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0)})
    model = resolve_unspecified(single_term_model(scen, term, scale), "zero").model
    setup = ChainSetup.build(scen, McOptions(scene="points", unspecified="zero"))
    assert setup.geom.scene_extent_m[0] == pytest.approx(extent_cells * scen.azimuth_resolution_m)
    return scen, model, setup


def _p_pass(monkeypatch, extent_cells: float, scale: float, term: str = "gyro_bias") -> tuple[int, int]:
    """(passes, trials) of :func:`_single_term`."""
    _, model, setup = _single_term(monkeypatch, extent_cells, scale, term)
    out = run_chunk(setup, model, SEED, 0, TRIALS)
    return sum(o.passed_after for o in out), len(out)


def test_gyro_bias_verdict_does_not_depend_on_scene_extent(monkeypatch):
    """P(pass) at 0.2× the bound is the same, within each other's 95 % Wilson intervals, on a
    48-cell scene (the default; no zero-padding, 189 azimuth samples) and a 96-cell one (242
    pulses padded to 320 samples, where the verdict was 0.28 against 0.84)."""
    counts = {ext: _p_pass(monkeypatch, ext, 0.2) for ext in (48.0, 96.0)}
    (k1, n1), (k2, n2) = counts[48.0], counts[96.0]
    lo1, hi1 = wilson_interval(k1, n1)
    lo2, hi2 = wilson_interval(k2, n2)
    assert lo2 <= k1 / n1 <= hi2, counts
    assert lo1 <= k2 / n2 <= hi1, counts


def test_vrw_verdict_does_not_depend_on_scene_extent(monkeypatch):
    """Accel VRW at 0.05× the bound (fast phase: what PGA's window sees decides): P(pass) on 48 and
    96-cell scenes within each other's 95 % Wilson intervals (0.50 against 0.09 with a floor of 8
    samples; 17/32 against 24/32 with the floor of 4 cells while the fast-phase stage's first band
    began above the cut-back's K over the span, leaving a gap of 0.2–0.5° at 1–4 cycles per
    aperture that moved with the image's length; 25/32 against 24/32 with the handover band,
    :func:`budget.sar.pga_fast._fast_bands`)."""
    counts = {ext: _p_pass(monkeypatch, ext, 0.05, "accel_vrw") for ext in (48.0, 96.0)}
    (k1, n1), (k2, n2) = counts[48.0], counts[96.0]
    lo1, hi1 = wilson_interval(k1, n1)
    lo2, hi2 = wilson_interval(k2, n2)
    assert lo2 <= k1 / n1 <= hi2, counts
    assert lo1 <= k2 / n2 <= hi1, counts


@pytest.mark.slow
@pytest.mark.xfail(strict=False, reason=(
    "over 256 trials the 48 and 96-cell images still differ beyond their intervals: 221/256 = "
    "0.86 [0.82, 0.90] against 198/256 = 0.77 [0.72, 0.82] with the handover band (before it 158 "
    "against 195: 0.62 against 0.76); at other lengths 0.85–0.93 (n_ap 111, 133, 173, 163, 227; "
    "the 64-cell image, 97 bins as the 48-cell one, 0.90). On the 96-cell image PGA's error at DCT "
    "index ≤ 3 of the span is 0.75° rms against 0.43° at 48 cells (64 trials) after the handover band, whose "
    "Wiener gain is 0.99 at both; where that comes from is not found (docs/monte-carlo.md, 4)"))
def test_vrw_verdict_does_not_depend_on_scene_extent_over_256_trials(monkeypatch):
    """The same as :func:`test_vrw_verdict_does_not_depend_on_scene_extent` over 256 trials, where
    the Wilson intervals (±0.05) are narrower than the sampling dependence that 32 trials hide."""
    counts = {}
    for ext in (48.0, 96.0):
        _, model, setup = _single_term(monkeypatch, ext, 0.05, "accel_vrw")
        out = run_chunk(setup, model, SEED, 0, 256)
        counts[ext] = (sum(o.passed_after for o in out), len(out))
    (k1, n1), (k2, n2) = counts[48.0], counts[96.0]
    lo1, hi1 = wilson_interval(k1, n1)
    lo2, hi2 = wilson_interval(k2, n2)
    assert lo2 <= k1 / n1 <= hi2, counts
    assert lo1 <= k2 / n2 <= hi1, counts


def _vrw_images(monkeypatch, extent_cells: float):
    """(setup, plan, clean images and their phase histories (B, n_a, n_r), true phase on every bin
    (B, n_a)) of the accel VRW at 0.05× on ``extent_cells`` (:func:`_single_term`), the truth read
    at each bin's slow time and held at the track's ends beyond the aperture band."""
    scen, model, setup = _single_term(monkeypatch, extent_cells, 0.05, "accel_vrw")
    g, plan = setup.geom, chain_plan(setup)
    motion = simulate_motion(scen, model, TRIALS, SEED, first_trial=0, keep_series="position")
    errors = np.stack([chain._to_pulses(motion.time_s, motion.position_error_m[k], g.pulse_times_s)
                       for k in range(TRIALS)])
    measured = -g.imaging_frame(errors)
    clean, _ = plan.form(setup, measured, range(TRIALS), SEED, 0)
    hist = plan.clean_products(clean).hist
    truth = np.stack([phase_on_bins(plan.template, g, residual_phase_rad(g, None, m), outside="hold")
                      for m in measured])
    return setup, plan, clean, hist, truth


def _worst_pslr(plan, hist, phase):
    """Worst target's PSLR (dB) of each image after the correction ``phase`` (B, n_a; centred bins)."""
    corrected = hist * np.exp(-1j * np.fft.ifftshift(phase, axes=1))[:, :, None]
    m = plan.meter.measure(np.fft.fft(corrected, axis=1))
    return np.maximum(m["azimuth_pslr_db"], m["range_pslr_db"]).max(axis=1), m


def test_vrw_images_corrected_with_the_true_phase_are_the_same_at_48_and_96_cells(monkeypatch):
    """The simulated image is not what makes the VRW verdict depend on the extent: corrected with
    the exact phase (read at each bin's slow time, held at the aperture band's edges, where the
    band's edge pulses still leave some energy), the worst target's PSLR has the same median at
    48 and 96 cells within 0.3 dB (measured −34.78 / −34.60 dB; with no motion error −35.14 /
    −34.75) and every trial meets the acceptance. Applied with zero outside the band, as an
    earlier oracle did, the 48-cell images read worse than with the held phase (−34.09 against
    −34.78 dB: the band's edge energy keeps its error there)."""
    medians = {}
    for ext in (48.0, 96.0):
        setup, plan, _, hist, truth = _vrw_images(monkeypatch, ext)
        worst, m = _worst_pslr(plan, hist, truth)
        assert not any(v.any() for v in failed_checks(m, setup.options.acceptance).values())
        medians[ext] = float(np.median(worst))
        if ext == 48.0:
            zeroed, _ = _worst_pslr(plan, hist, np.where(plan.mask, truth, 0.0))
            assert np.median(zeroed) > medians[ext] + 0.2
    assert abs(medians[48.0] - medians[96.0]) < 0.3, medians


def test_pga_without_its_fast_phase_stage_reads_the_same_at_48_and_96_cells(monkeypatch):
    """PGA's iterations alone (fast-phase stage off) leave the VRW images at 0.05× with the same
    worst-target PSLR at 48 and 96 cells (medians within 0.3 dB; measured −27.80 / −27.88 dB over
    these 32 trials, −28.17 / −28.29 over 128 through the chain, where all but one fail on the
    residual): the extent dependence of the expected
    failure above enters with the fast-phase stage."""
    medians = {}
    for ext in (48.0, 96.0):
        setup, plan, clean, hist, _ = _vrw_images(monkeypatch, ext)
        mask = plan.mask
        kw = {**chain._pga_kwargs(setup.options, pga_min_window(mask.size, int(mask.sum()))),
              "aperture_bins": mask, "fast_phase": False}
        estimates = []
        for b in range(TRIALS):
            res = chain.pga(clean[b], **kw)
            assert res.usable_lines > 0 and res.converged
            estimates.append(np.asarray(res.phase_error_rad, float))
        worst, _ = _worst_pslr(plan, hist, np.array(estimates))
        medians[ext] = float(np.median(worst))
    assert abs(medians[48.0] - medians[96.0]) < 0.3, medians


def test_pga_min_window_is_four_cells():
    """n/n_ap samples per resolution cell: 4 cells (K = 2 cycles per aperture), rounded up."""
    assert PGA_MIN_WINDOW_CELLS == 4.0
    assert pga_min_window(189, 97) == 8  # automotive_77ghz default: 7.8
    assert pga_min_window(462, 313) == 6  # airborne_xband default: 5.9
    assert pga_min_window(320, 129) == 10  # 96-cell scene: 9.9
    assert pga_min_window(847, 227) == 15  # 192-cell scene: 14.9
    assert pga_min_window(400, 200) == 8  # exactly 8 samples
    assert pga_min_window(10, 40) == 3  # PGA's smallest (1 sample of 4 cells)
    for n, n_ap in ((189, 97), (462, 313), (320, 129), (847, 227)):
        w = pga_min_window(n, n_ap)
        assert pga_bandwidth_cycles(w, n, n_ap) >= 2.0 > pga_bandwidth_cycles(w - 1, n, n_ap)


def test_settled_window_falls_back_to_the_chain_floor():
    """A result that reports no window (a zero image: PGA never iterated) is read at the floor the
    chain gave PGA, not at PGA's own 8 samples; a reported window is read as it is."""
    none = PgaResult(image=np.zeros((16, 1), complex), phase_error_rad=np.zeros(16), iterations=0,
                     converged=False, reason="no usable scatterers: the image is zero", usable_lines=0)
    assert settled_window(none, 6) == 6 != DEFAULT_MIN_WINDOW
    assert settled_window(none, 10) == 10
    assert settled_window(replace(none, history=[{"window": 24}, {"window": 12}]), 6) == 12
    assert settled_window(replace(none, final_window=9, history=[{"window": 12}]), 6) == 9


def test_chain_reads_a_windowless_result_at_its_floor(monkeypatch):
    """Through the chain (airborne_xband, points: floor 6 samples): PGA results without a window
    are judged at K of the floor the chain passed; results with one at K of their own window."""
    setup = ChainSetup.build(PRESETS["airborne_xband"], McOptions(scene="points"))
    mask = chain_plan(setup).mask
    n, n_ap = mask.size, int(mask.sum())
    floor = pga_min_window(n, n_ap)
    assert floor == 6
    zero = np.zeros((2, setup.geom.n_pulses, 3))
    real = chain.pga
    seen = []

    def reporting(img, **kw):
        assert kw["min_window"] == floor
        res = real(img, **kw)
        seen.append(res.final_window)
        return res

    monkeypatch.setattr(chain, "pga", reporting)
    out = run_trials(setup, zero, range(2), SEED, np.zeros(2), keep_detail=True)
    assert all(w > 0 for w in seen)
    assert [o.detail["pga_bandwidth_cycles"] for o in out] == [pga_bandwidth_cycles(w, n, n_ap) for w in seen]

    def windowless(img, **kw):
        return PgaResult(image=img, phase_error_rad=np.zeros(img.shape[0]), iterations=0, converged=False,
                         reason="no usable scatterers: the image is zero", usable_lines=0)

    monkeypatch.setattr(chain, "pga", windowless)
    out = run_trials(setup, zero, range(2), SEED, np.zeros(2), keep_detail=True)
    assert [o.detail["pga_bandwidth_cycles"] for o in out] == [pga_bandwidth_cycles(floor, n, n_ap)] * 2
    assert pga_bandwidth_cycles(floor, n, n_ap) != pga_bandwidth_cycles(DEFAULT_MIN_WINDOW, n, n_ap)
    assert all("pga_failed" in o.reasons for o in out)


def test_joined_to_peak_drops_an_isolated_line_only():
    """At the stage's level (30 dB below the peak), a bin at −29 dB cut off from the band by bins at
    −60 dB (30 dB below the level, deeper than the 10 dB gap allowed) is not joined to the peak; a
    bin reached through bins less than the gap below the level is; without any gap every bin is."""
    n = 128
    energy = np.full(n, 1e-6)
    energy[40:88] = np.hanning(50)[1:-1] ** 2 + 1e-3  # the band, connected to its peak
    energy[10] = 10 ** (-2.9)  # isolated line within 30 dB of the peak
    level = 1e-3 * float(energy.max())
    assert _BAND_GAP_DB == 10.0
    assert _joined_to_peak(energy, level) == (40, 88)
    energy[10] = 1e-6
    assert _joined_to_peak(energy, level) == (40, 88)
    energy[88:95] = 0.2 * level  # 7 dB below the level: a shallow gap
    energy[95] = 2.0 * level
    assert _joined_to_peak(energy, level) == (40, 96)
    energy[91] = 0.09 * level  # one bin deeper than the gap cuts the rest off
    assert _joined_to_peak(energy, level) == (40, 91)
    assert _joined_to_peak(np.full(n, 1.0), 2.0) == (0, n)
