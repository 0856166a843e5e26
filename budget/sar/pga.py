"""Phase gradient autofocus (Wahl, Eichel, Ghiglia & Jakowatz, IEEE TAES 30(3), 1994).

Model: the image g(x, r) (azimuth along axis 0) is the DFT of a phase history
G(k, r) = |G| e^{jφ(k)} whose phase error φ(k) is the same for every range line. Here the phase
history is the inverse DFT along azimuth (bin k, centred order, ↔ slow time; see
:mod:`budget.sar.image`), and the correction multiplies it by e^{−jφ̂(k)}.

Each iteration (Wahl et al. 1994, steps 1–5):

1. range-line selection (once, on the input): lines whose peak power is ≥ ``min_contrast_db``
   above their median power (isolated dominant scatterer; Gaussian speckle reaches ≈ 10 dB over
   ~500 samples, sparse clutter up to ≈ 17 dB) and within
   ``dynamic_range_db`` of the strongest line; at most ``max_lines`` strongest;
2. centre shift: each line shifted so that its brightest point (parabolic fit) is at index 0,
   then refined to the centroid given by the mean phase slope of its windowed phase history —
   a phase ramp on the phase history, so the window is symmetric about the true peak and a
   focused target gives no gradient (an integer or parabolic-only shift leaves a bias that
   the iterations accumulate);
3. windowing: rectangular window of width W centred on the shifted peaks; W starts at the
   whole line and follows ``win_scale`` × the width over which the line-summed intensity stays
   within ``win_db`` of its peak, but never grows, shrinks by at most the factor ``shrink`` per
   iteration (so the estimate first sees the whole blur) and never falls below ``min_window``;
4. phase-gradient estimation over the selected lines:
   ML   Δφ(k) = arg Σ_r G(k, r) G*(k−1, r)      (Jakowatz & Wahl, JOSA A 10(12), 1993),
   LUMV φ̇(k) = Σ_r Im{G*(k, r) Ġ(k, r)} / Σ_r |G(k, r)|²   (Wahl et al. 1994, eq. 7),
   Ġ the derivative in k (inverse DFT of j2πx/n · g);
5. integration (cumulative sum; trapezoid for LUMV), removal of the constant and linear terms by
   a least-squares fit weighted with the selected lines' energy per bin; bins more than
   ``band_db`` below the strongest carry no gradient and no weight; correction applied.

Usability (besides the line selection): at convergence the selected lines must hold at least
``min_dominance`` of their energy inside the final window around their peaks — a focused point
scatterer holds most of its line's energy there, speckle a few per cent (clutter-only scenes).

Iteration stops when the energy-weighted rms of the increment is below ``tol_rad`` once the
window has stopped shrinking (narrower windows mainly reject clutter and noise; iterating
further on a focused image only adds jitter of ~0.01 rad). Outcomes:
``converged`` with the focused image; or ``converged=False`` with the INPUT image returned
unchanged and ``reason`` saying why ("no usable scatterers …" or "did not converge …").
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.fft as sfft

from ..errors import InputError


@dataclass
class PgaResult:
    """Outcome of :func:`pga`; ``phase_error_rad`` on centred azimuth-frequency bins."""

    image: np.ndarray = field(repr=False)
    phase_error_rad: np.ndarray = field(repr=False)
    iterations: int
    converged: bool
    reason: str
    usable_lines: int
    history: list[dict] = field(default_factory=list, repr=False)
    support: np.ndarray | None = field(default=None, repr=False)  # bins within 20 dB of the peak energy

    @property
    def estimated_bins(self) -> np.ndarray:
        """Boolean mask of the bins with signal (all bins when unknown)."""
        if self.support is None or not np.any(self.support):
            return np.ones(self.phase_error_rad.size, dtype=bool)
        return self.support

    def summary(self) -> dict:
        return {"converged": self.converged, "reason": self.reason, "iterations": self.iterations,
                "usable_lines": self.usable_lines,
                "phase_error_peak_to_peak_rad": float(np.ptp(self.phase_error_rad[self.estimated_bins]))}

    def to_frame(self) -> pd.DataFrame:
        n = self.phase_error_rad.size
        return pd.DataFrame({"bin": np.arange(n) - n // 2, "phase_error_rad": self.phase_error_rad,
                             "estimated": self.estimated_bins})


def _select_lines(power: np.ndarray, min_contrast_db: float, dynamic_range_db: float,
                  max_lines: int) -> np.ndarray:
    peak = power.max(axis=0)
    med = np.median(power, axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        contrast = np.where(med > 0, peak / med, np.inf)
    ok = (contrast >= 10 ** (min_contrast_db / 10)) & (peak >= peak.max() * 10 ** (-dynamic_range_db / 10))
    ok &= peak > 0
    idx = np.nonzero(ok)[0]
    return idx[np.argsort(peak[idx])[::-1][:max_lines]]


def _window_width(summed: np.ndarray, win_db: float, win_scale: float) -> int:
    """Width (samples) of the region around index 0 where ``summed`` stays within ``win_db``."""
    n = summed.size
    thr = summed[0] * 10 ** (-win_db / 10)
    right = np.argmax(summed[1:n // 2] < thr) if np.any(summed[1:n // 2] < thr) else n // 2
    rev = summed[::-1][:n // 2]
    left = np.argmax(rev < thr) if np.any(rev < thr) else n // 2
    return int(np.ceil(win_scale * (right + left + 1)))


def _detrend(phi: np.ndarray, weight: np.ndarray) -> np.ndarray:
    k = np.arange(phi.size, dtype=float)
    a = np.stack([np.ones_like(k), k], axis=1) * np.sqrt(weight)[:, None]
    coef, *_ = np.linalg.lstsq(a, phi * np.sqrt(weight), rcond=None)
    return phi - coef[0] - coef[1] * k


def _integrated_estimate(big_g: np.ndarray, win: np.ndarray, pos: np.ndarray, kernel: str,
                         weight: np.ndarray) -> np.ndarray:
    """Phase estimate (centred bins, not detrended) from windowed lines ``win`` and their
    centred phase histories ``big_g`` (step 4 and the integration of step 5)."""
    n = big_g.shape[0]
    if kernel == "ml":
        dphi = np.angle((big_g[1:] * np.conj(big_g[:-1])).sum(axis=1)) * (weight[1:] > 0) * (weight[:-1] > 0)
        return np.concatenate([[0.0], np.cumsum(dphi)])
    d_g = np.fft.fftshift(sfft.ifft(win * (2j * np.pi * pos / n)[:, None], axis=0), axes=0)
    grad = np.where(weight > 0, np.imag(np.conj(big_g) * d_g).sum(axis=1) / np.maximum(weight, 1e-300), 0.0)
    return np.concatenate([[0.0], np.cumsum(0.5 * (grad[1:] + grad[:-1]))])


def _wrms(phi: np.ndarray, weight: np.ndarray) -> float:
    return float(np.sqrt(np.sum(weight * phi ** 2) / max(weight.sum(), 1e-300)))


def pga(image_data, *, kernel: str = "ml", max_iter: int = 30, tol_rad: float = 0.02,
        min_contrast_db: float = 20.0, dynamic_range_db: float = 40.0, max_lines: int = 32,
        min_lines: int = 1, win_db: float = 10.0, win_scale: float = 1.5, shrink: float = 0.5,
        min_window: int = 8, band_db: float = 30.0, min_dominance: float = 0.1) -> PgaResult:
    """Autofocus a complex image (azimuth along axis 0); see module docstring for the steps."""
    g = np.asarray(image_data)
    if g.ndim != 2 or g.shape[0] < 16 or g.shape[1] < 1:
        raise InputError(f"image has shape {g.shape}", field="image_data",
                         expected="a 2-D complex array with ≥ 16 azimuth samples")
    if not np.all(np.isfinite(g)):
        raise InputError("image holds NaN or infinite values", field="image_data", expected="finite values")
    if kernel not in ("ml", "lumv"):
        raise InputError("unknown PGA kernel", field="kernel", value=kernel, expected="'ml' or 'lumv'")
    if max_iter < 1 or not tol_rad > 0 or min_lines < 1 or max_lines < min_lines or min_window < 3:
        raise InputError("invalid PGA settings", field="max_iter/tol_rad/min_lines/max_lines/min_window",
                         expected="max_iter ≥ 1, tol_rad > 0, 1 ≤ min_lines ≤ max_lines, min_window ≥ 3")
    g = g.astype(complex, copy=False)
    n = g.shape[0]
    zero = np.zeros(n)
    lines = _select_lines(np.abs(g) ** 2, min_contrast_db, dynamic_range_db, max_lines)
    if lines.size < min_lines:
        return PgaResult(image=g, phase_error_rad=zero, iterations=0, converged=False, usable_lines=int(lines.size),
                         reason=(f"no usable scatterers: {lines.size} range line(s) have a peak ≥ "
                                 f"{min_contrast_db:g} dB above their median (need {min_lines})"))
    hist_sel = sfft.ifft(g[:, lines], axis=0)  # phase history of the selected lines (numpy order)
    freq = np.fft.fftfreq(n)
    pos = freq * n  # signed sample index: the centre-shifted peak sits at 0
    phi_c = np.zeros(n)  # accumulated estimate, centred order
    width = n
    history: list[dict] = []
    weight = np.ones(n)
    converged = False
    dominance = 0.0
    it = 0
    for it in range(1, max_iter + 1):
        phi_np = np.fft.ifftshift(phi_c)
        mag = np.abs(sfft.fft(hist_sel * np.exp(-1j * phi_np)[:, None], axis=0))
        peaks = np.argmax(mag, axis=0)
        cols = np.arange(lines.size)
        a_m, a_0, a_p = mag[(peaks - 1) % n, cols], mag[peaks, cols], mag[(peaks + 1) % n, cols]
        den = a_m - 2 * a_0 + a_p
        frac = np.where(den < 0, 0.5 * (a_m - a_p) / np.where(den < 0, den, -1.0), 0.0)
        # centre shift by the sub-pixel peak position, as a phase ramp on the phase history
        ramp = phi_np[:, None] + 2.0 * np.pi * freq[:, None] * (peaks + frac)[None, :]
        shifted = sfft.fft(hist_sel * np.exp(-1j * ramp), axis=0)
        summed = (np.abs(shifted) ** 2).sum(axis=1)
        measured = _window_width(summed, win_db, win_scale)
        previous = width
        width = max(min_window, min(width, max(measured, int(np.ceil(shrink * width)))))
        inside = np.abs(pos) <= width / 2.0
        win = shifted * inside[:, None]
        # refine each line's centre with the mean phase slope of its windowed phase history
        # (the centroid; unbiased for a sinc, unlike the parabolic peak fit) and window again
        h_w = sfft.ifft(win, axis=0)
        slope = np.angle((h_w[1:] * np.conj(h_w[:-1])).sum(axis=0))
        ramp = ramp + 2.0 * np.pi * freq[:, None] * (slope * n / (2.0 * np.pi))[None, :]
        shifted = sfft.fft(hist_sel * np.exp(-1j * ramp), axis=0)
        win = shifted * inside[:, None]
        big_g = np.fft.fftshift(sfft.ifft(win, axis=0), axes=0)
        weight = (np.abs(big_g) ** 2).sum(axis=1)
        weight = np.where(weight >= weight.max() * 10 ** (-band_db / 10), weight, 0.0)
        inc = _integrated_estimate(big_g, win, pos, kernel, weight)
        inc = _detrend(inc, weight)
        rms = _wrms(inc, weight)
        phi_c += inc
        history.append({"iteration": it, "rms_increment_rad": rms, "window": int(width),
                        "dominance": float(summed[inside].sum() / max(summed.sum(), 1e-300))})
        if rms < tol_rad and width == previous:  # small correction and the window has settled
            converged = True
            dominance = float(summed[inside].sum() / max(summed.sum(), 1e-300))
            break
    phi_c = _detrend(phi_c, weight)
    if converged and dominance < min_dominance:
        return PgaResult(image=g, phase_error_rad=zero, iterations=it, converged=False, usable_lines=0,
                         history=history, reason=(
                             f"no usable scatterers: the {lines.size} selected range lines hold only "
                             f"{100 * dominance:.3g} % of their energy within ±{width // 2} samples of their "
                             f"peaks (need {100 * min_dominance:g} %): clutter-like, no dominant point scatterers"))
    if not converged:
        return PgaResult(image=g, phase_error_rad=phi_c, iterations=it, converged=False, usable_lines=int(lines.size),
                         reason=f"did not converge: rms increment {history[-1]['rms_increment_rad']:.3g} rad "
                                f"after {it} iterations (tol {tol_rad:g} rad)", history=history,
                         support=weight >= weight.max() * 0.01)
    focused = sfft.fft(sfft.ifft(g, axis=0) * np.exp(-1j * np.fft.ifftshift(phi_c))[:, None], axis=0)
    return PgaResult(image=focused, phase_error_rad=phi_c, iterations=it, converged=True, usable_lines=int(lines.size),
                     reason=f"converged: rms increment {history[-1]['rms_increment_rad']:.3g} rad < {tol_rad:g} rad",
                     history=history, support=weight >= weight.max() * 0.01)
