"""What autofocus cannot remove: fast phase limits (seed 004).

PGA removes smooth phase errors; a fast harmonic phase error must stay ≤ 1° peak and random
phase noise ≤ 1° rms. As LOS range error: Δr = λ/(4π)·φ (1.7e-5 m at 24 GHz, 5.4e-6 m at
77 GHz). A fast sinusoid of amplitude β rad gives paired echoes at 20·log10(β/2) dB; white
phase noise of σ rad moves σ² of the main-lobe energy into the sidelobes (ISLR ≈ 10·log10 σ²).

Random walks also leave a part PGA does not take: what lies beyond PGA's settled window, K
cycles per aperture — the one definition of "what PGA cannot remove" that the Monte Carlo uses
too (:mod:`budget.sar.residual`; K = 2.5 by default, PGA's 8-sample window on the presets). Its
expected rms is exact from the random walk's covariance. :func:`fast_phase_limits` turns the
1° rms limit into VRW and ARW limits for a given Tc — a bound the paper does not print, shown
beside its (10)–(11). It credits PGA with nothing beyond its settled window, a worst case: on a
clean scene PGA's early wide-window iterations remove part of the fast phase as well.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import InputError
from ..sar.residual import DEFAULT_PGA_BANDWIDTH_CYCLES, random_walk_highpass_rms
from ..units import G0, phase_error_to_range_error


@dataclass(frozen=True)
class FastPhaseLimits:
    """Fast-phase limits for one wavelength (SI)."""

    wavelength_m: float
    noise_rms_deg: float
    harmonic_peak_deg: float
    noise_range_rms_m: float
    harmonic_range_peak_m: float
    paired_echo_db: float
    noise_islr_db: float
    tc_s: np.ndarray
    vrw_m_s2_rt_hz: np.ndarray
    arw_rad_s_rt_hz: np.ndarray
    pga_bandwidth_cycles: float = DEFAULT_PGA_BANDWIDTH_CYCLES

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"tc_s": self.tc_s, "vrw_fast_limit_m_s2_rt_hz": self.vrw_m_s2_rt_hz,
                             "arw_fast_limit_rad_s_rt_hz": self.arw_rad_s_rt_hz})

    def to_dict(self) -> dict:
        """JSON-ready: the inputs (wavelength, phase limits, PGA bandwidth) and the limits, SI."""
        return {"wavelength_m": self.wavelength_m, "noise_rms_deg": self.noise_rms_deg,
                "harmonic_peak_deg": self.harmonic_peak_deg, "pga_bandwidth_cycles": self.pga_bandwidth_cycles,
                "noise_range_rms_m": self.noise_range_rms_m, "harmonic_range_peak_m": self.harmonic_range_peak_m,
                "paired_echo_db": self.paired_echo_db, "noise_islr_db": self.noise_islr_db,
                "rows": self.to_frame().to_dict(orient="records")}

    def summary(self) -> str:
        return (f"fast phase (λ = {self.wavelength_m:.4g} m): random ≤ {self.noise_rms_deg}° rms "
                f"→ {self.noise_range_rms_m:.3g} m rms, harmonic ≤ {self.harmonic_peak_deg}° peak → "
                f"{self.harmonic_range_peak_m:.3g} m peak; paired echoes {self.paired_echo_db:.1f} dB, "
                f"noise ISLR {self.noise_islr_db:.1f} dB")


def fast_phase_limits(wavelength_m: float, tc_s=(), *, noise_rms_deg: float = 1.0,
                      harmonic_peak_deg: float = 1.0, gravity_m_s2: float = G0,
                      pga_bandwidth_cycles: float = DEFAULT_PGA_BANDWIDTH_CYCLES) -> FastPhaseLimits:
    """Fast-phase limits for ``wavelength_m`` and, for each Tc, the VRW/ARW whose residual beyond
    PGA's bandwidth (``pga_bandwidth_cycles`` per aperture, :mod:`budget.sar.residual`) stays
    within ``noise_rms_deg`` rms (each source alone, whole error along the line of sight)."""
    lam = float(wavelength_m)
    if not (math.isfinite(lam) and lam > 0):
        raise InputError("wavelength must be finite and > 0", field="wavelength_m", value=lam,
                         expected="λ in m, > 0")
    noise_m = phase_error_to_range_error(math.radians(noise_rms_deg), lam)
    harm_m = phase_error_to_range_error(math.radians(harmonic_peak_deg), lam)
    tc = np.atleast_1d(np.asarray(tc_s, dtype=float))
    if not (math.isfinite(pga_bandwidth_cycles) and pga_bandwidth_cycles >= 0):
        raise ValueError("PGA bandwidth must be finite and ≥ 0 cycles per aperture")
    r_v = random_walk_highpass_rms("vrw", float(pga_bandwidth_cycles))
    r_a = random_walk_highpass_rms("arw", float(pga_bandwidth_cycles))
    sigma = math.radians(noise_rms_deg)
    return FastPhaseLimits(
        wavelength_m=lam, noise_rms_deg=noise_rms_deg, harmonic_peak_deg=harmonic_peak_deg,
        noise_range_rms_m=noise_m, harmonic_range_peak_m=harm_m,
        paired_echo_db=20.0 * math.log10(math.radians(harmonic_peak_deg) / 2.0),
        noise_islr_db=10.0 * math.log10(sigma**2),
        tc_s=tc, vrw_m_s2_rt_hz=noise_m / (r_v * tc**1.5),
        arw_rad_s_rt_hz=noise_m / (r_a * gravity_m_s2 * tc**2.5),
        pga_bandwidth_cycles=float(pga_bandwidth_cycles),
    )
