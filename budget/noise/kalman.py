"""State-augmented Kalman filter for ARMA-coloured noise, and the RTS smoother (seed 000 §3.2).

Seed 000 (14)–(16), generalised from ARMA(2,1) to any ARMA(p, q) with p' = max(p, 1):

    X_k = [x_k, …, x_{k−p'+1}, w_k, …, w_{k−q+1}]ᵀ
    x_{k+1} = Σφᵢ x_{k+1−i} + Σθⱼ w_{k+1−j} + w_{k+1},   Z_k = x_k + v_k

so F has (φ, θ) in its first row, shifts below, and w_{k+1} enters the x and w₀ rows (G).
Paper settings: X₀ = 0, P₀ = I, R = δ₂ = variance of the static data the model was fitted to,
Q = δ₁·I with δ₁ the ARMA residual variance (``process_noise="paper"``); ``"model"`` uses the
model-consistent Q = δ₁ G Gᵀ instead. Updates use the Joseph form (always symmetric and
positive semi-definite).

Speed: the covariance recursion does not depend on the data, so it is run once until the gain
stops changing (relative change ≤ ``tol``); the first T samples are filtered with the
time-varying gains, the rest with the steady-state gain as one linear recurrence
(:func:`~budget.noise.recurrence.linear_recurrence`, C speed). The RTS smoother (Rauch, Tung &
Striebel 1965: C_k = P_k Fᵀ P⁻_{k+1}⁻¹, x̃_k = x̂_k + C_k (x̃_{k+1} − F x̂_k)) is split the same way.
The filtered estimate x̂ of x is what the paper plots as the filtered signal; it is also a
low-pass filter of the measurement — see :mod:`.kalman_response` for what it does to motion.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import linalg

from ..errors import InputError
from .arguments import float_series
from .arma import ArmaFit
from .recurrence import linear_recurrence

MAX_TRANSIENT = 200_000


def state_space(fit: ArmaFit) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(F, G, H) of the augmented state for ``fit`` (module doc)."""
    p, q = max(fit.p, 1), fit.q
    n = p + q
    F = np.zeros((n, n))
    F[0, :fit.p] = fit.phi
    F[0, p:] = fit.theta
    F[1:p, :p - 1] = np.eye(p - 1)
    if q > 1:
        F[p + 1:, p:n - 1] = np.eye(q - 1)
    G = np.zeros(n)
    G[0] = 1.0
    if q:
        G[p] = 1.0
    H = np.zeros(n)
    H[0] = 1.0
    return F, G, H


@dataclass(frozen=True)
class KalmanResult:
    """Filtered or smoothed series; ``signal`` is x̂ (+ the removed mean), same unit as ``z``."""

    signal: np.ndarray
    states: np.ndarray
    variance_before: float
    variance_after: float
    mean_removed: float
    smoothed: bool
    transient_samples: int

    def summary(self) -> str:
        what = "RTS smoother" if self.smoothed else "Kalman filter"
        return (f"{what}: variance {self.variance_before:.4g} → {self.variance_after:.4g} "
                f"(÷{self.variance_before / self.variance_after:.3g}); gain steady after "
                f"{self.transient_samples} samples")

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"signal": self.signal})

    def to_dict(self) -> dict:
        """JSON-ready: filter or RTS smoother, variance before/after, mean removed, transient
        samples and the series length; the filtered series itself is in :meth:`to_frame`."""
        return {"smoothed": bool(self.smoothed), "samples": int(self.signal.size),
                "variance_before": float(self.variance_before), "variance_after": float(self.variance_after),
                "mean_removed": float(self.mean_removed), "transient_samples": int(self.transient_samples)}


class ArmaKalman:
    """Kalman filter / RTS smoother of seed 000 for one fitted ARMA model."""

    def __init__(self, fit: ArmaFit, *, measurement_variance: float | None = None,
                 process_noise: str = "paper", p0: float = 1.0, tol: float = 1e-13):
        if process_noise not in ("paper", "model"):
            raise InputError(f"unknown process_noise {process_noise!r}", field="process_noise",
                             expected="paper (Q = δ₁·I) or model (Q = δ₁·G·Gᵀ)")
        R = fit.data_variance if measurement_variance is None else measurement_variance
        if isinstance(R, bool) or not isinstance(R, numbers.Real) or not (math.isfinite(R) and R > 0):
            raise InputError("measurement variance must be positive", field="measurement_variance",
                             value=R, expected="R in the series' unit squared, a finite number > 0")
        R = float(R)
        if isinstance(p0, bool) or not isinstance(p0, numbers.Real) or not (math.isfinite(p0) and p0 > 0):
            # P₀ = p0·I is a covariance: ≤ 0 or NaN gave a wrong transient or an SVD failure
            raise InputError("initial covariance scale p0 must be positive", field="p0", value=p0,
                             expected="a finite number > 0 (P₀ = p0·I, the paper's 1)")
        F, G, _ = state_space(fit)
        n = F.shape[0]
        Q = fit.sigma2 * (np.eye(n) if process_noise == "paper" else np.outer(G, G))
        self._setup(fit, Q, R, p0 * np.eye(n), process_noise, tol)

    @classmethod
    def exact_predictor(cls, fit: ArmaFit, tol: float = 1e-13) -> "ArmaKalman":
        """The model's own exact one-step predictor: Q = σ² G Gᵀ, no measurement noise (R = 0),
        the state started from the model's stationary covariance P∞ = F P∞ Fᵀ + Q (zero for a
        non-stationary fit, where the predictor starts from Q). Its innovations are the
        prediction errors of the exact Gaussian likelihood (Harvey 1989, §3.4), tending to the
        ARMA's own w(k) with S = σ²; :mod:`.adequacy` tests them."""
        F, G, _ = state_space(fit)
        Q = fit.sigma2 * np.outer(G, G)
        # the first prediction is F P₀ Fᵀ + Q: P₀ = P∞ makes it P∞ itself
        P0 = linalg.solve_discrete_lyapunov(F, Q) if fit.stationary else np.zeros_like(Q)
        kf = cls.__new__(cls)
        kf._setup(fit, Q, 0.0, P0, "model", tol)
        return kf

    def _setup(self, fit: ArmaFit, Q: np.ndarray, R: float, P0: np.ndarray, process_noise: str,
               tol: float) -> None:
        self.fit = fit
        self.F, self.G, self.H = state_space(fit)
        self.Q, self.R, self.P0 = Q, R, P0
        self.process_noise = process_noise
        self._riccati(tol)

    @property
    def n_states(self) -> int:
        return self.F.shape[0]

    def _riccati(self, tol: float) -> None:
        """Gains until steady: K[k], filtered P[k], predicted Pp[k] for k < T, then *_ss."""
        F, H, Q, R = self.F, self.H, self.Q, self.R
        n = F.shape[0]
        Ks, Ps, Pps = [], [], []
        P = self.P0
        last = np.inf
        self.gain_converged = False
        for _ in range(MAX_TRANSIENT):
            Pp = F @ P @ F.T + Q
            K = Pp @ H / (H @ Pp @ H + R)
            IKH = np.eye(n) - np.outer(K, H)
            P = IKH @ Pp @ IKH.T + R * np.outer(K, K)
            if Ks:
                change = np.max(np.abs(K - Ks[-1])) / np.max(np.abs(K))
                if change <= tol or (change < 1e-10 and change >= last):  # settled to rounding
                    self.gain_converged = True
                    break
                last = change
            Ks.append(K)
            Ps.append(P)
            Pps.append(Pp)
        self.K_ss, self.P_ss, self.Pp_ss = K, P, Pp
        self.T = len(Ks)
        self._K, self._P, self._Pp = np.array(Ks), np.array(Ps), np.array(Pps)
        self.A_ss = (np.eye(n) - np.outer(K, H)) @ F
        self.C_ss = P @ F.T @ np.linalg.pinv(Pp)

    def _gain(self, k: int) -> np.ndarray:
        return self._K[k] if k < self.T else self.K_ss

    def _states(self, z: np.ndarray) -> np.ndarray:
        n, N = self.n_states, z.size
        X = np.empty((N, n))
        x = np.zeros(n)  # X₀ = 0
        T = min(self.T, N)
        for k in range(T):
            x = self.F @ x
            x = x + self._K[k] * (z[k] - x[0])
            X[k] = x
        if N > T:
            X[T:] = linear_recurrence(self.A_ss, np.outer(z[T:], self.K_ss), x)
        return X

    def _prep(self, z):
        z = float_series(z, "z", "a 1-D array of samples in the fitted series' unit")
        if z.ndim != 1 or z.size < 2:
            raise InputError("expected a 1-D series of at least 2 samples", field="z")
        bad = np.flatnonzero(~np.isfinite(z))
        if bad.size:
            raise InputError(f"{bad.size} non-finite sample(s), first at index {bad[0]}", field="z")
        return z

    def filter(self, z, *, center: bool = True) -> KalmanResult:
        """Filter ``z``; with ``center`` its mean is removed first and added back."""
        z = self._prep(z)
        mean = float(z.mean()) if center else 0.0
        X = self._states(z - mean)
        out = X[:, 0] + mean
        return KalmanResult(out, X, float(np.var(z)), float(np.var(out)), mean, False, self.T)

    def smooth(self, z, *, center: bool = True) -> KalmanResult:
        """RTS fixed-interval smoothing of ``z`` (post-processing)."""
        z = self._prep(z)
        mean = float(z.mean()) if center else 0.0
        X = self._states(z - mean)
        N, T, F = z.size, self.T, self.F
        Xs = np.empty_like(X)
        Xs[-1] = X[-1]
        start = N - 1  # first index still to compute is start − 1
        if N - 1 > T:
            # Reverse time: r_0 = x̂_{N−1}, r_j = C r_{j−1} + (I − C F) x̂_{N−1−j}.
            D = np.eye(self.n_states) - self.C_ss @ F
            u = np.empty((N - T, self.n_states))
            u[0] = X[-1]
            u[1:] = X[N - 2:T - 1 if T > 0 else None:-1] @ D.T
            Xs[T:] = linear_recurrence(self.C_ss, u)[::-1]
            start = T
        for k in range(start - 1, -1, -1):
            Pp_next = self._Pp[k + 1] if k + 1 < T else self.Pp_ss
            C = self._P[k] @ F.T @ np.linalg.pinv(Pp_next)
            Xs[k] = X[k] + C @ (Xs[k + 1] - F @ X[k])
        out = Xs[:, 0] + mean
        return KalmanResult(out, Xs, float(np.var(z)), float(np.var(out)), mean, True, self.T)

    def summary(self) -> str:
        return (f"Kalman filter for {self.fit.name}: {self.n_states} states, Q = δ₁·"
                f"{'I' if self.process_noise == 'paper' else 'G·Gᵀ'} (δ₁ = {self.fit.sigma2:.4g}), "
                f"R = δ₂ = {self.R:.4g}; steady gain {np.array2string(self.K_ss, precision=4)} after "
                f"{self.T} samples{'' if self.gain_converged else ' (NOT converged)'}")
