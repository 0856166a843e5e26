"""Imaging scenario: what the radar or sonar must achieve, in SI units.

A :class:`Scenario` is what a user writes (JSON or YAML). Derived quantities (wavelength,
synthetic-aperture time Tc, aperture length) are properties, never stored, so they cannot
disagree with the inputs.
"""

from __future__ import annotations

import json
import math
import unicodedata
import warnings
from pathlib import Path
from typing import Literal

import numpy as np
import yaml
from pydantic import (BaseModel, ConfigDict, Field, ValidationError, ValidationInfo, field_validator,
                      model_validator)

from .aiding_spec import CORRECTION_MODES, DEFAULT_CORRECTION_MODE, AidingConfig, parse_aiding
from .errors import InputError, combine_errors, refuse_bool_numbers
from .fileio import atomic_write_text
from .structured import read_structured
from .scenario_errors import (DERIVED_KEYS, REQUIRED_KEYS, TYPICAL_PRESET, key_unit,  # noqa: F401 (re-exported)
                              name_scenario_file, scenario_errors, scenario_field)
from .scenario_limits import (HIGH_PLATFORM_ACCEL_M_S2, LEVER_ARM_EXPECTED, LONG_LEVER_ARM_M,  # noqa: F401
                              ORBITAL_SPECIFIC_FORCE_SHARE, PLAUSIBLE, PLAUSIBLE_CARRIER_HZ, PLAUSIBLE_TC_S,
                              PLAUSIBLE_WAVELENGTH_M, RADAR_MIN_SPEED_M_S, SONAR_MAX_SPEED_M_S,
                              TYPICAL_CARRIER_HZ, WIDE_APERTURE_RATIO, carrier_unit_hint)
from .units import C_LIGHT, C_SOUND_WATER, G0


def los_unit_vector(depression_deg: float, squint_deg: float) -> np.ndarray:
    """Unit vector APC → scene at depression ψ (below horizontal) and squint s (positive
    forward, 0 = broadside): u = (cos ψ·sin s, cos ψ·cos s, −sin ψ), in the local-level frame
    x along-track, y horizontal cross-track toward the imaged side, z up."""
    psi, s = math.radians(depression_deg), math.radians(squint_deg)
    return np.array([math.cos(psi) * math.sin(s), math.cos(psi) * math.cos(s), -math.sin(psi)])


#: Scenario keys with a default that feed a result (Tc, the bounds, the check, the simulation):
#: a result computed with one the user did not write states it (:meth:`Scenario.defaults_note`).
#: Each command passes the subset it uses (:data:`TC_KEYS` and what its mode adds).
DEFAULTED_KEYS = ("medium", "propagation_speed_m_s", "squint_deg", "window_broadening", "depression_deg",
                  "lever_arm_m", "platform_accel_m_s2", "platform_rate_deg_s", "imu_rate_hz")
#: The defaulted keys Tc = a_w λ R / (2 δℓ V sin θ) depends on (λ = c/f0, c from the medium).
TC_KEYS = ("medium", "propagation_speed_m_s", "squint_deg", "window_broadening")


def _default_text(key: str, value, scenario: "Scenario") -> str:
    """A default value with its unit and, where the bare number says little, its meaning."""
    if key == "propagation_speed_m_s":
        return f"{value:g} m/s ({scenario.medium})"
    if key == "squint_deg":
        return f"{value:g} (broadside)"
    if key == "depression_deg":
        return f"{value:g} (line of sight {value:g}° below horizontal)"
    if key == "window_broadening":
        return f"{value:g} (unweighted azimuth main lobe)"
    if key == "lever_arm_m":
        return "[" + ", ".join(f"{v:g}" for v in value) + "] m (IMU at the antenna phase centre)"
    if key == "platform_accel_m_s2":
        return f"{value:.6g} m/s² (g, level flight)"
    if key == "platform_rate_deg_s":
        return f"{value:g} deg/s (no turn)"
    if key == "imu_rate_hz":
        return f"{value:g} Hz"
    return str(value)


class Scenario(BaseModel):
    """A synthetic-aperture imaging geometry and its resolution requirement.

    All fields SI; the unit is in the name. ``squint_deg`` 0 is broadside; the angle θ between
    velocity and line of sight of seed 004 (5) is 90° − squint.
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str = Field("custom", min_length=1, max_length=200)
    medium: Literal["radar", "sonar"] = "radar"
    carrier_frequency_hz: float = Field(..., gt=0, allow_inf_nan=False)
    propagation_speed_m_s: float | None = Field(
        None, gt=0, allow_inf_nan=False,
        description="c; defaults to 299792458 m/s (radar) or 1500 m/s (sonar)")
    slant_range_m: float = Field(..., gt=0, allow_inf_nan=False)
    azimuth_resolution_m: float = Field(..., gt=0, allow_inf_nan=False, description="δℓ")
    range_resolution_m: float = Field(..., gt=0, allow_inf_nan=False, description="δr")
    platform_speed_m_s: float = Field(..., gt=0, allow_inf_nan=False)
    squint_deg: float = Field(0.0, gt=-80, lt=80, allow_inf_nan=False)
    depression_deg: float = Field(30.0, ge=0, lt=90, allow_inf_nan=False)
    window_broadening: float = Field(1.0, ge=1.0, le=2.0, allow_inf_nan=False,
                                     description="a_w: main-lobe broadening of the azimuth window")
    lever_arm_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    platform_accel_m_s2: float = Field(G0, ge=0, allow_inf_nan=False,
                                       description="specific force seen by scale factor/misalignment "
                                                   "(derived and no-autofocus bounds; g in level flight)")
    platform_rate_deg_s: float = Field(0.0, ge=0, allow_inf_nan=False,
                                       description="angular-rate level seen by gyro scale factor")
    imu_rate_hz: float = Field(200.0, gt=0, le=100_000, allow_inf_nan=False)
    # --- aiding section (typed; parsed once, here) ----------------------------------
    aiding: tuple[AidingConfig, ...] = Field(
        (), description="aiding sensors [{type: gnss|dvl|master_ins|star_tracker, ...}] "
                        "(budget.aiding_spec); empty = unaided IMU, as seed 004 assumes")
    aiding_mode: Literal[CORRECTION_MODES] = Field(
        DEFAULT_CORRECTION_MODE,
        description="how aiding corrections reach the antenna track: realtime (steps at each fix, "
                    "worst case), frozen (held across the aperture, real-time mocomp), feedforward "
                    "(slow blend), smoothed (RTS, offline)")
    aiding_warmup_s: float = Field(60.0, ge=0, le=3600, allow_inf_nan=False,
                                   description="aided navigation runs this long before the aperture")
    aiding_blend_time_s: float | None = Field(
        None, gt=0, le=3600, allow_inf_nan=False,
        description="feedforward mode: mean delay of the correction blend (default 5·Tc)")

    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    @model_validator(mode="before")
    @classmethod
    def _renamed_aiding_keys(cls, data):
        if isinstance(data, dict) and "aiding_smoother" in data:
            raise InputError("aiding_smoother was replaced by aiding_mode", field="aiding_smoother",
                             value=data["aiding_smoother"], expected="aiding_mode: realtime | frozen | "
                             "feedforward | smoothed (aiding_smoother: rts is aiding_mode: smoothed)")
        return data

    @field_validator("name")
    @classmethod
    def _printable_name(cls, v: str) -> str:
        # the name is printed by every command: a terminal escape or a newline in it would act
        # on the user's terminal or split a report line
        bad = sorted({repr(c) for c in v if unicodedata.category(c) in ("Cc", "Cf")})
        if bad:
            raise ValueError(f"control characters in the name ({', '.join(bad)}): letters, digits, spaces "
                             "and punctuation only")
        if not v.strip():
            raise ValueError("the name is blank")
        return v

    @field_validator("lever_arm_m", mode="before")
    @classmethod
    def _three_components(cls, value):
        # pydantic's own message for [0.5, 0.3] is "lever_arm_m.2: Field required", for null
        # "Input should be a valid tuple"
        if isinstance(value, (list, tuple)) and len(value) != 3:
            raise InputError(f"lever_arm_m has {len(value)} component{'' if len(value) == 1 else 's'}",
                             field="lever_arm_m", value=list(value), expected=LEVER_ARM_EXPECTED)
        if value is None:
            raise InputError("lever_arm_m is empty (got null)", field="lever_arm_m",
                             expected=LEVER_ARM_EXPECTED + "; leave the key out for [0, 0, 0], the IMU at the "
                                                           "antenna phase centre")
        if not isinstance(value, (list, tuple)):
            raise InputError("lever_arm_m is not a list of three numbers", field="lever_arm_m", value=value,
                             expected=LEVER_ARM_EXPECTED)
        return value

    @field_validator("lever_arm_m")
    @classmethod
    def _finite_lever_arm(cls, value):
        if not all(math.isfinite(v) for v in value):
            raise InputError("lever_arm_m must hold three finite numbers", field="lever_arm_m",
                             value=list(value), expected=LEVER_ARM_EXPECTED + ", none NaN or infinite")
        if any(abs(v) > 1e3 for v in value):
            raise InputError("lever arm longer than 1 km", field="lever_arm_m",
                             value=list(value), expected="|component| ≤ 1000 m")
        return value

    @field_validator("carrier_frequency_hz")
    @classmethod
    def _plausible_carrier(cls, f0: float, info: ValidationInfo) -> float:
        # checked per field, so that one run names it beside every other error of the file
        medium = info.data.get("medium")  # absent when the medium itself is in error
        if medium == "sonar" and f0 > PLAUSIBLE_CARRIER_HZ["sonar"][1]:
            raise InputError("sonar carrier above 5 MHz: did you mean medium 'radar'?",
                             field="carrier_frequency_hz", value=f0,
                             expected="{:g} … {:g} Hz for sonar, or medium: radar".format(
                                 *PLAUSIBLE_CARRIER_HZ["sonar"]))
        if medium == "radar" and f0 < PLAUSIBLE_CARRIER_HZ["radar"][0]:
            raise InputError("radar carrier below 1 MHz: " + carrier_unit_hint("radar", f0),
                             field="carrier_frequency_hz", value=f0,
                             expected="{:g} … {:g} Hz for radar, the number in Hz".format(
                                 *PLAUSIBLE_CARRIER_HZ["radar"]))
        if medium in PLAUSIBLE_CARRIER_HZ:
            lo, hi = PLAUSIBLE_CARRIER_HZ[medium]
            if not lo <= f0 <= hi:
                raise InputError(f"{medium} carrier of {f0:.4g} Hz is not physically plausible",
                                 field="carrier_frequency_hz", expected=f"{lo:g} … {hi:g} Hz for {medium}")
        return f0

    @field_validator(*PLAUSIBLE)
    @classmethod
    def _plausible_value(cls, v, info: ValidationInfo):
        if v is None:
            return v
        name = info.field_name
        medium = info.data.get("medium")
        if name == "propagation_speed_m_s" and medium == "radar" and v < RADAR_MIN_SPEED_M_S:
            raise InputError("a speed of sound for radar: did you mean medium 'sonar'?",
                             field=name, value=v,
                             expected=f"≥ {RADAR_MIN_SPEED_M_S:g} m/s for radio waves (≈ c/9 in water)")
        if name == "propagation_speed_m_s" and medium == "sonar" and v > SONAR_MAX_SPEED_M_S:
            raise InputError("faster than sound in any medium: did you mean medium 'radar'?",
                             field=name, value=v, expected=f"≤ {SONAR_MAX_SPEED_M_S:g} m/s for sound")
        lo, hi, why = PLAUSIBLE[name]
        if not lo <= v <= hi:
            raise InputError(f"{v:.4g} is not physically plausible", field=name,
                             expected=f"{lo:g} … {hi:g} ({why})")
        return v

    @field_validator("aiding", mode="before")
    @classmethod
    def _parse_aiding(cls, value, info: ValidationInfo):
        if value is None or value == ():
            return ()
        return tuple(parse_aiding(value, imu_rate_hz=info.data.get("imu_rate_hz")))

    @model_validator(mode="after")
    def _check(self) -> "Scenario":
        # every key is valid and plausible alone here (the field validators): what is left are
        # the combinations, each error of them listed at once
        errors = self._combination_errors()
        if errors:
            raise combine_errors(errors)
        for note in self.notes():
            warnings.warn(note, UserWarning, stacklevel=2)
        return self

    def _combination_errors(self) -> list[InputError]:
        """Inputs valid alone that no radar or sonar can have together, and a Tc outside
        :data:`PLAUSIBLE_TC_S`, with the reason (every one found; the Tc only when the rest pass)."""
        errors: list[InputError] = []
        # resolutions no aperture or bandwidth can give: δr = c/(2B) with B < 2 f0 (the band's
        # lower edge above 0 Hz), δℓ ≥ λ/4 (a 180° synthetic aperture)
        lam = self.c_m_s / self.carrier_frequency_hz
        band_lo, band_hi = TYPICAL_CARRIER_HZ[self.medium]  # a carrier outside: its unit is named
        unit_hint = ("" if band_lo <= self.carrier_frequency_hz <= band_hi else
                     f" (a carrier outside the {self.medium} bands: "
                     f"{carrier_unit_hint(self.medium, self.carrier_frequency_hz)})")
        if self.range_resolution_m <= 0.25 * lam:
            errors.append(InputError(f"range resolution {self.range_resolution_m:.4g} m needs a bandwidth "
                             f"c/(2δr) = {self.c_m_s / (2 * self.range_resolution_m):.4g} Hz, more than "
                             f"twice the carrier {self.carrier_frequency_hz:.4g} Hz{unit_hint}",
                             field="range_resolution_m",
                             expected=f"> λ/4 = {0.25 * lam:.4g} m (bandwidth < 2 × carrier)"))
        reach = self.straight_track_aperture()
        if self.azimuth_resolution_m < 0.25 * lam:
            errors.append(InputError(f"azimuth resolution {self.azimuth_resolution_m:.4g} m is finer than any "
                                     f"synthetic aperture gives{unit_hint}", field="azimuth_resolution_m",
                                     expected=f"≥ λ/4 = {0.25 * lam:.4g} m (a 180° aperture)"))
        elif not reach["reachable"]:
            errors.append(InputError(f"azimuth resolution {self.azimuth_resolution_m:.4g} m needs an angular "
                             f"aperture {reach['text']}, which no straight track gives at squint "
                             f"{self.squint_deg:g}°", field="azimuth_resolution_m",
                             expected=f"> {reach['finest_m']:.4g} m at this squint, window and wavelength "
                                      "(δℓ = a_w λ / (4 sin(Δθ/2)), the aperture within 0° … 180° of "
                                      "the velocity)"))
        for key in ("range_resolution_m", "azimuth_resolution_m"):
            # a cell as wide as the range itself holds the whole scene and the platform: no image,
            # and every bound (∝ δr) or Tc (∝ 1/δℓ) computed from it would be a silently wrong number
            cell = getattr(self, key)
            if cell >= self.slant_range_m:
                errors.append(InputError(f"a resolution cell of {cell:.4g} m is as wide as the slant range "
                                 f"{self.slant_range_m:.4g} m: no image resolves anything", field=key,
                                 expected=f"< slant_range_m = {self.slant_range_m:.4g} m (check the units of "
                                          "the resolution and of the range)"))
        tc = self.tc_s
        lo, hi = PLAUSIBLE_TC_S
        if not errors and not (math.isfinite(tc) and lo <= tc <= hi):
            errors.append(InputError(f"these inputs give an aperture time Tc = a_w λ R / (2 δℓ V sin θ) of "
                             f"{tc:.3g} s, which no IMU budget can mean", field="tc_s (derived)",
                             expected=f"inputs giving {lo:g} s ≤ Tc ≤ {hi:g} s (check the units of "
                             "frequency, range, resolution and speed)"))
        return errors

    def notes(self) -> list[str]:
        """What the scenario's numbers hold that the tool does not model (one sentence each;
        empty for every preset). Also emitted as a :class:`UserWarning` when the scenario is
        built; a caller that shows results (the dashboard) lists these beside them.

        Stop-and-go (seed 004's geometry, the simulator's echoes) assumes the platform does not
        cross the whole synthetic aperture while one pulse travels to the scene and back:
        Tc > 2R/c, i.e. V < a_w λ c / (4 δℓ sin θ); only a sonar flown fast misses it. A lever arm
        longer than :data:`LONG_LEVER_ARM_M` is noted too (entries in cm read as m), a
        ``platform_accel_m_s2`` above :data:`HIGH_PLATFORM_ACCEL_M_S2` (100 g: g in cm/s² or mm/s²), and so are an
        angular aperture wide enough that seed 004 (5)'s small-angle Tc is more than
        :data:`WIDE_APERTURE_RATIO` short of the straight-track aperture
        (:meth:`straight_track_aperture`) and a speed at which level flight's specific force is no
        longer ≈ g (V²/r_E > :data:`ORBITAL_SPECIFIC_FORCE_SHARE`·g: a spaceborne or ballistic
        platform). So is a Tc over which the flat-earth, free-inertial error growth of the bounds is
        off by more than :data:`budget.nav.earth.MAX_FLAT_EARTH_NEGLECT` (Tc ≳ 790 s; the
        bounds refuse Tc beyond 3000 s, :func:`budget.bounds.check_bounds_tc`). A carrier outside the medium's typical bands (:data:`TYPICAL_CARRIER_HZ`: a kHz
        figure written into the Hz key, 100 for a 100 kHz sonar) that the resolution checks let
        through is noted with the unit that would put it in band (:func:`carrier_unit_hint`)."""
        out = []
        tc = self.tc_s
        f0 = self.carrier_frequency_hz
        band_lo, band_hi = TYPICAL_CARRIER_HZ[self.medium]
        if not band_lo <= f0 <= band_hi:
            out.append(f"{self.name}: a {self.medium} carrier of {f0:.4g} Hz (λ = {self.wavelength_m:.4g} m) is "
                       f"outside the {self.medium} bands a synthetic aperture is flown in ({band_lo:g} … "
                       f"{band_hi:g} Hz): {carrier_unit_hint(self.medium, f0)}; Tc and every bound "
                       "scale with λ")
        delay = 2.0 * self.slant_range_m / self.c_m_s
        if delay >= tc:
            v_max = self.platform_speed_m_s * tc / delay
            out.append(f"{self.name}: the echo delay 2R/c = {delay:.3g} s is longer than the "
                       f"aperture time Tc = {tc:.3g} s: the platform moves "
                       f"{self.platform_speed_m_s * delay:.3g} m while one pulse travels, more than "
                       f"the whole {self.aperture_length_m:.3g} m synthetic aperture; the bounds and "
                       "the simulator assume stop-and-go and do not model this (platform_speed_m_s "
                       f"< {v_max:.3g} m/s keeps Tc > 2R/c: check the speed's unit and the medium)")
        reach = self.straight_track_aperture()
        if reach["reachable"] and reach["length_ratio"] > WIDE_APERTURE_RATIO:
            out.append(f"{self.name}: the azimuth resolution asks for an angular aperture of "
                       f"{math.degrees(reach['angle_rad']):.3g}°; Tc = a_w λ R / (2 δℓ V sin θ) (seed 004 (5)) "
                       "is its small-angle form, and a straight track needs "
                       f"{reach['length_m']:.4g} m (Tc = {reach['length_m'] / self.platform_speed_m_s:.4g} s), "
                       f"{reach['length_ratio']:.3g}× the {self.aperture_length_m:.4g} m the bounds and the "
                       "simulator use (exact: δℓ = a_w λ / (4 sin(Δθ/2)))")
        from .nav.earth import (AIDED_FLAT_EARTH_MAX_TC_S, EARTH_RADIUS_M, MAX_FLAT_EARTH_NEGLECT,
                                flat_earth_neglect)
        neglect = flat_earth_neglect(tc, self.platform_speed_m_s)
        if neglect > MAX_FLAT_EARTH_NEGLECT:
            out.append(f"{self.name}: over Tc = {tc:.4g} s the Schuler, Earth-rate and transport-rate terms "
                       f"change a free-inertial error by ≈ {100 * neglect:.0f} %: the bounds and the check "
                       "(error growth b·t²/2, g·ε·t³/6 on a flat Earth) overstate it, and the Monte Carlo "
                       "refuses a free-inertial coast this long (aiding that corrects inside the aperture "
                       f"runs up to Tc = {AIDED_FLAT_EARTH_MAX_TC_S:g} s)")
        centripetal = self.platform_speed_m_s ** 2 / EARTH_RADIUS_M
        if centripetal > ORBITAL_SPECIFIC_FORCE_SHARE * G0:
            out.append(f"{self.name}: at {self.platform_speed_m_s:.4g} m/s level flight around the Earth "
                       f"needs a specific force of only g − V²/r_E = {G0 - centripetal:.3g} m/s² (an orbit: ≈ 0), "
                       "where the bounds' gyro terms (tilt × g) and the motion engine assume g on "
                       "a flat Earth and a straight track: for an orbiting or ballistic platform they "
                       "do not describe its navigation error")
        d = math.sqrt(sum(v * v for v in self.lever_arm_m))
        if d > LONG_LEVER_ARM_M:
            big = max(self.lever_arm_m, key=abs)
            out.append(f"{self.name}: the lever arm lever_arm_m = [{', '.join(f'{v:g}' for v in self.lever_arm_m)}] "
                       f"is {d:.4g} m long, more than the {LONG_LEVER_ARM_M:g} m between an IMU and its "
                       "antenna on any platform the presets describe; its entries are in metres (an "
                       f"entry of {big:g} reads as {big:g} m: if the arm was written in cm, that entry is "
                       f"{big / 100:g} m and the arm {d / 100:.4g} m long): check its unit")
        a = self.platform_accel_m_s2
        if a > HIGH_PLATFORM_ACCEL_M_S2:
            out.append(f"{self.name}: platform_accel_m_s2 = {a:.6g} m/s² is {a / G0:.4g} g, more than the "
                       f"{HIGH_PLATFORM_ACCEL_M_S2 / G0:g} g ({HIGH_PLATFORM_ACCEL_M_S2:.0f} m/s²) any platform "
                       "flying a synthetic aperture sustains (missile manoeuvres reach tens of g); it is in "
                       f"m/s² (1 g written in cm/s² is {100 * G0:g}, in mm/s² {1000 * G0:g}): check its unit "
                       "— the derived and no-autofocus bounds use it as given")
        return out

    def defaults_taken(self, keys=DEFAULTED_KEYS) -> dict[str, object]:
        """The scenario keys of ``keys`` that the file (or mapping, or constructor call) did not
        set, or set to null, with the value used in their place (``propagation_speed_m_s``: sound's
        1500 m/s for sonar; radar's speed of light is not listed). A scenario rebuilt from a full
        dump (every key written) has none, except a sonar's null speed of sound."""
        out: dict[str, object] = {}
        for key in keys:
            # a key written as null (``propagation_speed_m_s: null``, as ``scenario write`` puts it)
            # takes the default as much as a key left out
            if key in self.model_fields_set and getattr(self, key) is not None:
                continue
            if key == "propagation_speed_m_s" and self.medium == "radar":
                continue  # the speed of light: a constant, not an assumption (sound's 1500 m/s is)
            out[key] = self.c_m_s if key == "propagation_speed_m_s" else getattr(self, key)
        return out

    def defaults_note(self, keys=DEFAULTED_KEYS) -> str:
        """:meth:`defaults_taken` in words ('' if every key of ``keys`` was set): what a result
        computed from those keys rests on without the user having written it."""
        taken = self.defaults_taken(keys)
        if not taken:
            return ""
        text = ", ".join(f"{k} = {_default_text(k, v, self)}" for k, v in taken.items())
        return f"{self.name}: not in the scenario, taken at their defaults: {text}"

    # --- derived -----------------------------------------------------------------
    @property
    def c_m_s(self) -> float:
        """Propagation speed c (m/s)."""
        if self.propagation_speed_m_s is not None:
            return self.propagation_speed_m_s
        return C_LIGHT if self.medium == "radar" else C_SOUND_WATER

    @property
    def wavelength_m(self) -> float:
        """λ = c / f0 (m)."""
        return self.c_m_s / self.carrier_frequency_hz

    @property
    def theta_rad(self) -> float:
        """Angle between velocity and line of sight, θ = 90° − squint (rad)."""
        return math.radians(90.0 - self.squint_deg)

    @property
    def tc_s(self) -> float:
        """Synthetic-aperture time Tc = a_w λ R / (2 δℓ V sin θ), seed 004 (5), in s."""
        return (self.window_broadening * self.wavelength_m * self.slant_range_m
                / (2.0 * self.azimuth_resolution_m * self.platform_speed_m_s * math.sin(self.theta_rad)))

    @property
    def aperture_length_m(self) -> float:
        """Synthetic-aperture length L = V·Tc (m)."""
        return self.platform_speed_m_s * self.tc_s

    def straight_track_aperture(self) -> dict:
        """The angular aperture δℓ asks for and the straight-track aperture that gives it, exact.

        δℓ = a_w λ / (4 sin(Δθ/2)) (the two-way wavenumber support 2k·2 sin(Δθ/2)); on a straight
        track at perpendicular distance h = R sin θ the line of sight sweeps θ ± Δθ/2, so
        L = h (cot(θ − Δθ/2) − cot(θ + Δθ/2)), which reduces to seed 004 (5)'s R Δθ / sin θ with
        Δθ = a_w λ / (2 δℓ) for narrow apertures. ``reachable`` is False when no aperture gives δℓ
        (sin(Δθ/2) > 1) or the sweep would pass 0° or 180° from the velocity (a squinted line of
        sight cannot turn past the track's direction); ``length_ratio`` is exact L ÷ V·Tc."""
        x = self.window_broadening * self.wavelength_m / (4.0 * self.azimuth_resolution_m)
        theta = self.theta_rad
        # finest δℓ this squint allows: Δθ/2 up to min(θ, π − θ)
        edge = min(theta, math.pi - theta)
        finest = self.window_broadening * self.wavelength_m / (4.0 * math.sin(edge))
        if x >= 1.0:
            return {"reachable": False, "angle_rad": math.pi, "length_m": math.inf, "length_ratio": math.inf,
                    "finest_m": finest, "text": "of 180° or more"}
        half = math.asin(x)
        if half >= edge:
            return {"reachable": False, "angle_rad": 2 * half, "length_m": math.inf,
                    "length_ratio": math.inf, "finest_m": finest,
                    "text": f"of {math.degrees(2 * half):.3g}° about a line of sight "
                            f"{math.degrees(theta):.3g}° from the velocity"}
        h = self.slant_range_m * math.sin(theta)
        length = h * (1.0 / math.tan(theta - half) - 1.0 / math.tan(theta + half))
        return {"reachable": True, "angle_rad": 2 * half, "length_m": length,
                "length_ratio": length / self.aperture_length_m, "finest_m": finest, "text": ""}

    def derived(self) -> dict[str, float]:
        """The derived quantities as a dict (for tables and JSON)."""
        return {"wavelength_m": self.wavelength_m, "tc_s": self.tc_s,
                "aperture_length_m": self.aperture_length_m, "propagation_speed_m_s": self.c_m_s}

    # --- I/O ---------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: dict, *, source: str | Path | None = None) -> "Scenario":
        if not isinstance(data, dict):
            raise InputError("a scenario must be a mapping of keys to values", file=source,
                             expected="a JSON object / YAML mapping")
        try:
            return cls.model_validate(data)
        except ValidationError as err:
            # every error of the file at once: pydantic's (types, bounds, unknown and missing
            # keys) beside our validators' (a value valid alone but implausible, the aiding
            # section naming its own field), each with its value and what was expected
            raise combine_errors(scenario_errors(err), file=source) from None

    @classmethod
    def load(cls, path: str | Path) -> "Scenario":
        """Read a scenario from ``.json``, ``.yaml`` or ``.yml``; errors name the file and field."""
        data = read_structured(path, "a scenario")
        return cls.from_dict(data, source=path)

    def save(self, path: str | Path) -> None:
        """Write as JSON or YAML (by suffix), atomically."""
        path = Path(path)
        data = self.model_dump(mode="json")
        if path.suffix.lower() in (".yaml", ".yml"):
            text = yaml.safe_dump(data, sort_keys=False)
        else:
            text = json.dumps(data, indent=2) + "\n"
        atomic_write_text(path, text)
