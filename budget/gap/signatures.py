"""Signatures of one channel, computed identically on the measured and the simulated series.

A static log holds gravity on one accelerometer axis, Earth rate and the turn-on bias on the
gyros: none of them is a noise statistic, so **each channel's mean is removed first** (the
time-slope and temperature statistics below have an intercept anyway). Then, on rate samples
x_k (rad/s or m/s²) at ``rate_hz``:

* ``avar``: overlapping Allan variance at octave averaging factors m = 1, 2, 4, … ≤ N/4, by
  the noise lab's estimator (:func:`budget.noise.allan.overlapping_avar`, NIST SP 1065 eq. (11)
  on the cumulative sum, the package's one implementation);
* ``psd``: Welch PSD (:func:`budget.noise.welch_psd`), Hann segments of L = 2^⌊log2(N/16)⌋
  samples (≥ 16 segments, ≤ 2¹⁶ samples), one-sided, unit²/Hz;
* distribution of the first differences d_k = x_k − x_{k−1} (differences remove the slow
  terms that make the raw series non-Gaussian): excess kurtosis; robust scale
  σ_r = 1.4826·MAD; ``tail_count`` = #{|d − median| > k_N·σ_r} with k_N = Φ⁻¹(1 − 2.5/N),
  i.e. 5 expected exceedances for Gaussian data of any length, and ``tail2_count`` beyond
  twice that limit (≈ 0 for Gaussian data: how the tail falls off tells heavy-tailed noise,
  a power law, from spikes of one size); isolated spikes (an exceedance
  followed by one of opposite sign, Pauta-like) give ``spike_count`` and ``spike_magnitude``;
  ``diff_max`` is the largest |d − median|;
* ``slope``: least-squares slope of x on time (unit/s);
* ``lattice``: the step δ (unit of the channel) when every first difference is a whole multiple
  of one step (raw counts, or an integrated output quantized to √12·Q = δ·dt), else ``None``;
  tested on the first ``LATTICE_SAMPLES`` differences, |d/δ − round(d/δ)| < 0.02 for 99.9 %;
* ``temp_coef``: coefficient of x on the temperature channel in a regression with intercept
  and linear time trend (unit/°C), when the log has one (a temperature that only rises
  linearly cannot be told from a rate ramp, and is not used): generalised least squares under
  the channel model's noise spectrum when the grid has one (:mod:`budget.gap.gls`, what the
  workflow uses), else ordinary least squares;
* ``low`` (grids built with ``low_frequency``): c_k² of the detrended record's DCT-II
  coefficients below the first Welch band (unit², :mod:`budget.gap.lowfreq`): periods from
  ≈ 40 s to the record;
* ``walk``: the record's slowest modes (block sums projected on the slowest DCT modes,
  orthogonal to bias, trend and temperature; :mod:`budget.gap.walk`), judged against the
  model's exact covariance of them.

A measured Allan-deviation table gives only ``avar`` (with its own EDF): the other fields are
``None`` and the comparison uses the ADEV signature alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from ..errors import InputError
from ..noise import welch_psd
from ..noise.allan import AllanResult, overlapping_avar
from . import lowfreq, walk as walk_modes
from .gls import regression_weights
from .whitening import Whitening

#: Fewest samples the workflow accepts (≥ 10 octave τ and a 256-point Welch segment).
MIN_SAMPLES = 4096
#: Fewest τ an Allan table must have to be compared.
MIN_TABLE_TAUS = 6
#: Expected number of Gaussian exceedances that sets the tail threshold k_N.
TAIL_EXPECTED = 5.0
#: Lowest Welch bin used (the first bins carry the segment-mean removal and window leakage).
FIRST_BIN = 4
MAX_NPERSEG = 1 << 16
#: Differences examined by the lattice test (enough for a stable verdict, bounded time).
LATTICE_SAMPLES = 200_000
#: First differences read to decide whether a series' robust scale needs the grouped median.
SCALE_LATTICE_SAMPLES = 20_000


@dataclass(frozen=True)
class SignatureGrid:
    """Where the signatures of one channel are evaluated (shared by measured and simulated).

    ``m``: averaging factors (τ = m/rate); ``nperseg``/``n_segments``: Welch layout (``None``/0
    for an Allan table); ``band_start``: first Welch bin of each octave band, the last band
    ending at ``bin_stop`` (Nyquist excluded); ``tail_k``: k_N; ``time_w``/``temp_w``:
    regression weights so that slope = time_w·x and coefficient = temp_w·x; ``low_k_max``: last
    DCT index of the low-frequency coefficients (0: none), ``low_starts``: where their octave
    bands start (:mod:`budget.gap.lowfreq`); ``whitening``: the metric's decorrelation of the
    spectral terms, set by the workflow once it has the model's realizations
    (:mod:`budget.gap.whitening`; ``None``: plain Σz²); ``walk``: blocks and slowest modes of
    the record (:mod:`budget.gap.walk`; ``None``: an Allan table or a record too short).
    """

    rate_hz: float
    n_samples: int
    m: np.ndarray
    nperseg: int | None = None
    n_segments: int = 0
    band_start: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    bin_stop: int = 0
    tail_k: float = 0.0
    time_w: np.ndarray | None = None
    temp_w: np.ndarray | None = None
    temp_c: np.ndarray | None = None
    low_k_max: int = 0
    low_starts: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    whitening: Whitening | None = None
    walk: walk_modes.WalkLayout | None = None

    @property
    def dt_s(self) -> float:
        return 1.0 / self.rate_hz

    @property
    def tau_s(self) -> np.ndarray:
        return self.m / self.rate_hz

    @property
    def has_psd(self) -> bool:
        return self.nperseg is not None

    @property
    def freq_hz(self) -> np.ndarray:
        return np.fft.rfftfreq(self.nperseg, self.dt_s) if self.nperseg else np.zeros(0)

    @property
    def has_low(self) -> bool:
        return self.low_k_max >= lowfreq.FIRST_K

    @property
    def low_freq_hz(self) -> np.ndarray:
        """f_k of the low-frequency coefficients, Hz."""
        return lowfreq.frequencies(self.n_samples, self.dt_s, self.low_k_max) if self.has_low else np.zeros(0)

    @property
    def low_counts(self) -> np.ndarray:
        return np.diff(np.append(self.low_starts, self.low_k_max + 1 - lowfreq.FIRST_K))

    @property
    def low_band_edges_hz(self) -> np.ndarray:
        """Lower edges of the low-frequency bands and the upper edge of the last one, Hz."""
        k = np.append(self.low_starts + lowfreq.FIRST_K, self.low_k_max + 1)
        return (k - 0.5) / (2.0 * self.n_samples * self.dt_s)

    @property
    def band_edges_hz(self) -> np.ndarray:
        """Lower edges of the bands and the upper edge of the last one, Hz."""
        if not self.nperseg:
            return np.zeros(0)
        return np.append(self.band_start, self.bin_stop) * self.rate_hz / self.nperseg

    @classmethod
    def for_log(cls, n_samples: int, rate_hz: float, temp_c: np.ndarray | None = None,
                low_frequency: bool = False, noise_psd=None, slow_modes: bool = True) -> "SignatureGrid":
        """The grid of a log; ``low_frequency``: also the low-frequency bands
        (:mod:`budget.gap.lowfreq`); ``slow_modes``: the record's slowest modes
        (:mod:`budget.gap.walk`, on by default); ``noise_psd``: the channel model's two-sided PSD
        S(f) (:func:`budget.gap.gls.model_spectrum`), which makes the temperature statistic a
        GLS coefficient weighted by 1/S (:mod:`budget.gap.gls`; ``None``: ordinary least
        squares given intercept and trend)."""
        if n_samples < MIN_SAMPLES:
            raise InputError(f"log too short: {n_samples} samples", field="samples",
                             expected=f"at least {MIN_SAMPLES} samples (≥ 10 octave τ and a Welch "
                                      "PSD with 16 segments)")
        m = 2 ** np.arange(int(math.floor(math.log2(n_samples // 4))) + 1)
        nperseg = int(min(MAX_NPERSEG, 2 ** int(math.floor(math.log2(n_samples / 16)))))
        n_seg = 1 + (n_samples - nperseg) // (nperseg // 2)
        stop = nperseg // 2  # exclude the Nyquist bin (real-valued: twice the variance)
        starts = []
        b = FIRST_BIN
        while b < stop:
            starts.append(b)
            b *= 2
        tail_k = float(stats.norm.isf(TAIL_EXPECTED / (2.0 * n_samples)))
        t = np.arange(n_samples) / rate_hz
        tc = t - t.mean()
        time_w = tc / _dot(tc, tc)
        temp_w = None
        if temp_c is not None:
            # partial regression on T given a linear trend: a rate ramp is left to the slope
            # statistic and a slow warm-up does not mask faster temperature changes
            temp = np.asarray(temp_c, float)
            if noise_psd is not None:
                temp_w = regression_weights(temp, rate_hz, noise_psd)
            else:
                dT = temp - temp.mean()
                dT = dT - _dot(time_w, dT) * tc
                ss = _dot(dT, dT)
                temp_w = dT / ss if ss > 1e-12 * temp.size else None
        k_max = (lowfreq.low_k_max(n_samples, FIRST_BIN * rate_hz / nperseg, 1.0 / rate_hz)
                 if low_frequency else 0)
        return cls(float(rate_hz), int(n_samples), m.astype(np.int64), nperseg, n_seg,
                   np.array(starts, dtype=np.int64), stop, tail_k, time_w, temp_w,
                   None if temp_c is None else np.asarray(temp_c, float), k_max,
                   lowfreq.band_starts(k_max),
                   walk=walk_modes.layout(n_samples, 1.0 / rate_hz, temp_c) if slow_modes else None)

    @classmethod
    def for_table(cls, allan: AllanResult) -> "SignatureGrid":
        if allan.tau_s.size < MIN_TABLE_TAUS:
            raise InputError(f"Allan table for {allan.channel} has {allan.tau_s.size} τ",
                             field=allan.channel, expected=f"at least {MIN_TABLE_TAUS} τ values")
        return cls(float(allan.rate_hz), int(allan.samples), allan.m.astype(np.int64))


@dataclass(frozen=True)
class Signature:
    """The statistics of one channel series (see module docstring); ``None`` = not available."""

    avar: np.ndarray
    psd: np.ndarray | None = None
    kurtosis: float | None = None
    diff_var: float | None = None
    sigma_r: float | None = None
    tail_count: int | None = None
    tail2_count: int | None = None
    spike_count: int | None = None
    spike_magnitude: float | None = None
    diff_max: float | None = None
    slope: float | None = None
    temp_coef: float | None = None
    edf: np.ndarray | None = None  # measured tables only: EDF behind the published interval
    lattice: float | None = None
    low: np.ndarray | None = None
    walk: np.ndarray | None = None


def series_signature(x: np.ndarray, grid: SignatureGrid, *, lattice: bool = False) -> Signature:
    """All signatures of one rate series ``x`` (its mean is removed here); the lattice test
    only when asked (a measured series: simulated ones are not read for it)."""
    x = np.asarray(x, dtype=np.float64)
    if x.shape != (grid.n_samples,):
        raise InputError(f"series has shape {x.shape}", expected=f"({grid.n_samples},)")
    x = x - x.mean()
    avar = overlapping_avar(x, grid.m)
    psd = welch_psd(x, grid.rate_hz, nperseg=grid.nperseg).psd
    d = np.diff(x)
    med = float(np.median(d))
    dev = np.abs(d - med)
    # on a lattice the plain median of |Δx − med| jumps by whole steps between two series of the
    # same process, and the tail limit k·σ with it across several levels; the grouped median moves
    # continuously with the distribution (continuous data: the plain median, unchanged)
    step = lattice_step(d[:SCALE_LATTICE_SAMPLES])
    sigma_r = 1.4826 * (float(np.median(dev)) if step is None else grouped_median(dev, step))
    c = d - d.mean()
    m2 = _dot(c, c) / c.size
    kurt = float(np.mean(c ** 4) / m2 ** 2 - 3.0) if m2 > 0 else 0.0
    if sigma_r <= 0:  # heavily quantized data: more than half the differences are zero
        sigma_r = math.sqrt(m2)
    limit = grid.tail_k * sigma_r
    hit = dev > limit
    tails = int(hit.sum())
    spikes = hit[:-1] & hit[1:] & (np.sign(d[:-1] - med) != np.sign(d[1:] - med))
    n_sp = int(spikes.sum())
    mag = float(np.median(0.5 * np.abs(d[:-1][spikes] - d[1:][spikes]))) if n_sp else 0.0
    slope = _dot(grid.time_w, x)
    temp = _dot(grid.temp_w, x) if grid.temp_w is not None else None
    low = lowfreq.coefficients_sq(x, grid.low_k_max) if grid.has_low else None
    return Signature(avar, psd, kurt, m2, sigma_r, tails, int(np.count_nonzero(dev > 2.0 * limit)),
                     n_sp, mag, float(dev.max()), slope, temp,
                     lattice=lattice_step(d) if lattice else None, low=low,
                     walk=walk_modes.modes(x, grid.walk) if grid.walk is not None else None)


def grouped_median(v: np.ndarray, step: float) -> float:
    """Median of values ``v`` that lie on a lattice of spacing ``step`` (whole or half steps from
    0), interpolated within its class of width ``step`` — the grouped-data median
    L + (n/2 − F_below)/f·step, L the class's lower boundary — so that it is continuous in the
    distribution instead of jumping from one level to the next."""
    half = np.round(np.asarray(v, float) * (2.0 / step)).astype(np.int64)  # levels in half steps
    levels, counts = np.unique(half, return_counts=True)
    cum = np.cumsum(counts)
    n = 0.5 * v.size
    j = int(np.searchsorted(cum, n))
    below = float(cum[j] - counts[j])
    return float((0.5 * levels[j] - 0.5) * step + step * (n - below) / counts[j])


def lattice_step(d: np.ndarray) -> float | None:
    """The common step δ of the first differences ``d`` if they all lie on a lattice kδ, else
    ``None`` (continuous data, or a step below 10⁻⁹ of the largest difference)."""
    d = np.asarray(d[:LATTICE_SAMPLES], float)
    a = np.abs(d)
    top = float(a.max()) if a.size else 0.0
    nz = a[a > 1e-9 * top]
    if nz.size < 10:
        return None
    step = float(nz.min())
    near = nz[nz < 1.5 * step]
    step = float(np.median(near))  # robust to round-off in a value printed in decimal
    k = d / step
    ok = np.abs(k - np.round(k)) < 0.02
    if ok.mean() < 0.999 or np.unique(np.round(k[ok])).size > d.size / 10:
        return None
    return step


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.einsum("i,i->", a, b))


def table_signature(allan: AllanResult) -> Signature:
    """The ADEV signature of a measured Allan-deviation table (its EDF kept for the metric)."""
    return Signature(np.asarray(allan.adev, float) ** 2, edf=np.asarray(allan.edf, float))


def band_means(psd: np.ndarray, grid: SignatureGrid) -> np.ndarray:
    """Mean PSD over each octave band of ``grid`` (works on (..., bins) arrays)."""
    seg = psd[..., grid.band_start[0]:grid.bin_stop]
    sums = np.add.reduceat(seg, grid.band_start - grid.band_start[0], axis=-1)
    counts = np.diff(np.append(grid.band_start, grid.bin_stop))
    return sums / counts


def band_counts(grid: SignatureGrid) -> np.ndarray:
    return np.diff(np.append(grid.band_start, grid.bin_stop))
