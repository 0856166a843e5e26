"""Cross-channel coherence: a component common to two or more channels of a log.

The noise model is per channel, and its channels are independent: a vibration or a flicker
that reaches gyro_x and gyro_y as one series is named, at best, as two independent effects
that each fit their channel, and every combination of the channels (a rotation about an axis
between them, a difference of two accelerometers) is then misstated. This check looks for it.

Statistic. Each channel (its mean and, with a temperature column, its least-squares part on
[1, t, T] removed) is cut into ``K`` non-overlapping segments, each detrended and Hann
windowed; for every pair of channels the magnitude-squared coherence

    |γ|²(f) = |Σ_k X_k(f) Y_k(f)*|² / (Σ_k |X_k(f)|² · Σ_k |Y_k(f)|²)

is formed at every second frequency bin from bin 3 on (Hann-windowed bins two apart are
correlated by 1/6, |ρ|² = 1/36; bins 0–2 carry the window's leakage of the trend). For a channel
independent of the other and Gaussian, |γ|² at one bin is Beta(1, K − 1) (Carter, Knapp &
Nuttall 1973): P(|γ|² > c) = (1 − c)^(K−1), so u = −(K − 1)·ln(1 − |γ|²) is Exp(1), and over the
n bins of an octave band U = Σu is Gamma(n, 1). A band is *coherent* when its Gamma tail
probability is below α / M, M = pairs × bands tested (Bonferroni over every pair and band of
the log). The independent-channel model gives exactly that null: its channels are drawn
independently, so the check needs no simulation.

The result (:func:`findings`): per coherent pair, the bands where it is coherent, the mean
|γ|² there against the null mean 1/K, the peak bin, the phase of the cross spectrum (in phase,
opposite, or in between) and log10 of the tail probability; :func:`notes` words them for the
report. Segments: ``K`` = 8 (a component is resolved down to 24/T, T the record length).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from scipy import signal, special

#: Segments averaged (non-overlapping): |γ|² of independent channels has mean 1/K.
SEGMENTS = 8
#: First frequency bin used (bins below carry the window's leakage of the segment's trend).
FIRST_BIN = 3
#: Shortest segment (samples) for which the check runs.
MIN_SEGMENT = 64
#: At most this many pairs are worded in the notes (the JSON has all).
MAX_NOTES = 6


def _residual(x: np.ndarray, temp_c: np.ndarray | None) -> np.ndarray:
    x = np.asarray(x, float)
    if temp_c is None:
        return x - x.mean()
    n = x.size
    basis = np.column_stack([np.ones(n), np.arange(n) / n, np.asarray(temp_c, float) - float(np.mean(temp_c))])
    coef, *_ = np.linalg.lstsq(basis, x, rcond=None)
    return x - basis @ coef


def _segment_spectra(x: np.ndarray, nperseg: int, k: int) -> np.ndarray:
    seg = signal.detrend(x[:k * nperseg].reshape(k, nperseg), axis=1, type="linear")
    win = signal.get_window("hann", nperseg)
    return np.fft.rfft(seg * win, axis=1)


def _bands(nperseg: int) -> list[np.ndarray]:
    """Octave bands of every second bin from :data:`FIRST_BIN` below Nyquist."""
    top = nperseg // 2  # Nyquist bin, excluded
    out, lo = [], FIRST_BIN
    while lo < top:
        hi = min(2 * lo, top)
        bins = np.arange(lo, hi, 2)
        if bins.size:
            out.append(bins)
        lo = hi
    return out


def log10_tail(gamma2: np.ndarray, k: int) -> float:
    """log10 of P(U ≥ u) for U = −(K − 1)·Σ ln(1 − |γ|²) over the bins ``gamma2`` of channels
    independent of each other: Gamma(n, 1), n = number of bins."""
    g = np.clip(np.asarray(gamma2, float), 0.0, 1.0 - 1e-15)
    u = float(-(k - 1) * np.sum(np.log1p(-g)))
    n = g.size
    p = special.gammaincc(n, u)
    if p > 0.0:
        return math.log10(p)
    # far tail: ln Γ(n, u) ≈ (n − 1) ln u − u − ln Γ(n) (leading term of the asymptotic series)
    return ((n - 1) * math.log(u) - u - special.gammaln(n)) / math.log(10.0)


def _phase_word(deg: float) -> str:
    if abs(deg) <= 30.0:
        return "in phase"
    if abs(deg) >= 150.0:
        return "in opposite phase"
    return f"at {deg:+.0f}° phase"


def findings(series: dict[str, np.ndarray], rate_hz: float, temp_c=None, alpha: float = 0.01,
             segments: int = SEGMENTS) -> list[dict]:
    """Pairs of channels with a common component: one dict per coherent pair (channels, bands,
    coherence, null mean, phase, log10 p), strongest first; ``[]`` when no band of any pair is
    coherent at ``alpha`` (Bonferroni over every pair and band), or with fewer than two
    channels or segments shorter than :data:`MIN_SEGMENT` samples."""
    chans = list(series)
    n = min(np.asarray(v).size for v in series.values()) if chans else 0
    k = int(segments)
    nperseg = n // k if k else 0
    if len(chans) < 2 or nperseg < MIN_SEGMENT:
        return []
    spectra = {ch: _segment_spectra(_residual(np.asarray(series[ch], float)[:n], None if temp_c is None
                                              else np.asarray(temp_c, float)[:n]), nperseg, k) for ch in chans}
    power = {ch: np.sum(np.abs(s) ** 2, axis=0) for ch, s in spectra.items()}
    bands = _bands(nperseg)
    pairs = list(itertools.combinations(chans, 2))
    n_tests = len(pairs) * len(bands)
    limit = math.log10(alpha / n_tests)
    freq = np.fft.rfftfreq(nperseg, 1.0 / rate_hz)
    out = []
    for a, b in pairs:
        cross = np.sum(spectra[a] * np.conj(spectra[b]), axis=0)
        denom = power[a] * power[b]
        with np.errstate(invalid="ignore", divide="ignore"):
            g2 = np.where(denom > 0, np.abs(cross) ** 2 / denom, 0.0)
        hits = []
        for bins in bands:
            lp = log10_tail(g2[bins], k)
            if lp < limit:
                hits.append((bins, lp))
        if not hits:
            continue
        bins = np.concatenate([h[0] for h in hits])
        peak = int(bins[np.argmax(g2[bins])])
        phase = float(np.degrees(np.angle(np.sum(cross[bins]))))
        df = rate_hz / nperseg
        out.append({
            "channels": [a, b],
            "bands_hz": [[float(freq[h[0][0]] - df), float(freq[h[0][-1]] + df)] for h in hits],
            "coherence": float(np.mean(g2[bins])),
            "peak_coherence": float(g2[peak]), "peak_hz": float(freq[peak]),
            "null_mean": 1.0 / k, "segments": k, "bins": int(bins.size),
            "phase_deg": phase, "log10_p": float(min(h[1] for h in hits)),
            "tests": n_tests, "alpha": alpha})
    out.sort(key=lambda d: d["log10_p"])
    return out


def _span(bands: list[list[float]]) -> str:
    lo, hi = bands[0][0], bands[-1][1]
    return f"{lo:.3g}–{hi:.3g} Hz" + ("" if len(bands) == 1 or all(
        abs(bands[i][1] - bands[i + 1][0]) < 1e-9 * max(1.0, hi) or bands[i + 1][0] <= bands[i][1]
        for i in range(len(bands) - 1)) else f" (in {len(bands)} octave bands)")


def notes(found: list[dict]) -> list[str]:
    """The report's notes for :func:`findings`: one per coherent pair (at most
    :data:`MAX_NOTES`, then a count), each with the channels, band, coherence against the
    independent-channel null, phase and what it means for the named effects."""
    out = []
    for f in found[:MAX_NOTES]:
        a, b = f["channels"]
        out.append(
            f"{a} and {b} share a component the per-channel model cannot express: coherence "
            f"|γ|² {f['coherence']:.2f} over {_span(f['bands_hz'])} (peak {f['peak_coherence']:.2f} at "
            f"{f['peak_hz']:.3g} Hz, {_phase_word(f['phase_deg'])}), where independent channels give "
            f"{f['null_mean']:.3f} on average (Beta(1, {f['segments'] - 1}) per bin, {f['segments']} "
            f"segments; p = 10^{f['log10_p']:.0f} over {f['tests']} pair-bands, α = {f['alpha']:g}) — "
            "effects named on these channels are fitted as if independent: a sum or difference of "
            "the two channels (a rotation between their axes) is misstated by the updated model")
    if len(found) > MAX_NOTES:
        out.append(f"… and {len(found) - MAX_NOTES} more coherent channel pairs (REPORT.json: cross_channel)")
    return out
