"""What the ARMA Kalman filter does to real motion: frequency response and signal distortion.

The filter of seed 000 treats everything in the measurement as "ARMA noise + white noise". On
a moving platform the measurement also carries the motion, which the steady-state filter
passes through its transfer function (steady state, ω = 2πf/f_s):

    filter:   H_f(ω) = e₀ᵀ (I − A e^{−iω})⁻¹ K,             A = (I − K H) F
    smoother: H_s(ω) = e₀ᵀ (I − C e^{iω})⁻¹ (I − C F) (I − A e^{−iω})⁻¹ K

|H| < 1 means real motion at that frequency is attenuated, arg H a phase lag (filter) — the
smoother is zero-phase-like but attenuates too. :func:`motion_distortion` runs a noise-free
motion signal through the filter and reports the RMS error it introduces.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import InputError
from .arguments import check_rate_hz
from .kalman import ArmaKalman


@dataclass(frozen=True)
class FrequencyResponse:
    """Complex steady-state response from measurement to estimate at ``freq_hz``."""

    freq_hz: np.ndarray
    response: np.ndarray
    rate_hz: float
    smoother: bool

    @property
    def magnitude(self) -> np.ndarray:
        return np.abs(self.response)

    @property
    def phase_deg(self) -> np.ndarray:
        return np.degrees(np.angle(self.response))

    @property
    def dc_gain(self) -> float:
        return float(np.abs(self.response[0])) if self.freq_hz[0] == 0 else float("nan")

    @property
    def bandwidth_hz(self) -> float | None:
        """First frequency where |H| falls below 1/√2 (None if it never does on the grid)."""
        below = np.flatnonzero(self.magnitude < 1 / np.sqrt(2))
        return float(self.freq_hz[below[0]]) if below.size else None

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"freq_hz": self.freq_hz, "magnitude": self.magnitude,
                             "magnitude_db": 20 * np.log10(np.maximum(self.magnitude, 1e-300)),
                             "phase_deg": self.phase_deg})

    def to_dict(self) -> dict:
        """JSON-ready: filter or smoother, sampling rate (Hz), DC gain, −3 dB frequency (Hz) and
        the response per frequency."""
        return {"smoother": bool(self.smoother), "rate_hz": float(self.rate_hz), "dc_gain": self.dc_gain,
                "bandwidth_hz": self.bandwidth_hz, **{k: v.tolist() for k, v in self.to_frame().items()}}

    def summary(self) -> str:
        bw = self.bandwidth_hz
        return (f"{'smoother' if self.smoother else 'filter'} response: DC gain {self.dc_gain:.3g}, "
                f"−3 dB at {'—' if bw is None else f'{bw:.3g} Hz'} (sampling {self.rate_hz:g} Hz)")


def frequency_response(kf: ArmaKalman, rate_hz: float, freq_hz=None, *,
                       smoother: bool = False) -> FrequencyResponse:
    """Steady-state response of ``kf`` (filter or RTS smoother) at ``freq_hz`` (default: 0…f_s/2)."""
    rate_hz = check_rate_hz(rate_hz)
    if freq_hz is None:
        f = np.linspace(0.0, rate_hz / 2, 513)
    else:
        try:
            f = np.atleast_1d(np.asarray(freq_hz, float))
        except (TypeError, ValueError):
            f = np.array([np.nan])
        if f.ndim != 1 or not np.all(np.isfinite(f)) or np.any(f < 0):
            raise InputError("frequencies must be finite numbers ≥ 0", field="freq_hz", value=freq_hz,
                             expected="a 1-D array of frequencies in Hz, 0 … rate_hz/2")
    w = 2 * np.pi * f / rate_hz
    n = kf.n_states
    eye = np.eye(n)
    resp = np.empty(f.size, complex)
    D = eye - kf.C_ss @ kf.F
    for i, wi in enumerate(w):
        xf = np.linalg.solve(eye - kf.A_ss * np.exp(-1j * wi), kf.K_ss)
        if smoother:
            xf = np.linalg.solve(eye - kf.C_ss * np.exp(1j * wi), D @ xf)
        resp[i] = xf[0]
    return FrequencyResponse(f, resp, float(rate_hz), smoother)


def motion_distortion(kf: ArmaKalman, motion, *, smoother: bool = False) -> dict:
    """RMS error the filter adds to a noise-free ``motion`` series (same unit), and its ratio."""
    m = np.asarray(motion, float)
    out = (kf.smooth(m, center=False) if smoother else kf.filter(m, center=False)).signal
    err = out - m
    rms = float(np.sqrt(np.mean(m ** 2)))
    return {"rms_motion": rms, "rms_error": float(np.sqrt(np.mean(err ** 2))),
            "relative_error": float(np.sqrt(np.mean(err ** 2)) / rms) if rms > 0 else float("nan"),
            "amplitude_ratio": float(np.std(out) / np.std(m)) if np.std(m) > 0 else float("nan")}
