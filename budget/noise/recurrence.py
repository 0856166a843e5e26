"""Fast constant-coefficient vector recurrence s_k = M s_{k−1} + u_k (the steady-state filter).

Once a Kalman filter's gain has converged, filtering and RTS smoothing are such recurrences.
Instead of a Python loop, the recurrence is turned into n scalar IIR filters sharing one
denominator (run by ``scipy.signal.lfilter`` in C):

    Σ_{m=0..n} c_m s_{k−m} = Σ_{m=0..n−1} B_m u_{k−m}

with c the characteristic polynomial of M (c₀ = 1) and B₀ = I, B_m = M B_{m−1} + c_m I — the
Faddeev–LeVerrier expansion of adj(I − M z⁻¹), exact by Cayley–Hamilton. An initial state s₋₁
is folded into the first input (u₀ ← u₀ + M s₋₁). The all-pole part 1/c(z) is applied as a
cascade of second-order sections built from the eigenvalues of M.
"""

from __future__ import annotations

import numpy as np
from scipy import signal


def linear_recurrence(M: np.ndarray, u: np.ndarray, s0: np.ndarray | None = None) -> np.ndarray:
    """States s_0 … s_{L−1} (rows) of s_k = M s_{k−1} + u_k; ``u`` has shape (L, n)."""
    M = np.asarray(M, dtype=float)
    n = M.shape[0]
    u = np.array(u, dtype=float, copy=True).reshape(-1, n)
    if u.shape[0] == 0:
        return u
    if s0 is not None:
        u[0] += M @ np.asarray(s0, float)
    c = np.real(np.poly(M))
    v = u.copy()  # B_0 = I
    B = np.eye(n)
    for m in range(1, n):
        B = M @ B + c[m] * np.eye(n)
        v[m:] += u[:-m] @ B.T
    # The all-pole part runs as second-order sections: far less round-off than one direct-form
    # filter when poles cluster near the unit circle.
    sos = signal.zpk2sos([], np.linalg.eigvals(M), 1.0)
    return signal.sosfilt(sos, v, axis=0)
