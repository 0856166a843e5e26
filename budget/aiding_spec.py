"""What a user writes to aid the IMU: the typed ``aiding`` section of a scenario.

The scenario lists the aiding sensors (``aiding``), how their corrections reach the antenna
track (``aiding_mode``, :data:`CORRECTION_MODES`) and how long the aided navigation runs before
the aperture (``aiding_warmup_s``)::

    aiding_mode: frozen
    aiding:
      - {type: gnss, rate_hz: 10, sigma_m: 0.05, latency_s: 0.05, lever_arm_m: [0.5, 0, 0.3]}
      - {type: dvl, rate_hz: 5, sigma_m_s: 0.01}
      - {type: master_ins, rate_hz: 1, sigma_position_m: 2, sigma_velocity_m_s: 0.02,
         lever_arm_m: [1.8, 0.5, -0.7], flexure: {frequency_hz: 3, damping_ratio: 0.05,
         amplitude_m: [0, 0, 0.01]}}
      - {type: star_tracker, rate_hz: 1, sigma_arcsec: 15}

Every σ is a 1σ per axis, SI except ``sigma_arcsec`` (the unit star trackers are specified in);
``*_m`` are in the local-level frame (position/velocity) or the body frame (lever arms, flexure
amplitude, DVL). ``rate_hz`` must not exceed the IMU rate (checked when the IMU rate is known:
:func:`parse_aiding` with ``imu_rate_hz`` or pydantic validation with context
``{"imu_rate_hz": …}``). Bad input raises :class:`~budget.errors.InputError` naming
``aiding[i].field``.

Correction modes (what a motion-compensation chain does with the filter's corrections):

* ``realtime`` — closed loop, the navigation output steps at every fix (a worst case: each
  step is a fast phase error inside the aperture);
* ``frozen`` — corrections estimated up to the aperture start and held across it: the INS
  coasts on its aiding-calibrated state (position, velocity, attitude and sensor biases reset
  at the aperture start, no update inside it). What real-time motion compensation uses;
* ``feedforward`` — the filter keeps running, its corrections reach the track through a
  critically damped blend with mean delay ``aiding_blend_time_s`` (default 5·Tc), so the track
  has no steps or kinks and changes only slowly inside the aperture (continuous strip-map
  imaging, where there is no gap between apertures to reset in);
* ``smoothed`` — fixed-interval RTS smoothing of the whole record (post-processing; what
  offline image formation uses).

This module sits on the scenario's floor (it imports only pydantic, the error type and the unit
table), so the scenario can hold typed aiding configs without importing the aiding library.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Literal, Union

from pydantic import (BaseModel, BeforeValidator, ConfigDict, Field, TypeAdapter, ValidationError,
                      ValidationInfo, field_validator)

from .errors import BOOL_FOR_NUMBER, InputError, bool_number_field, refuse_bool_numbers
from .units import unit_of_name, value_text_hint

Finite = Annotated[float, Field(allow_inf_nan=False)]
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Vec3 = tuple[Finite, Finite, Finite]


def sigma3(value) -> tuple[float, float, float]:
    """One σ for all axes, or three, → three finite floats > 0 (ValueError otherwise)."""
    if isinstance(value, bool):
        raise ValueError("a standard deviation must be a number, not true/false")
    if isinstance(value, (int, float)):
        vals = (float(value),) * 3
    elif isinstance(value, (list, tuple)) and len(value) == 3:
        try:
            vals = tuple(float(v) for v in value)
        except (TypeError, ValueError):
            raise ValueError("expected three numbers") from None
    else:
        raise ValueError("expected one number or a list of three numbers")
    if not all(math.isfinite(v) and v > 0 for v in vals):
        raise ValueError("a standard deviation must be finite and > 0")
    return vals


#: a 1σ: one positive number for all three axes, or three positive numbers (stored as three)
Sigma = Annotated[tuple[float, float, float], BeforeValidator(sigma3)]


class FlexureConfig(BaseModel):
    """One structural bending mode between two points of the airframe (body frame).

    The relative displacement d(t) per axis is a damped oscillator driven by white noise,
    d̈ + 2ζω d˙ + ω² d = w (ω = 2π ``frequency_hz``), scaled so the stationary 1σ of d is
    ``amplitude_m`` on each axis (see :mod:`budget.aiding.flexure`).
    """

    model_config = ConfigDict(extra="forbid", frozen=True)
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    frequency_hz: Positive = Field(..., le=1000.0, description="natural frequency of the mode")
    damping_ratio: float = Field(..., gt=0, lt=1, allow_inf_nan=False, description="ζ, 0 < ζ < 1")
    amplitude_m: tuple[NonNegative, NonNegative, NonNegative] = Field(
        ..., description="stationary 1σ displacement per body axis (m)")


class _AidBase(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    rate_hz: Positive = Field(..., description="measurement rate; must not exceed the IMU rate")
    latency_s: NonNegative = Field(0.0, le=60.0, description="delay from validity to availability")

    @field_validator("rate_hz")
    @classmethod
    def _rate_within_imu(cls, rate: float, info: ValidationInfo) -> float:
        imu_rate = (info.context or {}).get("imu_rate_hz")
        if imu_rate is not None and rate > imu_rate * (1 + 1e-9):
            raise ValueError(f"{rate:g} Hz is above the IMU rate {imu_rate:g} Hz; an aiding "
                             "sensor cannot be processed faster than the IMU it corrects")
        return rate


class GnssAiding(_AidBase):
    """GNSS/DGPS antenna position, white noise ``sigma_m`` plus optional Gauss–Markov error."""

    type: Literal["gnss"] = "gnss"
    sigma_m: Sigma = Field(..., description="white position noise 1σ per n-frame axis (m)")
    lever_arm_m: Vec3 = Field((0.0, 0.0, 0.0), description="IMU → GNSS antenna, body frame (m)")
    correlated_sigma_m: NonNegative = Field(0.0, description="slow (GM) position error 1σ (m)")
    correlation_time_s: Positive = Field(600.0, description="its correlation time (s)")


class DvlAiding(_AidBase):
    """Doppler velocity log: body-frame velocity, white noise ``sigma_m_s`` plus an optional
    velocity error (random constant, or Gauss–Markov with ``bias_correlation_time_s``)."""

    type: Literal["dvl"] = "dvl"
    sigma_m_s: Sigma = Field(..., description="white velocity noise 1σ per body axis (m/s)")
    bias_sigma_m_s: NonNegative = Field(0.0, description="velocity error 1σ per body axis (m/s)")
    bias_correlation_time_s: Positive | None = Field(
        None, description="first-order Gauss–Markov correlation time of that error (seed 003's "
                          "DVL error states); omitted: a random constant")


class MasterInsAiding(_AidBase):
    """Master INS position and velocity transferred to the slave IMU through a lever arm.

    The transfer uses the master's own attitude (seed 001 and seed 002), so the slave's attitude
    error does not enter the measurement; the master's errors are the white ``sigma_*``. With a
    ``flexure`` the true arm is l + d(t) — d is a measurement error the filter estimates as extra
    states when ``estimate_flexure`` is true, otherwise it is treated as extra white noise.
    """

    type: Literal["master_ins"] = "master_ins"
    sigma_position_m: Sigma
    sigma_velocity_m_s: Sigma
    lever_arm_m: Vec3 = Field(..., description="master IMU → slave IMU, body frame (m)")
    flexure: FlexureConfig | None = None
    estimate_flexure: bool = True


class StarTrackerAiding(_AidBase):
    """Attitude from a star tracker (celestial navigation), white noise per axis."""

    type: Literal["star_tracker"] = "star_tracker"
    sigma_arcsec: Sigma


#: How the aiding corrections reach the antenna track (see the module docstring).
CORRECTION_MODES = ("realtime", "frozen", "feedforward", "smoothed")
#: Default mode: what real-time motion compensation uses (offline processing: ``smoothed``).
DEFAULT_CORRECTION_MODE = "frozen"

AidingConfig = Annotated[Union[GnssAiding, DvlAiding, MasterInsAiding, StarTrackerAiding],
                         Field(discriminator="type")]
AIDING_TYPES = ("gnss", "dvl", "master_ins", "star_tracker")
_MODELS = dict(zip(AIDING_TYPES, (GnssAiding, DvlAiding, MasterInsAiding, StarTrackerAiding)))
_LIST = TypeAdapter(list[AidingConfig])


def _field_path(loc: tuple) -> str:
    """(0, 'gnss', 'lever_arm_m', 1) → 'aiding[0].lever_arm_m[1]'.

    Drops what pydantic inserts that is not a field: the discriminator tag and the name of the
    union member tried (``float``, ``tuple[...]``).
    """
    out = "aiding"
    for i, part in enumerate(loc):
        if isinstance(part, int):
            out += f"[{part}]"
        elif (i == 1 and part in AIDING_TYPES) or part in ("float", "int") or "[" in str(part):
            continue
        else:
            out += "." + str(part)
    return out


def _unit_text_hint(field: str, value) -> tuple[str, str] | None:
    """(reason, expected) for text such as ``'2 cm'`` given to the number field ``field``
    (``aiding[0].sigma_m``), :func:`budget.units.value_text_hint`; None when it does not apply."""
    if not isinstance(value, str):
        return None
    name = field.rsplit(".", 1)[-1].split("[")[0]
    unit = unit_of_name(name)
    return None if unit is None else value_text_hint(name, value, unit, noun="field")


def parse_aiding(data, *, imu_rate_hz: float | None = None,
                 source: str | Path | None = None) -> list:
    """Validate the ``aiding`` list of a scenario; returns typed configs or raises InputError.

    ``imu_rate_hz`` (if given) bounds every ``rate_hz``. Errors read like
    ``scenario.yaml, field aiding[1].sigma_m: Input should be greater than 0 (got -1.0)``.
    """
    if data is None:
        return []
    if isinstance(data, tuple):
        data = list(data)
    if not isinstance(data, list):
        raise InputError("aiding must be a list of sensors", file=source, field="aiding",
                         expected=f"a list of mappings with type {' | '.join(AIDING_TYPES)}")
    if imu_rate_hz is not None and not (isinstance(imu_rate_hz, (int, float))
                                        and math.isfinite(imu_rate_hz) and imu_rate_hz > 0):
        raise InputError("IMU rate must be a positive number", field="imu_rate_hz", value=imu_rate_hz)
    data = [item.model_dump() if isinstance(item, BaseModel) else item for item in data]
    for i, item in enumerate(data):
        if not isinstance(item, dict) or "type" not in item:
            raise InputError("each aiding entry needs a 'type'", file=source, field=f"aiding[{i}].type",
                             expected=" | ".join(AIDING_TYPES))
        if item["type"] not in AIDING_TYPES:
            raise InputError("unknown aiding type", file=source, field=f"aiding[{i}].type",
                             value=item["type"], expected=" | ".join(AIDING_TYPES))
        name = bool_number_field(_MODELS[item["type"]], item)
        if name is not None:
            raise InputError(BOOL_FOR_NUMBER, file=source, field=f"aiding[{i}].{name}",
                             value=item[name])
    try:
        return _LIST.validate_python(data, context={"imu_rate_hz": imu_rate_hz})
    except ValidationError as err:
        first = err.errors()[0]
        value = first.get("input")
        if isinstance(value, dict):
            value = None
        field = _field_path(tuple(first.get("loc", ())))
        msg = first.get("msg", "invalid value").removeprefix("Value error, ")
        hint = _unit_text_hint(field, value)
        if hint is not None:
            raise InputError(hint[0], file=source, field=field, value=value, expected=hint[1]) from None
        raise InputError(msg, file=source, field=field,
                         value=value) from None


#: Feed-forward blend time when the plan gives none, in apertures (5·Tc).
BLEND_APERTURES = 5.0


class AidingPlan(BaseModel):
    """Aiding sensors plus how the corrections reach the track (``mode``, :data:`CORRECTION_MODES`).

    ``warmup_s`` is how long the filter runs before the aperture starts (to converge);
    ``smoothed`` = fixed-interval Rauch–Tung–Striebel post-processing (seed 002).
    """

    model_config = ConfigDict(extra="forbid", frozen=True)
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    aiding: list[AidingConfig] = Field(default_factory=list)
    mode: Literal[CORRECTION_MODES] = DEFAULT_CORRECTION_MODE
    warmup_s: NonNegative = Field(60.0, le=86_400.0)
    blend_time_s: Positive | None = Field(
        None, description="feedforward: mean delay of the correction blend (default 5·Tc)")
    antenna_flexure: FlexureConfig | None = Field(
        None, description="IMU → antenna bending the IMU cannot see (added to the motion error)")

    @classmethod
    def from_scenario(cls, scenario) -> "AidingPlan":
        """The plan of a scenario's aiding section (its sensors are already typed)."""
        return cls(aiding=list(scenario.aiding), mode=scenario.aiding_mode,
                   warmup_s=scenario.aiding_warmup_s, blend_time_s=scenario.aiding_blend_time_s)

    def blend_time_for(self, tc_s: float) -> float:
        """Feed-forward blend time (s) over an aperture of ``tc_s``: the plan's, or
        :data:`BLEND_APERTURES`·Tc."""
        return self.blend_time_s or BLEND_APERTURES * tc_s

    def label(self) -> str:
        """Short text for results: sensors, mode and warm-up (``none`` without sensors)."""
        if not self.aiding:
            return "none"
        sensors = "+".join(a.type for a in self.aiding)
        return f"{sensors}, {self.mode}, {self.warmup_s:g} s warm-up"
