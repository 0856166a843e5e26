"""ARMA-Kalman pre-filtering of IMU output, as seed 000 applies it, for the Monte Carlo chain.

Seed 000 (§3–4) fits an ARMA model to each channel of a *static* record, then runs the
state-augmented Kalman filter (14)–(16) on the sensor output before navigation. Here the static
record is simulated from the part's own noise model (``calibration_samples`` at the IMU rate,
a seed of its own), each channel gets its AIC-selected ARMA model (:func:`select_arma`, least
squares as in the paper) and an :class:`ArmaKalman` (X₀ = 0, P₀ = I, Q = δ₁I, R = the static
variance). In a trial the filter sees what the sensor outputs, true signal + error, with the
aperture mean removed and restored (``center``), and the error left is filtered − true.

What users should expect (and what the Monte Carlo shows): the filter lowers the sample-to-sample
scatter, but the position error over an aperture comes from the slow part of the noise, which a
filter with unit-order DC gain passes; and on a moving platform it also attenuates real motion
(:func:`budget.noise.motion_distortion`). It rarely changes a verdict.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..imu.generator import simulate_static_log
from ..units import ACCEL_CHANNELS, GYRO_CHANNELS
from .arma import DEFAULT_ORDERS, select_arma
from .kalman import ArmaKalman

KINDS = ("kalman", "rts")
#: Random stream of the calibration record (independent of every trial stream).
CALIBRATION_STREAM = 21


@dataclass(frozen=True)
class ImuPrefilter:
    """Per-channel ARMA-Kalman filters (``None``: a noise-free channel, left as is)."""

    kind: str
    filters: dict[str, ArmaKalman | None]

    def summary(self) -> str:
        parts = [f"{ch}: {'—' if f is None else f.fit.name}" for ch, f in self.filters.items()]
        what = "Kalman filter" if self.kind == "kalman" else "RTS smoother"
        return f"ARMA pre-filter, {what} (seed 000 (14)–(16)): {', '.join(parts)}"

    def _apply(self, err: np.ndarray, true: np.ndarray | None, channels) -> np.ndarray:
        out = err.copy()
        for axis, ch in enumerate(channels):
            kf = self.filters.get(ch)
            if kf is None:
                continue
            truth = np.broadcast_to(0.0 if true is None else true[..., axis], err.shape[:2])
            for t in range(err.shape[0]):
                tr = truth[t]
                z = err[t, :, axis] + tr
                res = kf.filter(z) if self.kind == "kalman" else kf.smooth(z)
                out[t, :, axis] = res.signal - tr
        return out

    def apply(self, gyro_err: np.ndarray, accel_err: np.ndarray, true_rate_rad_s=None,
              true_force_m_s2=None) -> tuple[np.ndarray, np.ndarray]:
        """Errors (T, N, 3) after filtering what the sensor outputs (true + error); the true
        signals are (N, 3) or (T, N, 3), ``None`` = zero."""
        return (self._apply(gyro_err, true_rate_rad_s, GYRO_CHANNELS),
                self._apply(accel_err, true_force_m_s2, ACCEL_CHANNELS))


def calibrate_prefilter(model, rate_hz: float, *, kind: str = "kalman", samples: int = 16_384,
                        seed: int = 0, orders=DEFAULT_ORDERS) -> ImuPrefilter:
    """Fit the per-channel ARMA-Kalman filters on a simulated static record of ``model``."""
    if kind not in KINDS:
        raise InputError(f"unknown pre-filter {kind!r}", field="prefilter", expected=" | ".join(KINDS))
    if not isinstance(samples, (int, np.integer)) or samples < 1024:
        raise InputError("the calibration record needs at least 1024 samples",
                         field="prefilter_calibration_samples", value=samples)
    rng = np.random.default_rng([int(seed), CALIBRATION_STREAM])
    log = simulate_static_log(model, int(samples), float(rate_hz), rng)
    filters: dict[str, ArmaKalman | None] = {}
    for ch, x in log.items():
        x = x - x.mean()
        if not np.any(x):
            filters[ch] = None
            continue
        filters[ch] = ArmaKalman(select_arma(x, orders).selected)
    return ImuPrefilter(kind, filters)
