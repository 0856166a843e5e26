"""What the platform does during a Monte Carlo aperture: straight flight or a named manoeuvre.

The gyro scale factor and misalignment act on the true angular rate, so in straight, level,
unrotated flight they have no effect at all. A :class:`PlatformMotion` turns the scenario's
manoeuvre levels into a :class:`~budget.nav.platform.Disturbance` the motion engine flies:

* ``straight`` — no rotation (seed 004's straight trajectory; the default);
* ``oscillation`` — roll, pitch and yaw sinusoids of one period P, each with peak rate
  ω_p (default the scenario's ``platform_rate_deg_s``), phases 0, 2π/3, 4π/3 so that the rate
  vector never vanishes: amplitude A = ω_p·P/(2π) per axis (attitude oscillation of an aircraft
  in turbulence, a ship in a seaway);
* ``attitude_change`` — one smooth roll through Θ over the aperture,
  roll(t) = −(Θ/2)·cos(π t/Tc), t = 0 … Tc (from −Θ/2 to +Θ/2, peak rate πΘ/(2Tc) at mid-aperture):
  the attitude change the gyro-scale-factor bound assumes (seed 004 (6), reconstructed as
  g·γ·Θ·Tc²/2 ≤ δr/2 with Θ = 1 rad, :mod:`budget.bounds.derived`). The bound holds the tilt γΘ
  over the whole aperture; here it builds up as γ·(roll(t) − roll(0)) and the horizontal
  position error at the aperture end is g·γ·Θ·Tc²·(1/4 − 1/π²) — 0.297 of the bound's
  g·γ·Θ·Tc²/2;
* ``custom`` — the user's own :class:`~budget.nav.platform.Disturbance` (sinusoids and random
  PSD tables on any axis).

Time 0 is the aperture start (an aided run's warm-up runs at negative times through the same
sinusoids). The track stays straight at the scenario's speed: the disturbance rotates the body
and displaces the IMU about the nominal track (:func:`budget.nav.platform.true_motion`).
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from ..errors import InputError, refuse_bool_numbers
from .platform import ROTATION_AXES, TRANSLATION_AXES, Disturbance, SinusoidalMotion

KINDS = ("straight", "oscillation", "attitude_change", "custom")
#: Oscillation period when none is given (s): aircraft attitude in turbulence, 0.1 Hz.
DEFAULT_PERIOD_S = 10.0
#: Attitude change of ``attitude_change`` when none is given: 1 rad, the Θ of the derived bound.
DEFAULT_ANGLE_DEG = math.degrees(1.0)
#: Largest attitude amplitude a manoeuvre may ask for (rad): the disturbance's own limit.
MAX_AMPLITUDE_RAD = 1.0


class PlatformMotion(BaseModel):
    """The platform's motion over a Monte Carlo aperture (module docstring): ``kind`` and the
    parameters of that kind; a parameter left None takes its stated default."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    kind: Literal[KINDS] = "straight"
    peak_rate_deg_s: float | None = Field(
        None, gt=0, le=1e4, allow_inf_nan=False,
        description="oscillation: peak angular rate per axis (default the scenario's platform_rate_deg_s)")
    period_s: float | None = Field(None, gt=0, le=1e5, allow_inf_nan=False,
                                   description=f"oscillation: period (default {DEFAULT_PERIOD_S:g} s)")
    angle_deg: float | None = Field(None, gt=0, le=2 * math.degrees(MAX_AMPLITUDE_RAD), allow_inf_nan=False,
                                    description="attitude_change: roll change Θ over the aperture "
                                                f"(default {DEFAULT_ANGLE_DEG:.4g}° = 1 rad)")
    disturbance: Disturbance | None = Field(None, description="custom: the disturbance flown")

    @model_validator(mode="after")
    def _fields_match_kind(self) -> "PlatformMotion":
        used = {"oscillation": {"peak_rate_deg_s", "period_s"}, "attitude_change": {"angle_deg"},
                "custom": {"disturbance"}}.get(self.kind, set())
        stray = [f for f in ("peak_rate_deg_s", "period_s", "angle_deg", "disturbance")
                 if getattr(self, f) is not None and f not in used]
        if stray:
            raise ValueError(f"{', '.join(stray)} does not apply to platform motion '{self.kind}'")
        if self.kind == "custom" and self.disturbance is None:
            raise ValueError("platform motion 'custom' needs a disturbance (sinusoids and/or random)")
        return self

    @property
    def rotates(self) -> bool:
        """Whether the body rotates (so gyro scale factor and misalignment act)."""
        if self.kind == "custom":
            return self.disturbance.has_rotation
        return self.kind != "straight"

    def disturbance_for(self, scenario) -> Disturbance | None:
        """The disturbance flown over ``scenario``'s aperture (None: straight flight). Raises
        :class:`InputError` naming the field when the manoeuvre cannot be flown, or cannot be
        sampled at the scenario's IMU rate (:meth:`Disturbance.check_imu_rate`, the Monte Carlo's
        rule, so the analytic check refuses what the Monte Carlo refuses)."""
        dist = self._disturbance(scenario)
        if dist is not None:
            dist.check_imu_rate(scenario.imu_rate_hz)
        return dist

    def _disturbance(self, scenario) -> Disturbance | None:
        if self.kind == "straight":
            return None
        if self.kind == "custom":
            return self.disturbance
        if self.kind == "oscillation":
            rate = self.peak_rate_deg_s if self.peak_rate_deg_s is not None else scenario.platform_rate_deg_s
            if not rate > 0:
                raise InputError("an oscillation needs a peak angular rate: the scenario's platform_rate_deg_s "
                                 "is 0", field="platform_motion.peak_rate_deg_s", value=rate,
                                 expected="> 0 deg/s (or set the scenario's platform_rate_deg_s)")
            period = self.period_s or DEFAULT_PERIOD_S
            amp = math.radians(rate) * period / (2.0 * math.pi)
            if amp > MAX_AMPLITUDE_RAD:
                raise InputError(f"a {rate:g} deg/s oscillation of period {period:g} s swings "
                                 f"±{math.degrees(amp):.0f}°", field="platform_motion.period_s", value=period,
                                 expected=f"an amplitude ≤ {math.degrees(MAX_AMPLITUDE_RAD):.0f}° "
                                          "(a shorter period or a lower rate)")
            return Disturbance(sinusoids=tuple(
                SinusoidalMotion(axis=ax, frequency_hz=1.0 / period, amplitude_rad=amp,
                                 phase_rad=2.0 * math.pi * k / 3.0)
                for k, ax in enumerate(("roll", "pitch", "yaw"))))
        theta = math.radians(self.angle_deg if self.angle_deg is not None else DEFAULT_ANGLE_DEG)
        return Disturbance(sinusoids=(SinusoidalMotion(
            axis="roll", frequency_hz=1.0 / (2.0 * scenario.tc_s), amplitude_rad=0.5 * theta,
            phase_rad=-0.5 * math.pi),))

    def describe(self, scenario) -> str:
        """One line for a result: what was flown, with every default filled in."""
        if self.kind == "straight":
            return ("platform simulated in straight, level, unrotated flight: the gyros see no rotation and "
                    "the accelerometers gravity only, so gyro scale factor and misalignment have no effect here")
        dist = self.disturbance_for(scenario)
        if self.kind == "oscillation":
            s = dist.sinusoids[0]
            rate = math.degrees(s.amplitude_rad * 2.0 * math.pi * s.frequency_hz)
            return (f"platform oscillating in roll, pitch and yaw: ±{math.degrees(s.amplitude_rad):.3g}° at a "
                    f"period of {1.0 / s.frequency_hz:g} s, peak rate {rate:.3g} deg/s per axis"
                    + ("" if self.peak_rate_deg_s is not None else " (the scenario's platform_rate_deg_s)")
                    + ("" if self.period_s is not None else f" (default period {DEFAULT_PERIOD_S:g} s)")
                    + "; straight track")
        if self.kind == "attitude_change":
            theta = 2.0 * dist.sinusoids[0].amplitude_rad
            return (f"platform rolling through {math.degrees(theta):.3g}° over the aperture "
                    f"(−{math.degrees(theta) / 2:.3g}° → +{math.degrees(theta) / 2:.3g}°, peak rate "
                    f"{math.degrees(math.pi * theta / (2.0 * scenario.tc_s)):.3g} deg/s)"
                    + ("" if self.angle_deg is not None else " (default Θ = 1 rad, the gyro-scale-factor "
                                                            "bound's)") + "; straight track")
        unit = {ax: "m" for ax in TRANSLATION_AXES} | {ax: "rad" for ax in ROTATION_AXES}
        parts = [f"{s.axis} {s.amplitude:g} {unit[s.axis]} at {s.frequency_hz:g} Hz" for s in dist.sinusoids]
        parts += [f"{r.axis} random {r.rms:.3g} {unit[r.axis]} rms ({r.frequency_hz[0]:g}–{r.frequency_hz[-1]:g} Hz)"
                  for r in dist.random]
        return ("platform disturbance (custom): " + "; ".join(parts)
                + ("" if dist.has_rotation else "; no rotation, so gyro scale factor and misalignment have "
                                                 "no effect here"))
