"""Bounds when no autofocus runs: the phase error itself must stay small.

Without PGA, the quadratic phase error at the aperture edge must stay ≤ π/4 (defocus), the cubic
≤ π/8 (asymmetric sidelobes) and what is left beyond the cubic ≤ 1° rms (seed 004).
Phase φ = 4π Δr/λ with the whole error assumed along the line of sight (worst case).

Error accumulates from the aperture start t = 0 (zero initial error, seed 004 assumption 4);
over t ∈ [0, Tc] with u = 2t/Tc − 1:

* constant acceleration error b: e = b t²/2 = b Tc²/8 (u+1)² → edge quadratic φ₂ = (4π/λ) b Tc²/8,
  no cubic → b ≤ λ φ₂,max/(4π) · 8/Tc² = λ/(2 Tc²) for π/4;
* gyro bias ε: e = g ε t³/6 = g ε Tc³/48 (u+1)³ → φ₂ = (4π/λ) g ε Tc³/16 and, with
  u³ = (2 P₃ + 3 P₁)/5, the cubic Legendre component at the edge φ₃ = (4π/λ) g ε Tc³/120;
* VRW and ARW: k·σ of φ₂ and φ₃ from the exact Legendre statistics of :mod:`.legendre`, and
  the rms beyond the cubic ≤ the fast residual limit.

Definitions (shared with the motion engine): edge quadratic phase = c₂ (P₂(1) − P₂(0)) = 1.5 c₂;
edge cubic phase = c₃ P₃(1) = c₃, with c_k the Legendre coefficients of the phase over u ∈ [−1, 1].
"""

from __future__ import annotations

import math

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from ..errors import InputError
from ..units import G0, phase_error_to_range_error
from .legendre import P2_EDGE_RISE, random_walk_constants
from .paper import _inputs
from .table import BoundsTable


class NoAutofocusAssumptions(BaseModel):
    """Phase limits without autofocus and the levels the errors couple to."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    quadratic_edge_limit_rad: float = Field(math.pi / 4, gt=0)
    cubic_edge_limit_rad: float = Field(math.pi / 8, gt=0)
    fast_residual_limit_deg: float = Field(1.0, gt=0, description="rms beyond cubic")
    k_sigma: float = Field(2.0, gt=0, le=6, description="random terms: k·σ ≤ the limit")
    accel_level_m_s2: float = Field(G0, gt=0)
    attitude_excursion_rad: float = Field(1.0, gt=0)
    gravity_m_s2: float = Field(G0, gt=0)


def no_autofocus_bounds(tc_s, wavelength_m, a: NoAutofocusAssumptions | None = None) -> BoundsTable:
    """Per-source bounds (SI) so that, without autofocus, the phase limits above hold."""
    a = a or NoAutofocusAssumptions()
    lam = float(wavelength_m)
    if not (math.isfinite(lam) and lam > 0):
        raise InputError("wavelength must be finite and > 0", field="wavelength_m", value=lam,
                         expected="λ in m, > 0")
    tc, _ = _inputs(tc_s, 1.0)
    # LOS range errors allowed by the phase limits
    q_m = phase_error_to_range_error(a.quadratic_edge_limit_rad, lam)
    c_m = phase_error_to_range_error(a.cubic_edge_limit_rad, lam)
    f_m = phase_error_to_range_error(math.radians(a.fast_residual_limit_deg), lam)
    g = a.gravity_m_s2

    b_const = 8.0 * q_m / tc**2  # constant acceleration error, from e = b Tc²/8 (u+1)²
    gyro_bias = np.minimum(16.0 * q_m / (g * tc**3), 120.0 * c_m / (g * tc**3))

    def noise_bound(kind: str, power: float, scale: float) -> np.ndarray:
        k = random_walk_constants(kind)
        per_unit = tc**power * scale  # position statistics scale as N·Tc^power (·g for ARW)
        lim_q = q_m / (a.k_sigma * P2_EDGE_RISE * k["coef_std"][2] * per_unit)
        lim_c = c_m / (a.k_sigma * k["coef_std"][3] * per_unit)
        lim_f = f_m / (k["resid_rms"][3] * per_unit)
        return np.minimum(np.minimum(lim_q, lim_c), lim_f)

    return BoundsTable(
        mode="no-autofocus", tc_s=tc, range_resolution_m=np.full_like(tc, np.nan),
        accel_scale_factor=b_const / a.accel_level_m_s2,
        gyro_scale_factor=b_const / (g * a.attitude_excursion_rad),
        misalignment_rad=np.arcsin(np.minimum(b_const / a.accel_level_m_s2, 1.0)),
        accel_bias_m_s2=b_const,
        gyro_bias_rad_s=gyro_bias,
        accel_vrw_m_s2_rt_hz=noise_bound("vrw", 1.5, 1.0),
        gyro_arw_rad_s_rt_hz=noise_bound("arw", 2.5, g),
        notes=(f"no autofocus, wavelength {lam:.6g} m: {a.model_dump()}",),
        assumptions={"wavelength_m": lam, **a.model_dump(mode="json")},
    )
