"""Phase error over the aperture and its Legendre decomposition (seed 004).

Phase error φ = 4π·Δr/λ of the range error Δr = R_true − R_assumed (two-way; radar or sonar
through the scenario's λ = c/f0, seed 003 (12); sign convention in :mod:`budget.units`).
Over normalised aperture time u = 2(t − t_start)/(t_end − t_start) − 1 ∈ [−1, 1], the phase is
fitted by least squares with Legendre polynomials P0 = 1, P1 = u, P2 = (3u² − 1)/2,
P3 = (5u³ − 3u)/2: φ(u) ≈ c0 + c1·P1 + c2·P2 + c3·P3 + residual. Reported per trial:

* ``constant_rad`` = c0 (image shift only in phase);
* ``linear_edge_rad`` = c1 = the linear component's value at the edge (u = 1) minus the centre
  (shifts the image in azimuth);
* ``quadratic_edge_rad`` = c2·(P2(1) − P2(0)) = 1.5·c2: the quadratic component at the aperture
  edge relative to the centre — the edge quadratic phase error (defocus). A pure phase α·u²
  gives exactly α;
* ``cubic_edge_rad`` = c3·(P3(1) − P3(0)) = c3: the cubic component at the edge relative to
  the centre (asymmetric sidelobes). A pure α·u³ gives 0.4·α, because its other 0.6·α·u is a
  linear term (a shift), which P3 is orthogonal to;
* ``residual_rms_deg``: rms over the aperture of φ minus the cubic fit, in degrees (what PGA
  with a cubic model cannot remove).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np


@lru_cache(maxsize=16)
def legendre_basis(n_samples: int) -> tuple[np.ndarray, np.ndarray]:
    """Basis (N, 4) of P0..P3 on u = linspace(−1, 1, N) and its least-squares pseudo-inverse (4, N)."""
    u = np.linspace(-1.0, 1.0, n_samples)
    basis = np.stack([np.ones_like(u), u, 0.5 * (3 * u**2 - 1), 0.5 * (5 * u**3 - 3 * u)], axis=1)
    pinv = np.linalg.pinv(basis)
    basis.setflags(write=False)
    pinv.setflags(write=False)
    return basis, pinv


@dataclass
class PhaseDecomposition:
    """Legendre decomposition of phase series; every field has the leading shape of the input."""

    constant_rad: np.ndarray
    linear_edge_rad: np.ndarray
    quadratic_edge_rad: np.ndarray
    cubic_edge_rad: np.ndarray
    residual_rms_deg: np.ndarray


def decompose_phase(phase_rad: np.ndarray) -> PhaseDecomposition:
    """Decompose phase series (..., N) sampled uniformly over the aperture (N ≥ 5)."""
    phase = np.asarray(phase_rad, dtype=float)
    n = phase.shape[-1]
    if n < 5:
        raise ValueError("the aperture needs at least 5 samples for a cubic fit plus a residual")
    basis, pinv = legendre_basis(n)
    coef = phase @ pinv.T                      # (..., 4)
    resid = phase - coef @ basis.T
    rms = np.sqrt(np.mean(resid * resid, axis=-1))
    return PhaseDecomposition(constant_rad=coef[..., 0], linear_edge_rad=coef[..., 1],
                              quadratic_edge_rad=1.5 * coef[..., 2], cubic_edge_rad=coef[..., 3],
                              residual_rms_deg=rms * (180.0 / math.pi))
