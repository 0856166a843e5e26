"""Overlapping Allan deviation of rate data with chi-square confidence intervals.

σ²(τ = m τ0) = Σ_k (S_{k+2m} − 2 S_{k+m} + S_k)² / (2 m² (N − 2m)),  S = cumulative sum of the
mean-removed rate samples with S_0 = 0, N = number of S points (samples + 1) — NIST SP 1065
eq. (11) on phase data x = τ0·S. Each τ costs O(N) with in-place differences and one BLAS dot.

Confidence intervals come from the equivalent degrees of freedom (EDF) of the overlapping
estimator: the simple approximations of Howe, Allan & Barnes / Stein tabulated in NIST SP 1065
Table 5 (not Greenhall's exact algorithm). The noise type per τ, needed by those formulas, is
taken from the local log-log slope μ of σ²(τ): μ < −1.5 → white phase (α = +2, i.e. angle/
velocity quantization), −1.5…−0.5 → white frequency (α = 0, ARW/VRW), −0.5…0.5 → flicker
frequency (α = −1, bias instability), ≥ 0.5 → random-walk frequency (α = −2, RRW; rate ramp is
treated the same), then made non-increasing in τ (the slope of a sum of power laws never
decreases, and a lower α is the conservative choice). Interval: σ·√(edf/χ²_{(1±c)/2}(edf)).
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy import stats

from ..errors import InputError
from .arguments import check_rate_hz, float_series

#: Default confidence level of the interval: ±1σ of a Gaussian.
ONE_SIGMA = 0.682689492137086


@dataclass(frozen=True)
class AllanResult:
    """Allan deviation of one channel (``unit``: rad/s or m/s² for SI channels).

    ``lo``/``hi`` bound the interval at confidence ``ci``; ``edf`` is the equivalent number of
    degrees of freedom at each τ; ``n`` the number of second differences (N − 2m); ``alpha``
    the noise type used for the EDF; ``samples`` and ``rate_hz`` describe the record.
    """

    tau_s: np.ndarray
    adev: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    edf: np.ndarray
    n: np.ndarray
    rate_hz: float
    samples: int
    channel: str | None = None
    unit: str = ""
    ci: float = ONE_SIGMA
    alpha: np.ndarray = field(default_factory=lambda: np.zeros(0))
    source: str = "computed"
    notes: tuple[str, ...] = ()

    @property
    def m(self) -> np.ndarray:
        return np.rint(self.tau_s * self.rate_hz).astype(np.int64)

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"tau_s": self.tau_s, "adev": self.adev, "lo": self.lo, "hi": self.hi,
                             "edf": self.edf, "n": self.n, "alpha": self.alpha})

    def to_dict(self) -> dict:
        """JSON-ready: inputs (channel, unit, rate, samples, confidence level, source) and the
        Allan deviation per τ (``unit``) with its interval, EDF and noise exponent α."""
        return {"channel": self.channel, "unit": self.unit, "rate_hz": float(self.rate_hz),
                "samples": int(self.samples), "ci": float(self.ci), "source": self.source,
                "notes": list(self.notes), **{k: v.tolist() for k, v in self.to_frame().items()}}

    def summary(self) -> str:
        name = self.channel or "series"
        i = int(np.argmin(self.adev))
        record = (f"{self.samples} samples at {self.rate_hz:.6g} Hz" if self.samples
                  else "digitised curve, no record")
        return (f"{name}: {self.tau_s.size} τ from {self.tau_s[0]:.4g} to {self.tau_s[-1]:.4g} s "
                f"({record}, {self.source}); minimum "
                f"{self.adev[i]:.4g} {self.unit} at τ = {self.tau_s[i]:.4g} s")


def averaging_factors(n_samples: int, rate_hz: float, taus="octave") -> np.ndarray:
    """Averaging factors m (τ = m/rate) with at least two second differences each.

    ``taus``: ``"octave"`` (1, 2, 4, …), ``"decade"`` (1, 2, 4, 10, 20, 40, …), ``"dense"``
    (about 10 per decade), ``"all"`` or an increasing array of τ in seconds, each > 0 and given
    once (rounded to whole samples; τ outside the record are dropped; a negative, repeated or
    out-of-order τ is an :class:`InputError`). The octave list equals allantools' for the same data.
    """
    n_phase = n_samples + 1
    m_max = (n_phase - 2) // 2
    if m_max < 1:
        raise InputError(f"{n_samples} samples are too few for an Allan deviation",
                         field="samples", expected="at least 3 samples")
    if isinstance(taus, str):
        if taus == "octave":
            m = 2.0 ** np.arange(int(np.floor(np.log2(m_max))) + 1)
        elif taus == "decade":
            dec = 10.0 ** np.arange(int(np.floor(np.log10(m_max))) + 1)
            m = np.concatenate([dec, 2 * dec, 4 * dec])
        elif taus == "dense":
            m = np.round(np.logspace(0, np.log10(m_max), int(10 * np.log10(m_max)) + 2))
        elif taus == "all":
            m = np.arange(1, m_max + 1, dtype=float)
        else:
            raise InputError(f"unknown τ list {taus!r}", field="taus",
                             expected="octave, decade, dense, all or an array of τ in seconds")
    else:
        try:
            arr = np.asarray(taus, dtype=float).ravel()
        except (TypeError, ValueError):
            raise InputError("τ list must be finite numbers", field="taus", value=taus,
                             expected="an increasing array of τ in seconds, each > 0") from None
        if arr.size == 0 or not np.all(np.isfinite(arr)):
            raise InputError("τ list must be finite numbers", field="taus", value=taus,
                             expected="an increasing array of τ in seconds, each > 0")
        if np.any(arr <= 0):
            raise InputError("τ must be > 0 s", field="taus", value=arr[np.argmax(arr <= 0)],
                             expected="an increasing array of τ in seconds, each > 0")
        step = np.diff(arr)
        if np.any(step <= 0):
            i = int(np.argmax(step <= 0))
            what = f"τ = {arr[i]:g} s is given twice" if step[i] == 0 else \
                f"τ list is not increasing: {arr[i + 1]:g} s follows {arr[i]:g} s"
            raise InputError(what, field="taus", expected="an increasing array of τ in seconds, each given "
                                                          "once (sort it: τ are never reordered)")
        m = np.round(arr * rate_hz)
    m = np.unique(m[(m >= 1) & (m <= m_max)]).astype(np.int64)
    if m.size == 0:
        raise InputError("no τ inside the record", field="taus",
                         expected=f"τ between {1 / rate_hz:.4g} s and {m_max / rate_hz:.4g} s")
    return m


def edf_simple(n_phase: int, m: np.ndarray, alpha: np.ndarray) -> np.ndarray:
    """EDF of the overlapping Allan variance, NIST SP 1065 Table 5 (Howe/Stein approximations).

    ``n_phase``: number of phase points (samples + 1); ``alpha``: PSD exponent of the rate
    noise (+2 white PM, +1 flicker PM, 0 white FM, −1 flicker FM, −2 random-walk FM).
    Non-finite or < 1 results are clipped to 1 (conservative).
    """
    N = float(n_phase)
    m = np.asarray(m, dtype=float)
    alpha = np.broadcast_to(np.asarray(alpha), m.shape)
    edf = np.full(m.shape, np.nan)
    with np.errstate(all="ignore"):
        a = alpha == 2
        edf[a] = (N + 1) * (N - 2 * m[a]) / (2 * (N - m[a]))
        a = alpha == 1
        edf[a] = np.exp(np.sqrt(np.log((N - 1) / (2 * m[a])) * np.log((2 * m[a] + 1) * (N - 1) / 4)))
        a = alpha == 0
        edf[a] = (3 * (N - 1) / (2 * m[a]) - 2 * (N - 2) / N) * 4 * m[a] ** 2 / (4 * m[a] ** 2 + 5)
        a = (alpha == -1) & (m == 1)
        edf[a] = 2 * (N - 2) ** 2 / (2.3 * N - 4.9)
        a = (alpha == -1) & (m >= 2)
        edf[a] = 5 * N ** 2 / (4 * m[a] * (N + 3 * m[a]))
        a = alpha == -2
        edf[a] = (N - 2) / (m[a] * (N - 3) ** 2) * ((N - 1) ** 2 - 3 * m[a] * (N - 1) + 4 * m[a] ** 2)
    edf[~np.isfinite(edf) | (edf < 1)] = 1.0
    return edf


def noise_type_from_slope(tau_s: np.ndarray, adev: np.ndarray) -> np.ndarray:
    """Power-law noise exponent α per τ from the local slope of log σ² vs log τ (see module doc)."""
    tau_s, adev = np.asarray(tau_s, float), np.asarray(adev, float)
    if tau_s.size < 2 or np.any(adev <= 0):
        return np.zeros(tau_s.shape, dtype=np.int64)
    mu = np.gradient(np.log(adev ** 2), np.log(tau_s))
    alpha = np.select([mu < -1.5, mu < -0.5, mu < 0.5], [2, 0, -1], default=-2).astype(np.int64)
    # A sum of power laws has a log-log slope that never decreases with τ, so α may only fall:
    # this stops a noisy long-τ point from being read as white phase noise (EDF ≈ N/2).
    return np.minimum.accumulate(alpha)


def confidence_interval(adev: np.ndarray, edf: np.ndarray, ci: float = ONE_SIGMA):
    """Chi-square interval (lo, hi) of a deviation with ``edf`` degrees of freedom."""
    if isinstance(ci, bool) or not isinstance(ci, numbers.Real) or not 0.0 < ci < 1.0:
        raise InputError("confidence level must be in (0, 1)", field="ci", value=ci,
                         expected="a number between 0 and 1, e.g. 0.683 (±1σ) or 0.95")
    lo = adev * np.sqrt(edf / stats.chi2.ppf(0.5 + ci / 2, edf))
    hi = adev * np.sqrt(edf / stats.chi2.ppf(0.5 - ci / 2, edf))
    return lo, hi


def overlapping_avar(y: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Overlapping Allan variance of rate samples ``y`` at averaging factors ``m`` (NIST SP 1065
    eq. (11)): Σ_k (S_{k+2m} − 2S_{k+m} + S_k)² / (2m²(N+1−2m)), S = cumsum with S_0 = 0 (no
    τ0 factor needed: it cancels). The one implementation of the package (the noise lab and the
    model gap both call it); the final dot product by ``einsum``, since OpenBLAS's threaded dot
    can stall for milliseconds per call on a loaded two-core machine."""
    y = np.asarray(y, dtype=np.float64)
    m = np.asarray(m, dtype=np.int64)
    s = np.empty(y.size + 1)
    s[0] = 0.0
    np.cumsum(y - y.mean(), out=s[1:])  # mean removed first: keeps the differences precise
    buf = np.empty(s.size)
    var = np.empty(m.size)
    for i, mj in enumerate(m):
        k = s.size - 2 * mj
        if k < 1:
            raise InputError(f"averaging factor {mj} exceeds half the record", field="taus")
        d = buf[:k]
        np.subtract(s[2 * mj:], s[mj:mj + k], out=d)
        d -= s[mj:mj + k]
        d += s[:k]
        var[i] = float(np.einsum("i,i->", d, d)) / (2.0 * mj * mj * k)
    return var


def allan_deviation(x, rate_hz: float, taus="octave", *, ci: float = ONE_SIGMA,
                    channel: str | None = None, unit: str = "") -> AllanResult:
    """Overlapping Allan deviation of rate samples ``x`` (any unit; SI by convention).

    Equals ``allantools.oadev(x, rate_hz, data_type="freq", taus=...)`` for the same τ list
    (to rounding), with EDF-based intervals instead of σ/√n.
    """
    y = float_series(x, channel or "x", "a 1-D array of rate samples")
    if y.ndim != 1:
        raise InputError("expected a 1-D series", field=channel or "x", value=f"shape {y.shape}")
    check_rate_hz(rate_hz)
    bad = np.flatnonzero(~np.isfinite(y))
    if bad.size:
        raise InputError(f"{bad.size} non-finite sample(s), first at index {bad[0]}",
                         field=channel or "x", expected="finite values (repair the log first)")
    m = averaging_factors(y.size, rate_hz, taus)
    adev = np.sqrt(overlapping_avar(y, m))
    tau = m / float(rate_hz)
    alpha = noise_type_from_slope(tau, adev)
    edf = edf_simple(y.size + 1, m, alpha)
    lo, hi = confidence_interval(adev, edf, ci)
    return AllanResult(tau, adev, lo, hi, edf, (y.size + 1 - 2 * m).astype(np.int64),
                       float(rate_hz), int(y.size), channel, unit, ci, alpha, "computed")
