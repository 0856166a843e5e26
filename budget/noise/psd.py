"""Welch power spectral density of rate data, alongside the Allan deviation.

One-sided PSD S₁(f) in unit²/Hz (Welch 1967, Hann window, 50 % overlap, mean removed per
segment; ``scipy.signal.welch``). For white rate noise of IEEE-952 coefficient N (two-sided
PSD N²), S₁ = 2N², hence :meth:`PsdResult.white_level` = √(S₁/2) over the upper part of the
band is an independent estimate of N (rad/s/√Hz or m/s²/√Hz).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import signal

from ..errors import InputError


@dataclass(frozen=True)
class PsdResult:
    freq_hz: np.ndarray
    psd: np.ndarray          # one-sided, unit²/Hz
    rate_hz: float
    unit: str = ""
    channel: str | None = None

    def white_level(self, band: tuple[float, float] | None = None) -> float:
        """√(median S₁ / 2) over ``band`` (default: 0.25–0.45 of the sampling rate)."""
        lo, hi = band or (0.25 * self.rate_hz, 0.45 * self.rate_hz)
        sel = (self.freq_hz >= lo) & (self.freq_hz <= hi)
        if not sel.any():
            raise InputError("no PSD bin in the band", field="band", value=(lo, hi))
        return float(np.sqrt(np.median(self.psd[sel]) / 2.0))

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"freq_hz": self.freq_hz, "psd": self.psd})

    def to_dict(self) -> dict:
        """JSON-ready: channel, unit, sampling rate (Hz), the white level (unit/√Hz) and the
        one-sided PSD (unit²/Hz) per frequency."""
        return {"channel": self.channel, "unit": self.unit, "rate_hz": float(self.rate_hz),
                "white_level": self.white_level(), "freq_hz": self.freq_hz.tolist(), "psd": self.psd.tolist()}

    def summary(self) -> str:
        return (f"{self.channel or 'series'}: Welch PSD, {self.freq_hz.size} bins to "
                f"{self.freq_hz[-1]:.4g} Hz; white level {self.white_level():.4g} {self.unit}/√Hz")


def welch_psd(x, rate_hz: float, *, nperseg: int | None = None, channel: str | None = None,
              unit: str = "") -> PsdResult:
    """Welch PSD of ``x`` sampled at ``rate_hz`` (segments of ``nperseg``, default ≤ 2¹⁴)."""
    x = np.asarray(x, dtype=np.float64)
    if x.ndim != 1 or x.size < 16:
        raise InputError("expected a 1-D series of at least 16 samples", field=channel or "x")
    if not np.all(np.isfinite(x)):
        raise InputError("series contains NaN or infinite values", field=channel or "x")
    if not (np.isfinite(rate_hz) and rate_hz > 0):
        raise InputError("sampling rate must be positive", field="rate_hz", value=rate_hz)
    seg = nperseg or int(min(1 << 14, 1 << int(np.log2(max(16, x.size // 8)))))
    f, p = signal.welch(x, fs=rate_hz, nperseg=min(seg, x.size), detrend="constant")
    return PsdResult(f, p, float(rate_hz), unit, channel)
