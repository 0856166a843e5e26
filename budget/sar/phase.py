"""Slow-time phase errors: models, injection as APC offsets, and comparison with PGA estimates.

Conventions: u = 2t/T ∈ [−1, 1] is normalised aperture time; a phase error ψ(t) multiplies the
echo, e^{jψ}, which a range error Δr produces as ψ = −4πΔr/λ (seed 003 (12), with the sign of
exp(−j4πR/λ)). Constant and linear terms only shift the image, so comparisons
remove them by a least-squares fit. Legendre decomposition over u as in seed 004.
"""

from __future__ import annotations

import numpy as np
from numpy.polynomial import legendre

from ..errors import InputError
from ..units import phase_to_range, range_to_phase
from .geometry import SarGeometry
from .image import SarImage
from .mocomp import los_range_change_m


def normalised_time(geom: SarGeometry) -> np.ndarray:
    """u = 2 t / T of every pulse."""
    return 2.0 * geom.pulse_times_s / geom.aperture_time_s


def smooth_phase_error(u, *, quadratic_rad: float = 0.0, cubic_rad: float = 0.0, sinusoid_rad: float = 0.0,
                       sinusoid_cycles: float = 1.0, sinusoid_phase_rad: float = 0.0) -> np.ndarray:
    """ψ(u) = q u² + c u³ + s sin(π n u + φ0): q, c are the values at the aperture edge u = 1,
    n the number of sinusoid cycles over the aperture (rad)."""
    u = np.asarray(u, dtype=float)
    return (quadratic_rad * u ** 2 + cubic_rad * u ** 3
            + sinusoid_rad * np.sin(np.pi * sinusoid_cycles * u + sinusoid_phase_rad))


def check_phase_sampled(psi, field: str) -> np.ndarray:
    """``psi`` (one phase per pulse, rad) if no two neighbouring pulses differ by more than π;
    otherwise :class:`InputError` naming ``field``: the pulses cannot sample a smooth error that
    fast (it would alias to a slower one, and the image and the metrics would describe that)."""
    psi = np.asarray(psi, dtype=float)
    step = float(np.max(np.abs(np.diff(psi)))) if psi.size > 1 else 0.0
    if step > np.pi:
        raise InputError(f"the injected phase error changes by up to {step:.3g} rad from one pulse to "
                         f"the next: the {psi.size} pulses cannot sample it (it would alias to a slower "
                         "error)", field=field,
                         expected=f"at most π rad per pulse: 2|q| + 3|c| + π|s·n| ≤ π(n−1)/2 = "
                                  f"{np.pi * (psi.size - 1) / 2:.4g} rad")
    return psi


def los_offset_for_phase(geom: SarGeometry, phase_rad, point_m: np.ndarray | None = None) -> np.ndarray:
    """APC offsets (n_pulses, 3) along the line of sight to ``point_m`` (default the scene centre)
    that put exactly the phase error ``phase_rad`` (per pulse) on that point: Δr = −ψλ/(4π)."""
    psi = np.broadcast_to(np.asarray(phase_rad, dtype=float), (geom.n_pulses,))
    c = geom.scene_centre_m if point_m is None else np.asarray(point_m, dtype=float)
    los = geom.nominal_apc_m() - c[None, :]
    los /= np.linalg.norm(los, axis=1, keepdims=True)
    return phase_to_range(psi, geom.wavelength_m)[:, None] * los


def residual_phase_rad(geom: SarGeometry, true_offset_m=None, measured_offset_m=None,
                       point_m: np.ndarray | None = None) -> np.ndarray:
    """Phase error left on ``point_m`` (default scene centre) after motion compensation with the
    measured trajectory: ψ(t) = −4π/λ (Δr_true(t) − Δr_meas(t)), per pulse (rad)."""
    c = (geom.scene_centre_m if point_m is None else np.asarray(point_m, dtype=float))[None, :]
    tru = geom.check_offset(true_offset_m, "true_offset_m")
    mea = geom.check_offset(measured_offset_m, "measured_offset_m")
    d = los_range_change_m(geom, tru, c)[:, 0] - los_range_change_m(geom, mea, c)[:, 0]
    return range_to_phase(d, geom.wavelength_m)


def phase_on_bins(image: SarImage, geom: SarGeometry, psi_pulses, outside: str = "nan") -> np.ndarray:
    """A per-pulse phase ψ(t_n) read at the slow time of each azimuth-frequency bin of ``image``
    (centred order, as :func:`budget.sar.pga.pga` returns). Outside the aperture band
    (|t| > T/2): NaN (``outside="nan"``, for comparing estimates on the band), or ψ at the
    track's nearer end (``"hold"``, for *applying* the phase as a correction: the band's edge
    pulses leave some energy in the bins just beyond it, and a correction of zero there leaves
    them their error — on ``automotive_77ghz`` enough to cost the exact correction 0.7 dB of PSLR
    on a 48-cell image)."""
    if outside not in ("nan", "hold"):
        raise InputError("unknown choice for the bins outside the aperture band", field="outside",
                         value=outside, expected="'nan' or 'hold'")
    t = image.slow_time_of_bins_s()
    val = np.interp(t, geom.pulse_times_s, np.asarray(psi_pulses, dtype=float))
    return val if outside == "hold" else np.where(image.aperture_mask(), val, np.nan)


def remove_linear(phi, mask=None, weight=None) -> np.ndarray:
    """φ minus its weighted least-squares constant + linear fit over ``mask`` (NaN elsewhere)."""
    phi = np.asarray(phi, dtype=float)
    k = np.arange(phi.size, dtype=float)
    m = np.isfinite(phi) if mask is None else (np.asarray(mask, bool) & np.isfinite(phi))
    w = np.ones(phi.size) if weight is None else np.asarray(weight, dtype=float)
    sw = np.sqrt(w[m])
    coef, *_ = np.linalg.lstsq(np.stack([np.ones(m.sum()), k[m]], axis=1) * sw[:, None], phi[m] * sw, rcond=None)
    out = np.full(phi.size, np.nan)
    out[m] = phi[m] - coef[0] - coef[1] * k[m]
    return out


def residual_rms_rad(estimate_rad, truth_rad, mask=None) -> float:
    """rms of (estimate − truth) over ``mask`` after removing constant and linear terms (rad)."""
    diff = np.asarray(estimate_rad, dtype=float) - np.asarray(truth_rad, dtype=float)
    r = remove_linear(diff, mask)
    return float(np.sqrt(np.nanmean(r ** 2)))


def legendre_decomposition(u, psi, order: int = 5) -> np.ndarray:
    """Least-squares Legendre coefficients c_0…c_order of ψ(u) on u ∈ [−1, 1] (seed 004):
    c_0 constant, c_1 linear (shift), c_2 quadratic (defocus), c_3 cubic (asymmetric sidelobes)."""
    return legendre.legfit(np.asarray(u, dtype=float), np.asarray(psi, dtype=float), order)
