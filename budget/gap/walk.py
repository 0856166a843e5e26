"""The record's slowest modes as one statistic, judged against the model's exact covariance.

A rate random walk over one hour shows in the last few Allan-deviation octaves (2–5 degrees of
freedom) and in the lowest Welch bins, each a weak view; the most powerful test of "more slow
power than the model" uses the record's slowest modes together, weighted by how much a walk
adds to each against what the model already puts there (Neyman–Pearson). This module builds
that statistic so that its null distribution is exact rather than read off a dozen
realizations:

* the record (rate samples x_j, N of them, step dt) is cut into ``N_BLOCKS`` blocks of
  M = ⌊N/N_BLOCKS⌋ samples (the last N − N_BLOCKS·M samples are left out) and reduced to block
  sums S_a; below the block rate 1/(M·dt) the reduction loses nothing the test needs;
* the slowest ``N_MODES`` DCT-II modes of the block sums, made orthogonal to a constant, a linear
  trend and — when the log has a temperature column — the block sums of the temperature
  (y = D·S, D orthonormal rows): the bias, a rate ramp and a temperature sensitivity, which the
  mean-change statistics (time slope, temperature coefficient) judge, leave y unchanged;
* the model's covariance of y in closed form, C = D·Σ_S·Dᵀ, every registered effect as the
  package's generator (:mod:`budget.imu.generator`) draws it (:func:`effect_cov`): white and
  Student-t noise, spikes and rate rounding M·σ²·I; each Gauss–Markov term (and the bias-
  instability bank, :func:`budget.imu.flicker.flicker_bank`) the block sums of a sampled AR(1),
  Cov(S_a, S_{a+d}) = φ^((d−1)M+1)·((1 − φ^M)/(1 − φ))² for d ≥ 1 and
  M(1 + φ)/(1 − φ) − 2φ(1 − φ^M)/(1 − φ)² on the diagonal; the random walk (a cumulative sum
  from the first sample) K²·dt·(M³·min(a, b) + M²(M + 1)/2) off the diagonal and
  K²·dt·(M³·a + M(M + 1)(2M + 1)/6) on it; a random-phase sinusoid (A²/2)·Re(z_a·z̄_b) with
  z_a = e^(iωaM·dt)·(1 − e^(iωM·dt))/(1 − e^(iω·dt)); the integrated-output quantizer
  2Q²/dt² on the diagonal and −Q²/dt² beside it; a vibration from its autocorrelation
  (:func:`budget.imu.effects.vibration_acov`) when its band reaches below 4× the block rate,
  otherwise nothing (its power sits far above the modes). Ramp and temperature terms are
  projected out; a thermal lag is not (its response is not the temperature column), nor a
  warm-up transient (e^(−t/τ) is not a trend): each is deterministic and gives the modes a
  mean, D times the block sums of c·(T_e − T_0) or A·e^(−t/τ) (:func:`model_mean`), which is
  subtracted before they are whitened. The output low-pass filter is left out: at the modes' frequencies (below
  N_MODES/(2N·dt), a few mHz for a one-hour log) its gain is 1 to within (f/f_c)²;
* whitened, y becomes ξ = Vᵀ·L⁻¹·y (C = L·Lᵀ, L⁻¹·U·L⁻ᵀ = V·Λ·Vᵀ with U the covariance a
  walk with K = 1 adds): under the model ξ ~ N(0, I), and a walk of K² = q adds q·λ_i to the
  variance of ξ_i. The statistic T = Σ w_i·ξ_i² with w_i = λ_i/(1 + q₀·λ_i), q₀·λ_max =
  ``TEMPER`` = 3 — the Neyman–Pearson weights for a walk that adds three times the model's
  variance to the slowest mode (q₀ = 0 would be the locally most powerful weights λ_i of Rao's score test,
  which let the two or three slowest modes, a few degrees of freedom, carry it all) — is under
  the model a weighted sum of χ²₁, whose distribution follows from the four-cumulant match of
  Liu, Tang & Zhang (2009) (:func:`budget.quadform.quadratic_form_sf`); its z is the normal
  score of that probability (positive: more slow power than the model, negative: less).

The statistic is the same for a bias instability, a long Gauss–Markov term or a walk: it
measures slow power, and a candidate effect that adds slow power changes C and so its own
predicted z (:meth:`budget.gap.fitting.FitContext.sumsq`), which is how a walk and a flicker
term of the same long-τ excess are told apart.

Beside T, the **early statistic** (:func:`early_z`) is linear in the same modes: their projection
s = vᵀy on the unit vector v of the modes of e^(−t/τ₀), τ₀ = ``EARLY_TAU_FRACTION`` × the record
length, scored as (s − vᵀμ)/√(vᵀCv) under the model's exact mean μ and covariance C. T says how
much slow power there is, not where; a turn-on transient (a mean) shifts s, a walk or a flicker
term (a spread) only widens it — and pays ln(var'/var) for that in the candidate fits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import linalg, special

from ..imu import effects as fx
from ..imu.flicker import flicker_bank
from ..imu.registry import DETERMINISTIC_EFFECTS
from ..quadform import quadratic_form_sf

#: Blocks the record is reduced to.
N_BLOCKS = 256
#: Slowest modes kept (periods from the record length down to 2N·dt/N_MODES: 150 s for 1 h;
#: on the benchmark's one-hour walks 16 → 24 → 48 modes raise the weakest z 2.4 → 2.6 → 2.9
#: at the same null spread, 64 adds nothing).
N_MODES = 48
#: q·λ_max of the alternative the weights are tempered for (:func:`weights`): a walk that adds
#: three times the model's variance to the slowest mode.
TEMPER = 3.0
#: Fewest samples per block (shorter logs get no walk statistic).
MIN_BLOCK = 16
#: Decay time of the start-of-record pattern e^(−t/τ₀) of the early statistic, as a fraction of
#: the record length (:func:`early_z`).
EARLY_TAU_FRACTION = 1.0 / 8.0


@dataclass(frozen=True)
class WalkLayout:
    """Blocks and modes of one record: ``block`` samples per block, ``basis`` (K, n_blocks)
    orthonormal rows, ``unit`` (K, K) the covariance of the modes that a walk with K = 1
    (unit/√s) adds; ``n_samples``, ``dt_s`` of the whole record (the bias-instability bank of
    the generator depends on the record length)."""

    n_blocks: int
    block: int
    dt_s: float
    n_samples: int
    basis: np.ndarray
    unit: np.ndarray
    #: unit vector in mode space: the modes of e^(−t/τ₀), τ₀ = ``EARLY_TAU_FRACTION`` × the
    #: record length (:func:`early_z`)
    early: np.ndarray | None = None
    #: (K, K − 1) orthonormal basis of the modes orthogonal to ``early`` (:func:`walk_z`)
    early_complement: np.ndarray | None = None

    @property
    def n_modes(self) -> int:
        return int(self.basis.shape[0])

    @property
    def block_rate_hz(self) -> float:
        return 1.0 / (self.block * self.dt_s)

    @property
    def shortest_period_s(self) -> float:
        """Period of the fastest mode kept (s)."""
        return 2.0 * self.n_blocks * self.block * self.dt_s / self.n_modes


def layout(n_samples: int, dt_s: float, temp_c: np.ndarray | None = None) -> WalkLayout | None:
    """The layout of a record of ``n_samples`` at step ``dt_s`` (``temp_c``: its temperature
    column, °C, projected out with the bias and the trend); ``None`` when the record has fewer
    than ``N_BLOCKS``·``MIN_BLOCK`` samples."""
    m = n_samples // N_BLOCKS
    if m < MIN_BLOCK:
        return None
    nb = N_BLOCKS
    a = np.arange(nb, dtype=float)
    lead = [np.ones(nb), a - a.mean()]
    if temp_c is not None:
        tb = block_sums(np.asarray(temp_c, float), nb, m)
        q2, _ = np.linalg.qr(np.column_stack(lead))
        rest = tb - q2 @ (q2.T @ tb)
        # a temperature that only rises linearly is the trend itself: nothing more to remove
        if np.linalg.norm(rest) > 1e-9 * max(np.linalg.norm(tb), 1e-300):
            lead.append(rest)
    q, _ = np.linalg.qr(np.column_stack(lead))
    k = np.arange(1, N_MODES + len(lead) + 1, dtype=float)
    dct = np.cos(np.pi * np.outer(k, a + 0.5) / nb)
    dct -= (dct @ q) @ q.T
    keep = np.linalg.norm(dct, axis=1) > 1e-6 * math.sqrt(nb)
    basis, _ = np.linalg.qr(dct[keep].T)
    basis = basis[:, :N_MODES].T
    unit = basis @ walk_block_cov(nb, m, dt_s) @ basis.T
    t = np.arange(nb * m) * dt_s
    early = basis @ block_sums(np.exp(-t / (EARLY_TAU_FRACTION * n_samples * dt_s)), nb, m)
    norm = float(np.linalg.norm(early))
    if not norm > 0:
        return WalkLayout(nb, m, float(dt_s), int(n_samples), basis, unit)
    early = early / norm
    return WalkLayout(nb, m, float(dt_s), int(n_samples), basis, unit, early,
                      linalg.null_space(early[None, :]))


def block_sums(x: np.ndarray, n_blocks: int, block: int) -> np.ndarray:
    return np.asarray(x[:n_blocks * block], float).reshape(n_blocks, block).sum(axis=1)


def modes(x: np.ndarray, lay: WalkLayout) -> np.ndarray:
    """The slowest modes y = D·S of a rate series (unit·samples)."""
    return lay.basis @ block_sums(x, lay.n_blocks, lay.block)


# --- block-sum covariances ------------------------------------------------------------------

def walk_block_cov(n_blocks: int, m: int, dt_s: float) -> np.ndarray:
    """Cov(S_a, S_b) of a rate random walk with K = 1 drawn as K·√dt·Σ_{u ≤ j} e_u."""
    i = np.arange(n_blocks, dtype=float)
    cov = m ** 3 * np.minimum.outer(i, i) + m * m * (m + 1) / 2.0
    cov[np.diag_indices(n_blocks)] = m ** 3 * i + m * (m + 1) * (2 * m + 1) / 6.0
    return dt_s * cov


def ar1_block_acov(n_blocks: int, m: int, dt_s: float, tau_s) -> np.ndarray:
    """c(d), d = 0 … n_blocks − 1: Cov(S_a, S_{a+d}) of unit-variance sampled Gauss–Markov
    processes of correlation times ``tau_s`` (shape (len(tau_s), n_blocks))."""
    tau = np.atleast_1d(np.asarray(tau_s, float))[:, None]
    r = dt_s / tau
    phi = np.exp(-r)
    one = -np.expm1(-r)                 # 1 − φ
    one_m = -np.expm1(-m * r)           # 1 − φ^M
    c0 = m * (1.0 + phi) / one - 2.0 * phi * one_m / one ** 2
    d = np.arange(1, n_blocks, dtype=float)[None, :]
    cd = np.exp(-r * ((d - 1.0) * m + 1.0)) * (one_m / one) ** 2
    return np.concatenate([c0, cd], axis=1)


def _toeplitz_modes(c: np.ndarray, lay: WalkLayout) -> np.ndarray:
    return lay.basis @ linalg.toeplitz(c) @ lay.basis.T


def _stationary_block_acov(gamma: np.ndarray, n_blocks: int, m: int) -> np.ndarray:
    """c(d) = Σ_{|l|<M} (M − |l|)·γ(dM + l) from an autocovariance γ(0 … n_blocks·M)."""
    g = np.concatenate([gamma[:0:-1], gamma])       # γ(−L … L)
    zero = gamma.size - 1
    tri = (m - np.abs(np.arange(-(m - 1), m))).astype(float)
    out = np.empty(n_blocks)
    for d in range(n_blocks):
        lo = zero + d * m - (m - 1)
        seg = g[lo:lo + 2 * m - 1]
        out[d] = float(np.dot(tri[:seg.size], seg))
    return out


def effect_cov(name: str, params: dict, lay: WalkLayout) -> np.ndarray | None:
    """Covariance (K, K) that one effect (SI parameters) adds to the modes; ``None`` for an
    effect without an entry (module docstring)."""
    nb, m, dt = lay.n_blocks, lay.block, lay.dt_s
    k = lay.n_modes
    if name in ("white_noise", "heavy_tailed"):
        return (params["density"] ** 2 / dt * m) * np.eye(k)
    if name == "rate_quantization":
        return (params["step"] ** 2 / 12.0 * m) * np.eye(k)
    if name == "outliers":
        return (params["rate"] * params["magnitude"] ** 2 * m) * np.eye(k)
    if name == "lowpass" or name in DETERMINISTIC_EFFECTS:
        return np.zeros((k, k))
    if name == "rate_random_walk":
        return params["K"] ** 2 * lay.unit
    if name == "gauss_markov":
        return params["sigma"] ** 2 * _toeplitz_modes(ar1_block_acov(nb, m, dt, params["tau_s"])[0], lay)
    if name == "bias_instability":
        tau, var = flicker_bank(params["B"], dt, dt * (lay.n_samples - 1))
        return _toeplitz_modes(var @ ar1_block_acov(nb, m, dt, tau), lay)
    if name == "quantization":
        c = np.zeros(nb)
        c[0], c[1] = 2.0, -1.0
        return params["Q"] ** 2 / dt ** 2 * _toeplitz_modes(c, lay)
    if name == "sinusoid":
        w = 2.0 * math.pi * params["frequency_hz"] * dt
        if abs(math.sin(0.5 * w)) < 1e-12:
            gain = complex(m)
        else:
            gain = (1.0 - np.exp(1j * w * m)) / (1.0 - np.exp(1j * w))
        z = lay.basis @ (np.exp(1j * w * m * np.arange(nb)) * gain)
        return 0.5 * params["amplitude"] ** 2 * np.real(np.outer(z, np.conj(z)))
    if name == "vibration":
        if params["center_hz"] - 4.0 * params["width_hz"] > 4.0 * lay.block_rate_hz:
            return np.zeros((k, k))
        gamma = fx.vibration_acov(np.arange(nb * m + m), params["center_hz"], params["width_hz"], dt)
        return params["sigma"] ** 2 * _toeplitz_modes(_stationary_block_acov(gamma, nb, m), lay)
    return None


def model_cov(effects, lay: WalkLayout) -> np.ndarray | None:
    """Covariance (K, K) of the modes under a channel's effects (SI); ``None`` when one of them
    has no entry in :func:`effect_cov`, or when the model puts (almost) no noise in some mode
    (a model of deterministic terms only: no slow-mode statistic can be formed against it)."""
    total = np.zeros((lay.n_modes, lay.n_modes))
    for f in effects:
        c = effect_cov(f.name, dict(f.params), lay)
        if c is None:
            return None
        total += c
    lam = np.linalg.eigvalsh(total)
    if not np.all(np.isfinite(lam)) or lam[-1] <= 0 or lam[0] <= 1e-10 * lam[-1]:
        return None
    return total


def effect_mean(name: str, params: dict, lay: WalkLayout, temp_c: np.ndarray | None) -> np.ndarray | None:
    """Mean (K,) that one deterministic effect (SI parameters) gives the modes: zero for every
    effect but a thermal lag, whose response c·(T_e − T_0) is not the projected-out
    temperature column, a warm-up transient A·e^(−t/τ) and a bias step A·H(t − t₀), which are
    not trends (:func:`budget.imu.effects.mean_series`); ``None`` for a temperature effect
    without a temperature column."""
    if name not in DETERMINISTIC_EFFECTS:
        return np.zeros(lay.n_modes)
    if name in ("rate_ramp", "temperature_sensitivity"):
        # a ramp and the temperature column are projected out of the modes; without the
        # column, a temperature sensitivity has no mean to give
        return None if (name == "temperature_sensitivity" and temp_c is None) else np.zeros(lay.n_modes)
    series = fx.mean_series(name, params, lay.n_samples, lay.dt_s, temp_c)
    return None if series is None else modes(series, lay)


def model_mean(effects, lay: WalkLayout, temp_c: np.ndarray | None) -> np.ndarray | None:
    """Mean (K,) of the modes under a channel's effects (:func:`effect_mean`); ``None`` when a
    temperature effect has no temperature column."""
    total = np.zeros(lay.n_modes)
    for f in effects:
        m = effect_mean(f.name, dict(f.params), lay, temp_c)
        if m is None:
            return None
        total += m
    return total


# --- the statistic ------------------------------------------------------------------------------

def apart_from_early(y: np.ndarray, cov: np.ndarray, lay: WalkLayout) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(y', C', U'): the part of the modes y (covariance C) independent of the early statistic
    s = vᵀy, in K − 1 coordinates, with its covariance and the covariance a walk with K = 1 adds.

    With u = C·v, y − u·s/(vᵀu) has zero covariance with s (jointly Gaussian: independent) and
    lies in v's orthogonal complement Q: y' = Qᵀ(I − u·vᵀ/(vᵀu))·y = M·y, C' = M·C·Mᵀ,
    U' = M·U·Mᵀ. T built on y' does not count a chance excursion of s a second time: without
    it a start-of-record excursion of 2.9σ also lifted T to z ≈ 3 on short model-following logs,
    and the two were summed as independent evidence."""
    if lay.early is None:
        return y, cov, lay.unit
    v = lay.early
    u = cov @ v
    m = lay.early_complement.T @ (np.eye(v.size) - np.outer(u, v) / float(v @ u))
    return m @ y, m @ cov @ m.T, m @ lay.unit @ m.T


def weights(cov: np.ndarray, lay: WalkLayout, unit: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(w, R): the weights w_i of the whitened modes and the map R with ξ = R·y (``unit``: the
    walk's covariance in these coordinates, ``lay.unit`` by default)."""
    chol = linalg.cholesky(cov, lower=True)
    li = linalg.solve_triangular(chol, np.eye(cov.shape[0]), lower=True)
    b = li @ (lay.unit if unit is None else unit) @ li.T
    lam, vec = np.linalg.eigh(0.5 * (b + b.T))
    lam = np.clip(lam, 0.0, None)
    top = float(lam.max())
    w = lam / (1.0 + TEMPER * lam / top) if top > 0 else lam
    return w, vec.T @ li


def walk_z(y: np.ndarray, cov: np.ndarray, lay: WalkLayout, whole: bool = False) -> float:
    """Normal score of T = Σ w_i ξ_i² under the covariance ``cov`` of the modes (module
    docstring), on their part independent of the early statistic (:func:`apart_from_early`):
    > 0 when the record has more slow power than ``cov`` says.

    ``whole``: T on all K modes, the early direction included. A walk runs from the record's
    first sample, so part of its slow power lies in that direction; split off, it is scored
    by the early statistic as a widened spread, which alone never opens a channel. The whole
    form is the one to ask "is there more slow power than the model's?" (on 40 one-hour walks
    sized to 3× the model's Allan deviation, z > 2.64 on 40/40 against 38/40 for the split
    form, the same null spread); the split form is the one the fits sum beside the early
    statistic, which must not count a start-of-record excursion twice."""
    key = (cov.tobytes(), y.tobytes(), whole)
    if key in _CACHE:
        return _CACHE[key]
    if len(_CACHE) > 256:  # ≈ 19 kB a key: a few MB at most
        _CACHE.clear()
    y2, cov2, unit2 = (y, cov, lay.unit) if whole else apart_from_early(y, cov, lay)
    w, r = weights(cov2, lay, unit2)
    xi = r @ y2
    t = float(np.dot(w, xi * xi))
    sf = quadratic_form_sf(w, t)
    z = float(special.ndtri(max(1.0 - sf, 1e-300)) if sf >= 0.5 else -special.ndtri(max(sf, 1e-300)))
    _CACHE[key] = z
    return z


def early_var(cov: np.ndarray, lay: WalkLayout) -> float:
    """Variance of the early statistic vᵀy under the covariance ``cov`` of the modes."""
    v = lay.early
    return float(v @ cov @ v)


def early_z(y: np.ndarray, cov: np.ndarray, lay: WalkLayout) -> float:
    """Normal score of the early statistic vᵀy (v = ``lay.early``, y the modes less the model's
    mean) under the covariance ``cov``: how much the record's start stands above or below the
    rest, beyond what a constant and a trend (and a temperature column) explain.

    The slow-mode statistic T (:func:`walk_z`) is quadratic: it says how much slow power there
    is, not where it lies, so a warm-up transient A·e^(−t/τ) (a deterministic mean) and a rate
    random walk (slow power in every mode) can explain it equally well. This linear statistic
    separates them: a transient shifts its mean, which the transient's fit removes, while a walk
    or a flicker term only widens its spread — and a candidate that widens it pays
    ln(var'/var) beside z² (:meth:`budget.gap.fitting.FitContext.sumsq_parts`), as for the
    time slope. The pattern is fixed by the record's length alone (τ₀ = 1/8 of it): any
    transient from a few minutes to about a third of a one-hour record projects on it; its
    distribution under the model is exact (y is Gaussian with covariance ``cov``)."""
    return float(lay.early @ y) / math.sqrt(early_var(cov, lay))


def log_likelihood(y: np.ndarray, mean: np.ndarray | None, cov: np.ndarray) -> float:
    """Gaussian log-likelihood of the modes y under mean ``mean`` (``None``: zero) and
    covariance ``cov``, less the constant −K/2·ln 2π: −½[(y − μ)ᵀC⁻¹(y − μ) + ln det C].

    T and the early statistic say how much slow power there is and how much of it sits at the
    start; this says where and in what shape: a located pattern (a bias step, a mean) and a
    spread (a walk) of the same power differ here by tens (measured: on one-hour logs with a
    step sized to 3× the model's Allan deviation, 2·ln LR of the best step over the best walk
    22–47 on 10 of 10; on walks, −18 to +4.4)."""
    r = y if mean is None else y - mean
    chol = linalg.cholesky(cov, lower=True)
    z = linalg.solve_triangular(chol, r, lower=True)
    return float(-0.5 * np.dot(z, z) - np.sum(np.log(np.diag(chol))))


def located_log_likelihood(y: np.ndarray, mean: np.ndarray | None, cov: np.ndarray,
                           units: np.ndarray) -> tuple[float, int, float]:
    """(max ln L, i, a): the modes' Gaussian log-likelihood (:func:`log_likelihood`) of
    y − mean − a·u_i maximised over the coefficient a (generalised least squares, closed form:
    a = uᵀC⁻¹r / uᵀC⁻¹u, which lowers rᵀC⁻¹r by (uᵀC⁻¹r)²/uᵀC⁻¹u) and over the rows u_i of
    ``units`` (M, K): the modes of a located pattern at unit coefficient for M values of its
    shape parameter (a step's time, a transient's τ). A located pattern's mean is linear in its
    coefficient, so the profile over the coefficient is exact."""
    r = y if mean is None else y - mean
    chol = linalg.cholesky(cov, lower=True)
    zr = linalg.solve_triangular(chol, r, lower=True)
    zu = linalg.solve_triangular(chol, np.atleast_2d(units).T, lower=True)  # (K, M)
    num, den = zr @ zu, np.einsum("km,km->m", zu, zu)
    gain = np.where(den > 0, num * num / np.where(den > 0, den, 1.0), 0.0)
    i = int(np.argmax(gain))
    a = float(num[i] / den[i]) if den[i] > 0 else 0.0
    return float(-0.5 * (np.dot(zr, zr) - gain[i]) - np.sum(np.log(np.diag(chol)))), i, a


# --- nested spreads: the modes' profile likelihood --------------------------------------------

#: (simpler, richer) spreads whose richer family holds the simpler as a limit in the modes: a
#: Gauss–Markov term of correlation time τ → ∞ with q = 2σ²/τ held is x₀ + a walk of K² = q
#: (x_k = φx_{k−1} + w_k, 1 − φ² → 2dt/τ, Var w → q·dt), and the constant x₀ is projected
#: out of the modes; at f ≫ 1/(2πτ) the two spectra agree (q/(2πf)²), below it the Gauss–Markov
#: term's is flat.
NESTED_SPREADS = frozenset({("rate_random_walk", "gauss_markov")})
#: Longest Gauss–Markov correlation time of the profile, × the record length: the walk limit
#: (the modes' covariance of τ = 100·T at q = K² differs from the walk's by 7e-6, relative
#: Frobenius norm, on 30-min and one-hour layouts).
GM_TAU_LIMIT = 100.0


def _lag_stack(lay: WalkLayout) -> np.ndarray:
    """(n_blocks, K, K): D·(E_d + E_dᵀ)·Dᵀ for each block lag d (E_d ones on the d-th
    superdiagonal, E_0 + E_0ᵀ taken as I), so that D·toeplitz(c)·Dᵀ = Σ_d c(d)·stack[d]: a
    stationary term's modes' covariance as one contraction (cached per layout)."""
    key = (lay.n_blocks, lay.block, lay.basis.tobytes())
    if key not in _STACKS:
        b = lay.basis
        out = np.empty((lay.n_blocks, b.shape[0], b.shape[0]))
        out[0] = b @ b.T
        for d in range(1, lay.n_blocks):
            g = b[:, :-d] @ b[:, d:].T
            out[d] = g + g.T
        _STACKS.clear()
        _STACKS[key] = out
    return _STACKS[key]


_STACKS: dict[tuple, np.ndarray] = {}


def _spread_cov(name: str, theta: np.ndarray, lay: WalkLayout, stack: np.ndarray | None = None) -> np.ndarray:
    """Covariance a nested spread adds to the modes at θ: ln K for the walk, (ln q, ln τ) with
    q = 2σ²/τ for the Gauss–Markov term (the walk-equivalent level, which the modes above its
    corner fix, held while τ moves); ``stack``: :func:`_lag_stack` of ``lay``."""
    if name == "rate_random_walk":
        return math.exp(2.0 * theta[0]) * lay.unit
    tau = math.exp(theta[1])
    c = ar1_block_acov(lay.n_blocks, lay.block, lay.dt_s, tau)[0]
    stack = _lag_stack(lay) if stack is None else stack
    # lags whose covariance is below 1e-17 of the variance add nothing at double precision
    # (and their subnormal values slow the contraction a hundredfold)
    used = int(np.count_nonzero(c > 1e-17 * c[0]))
    return 0.5 * math.exp(theta[0]) * tau * np.tensordot(c[:used], stack[:used], axes=1)


#: Spreads :func:`profile_log_likelihood` maximises over their own parameters.
PROFILED_SPREADS = frozenset({"rate_random_walk", "gauss_markov"})


def walk_level(name: str, params: dict) -> float:
    """Walk-equivalent level K² ((rad/s)²/s or (m/s²)²/s, per second of record) of a profiled
    spread: K² for the walk; q = 2σ²/τ for a Gauss–Markov term, the level its modes above the
    corner 1/τ share with a walk (:func:`_spread_cov`) — what :func:`profile_log_likelihood`
    centres its search on."""
    if name == "rate_random_walk":
        return float(params["K"]) ** 2
    if name == "gauss_markov":
        return 2.0 * float(params["sigma"]) ** 2 / float(params["tau_s"])
    raise ValueError(f"no walk-equivalent level for {name!r}")


def profile_log_likelihood(name: str, y: np.ndarray, mean: np.ndarray | None, cov0: np.ndarray,
                           lay: WalkLayout, level: float) -> tuple[float, np.ndarray]:
    """(max ln L, θ̂): the modes' Gaussian log-likelihood (:func:`log_likelihood`) under the
    model's covariance ``cov0`` plus a walk (``name`` "rate_random_walk", θ = ln K) or a
    Gauss–Markov term ("gauss_markov", θ = (ln q, ln τ), q = 2σ²/τ), maximised over θ — the
    profile likelihood of the effect's family (its parameters are nuisance here). ``level``:
    a walk-equivalent K² to centre the search on (the candidates' fit).

    The walk: a bounded 1-D search of ln K over e^(±4) of the start. The Gauss–Markov term:
    τ on a log grid from 4 samples to :data:`GM_TAU_LIMIT` × the record (its last point is the
    walk limit), q profiled at each τ by the same 1-D search, then Nelder–Mead from the best
    point; bounded in τ by the same range."""
    key = (name, y.tobytes(), None if mean is None else mean.tobytes(), cov0.tobytes(), lay.n_samples,
           lay.dt_s, level)
    if key in _PROFILE_CACHE:
        f, th = _PROFILE_CACHE[key]
        return f, th.copy()
    if len(_PROFILE_CACHE) > 64:
        _PROFILE_CACHE.clear()
    f, th = _profile(name, y, mean, cov0, lay, level)
    _PROFILE_CACHE[key] = (f, th.copy())
    return f, th


def _profile(name: str, y: np.ndarray, mean: np.ndarray | None, cov0: np.ndarray,
             lay: WalkLayout, level: float) -> tuple[float, np.ndarray]:
    """:func:`profile_log_likelihood` without its cache."""
    from scipy import optimize

    stack = _lag_stack(lay) if name == "gauss_markov" else None

    def nll(name_, th):
        try:
            return -log_likelihood(y, mean, cov0 + _spread_cov(name_, th, lay, stack))
        except (np.linalg.LinAlgError, ValueError):
            return np.inf

    def line(f, c):
        grid = np.linspace(c - 4.0, c + 4.0, 17)
        vals = [f(g) for g in grid]
        i = int(np.argmin(vals))
        a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        res = optimize.minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": 1e-4})
        return (float(res.x), float(res.fun)) if res.fun <= vals[i] else (float(grid[i]), float(vals[i]))

    ln_q0 = math.log(max(level, 1e-300))
    if name == "rate_random_walk":
        x, f = line(lambda u: nll(name, np.array([u])), 0.5 * ln_q0)
        return -f, np.array([x])
    if name != "gauss_markov":
        raise ValueError(f"no profile for {name!r}")
    record = lay.n_samples * lay.dt_s
    lo, hi = math.log(4.0 * lay.dt_s), math.log(GM_TAU_LIMIT * record)
    best = None
    for lt in np.linspace(lo, hi, 12):
        x, f = line(lambda u: nll(name, np.array([u, lt])), ln_q0)
        if best is None or f < best[1]:
            best = (np.array([x, lt]), f)
    bound = lambda th: nll(name, np.array([th[0], min(max(th[1], lo), hi)]))
    res = optimize.minimize(bound, best[0], method="Nelder-Mead",
                            options={"xatol": 1e-3, "fatol": 1e-4, "maxiter": 300})
    if res.fun < best[1]:
        best = (np.array([res.x[0], min(max(res.x[1], lo), hi)]), float(res.fun))
    return -best[1], best[0]


def nested_spread_lr(simple: str, rich: str, y: np.ndarray, mean: np.ndarray | None,
                     cov0: np.ndarray, lay: WalkLayout, level: float) -> float | None:
    """2·ln Λ, Λ the ratio of the modes' profile likelihoods (:func:`profile_log_likelihood`)
    of the richer spread's family over the simpler's, when the pair is in
    :data:`NESTED_SPREADS`; ``None`` otherwise. The richer family holds the simpler as its
    limit, so 2·ln Λ ≥ 0 (the Gauss–Markov profile is started at that limit too), and with the
    simpler true it follows Wilks' χ²_Δp — at the boundary τ = ∞ the mixture ½χ²₀ + ½χ²₁ of
    Self & Liang (JASA 82(398), 1987), so χ²₁(1 − α) is a test of level α/2."""
    if (simple, rich) not in NESTED_SPREADS:
        return None
    key = (y.tobytes(), None if mean is None else mean.tobytes(), cov0.tobytes(), simple, rich)
    if key in _LR_CACHE:
        return _LR_CACHE[key]
    if len(_LR_CACHE) > 64:
        _LR_CACHE.clear()
    ls, th = profile_log_likelihood(simple, y, mean, cov0, lay, level)
    lr_, _ = profile_log_likelihood(rich, y, mean, cov0, lay, math.exp(2.0 * th[0]))
    # the walk limit itself is a point of the richer family
    limit = np.array([2.0 * th[0], math.log(GM_TAU_LIMIT * lay.n_samples * lay.dt_s)])
    try:
        lr_ = max(lr_, log_likelihood(y, mean, cov0 + _spread_cov(rich, limit, lay)))
    except np.linalg.LinAlgError:
        pass
    out = 2.0 * (lr_ - ls)
    _LR_CACHE[key] = out
    return out


_LR_CACHE: dict[tuple, float] = {}
#: profile likelihoods asked again for the same modes, model and start (the located effects' tests)
_PROFILE_CACHE: dict[tuple, tuple[float, np.ndarray]] = {}

#: (covariance, modes) → z: a candidate that adds no slow power leaves both unchanged, and
#: the fits ask for the same z many times
_CACHE: dict[tuple[bytes, bytes, bool], float] = {}
