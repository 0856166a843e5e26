"""Distribution of a weighted sum of independent χ²₁ variables, Q = Σ λ_i χ²_1,i.

The gap's null (:class:`budget.gap.metric.NullModel`), the slow-mode statistic
(:mod:`budget.gap.walk`) and the mean square of a random walk's phase beyond PGA's window
(:meth:`budget.bounds.fast_phase.FastPhaseResidual.p_within_limit`) are all such sums; their
tail probabilities and quantiles come from the four-cumulant noncentral-χ² match of Liu, Tang &
Zhang (2009), Comput. Stat. Data Anal. 53, 853–856, exact for equal λ (checked against simulation in ``tests/test_gap_walk.py``). The
match is built for the upper tail; where the whole distribution matters (a sum dominated by a
few λ, read in its lower tail too) :func:`quadratic_form_sf_imhof` integrates Imhof's (1961)
inversion of the characteristic function instead, exact to the quadrature's tolerance, and
:func:`quadratic_form_quantile_imhof` inverts it.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy import stats


def _liu_parameters(eigenvalues: np.ndarray) -> tuple[float, float, float, float, float]:
    """(a, δ, ν, c1, c2) of the Liu, Tang & Zhang (2009) match of Q = Σ λ_i χ²_1,i: a noncentral
    χ²(ν, δ) with the first four cumulants of Q (Comput. Stat. Data Anal. 53, 853–856)."""
    lam = np.asarray(eigenvalues, float)
    lam = lam[lam > 1e-12 * lam.max()]
    c1, c2, c3, c4 = (float(np.sum(lam ** k)) for k in (1, 2, 3, 4))
    s1, s2 = c3 / c2 ** 1.5, c4 / c2 ** 2
    if s1 * s1 > s2:
        a = 1.0 / (s1 - math.sqrt(s1 * s1 - s2))
        delta = s1 * a ** 3 - a * a
        dof = a * a - 2.0 * delta
    else:
        a, delta, dof = 1.0 / s1, 0.0, c2 ** 3 / c3 ** 2
    return a, delta, dof, c1, c2


def quadratic_form_quantile(eigenvalues: np.ndarray, alpha: float) -> float:
    """Upper-α quantile of Q = Σ λ_i χ²_1,i (independent) by the Liu, Tang & Zhang (2009)
    approximation (:func:`_liu_parameters`), exact for equal λ."""
    a, delta, dof, c1, c2 = _liu_parameters(eigenvalues)
    q = stats.ncx2.isf(alpha, dof, delta) if delta > 0 else stats.chi2.isf(alpha, dof)
    return float((q - (dof + delta)) / (math.sqrt(2.0) * a) * math.sqrt(2.0 * c2) + c1)


def quadratic_form_sf(eigenvalues: np.ndarray, t: float) -> float:
    """P(Q > t) for Q = Σ λ_i χ²_1,i, the inverse of :func:`quadratic_form_quantile`."""
    a, delta, dof, c1, c2 = _liu_parameters(eigenvalues)
    q = (t - c1) / math.sqrt(2.0 * c2) * (math.sqrt(2.0) * a) + dof + delta
    return float(stats.ncx2.sf(q, dof, delta) if delta > 0 else stats.chi2.sf(q, dof))


def quadratic_form_sf_imhof(eigenvalues: np.ndarray, t: float) -> float:
    """P(Q > t) for Q = Σ λ_i χ²_1,i (λ_i ≥ 0, independent), exact by Imhof's inversion
    (Biometrika 48 (1961) 419–426, eq. 3.2 with no noncentrality):

        P(Q > t) = ½ + (1/π) ∫₀^∞ sin θ(u) / (u ρ(u)) du,
        θ(u) = ½ Σ arctan(λ_i u) − ½ t u,   ρ(u) = Π (1 + λ_i² u²)^{1/4}.

    On [0, A] (at most half a period of the t·u/2 oscillation) by adaptive quadrature; beyond,
    sin θ = sin φ cos(tu/2) − cos φ sin(tu/2) with φ = ½ Σ arctan(λ_i u) slow, so the rest is
    Fourier integrals of smooth decaying functions (QUADPACK's QAWF, for which neither the few-λ
    tail's slow u^(−1−m/2) decay nor a fast oscillation far in Q's upper tail is a difficulty).
    Absolute error ≲ 1e-6 (checked against χ²_k); where Chernoff's bounds put the answer within
    1e-9 of 0 or 1 that is returned, and the integral is always held within those bounds. λ below
    1e-10 of the largest are dropped."""
    from scipy import integrate

    lam = np.asarray(eigenvalues, float)
    lam = lam[lam > 1e-10 * lam.max()] if lam.size and lam.max() > 0 else lam[:0]
    if lam.size == 0 or t <= 0:
        return 1.0 if (lam.size and t <= 0) else 0.0
    scale = float(lam.max())  # in units of the largest λ: u of order 1 where Q's shape shows
    lam, x = lam / scale, float(t) / scale
    # Far in either tail the answer is within 1e-9 of 0 or 1 (Chernoff's bound says so) and the
    # integral is all cancellation: return the bound's side.
    upper, lower = _chernoff_bounds(lam, x)
    if upper < 1e-9:
        return 0.0
    if lower < 1e-9:
        return 1.0

    def phi(u: float) -> float:
        return 0.5 * float(np.sum(np.arctan(lam * u)))

    def inv_u_rho(u: float) -> float:
        lu = lam * u
        return math.exp(-0.25 * float(np.sum(np.log1p(lu * lu)))) / u  # underflows to 0, never overflows

    with warnings.catch_warnings():
        # QUADPACK flags slow cycles where the answer is near 0 or 1; the bounds keep it honest
        warnings.simplefilter("ignore", integrate.IntegrationWarning)
        value = _imhof_integral(phi, inv_u_rho, x)
    return float(min(upper, max(1.0 - lower, value)))


def quadratic_form_quantile_imhof(eigenvalues: np.ndarray, p: float, rtol: float = 1e-5) -> float:
    """The t with P(Q ≤ t) = p for Q = Σ λ_i χ²_1,i (λ_i ≥ 0, not all 0; 0 < p < 1): the exact
    inverse of :func:`quadratic_form_sf_imhof`, found by Brent's method on log t from a bracket
    about Liu's approximation (:func:`quadratic_form_quantile`), to ``rtol`` relative in t (the
    inversion's own accuracy, ≲ 1e-6 in probability, bounds it where the density is small)."""
    from scipy.optimize import brentq

    lam = np.asarray(eigenvalues, float)
    if not (0.0 < p < 1.0) or lam.size == 0 or not np.all(np.isfinite(lam)) or np.any(lam < 0) or lam.max() <= 0:
        raise ValueError("need 0 < p < 1 and finite eigenvalues ≥ 0, not all zero")
    target = 1.0 - float(p)

    def gap(log_t: float) -> float:
        return quadratic_form_sf_imhof(lam, math.exp(log_t)) - target

    guess = quadratic_form_quantile(lam, target)
    log_t = math.log(guess if math.isfinite(guess) and guess > 0 else float(lam.sum()))
    lo, hi = log_t - 0.25, log_t + 0.25
    while gap(lo) < 0:  # P(Q > e^lo) still below 1 − p: the quantile lies further down
        lo -= 1.0
    while gap(hi) > 0:
        hi += 1.0
    return float(math.exp(brentq(gap, lo, hi, xtol=rtol)))


def _imhof_integral(phi, inv_u_rho, x: float) -> float:
    """½ + (1/π) ∫₀^∞ sin(φ(u) − x u/2) / (u ρ(u)) du (:func:`quadratic_form_sf_imhof`)."""
    from scipy import integrate

    w = 0.5 * x
    a = min(10.0, math.pi / w)  # at most half a period of the oscillation, which QAWF takes beyond
    head = integrate.quad(lambda u: math.sin(phi(u) - w * u) * inv_u_rho(u), 0.0, a,
                          limit=500, epsabs=1e-10, epsrel=1e-10)[0]
    # sin(φ − w(v + a)) = sin φ cos(wv + wa) − cos φ sin(wv + wa): four Fourier integrals ∫ f(v+a) g(wv),
    # f ∈ {sin φ, cos φ}/(uρ), g ∈ {cos, sin}
    fourier = {(f, g): integrate.quad(lambda v, f=f: getattr(math, f)(phi(v + a)) * inv_u_rho(v + a), 0.0,
                                      np.inf, weight=g, wvar=w, limlst=200)[0]
               for f in ("sin", "cos") for g in ("cos", "sin")}
    ca, sa = math.cos(w * a), math.sin(w * a)
    tail = (ca * fourier["sin", "cos"] - sa * fourier["sin", "sin"]
            - ca * fourier["cos", "sin"] - sa * fourier["cos", "cos"])
    return 0.5 + (head + tail) / math.pi


def _chernoff_bounds(lam: np.ndarray, x: float) -> tuple[float, float]:
    """Chernoff's bounds (P(Q > x), P(Q < x)) for Q = Σ λ_i χ²_1,i: min over s of
    e^(∓s x) Π (1 ∓ 2 s λ_i)^(−1/2) (the χ²₁ moment generating function), on a grid of s."""
    s_up = 0.5 / float(lam.max()) * (1.0 - np.logspace(-6, -1e-3, 60))  # s < 1/(2 λ_max)
    log_up = -s_up * x - 0.5 * np.log1p(-2.0 * np.outer(s_up, lam)).sum(axis=1)
    s_lo = np.logspace(-6, 6, 60) / max(float(lam.sum()), 1e-300)
    log_lo = s_lo * x - 0.5 * np.log1p(2.0 * np.outer(s_lo, lam)).sum(axis=1)
    return float(np.exp(min(0.0, log_up.min()))), float(np.exp(min(0.0, log_lo.min())))
