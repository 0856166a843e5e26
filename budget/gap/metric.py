"""The gap metric: standardized differences between measured and simulated signatures.

For one channel, the model is simulated S times at the log's rate and length
(:mod:`budget.gap.simulate`) and every signature of :mod:`budget.gap.signatures` is compared
with the mean over the realizations through a standardized difference z:

* ADEV at each octave τ_k: z = (ln σ̂_meas − mean ln σ̂_model) / s_k,
  s_k² = v_meas,k + v_k/S, v = 1/(2·EDF) (var of ln σ̂ for a χ² estimate with EDF degrees of
  freedom; EDF from NIST SP 1065 Table 5 with the noise type of the *model* curve, or, for a
  measured table, from its published interval);
* PSD in octave bands: z = (ln P̄_meas − ln P̄_model)/√(v_b(1 + 1/S)),
  v_b = 1.056·c(n)/(K·n) for n bins and K Welch segments (1.056: 50 %-overlapped Hann
  segments; c(n) = 1 + (8/9)(n−1)/n + (1/18)(n−2)/n: correlation of adjacent Hann bins);
* PSD line: the largest ratio P_meas/P_model over the bins, p-value from F(ν, S·ν) with
  ν = 2K/1.056, made global over the n bins (1 − (1 − p)ⁿ) and mapped to z = Φ⁻¹(1 − P/2);
* kurtosis of the first differences: z = Δκ / √(v_κ(1 + 1/S)), v_κ = max(27/N, scatter);
* tail count: Freeman–Tukey z = (√c + √(c+1) − √(4μ+1)) / √(D(1 + 1/S)) for a Poisson count c
  of mean μ (dispersion D ≥ 1 from the realizations);
* time slope and temperature coefficient: (meas − mean)/√var with the model's exact mean and
  variance of the statistic (:class:`LinearMoments`, :mod:`budget.gap.regression_var`), a
  normal score; when an effect of the channel has no closed form, Student t with S − 1 degrees
  of freedom from the realizations' mean and scatter (variance × (1 + 1/S)), mapped to a normal
  score (with S = 12 a 5σ trend would read ≈ 3.4σ);
* slow modes (:mod:`budget.gap.walk`): the normal score of a weighted sum of the record's
  slowest whitened modes under the model's exact covariance of them (more slow power than the
  model: z > 0), and beside it the early statistic, the linear projection of the same modes on
  the start-of-record pattern e^(−t/τ₀) (τ₀ = 1/8 of the record), (vᵀy − mean)/√(vᵀCv), which
  tells a turn-on transient (a mean) from slow noise (a spread) (:func:`budget.gap.walk.early_z`;
  a linear statistic, in :data:`LINEAR_KINDS`);
* low-frequency bands (below the first Welch band; when the grid has them): mean c̄² of the
  detrended record's DCT coefficients in octave bands, z = normal score of c̄²_meas/c̄²_model under F(n, S·n)
  (:mod:`budget.gap.lowfreq`).

**Gap** of a channel = mean of z² over its K terms (≈ 1 when the log follows the model), the
spectral terms (ADEV, PSD bands, low-frequency bands) taken decorrelated when the workflow has
fitted a whitening (:mod:`budget.gap.whitening`);
overall gap = mean of the channel gaps. **Null distribution**: each realization in turn is
treated as the measurement and compared with the other S − 1 (leave one out); the covariance C
of those z vectors (pooled over channels, eigenvalues de-biased) makes the gap a weighted
sum of χ²_1 variables, Σλ_i χ²_1/K, whose quantiles come from a four-cumulant noncentral-χ²
match (Liu, Tang & Zhang 2009). A channel is *within noise* below its 1 − α/n_channels
quantile, the overall gap below the 1 − α quantile of the mean of the channels (default
α = 0.01). A drop of Σz² is deflated block by block (:meth:`NullModel.drop`): the correlated
quadratic statistics by their inflation φ, the linear ones (slope, temperature), which a
Gaussian null leaves uncorrelated with them, by their own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import special, stats

from ..noise.allan import edf_simple, noise_type_from_slope
from . import lowfreq, walk
from ..quadform import quadratic_form_quantile
from .signatures import Signature, SignatureGrid, band_counts, band_means
from .theory import Increment

#: Relative variance of one Welch bin (50 % overlap, Hann) per segment.
WELCH_VAR = 1.056
#: Statistics linear in the series (regression coefficients): under a Gaussian null they are
#: uncorrelated with every quadratic one (ADEV, PSD, distribution), odd moments vanishing.
LINEAR_KINDS = ("slope", "temperature", "early")
KINDS = ("adev", "psd_band", "psd_line", "kurtosis", "tails", "tails2", "slope", "temperature",
         "psd_low", "walk", "early")


@dataclass(frozen=True)
class LinearMoments:
    """The model's exact mean and variance of the time slope and of the temperature coefficient
    (``None``: no closed form; :mod:`budget.gap.regression_var`)."""

    slope_mean: float | None
    slope_var: float | None
    temp_mean: float | None = None
    temp_var: float | None = None
    #: the model's covariance of the record's slowest modes (:mod:`budget.gap.walk`)
    walk_cov: np.ndarray | None = None
    #: their mean (a thermal lag's or a warm-up transient's deterministic response; ``None``: zero)
    walk_mean: np.ndarray | None = None

    def covers(self, with_temperature: bool) -> bool:
        ok = self.slope_mean is not None and self.slope_var is not None and self.slope_var > 0
        if with_temperature:
            ok = ok and self.temp_mean is not None and self.temp_var is not None and self.temp_var > 0
        return bool(ok)


@dataclass(frozen=True)
class ModelSummary:
    """Mean signatures of S simulated realizations (what the model predicts for the log)."""

    n_real: int
    avar: np.ndarray
    ln_adev: np.ndarray
    psd: np.ndarray | None = None
    kurtosis: float | None = None
    kurt_var: float = 0.0
    diff_var: float | None = None
    sigma_r: float | None = None
    tails: float | None = None
    tails_disp: float = 1.0
    tails2: float | None = None
    tails2_disp: float = 1.0
    slope: float | None = None
    slope_var: float = 0.0
    temp_coef: float | None = None
    temp_var: float = 0.0
    #: E c_k² of the low-frequency coefficients (unit²): the realizations' mean plus predicted
    #: increments; ``low_sim``: the realizations' part alone (its scatter sets the F score)
    low: np.ndarray | None = None
    low_sim: np.ndarray | None = None
    #: ``slope``/``slope_var`` and ``temp_coef``/``temp_var`` are the model's exact moments
    #: (:class:`LinearMoments`), not the realizations' mean and scatter: the slope and
    #: temperature z are then normal, not Student t with S − 1 degrees of freedom
    linear_exact: bool = False
    #: the model's exact covariance of the slowest modes (:mod:`budget.gap.walk`; ``None``:
    #: no closed form for one of the channel's effects, or no modes)
    walk_cov: np.ndarray | None = None
    #: the model's mean of the slowest modes (``None``: zero; :func:`budget.gap.walk.model_mean`)
    walk_mean: np.ndarray | None = None

    @classmethod
    def from_signatures(cls, sigs: list[Signature], linear: "LinearMoments | None" = None) -> "ModelSummary":
        """Mean signatures of ``sigs``; ``linear``: the model's exact moments of the slope and
        temperature coefficient, used instead of the realizations' when every one the log has
        is known."""
        S = len(sigs)
        avar = np.array([s.avar for s in sigs])
        kw = dict(n_real=S, avar=avar.mean(0), ln_adev=0.5 * np.log(avar).mean(0))
        if sigs[0].psd is not None:
            kw["psd"] = np.mean([s.psd for s in sigs], axis=0)
            k = np.array([s.kurtosis for s in sigs])
            c = np.array([s.tail_count for s in sigs], float)
            sl = np.array([s.slope for s in sigs])
            mu = c.mean()
            c2 = np.array([s.tail2_count for s in sigs], float)
            mu2 = c2.mean()
            kw.update(tails2=float(mu2), tails2_disp=float(max(1.0, c2.var(ddof=1) / mu2))
                      if S > 1 and mu2 > 0 else 1.0)
            kw.update(kurtosis=float(k.mean()), kurt_var=float(k.var(ddof=1)) if S > 1 else 0.0,
                      diff_var=float(np.mean([s.diff_var for s in sigs])),
                      sigma_r=float(np.mean([s.sigma_r for s in sigs])), tails=float(mu),
                      tails_disp=float(max(1.0, c.var(ddof=1) / mu)) if S > 1 and mu > 0 else 1.0,
                      slope=float(sl.mean()), slope_var=float(sl.var(ddof=1)) if S > 1 else 0.0)
            if sigs[0].temp_coef is not None:
                t = np.array([s.temp_coef for s in sigs])
                kw.update(temp_coef=float(t.mean()), temp_var=float(t.var(ddof=1)) if S > 1 else 0.0)
            if sigs[0].low is not None:
                low = np.mean([s.low for s in sigs], axis=0)
                kw.update(low=low, low_sim=low)
            if linear is not None and linear.walk_cov is not None and sigs[0].walk is not None:
                kw["walk_cov"] = linear.walk_cov
                kw["walk_mean"] = linear.walk_mean
            if linear is not None and linear.covers(sigs[0].temp_coef is not None):
                kw.update(slope=linear.slope_mean, slope_var=linear.slope_var, linear_exact=True)
                if sigs[0].temp_coef is not None:
                    kw.update(temp_coef=linear.temp_mean, temp_var=linear.temp_var)
        return cls(**kw)

    def predict(self, inc: Increment, grid: SignatureGrid) -> "ModelSummary":
        """The summary after adding an effect with expected increments ``inc``."""
        avar = self.avar + inc.avar
        ln_adev = self.ln_adev + 0.5 * np.log(np.clip(avar, 1e-300, None) / self.avar)
        kw = dict(avar=avar, ln_adev=ln_adev)
        if self.psd is not None:
            kw["psd"] = self.psd + inc.psd if inc.psd is not None else self.psd
            v0, v1 = self.diff_var, inc.diff_var
            cum4 = self.kurtosis * v0 ** 2 + inc.diff_cum4
            kw["kurtosis"] = cum4 / (v0 + v1) ** 2
            kw["diff_var"] = v0 + v1
            kw["slope"] = self.slope + inc.slope
            kw["slope_var"] = self.slope_var + inc.slope_var
            if self.temp_coef is not None:
                kw["temp_coef"] = self.temp_coef + inc.temp
                kw["temp_var"] = self.temp_var + inc.temp_var
            if inc.outliers is not None:
                kw["tails"] = _tails_with_outliers(self, inc.outliers, grid, 1.0)
                kw["tails2"] = _tails_with_outliers(self, inc.outliers, grid, 2.0, self.tails2)
            if inc.tails is not None:
                kw["tails"], kw["tails2"] = inc.tails
            if self.low is not None and inc.low is not None:
                kw["low"] = self.low + inc.low
            if self.walk_cov is not None and inc.walk_cov is not None:
                kw["walk_cov"] = self.walk_cov + inc.walk_cov
            if self.walk_cov is not None and inc.walk_mean is not None:
                kw["walk_mean"] = inc.walk_mean if self.walk_mean is None else self.walk_mean + inc.walk_mean
        return replace(self, **kw)


def _tails_with_outliers(model: ModelSummary, outl: tuple[float, float], grid: SignatureGrid,
                         level: float = 1.0, base: float | None = None) -> float:
    """Expected exceedances of ``level`` × the tail limit when spikes of ±M hit a fraction p of
    samples (2 differences each); ``base``: the model's count at that level."""
    p, mag = outl
    p = min(p, 0.5)
    sd = math.sqrt(model.diff_var)
    lim = level * grid.tail_k * model.sigma_r
    hit = stats.norm.sf((lim - mag) / sd) + stats.norm.sf((lim + mag) / sd)
    base = model.tails if base is None else base
    return base * (1.0 - 2.0 * p) + 2.0 * p * (grid.n_samples - 1) * hit


@dataclass
class GapTerms:
    """The z of every statistic of one channel, with what and where each one is."""

    z: np.ndarray
    kind: np.ndarray           # one of KINDS per term
    where: list[str]           # "τ = 0.64 s", "1.56–3.12 Hz", "19.9 Hz", ""
    locus: np.ndarray          # τ (s) for adev, band centre / line frequency (Hz), nan otherwise
    line_hz: float | None = None
    #: z with the spectral block decorrelated (:mod:`budget.gap.whitening`), what Σz² sums;
    #: ``None``: the z themselves
    zw: np.ndarray | None = None
    #: the slow-mode statistic on all the modes, the early direction included
    #: (:func:`budget.gap.walk.walk_z` with ``whole``): what opens a channel for slow power;
    #: not a term of Σz² (the split form and the early statistic are)
    slow_whole_z: float | None = None

    @property
    def objective_z(self) -> np.ndarray:
        return self.z if self.zw is None else self.zw

    @property
    def sum_sq(self) -> float:
        return float(np.sum(self.objective_z ** 2))

    @property
    def linear_sq(self) -> float:
        """The part of :attr:`sum_sq` from the linear statistics (:data:`LINEAR_KINDS`)."""
        return float(np.sum(self.objective_z[np.isin(self.kind, LINEAR_KINDS)] ** 2))

    @property
    def n_terms(self) -> int:
        return int(self.z.size)

    @property
    def gap(self) -> float:
        return self.sum_sq / self.n_terms

    def share(self) -> dict[str, float]:
        """Contribution of each statistic kind to the gap (sums to the gap)."""
        zo = self.objective_z
        return {k: float(np.sum(zo[self.kind == k] ** 2) / self.n_terms)
                for k in KINDS if np.any(self.kind == k)}


def _t_to_z(t: float, dof: int) -> float:
    """Normal score with the same two-sided tail probability as Student t (``dof`` = 0: t is
    already a normal score)."""
    if not math.isfinite(t):
        return 0.0
    if dof == 0:
        return float(t)
    if dof < 0:
        return 0.0
    logp = stats.t.logsf(abs(t), dof)
    return float(math.copysign(-special.ndtri_exp(logp), t))


def adev_variance(model: ModelSummary, grid: SignatureGrid) -> np.ndarray:
    """var(ln σ̂) of one record at each τ: 1/(2·EDF), noise type from the model curve."""
    adev = np.sqrt(model.avar)
    alpha = noise_type_from_slope(grid.tau_s, adev)
    edf = edf_simple(grid.n_samples + 1, grid.m, alpha)
    return 0.5 / edf


def gap_terms(meas: Signature, model: ModelSummary, grid: SignatureGrid) -> GapTerms:
    """Standardized differences of every statistic (module docstring)."""
    S = model.n_real
    v_mod = adev_variance(model, grid)
    v_meas = 0.5 / meas.edf if meas.edf is not None else v_mod
    z = [(0.5 * np.log(meas.avar) - model.ln_adev) / np.sqrt(v_meas + v_mod / S)]
    tau = grid.tau_s
    kinds = ["adev"] * tau.size
    where = [f"τ = {t:.4g} s" for t in tau]
    locus = [tau]
    line_hz = None
    slow_whole = None
    if meas.psd is not None and model.psd is not None:
        counts = band_counts(grid)
        K = grid.n_segments
        v_b = WELCH_VAR * (1 + (8 / 9) * (counts - 1) / counts
                           + (1 / 18) * np.clip(counts - 2, 0, None) / counts) / (K * counts)
        zb = (np.log(band_means(meas.psd, grid)) - np.log(band_means(model.psd, grid))) / np.sqrt(v_b * (1 + 1 / S))
        edges = grid.band_edges_hz
        z.append(zb)
        kinds += ["psd_band"] * zb.size
        where += [f"{a:.4g}–{b:.4g} Hz" for a, b in zip(edges[:-1], edges[1:])]
        locus.append(np.sqrt(edges[:-1] * edges[1:]))
        zl, line_hz = _line_z(meas.psd, model.psd, grid, S)
        z.append(np.array([zl]))
        kinds.append("psd_line")
        where.append(f"{line_hz:.4g} Hz")
        locus.append(np.array([line_hz]))
        n = grid.n_samples
        v_k = max(27.0 / n, model.kurt_var)
        zk = (meas.kurtosis - model.kurtosis) / math.sqrt(v_k * (1 + 1 / S))
        c, mu = meas.tail_count, max(model.tails, 0.0)
        zt = (math.sqrt(c) + math.sqrt(c + 1) - math.sqrt(4 * mu + 1)) / math.sqrt(model.tails_disp * (1 + 1 / S))
        c2, mu2 = meas.tail2_count, max(model.tails2 or 0.0, 0.0)
        zt2 = (math.sqrt(c2) + math.sqrt(c2 + 1) - math.sqrt(4 * mu2 + 1)) / math.sqrt(model.tails2_disp * (1 + 1 / S))
        # exact model moments: a normal score (∞ degrees of freedom, no sampling of the mean);
        # the realizations' mean and scatter: t(S − 1), the mean's own scatter in the variance
        dof, inflate = (0, 1.0) if model.linear_exact else (S - 1, 1 + 1 / S)
        zs = _t_to_z((meas.slope - model.slope) / math.sqrt(model.slope_var * inflate), dof) \
            if model.slope_var > 0 else 0.0
        z.append(np.array([zk, zt, zt2, zs]))
        kinds += ["kurtosis", "tails", "tails2", "slope"]
        where += ["first differences", f"|Δx| > {grid.tail_k:.2f} σ", f"|Δx| > {2 * grid.tail_k:.2f} σ",
                  "trend over the record"]
        locus.append(np.full(4, np.nan))
        if meas.temp_coef is not None and model.temp_coef is not None:
            zc = _t_to_z((meas.temp_coef - model.temp_coef) / math.sqrt(model.temp_var * inflate), dof) \
                if model.temp_var > 0 else 0.0
            z.append(np.array([zc]))
            kinds.append("temperature")
            where.append("regression on temp_c")
            locus.append(np.array([np.nan]))
        if meas.walk is not None and model.walk_cov is not None and grid.walk is not None:
            y = meas.walk if model.walk_mean is None else meas.walk - model.walk_mean
            z.append(np.array([walk.walk_z(y, model.walk_cov, grid.walk)]))
            slow_whole = walk.walk_z(y, model.walk_cov, grid.walk, whole=True)
            kinds.append("walk")
            where.append(f"slow modes, periods ≥ {grid.walk.shortest_period_s:.0f} s")
            locus.append(np.array([np.nan]))
            if grid.walk.early is not None:
                z.append(np.array([walk.early_z(y, model.walk_cov, grid.walk)]))
                kinds.append("early")
                where.append("start of the record (e^(−t/τ₀), τ₀ = "
                             f"{walk.EARLY_TAU_FRACTION * grid.n_samples * grid.dt_s:.0f} s)")
                locus.append(np.array([np.nan]))
        if meas.low is not None and model.low is not None and grid.has_low:
            st, counts = grid.low_starts, grid.low_counts
            zl = lowfreq.band_z(lowfreq.band_means(meas.low, st), lowfreq.band_means(model.low, st),
                                lowfreq.band_means(model.low_sim, st), counts, S)
            edges = grid.low_band_edges_hz
            z.append(zl)
            kinds += ["psd_low"] * zl.size
            where += [f"{1e3 * a:.3g}–{1e3 * b:.3g} mHz" for a, b in zip(edges[:-1], edges[1:])]
            locus.append(np.sqrt(edges[:-1] * edges[1:]))
    z = np.concatenate(z)
    zw = grid.whitening.apply(z) if grid.whitening is not None else None
    return GapTerms(z, np.array(kinds), where, np.concatenate(locus), line_hz, zw, slow_whole)


def _line_z(p_meas: np.ndarray, p_model: np.ndarray, grid: SignatureGrid, S: int) -> tuple[float, float]:
    lo, hi = grid.band_start[0], grid.bin_stop
    ratio = p_meas[lo:hi] / p_model[lo:hi]
    nu = 2.0 * grid.n_segments / WELCH_VAR
    j = int(np.argmax(ratio))
    logp = float(stats.f.logsf(ratio[j], nu, S * nu))
    if not math.isfinite(logp):  # beyond double range: the F tail falls as ratio^(−Sν/2)
        logp = -0.5 * S * nu * math.log(max(ratio[j], 1.0))
    n = hi - lo
    if logp < -20:
        log_global = math.log(n) + logp
    elif logp > -1e-12:
        log_global = 0.0
    else:
        log_global = math.log(-math.expm1(n * math.log1p(-math.exp(logp))))
    log_global = min(log_global, 0.0)
    z = float(-special.ndtri_exp(log_global - math.log(2.0)))
    freq = (lo + j) * grid.rate_hz / grid.nperseg
    return max(z, 0.0), freq


def _eigenvalues(z: np.ndarray) -> np.ndarray:
    """Eigenvalues of the covariance of M null z vectors (M, K), shrunk toward their mean so
    that Σλ² equals its unbiased estimate (Wishart: E tr Ĉ² = (1 + 1/M) tr C² + (tr C)²/M);
    the raw sample eigenvalues are too spread, which would make the threshold too high."""
    m, k = z.shape
    lam = np.clip(np.linalg.eigvalsh(z.T @ z / m), 0.0, None)
    t1, t2 = float(lam.sum()), float(np.sum(lam ** 2))
    floor = t1 * t1 / k  # Σλ² of equal eigenvalues: the least it can be
    target = max((t2 - t1 * t1 / m) / (1.0 + 1.0 / m), floor)
    if t2 - floor <= 0:
        return lam
    keep = math.sqrt((target - floor) / (t2 - floor))
    return keep * lam + (1.0 - keep) * t1 / k


def _phi(lam: np.ndarray) -> float:
    """Variance inflation Σλ²/K of a quadratic form's eigenvalues (≥ 1)."""
    return max(1.0, float(np.sum(lam ** 2) / lam.size))


def _linear_mask(key, k: int) -> np.ndarray:
    """Which of the k terms are linear statistics, read from a layout key (n_terms, kinds, …)
    (:attr:`budget.gap.workflow._State.layout`); none for any other key."""
    kinds = key[1] if isinstance(key, tuple) and len(key) > 1 else None
    if not isinstance(kinds, tuple) or len(kinds) != k:
        return np.zeros(k, dtype=bool)
    return np.isin(np.array(kinds, dtype=object), LINEAR_KINDS)


@dataclass(frozen=True)
class NullModel:
    """Null distribution of the gaps (the log follows the model).

    A channel's gap is zᵀz/K with z ≈ N(0, C): a weighted sum Σλ_i χ²_1 of the eigenvalues λ
    of C, so its quantiles follow from :func:`quadratic_form_quantile`. C is estimated from the
    leave-one-out z vectors of the realizations, pooled over channels with the same statistics,
    its eigenvalues shrunk as in :func:`_eigenvalues` — the correlation between terms
    (neighbouring τ, ADEV vs PSD) is what makes the gap's tail heavier than χ²_K/K.
    ``eigen``: channel → λ; ``samples``: channel → leave-one-out gaps.
    """

    eigen: dict[str, np.ndarray]
    alpha: float
    samples: dict[str, np.ndarray] = field(repr=False, default_factory=dict)
    #: channel → (φ of the quadratic statistics, φ of the linear ones): see :meth:`drop`
    blocks: dict[str, tuple[float, float]] = field(repr=False, default_factory=dict)

    @classmethod
    def fit(cls, loo: dict[str, tuple[np.ndarray, tuple]], alpha: float = 0.01) -> "NullModel":
        """``loo``: channel → (z vectors (S, K), layout key); channels sharing a key are pooled."""
        groups: dict[tuple, list[str]] = {}
        for ch, (_, key) in loo.items():
            groups.setdefault(key, []).append(ch)
        eigen, samples, blocks = {}, {}, {}
        for key, chans in groups.items():
            z = np.concatenate([loo[ch][0] for ch in chans])
            lam = _eigenvalues(z)
            lin = _linear_mask(key, z.shape[1])
            phi = (_phi(_eigenvalues(z[:, ~lin])) if np.any(~lin) else 1.0,
                   _phi(_eigenvalues(z[:, lin])) if np.any(lin) else 1.0)
            for ch in chans:
                eigen[ch] = lam
                samples[ch] = np.mean(loo[ch][0] ** 2, axis=1)
                blocks[ch] = phi
        return cls(eigen, alpha, samples, blocks)

    @property
    def n_channels(self) -> int:
        return len(self.eigen)

    def mean(self, channel: str) -> float:
        lam = self.eigen[channel]
        return float(lam.sum() / lam.size)

    def channel_threshold(self, channel: str) -> float:
        lam = self.eigen[channel]
        return quadratic_form_quantile(lam, self.alpha / self.n_channels) / lam.size

    @property
    def overall_threshold(self) -> float:
        n = self.n_channels
        lam = np.concatenate([v / (n * v.size) for v in self.eigen.values()])
        return quadratic_form_quantile(lam, self.alpha)

    def inflation(self, channel: str) -> float:
        """var(Σz²)/(2K) = Σλ²/K: how much the correlated terms inflate a χ² difference."""
        return _phi(self.eigen[channel])

    def drop(self, channel: str, old_sq: float, old_linear: float, new_sq: float,
             new_linear: float) -> float:
        """Deflated drop of a channel's Σz² from (total, linear part) ``old`` to ``new``:
        ΔΣz²_quadratic/φ_q + ΔΣz²_linear/φ_l, each block by its own inflation. The linear
        statistics (time slope, temperature coefficient) are uncorrelated with the quadratic
        ones under the null, so a drop in their z² is evidence at its face value, not shrunk
        by the correlation of neighbouring Allan-deviation τ (one φ for both would make a ramp
        whose slope stands at 5σ read as ≈ 2σ). Without a linear block: ΔΣz²/φ."""
        phi_q, phi_l = self.blocks.get(channel, (self.inflation(channel), 1.0))
        return ((old_sq - old_linear) - (new_sq - new_linear)) / phi_q + (old_linear - new_linear) / phi_l

    def to_dict(self) -> dict:
        return {"alpha": self.alpha,
                "overall_threshold": self.overall_threshold,
                "channel_threshold": {ch: self.channel_threshold(ch) for ch in self.eigen},
                "channel_mean": {ch: self.mean(ch) for ch in self.eigen},
                "inflation": {ch: self.inflation(ch) for ch in self.eigen},
                "loo_gap_mean": float(np.mean(np.concatenate(list(self.samples.values())))),
                "n_loo": int(sum(v.size for v in self.samples.values()))}


def loo_z(sigs: list[Signature], grid: SignatureGrid, linear: LinearMoments | None = None) -> np.ndarray:
    """Leave-one-out z vectors (S, K): each realization against the summary of the others, in
    the metric of the gap (decorrelated when the grid carries a whitening); ``linear`` as in
    :meth:`ModelSummary.from_signatures`."""
    return np.array([gap_terms(s, ModelSummary.from_signatures(sigs[:i] + sigs[i + 1:], linear),
                               grid).objective_z for i, s in enumerate(sigs)])
