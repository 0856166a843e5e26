"""Legendre statistics of random-walk position errors over the aperture (exact, by covariance).

A velocity random walk of density N (m/s²/√Hz) gives a position error
e(t) = N ∫₀ᵗ (t − s) dW(s); an angle random walk N_θ (rad/√s) tilting gravity g gives
e(t) = g N_θ ∫₀ᵗ (t − s)²/2 dW(s) (accelerometer errors enter position by double
integration, gyro errors by triple integration through gravity). Over t ∈ [0, Tc] mapped to
u = 2t/Tc − 1 ∈ [−1, 1], e(u) = Σ c_k P_k(u) + r(u).

For unit density, Tc = 1 s (and g = 1 for ARW) this module returns, from the exact covariance of
e on a fine grid (no Monte Carlo):

* ``endpoint_std``: std of e(Tc) — √(1/3) (VRW) and √(1/20) (ARW), the closed forms;
* ``coef_std[k]``: std of the Legendre coefficient c_k, k = 0…3;
* ``resid_rms[m]``: √E[mean r²] after removing the best-fit polynomial of degree ≤ m.

Scale: VRW results × N·Tc^1.5, ARW results × g·N_θ·Tc^2.5.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.polynomial import legendre as L


@lru_cache(maxsize=4)
def random_walk_constants(kind: str, n: int = 1500) -> dict[str, np.ndarray | float]:
    """Dimensionless Legendre statistics of ``kind`` ``'vrw'`` or ``'arw'`` (see module doc)."""
    power = {"vrw": 1, "arw": 2}.get(kind)
    if power is None:
        raise ValueError("kind must be 'vrw' or 'arw'")
    ds = 1.0 / n
    t = (np.arange(n) + 0.5) * ds
    s = np.arange(n) * ds  # left ends of the white-noise increments
    lag = np.clip(t[:, None] - s[None, :], 0.0, None)
    kernel = lag**power / (1.0 if power == 1 else 2.0)  # e = kernel @ dW, var(dW) = ds
    u = 2.0 * t - 1.0
    basis = L.legvander(u, 3)  # (n, 4)
    proj = np.linalg.pinv(basis)  # least-squares coefficients c = proj @ e
    cov_c = proj @ kernel @ kernel.T @ proj.T * ds
    resid = []
    for m in range(4):
        b = basis[:, : m + 1]
        hat = b @ np.linalg.pinv(b)
        r = kernel - hat @ kernel
        resid.append(np.sqrt(np.sum(r * r) * ds / n))
    end = np.sqrt(np.sum((np.clip(1.0 - s, 0, None) ** power / (1.0 if power == 1 else 2.0)) ** 2) * ds)
    return {"endpoint_std": float(end), "coef_std": np.sqrt(np.diag(cov_c)),
            "resid_rms": np.array(resid)}


#: P2(1) − P2(0): the quadratic Legendre component's rise from aperture centre to edge per unit c2.
P2_EDGE_RISE = 1.5
