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
(:func:`budget.sar.pga._connected_band`).

Accel VRW at 0.05× passed 0.50 / 0.09 / 0.03 at 48 / 96 / 192 cells: PGA's smallest window was 8
samples, so its bandwidth K = W·n_ap/(2n) fell from 2.05 to 1.47 cycles per aperture as the image
was sampled more finely. The chain now gives PGA a floor of 4 resolution cells (K = 2;
:func:`budget.mc.chain.pga_min_window`): 0.50 / 0.56 / 0.62.
"""

from __future__ import annotations

import numpy as np
import pytest

from budget.mc.chain import PGA_MIN_WINDOW_CELLS, ChainSetup, pga_min_window, run_chunk
from budget.mc.consistency import single_term_model
from budget.mc.options import McOptions
from budget.mc.runner import resolve_unspecified
from budget.mc.stats import wilson_interval
from budget.presets import PRESETS
from budget.sar import SarGeometry
from budget.sar.pga import _connected_band
from budget.sar.pga_lines import _Lines
from budget.sar.residual import pga_bandwidth_cycles

TRIALS = 32
SEED = 1


def _p_pass(monkeypatch, extent_cells: float, scale: float, term: str = "gyro_bias") -> tuple[int, int]:
    """(passes, trials) of the single-term model ``term`` at ``scale`` × its paper bound on
    automotive_77ghz with lever arm 0, points scene, the simulated scene ``extent_cells`` wide."""
    original = SarGeometry.from_scenario.__func__

    def sized(cls, scenario, **kw):
        kw.setdefault("scene_extent_cells", extent_cells)
        return original(cls, scenario, **kw)

    monkeypatch.setattr(SarGeometry, "from_scenario", classmethod(sized))
    scen = PRESETS["automotive_77ghz"].model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0)})
    opts = McOptions(scene="points", unspecified="zero")
    model = resolve_unspecified(single_term_model(scen, term, scale), "zero").model
    setup = ChainSetup.build(scen, opts)
    assert setup.geom.scene_extent_m[0] == pytest.approx(extent_cells * scen.azimuth_resolution_m)
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
    samples, 0.50 against 0.56 now)."""
    counts = {ext: _p_pass(monkeypatch, ext, 0.05, "accel_vrw") for ext in (48.0, 96.0)}
    (k1, n1), (k2, n2) = counts[48.0], counts[96.0]
    lo1, hi1 = wilson_interval(k1, n1)
    lo2, hi2 = wilson_interval(k2, n2)
    assert lo2 <= k1 / n1 <= hi2, counts
    assert lo1 <= k2 / n2 <= hi1, counts


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


def _lines_with_energy(energy_centred: np.ndarray) -> _Lines:
    """A one-line ``_Lines`` whose energy per bin is ``energy_centred`` (centred order)."""
    hist = np.sqrt(np.fft.ifftshift(energy_centred)).astype(complex)[:, None]
    return _Lines(hist=hist, c_line=np.ones(1), kernel="ml", tol_rad=0.05, win_db=10.0, win_scale=1.5,
                  shrink=0.5, min_window=8, band_db=30.0, smooth=1.0)


def test_connected_band_drops_an_isolated_line_only():
    """A bin at −29 dB cut off from the band by bins at −60 dB (30 dB below the −30 dB level, deeper
    than the 10 dB gap allowed) is capped below that level
    (0.75 × it); the band, the floor's 5th percentile and every other bin are unchanged; without
    such a bin the lines come back as they are."""
    n = 128
    energy = np.full(n, 1e-6)
    energy[40:88] = np.hanning(50)[1:-1] ** 2 + 1e-3  # the band, connected to its peak
    energy[10] = 10 ** (-2.9)  # isolated line within 30 dB of the peak
    d = _lines_with_energy(energy)
    out = np.fft.fftshift(_connected_band(d).energy)
    peak = float(np.fft.fftshift(d.energy).max())
    assert out[10] == pytest.approx(0.75 * 1e-3 * peak)
    keep = np.ones(n, bool)
    keep[10] = False
    np.testing.assert_allclose(out[keep], np.fft.fftshift(d.energy)[keep], rtol=1e-12)
    assert np.percentile(out, 5) == pytest.approx(np.percentile(np.fft.fftshift(d.energy), 5))
    energy[10] = 1e-6
    d2 = _lines_with_energy(energy)
    assert _connected_band(d2) is d2
