"""Phase gradient autofocus (Wahl, Eichel, Ghiglia & Jakowatz, IEEE TAES 30(3), 1994).

Model: the image g(x, r) (azimuth along axis 0) is the DFT of a phase history
G(k, r) = |G| e^{jφ(k)} whose phase error φ(k) is the same for every range line. Here the phase
history is the inverse DFT along azimuth (bin k, centred order, ↔ slow time; see
:mod:`budget.sar.image`), and the correction multiplies it by e^{−jφ̂(k)}
(:func:`apply_phase_correction`).

Clutter level. c̄ = median(|g|²)/ln 2 over the whole image: the mean power of fully developed
speckle (exponential intensity, median = mean·ln 2), robust to the few pixels of the dominant
scatterers. Each candidate line gets its own level c_r = its median / ln 2 (real scenes are not
uniform), floored at c̄/10, at a tenth of the level across range at its scatterer, ρ_r = the
median / ln 2 of the row (azimuth sample) through the line's brightest pixel over every range
line, and, for noise-free simulations, at 10⁻¹² of the brightest pixel. Why ρ_r: on clutter or
noise it is the clutter level there (≈ c̄: the floor does not act), but on an image without
either, a line's median is its own response's azimuth sidelobes, which scale with its energy, so
every line holding some scatterer's response — a stronger line's range sidelobes included — had
the same SCR and the same weight in the ML kernel, as though each were an independent scatterer.
They are not: at short range the residual range migration over the aperture makes a range
sidelobe's azimuth phase differ from its scatterer's (measured, 24 GHz at 30 m, 7° of aperture:
up to 30–140° across the band on lines 37–54 dB below the peak), and 38 such lines outweighed the
target's three main-lobe lines — a focused single target came out of PGA with 9.7° rms of
estimate and its Taylor PSLR raised from −35.3 to −28.4 dB. Along the row, such a line holds no
more than the scatterer's range response: its SCR there is ≈ 0 and it drops out, as it would
under any white noise however weak (the noise-free limit of a noisy image), and the estimate is
0.13° rms. With clutter or noise present ρ_r ≈ c̄ and nothing changes (``benchmarks/bench_pga.py``:
the same residual on every clutter, points and Gotcha case).

Steps (Wahl et al. 1994, steps 1–5):

1. candidate lines (once): the ``line_fraction`` (at most ``max_lines``, at least ``min_lines``)
   range lines with the most energy Σ_x |g|². A line's energy is invariant under any azimuth
   phase correction (Parseval), so the ranking does not depend on how defocused the input is —
   unlike a peak-contrast rule, which a blurred target fails (the former 20 dB peak-to-median
   rule gave up on −25 dB clutter scenes);
2. centre shift: each candidate shifted so that its brightest point (parabolic fit) is at index 0,
   then refined to the centroid given by the mean phase slope of its windowed phase history — a
   phase ramp on the phase history, so a focused target gives no gradient;
3. windowing: rectangular window of W samples centred on the shifted peaks. W follows
   ``win_scale`` × the width over which the weighted, line-summed intensity stays within
   ``win_db`` of its peak (the measured width), but never grows, shrinks by at most the factor
   ``shrink`` per iteration and never falls below ``min_window``. The first window
   (``first_window="auto"``) is the widest of n, n/2, n/4, … (as the first iteration shrinks it)
   whose predicted clutter × clutter random walk stays below ``tol_rad``: the product term
   clutter × clutter of the ML kernel does not cancel in the integration, so at per-bin SCR < 1
   (a wide window on clutter) the estimate is a random walk (2.6 rad rms on a focused −35 dB
   scene with the whole-line start, measured) that the narrower later windows cannot see beyond
   their bandwidth. Its step variance is Σ q_r²/(2 (Σ q_r s_r)²), q_r = s_r/(2 s_r + 1), s_r the
   per-bin SCR, and a walk of N steps tied at both ends has rms σ_step √(N/6) (N: bins within
   10 dB of the peak energy). Clean images start from the whole line; when no wide window
   qualifies, from 3 × the measured width (it holds the tails of a blurred response below
   ``win_db``; 1 × truncated them: 4.1× the ML limit on one −25 dB scene of the tests, 1.1× with 3).
   "full" and "measured" force either start;
4. line weights: SCR_r = E_r/(W c_r) − 1 − b, E_r the line's energy inside the window and
   b = (H_n − 1)/W the excess a clutter-only line shows when centred on its brightest of n samples
   (H_n ≈ ln n + 0.577); the line enters the kernel scaled so that its products carry the weight
   SCR_r/(2 SCR_r + 1) per unit clutter — the inverse variance of G(k)G*(k−1) for a point of
   per-bin SNR SCR_r in white clutter (Jakowatz & Wahl, JOSA A 10(12), 1993: ML weighting by the
   signal-to-clutter ratio). A clutter-only line gets ≈ 0, a strong point ≈ ½, whatever the
   brightness of its neighbourhood. Kernels:
   ML   Δφ(k) = arg Σ_r G(k, r) G*(k−1, r)      (Jakowatz & Wahl 1993),
   LUMV φ̇(k) = Σ_r Im{G*(k, r) Ġ(k, r)} / Σ_r |G(k, r)|²   (Wahl et al. 1994, eq. 7);
5. integration (cumulative sum; trapezoid for LUMV), removal of the constant and linear terms by
   a least-squares fit weighted with the lines' energy per bin (bins more than ``band_db`` below
   the strongest carry no gradient and no weight), and smoothing of the increment by a cubic
   Savitzky–Golay filter of 2.5·n/W' bins (at most 70 % of the bins with signal),
   W' = min(W, ``smooth`` × the measured width): lines windowed to W samples carry phase that
   varies at most W/2 cycles per n bins, so faster wiggles are clutter noise (a local cubic keeps
   polynomial errors exact; a cubic SG filter of L bins passes ≈ 2.5/L cycles per bin).

Fast-phase stage (``fast_phase=True``, after convergence). The settled window W sees phase up to
K = W·n_ap/(2n) cycles per aperture (:mod:`budget.sar.residual`); a faster component (a vibration,
a random walk's fine structure) puts its paired echoes outside the window. Over the span of bins
where the candidate lines' energy is within 10 dB of its peak and at least twice its 5th
percentile (signal ≥ noise: on a noisy image the out-of-band bins hold receiver noise only, and a
basis stretched over them cannot follow the in-band phase) the bands below are estimated. First,
over every bin with signal (within 30 dB of the peak energy and above that noise floor, a wider
interval than the span: a weighted aperture's ends lie below the span's 10 dB; both count only
the bins joined to the peak, :func:`~budget.sar.pga_fast._joined_to_peak` — an isolated spectral
line outside the aperture band stretched the interval 42 bins beyond the band on a 96-cell
simulated scene and left 27–32° at the aperture's ends), the accumulated
estimate is cut back to what the settled window sees (Legendre terms to the cubic and DCT
cosines up to W·L/(2n) cycles over those L bins, least squares weighted by the lines' energy per
bin): what the early, wider windows left above it is, on clutter, mostly their clutter × clutter
random walk, largest at the aperture's ends where the lines have least energy and the
increments are not smoothed, and nothing earns a place above the window without the test below
(measured on the realistic airborne X-band scene, −25 dB, 64 trials: STIM300's P(pass) rises
from 0.59 to 0.72 with the cut-back over the span, to 0.84 over every bin with signal; on the
failing trials the estimate's content beyond the window was 8–13° rms in the outer eighths of
the aperture, against 0.3–0.8° in the truth: the early windows' noise grows with the error they
start from). When the caller knows the processed aperture (``aperture_bins``: the image former's
band |t| ≤ T/2, as the Monte Carlo chain gives it), the cut-back covers exactly that band
instead: on a noisy image the aperture's ends hold less signal than receiver noise, so the band
read off the lines' energy is wrong by tens of bins either way (realistic airborne X-band scene,
SNR 30 dB: the lines' energy at the aperture's edges 0.03–0.08 of its peak, 0.05–0.07 outside
the band; the interval 227–430 bins for an aperture of 313, either edge off by up to 120 bins).
Aperture bins outside a too narrow interval keep the early windows' random walk; a much wider
one fits the basis over noise-only bins, where the accumulated estimate is such a walk, and
leaves part of it above the window over the aperture (measured on the 25 trials of STIM300,
128 trials, seed 1, that failed on the residual, 1.5–4.3° against a limit of 1.43°: the
interval moved 2 / 5 / 10 bins inside the aperture's edges left 25 / 21 / 13 of them passing,
0–20 bins outside all 25, the aperture itself 0.27–0.70°, the true phase's own part beyond the
window). Then the DCT band (m_{j−1}, m_j],
m_j = ⌊2^j W · span/n⌋ (DCT index m ↔ m/2 cycles over the span), is estimated at the window 2^j W —
the narrowest that sees it, so the one with the most signal per unit clutter — on the lines
corrected with everything found so far, octave by octave up to the whole line. Before the first
band, the handover band (0, m_0], m_0 = ⌊W · span/n⌋, is estimated at the first band's window 2W:
the cut-back works over another, wider interval than the span, so what it took above K there has
a part at low m over the span that the bands above m_0 could never give back. Measured on
``automotive_77ghz``, accel VRW at 0.05× its paper bound, points scene, lever arm 0, seed 1:
that part was 0.2–0.5° at 1–4 cycles per aperture, enough to lift the Taylor window's −35 dB first
sidelobe by 1–2 dB, and it changed with the simulated image's length, so the verdict did too
(17/32 on a 48-cell image, 24/32 on a 96-cell one; 0.62–0.87 over 256 trials at eight lengths).
With the handover band 0.77–0.93 over 256 trials at eight lengths (the 96-cell image lowest, an
open question in docs/monte-carlo.md). Re-estimating the low terms inside the first band instead
(one band from m = 1) did as well there but, without a test of their own, added error beyond K on
other images (KVH1775 on the sonar, points: 0.31 → 0.16). On `benchmarks/bench_pga.py`'s
clutter, point and chip cases every residual is the same to the third decimal. A band is kept only
if significant: its power P = Σ a_m² must reach ``band_snr`` (default 9, i.e. 3× in rms) times its
noise power V = Σ var(a_m), the delete-one-group jackknife variance of the coefficients (Efron &
Stein 1981; a group = a run of adjacent range lines, whose clutter is correlated by the range
oversampling; a band seen by fewer than 3 groups — one or two scatterers, a calibration reflector —
is judged against the closed form instead, (m_j − m_{j−1}) / (2 Σ_r SCR_r), which covers first-order
clutter only); it is then scaled by the Wiener gain
1 − V/P. The jackknife measures whatever the noise is — first-order clutter, the clutter × clutter
random walk of wide windows, neighbouring scatterers in the same line — where the closed form
1/√(2 Σ SCR_r) only covers the first. On clean points every band of a real fast error is
significant and kept; on clutter, noise bands are dropped instead of staying in the estimate.
The records are in :attr:`PgaResult.fast_bands`.

Measured (before the cut-back covered every bin with signal, which lowers these), realistic
airborne X-band scene (:meth:`budget.sar.Scene.realistic`, SNR 30 dB) with NO motion error,
through the Monte Carlo chain (:mod:`budget.mc.chain`: residual beyond K, energy weighted), 3 scenes × 8 noise draws, median per scene: clutter −20 / −25 / −35 dB leaves
0.49–0.93 / 0.27–0.45 / 0.02–0.04° rms beyond the window (before the cut-back of the fast-phase
stage 0.5–1.2 / 0.4–1.3 / 0.1–0.2°; whole-line start with the former smoothed restart:
5.9–9.1 / 2.8–3.7 / 2.5–4.5°). For scale, an unconstrained per-bin estimator at the
settled window's SCR would leave 1/√(2 Σ SCR_r) × √(fraction of the aperture's degrees of freedom
beyond K) = 4.9–9.5 / 2.7–3.9 / 1.6–2.1° there: the windowed estimate is band-limited, so its noise
stays mostly inside K — where, at 3–6° rms for −20 dB, it still lifts a Taylor PSLR. A sinusoid of
0.3 rad at 6 cycles per aperture on the noise-free five-point scene (11.5° rms beyond K) is left
at 1.4° (before: 12.1°: the increments' smoothing to the measured width discarded it). Monte
Carlo, airborne X-band, points scene, lever arm 0, 64 trials: P(pass after PGA) for ARW at 0.1 /
0.3× its paper bound 1.00 / 0.95 (before 0.98 / 0.77), VRW at 0.03 / 0.05× 1.00 / 0.67 (before
0.25 / 0.06); with the cut-back ARW 1.00 / 1.00, VRW 1.00 / 0.70.

Restarts (the capture check, ``restarts=True``). PGA is a fixed-point iteration: with few lines
to average and a first window the clutter keeps narrow, a large error is not all inside the window
when the window shrinks, and the run can settle on a wrong solution that still passes the stop
rule (measured on a real Gotcha chip with five usable lines and 2 rad rms of smooth error: 0.90
rad left where another start leaves 0.28). When the first window was narrower than the line
(``start_window`` < n) and fewer than ``min_lines`` lines are usable, PGA also runs from the
measured width (``first_window="measured"``) and with a slower shrink (0.7), and keeps the run
whose corrected image is sharpest, Σ|g|⁴/(Σ|g|²)² (:mod:`budget.sar.sharpness`; Muller &
Buffington 1974, Fienup & Miller 2003); ``restarts`` lists every run and the reason names the one
kept. A whole-line start is not among them: on clutter its estimate is the random walk described
in step 3 (in the Monte Carlo's perfect-IMU reference it raised the 99 % residual from 1.26° to
1.91°). Noise-free images (whole-line start) and images with many usable lines never run the
check. What it trades, measured on 72 simulated scenes with 3, 5 or 8 scatterers over −25 dB
clutter and 2 or 3 rad of error (``tests/test_sar_pga_clutter.py``'s generator; the check ran on
68): of the two runs that settled elsewhere (> 0.5 rad) one is recovered (1.01 → 0.19 rad), the
other not (0.89 → 0.88); the rest move by a median 0.01 rad either way (29 better, 23 worse by
at most 0.08 rad, 16 unchanged; median 0.104 → 0.108 rad): between runs that all settled on the
right solution, the sharpest image is not always the one with the least phase error.

Second pass (``second_pass_above_rad``, default π rad; ``restarts=False`` leaves it out too). PGA's
window halves from iteration to iteration while the lines still carry a large error; after a large
correction the iteration can stop at the narrow final window with part of the error left (measured
in the Monte Carlo: MTi-300 on the realistic airborne X-band scene, 64 trials: the trials whose
phase error before PGA exceeded ≈ 330° were left with 4–41°, five of seven ≥ 13°). So when a run
that started from a clutter-limited window (``start_window`` < n) corrected more than
``second_pass_above_rad`` rad rms (:func:`correction_rms_rad`), PGA runs again, from its own
start, on the image that run corrected, and adds the second estimate when the image gets sharper
(Σ|g|⁴/(Σ|g|²)², as the capture check judges); ``second_pass`` records it, kept or not, and the
reason says so. Why only after a large correction: after a small one the second run mostly
fits the clutter — on the same Monte Carlo's perfect-IMU trials (corrections of 0.1–0.5 rad) it
added 0.15–0.6 rad rms of estimate and raised the scene's 99 % PSLR and ISLR after PGA by 1.0 and
0.8 dB — while after corrections beyond ≈ 6 rad it sharpened 35 of 36 images. Its effect, measured:
MTi-300 on airborne X band P(pass after PGA) 0.77 → 0.91 (64 trials, seed 1), the four ADIS1646x/
1647x parts 0.83–0.86 → 0.89–0.97, MPU-6050 on the missile 0.63 → 0.78, the perfect-IMU reference
unchanged; on the tests' independent clutter generator (24 scatterers, −25 dB, 6 or 10 rad rms,
8 seeds each) it ran on every image and left less on 10 of 16, more on none
(``tests/test_pga_second_pass.py``); on ``benchmarks/bench_pga.py`` (2 rad) it ran on 4 of 12
512² clutter scenes (kept on 3, each a little better) and on 1 of 50 Gotcha chips (not kept).
The threshold π is measured, not derived: on that Monte Carlo any threshold from 1 to 5 rad gives
the same verdicts with the same perfect-IMU reference; at 0.5 rad the pass reaches the reference's
own trials, at 8 rad verdicts fall back (``docs/autofocus.md``, "Where the gate sits").

Usable lines: candidates whose final-window SCR is ≥ ``min_scr_db``. None → "no usable
scatterers": estimate zero, image unchanged, ``usable_lines = 0``.

Stopping and policy. Iteration stops when the energy-weighted rms of the increment is below
``tol_rad`` (default 0.05 rad ≈ 3°) once the window has stopped shrinking, or after ``max_iter``
iterations (default 30). An increment of 0.05 rad moves ≤ 0.25 % of the main-lobe energy (σ²,
−26 dB); on clutter, successive increments level off near the clutter-limited noise
(≈ 1/√(2 Σ SCR_r) rad per bin, reported as ``predicted_noise_rad``). Whatever the outcome, the
returned ``image`` is the input corrected with the accumulated estimate; ``converged=False`` with
reason "did not converge …" is reported, never dropped: the caller decides what it means (the
fast-phase stage runs only after convergence).

Code: this module drives the iterations and holds the policy; the operations on the candidate
lines (steps 2–5) are in :mod:`budget.sar.pga_lines`, the fast-phase stage in
:mod:`budget.sar.pga_fast`, and the loops other than the FFTs (phase correction, peak fit and
phase ramps, centroid slope, window, line weights, the kernel's sums, the increment's
integration, detrending and smoothing, the bands' group sums) are compiled in
:mod:`budget.sar.pga_kernels` (the image's power and exact medians in :mod:`budget.sar.pga_lines`,
a band's sums and jackknife noise in :mod:`budget.sar.pga_fast`): the same arithmetic, without the
temporaries and the per-call overhead of many small NumPy steps (sums over lines add in sequence,
so the last bits can differ). The FFTs call scipy.fft's pocketfft binding directly
(:func:`~budget.sar.pga_lines.fft_lines`): the same transforms bit for bit, without scipy.fft's
dispatch, which on 128-sample lines cost a quarter of the transform.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.fft as sfft

from ..errors import InputError
from .pga_fast import _fast_bands
from .pga_kernels import (line_sums, measured_width, ml_step, refine_ramp, smoothed_rms, weights_and_lines,
                          window_in_place, wrms)
from .pga_lines import (_LN2, _SG_MAX_FRACTION, _SG_STRETCH_INC, _Lines, _bias, _centre, _corrected, _detrend,
                        _increment, _line_weights, _lowpass, _power_stats, _predicted_noise, _savgol_parts, _window,
                        fft_lines, ifft_lines, median_all, median_columns)
from .pga_lines import _median  # noqa: F401  (its home was this module; tests import it from here)
from .pga_passes import SECOND_PASS_ABOVE_RAD, _second_pass, _sharpest, correction_rms_rad

# First window on clutter (step 3, "auto"): this many times the measured width, which holds the
# tails of a blurred response below win_db.
_FIRST_SCALE = 3.0
#: A candidate line's clutter level is floored at this fraction of the level across range at its
#: scatterer (:func:`_row_levels`), as at this fraction of the image's c̄.
_ROW_FLOOR = 0.1
#: PGA's smallest window (samples) when the caller gives none.
DEFAULT_MIN_WINDOW = 8


@dataclass
class PgaResult:
    """Outcome of :func:`pga`; ``phase_error_rad`` on centred azimuth-frequency bins (rad).

    ``final_window``: the settled window W (azimuth samples), PGA's estimation bandwidth: a phase
    component of more than W·n_ap/(2n) cycles over an aperture of n_ap of the n bins puts its
    paired echoes outside the window and is not seen by it; only the fast-phase stage (``fast_bands``)
    can keep such a component, when it is significant.
    ``clutter_level``: c̄, the image's mean speckle power per pixel (|g|² units).
    ``fast_bands``: one dict per band beyond the settled window tested by the fast-phase stage
    (window, DCT index range, band rms and jackknife noise rms in rad, gain applied).
    """

    image: np.ndarray = field(repr=False)
    phase_error_rad: np.ndarray = field(repr=False)
    iterations: int
    converged: bool
    reason: str
    usable_lines: int
    final_window: int = 0
    candidate_lines: int = 0
    clutter_level: float = 0.0
    predicted_noise_rad: float = float("nan")
    history: list[dict] = field(default_factory=list, repr=False)
    support: np.ndarray | None = field(default=None, repr=False)  # bins within 20 dB of the peak energy
    fast_bands: list[dict] = field(default_factory=list, repr=False)
    #: the capture check's runs (start, sharpness, converged, iterations, usable lines, final
    #: window, kept), empty when it did not run (module docstring, "Restarts")
    restarts: list[dict] = field(default_factory=list, repr=False)
    #: the second pass (module docstring, "Second pass"): the first pass's correction (rad rms),
    #: the threshold, kept, the sharpness before and after, and the second run's start window,
    #: iterations, convergence, usable lines and final window; empty when it did not run
    second_pass: dict = field(default_factory=dict, repr=False)
    #: the first iteration's window before it shrinks (samples): the whole line, or narrower when
    #: the lines' SCR limits it on clutter (step 3)
    start_window: int = 0

    @property
    def estimated_bins(self) -> np.ndarray:
        """Boolean mask of the bins with signal (all bins when unknown)."""
        if self.support is None or not np.any(self.support):
            return np.ones(self.phase_error_rad.size, dtype=bool)
        return self.support

    @property
    def failed(self) -> bool:
        """True for "no usable scatterers" (estimate zero, image unchanged)."""
        return self.usable_lines == 0

    def summary(self) -> str:
        d = self._scalars()
        state = "converged" if d["converged"] else "did not converge"
        return (f"PGA {state} ({d['reason']}) after {d['iterations']} iterations: {d['usable_lines']} usable "
                f"lines, final window {d['final_window']} samples, {d['fast_bands_kept']} fast-phase bands kept, "
                f"estimate {d['phase_error_peak_to_peak_rad']:.3g} rad peak to peak")

    def _scalars(self) -> dict:
        """Outcome, iterations, lines, window, estimate peak-to-peak (JSON-safe)."""
        return {"converged": self.converged, "reason": self.reason, "iterations": self.iterations,
                "usable_lines": self.usable_lines, "start_window": self.start_window,
                "final_window": self.final_window,
                "fast_bands_kept": int(sum(b["gain"] > 0 for b in self.fast_bands)),
                "phase_error_peak_to_peak_rad": float(np.ptp(self.phase_error_rad[self.estimated_bins]))}

    def to_dict(self) -> dict:
        """JSON-safe dict: outcome, iterations, lines, window, estimate peak-to-peak, the candidates,
        clutter level, the history and the fast-phase bands."""
        out = self._scalars()

        def _js(h):
            return {k: (float(v) if isinstance(v, (float, np.floating)) else v if isinstance(v, str) else int(v))
                    for k, v in h.items()}

        out.update({"candidate_lines": self.candidate_lines, "clutter_level": float(self.clutter_level),
                    "predicted_noise_rad": float(self.predicted_noise_rad),
                    "failed": self.failed,
                    "history": [_js(h) for h in self.history],
                    "fast_bands": [_js(b) for b in self.fast_bands],
                    "restarts": [_js(r) for r in self.restarts],
                    "second_pass": _js(self.second_pass) if self.second_pass else {}})
        return out

    def to_frame(self) -> pd.DataFrame:
        n = self.phase_error_rad.size
        return pd.DataFrame({"bin": np.arange(n) - n // 2, "phase_error_rad": self.phase_error_rad,
                             "estimated": self.estimated_bins})


def apply_phase_correction(image_data, phase_error_rad) -> np.ndarray:
    """``image_data`` (azimuth along axis 0) with its phase history multiplied by e^{−jφ̂(k)}
    (Wahl et al. 1994, step 5); ``phase_error_rad`` on centred azimuth-frequency bins, one per
    azimuth sample (as :attr:`PgaResult.phase_error_rad`)."""
    g = np.asarray(image_data)
    phi = np.asarray(phase_error_rad, dtype=float)
    if g.ndim != 2 or phi.shape != (g.shape[0],):
        raise InputError(f"image shape {g.shape}, phase estimate shape {phi.shape}", field="phase_error_rad",
                         expected="a 2-D image and one phase value per azimuth sample (axis 0)")
    if not np.all(np.isfinite(phi)):
        raise InputError("phase estimate holds NaN or infinite values", field="phase_error_rad",
                         expected="finite values")
    if g.dtype != np.complex128:
        return sfft.fft(sfft.ifft(g, axis=0) * np.exp(-1j * np.fft.ifftshift(phi))[:, None], axis=0)
    return _corrected(ifft_lines(g), phi, overwrite=True)


def _row_levels(power: np.ndarray, lines: np.ndarray) -> np.ndarray:
    """The background level across range at each candidate line's scatterer (|g|² units): the
    median over every range line of the power in the row (azimuth sample) of the line's
    brightest pixel, / ln 2 (the mean of exponential speckle, as c̄). On clutter or noise it is
    the clutter level there; on a noise-free image it is the range response of the scatterer
    on that row (module docstring, "Clutter level")."""
    peaks = np.argmax(power[:, lines], axis=0)
    rows, which = np.unique(peaks, return_inverse=True)
    return np.median(power[rows], axis=1)[which] / _LN2


def _check(g: np.ndarray, kernel: str, max_iter: int, tol_rad: float, line_fraction: float,
           min_window: int, first_window: str, band_snr: float, finite: bool | None = None,
           second_pass_above_rad: float | None = None) -> None:
    """Raises InputError for a bad image or setting; ``finite``: whether every pixel is finite,
    when already known."""
    if g.ndim != 2 or g.shape[0] < 16 or g.shape[1] < 1:
        raise InputError(f"image has shape {g.shape}", field="image_data",
                         expected="a 2-D complex array with ≥ 16 azimuth samples")
    if not (np.all(np.isfinite(g)) if finite is None else finite):
        raise InputError("image holds NaN or infinite values", field="image_data", expected="finite values")
    if kernel not in ("ml", "lumv"):
        raise InputError("unknown PGA kernel", field="kernel", value=kernel, expected="'ml' or 'lumv'")
    if first_window not in ("auto", "measured", "full"):
        raise InputError("unknown first window", field="first_window", value=first_window,
                         expected="'auto', 'measured' or 'full'")
    if max_iter < 1 or not tol_rad > 0 or not 0 < line_fraction <= 1 or min_window < 3 or not band_snr >= 1:
        raise InputError("invalid PGA settings", field="max_iter/tol_rad/line_fraction/min_window/band_snr",
                         expected="max_iter ≥ 1, tol_rad > 0, 0 < line_fraction ≤ 1, min_window ≥ 3, "
                                  "band_snr ≥ 1")
    t = second_pass_above_rad
    if t is not None and not (isinstance(t, (int, float)) and not isinstance(t, bool) and np.isfinite(t) and t > 0):
        raise InputError("the second pass's threshold must be a positive, finite number of radians",
                         field="second_pass_above_rad", value=t,
                         expected="a correction size in rad rms > 0 (default π), or None for no second pass")


def _aperture_interval(aperture_bins, n: int) -> tuple[int, int] | None:
    """(first, last + 1) of the centred bins of ``aperture_bins`` (a boolean mask of n bins, one
    contiguous run), None when it is None; InputError for any other mask."""
    if aperture_bins is None:
        return None
    m = np.asarray(aperture_bins)
    idx = np.flatnonzero(m) if m.shape == (n,) and m.dtype == bool else np.zeros(0, dtype=int)
    if idx.size < 2 or idx[-1] - idx[0] + 1 != idx.size:
        raise InputError("the aperture mask is not one run of bins", field="aperture_bins",
                         expected=f"a boolean mask of the {n} centred azimuth bins, one contiguous run of ≥ 2")
    return int(idx[0]), int(idx[-1]) + 1


def _random_walk_rms(pw: np.ndarray, rows: np.ndarray, c_line: np.ndarray, n_bins: int) -> float:
    """Predicted rms (rad) of the part of an ML estimate that does not cancel in the integration:
    the clutter × clutter term of G(k)G*(k−1), independent from bin to bin, so its running sum
    is a random walk. With weights a_r (per unit clutter c_r) and per-bin SCR s_r its step
    variance is Σ (a_r c_r)²/2 / (Σ a_r c_r s_r)² = Σ q_r² / (2 (Σ q_r s_r)²), q_r = s_r/(2 s_r + 1);
    a random walk of N steps tied at both ends (Brownian bridge) has rms σ_step √(N/6)."""
    s, _ = _line_weights(pw, rows, c_line)
    q = s / (2.0 * s + 1.0)
    den = float(np.sum(q * s))
    if den <= 0:
        return float("inf")
    return float(np.sqrt(np.sum(q * q) / (2.0 * den * den) * n_bins / 6.0))


def _start_width(d: _Lines, pw: np.ndarray, measured: int, n_bins: int) -> int:
    """Step 3's first window ("auto"): the widest of n, n/2, n/4, … (as the first iteration would
    shrink it) whose predicted random walk (:func:`_random_walk_rms`) stays below ``tol_rad``;
    when none does, ``_FIRST_SCALE`` × the measured width. Noise-free images start from the whole
    line; on clutter a wide window's per-bin SCR is < 1 and its estimate would be dominated by
    that random walk."""
    n = pw.shape[0]
    width = n
    while True:
        used = max(d.min_window, min(width, max(measured, int(np.ceil(d.shrink * width)))))
        if used <= max(measured, d.min_window):
            return max(d.min_window, min(n, int(_FIRST_SCALE * measured)))
        if _random_walk_rms(pw, _window(n, used)[0], d.c_line, n_bins) <= d.tol_rad:
            return width
        width = int(np.ceil(d.shrink * width))


def _iterate(d: _Lines, phi_c: np.ndarray, width: int, max_iter: int, first: str = "full") -> dict:
    """Iterations of steps 2–5 from the estimate ``phi_c`` (centred) and window ``width``; the first
    window: ``first`` = "full" (``width``, shrunk as always), "measured" (the measured one) or
    "auto" (:func:`_start_width`)."""
    n = d.hist.shape[0]
    phi_c = phi_c.copy()
    history: list[dict] = []
    weight = np.ones(n)
    scr = np.zeros(d.hist.shape[1])
    converged = False
    start = width
    for it in range(1, max_iter + 1):
        h_shift, shifted, pw = d.centred_uncorrected() if it == 1 and not phi_c.any() else _centre(d, phi_c)
        # line weights from the SCR inside the current window (step 4), then the window (step 3)
        rows = _window(n, width)[0]
        measured = int(measured_width(pw, rows, d.c_line, _bias(d, rows), d.win_db, d.win_scale, width))
        previous = width
        if it == 1 and first == "auto":
            width = start = _start_width(d, pw, measured, d.n_signal_bins)
            first = "full" if width == n else "start"
        if it == 1 and first == "start":
            previous = width
        elif it == 1 and first == "measured":
            width = previous = start = max(d.min_window, min(width, measured))
        else:
            width = max(d.min_window, min(width, max(measured, int(np.ceil(d.shrink * width)))))
        rows, rot, inside = _window(n, width)
        scr, w_line, cols = weights_and_lines(pw, rows, d.c_line, _bias(d, rows))
        if cols.size == 0:
            break
        # step 2's centroid refinement and step 3's window (:func:`_refine`)
        win = refine_ramp(shifted, h_shift, rows, rot, cols)
        win = fft_lines(win, out=win)
        window_in_place(win, inside, w_line, cols)
        if d.kernel == "ml":
            sg_window = min(width, d.smooth * max(measured, d.min_window)) if d.smooth else 0.0
            inc, weight, lo, hi, length = ml_step(ifft_lines(win, out=win), d.band_db, float(sg_window),
                                                  _SG_STRETCH_INC, _SG_MAX_FRACTION)
            rms = float(smoothed_rms(inc, weight, lo, hi, *_savgol_parts(int(length))) if length else
                        wrms(inc, weight))
        else:
            hist_w = ifft_lines(win)
            inc, weight = _increment(d, hist_w, win, *line_sums(hist_w)[::-1])
            if d.smooth:
                inc = _lowpass(inc, weight, min(width, d.smooth * max(measured, d.min_window)), _SG_STRETCH_INC)
            rms = float(wrms(inc, weight))
        phi_c += inc
        history.append({"iteration": it, "rms_increment_rad": rms, "window": int(width),
                        "lines_weighted": int(cols.size)})
        if rms < d.tol_rad and width == previous:  # small correction and the window has settled
            converged = True
            break
    return {"phi": phi_c, "width": int(width), "history": history, "converged": converged, "scr": scr,
            "weight": weight, "start": int(start)}


def pga(image_data, *, kernel: str = "ml", max_iter: int = 30, tol_rad: float = 0.05,
        line_fraction: float = 0.3, min_lines: int = 8, max_lines: int = 64, min_scr_db: float = 6.0,
        win_db: float = 10.0, win_scale: float = 1.5, shrink: float = 0.5, min_window: int = DEFAULT_MIN_WINDOW, band_db: float = 30.0,
        smooth: float = 1.0, first_window: str = "auto", fast_phase: bool = True,
        band_snr: float = 9.0, corrected_image: bool = True, restarts: bool = True,
        aperture_bins=None, second_pass_above_rad: float | None = SECOND_PASS_ABOVE_RAD) -> PgaResult:
    """Autofocus a complex image (azimuth along axis 0); see the module docstring for the steps,
    the stop rule and the outcomes. ``min_lines``: fewest candidate lines (all lines if fewer).
    ``first_window``: "auto" (the widest the lines' SCR allows, module docstring), "measured"
    (from the data) or "full" (the whole line, the classic start).
    ``fast_phase``: run the fast-phase stage after convergence; ``band_snr``: its significance
    threshold (band power over jackknife noise power). ``corrected_image=False``: the result's
    ``image`` is the input (the caller applies ``phase_error_rad`` itself; saves two image FFTs).
    ``restarts``: the capture check (module docstring, "Restarts"). ``aperture_bins``: boolean
    mask of the centred azimuth-frequency bins inside the processed aperture (|t| ≤ T/2, a
    property of the image former, e.g. :meth:`budget.sar.image.SarImage.aperture_mask`), when
    the caller knows it: the fast-phase stage's cut-back then covers exactly that band (module
    docstring, "Fast-phase stage"); None: the band is read off the lines' energy.
    ``second_pass_above_rad``: the second pass after a large correction (module docstring,
    "Second pass"); None: never."""
    settings = {k: v for k, v in locals().items() if k != "image_data"}  # the second pass reruns with them
    try:
        g = np.asarray(image_data)
    except ValueError:  # ragged rows: numpy refuses the shape itself
        raise InputError("the image's rows differ in length", field="image_data",
                         expected="a 2-D complex array (azimuth × range)") from None
    stats = None
    if g.ndim == 2 and g.shape[0] >= 16 and g.shape[1] >= 1 and g.dtype.kind in "fc":
        g = g.astype(complex, copy=False)
        stats = _power_stats(g)  # the finiteness check comes with it
    _check(g, kernel, max_iter, tol_rad, line_fraction, min_window, first_window, band_snr,
           None if stats is None else stats[3], second_pass_above_rad)
    aperture = _aperture_interval(aperture_bins, g.shape[0])
    if stats is None:
        g = g.astype(complex, copy=False)
        stats = _power_stats(g)
    power, col_energy, peak_all, _ = stats
    n, n_lines = g.shape
    zero = np.zeros(n)
    clutter = float(median_all(np.ascontiguousarray(power))) / _LN2
    if peak_all <= 0:
        return PgaResult(image=g, phase_error_rad=zero, iterations=0, converged=False, usable_lines=0,
                         reason="no usable scatterers: the image is zero")
    floor = max(0.1 * clutter, 1e-12 * peak_all, 1e-300)
    n_cand = min(n_lines, max(min_lines, min(max_lines, int(np.ceil(line_fraction * n_lines)))))
    lines = np.sort(np.argsort(col_energy)[::-1][:n_cand])
    # a line's level is not trusted below a tenth of the background seen across the image (c̄)
    # nor below a tenth of that across range at its scatterer (:func:`_row_levels`)
    c_line = np.maximum(median_columns(power, lines) / _LN2,
                        np.maximum(floor, _ROW_FLOOR * _row_levels(power, lines)))
    d = _Lines(hist=ifft_lines(g[:, lines]),
               c_line=c_line, kernel=kernel,
               tol_rad=tol_rad, win_db=win_db, win_scale=win_scale, shrink=shrink, min_window=min_window,
               band_db=band_db, smooth=smooth)

    def finish(dd: _Lines, start: str) -> PgaResult:
        return _outcome(g, dd, _iterate(dd, zero, n, max_iter, first=start), lines, clutter, tol_rad, min_scr_db,
                        fast_phase, band_snr, aperture)

    res, corrected, hist = finish(d, first_window), None, None
    if restarts and first_window == "auto" and res.start_window < n and 0 < res.usable_lines < min_lines:
        res, corrected, hist = _sharpest(g, d, res, finish)
    if restarts and second_pass_above_rad is not None and res.usable_lines and res.start_window < n:
        size = correction_rms_rad(res)
        if size > second_pass_above_rad:
            def again(g1):  # from its own start, one run, the caller forms the image
                return pga(g1, **{**settings, "first_window": "auto", "corrected_image": False, "restarts": False})
            # the capture check's image and phase history, when it ran, are not formed again
            res, corrected = _second_pass(g, res, size, second_pass_above_rad, again, corrected, hist)
    if corrected_image and res.usable_lines:
        res.image = corrected if corrected is not None else apply_phase_correction(g, res.phase_error_rad)
    return res


def _outcome(g: np.ndarray, d: _Lines, run: dict, lines: np.ndarray, clutter: float, tol_rad: float,
             min_scr_db: float, fast_phase: bool, band_snr: float,
             aperture: tuple[int, int] | None = None) -> PgaResult:
    """The result of one run of the iterations (``image``: the input; :func:`pga` corrects it)."""
    n = g.shape[0]
    zero = np.zeros(n)
    iterations = len(run["history"])
    scr, width, history = run["scr"], run["width"], run["history"]
    usable = int(np.sum(scr >= 10 ** (min_scr_db / 10)))
    if not history or usable == 0:
        return PgaResult(image=g, phase_error_rad=zero, iterations=iterations, converged=False, usable_lines=0,
                         final_window=width, candidate_lines=int(lines.size), clutter_level=clutter,
                         history=history, start_window=run["start"], reason=(
                             f"no usable scatterers: none of the {lines.size} most energetic range lines "
                             f"has a signal-to-clutter ratio ≥ {min_scr_db:g} dB within ±{width // 2} samples "
                             "of its peak (clutter-like, no dominant point scatterers)"))
    phi_c = _detrend(run["phi"], run["weight"])
    bands: list[dict] = []
    if fast_phase and run["converged"]:
        phi_c, bands = _fast_bands(d, phi_c, width, lines, band_snr, aperture)
        phi_c = _detrend(phi_c, run["weight"])
    support = run["weight"] >= run["weight"].max() * 0.01
    last = history[-1]["rms_increment_rad"]
    reason = (f"converged: rms increment {last:.3g} rad < {tol_rad:g} rad" if run["converged"] else
              f"did not converge: rms increment {last:.3g} rad after {iterations} iterations (tol {tol_rad:g} rad); "
              "the image is corrected with the accumulated estimate")
    return PgaResult(image=g, phase_error_rad=phi_c, iterations=iterations,
                     converged=bool(run["converged"]), usable_lines=usable, final_window=width,
                     candidate_lines=int(lines.size), clutter_level=clutter, reason=reason,
                     predicted_noise_rad=_predicted_noise(scr[scr >= 10 ** (min_scr_db / 10)]),
                     history=history, support=support, fast_bands=bands, start_window=run["start"])
