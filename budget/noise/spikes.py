"""Isolated spikes in a static log: found, reported, and replaced where they would decide the fit.

A single corrupted sample (a bus glitch, a bit flip, a shock) of amplitude A adds 2A² to the sum
of squared first differences, which is what the Allan variance at the shortest τ measures
(IEEE Std 952-1997, annex C: σ²(τ₀) = ⟨(x_{k+1} − x_k)²⟩/2 for a rate record). One sample of
5000 deg/s in ten minutes of a 0.5 deg/√h gyro lifts its fitted ARW by two orders of magnitude,
and nothing else in the record says why. So before the Allan fit every channel is searched:

* **local residual** e_k = x_k − median(x_{k−3} … x_{k+3}) (:data:`WINDOW` = 7): the running
  median is the sample's local level — every slow term (bias instability, random walk, a ramp,
  a warm-up) moves it along, and a spike, or a burst of up to three adjacent ones, does not;
* **scale** s = 1.4826·MAD of e about its median (robust: the spikes do not move it; on a
  quantized channel whose MAD is 0, the mean absolute deviation × √(π/2));
* **spike**: |e_k| ≥ :data:`SPIKE_SIGMAS` = 50 s. That is beyond any noise the tool fits: a Gaussian
  record never reaches 8 σ in 10⁹ samples, and Student-t noise (heavy tails, the gap workflow's
  ``heavy_tailed``) gave 1.7 (ν = 4) and 22 (ν = 3) such samples per 10⁶ (10⁷ samples each, none
  of them near the dominance share below);
* **dominance**: the spikes' share of the sum of squared first differences, Σ 2h_k² / Σ d² (h_k
  the spike's height above the line between its nearest non-spike neighbours). At
  :data:`DOMINANT_FRACTION` = 10 % or more they decide σ(τ₀) — and with it ARW/VRW and the
  quantization term — so they are **replaced** by that line (the mean of the two neighbours for a single
  spike) before the fit, and the result says so (rows, values, share). Below it they are kept and
  reported: heavy-tailed noise is the part's noise, and a few large samples that do not decide
  the fit are left to the user (the model-gap workflow names ``outliers`` and ``heavy_tailed``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import KEEP_SPIKES_WAY
from .stationarity import record_rows

#: A spike's local residual exceeds this many robust standard deviations of the residuals.
SPIKE_SIGMAS = 50.0
#: Spikes carrying at least this share of the squared first differences are replaced.
DOMINANT_FRACTION = 0.1
#: Samples of the running median that gives each sample's local level (odd; a burst of up to
#: (WINDOW − 1)/2 adjacent spikes does not move it).
WINDOW = 7
#: Samples (evenly spaced) from which the scale s of the residuals is estimated.
SCALE_SAMPLES = 1 << 16
#: Spikes listed by row in a message.
LISTED = 5

_MAD = 1.482602218505602  # σ / MAD of a Gaussian


@dataclass(frozen=True)
class Spikes:
    """The spikes of one channel: sample indices (0-based), values and their size in robust σ of
    the local residual, their share of the squared first differences, and whether they were
    replaced (:func:`find_spikes`)."""

    channel: str
    index: np.ndarray
    values: np.ndarray
    sigmas: np.ndarray
    share: float
    replaced: bool

    def message(self, rows=None, unit: str = "") -> str:
        """One line naming the rows (``rows``: :func:`budget.noise.stationarity.record_rows`, by
        default those of an unrepaired file), the values and what was done."""
        rows = rows or record_rows(False)
        shown = ", ".join(f"{rows.at(int(k))}: {v:.4g} {unit}".rstrip() + f", {s:,.0f} σ"
                          for k, v, s in zip(self.index[:LISTED], self.values[:LISTED], self.sigmas[:LISTED]))
        more = f"; +{self.index.size - LISTED} more" if self.index.size > LISTED else ""
        what = (f"{self.index.size} isolated spike(s) ({shown}{more}; σ: the robust σ of the residual "
                f"from the 7-sample running median) carry {100 * self.share:.3g} % of the sample-to-sample variance")
        if self.replaced:
            return (what + " and would decide the short-τ Allan deviation (ARW/VRW): replaced by the mean of "
                    f"their neighbours before the fit ({KEEP_SPIKES_WAY.cli})")
        if self.share >= DOMINANT_FRACTION:
            return what + " and decide the short-τ Allan deviation (ARW/VRW): kept on request (keep_spikes)"
        return what + f"; kept (below {100 * DOMINANT_FRACTION:g} %, they do not decide the fit)"


def _scale(e: np.ndarray) -> float:
    dev = np.abs(e - np.median(e))
    mad = float(np.median(dev))
    return _MAD * mad if mad > 0 else float(np.mean(dev)) * np.sqrt(np.pi / 2)


def _fill(x: np.ndarray, bad: np.ndarray) -> np.ndarray:
    """``x`` with the samples ``bad`` (boolean) replaced by linear interpolation between the nearest
    good neighbours (the mean of the two for an isolated spike)."""
    good = np.nonzero(~bad)[0]
    out = x.copy()
    out[bad] = np.interp(np.nonzero(bad)[0], good, x[good])
    return out


def _median_residual(x: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """x[k] − median(x[k−3] … x[k+3]) at the indices ``idx``; within 3 samples of an end, the
    median of the first (last) 7 samples (padding by the end value would hide a spike there)."""
    half = WINDOW // 2
    start = np.clip(idx - half, 0, x.size - WINDOW)  # near the ends, the first/last WINDOW samples
    return x[idx] - np.median(x[start[:, None] + np.arange(WINDOW)], axis=1)


def find_spikes(x: np.ndarray, channel: str = "", *, replace: bool = True) -> tuple[np.ndarray, Spikes | None]:
    """(the series to fit, the spikes found or None) for one channel (module docstring): with
    ``replace`` the spikes are replaced when they carry ≥ :data:`DOMINANT_FRACTION` of the squared
    first differences; otherwise, and below that share, ``x`` is returned unchanged.

    Cost: the running median is evaluated where it can matter only — the scale s from an evenly
    spaced subsample of :data:`SCALE_SAMPLES` samples, the residual at the samples whose
    three-point residual x_k − (x_{k−1} + x_{k+1})/2 reaches s·:data:`SPIKE_SIGMAS`/4 and their
    neighbours (a spike, or the edge of a burst, gives at least half its height there) — so 10⁷
    samples take a fraction of their Allan deviation's time."""
    x = np.asarray(x, dtype=float)
    n = x.size
    if n < 2 * WINDOW:
        return x, None
    d = np.diff(x)
    d2 = float(d @ d)
    step = max(1, n // SCALE_SAMPLES)
    s = _scale(_median_residual(x, np.arange(0, n, step)))
    if not (s > 0 and d2 > 0):
        return x, None
    # three-point residual (d_{k−1} − d_k)/2 inside, the one difference at the ends
    limit = 0.25 * SPIKE_SIGMAS * s
    inner = d[:-1] - d[1:]
    np.abs(inner, out=inner)
    near = np.nonzero(inner >= 2.0 * limit)[0] + 1
    ends = [k for k, v in ((0, d[0]), (n - 1, d[-1])) if abs(v) >= limit]
    near = np.concatenate([ends[:1] if ends and ends[0] == 0 else [], near,
                           [n - 1] if n - 1 in ends else []]).astype(np.int64)
    if near.size == 0:
        return x, None
    half = WINDOW // 2
    near = np.unique(np.clip(near[:, None] + np.arange(-half, half + 1), 0, n - 1))
    e = _median_residual(x, near)
    hit = np.abs(e) >= SPIKE_SIGMAS * s
    if not np.any(hit) or hit.sum() > 0.5 * n:
        return x, None
    idx, e = near[hit], e[hit]
    bad = np.zeros(n, dtype=bool)
    bad[idx] = True
    work = _fill(x, bad)
    local = x[idx] - work[idx]  # the spike's height above its neighbours' line
    share = min(1.0, float(np.sum(2.0 * local ** 2)) / d2)
    order = np.argsort(-np.abs(e), kind="stable")
    found = Spikes(channel, idx[order], x[idx][order], np.abs(e[order]) / s, share,
                   replace and share >= DOMINANT_FRACTION)
    return (work if found.replaced else x), found
