"""Fixed-interval Rauch–Tung–Striebel smoother over the filter of :mod:`budget.aiding.kalman`.

RTS (Rauch, Tung & Striebel 1965; seed 002's smoothing recursion)::

    A_k   = P⁺_k Φ_kᵀ (P⁻_{k+1})⁻¹
    x̂ˢ_k = x̂⁺_k + A_k (x̂ˢ_{k+1} − Φ_k x̂⁺_k)
    Pˢ_k  = P⁺_k + A_k (Pˢ_{k+1} − P⁻_{k+1}) A_kᵀ,   starting from x̂ˢ_N = x̂⁺_N, Pˢ_N = P⁺_N.

As in the filter, A_k and Pˢ are shared by all trials and applied to the (T, n) batch.

Memory: the filter keeps x̂⁺, P⁺, P⁻ only at checkpoints (measurement epochs, the ends, and at
least every ``MAX_INTERVAL`` samples). Between two checkpoints there is no update, so the
smoother re-runs the prediction over the interval from the earlier checkpoint and then steps
backwards through it: memory O(T·interval·n) instead of O(T·N·n), twice the prediction work.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.linalg import LinAlgError, cho_factor, cho_solve

from .kalman import FilterOutput
from .system import AidedSystem, TransitionCache


@dataclass
class SmootherOutput:
    """``estimate`` (T, N, s) smoothed stored components, ``p_diag`` (N, n), and the full smoothed
    covariance at the filter's checkpoints ``p_smooth`` (C, n, n), ``x_smooth`` (T, C, n)."""

    store_index: np.ndarray
    estimate: np.ndarray
    p_diag: np.ndarray
    checkpoints: np.ndarray
    x_smooth: np.ndarray
    p_smooth: np.ndarray

    def to_dict(self) -> dict:
        """JSON-ready: trials, samples, states and checkpoints."""
        T, N, _ = self.estimate.shape
        return {"trials": T, "samples": N, "states": int(self.p_diag.shape[1]),
                "store_index": np.asarray(self.store_index).tolist(), "checkpoints": int(self.checkpoints.size)}

    def summary(self) -> str:
        """One line: trials, samples, states and checkpoints."""
        d = self.to_dict()
        return (f"RTS smoother: {d['trials']} trials × {d['samples']} samples, {d['states']} states, "
                f"{d['checkpoints']} checkpoints")

    def to_frame(self) -> pd.DataFrame:
        """Smoothed 1σ of every state per sample (columns ``sigma_<index>``)."""
        return pd.DataFrame(np.sqrt(np.clip(self.p_diag, 0, None)),
                            columns=[f"sigma_{i}" for i in range(self.p_diag.shape[1])])


def _gain(P_post: np.ndarray, phi: np.ndarray, P_prior_next: np.ndarray) -> np.ndarray:
    """A = P⁺ Φᵀ (P⁻)⁻¹ via Cholesky; pseudo-inverse when P⁻ is singular (unexcited states)."""
    B = phi @ P_post  # = (P⁺ Φᵀ)ᵀ
    try:
        return cho_solve(cho_factor(P_prior_next), B).T
    except LinAlgError:
        return (np.linalg.pinv(P_prior_next, hermitian=True) @ B).T


def run_rts(system: AidedSystem, filt: FilterOutput) -> SmootherOutput:
    """Smooth the filter output ``filt`` (same system, same trials)."""
    sel = filt.store_index
    ck = filt.checkpoints
    T, C, n = filt.x_post.shape
    N = system.n_samples
    est = np.empty((T, N, sel.size))
    p_diag = np.empty((N, n))
    x_s = np.empty((T, C, n))
    p_s = np.empty((C, n, n))
    trans = TransitionCache(system, "filter")
    xs_next, Ps_next = filt.x_post[:, -1].copy(), filt.p_post[-1].copy()
    x_s[:, -1], p_s[-1] = xs_next, Ps_next
    est[:, ck[-1]] = xs_next[:, sel]
    p_diag[ck[-1]] = np.diag(Ps_next)
    for c in range(C - 2, -1, -1):
        a, b = int(ck[c]), int(ck[c + 1])
        L = b - a
        # forward re-prediction inside the interval: x̂⁺(i) = x̂⁻(i), i = a+1 … b−1
        xf = np.empty((L, T, n))
        Pf = np.empty((L, n, n))
        phis = np.empty((L, n, n))
        xf[0], Pf[0] = filt.x_post[:, c], filt.p_post[c]
        for i in range(L):
            phi, qd = trans.get(a + i)
            phis[i] = phi
            if i + 1 < L:
                xf[i + 1] = xf[i] @ phi.T
                Pf[i + 1] = phi @ Pf[i] @ phi.T + qd
        for i in range(L - 1, -1, -1):
            phi = phis[i]
            P_prior_next = filt.p_prior[c + 1] if i == L - 1 else Pf[i + 1]
            A = _gain(Pf[i], phi, P_prior_next)
            xs = xf[i] + (xs_next - xf[i] @ phi.T) @ A.T
            Ps = Pf[i] + A @ (Ps_next - P_prior_next) @ A.T
            Ps = 0.5 * (Ps + Ps.T)
            est[:, a + i] = xs[:, sel]
            p_diag[a + i] = np.diag(Ps)
            xs_next, Ps_next = xs, Ps
        x_s[:, c], p_s[c] = xs_next, Ps_next
    return SmootherOutput(store_index=sel, estimate=est, p_diag=p_diag, checkpoints=ck,
                          x_smooth=x_s, p_smooth=p_s)
