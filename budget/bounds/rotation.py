"""The rotation a gyro scale factor and a gyro misalignment see: the platform's own manoeuvre.

Seed 004 (6) bounds the gyro scale factor γ for an attitude change Θ = 1 rad held over the whole
aperture: the tilt γΘ turns gravity into a horizontal acceleration g·γ·Θ, whose position error
g·γ·Θ·Tc²/2 must stay within its share of a range cell (:mod:`budget.bounds.derived`). A platform
that rotates otherwise — not at all in straight flight, an oscillation in turbulence, one roll
through Θ — puts a different error on the track. This module computes it for the motion flown
(:class:`~budget.nav.platform.Disturbance`, as the Monte Carlo flies it) and states it as the
*equivalent excursion* Θ_eq: the constant tilt held from t = 0 that gives the same largest
position error over the aperture, so that every bound of the γ/Θ form scales by Θ/Θ_eq.

Physics (small angles, the INS initialised with the true attitude at the aperture start t = 0):
a scale-factor error γ on the roll (pitch) gyro makes the attitude error γ·(θ(t) − θ(0)) about
that axis; it tilts the specific force g into the horizontal, and the position error is

    e(t) = g·γ·E(t),   E(t) = ∫₀ᵗ (t − s)·(θ(s) − θ(0)) ds        (double integral of the tilt).

A constant Θ from t = 0 gives E = Θt²/2, the bound's form; so Θ_eq = 2·max_{t ≤ Tc} |E(t)| / Tc².

* a sinusoid θ = A·sin(ωt + φ):  E(t) = A·[t·cos φ/ω − (sin(ωt + φ) − sin φ)/ω² − sin φ·t²/2]
  (exact);
* a random component with one-sided PSD S(f): E(t) is Gaussian with variance
  ∫ S(f)·|H(f, t)|² df, H(f, t) = ∫₀ᵗ (t − s)(e^{jωs} − 1) ds = −(e^{jωt} − 1 − jωt + (ωt)²/2)/ω²,
  and enters as k·σ(t) (k = ``k_sigma``, 2 by default, as the noise bounds' k);
* a component's deterministic and random parts add as |E_sin(t)| + k·σ(t) (a bound, not an rms).

Only a roll error moves the antenna in range: it tilts gravity into the cross-track axis (y),
whose error the line of sight sees (cos ε of it at depression ε; seed 004's bound, and this
module, take the whole cross-track error). A pitch error tilts gravity along the track (x),
which moves the samples along the aperture: at broadside (:func:`motion_excursion` refuses a squint) the range
to a target changes by (x − x_t)/R of it, at most ≈ λ/(4δℓ) at the aperture's ends (a few
per cent; left out here); a yaw error turns a horizontal specific force that a straight track
does not have. So a gyro scale factor acts through the roll gyro's own rotation:
Θ_eq(SF) = Θ_eq(roll). A gyro misalignment leaks the rotation about one axis into the reading
of another (E = diag(s) + M, :mod:`budget.imu.generator`, the six entries of M independent with
the same 1σ): the roll reading takes m·θ_pitch and m·θ_yaw terms, each with its own random
entry, so its envelope is √(E_pitch² + E_yaw²) at each t, and Θ_eq(misalignment) is its
largest value. A roll manoeuvre alone leaks only into the pitch and yaw readings: it does not
exercise the misalignment. Both terms tilt the platform by (their value)·Θ_eq, so both take the
γ bound's share of the range cell (:meth:`RotationExcursion.bounds`): one half in seed 004 (6),
not the full cell of seed 004 (7), which is written for a misalignment that tilts the specific
force itself.

With Θ_eq = 0 (straight, level, unrotated flight, or a rotation about yaw only for the scale
factor) the term has no effect and its bound is infinite.

Attitude error × lever arm (:mod:`budget.bounds.lever_arm`) sees the attitude error itself, not
its double integral: γ·(θ(t) − θ(0))·|d| on any axis. Its excursion is the peak tilt
Θ_peak = max over axes and t of |θ_sin(t) − θ_sin(0)| + k·σ_θ(t), σ_θ² = ∫ S(f)·2(1 − cos ωt) df.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import InputError
from ..nav.platform import Disturbance

#: Points of the time grid over [0, Tc] on which the largest |E(t)| is sought.
_N_TIME = 1025
#: Points of the frequency grid of a random component's variance integral.
_N_FREQ = 2049
#: Below this ωt the random transfer function is summed from its series (no cancellation).
_SERIES_BELOW = 0.05
#: The axis whose attitude error moves the antenna in range, and the rotations that leak into it.
_RANGE_AXIS, _LEAKS = "roll", ("pitch", "yaw")


def _sinusoid_e(t: np.ndarray, amplitude: float, omega: float, phase: float) -> np.ndarray:
    """E(t) of θ = A·sin(ωt + φ) (module docstring, exact)."""
    s0, c0 = math.sin(phase), math.cos(phase)
    return amplitude * (t * c0 / omega - (np.sin(omega * t + phase) - s0) / omega ** 2 - s0 * t * t / 2.0)


def _transfer_sq(omega: np.ndarray, t: float) -> np.ndarray:
    """|H(f, t)|² (s⁴) of the random part (module docstring) for angular frequencies ``omega``."""
    x = omega * t
    small = np.abs(x) < _SERIES_BELOW
    big = ~small
    h = np.zeros(omega.shape, dtype=complex)
    xb = x[big]
    h[big] = -(np.exp(1j * xb) - 1.0 - 1j * xb + 0.5 * xb * xb) / omega[big] ** 2
    xs = x[small]
    # −Σ_{k≥3} (jx)^k/k! / ω² = −t²·Σ_{k≥3} j^k x^{k−2}/k!  (no 1/ω² cancellation)
    series = np.zeros(xs.shape, dtype=complex)
    for k in range(3, 11):
        series += (1j ** k) * xs ** (k - 2) / math.factorial(k)
    h[small] = -t * t * series
    return h.real ** 2 + h.imag ** 2


def _random_sigma(comp, t: np.ndarray, tilt: bool = False) -> np.ndarray:
    """σ(t) of E(t) for a random component (``psd_rad2_per_hz`` table), one value per ``t``;
    ``tilt=True``: σ_θ(t) of θ(t) − θ(0), |e^{jωt} − 1|² = 2(1 − cos ωt) in place of |H|²."""
    f = np.geomspace(comp.frequency_hz[0], comp.frequency_hz[-1], _N_FREQ)
    s = comp.psd_at(f)
    omega = 2.0 * math.pi * f
    if tilt:
        return np.sqrt(np.maximum(np.trapezoid(s * 2.0 * (1.0 - np.cos(np.outer(t, omega))), f, axis=1), 0.0))
    return np.array([math.sqrt(max(float(np.trapezoid(s * _transfer_sq(omega, float(ti)), f)), 0.0))
                     for ti in t])


def axis_envelopes(disturbance: Disturbance | None, tc_s: float, k_sigma: float = 2.0,
                   n_time: int = _N_TIME, *, tilt: bool = False) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """(t (n,), {axis: |E_sin(t)| + k·σ(t)} in rad·s²) for roll, pitch and yaw over [0, Tc];
    ``tilt=True``: the attitude change itself, |θ_sin(t) − θ_sin(0)| + k·σ_θ(t) in rad."""
    t = np.linspace(0.0, float(tc_s), int(n_time))
    env = {ax: np.zeros(t.size) for ax in ("roll", "pitch", "yaw")}
    if disturbance is None:
        return t, env
    det = {ax: np.zeros(t.size) for ax in env}
    for s in disturbance.sinusoids:
        if s.axis in det:
            w = 2.0 * math.pi * s.frequency_hz
            det[s.axis] += (s.amplitude * (np.sin(w * t + s.phase_rad) - math.sin(s.phase_rad)) if tilt
                            else _sinusoid_e(t, s.amplitude, w, s.phase_rad))
    rand = {ax: np.zeros(t.size) for ax in env}
    for r in disturbance.random:
        if r.axis in rand:  # independent components: variances add
            sig = _random_sigma(r, t, tilt)
            rand[r.axis] = np.sqrt(rand[r.axis] ** 2 + sig ** 2)
    return t, {ax: np.abs(det[ax]) + k_sigma * rand[ax] for ax in env}


@dataclass(frozen=True)
class RotationExcursion:
    """Equivalent excursions Θ_eq (rad) of one motion over one aperture (module docstring).

    ``scale_factor_rad``: what a gyro scale factor sees; ``misalignment_rad``: what a gyro
    misalignment sees; ``per_axis_rad``: Θ_eq of each axis' own rotation; ``peak_tilt_rad``: the
    largest attitude change over the aperture (what attitude error × lever arm sees); ``motion``:
    what was flown, in words; ``reference_rad``: the excursion the bounds were written for (seed
    004: 1 rad).
    """

    motion: str
    tc_s: float
    scale_factor_rad: float
    misalignment_rad: float
    per_axis_rad: dict = field(default_factory=dict)
    peak_tilt_rad: float = 0.0
    k_sigma: float = 2.0
    reference_rad: float = 1.0

    def factor(self, term: str) -> float:
        """Θ_ref/Θ_eq for ``term`` ("gyro_scale_factor" | "gyro_misalignment"): the multiplier on
        the gyro scale-factor bound γ (written for Θ_ref) that gives the term's motion-aware
        bound (:meth:`bounds`); inf when the motion does not exercise the term."""
        theta = self.scale_factor_rad if term == "gyro_scale_factor" else self.misalignment_rad
        return math.inf if theta <= 0 else self.reference_rad / theta

    def bounds(self, gamma_bound: float) -> dict[str, float]:
        """Motion-aware bounds (rad/rad) of the gyro scale factor and the gyro misalignment from
        the γ bound of seed 004 (6) (or the derived mode's), written for an attitude change
        Θ_ref: γ·Θ_ref/Θ_eq for both. A gyro misalignment tilts the platform by m·Θ_eq as a scale
        factor does by γ·Θ_eq, so it takes γ's share of the range cell (one half in seed 004), not
        the full cell of seed 004 (7), which bounds a misalignment that tilts the specific force
        itself (the accelerometers')."""
        return {term: gamma_bound * self.factor(term) for term in ("gyro_scale_factor", "gyro_misalignment")}

    def summary(self) -> str:
        def words(theta: float) -> str:
            return "not exercised (no tilting rotation)" if theta <= 0 else (
                f"Θ_eq = {theta:.3g} rad, bound = γ bound × {self.reference_rad / theta:.3g}")
        return (f"Rotation over Tc = {self.tc_s:.3g} s: {self.motion}\n"
                f"  gyro scale factor: {words(self.scale_factor_rad)}\n"
                f"  gyro misalignment: {words(self.misalignment_rad)}\n"
                f"  (Θ_eq: the constant tilt from t = 0 with the same largest position error; the bounds "
                f"assume {self.reference_rad:g} rad; random parts at {self.k_sigma:g}σ)")

    def to_dict(self) -> dict:
        return {"motion": self.motion, "tc_s": self.tc_s, "scale_factor_excursion_rad": self.scale_factor_rad,
                "misalignment_excursion_rad": self.misalignment_rad,
                "per_axis_excursion_rad": dict(self.per_axis_rad), "peak_tilt_rad": self.peak_tilt_rad,
                "k_sigma": self.k_sigma,
                "reference_excursion_rad": self.reference_rad,
                "gyro_scale_factor_bound_factor": self.factor("gyro_scale_factor"),
                "gyro_misalignment_bound_factor": self.factor("gyro_misalignment")}

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame([{"term": term, "excursion_rad": theta, "bound_factor": self.factor(term)}
                             for term, theta in (("gyro_scale_factor", self.scale_factor_rad),
                                                 ("gyro_misalignment", self.misalignment_rad))])


def rotation_excursion(disturbance: Disturbance | None, tc_s: float, *, k_sigma: float = 2.0,
                       motion: str = "", reference_rad: float = 1.0) -> RotationExcursion:
    """Θ_eq of ``disturbance`` (None: straight flight) over an aperture of ``tc_s`` seconds for a
    gyro scale factor and a gyro misalignment (module docstring); ``reference_rad`` is the
    excursion the bounds being scaled assume (seed 004 (6): 1 rad)."""
    if not (math.isfinite(tc_s) and tc_s > 0):
        raise InputError("the aperture time must be finite and > 0", field="tc_s", value=tc_s, expected="s, > 0")
    if not (math.isfinite(k_sigma) and k_sigma > 0):
        raise InputError("k_sigma must be finite and > 0", field="k_sigma", value=k_sigma, expected="> 0")
    t, env = axis_envelopes(disturbance, tc_s, k_sigma)
    scale = 2.0 / tc_s ** 2
    per_axis = {ax: float(scale * env[ax].max()) for ax in env}
    sf = per_axis[_RANGE_AXIS]
    mis = float(scale * np.max(np.hypot(*(env[a] for a in _LEAKS))))
    peak = max(float(v.max()) for v in axis_envelopes(disturbance, tc_s, k_sigma, tilt=True)[1].values())
    return RotationExcursion(motion=motion or ("straight, level, unrotated flight" if disturbance is None
                                               else "platform disturbance"),
                             tc_s=float(tc_s), scale_factor_rad=sf, misalignment_rad=mis, per_axis_rad=per_axis,
                             peak_tilt_rad=peak,
                             k_sigma=float(k_sigma), reference_rad=float(reference_rad))


def motion_excursion(platform_motion, scenario, *, reference_rad: float = 1.0,
                     k_sigma: float = 2.0) -> RotationExcursion:
    """:func:`rotation_excursion` of a :class:`~budget.nav.manoeuvre.PlatformMotion` over
    ``scenario``'s aperture (its disturbance and description as the Monte Carlo flies them).
    A rotating motion over a squinted scenario is refused: the excursion is the broadside one (a
    pitch error's along-track tilt is left out), which a squinted line of sight sees by
    cos ψ·sin(squint). The Monte Carlo flies the rotation at any squint
    (``McOptions.platform_motion``; :mod:`budget.sar.squint`)."""
    if getattr(platform_motion, "rotates", False) and scenario.squint_deg != 0.0:
        along = math.cos(math.radians(scenario.depression_deg)) * abs(math.sin(math.radians(scenario.squint_deg)))
        raise InputError("the rotation a gyro scale factor and misalignment see is derived for a broadside "
                         "line of sight: at a squint the along-track tilt a pitch error makes enters the "
                         f"range by cos ψ·sin(squint) = {along:.2g} of it, which it leaves out (the Monte "
                         "Carlo flies it: McOptions.platform_motion)",
                         field="squint_deg", value=scenario.squint_deg,
                         expected="squint_deg 0 with a rotating platform motion, or no platform motion "
                                  "(the bounds' own 1-rad attitude change) or 'straight'")
    return rotation_excursion(platform_motion.disturbance_for(scenario), scenario.tc_s, k_sigma=k_sigma,
                              motion=platform_motion.describe(scenario), reference_rad=reference_rad)
