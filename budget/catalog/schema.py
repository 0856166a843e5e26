"""Catalog row models: an IMU part and an IMU grade, in datasheet units (the catalog's edge).

A part row *is* a noise model: :meth:`PartSpec.to_si` gives the SI error parameters the
simulator and the bounds check use. Unknown datasheet values stay ``None`` (empty cell) —
never invented; consumers treat ``None`` as "not specified".

Bias convention (column ``bias_instability_convention``, one per row, :data:`BIAS_CONVENTIONS`)
says what the figures in the two ``*_bias_instability_*`` columns are:

* ``adev_min`` (default): in-run bias instability as the *minimum of the Allan deviation*
  (Analog Devices, Sensonor, Xsens, KVH "in-run bias stability"); simulated as flicker noise;
* ``ieee_b``: the IEEE Std 952 flicker coefficient B (Allan minimum = B·√(2 ln2/π) ≈ 0.664·B);
* ``total_1sigma``: a total 1σ bias (Honeywell's "bias, 1σ"), mostly a turn-on constant:
  simulated as a per-trial Gaussian constant, not as flicker noise;
* ``turn_on_1sigma``: a turn-on-to-turn-on (repeatability) 1σ figure; simulated as the same
  per-trial constant.

With ``total_1sigma`` / ``turn_on_1sigma`` the repeatability columns must stay empty (the figure
already is the turn-on bias). :meth:`PartSpec.to_si` gives the flicker coefficient B, the Allan
floor and the turn-on 1σ accordingly; :meth:`PartSpec.bias_figure` gives the figure the bias
bounds of seed 004 (8)–(9) are checked against (the Allan-minimum equivalent for ``ieee_b``,
with a separately given turn-on bias added in quadrature).

``verified`` (:data:`VERIFIED_STATES`) says how the row's numbers were checked: ``datasheet``
(read in the vendor's document), ``second_hand`` (a third-party transcription of it),
``partial`` (some values read, some recalled) or ``unverified`` (recalled, not checked);
empty = not stated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from .. import units as u
from ..errors import refuse_bool_numbers

GRADES = ("strategic", "navigation", "stabilization", "tactical", "industrial", "consumer")
#: Rank 1 = best. Used for "cheapest/lowest grade that passes" and sorting.
GRADE_RANK = {g: i + 1 for i, g in enumerate(GRADES)}

#: √(2 ln 2 / π): Allan-deviation floor of flicker noise per unit IEEE B.
FLICKER_FLOOR = math.sqrt(2.0 * math.log(2.0) / math.pi)

#: Values of ``bias_instability_convention`` (see the module docstring).
BIAS_CONVENTIONS = ("adev_min", "ieee_b", "total_1sigma", "turn_on_1sigma")
#: Conventions whose figure is a per-trial constant (turn-on) bias, not flicker noise.
CONSTANT_BIAS_CONVENTIONS = ("total_1sigma", "turn_on_1sigma")
#: Values of ``verified``.
VERIFIED_STATES = ("datasheet", "second_hand", "partial", "unverified")

_num = dict(ge=0.0, allow_inf_nan=False)

#: Numeric columns of parts.csv with their unit (for messages and docs) and plausible maximum.
PART_NUMERIC_COLUMNS: dict[str, tuple[str, float]] = {
    "rate_hz": ("Hz", 1e6),
    "gyro_bias_instability_deg_h": ("deg/h", 1e5),
    "gyro_bias_repeatability_deg_h": ("deg/h", 1e6),
    "gyro_arw_deg_rt_h": ("deg/√h", 1e3),
    "gyro_rrw_deg_h_rt_h": ("deg/h/√h", 1e5),
    "gyro_scale_factor_ppm": ("ppm", 1e6),
    "gyro_misalignment_mrad": ("mrad", 1e3),
    "accel_bias_instability_ug": ("µg", 1e6),
    "accel_bias_repeatability_ug": ("µg", 1e7),
    "accel_vrw_m_s_rt_h": ("m/s/√h", 1e2),
    "accel_scale_factor_ppm": ("ppm", 1e6),
    "accel_misalignment_mrad": ("mrad", 1e3),
    "mass_g": ("g", 1e6),
    "price_usd": ("USD", 1e8),
}
PART_TEXT_COLUMNS = ("part_id", "vendor", "model", "grade", "source",
                     "bias_instability_convention", "verified", "notes")
#: Canonical column order of parts.csv.
PART_COLUMNS = ("part_id", "vendor", "model", "grade", *PART_NUMERIC_COLUMNS, "source",
                "bias_instability_convention", "verified", "notes")
PART_REQUIRED = ("part_id", "grade", "source")



def expected_text(canon: str | None, unit: str) -> str | None:
    """What a cell of column ``canon`` (its unit ``unit``) must hold, in the words every catalog
    error uses; ``None`` for a column with nothing more to say."""
    if canon == "grade":
        return "one of " + ", ".join(GRADES)
    if canon == "part_id":
        return "letters, digits, '.', '_' or '-' (1-64 characters, starting with a letter or digit)"
    if canon in PART_NUMERIC_COLUMNS:
        lim = PART_NUMERIC_COLUMNS[canon][1]
        return f"a number in {unit}, 0 … {lim:g}" + (" (> 0)" if canon == "rate_hz" else "")
    if canon == "bias_instability_convention":
        return ("one of " + ", ".join(BIAS_CONVENTIONS) + " (empty = adev_min); total_1sigma and "
                "turn_on_1sigma leave the repeatability columns empty")
    if canon == "verified":
        return "one of " + ", ".join(VERIFIED_STATES) + " (or empty)"
    if canon == "source":
        return "the datasheet (with revision) the numbers come from"
    return None

class PartSpec(BaseModel):
    """One IMU part in datasheet units (a row of ``catalog/parts.csv``).

    Number fields refuse ``True``/``False`` (Python or numpy), as the CSV reader refuses
    ``true`` in a number column; pydantic's lax mode would otherwise take them as 1.0 and 0.0.
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    part_id: str = Field(..., pattern=r"^[A-Za-z0-9][A-Za-z0-9._\-]{0,63}$")
    vendor: str = ""
    model: str = ""
    grade: Literal["strategic", "navigation", "stabilization", "tactical", "industrial", "consumer"]
    rate_hz: float | None = Field(None, gt=0.0, le=1e6, allow_inf_nan=False)
    gyro_bias_instability_deg_h: float | None = Field(None, le=1e5, **_num)
    gyro_bias_repeatability_deg_h: float | None = Field(None, le=1e6, **_num)
    gyro_arw_deg_rt_h: float | None = Field(None, le=1e3, **_num)
    gyro_rrw_deg_h_rt_h: float | None = Field(None, le=1e5, **_num)
    gyro_scale_factor_ppm: float | None = Field(None, le=1e6, **_num)
    gyro_misalignment_mrad: float | None = Field(None, le=1e3, **_num)
    accel_bias_instability_ug: float | None = Field(None, le=1e6, **_num)
    accel_bias_repeatability_ug: float | None = Field(None, le=1e7, **_num)
    accel_vrw_m_s_rt_h: float | None = Field(None, le=1e2, **_num)
    accel_scale_factor_ppm: float | None = Field(None, le=1e6, **_num)
    accel_misalignment_mrad: float | None = Field(None, le=1e3, **_num)
    mass_g: float | None = Field(None, le=1e6, **_num)
    price_usd: float | None = Field(None, le=1e8, **_num)
    source: str = Field(..., min_length=1)
    bias_instability_convention: Literal["adev_min", "ieee_b", "total_1sigma", "turn_on_1sigma"] = "adev_min"
    verified: Literal["datasheet", "second_hand", "partial", "unverified"] | None = None
    notes: str = ""

    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    @field_validator("bias_instability_convention")
    @classmethod
    def _constant_bias_has_no_repeatability(cls, v: str, info) -> str:
        # The columns above are validated first, so their values are in info.data.
        if v in CONSTANT_BIAS_CONVENTIONS:
            both = [c for c in ("gyro_bias_repeatability_deg_h", "accel_bias_repeatability_ug")
                    if info.data.get(c) is not None]
            if both:
                raise ValueError(f"{v} says the bias columns already hold the turn-on bias, but "
                                 f"{' and '.join(both)} is also given; leave it empty or use "
                                 "adev_min / ieee_b for an in-run figure")
        return v

    @field_validator("vendor", "model", "source", "notes")
    @classmethod
    def _no_formula(cls, v: str) -> str:
        if v and v[0] in "=+-@" and not v[1:2].isdigit():
            raise ValueError("text starting with =, +, - or @ looks like a spreadsheet formula")
        return v

    @property
    def bias_is_constant(self) -> bool:
        """True when the bias columns hold a turn-on / total 1σ constant (not flicker)."""
        return self.bias_instability_convention in CONSTANT_BIAS_CONVENTIONS

    def bias_figure(self, column: str) -> float | None:
        """The bias column in its datasheet unit as compared with seed 004 (8)–(9): the bias that
        stays constant over Tc. The in-run figure as given (``ieee_b`` → Allan minimum 0.664·B),
        combined with a separately given turn-on bias (the row's ``*_bias_repeatability`` column,
        same unit) as √(in-run² + turn-on²): both are constant over an aperture, and the Monte
        Carlo simulates both, so one constant bias stored as repeatability or as a total 1σ gives
        one margin. With ``total_1sigma`` / ``turn_on_1sigma`` the column already is that bias.
        ``None`` when neither is given."""
        v = getattr(self, column)
        rep_col = column.replace("_instability_", "_repeatability_")
        rep = getattr(self, rep_col, None) if rep_col != column else None
        if v is None and rep is None:
            return None
        fig = 0.0 if v is None else float(v) * (FLICKER_FLOOR if self.bias_instability_convention == "ieee_b" else 1.0)
        return math.hypot(fig, 0.0 if rep is None else float(rep))

    def to_si(self) -> "ImuErrorsSI":
        """SI error parameters (``None`` datasheet values become 0.0 and are listed in ``missing``).

        The bias convention decides where the bias figure goes: flicker B and its Allan floor
        (``adev_min``, ``ieee_b``) or the per-trial turn-on constant (``total_1sigma``,
        ``turn_on_1sigma``; the flicker terms are then 0).
        """
        conv = self.bias_instability_convention
        # with a constant-bias convention the bias columns already are the turn-on bias
        covered = (("gyro_bias_repeatability_deg_h", "accel_bias_repeatability_ug")
                   if conv in CONSTANT_BIAS_CONVENTIONS else ())
        missing = tuple(k for k in PART_NUMERIC_COLUMNS
                        if k not in ("mass_g", "price_usd", *covered) and getattr(self, k) is None)

        def val(name: str) -> float:
            v = getattr(self, name)
            return 0.0 if v is None else float(v)

        def floor_and_b(raw_si: float) -> tuple[float, float]:
            if conv == "adev_min":
                return raw_si, raw_si / FLICKER_FLOOR
            if conv == "ieee_b":
                return raw_si * FLICKER_FLOOR, raw_si
            return 0.0, 0.0

        g_bias = u.deg_h_to_rad_s(val("gyro_bias_instability_deg_h"))
        a_bias = u.ug_to_m_s2(val("accel_bias_instability_ug"))
        g_floor, g_b = floor_and_b(g_bias)
        a_floor, a_b = floor_and_b(a_bias)
        const = conv in CONSTANT_BIAS_CONVENTIONS
        return ImuErrorsSI(
            rate_hz=self.rate_hz,
            gyro_bias_instability_adev_rad_s=g_floor,
            gyro_bias_instability_b_rad_s=g_b,
            gyro_turn_on_bias_rad_s=(g_bias if const else
                                     u.deg_h_to_rad_s(val("gyro_bias_repeatability_deg_h"))),
            gyro_arw_rad_s_rt_hz=u.deg_rt_h_to_rad_s_rt_hz(val("gyro_arw_deg_rt_h")),
            gyro_rrw_rad_s_rt_s=u.deg_h_rt_h_to_rad_s_rt_s(val("gyro_rrw_deg_h_rt_h")),
            gyro_scale_factor=u.ppm_to_ratio(val("gyro_scale_factor_ppm")),
            gyro_misalignment_rad=u.mrad_to_rad(val("gyro_misalignment_mrad")),
            accel_bias_instability_adev_m_s2=a_floor,
            accel_bias_instability_b_m_s2=a_b,
            accel_turn_on_bias_m_s2=(a_bias if const else
                                     u.ug_to_m_s2(val("accel_bias_repeatability_ug"))),
            accel_vrw_m_s2_rt_hz=u.m_s_rt_h_to_m_s2_rt_hz(val("accel_vrw_m_s_rt_h")),
            accel_scale_factor=u.ppm_to_ratio(val("accel_scale_factor_ppm")),
            accel_misalignment_rad=u.mrad_to_rad(val("accel_misalignment_mrad")),
            missing=missing,
            bias_convention=conv,
        )


@dataclass(frozen=True)
class ImuErrorsSI:
    """IMU error parameters in SI (rad, s, m). Absent datasheet values are 0.0, named in ``missing``.

    ``*_bias_instability_adev_*`` is the Allan-deviation floor; ``*_bias_instability_b_*`` the
    IEEE-952 flicker coefficient B (floor = 0.664·B). ``*_turn_on_bias_*`` is the 1σ
    run-to-run bias (repeatability, or the total 1σ bias of a ``total_1sigma`` row), drawn once
    per trial by the simulator. ``bias_convention`` is the row's convention.
    """

    rate_hz: float | None
    gyro_bias_instability_adev_rad_s: float
    gyro_bias_instability_b_rad_s: float
    gyro_turn_on_bias_rad_s: float
    gyro_arw_rad_s_rt_hz: float
    gyro_rrw_rad_s_rt_s: float
    gyro_scale_factor: float
    gyro_misalignment_rad: float
    accel_bias_instability_adev_m_s2: float
    accel_bias_instability_b_m_s2: float
    accel_turn_on_bias_m_s2: float
    accel_vrw_m_s2_rt_hz: float
    accel_scale_factor: float
    accel_misalignment_rad: float
    missing: tuple[str, ...] = ()
    bias_convention: str = "adev_min"


class GradeSpec(BaseModel):
    """Typical error ranges of one IMU grade, seed 004 Tables 3–4 (a row of ``catalog/grades.csv``)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    grade: Literal["strategic", "navigation", "stabilization", "tactical", "industrial", "consumer"]
    rank: int = Field(..., ge=1, le=6)
    accel_scale_factor_ppm_min: float = Field(..., **_num)
    accel_scale_factor_ppm_max: float = Field(..., **_num)
    accel_misalignment_mrad: float = Field(..., **_num)
    accel_bias_ug_min: float = Field(..., **_num)
    accel_bias_ug_max: float = Field(..., **_num)
    accel_noise_ug_rt_hz_min: float = Field(..., **_num)
    accel_noise_ug_rt_hz_max: float = Field(..., **_num)
    gyro_scale_factor_ppm_min: float = Field(..., **_num)
    gyro_scale_factor_ppm_max: float = Field(..., **_num)
    gyro_misalignment_mrad: float = Field(..., **_num)
    gyro_bias_deg_h_min: float = Field(..., **_num)
    gyro_bias_deg_h_max: float = Field(..., **_num)
    gyro_arw_deg_rt_h_min: float = Field(..., **_num)
    gyro_arw_deg_rt_h_max: float = Field(..., **_num)
    source: str = Field(..., min_length=1)
    notes: str = ""

    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)
