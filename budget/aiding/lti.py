"""Exact sampling of a discretised linear Gaussian system x_{k+1} = Φ_k x_k + w_k, w_k ~ N(0, Qd_k).

Used as the truth simulator of :mod:`budget.aiding` (so that a consistent filter is exactly
consistent) and for the flexure process. All trials share Φ and Qd; each trial draws its own
noise from one ``numpy.random.Generator``.
"""

from __future__ import annotations

import numpy as np


def psd_sqrt(Q: np.ndarray) -> np.ndarray:
    """L with L Lᵀ = Q for a symmetric positive *semi*-definite Q (…, n, n) (eigen-decomposition).

    Cholesky fails on the singular Qd of random-constant states; this does not.
    """
    w, U = np.linalg.eigh(0.5 * (Q + np.swapaxes(Q, -1, -2)))
    return U * np.sqrt(np.clip(w, 0.0, None))[..., None, :]


def sample_initial(P0: np.ndarray, trials: int, rng: np.random.Generator) -> np.ndarray:
    """x0 ~ N(0, P0) for every trial, (T, n)."""
    L = psd_sqrt(P0)
    return rng.standard_normal((trials, P0.shape[0])) @ L.T


def sample_lti(phi: np.ndarray, qd: np.ndarray, x0: np.ndarray, n_samples: int,
               rng: np.random.Generator) -> np.ndarray:
    """Trajectories (T, N, n) of a time-invariant system from x0 (T, n)."""
    T, n = x0.shape
    L = psd_sqrt(qd)
    out = np.empty((T, n_samples, n))
    out[:, 0] = x0
    x = x0
    for k in range(1, n_samples):
        x = x @ phi.T + rng.standard_normal((T, n)) @ L.T
        out[:, k] = x
    return out


def sample_ltv(transitions, x0: np.ndarray, n_samples: int, rng: np.random.Generator,
               chunk: int = 1000) -> np.ndarray:
    """Trajectories (T, N, n) of a time-varying system; ``transitions(start, stop)`` returns
    (Φ, Qd) stacks of shape (stop−start, n, n) for the steps k → k+1, k = start … stop−1."""
    T, n = x0.shape
    out = np.empty((T, n_samples, n))
    out[:, 0] = x0
    x = x0
    for start in range(0, n_samples - 1, chunk):
        stop = min(start + chunk, n_samples - 1)
        phis, qds = transitions(start, stop)
        Ls = psd_sqrt(qds)
        for i in range(stop - start):
            x = x @ phis[i].T + rng.standard_normal((T, n)) @ Ls[i].T
            out[:, start + i + 1] = x
    return out
