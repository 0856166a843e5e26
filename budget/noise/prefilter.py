"""ARMA-Kalman pre-filtering of IMU output, as seed 000 applies it, for the Monte Carlo chain.

Seed 000 (§3–4) fits an ARMA model to each channel of a *static* record, then runs the
state-augmented Kalman filter (14)–(16) on the sensor output before navigation. Here the static
record is simulated from the part's own noise model (``calibration_samples`` at the IMU rate,
stream ``prefilter_calibration`` of :data:`budget.rng.STREAMS`), each channel gets its
AIC-selected ARMA model (:func:`select_arma` among the paper's candidates, least squares) and an
:class:`ArmaKalman` (X₀ = 0, P₀ = I, Q = δ₁I, R = the static variance). In a trial the filter
sees what the sensor outputs, true signal + error, with the record mean removed and restored,
and the error left is filtered − true.

What the filter does to real motion: it is a linear filter of the measurement, so it passes
motion through its steady-state response H(f) (:mod:`budget.noise.kalman_response`). With the
paper's tuning (R = var(z), Q = δ₁) on a white channel — every catalog part: ARW/VRW dominate
at the sample scale, the fitted AR(1) has φ ≈ 0 — H is flat at ≈ 0.5 from DC to Nyquist: it
halves the noise *and the motion* (a −50 % scale-factor error the navigation cannot see).
:meth:`ImuPrefilter.check_dc_gain` therefore refuses a filter whose DC gain departs from 1 by
more than :data:`DC_GAIN_TOLERANCE` on any channel, naming the gains; the response of every
channel is reported by :meth:`ImuPrefilter.responses`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import InputError
from ..imu.generator import simulate_static_log
from ..imu.noise_model import as_noise_model_si
from ..rng import STREAMS
from ..units import ACCEL_CHANNELS, GYRO_CHANNELS
from .arma import PAPER_ORDERS, select_arma
from .kalman import ArmaKalman
from .kalman_response import FrequencyResponse, frequency_response

KINDS = ("kalman", "rts")
_CACHE: dict = {}
#: Random stream of the calibration record (independent of every trial stream).
CALIBRATION_STREAM = STREAMS["prefilter_calibration"]
#: Largest |DC gain − 1| accepted: a pre-filter must not rescale real motion.
DC_GAIN_TOLERANCE = 0.01


@dataclass(frozen=True)
class ImuPrefilter:
    """Per-channel ARMA-Kalman filters (``None``: a noise-free channel, left as is)."""

    kind: str
    filters: dict[str, ArmaKalman | None]

    def responses(self, rate_hz: float, freq_hz=None) -> dict[str, FrequencyResponse | None]:
        """Steady-state response of every channel (filter or RTS smoother, by ``kind``) at
        ``freq_hz`` (default 0 … f_s/2); ``None`` for a channel left as is (gain 1)."""
        return {ch: None if kf is None else
                frequency_response(kf, rate_hz, freq_hz, smoother=self.kind == "rts")
                for ch, kf in self.filters.items()}

    def dc_gains(self, rate_hz: float) -> dict[str, float]:
        """|H(0)| per channel (1.0 for a channel left as is)."""
        return {ch: 1.0 if r is None else r.dc_gain
                for ch, r in self.responses(rate_hz, [0.0]).items()}

    def response_frame(self, rate_hz: float) -> pd.DataFrame:
        """One row per channel: ARMA model, DC gain, |H| at f_s/4 and f_s/2, −3 dB frequency."""
        rows = []
        for ch, r in self.responses(rate_hz, np.linspace(0.0, rate_hz / 2, 513)).items():
            kf = self.filters[ch]
            rows.append({"channel": ch, "arma": "—" if kf is None else kf.fit.name,
                         "dc_gain": 1.0 if r is None else r.dc_gain,
                         "gain_quarter_rate": 1.0 if r is None else float(r.magnitude[256]),
                         "gain_nyquist": 1.0 if r is None else float(r.magnitude[-1]),
                         "minus_3db_hz": None if r is None else r.bandwidth_hz})
        return pd.DataFrame(rows)

    def check_dc_gain(self, rate_hz: float, tolerance: float = DC_GAIN_TOLERANCE) -> dict[str, float]:
        """The DC gains, or :class:`InputError` when one departs from 1 by more than
        ``tolerance``: such a filter rescales real motion (at 0.5, a −50 % scale factor)."""
        gains = self.dc_gains(rate_hz)
        bad = {ch: g for ch, g in gains.items() if abs(g - 1.0) > tolerance}
        if bad:
            text = ", ".join(f"{ch} {g:.3f}" for ch, g in bad.items())
            raise InputError(
                f"the ARMA-Kalman pre-filter ({self.kind}, seed 000 tuning R = var(z), Q = δ₁) "
                f"has DC gain {text}: it would scale real motion by that factor, not only the "
                f"noise", field="prefilter", value=self.kind,
                expected=f"a filter with |DC gain − 1| ≤ {tolerance:g} on every channel "
                         "(or prefilter = none)")
        return gains

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
                        seed: int = 0, orders=PAPER_ORDERS) -> ImuPrefilter:
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


def prefilter_for(model, rate_hz: float, *, kind: str = "kalman", samples: int = 16_384,
                  seed: int = 0) -> ImuPrefilter:
    """:func:`calibrate_prefilter`, fitted once per (model, rate, kind, samples, seed) and process."""
    key = (repr(as_noise_model_si(model)), float(rate_hz), kind, int(samples), int(seed))
    if key not in _CACHE:
        if len(_CACHE) > 32:
            _CACHE.clear()
        _CACHE[key] = calibrate_prefilter(model, rate_hz, kind=kind, samples=samples, seed=seed)
    return _CACHE[key]
