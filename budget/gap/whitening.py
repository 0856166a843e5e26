"""Decorrelating the spectral terms of the gap before they are summed.

The Allan variance at octave τ, the Welch octave bands and the low-frequency bands
(:mod:`budget.gap.lowfreq`) are overlapping views of one spectrum: on a model-following log
their z are correlated (adjacent Allan octaves 0.4–0.9 at long τ, long-τ Allan terms with the
low-frequency bands). A plain Σz² counts a misfit that several of them see once per term, so a
chance excess at τ ≈ 10–80 s that four Allan octaves share outweighs a misfit that only the
lowest band sees — and a likelihood comparison between two slow effects (bias instability
flat in the Allan deviation, rate random walk rising as τ^½) then follows the shared excess.

Here the spectral block z_s of each channel is replaced by its innovations w = L⁻¹·z_s, with
C = L·Lᵀ the covariance of z_s on the model itself: the leave-one-out z vectors of the
realizations (each against the others), pooled over channels that share the statistics' layout,
shrunk toward its diagonal with the Schäfer & Strimmer (2005) intensity (Stat. Appl. Genet.
Mol. Biol. 4, art. 32, target "D": λ = Σ_{i≠j} Var(r_ij)/Σ_{i≠j} r_ij² on the correlations,
clipped to [0, 1]). Then Σw² = z_sᵀC⁻¹z_s, the Gaussian log-likelihood of the block, and the
other terms (line, kurtosis, tails, slope, temperature: other statistics with their own
distributions) are added as they are. The map is fitted once per run, on the base model's
realizations, and kept: every Σz² of the run (measured, predicted, simulated, leave-one-out)
is taken in the same metric. The z themselves are still reported as measured.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Term kinds decorrelated together (one spectrum seen by three estimators).
SPECTRAL_KINDS = ("adev", "psd_band", "psd_low")


def shrinkage_intensity(z: np.ndarray) -> float:
    """Schäfer–Strimmer shrinkage intensity toward the diagonal for samples ``z`` (M, K)."""
    m = z.shape[0]
    if m < 3:
        return 1.0
    x = z - z.mean(0)
    sd = x.std(0, ddof=1)
    ok = sd > 0
    x = x[:, ok] / sd[ok]
    w = x[:, :, None] * x[:, None, :]                      # (M, k, k)
    r = w.mean(0) * m / (m - 1.0)
    var_r = w.var(0, ddof=1) * m / (m - 1.0) ** 2
    off = ~np.eye(r.shape[0], dtype=bool)
    den = float(np.sum(r[off] ** 2))
    return float(np.clip(np.sum(var_r[off]) / den, 0.0, 1.0)) if den > 0 else 1.0


def shrunk_covariance(z: np.ndarray) -> np.ndarray:
    """Covariance (about zero: the z are centred by construction) of samples ``z`` (M, K),
    off-diagonal terms shrunk by :func:`shrinkage_intensity`."""
    c = z.T @ z / z.shape[0]
    lam = shrinkage_intensity(z)
    out = (1.0 - lam) * c
    out[np.diag_indices_from(out)] = np.diag(c)
    return out


@dataclass(frozen=True)
class Whitening:
    """The spectral block of one channel's terms (``mask`` over its K terms) and the inverse
    Cholesky factor L⁻¹ of the block's covariance on the model (module docstring)."""

    mask: np.ndarray
    inv_chol: np.ndarray
    shrinkage: float = 0.0

    def apply(self, z: np.ndarray) -> np.ndarray:
        """z with its spectral block replaced by the innovations L⁻¹·z_s (works on (..., K))."""
        z = np.asarray(z, float)
        if z.shape[-1] != self.mask.size:
            return z
        out = z.copy()
        out[..., self.mask] = z[..., self.mask] @ self.inv_chol.T
        return out


def fit(z: np.ndarray, kinds: np.ndarray) -> Whitening:
    """The whitening of the spectral block from leave-one-out z vectors ``z`` (M, K)."""
    mask = np.isin(kinds, SPECTRAL_KINDS)
    block = z[:, mask]
    c = shrunk_covariance(block)
    still = np.diag(c) < 1e-9                           # a term that never moves stays as it is
    c[still, :] = 0.0
    c[:, still] = 0.0
    c[still, still] = 1.0
    lo = np.linalg.cholesky(c)
    inv = np.linalg.solve(lo, np.eye(lo.shape[0]))
    return Whitening(mask, inv, shrinkage_intensity(block))
