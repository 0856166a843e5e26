"""A squinted aperture simulated as its broadside equivalent.

The point-target simulator flies broadside: the nominal track is perpendicular to the line of
sight (LOS) to the scene centre. A scenario at squint s (positive forward; θ = 90° − s between
velocity and LOS, seed 004 (5)) is imaged the way a squinted processor sees it, in the frame of
its own LOS:

* **velocity.** The platform velocity V splits into V·sin s along the horizontal LOS — a linear
  range walk, Doppler centroid 2V·cos ψ·sin s/λ, which a squinted processor removes from the known
  nominal track (range-walk correction and Doppler-centroid deramp) — and V_c = V·cos s across it,
  which sweeps the LOS and makes the azimuth resolution. The equivalent flies broadside at V_c:
  its Doppler rate 2V_c²/(λR) is 2V²sin²θ/(λR) with the scenario's θ = 90° − s, and with the same
  Tc = a_w λ R / (2 δℓ V sin θ) of seed 004 (5) it gives the same cross-range cell δℓ/a_w =
  λR/(2 V_c Tc) (:func:`broadside_equivalent`). (With a depression ψ the exact squinted rate is
  2V²(1 − cos²ψ sin²s)/(λR): the walk's V·sin s·sin ψ across the LOS in the vertical plane also
  turns it — the term left out below.)
* **motion error.** The APC error the motion engine draws in the navigation frame (x along the
  velocity, y horizontal cross-track toward the imaged side, z up) is rotated about z by the squint
  into the equivalent's frame (:func:`to_imaging_frame`): x' = x cos s − y sin s,
  y' = x sin s + y cos s. The squinted LOS u = (cos ψ sin s, cos ψ cos s, −sin ψ) becomes the
  broadside (0, cos ψ, −sin ψ), so every error sees the range change u·δp it sees on the squinted
  aperture: an along-track error enters the range by cos ψ·sin s (none at broadside).

What the equivalent leaves out, first order: on the squinted track the range walk also tilts the
LOS in the vertical plane through it, by (V t/R)·sin s·sin ψ at time t from the aperture centre;
an error component δp_⊥ perpendicular to the LOS in that plane then changes the range by that
fraction of δp_⊥. Over the aperture (V·Tc/2R = the half-angle over cos s) that is about
(a_w λ / 4δℓ)·tan s·sin ψ of the error: 1.3·10⁻³ at X band (λ = 3 cm, δℓ = 1 m, s = 20°, ψ = 30°),
checked against the exact squinted ranges in the tests; every result states it for its scenario
(:func:`left_out_fraction`, :func:`squint_note`: 4 % at 79° squint on X band). The range-cell
migration of the walk (V·sin s·Tc) is not simulated: the verdict assumes a processor that
corrects it, as any squinted SAR processor does.
"""

from __future__ import annotations

import math

import numpy as np

from ..scenario import Scenario


def broadside_equivalent(scenario: Scenario) -> Scenario:
    """``scenario`` at squint 0 flying the cross-LOS speed V·cos s (m/s); every other field as
    given, so Tc (seed 004 (5)) and the cross-range resolution are the squinted scenario's.
    A broadside scenario is returned as it is."""
    if scenario.squint_deg == 0.0:
        return scenario
    v_c = scenario.platform_speed_m_s * math.cos(math.radians(scenario.squint_deg))
    return scenario.model_copy(update={"squint_deg": 0.0, "platform_speed_m_s": v_c})


def to_imaging_frame(error_m: np.ndarray, squint_rad: float) -> np.ndarray:
    """APC errors (…, 3) in the navigation frame (x along the velocity) rotated about z by the
    squint into the broadside equivalent's frame (x' across the squinted LOS); m. At squint 0 the
    array itself is returned."""
    if squint_rad == 0.0:
        return error_m
    e = np.asarray(error_m, dtype=float)
    c, s = math.cos(squint_rad), math.sin(squint_rad)
    out = np.empty_like(e)
    out[..., 0] = c * e[..., 0] - s * e[..., 1]
    out[..., 1] = s * e[..., 0] + c * e[..., 1]
    out[..., 2] = e[..., 2]
    return out


def left_out_fraction(squint_rad: float, depression_rad: float, wavelength_m: float,
                      cross_range_cell_m: float) -> float:
    """The first-order term the equivalent leaves out, as a fraction of the APC error:
    (λ / 4δ)·|tan s|·sin ψ with δ = δℓ/a_w the cross-range cell (module docstring)."""
    return wavelength_m / (4.0 * cross_range_cell_m) * abs(math.tan(squint_rad)) * math.sin(depression_rad)


def squint_note(squint_rad: float, speed_m_s: float, left_out: float = 0.0) -> str:
    """What a result simulated at squint ``squint_rad`` assumed (empty at broadside);
    ``left_out``: :func:`left_out_fraction`."""
    if squint_rad == 0.0:
        return ""
    s = math.degrees(squint_rad)
    return (f"squint {s:g}°: simulated as its broadside equivalent — cross-track speed "
            f"{speed_m_s:.4g} m/s (V·cos s), the same Tc and cross-range cell, the motion error rotated "
            "onto the squinted line of sight (leaving out the line of sight's tilt as the range walks, "
            f"≈ {100.0 * left_out:.2g} % of the error); the range walk V·sin s·Tc and its Doppler "
            "centroid are taken as removed by the processor (budget.sar.squint)")
