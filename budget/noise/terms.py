"""IEEE Std 952 noise-term fit of an Allan deviation.

Model (IEEE Std 952-1997 Annex C, rate data; the terms add in the variance domain):

    σ²(τ) = 3Q²/τ² + N²/τ + (2 ln2/π) B² + K² τ/3 + R² τ²/2

Q quantization (unit·s: rad or m/s), N white rate noise (unit·√s: rad/√s = rad/s/√Hz, ARW /
VRW), B bias instability (unit; Allan floor = √(2 ln2/π) B ≈ 0.664 B), K rate random walk
(unit/√s), R rate ramp (unit/s).

The coefficients c = (Q², N², B², K², R²) are fitted by non-negative weighted least squares in
the variance domain. Weights are 1/var(σ̂²) with var(σ̂²) = σ⁴ (2/edf + ε²): the χ² variance
behind the confidence intervals plus a relative *model-error floor* ε (default 5 %). Without
the floor the short-τ points of a long record (±0.2 % intervals) decide every term, and real
sensors — filtered, quantized, with small periodic components — rarely follow the five-term
model that closely (on the published ADIS16405 Allan curves ε = 0 gives bias instabilities
30–50 % high; any ε in 2–20 % gives nearly the same answer). The weights are iterated three
times with σ² taken from the model (a low noisy point does not pull the fit). Correlation between overlapping τ is neglected, so the
quoted uncertainties (from the inverse weighted normal matrix of the active terms, mapped to
the coefficients by the delta method) are optimistic.

A term is *resolved* when (1) its variance coefficient exceeds twice its standard error and
(2) it stands out of the curve's own uncertainty over at least an octave of τ: its share of the
fitted σ² exceeds :data:`RESOLVE_Z` times the relative standard deviation of σ̂² at that τ,
√(2/edf + ε²) — the degrees of freedom of each point itself, so a term seen only at the last,
few-dof points of a curve is not resolved (IEEE 952 Annex C; Lawrence & Lesso). Test (1) alone
treats overlapping-τ points as independent: on 40 simulated records each (two generators,
20 seeds each) it called a term the truth lacks resolved on 2/40 white-noise, 3/40 white +
random-walk and 1/40 white + flicker curves, and a FOG's bias instability (only beyond the
longest τ) resolved at 1.8–2.4× the truth on 6/40; with (2), none of these
(``tests/test_adev_limits.py``). **Not removed**: a record whose white-noise / random-walk
crossover lies inside the curve with several octaves of random walk after it (measured: ARW
0.15 deg/√h, RRW 10 deg/h/√h, crossover at 93 s, 2 h at 50 Hz, no flicker, 40 seeds) gets a
bias instability *resolved* on 4/40, its floor 0.664·B at 57–64 % of the true Allan minimum and
K 20–45 % low on those records (K −11 % over all 40, its quoted σ ≈ 1.5× too small): near the
crossover the flat B column and a lower K trade against each other, and the points' correlation
is not in (1). A parametric bootstrap of (1) under the fit without B (39 records drawn from it)
kept 3 of the 4: those curves are the null's own tail at the nominal level, so only a joint
(correlated-τ) likelihood or a stricter level would remove them; neither is built. A term
fitted to exactly zero is *absent* (None).

A term not resolved gets an *upper limit* (``limits``) from the curve alone: every term's
IEEE-952 variance c·f(τ) is ≥ 0, so c·f(τ) ≤ σ²(τ) at every τ and
c ≤ minτ σ²_up(τ)/f(τ), σ²_up the one-sided upper confidence bound of σ̂² from the point's
EDF, σ̂²·edf/χ²_a(edf): Q ≤ min σ_up·τ/√3, N ≤ min σ_up·√τ, B ≤ min σ_up/0.664,
K ≤ min σ_up·√(3/τ), R ≤ min σ_up·√2/τ. Each of the n points is bounded at a = (1 − level)/n
(Bonferroni), so that all hold together at :data:`LIMIT_LEVEL` and the minimum over τ keeps that
level: with each point at 95 % the minimum covered a true K at the edge of the curve on only
37/40 simulated records, with the joint level on 40/40 (limits ~1.3× wider;
``tests/test_adev_limits.py``). A digitised curve (no record, ``edf`` = ∞)
has no confidence level: the limits are the curve's own values, and a term is resolved when it
stands out of the model-error floor ε alone (its uncertainty is unknown: ``sigmas`` None).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.optimize import nnls

from ..errors import InputError
from .allan import AllanResult

TERMS = ("Q", "N", "B", "K", "R")
FLICKER = 2.0 * math.log(2.0) / math.pi
#: The two bias-instability quantities, named here once and so wherever either is printed: the
#: IEEE-952 coefficient B of a channel's fit (SI) and the Allan-deviation floor it sets,
#: √(2 ln2/π)·B ≈ 0.664·B — the catalog's column (convention ``adev_min``, what vendors quote).
#: One name for both read "bias instability 3.37 deg/h" beside "bias instability 2.46e-05 rad/s"
#: (5.07 deg/h): two numbers, one name.
B_NAME = "bias instability coefficient B"
FLOOR_NAME = "bias instability (Allan floor 0.664·B)"
TERM_NAMES = {"Q": "quantization", "N": "white noise (ARW/VRW)", "B": B_NAME,
              "K": "rate random walk", "R": "rate ramp"}
#: Width of the name column of :meth:`NoiseTerms.summary`.
_NAME_WIDTH = max(len(n) for n in TERM_NAMES.values())
#: A term must exceed this many standard deviations of σ̂² (relative, at each τ) … over
RESOLVE_Z = 2.0
#: … a τ span of at least this ratio (an octave) to be resolved (module doc).
RESOLVE_SPAN = 2.0
#: One-sided confidence level of the upper limit of a term not resolved (module doc).
LIMIT_LEVEL = 0.95


def _design(tau: np.ndarray, terms: tuple[str, ...]) -> np.ndarray:
    cols = {"Q": 3.0 / tau ** 2, "N": 1.0 / tau, "B": np.full(tau.shape, FLICKER),
            "K": tau / 3.0, "R": tau ** 2 / 2.0}
    return np.column_stack([cols[t] for t in terms])


def adev_model(tau_s, Q=0.0, N=0.0, B=0.0, K=0.0, R=0.0) -> np.ndarray:
    """Allan deviation of the IEEE-952 model at ``tau_s`` (closed form, see module doc)."""
    tau = np.asarray(tau_s, dtype=float)
    var = 3 * Q ** 2 / tau ** 2 + N ** 2 / tau + FLICKER * B ** 2 + K ** 2 * tau / 3 + R ** 2 * tau ** 2 / 2
    return np.sqrt(var)


def term_units(unit: str) -> dict[str, str]:
    """Units of Q, N, B, K, R for a channel whose rate unit is ``unit`` (rad/s, m/s², …)."""
    u = unit or "u"
    return {"Q": f"{u}·s", "N": f"{u}·√s", "B": u, "K": f"{u}/√s", "R": f"{u}/s"}


@dataclass(frozen=True)
class NoiseTerms:
    """Fitted IEEE-952 coefficients of one channel (``None`` = absent or not fitted)."""

    values: dict[str, float | None]
    sigmas: dict[str, float | None]
    resolved: dict[str, bool]
    channel: str | None
    unit: str
    tau_range_s: tuple[float, float]
    chi2: float
    dof: int
    #: upper limit of each term not resolved (``None`` for a resolved term), from the curve and
    #: its one-sided upper confidence bound at ``limit_level`` (module doc)
    limits: dict[str, float | None] | None = None
    #: confidence level of ``limits``; ``None`` for a digitised curve (limits from its values)
    limit_level: float | None = LIMIT_LEVEL
    #: False for a digitised curve: no record behind it, the fitted values' uncertainty is unknown
    uncertainty_known: bool = True

    Q = property(lambda self: self.values["Q"])
    N = property(lambda self: self.values["N"])
    B = property(lambda self: self.values["B"])
    K = property(lambda self: self.values["K"])
    R = property(lambda self: self.values["R"])

    @property
    def bias_instability_floor(self) -> float | None:
        """Allan-deviation floor of the flicker term, √(2 ln2/π)·B (vendors' usual number)."""
        return None if self.B is None else math.sqrt(FLICKER) * self.B

    def model_adev(self, tau_s) -> np.ndarray:
        return adev_model(tau_s, **{k: (v or 0.0) for k, v in self.values.items()})

    def to_dict(self) -> dict:
        """JSON-ready: channel, unit, the τ range fitted (s), the coefficients Q, N, B, K, R under
        ``values`` with their 1σ and whether each is resolved, and the fit's χ² and dof."""
        return {"channel": self.channel, "unit": self.unit, "tau_range_s": [float(v) for v in self.tau_range_s],
                "values": dict(self.values), "sigmas": dict(self.sigmas), "resolved": dict(self.resolved),
                "limits": dict(self.limits or {}), "limit_level": self.limit_level,
                "uncertainty_known": self.uncertainty_known,
                "chi2": float(self.chi2), "dof": int(self.dof)}

    def limit_text(self, term: str, value: float | None = None, unit: str | None = None) -> str:
        """``'≤ 3.1e-06 rad/s/√s at 95 %'`` for a term not resolved (``value``/``unit``: the
        limit converted by the caller); '' when the term has no limit."""
        lim = (self.limits or {}).get(term)
        if lim is None:
            return ""
        v = lim if value is None else value
        level = (f"at {100 * self.limit_level:.3g} %" if self.limit_level is not None
                 else "from the digitised curve's values, no confidence level")
        return f"≤ {v:.3g} {unit or term_units(self.unit)[term]} {level}"

    def to_frame(self) -> pd.DataFrame:
        units = term_units(self.unit)
        return pd.DataFrame([{"term": t, "name": TERM_NAMES[t], "value": self.values[t],
                              "sigma": self.sigmas[t], "resolved": self.resolved[t],
                              "upper_limit": (self.limits or {}).get(t), "unit": units[t]} for t in TERMS])

    def summary(self) -> str:
        units = term_units(self.unit)
        lines = [f"{self.channel or 'series'}: IEEE-952 fit over τ {self.tau_range_s[0]:.4g}–"
                 f"{self.tau_range_s[1]:.4g} s, χ²/dof = {self.chi2:.3g}/{self.dof}"]
        if not self.uncertainty_known:
            lines[0] += " (digitised curve: no record behind it, uncertainty unknown)"
        for t in TERMS:
            v, s = self.values[t], self.sigmas[t]
            lim = self.limit_text(t)
            if v is None:
                lines.append(f"  {t} {TERM_NAMES[t]:<{_NAME_WIDTH}} absent"
                             + (f", not resolved: {lim}" if lim else ""))
            else:
                # resolved = value² ≥ 2σ from 0 and above the curve's uncertainty over an octave
                # (module doc); the ± is the value's own 1σ
                flag = "" if self.resolved[t] else f"  (not resolved: {lim})" if lim else "  (not resolved)"
                err = f" ± {s:.3g}" if s is not None else ""
                # B is not the catalog's figure: its Allan floor is, said beside it in the same unit
                floor = f" (Allan floor 0.664·B = {math.sqrt(FLICKER) * v:.4g} {units[t]})" if t == "B" else ""
                lines.append(f"  {t} {TERM_NAMES[t]:<{_NAME_WIDTH}} {v:.4g}{err} {units[t]}{floor}{flag}")
        return "\n".join(lines)


def fit_noise_terms(allan: AllanResult, terms: Iterable[str] = TERMS, *,
                    tau_range_s: tuple[float, float] | None = None, iterations: int = 3,
                    model_error: float = 0.05) -> NoiseTerms:
    """Fit the IEEE-952 terms ``terms`` (subset of Q, N, B, K, R) to ``allan``.

    ``tau_range_s`` restricts the τ used; ``model_error`` is the relative floor ε on the
    uncertainty of each σ² (see module doc; 0 = pure χ² weights).
    """
    if not isinstance(allan, AllanResult):
        raise InputError(f"not an Allan deviation (type {type(allan).__name__})", field="allan",
                         value=allan, expected="the AllanResult of budget.noise.allan_deviation (or read_adev_table)")
    if not (isinstance(model_error, numbers.Real) and math.isfinite(model_error) and model_error >= 0):
        raise InputError("model_error must be ≥ 0", field="model_error", value=model_error)
    terms = tuple(terms)
    bad = [t for t in terms if t not in TERMS]
    if bad or not terms:
        raise InputError(f"unknown noise term(s) {bad}", field="terms", expected="a subset of Q N B K R")
    tau, adev, edf = allan.tau_s, allan.adev, allan.edf
    keep = np.isfinite(adev) & (adev > 0) & ~np.isnan(edf) & (edf > 0)  # edf = ∞: digitised
    if tau_range_s is not None:
        try:
            lo, hi = (float(v) for v in tau_range_s)
        except (TypeError, ValueError):
            lo = hi = math.nan
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi):
            raise InputError("tau_range_s must be two increasing τ values", field="tau_range_s",
                             value=tau_range_s, expected="(τ_min, τ_max) in s, 0 ≤ τ_min < τ_max")
        keep &= (tau >= lo) & (tau <= hi)
    tau, y, edf = tau[keep], adev[keep] ** 2, edf[keep]
    if tau.size < len(terms):
        what = allan.channel or "series"
        if np.all(allan.adev == 0):
            raise InputError("Allan deviation is zero everywhere (constant channel)", field=what)
        raise InputError(f"only {tau.size} usable τ for {len(terms)} terms", field=what,
                         expected="a longer record or fewer terms")
    A = _design(tau, terms)
    ref = y.copy()
    for _ in range(max(1, iterations)):
        sw = 1.0 / (ref * np.sqrt(2.0 / edf + model_error ** 2))  # weight = 1/var(σ̂²)
        Aw, yw = A * sw[:, None], y * sw
        scale = np.linalg.norm(Aw, axis=0)
        scale[scale == 0] = 1.0
        sol, _ = nnls(Aw / scale, yw, maxiter=50 * len(terms))
        c = sol / scale
        model = A @ c
        ref = np.where(model > 0, model, y)
    active = c > 0
    cov = np.full(len(terms), np.nan)
    if active.any():
        As = Aw[:, active] / scale[active]
        inv = np.linalg.pinv(As.T @ As)
        cov[active] = np.diag(inv) / scale[active] ** 2
    resid = (y - A @ c) * sw
    known = not bool(np.all(np.isinf(edf)))  # a digitised curve: no record, no sampling error
    rel = np.sqrt(2.0 / edf + model_error ** 2)  # relative standard deviation of σ̂² per τ
    values, sigmas, resolved = {}, {}, {}
    for t in TERMS:
        values[t], sigmas[t], resolved[t] = None, None, False
    for j, t in enumerate(terms):
        if c[j] > 0:
            values[t] = float(math.sqrt(c[j]))
            sd = math.sqrt(cov[j]) if np.isfinite(cov[j]) else float("nan")
            sigmas[t] = sd / (2.0 * values[t]) if known else None
            share = c[j] * A[:, j] / np.where(model > 0, model, np.inf)
            resolved[t] = bool((c[j] > 2.0 * sd or not known)
                               and _octave_above(tau, share > RESOLVE_Z * rel))
    level = LIMIT_LEVEL if known else None
    limits = upper_limits(tau, y, edf, level)
    limits = {t: (None if resolved[t] else limits[t]) for t in TERMS}
    return NoiseTerms(values, sigmas, resolved, allan.channel, allan.unit,
                      (float(tau[0]), float(tau[-1])), float(resid @ resid),
                      int(tau.size - active.sum()), limits, level, known)


def _octave_above(tau: np.ndarray, above: np.ndarray) -> bool:
    """True when ``above`` holds on consecutive τ spanning at least :data:`RESOLVE_SPAN`."""
    start = None
    for i, ok in enumerate(above):
        if ok and start is None:
            start = i
        if ok and tau[i] / tau[start] >= RESOLVE_SPAN * (1 - 1e-9):
            return True
        if not ok:
            start = None
    return False


def upper_limits(tau, var, edf, level: float | None = LIMIT_LEVEL) -> dict[str, float]:
    """Largest value of each IEEE-952 term the Allan variance ``var`` (σ̂² at ``tau``, with
    ``edf``) allows: c_t ≤ minτ σ²_up(τ)/f_t(τ), σ²_up = σ̂²·edf/χ²_a(edf) the one-sided upper
    bound of each point at a = (1 − ``level``)/n, jointly ``level`` over the n points (σ̂² itself
    for ``level`` None or edf = ∞) — module doc."""
    from scipy import stats

    tau, var, edf = (np.asarray(v, float) for v in (tau, var, edf))
    up = var.copy()
    if level is not None:
        fin = np.isfinite(edf)
        up[fin] = var[fin] * edf[fin] / stats.chi2.ppf((1.0 - level) / tau.size, edf[fin])
    f = _design(tau, TERMS)
    return {t: float(math.sqrt(np.min(up / f[:, k]))) for k, t in enumerate(TERMS)}
