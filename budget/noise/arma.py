"""ARMA candidates, their AIC/FPE table and the selection (seed 000 §3.1, Table 1).

Candidates default to white noise (p = q = 0) and the paper's AR(1), AR(2), AR(3), ARMA(1,1),
ARMA(2,1) (any p, q ≤ 3). Without the white candidate a white series cannot be called white: on
pure white noise (30,000 samples) AIC picked AR(1), AR(2) or an ARMA(1,1) with near-cancelling
roots (φ = −0.93, θ = +0.93) — each "significant" only by the criterion's penalty — where
statsmodels' own AIC and this one both rank white first.
Estimation: ``method="ls"`` — conditional least squares (:mod:`.arma_ls`, what the paper does);
``method="mle"`` — exact Gaussian maximum likelihood by statsmodels' state-space ARIMA, started
from the least-squares estimate.

Criteria (normalised by the number n of residuals, as MATLAB's ``aic``/``fpe`` that the paper
used): AIC = ln σ̂² + 2k/n and FPE = σ̂² (n + k)/(n − k), with k = p + q (σ² not counted).
The selected model minimises AIC among the stationary and invertible candidates whose AR and
MA roots do not cancel (:data:`REDUNDANT_PAIR_DB`; FPE's choice is reported too). By least
squares every candidate's residuals run over the same samples, from the largest p on
(n = N − max p): with each its own (N − p), AR(1) data picked AR(1) in 71 % of 2,000 simulated
series instead of the asymptotic 79 % (Shibata's rate among AR(1..3)); on one sample set,
79.6 %. ``method="mle"`` fits the series scaled to unit rms (statsmodels' optimiser did not move
from its start values at IMU magnitudes). Note the paper's Table 1 is not self-consistent under
these definitions: ln(FPE) of ARMA(2,1) is −4.871, not −4.948, and its FPE 0.007666 is below the
σ² 0.007778 it
reports (FPE ≥ σ̂² by definition).
"""

from __future__ import annotations

import math
import numbers
import warnings
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import InputError
from .arguments import float_series
from .arma_ls import fit_ls, max_root_modulus

#: The candidates of seed 000 (Table 1).
PAPER_ORDERS = ((1, 0), (2, 0), (3, 0), (1, 1), (2, 1))
#: White noise (0, 0) first, then the paper's candidates.
DEFAULT_ORDERS = ((0, 0), *PAPER_ORDERS)
#: Largest AR or MA order p, q of a candidate (the paper's candidates reach 3).
MAX_ORDER = 3
MIN_SAMPLES = 100
#: A series whose rms lies outside this range (in its own unit) is refused: its variance, and the
#: products of variances the fits and the filter form, would under- or overflow float64.
RMS_RANGE = (1e-100, 1e100)
#: A candidate whose residual variance is below this fraction of the series' variance predicts
#: the series almost exactly: a deterministic signal (a sinusoid, a periodic pattern), not noise.
DETERMINISTIC_RATIO = 1e-9
#: The selected model's record length in correlation times, n·(1 − ρ) with ρ the largest AR root,
#: below which a note says the model is doubtful (the relative standard error of the series'
#: variance is about √(2/(n(1 − ρ))) for ρ → 1, 20 % at 50; least squares biases ρ low).
MIN_CORRELATION_TIMES = 50.0
#: An AR root and an MA root whose pair changes the model's spectrum by less than this (dB, at
#: every frequency) cancel: the candidate is the lower-order model without the pair, its two
#: extra parameters fitted to noise (parameter redundancy, Box & Jenkins §7.3.5). 0.5 dB is about
#: the scatter of a periodogram averaged over 100 segments (4.34/√K dB): a spectrum no record of
#: ordinary length can tell apart from the lower order's.
REDUNDANT_PAIR_DB = 0.5
#: Level of the ADF test below which a unit root is rejected (the checks' α).
UNIT_ROOT_ALPHA = 0.05


def order_name(p: int, q: int) -> str:
    if p == q == 0:
        return "white"
    return f"AR({p})" if q == 0 else (f"MA({q})" if p == 0 else f"ARMA({p},{q})")


@dataclass(frozen=True)
class ArmaFit:
    """One fitted ARMA(p, q): x(k) = Σφᵢx(k−i) + w(k) + Σθⱼw(k−j), var w = σ² (seed 000 (11)).

    ``data_variance`` is the variance of the series it was fitted to (δ₂ of the Kalman filter,
    seed 000 §3.2); ``stderr`` the asymptotic standard errors of (φ, θ).
    """

    p: int
    q: int
    phi: np.ndarray
    theta: np.ndarray
    sigma2: float
    n: int
    method: str
    data_variance: float
    stderr: np.ndarray
    converged: bool = True
    notes: tuple[str, ...] = ()

    @property
    def name(self) -> str:
        return order_name(self.p, self.q)

    @property
    def k(self) -> int:
        return self.p + self.q

    @property
    def aic(self) -> float:
        return math.log(self.sigma2) + 2.0 * self.k / self.n

    @property
    def fpe(self) -> float:
        return self.sigma2 * (self.n + self.k) / (self.n - self.k)

    @property
    def ar_root_max(self) -> float:
        """Largest |root| of z^p − φ₁z^{p−1} − … − φ_p (stationary when < 1)."""
        return max_root_modulus(self.phi, -1.0)

    @property
    def ma_root_max(self) -> float:
        """Largest |root| of z^q + θ₁z^{q−1} + … + θ_q (invertible when < 1)."""
        return max_root_modulus(self.theta, +1.0)

    @property
    def cancelling_pair_db(self) -> float:
        """The least spectral effect (dB, largest over frequency) of any pair of one AR and one MA
        root: |e^{jω} − b|² / |e^{jω} − a|² on 512 frequencies in [0, π]; ∞ without a pair (p or q 0)."""
        if self.p == 0 or self.q == 0:
            return math.inf
        ar = np.roots(np.r_[1.0, -np.asarray(self.phi, float)])
        ma = np.roots(np.r_[1.0, np.asarray(self.theta, float)])
        z = np.exp(1j * np.linspace(0.0, math.pi, 512))
        effect = [float(np.max(np.abs(10.0 * np.log10(np.abs(z - b) ** 2 / np.maximum(np.abs(z - a) ** 2, 1e-300)))))
                  for a in ar for b in ma]
        return min(effect)

    @property
    def redundant(self) -> bool:
        """True when an AR and an MA root cancel (:data:`REDUNDANT_PAIR_DB`)."""
        return self.cancelling_pair_db < REDUNDANT_PAIR_DB

    @property
    def stationary(self) -> bool:
        return self.ar_root_max < 1.0

    @property
    def invertible(self) -> bool:
        return self.ma_root_max < 1.0

    def params(self) -> dict:
        return {"phi": [float(v) for v in self.phi], "theta": [float(v) for v in self.theta],
                "sigma2": float(self.sigma2)}

    def to_dict(self) -> dict:
        return {"order": self.name, "p": self.p, "q": self.q, "aic": self.aic, "fpe": self.fpe,
                "params": self.params(), "stderr": [float(v) for v in self.stderr],
                "stationary": self.stationary, "invertible": self.invertible,
                "ar_root_max": self.ar_root_max, "ma_root_max": self.ma_root_max,
                "method": self.method, "n": self.n, "converged": self.converged,
                "notes": list(self.notes)}

    def to_frame(self) -> pd.DataFrame:
        names = [f"phi{i + 1}" for i in range(self.p)] + [f"theta{j + 1}" for j in range(self.q)]
        return pd.DataFrame({"parameter": names + ["sigma2"],
                             "value": [*self.phi, *self.theta, self.sigma2],
                             "stderr": [*self.stderr, np.nan]})

    def summary(self) -> str:
        terms = " ".join([f"{v:+.4f}·x(k−{i + 1})" for i, v in enumerate(self.phi)]
                         + ["+ w(k)"] + [f"{v:+.4f}·w(k−{j + 1})" for j, v in enumerate(self.theta)])
        return (f"{self.name} [{self.method}]: x(k) = {terms}, σ² = {self.sigma2:.6g}; AIC "
                f"{self.aic:.4f}, FPE {self.fpe:.6g}; AR root max {self.ar_root_max:.4f}"
                f"{'' if self.stationary else ' (NOT stationary)'}, MA root max {self.ma_root_max:.4f}"
                f"{'' if self.invertible else ' (NOT invertible)'}")


@dataclass(frozen=True)
class ArmaSelection:
    """All candidates, the selected model and which one FPE would pick."""

    candidates: tuple[ArmaFit, ...]
    selected: ArmaFit
    by_fpe: ArmaFit
    mean_removed: float
    notes: tuple[str, ...] = field(default_factory=tuple)

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame([{**{k: v for k, v in c.to_dict().items() if k not in ("params", "notes")},
                              "phi": list(c.phi), "theta": list(c.theta), "sigma2": c.sigma2,
                              "selected": c is self.selected} for c in self.candidates])

    def to_dict(self) -> dict:
        return {"candidates": [c.to_dict() for c in self.candidates], "selected": self.selected.name,
                "selected_by_fpe": self.by_fpe.name, "mean_removed": self.mean_removed,
                "notes": list(self.notes)}

    def summary(self) -> str:
        lines = [f"{'model':<10}{'AIC':>10}{'FPE':>14}  stationary invertible"]
        for c in self.candidates:
            mark = " *" if c is self.selected else ""
            lines.append(f"{c.name:<10}{c.aic:>10.4f}{c.fpe:>14.6g}  {str(c.stationary):<10} "
                         f"{c.invertible}{mark}")
        lines.append("selected: " + self.selected.summary())
        if self.by_fpe is not self.selected:
            lines.append(f"FPE would select {self.by_fpe.name}")
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)


def _check_series(x, name: str = "x") -> np.ndarray:
    x = float_series(x, name, "a 1-D array of samples (SI for IMU channels)")
    if x.ndim != 1:
        raise InputError("expected a 1-D series", field=name, value=f"shape {x.shape}")
    bad = np.flatnonzero(~np.isfinite(x))
    if bad.size:
        raise InputError(f"{bad.size} non-finite sample(s), first at index {bad[0]}", field=name,
                         expected="finite values (repair the log first)")
    if x.size < MIN_SAMPLES:
        raise InputError(f"only {x.size} samples", field=name,
                         expected=f"at least {MIN_SAMPLES} samples for ARMA modelling")
    if np.ptp(x) == 0:
        raise InputError("series is constant (no noise to model)", field=name)
    check_magnitude(x, name)
    return x


def check_magnitude(x: np.ndarray, name: str = "x") -> None:
    """:class:`InputError` (field ``name``) unless the rms of the finite, non-constant series
    ``x`` about its mean lies within :data:`RMS_RANGE` (its variance must be representable)."""
    big = float(np.max(np.abs(x)))
    if not big > 0:
        return
    # scaled by a power of two (exact) so that the rms itself cannot under- or overflow
    e = int(np.frexp(big)[1])
    xs = np.ldexp(x, -e)
    rms = float(np.ldexp(np.sqrt(np.mean(np.square(xs - xs.mean()))), e))
    lo, hi = RMS_RANGE
    if not lo <= rms <= hi:
        raise InputError(f"the series' rms {rms:.3g} is outside {lo:g} … {hi:g}: its variance "
                         "is not representable in double precision", field=name, value=f"rms {rms:.3g}",
                         expected="a series in a physical unit (SI for IMU channels)")


def check_orders(orders) -> tuple[tuple[int, int], ...]:
    """Candidate orders as a tuple of whole (p, q), each once; :class:`InputError` (field
    ``orders``) unless 0 ≤ p, q ≤ :data:`MAX_ORDER` ((0, 0) is white noise) — the one home of the limit
    (:func:`select_arma`, :func:`fit_arma` and :class:`~budget.noise.pipeline.ArmaOptions`)."""
    expected = f"pairs (p, q) of whole numbers, 0 ≤ p, q ≤ {MAX_ORDER} ((0, 0): white noise)"
    if isinstance(orders, (str, bytes)) or not isinstance(orders, Iterable):
        raise InputError("orders must be a list of pairs (p, q)", field="orders", value=orders, expected=expected)
    out = []
    for o in orders:
        try:
            p, q = o
        except (TypeError, ValueError):
            raise InputError("order must be a pair (p, q)", field="orders", value=o, expected=expected) from None
        if not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in (p, q)):
            raise InputError("order must be a pair (p, q) of whole numbers", field="orders", value=o,
                             expected=expected)
        p, q = int(p), int(q)
        if not (0 <= p <= MAX_ORDER and 0 <= q <= MAX_ORDER):
            raise InputError(f"orders must have 0 ≤ p, q ≤ {MAX_ORDER}", field="orders",
                             value=(p, q), expected=expected)
        out.append((p, q))
    if not out:
        raise InputError("no candidate orders", field="orders")
    return tuple(dict.fromkeys(out))


def fit_arma(x, p: int, q: int, method: str = "ls", *, start: int | None = None) -> ArmaFit:
    """Fit ARMA(p, q) to the zero-mean series ``x`` by ``ls`` or ``mle``.

    ``start`` (least squares): first sample whose residual counts, default p; candidates that are
    compared must share it (:func:`select_arma` passes the largest p). :class:`InputError` if
    the model predicts ``x`` almost exactly (:data:`DETERMINISTIC_RATIO`: not noise)."""
    x = _check_series(x)
    (p, q), = check_orders([(p, q)])
    if method not in ("ls", "mle"):
        raise InputError(f"unknown method {method!r}", field="method", expected="ls or mle")
    if start is not None and not (isinstance(start, numbers.Integral) and p <= start < x.size - MIN_SAMPLES // 2):
        raise InputError("start must be a whole number from p on, leaving the samples to fit",
                         field="start", value=start, expected=f"{p} ≤ start < {x.size - MIN_SAMPLES // 2}")
    ls = fit_ls(x, p, q, start=start)
    var = float(np.var(x))
    if not ls.sigma2 > DETERMINISTIC_RATIO * var:
        raise InputError(f"{order_name(p, q)} predicts the series almost exactly (residual variance "
                         f"{ls.sigma2 / var:.2g} of the series' variance): it is a deterministic "
                         "signal (a sinusoid, a periodic or alternating pattern), not noise",
                         field="x", expected="a noise record (static IMU output)")
    if method == "ls":
        return ArmaFit(p, q, ls.phi, ls.theta, ls.sigma2, ls.n, "ls", var,
                       np.sqrt(np.diag(ls.cov)), ls.converged,
                       () if ls.converged else ("least squares did not converge",))
    return _fit_mle(x, p, q, ls, var)


def _fit_mle(x: np.ndarray, p: int, q: int, ls, var: float) -> ArmaFit:
    from statsmodels.tsa.arima.model import ARIMA  # exact Gaussian likelihood (state space)

    # statsmodels' optimiser works on the likelihood's own scale: at IMU magnitudes (variance
    # ~1e-6 (rad/s)²) it stopped at the start values, so the "MLE" was the LS estimate, flagged
    # unconverged. Fit the series scaled to unit rms (a power of two: exact) and scale σ² back.
    e = int(np.round(np.log2(np.sqrt(var))))
    xs = np.ldexp(x, -e)
    s2 = 4.0 ** e
    start = np.r_[ls.phi, ls.theta, ls.sigma2 / s2]
    ok = max_root_modulus(ls.phi, -1.0) < 1.0 and max_root_modulus(ls.theta, +1.0) < 1.0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = ARIMA(xs, order=(p, 0, q), trend="n").fit(start_params=start if ok else None)
    notes = tuple(sorted({str(w.message).split("\n")[0][:120] for w in caught}))
    params = np.asarray(res.params, float)
    bse = np.asarray(res.bse, float)[:p + q]
    converged = bool(res.mle_retvals.get("converged", True)) if res.mle_retvals else True
    return ArmaFit(p, q, params[:p], params[p:p + q], float(params[-1]) * s2, x.size, "mle", var,
                   bse, converged, notes + (() if converged else ("maximum likelihood did not converge",)))


def select_arma(x, orders=DEFAULT_ORDERS, method: str = "ls", *, demean: bool = True,
                unit_root_p: float | None = None) -> ArmaSelection:
    """Fit every candidate order and select by AIC (stationary and invertible models first).

    ``unit_root_p``: the p-value of the series' ADF test (:func:`budget.noise.checks.adf_test`,
    as the pipeline's checks made it); None: made here when the record is short for the selected
    model's correlation time, which is when it decides what the note on it says."""
    x = _check_series(x)
    orders = check_orders(orders)
    mean = float(x.mean()) if demean else 0.0
    xc = x - mean if demean else x
    # one residual set for every candidate (least squares): from the largest p on (arma_ls)
    start = max(p for p, _ in orders)
    fits = tuple(fit_arma(xc, p, q, method, start=start) for p, q in orders)
    valid = [f for f in fits if f.stationary and f.invertible] or list(fits)
    notes = []
    if len(valid) < len(fits):
        notes.append("not stationary or not invertible, not eligible: "
                     + ", ".join(f.name for f in fits if f not in valid))
    plain = [f for f in valid if not f.redundant]
    if plain and len(plain) < len(valid):
        first = min(valid, key=lambda f: f.aic)
        if first.redundant:  # said only where it changes the choice (most series have such a candidate)
            notes.append(f"AIC's lowest, {first.name}, has an AR and an MA root that cancel (the pair changes "
                         f"the spectrum by {first.cancelling_pair_db:.2g} dB < {REDUNDANT_PAIR_DB:g} dB: a lower "
                         "order in disguise, its two extra parameters fitted to noise); not eligible")
        valid = plain
    if not any(f.stationary and f.invertible for f in fits):
        notes.append("no candidate is both stationary and invertible; selected among all")
    best = min(valid, key=lambda f: f.aic)
    best_fpe = min(valid, key=lambda f: f.fpe)
    if not best.converged:
        notes.append(f"the selected {best.name} did not converge ({best.method}): its parameters "
                     "are the last iterate, not the estimate")
    if best.p == best.q == 0:
        notes.append("white noise selected: the samples are uncorrelated at AIC's resolution, so a "
                     "Kalman filter has no correlation to use — it only scales the measurement by its "
                     "gain (real motion too), and its variance reduction is that scaling, not noise removed")
    times = x.size * (1.0 - best.ar_root_max)
    if best.stationary and times < MIN_CORRELATION_TIMES:
        if unit_root_p is None:  # a random walk's record is "short" at any length: tell which
            from .checks import ADF_MAX_LAG, adf_test, decorrelation_lag
            unit_root_p = adf_test(xc, min(decorrelation_lag(xc), ADF_MAX_LAG), "c")[1]
        text = (f"record short for the model's correlation time: largest AR root ρ = "
                f"{best.ar_root_max:.4f}, n(1 − ρ) = {times:.0f} correlation times (expected ≥ "
                f"{MIN_CORRELATION_TIMES:g}); the series' variance (R of the filter) is uncertain "
                f"by about {100 * math.sqrt(2.0 / max(times, 1e-9)):.0f} % and ρ is biased low")
        if unit_root_p >= UNIT_ROOT_ALPHA:
            # n(1 − ρ̂) of a random walk does not grow with n (ρ̂ → 1 as fast): no record is long enough
            text += (f" — but ADF cannot reject a unit root (p = {unit_root_p:.3g}): the series may be a "
                     "random walk, for which a longer record does not help; characterise it with the "
                     "Allan variance as rate random walk instead (sar-budget noise characterize)")
        else:
            text += (" — a longer record is needed"
                     + (" (ρ near 1: a random walk, rate random walk, may describe it better)"
                        if best.ar_root_max > 0.99 else ""))
        notes.append(text)
    return ArmaSelection(fits, best, best_fpe, mean, tuple(notes))
