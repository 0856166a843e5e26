"""The seed 000 ARMA pipeline on one channel, as one result both the CLI and the dashboard render.

Preprocess (Pauta outliers, detrend, zero mean; seed 000 §3.1) → checks (runs test, normality)
→ ARMA candidates by least squares or exact ML, selected by AIC (seed 000 (12)–(13)) → the
state-augmented Kalman filter and RTS smoother on the selected model (seed 000 (14)–(16)) → the
filter's steady-state response to real motion (what it would also remove) → the adequacy of the
model and of the filter by their innovations, and the steady error variances (:mod:`.adequacy`). Units: the channel's
SI unit (rad/s or m/s²); variances in its square.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import REPAIR_WAY, InputError
from ..units import channel_si_unit
from .adequacy import ModelAdequacy, model_adequacy
from .arguments import float_series
from .arma import DEFAULT_ORDERS, MIN_SAMPLES, ArmaSelection, check_magnitude, check_orders, select_arma
from .checks import CheckReport, check_series
from .kalman import ArmaKalman, KalmanResult
from .kalman_response import FrequencyResponse, frequency_response
from .log_checks import max_abs_si
from .preprocess import Preprocessed, check_detrend_order, preprocess

AIC_DEFINITION = "AIC = ln(sigma2) + 2k/n, FPE = sigma2 (n+k)/(n-k), k = p+q, n = residuals (the same samples for every candidate)"
MOTION_WARNING = "the filter also attenuates real motion: see response_gain (1 = passed unchanged)"


@dataclass(frozen=True)
class ArmaOptions:
    """How the pipeline was run (carried by the result). ``orders`` and ``detrend_order`` are
    checked when built (:func:`~budget.noise.arma.check_orders`,
    :func:`~budget.noise.preprocess.check_detrend_order`): an :class:`InputError` naming the field."""

    orders: tuple[tuple[int, int], ...] = DEFAULT_ORDERS
    method: str = "ls"
    pauta_k: float | None = 4.0
    replace: str = "mean"
    detrend_order: int = 1
    process_noise: str = "paper"

    def __post_init__(self):  # the limits analyse_arma applies, refused here at construction
        object.__setattr__(self, "orders", check_orders(self.orders))
        object.__setattr__(self, "detrend_order", check_detrend_order(self.detrend_order))

    def to_dict(self) -> dict:
        return {"orders": [list(o) for o in self.orders], "method": self.method, "pauta_k": self.pauta_k,
                "replace": self.replace, "detrend_order": self.detrend_order,
                "process_noise": self.process_noise}


@dataclass
class ArmaAnalysis:
    """Everything the ARMA pipeline computed for one channel (see the module docstring)."""

    channel: str
    rate_hz: float
    raw: np.ndarray
    pre: Preprocessed
    checks: CheckReport
    selection: ArmaSelection
    kalman: ArmaKalman
    filtered: KalmanResult
    smoothed: KalmanResult
    response: FrequencyResponse
    options: ArmaOptions = field(default_factory=ArmaOptions)
    adequacy: ModelAdequacy | None = None

    @property
    def notes(self) -> tuple[str, ...]:
        """The selection's notes, then the adequacy's (e.g. the model does not describe the series)."""
        return tuple(self.selection.notes) + (self.adequacy.notes if self.adequacy is not None else ())

    @property
    def unit(self) -> str:
        return channel_si_unit(self.channel)

    @property
    def samples(self) -> int:
        return int(self.raw.size)

    @property
    def variance_reduction(self) -> float:
        """variance before / after the filter (seed 000 reports ÷10; see the README)."""
        return float(self.filtered.variance_before / self.filtered.variance_after)

    def to_frame(self) -> pd.DataFrame:
        """The ARMA candidates: order, AIC, FPE, parameters, stationarity and invertibility; the
        selected row also carries the adequacy's values (innovation tests, steady error variances in
        the channel's SI unit squared, named in the column), empty on the other rows."""
        frame = self.selection.to_frame()
        if self.adequacy is not None:
            for name, value in self.adequacy.fields().items():
                frame[name] = np.where(frame["selected"], value, np.nan)
        return frame

    def to_dict(self) -> dict:
        """JSON-safe result (the ``sar-budget noise arma --json`` contract)."""
        sel, kf, resp = self.selection, self.kalman, self.response
        return {
            "channel": self.channel, "rate_hz": self.rate_hz, "samples": self.samples,
            "preprocessing": list(self.pre.steps), "outliers": int(self.pre.outliers.size),
            "checks": self.checks.to_dict(), "method": self.options.method, "criteria": AIC_DEFINITION,
            "candidates": [{"order": c.name, "aic": c.aic, "fpe": c.fpe, "params": c.params(),
                            "stationary": c.stationary, "invertible": c.invertible,
                            "ar_root_max": c.ar_root_max, "ma_root_max": c.ma_root_max,
                            "converged": c.converged}
                           for c in sel.candidates],
            "selected": sel.selected.name, "selected_by_fpe": sel.by_fpe.name,
            "variance_unit": f"({self.unit})^2",
            "variance_before": self.filtered.variance_before, "variance_after": self.filtered.variance_after,
            "variance_after_smoother": self.smoothed.variance_after,
            "filter": {"process_noise": self.options.process_noise, "R": kf.R, "Q_scale": sel.selected.sigma2,
                       "steady_gain": np.asarray(kf.K_ss).tolist(), "transient_samples": kf.T,
                       "response_freq_hz": resp.freq_hz.tolist(), "response_gain": resp.magnitude.tolist(),
                       "warning": MOTION_WARNING},
            "adequacy": self.adequacy.to_dict() if self.adequacy is not None else None,
            "options": self.options.to_dict(),
            "notes": list(self.notes),
        }

    def summary(self) -> str:
        f = self.filtered
        lines = [f"{self.channel}: {self.samples} samples at {self.rate_hz:g} Hz; " + self.pre.summary(),
                 "checks: " + self.checks.summary(), self.selection.summary(), self.kalman.summary(),
                 f.summary() + f"; smoother → {self.smoothed.variance_after:.4g} ({self.unit})^2",
                 "response to motion: " + ", ".join(f"{fr:g} Hz ×{g:.3f}" for fr, g in
                                                   zip(self.response.freq_hz, self.response.magnitude))]
        if self.adequacy is not None:
            lines.append(self.adequacy.summary())
        return "\n".join(lines)


def analyse_arma(x, rate_hz: float, *, channel: str, options: ArmaOptions | None = None,
                 response_freq_hz=None) -> ArmaAnalysis:
    """Run the pipeline on the series ``x`` (SI, sampled at ``rate_hz``).

    ``response_freq_hz``: where to evaluate the filter's response to motion (default 0, 0.1, 1,
    10 Hz and a quarter of the rate, as the CLI prints; ``"dense"`` = 513 points 0…rate/2).
    """
    if not isinstance(channel, str):
        raise InputError(f"channel is not a name (type {type(channel).__name__})", field="channel", value=channel,
                         expected="a channel name such as 'gyro_x' or 'accel_z'")
    if isinstance(rate_hz, bool) or not isinstance(rate_hz, numbers.Real):
        raise InputError(f"the sampling rate is not a number (type {type(rate_hz).__name__})", field="rate_hz",
                         value=rate_hz, expected="a sampling rate in Hz, > 0")
    opt = options or ArmaOptions()
    if not isinstance(opt, ArmaOptions):
        raise InputError(f"not ArmaOptions (type {type(opt).__name__})", field="options", value=opt,
                         expected="budget.noise.pipeline.ArmaOptions or None")
    raw = float_series(x, channel, f"a 1-D array of numbers ({channel_si_unit(channel)})")
    if raw.ndim != 1:
        raise InputError(f"the series has shape {raw.shape}", field=channel, expected="a 1-D series")
    bad = np.flatnonzero(~np.isfinite(raw))
    if bad.size:  # named as such, not as a value beyond the log limits (inf) or as "x" (NaN)
        raise InputError(f"{bad.size} non-finite sample(s) (NaN or ±inf), first at index {bad[0]}",
                         field=channel, value=raw[bad[0]],
                         expected=f"finite values (repair the log first: {REPAIR_WAY.cli}, or drop the rows)")
    if raw.size < MIN_SAMPLES:  # one minimum for the whole pipeline (the checks need fewer)
        raise InputError(f"only {raw.size} samples", field=channel,
                         expected=f"at least {MIN_SAMPLES} samples for ARMA modelling")
    limit = max_abs_si(channel)
    with np.errstate(invalid="ignore"):
        big = np.flatnonzero(np.abs(raw) > limit)
    if big.size:  # a corrupt sample or a wrong unit (and its square would overflow: 1e300)
        raise InputError(f"{big.size} sample(s) beyond ±{limit:g} {channel_si_unit(channel)} (in SI), first "
                         f"at index {big[0]}", field=channel, value=raw.flat[big[0]],
                         expected="a series in SI (corrupt sample or wrong unit?)")
    if np.ptp(raw) > 0:
        check_magnitude(raw, channel)  # e.g. rms 1e-300: Pauta's σ underflowed to 0
    pre = preprocess(raw, pauta_k=opt.pauta_k, replace=opt.replace, detrend_order=opt.detrend_order,
                     unit=channel_si_unit(channel))
    if np.ptp(pre.x) <= 1e-9 * np.max(np.abs(raw)):  # what is left is round-off, not noise
        if pre.outliers.size and np.ptp(raw) > 0:
            # the variation was a few isolated samples, all replaced by the outlier step
            raise InputError(f"the channel's only variation is {pre.outliers.size} isolated sample(s) "
                             f"(first at index {pre.outliers[0]}) that the Pauta step (k = {opt.pauta_k:g}) "
                             "replaced as outliers: nothing is left to model", field=channel,
                             expected="a channel of a static IMU log with noise (or pauta_k=None, "
                                      "--no-outliers, to model the spikes themselves)")
        raise InputError("the channel holds no noise to model: it is constant (stuck or unused "
                         f"sensor) or an exact degree-{opt.detrend_order} trend", field=channel,
                         expected="a channel of a static IMU log with noise")
    checks = check_series(pre.x, detrend_order=opt.detrend_order)  # ADF with the trend removed
    try:
        sel = select_arma(pre.x, opt.orders, opt.method, demean=False, unit_root_p=checks.adf_p)
    except InputError as err:  # about the preprocessed channel: name it
        raise InputError(err.reason, field=channel, value=err.value, expected=err.expected) from None
    kf = ArmaKalman(sel.selected, process_noise=opt.process_noise)
    if response_freq_hz is None:
        freqs = [0.0, 0.1, 1.0, 10.0, rate_hz / 4]
    elif isinstance(response_freq_hz, str) and response_freq_hz == "dense":
        freqs = None
    else:
        freqs = response_freq_hz
    filtered = kf.filter(pre.x)
    return ArmaAnalysis(channel=channel, rate_hz=float(rate_hz), raw=raw, pre=pre, checks=checks,
                        selection=sel, kalman=kf, filtered=filtered, smoothed=kf.smooth(pre.x),
                        response=frequency_response(kf, rate_hz, freqs), options=opt,
                        adequacy=model_adequacy(sel.selected, kf, pre.x, filtered, unit=channel_si_unit(channel)))
