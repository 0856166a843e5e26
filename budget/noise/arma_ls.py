"""Least-squares ARMA(p, q) estimation (the prediction-error method of seed 000 §3.1).

Model, seed 000 (11): x(k) = Σᵢ φᵢ x(k−i) + w(k) + Σⱼ θⱼ w(k−j).

The residuals conditional on the first p samples and on zero pre-sample noise,
e(k) = θ(B)⁻¹ φ(B) x(k) for k ≥ p, are computed with one IIR filter pass. Their sum of squares
is minimised by Gauss–Newton (derivatives are themselves filtered series: ∂e/∂φᵢ =
−θ(B)⁻¹ x(k−i), ∂e/∂θⱼ = −θ(B)⁻¹ e(k−j)), started from the Hannan–Rissanen estimate (long
Yule–Walker AR → innovations → one linear regression) and guarded by step halving that keeps
the MA part invertible. AR models are plain linear least squares. This is what MATLAB's
``armax`` (used by the paper) minimises, up to its handling of the first samples.

``start`` (≥ p) is the first sample whose residual enters the sum of squares. Candidates compared
by AIC/FPE must share it (and so their n): residuals of AR(1) from k = 1 and of AR(3) from k = 3
differ by two squared innovations, a random term of standard deviation ≈ 2 in n·ΔAIC — as large as
the penalty 2k it is compared with — which made AIC overfit well beyond its asymptotic rate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import linalg, signal


@dataclass(frozen=True)
class LsEstimate:
    phi: np.ndarray
    theta: np.ndarray
    sigma2: float          # SSR / n
    n: int                 # number of residuals used
    cov: np.ndarray        # asymptotic covariance of (φ, θ): σ² (JᵀJ)⁻¹
    iterations: int
    converged: bool


def max_root_modulus(coeffs: np.ndarray, sign: float) -> float:
    """Largest |root| of z^n + sign·(c₁ z^{n−1} + … + c_n); 0 for an empty polynomial.

    AR: sign = −1 (stationary when < 1); MA: sign = +1 (invertible when < 1).
    """
    c = np.asarray(coeffs, float)
    if c.size == 0:
        return 0.0
    return float(np.max(np.abs(np.roots(np.r_[1.0, sign * c]))))


def _lagged(x: np.ndarray, p: int) -> np.ndarray:
    """Columns x(k−1) … x(k−p) for k = p … N−1."""
    n = x.size - p
    return np.column_stack([x[p - i:p - i + n] for i in range(1, p + 1)]) if p else np.empty((n, 0))


def residuals(x: np.ndarray, phi: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Conditional residuals e(k), k = p … N−1 (zero pre-sample noise)."""
    p = phi.size
    u = x[p:] - (_lagged(x, p) @ phi if p else 0.0)
    return signal.lfilter([1.0], np.r_[1.0, theta], u) if theta.size else u


def _yule_walker(x: np.ndarray, order: int) -> np.ndarray:
    n = x.size
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    spec = np.fft.rfft(x, nfft)
    acov = np.fft.irfft(spec * np.conj(spec), nfft)[:order + 1] / n
    return linalg.solve_toeplitz(acov[:order], acov[1:order + 1])


def _shrink_to_invertible(theta: np.ndarray, limit: float = 0.98) -> np.ndarray:
    """Scale MA roots into |z| ≤ limit (θⱼ → θⱼ ρʲ)."""
    r = max_root_modulus(theta, +1.0)
    if r < limit:
        return theta
    rho = limit / r
    return theta * rho ** np.arange(1, theta.size + 1)


def hannan_rissanen(x: np.ndarray, p: int, q: int) -> tuple[np.ndarray, np.ndarray]:
    """Initial (φ, θ): long AR by Yule–Walker, its innovations, then one OLS regression."""
    n = x.size
    # A long AR order lets a near-non-invertible MA (|θ| → 1) be represented well enough.
    long = int(max(p + q + 1, min(200, n // 20)))
    a = _yule_walker(x, long)
    ehat = signal.lfilter(np.r_[1.0, -a], [1.0], x)
    ehat[:long] = 0.0
    k0 = long + q
    cols = [x[k0 - i:n - i] for i in range(1, p + 1)] + [ehat[k0 - j:n - j] for j in range(1, q + 1)]
    beta = np.linalg.lstsq(np.column_stack(cols), x[k0:], rcond=None)[0]
    return beta[:p], _shrink_to_invertible(beta[p:])


def _jacobian_t(x: np.ndarray, e: np.ndarray, p: int, theta: np.ndarray) -> np.ndarray:
    """Transposed Jacobian (rows = parameters), contiguous for the filter pass."""
    n = e.size
    rows = np.empty((p + theta.size, n))
    for i in range(1, p + 1):
        rows[i - 1] = -x[p - i:p - i + n]
    for j in range(1, theta.size + 1):
        rows[p + j - 1, :j] = 0.0
        rows[p + j - 1, j:] = -e[:-j]
    return signal.lfilter([1.0], np.r_[1.0, theta], rows, axis=1)


def fit_ls(x: np.ndarray, p: int, q: int, *, start: int | None = None, max_iter: int = 100,
           tol: float = 1e-10) -> LsEstimate:
    """Conditional least-squares ARMA(p, q) fit of the zero-mean series ``x``; the sum of squares
    runs over the residuals e(k), k ≥ ``start`` (default p; module doc)."""
    x = np.asarray(x, dtype=np.float64)
    start = p if start is None else int(start)
    if start < p:
        raise ValueError(f"start {start} < p {p}")
    d = start - p  # residuals computed from k = p, the first d of them left out of the sum
    if q == 0:
        X, y = _lagged(x, p)[d:], x[start:]
        XtX = X.T @ X
        # lstsq: a deterministic series (a sinusoid, an alternating sign) makes XᵀX singular
        phi = np.linalg.lstsq(X, y, rcond=None)[0]
        e = y - X @ phi
        s2 = float(e @ e / e.size)
        return LsEstimate(phi, np.zeros(0), s2, e.size, s2 * np.linalg.pinv(XtX), 1, True)
    phi, theta = hannan_rissanen(x, p, q)
    e_all = residuals(x, phi, theta)
    e = e_all[d:]
    ssr = float(e @ e)
    converged, it, prev = False, 0, None
    for it in range(1, max_iter + 1):
        Jt = _jacobian_t(x, e_all, p, theta)[:, d:]
        step = -np.linalg.pinv(Jt @ Jt.T) @ (Jt @ e)  # pinv: singular on a degenerate series
        if prev is not None:
            # Misspecified models make Gauss–Newton converge linearly (steps shrink by a fixed
            # ratio r along one direction); then jump to the limit, step/(1 − r) (Aitken).
            r = float(step @ prev / (prev @ prev))
            cos = float(step @ prev / (np.linalg.norm(step) * np.linalg.norm(prev) + 1e-300))
            if 0.0 < r < 0.9 and cos > 0.99:
                step = step / (1.0 - r)
        lam = 1.0
        while lam > 1e-6:
            cand = np.r_[phi, theta] + lam * step
            th = cand[p:]
            if max_root_modulus(th, +1.0) < 1.0:
                e_all_new = residuals(x, cand[:p], th)
                e_new = e_all_new[d:]
                ssr_new = float(e_new @ e_new)
                if np.isfinite(ssr_new) and ssr_new <= ssr:
                    break
            lam /= 2.0
        else:
            converged = True  # no descent direction left: at the minimum within rounding
            break
        rel = (ssr - ssr_new) / ssr
        phi, theta, e, e_all, ssr = cand[:p], th, e_new, e_all_new, ssr_new
        prev = lam * step
        if rel < tol and np.max(np.abs(lam * step)) < 1e-7:
            converged = True
            break
    Jt = _jacobian_t(x, e_all, p, theta)[:, d:]
    s2 = ssr / e.size
    return LsEstimate(phi, theta, s2, e.size, s2 * np.linalg.pinv(Jt @ Jt.T), it, converged)
