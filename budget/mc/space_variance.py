"""Space variance over the simulated scene's range depth: the phase one PGA estimate cannot remove.

PGA estimates one phase error ψ(ν) over the image's azimuth wavenumber ν for every range line.
In the range-Doppler image the line at slant range r holds, at bin ν, the echo of the pulse at
slow time t = ν λ r / (2V) (:meth:`budget.sar.image.SarImage.slow_time_of_bins_s`): the mapping
scales with the line's range. The motion error's phase is a function of slow time, φ(t) =
4π Δr(t) / λ (Δr: the line-of-sight range error), so the line at r = R + D holds φ(τ (1 + ε)),
ε = D / R, where τ is the time the scene-centre line R gives the same bin. One phase for all lines
fits (about) the centre line; the line at depth D keeps

    Δψ(τ) = φ(τ (1 + ε)) − φ(τ),   τ ∈ [−T/2, T/2].

For a polynomial term φ = a uⁿ (u = 2τ/T) this is ((1 + ε)ⁿ − 1) a uⁿ, the same shape, so after
removing its constant and linear parts (they only move the image) its rms is |(1 + ε)ⁿ − 1|
times that of φ. The quadratic (n = 2: a constant acceleration error, the drift of an
accelerometer bias or of a tilt under gravity) is the lowest order that defocuses, and the factor
grows with n (≈ 3ε for a cubic: a gyro bias), so with D the scene's half depth in slant range

    Δψ_sv = ((1 + D/R)² − 1) · φ_rms ≈ 2 (D/R) φ_rms          (deg, as φ_rms)
    Δr_sv = λ / (4π) · Δψ_sv                                   (m, Δψ_sv in rad)

is a lower estimate of what stays on the scene's far edge line (the near edge's, |(1 − D/R)ⁿ − 1|
φ_rms, is slightly less), with φ_rms the rms of the phase PGA removes without its constant and
linear parts (the Monte Carlo's ``residual_phase_rms_deg`` before PGA, weighted by the phase
history's energy as the verdict is; its median over the trials). It is **material** when it
reaches the limit the acceptance puts on phase PGA cannot remove
(``McOptions.max_residual_phase_rms_deg``; seed 004's 1° when the verdict sets none): the
analytic bounds assume one phase error for the whole scene, and then the Monte Carlo can fail a
part whose every term passes them.

Measured on the formed image (``tests/test_mc_space_variance.py``: the phase history of one
target with and without a line-of-sight error a uⁿ, against
:func:`budget.sar.phase.residual_phase_rad` read at the bins' times; a 24 GHz car at 2 m/s,
R = 30 m, targets ±2 m in slant range): read with the centre line's mapping a target keeps
3.5° / 3.9° (n = 2, φ_rms 27.8°) and 2.3° / 2.8° (n = 3, φ_rms 12.6°) at D = −2 m / +2 m, where
|(1 + ε)ⁿ − 1| φ_rms gives 3.6° / 3.8° and 2.4° / 2.7°; read with its own line's mapping ≤ 0.2°.
A target 1 m off centre in azimuth keeps ≤ 0.35° with the centre's mapping: azimuth offsets do
not move the mapping in the simulated image, so they are not in Δψ_sv. Nor is the spread of the
line-of-sight direction over the scene: with each trial's error projected on the line of sight
to the scene centre (only the part along it kept) the verdict below is unchanged (25 of 64 pass,
as with the whole error), and the part across it alone passes every trial.

On that scenario (δℓ = 0.05 m, δr = 0.1 m, Tc = 1.86 s, five points at ±2 m of slant range,
STIM300, 64 trials, seed 1): ε = 0.067, φ_rms p50 62° → Δψ_sv ≈ 8.5°, and P(pass after PGA) =
0.39 while the check passes; the same error at 300 m (V = 20 m/s, same Tc and aperture angle):
ε = 0.0067, ≈ 0.8°, P = 1.00; the error scaled by 1/4 at 30 m: ≈ 2.1°, P = 0.92.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError
from ..sar import SarGeometry, Scene
from .options import McOptions

#: Limit (deg rms) on phase PGA cannot remove when the verdict sets none (seed 004: ≤ 1°).
DEFAULT_LIMIT_DEG = 1.0
#: Image checks a space-variant residual fails (a defocus of the edge lines), as opposed to range
#: migration or PGA's own residual beyond its window.
FOCUS_REASONS = ("broadening", "pslr", "islr", "peak_loss")


def stretch_residual_deg(depth_fraction: float, phase_rms_deg: float, order: int = 2) -> float:
    """|(1 + ε)ⁿ − 1| · φ_rms: the rms (deg, as ``phase_rms_deg``) a phase term of polynomial
    ``order`` n keeps on the range line at relative depth ε = D/R (signed: D > 0 beyond the scene
    centre) when one phase fits the centre line (module docstring; n = 2 gives the lower
    estimate)."""
    if order < 2:
        raise InputError("a constant or linear phase only moves the image", field="order", value=order,
                         expected="2 or more")
    return abs(math.pow(1.0 + float(depth_fraction), order) - 1.0) * float(phase_rms_deg)


def verdict_scene_half_depth_m(scenario, options: McOptions | None = None) -> float:
    """Largest slant-range offset (m) from the scene centre among the points the verdict is
    measured on (:meth:`budget.sar.Scene.default` on the Monte Carlo's geometry)."""
    options = options or McOptions()
    geom = SarGeometry.from_scenario(scenario, window=options.window_for(scenario))
    return max(abs(float(t.range_m)) for t in Scene.default(geom, snr_db=None).targets)


@dataclass(frozen=True)
class RangeSpaceVariance:
    """The figure of the module docstring for one scenario and one phase size."""

    slant_range_m: float
    scene_half_depth_m: float
    wavelength_m: float
    #: rms (deg) of the phase PGA removes, without its constant and linear parts
    phase_rms_deg: float
    limit_deg: float = DEFAULT_LIMIT_DEG

    @property
    def depth_fraction(self) -> float:
        """ε = D/R."""
        return self.scene_half_depth_m / self.slant_range_m

    @property
    def residual_deg(self) -> float:
        """Δψ_sv = ((1 + ε)² − 1) φ_rms (deg), the lower estimate."""
        return stretch_residual_deg(self.depth_fraction, self.phase_rms_deg)

    @property
    def differential_range_m(self) -> float:
        """Δr_sv = λ/(4π) Δψ_sv (m)."""
        return self.wavelength_m / (4.0 * math.pi) * math.radians(self.residual_deg)

    @property
    def material(self) -> bool:
        """Δψ_sv at or above the limit on phase PGA cannot remove."""
        return bool(self.residual_deg >= self.limit_deg)

    def to_dict(self) -> dict:
        return {"slant_range_m": self.slant_range_m, "scene_half_depth_m": self.scene_half_depth_m,
                "depth_fraction": self.depth_fraction, "wavelength_m": self.wavelength_m,
                "phase_rms_deg": self.phase_rms_deg, "residual_deg": self.residual_deg,
                "differential_range_m": self.differential_range_m, "limit_deg": self.limit_deg,
                "material": self.material}

    def sentence(self, sole: bool = True) -> str:
        """The disagreement explained in words, with the figure. ``sole``: nothing else named
        explains it (the disagreement is then expected); else space variance is said to add to
        it."""
        head = ("This is space variance, which the analytic bounds do not model" if sole else
                "Space variance, which the analytic bounds do not model, adds to it")
        tail = (" The disagreement is expected here; it shrinks with a longer range or a shallower scene."
                if sole else "")
        return (f"{head}: the simulated scene spans ±{self.scene_half_depth_m:.3g} m of slant range at "
                f"R = {self.slant_range_m:.4g} m (D/R = {self.depth_fraction:.2%}), a range line maps azimuth "
                f"frequency to slow time in proportion to its range, so the motion error's phase is stretched "
                f"by that fraction from the centre line to the edge lines, and PGA's one phase for the whole "
                f"scene leaves them at least ((1 + D/R)² − 1)·φ = {_deg(self.residual_deg)}° rms "
                f"({self.differential_range_m * 1e3:.2g} mm of range), φ = {_deg(self.phase_rms_deg)}° being "
                f"the median phase PGA removed — at or above the {self.limit_deg:g}° allowed for phase PGA "
                f"cannot remove.{tail}")


def _deg(value: float) -> str:
    """Degrees for a sentence: three figures, without an exponent."""
    return f"{value:.2g}" if value < 10 else f"{value:,.0f}"


def range_space_variance(scenario, phase_rms_deg: float, *, options: McOptions | None = None,
                         scene_half_depth_m: float | None = None) -> RangeSpaceVariance:
    """:class:`RangeSpaceVariance` of ``scenario`` for a phase of ``phase_rms_deg`` rms (deg,
    constant and linear parts removed); the depth defaults to the verdict's points
    (:func:`verdict_scene_half_depth_m`), the limit to ``options.max_residual_phase_rms_deg``."""
    options = options or McOptions()
    depth = verdict_scene_half_depth_m(scenario, options) if scene_half_depth_m is None else scene_half_depth_m
    limit = options.max_residual_phase_rms_deg
    return RangeSpaceVariance(slant_range_m=float(scenario.slant_range_m), scene_half_depth_m=float(depth),
                              wavelength_m=float(scenario.wavelength_m), phase_rms_deg=float(phase_rms_deg),
                              limit_deg=DEFAULT_LIMIT_DEG if limit is None else float(limit))


def space_variance_of(result) -> RangeSpaceVariance | None:
    """The figure for a Monte Carlo result (:class:`~budget.mc.McResult`), from its scenario,
    options and the median phase PGA removed (``residual_phase_rms_deg`` before PGA); None when
    the result does not carry them."""
    scenario = getattr(result, "scenario", None)
    if scenario is None or not hasattr(result, "percentiles"):
        return None
    try:
        phase = float(result.percentiles("before")["residual_phase_rms_deg"]["p50"])
        if not math.isfinite(phase):
            return None
        return range_space_variance(scenario, phase, options=getattr(result, "options", None))
    except (InputError, KeyError, AttributeError):
        return None
