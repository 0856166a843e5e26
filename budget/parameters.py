"""The eight checked IMU quantities, described once.

Seed 004 (6)–(11) bound eight sensor errors (scale factor, misalignment, bias and white noise
of the accelerometers and the gyros; one misalignment bound serves both triads) and its
Tables 3–4 give each grade's typical values for the same eight. Every place that pairs a
catalog column with a bound, a grade column, a unit or a label reads :data:`PARAMETERS`:
the bounds table (:data:`budget.bounds.BOUND_FIELDS`), the check (:mod:`budget.check`), the
catalog fill of unspecified values (:mod:`budget.catalog.fill`), the figures
(:mod:`budget.plots`) and the dashboard.

Units: ``unit`` is the datasheet unit of the catalog column (``parts.csv``), ``to_si`` the
factor that turns it into SI (value × ``to_si``); ``grade_unit`` / ``grade_to_si`` the same for
the ``grades.csv`` columns; ``bound_unit`` / ``bound_to_si`` for the datasheet key of the bound
in :meth:`budget.bounds.BoundsTable.datasheet` (the CLI JSON). The factors are the identities
of :mod:`budget.units` (1 deg/√h = 1/60 deg/s/√Hz, 1 m/s/√h = 1/60 m/s²/√Hz, g = 9.80665 m/s²).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .units import DEG, G0, HOUR, SQRT_HOUR

_PPM = 1e-6
_MRAD = 1e-3
_UG = 1e-6 * G0
_DEG_H = DEG / HOUR
_DEG_RT_H = DEG / SQRT_HOUR
_M_S_RT_H = 1.0 / SQRT_HOUR


@dataclass(frozen=True)
class Parameter:
    """One checked quantity: catalog column, grade columns, bound, units and label."""

    key: str                 #: short key, e.g. ``accel_bias``
    triad: str               #: ``accel`` or ``gyro``
    family: str              #: ``scale_factor`` | ``misalignment`` | ``bias`` | ``noise``
    column: str              #: parts.csv column (datasheet unit)
    unit: str                #: datasheet unit of ``column``
    to_si: float             #: column value × to_si = SI
    grade_columns: tuple[str, str]  #: grades.csv (min, max) columns (the same twice for one value)
    grade_unit: str
    grade_to_si: float
    bound: str               #: SI attribute of :class:`budget.bounds.BoundsTable`
    bound_key: str           #: datasheet key of the bound (CLI JSON, bounds figure)
    bound_unit: str
    bound_to_si: float
    label: str               #: short label with the datasheet unit (tables, figures)
    bound_label: str         #: label of the bound (shared by both triads for misalignment)
    equation: str            #: seed 004 equation of the bound

    @property
    def si_unit(self) -> str:
        return {"scale_factor": "–", "misalignment": "rad"}.get(
            self.family, ("m/s²" if self.triad == "accel" else "rad/s")
            + ("/√Hz" if self.family == "noise" else ""))


PARAMETERS: tuple[Parameter, ...] = (
    Parameter("accel_scale_factor", "accel", "scale_factor", "accel_scale_factor_ppm", "ppm", _PPM,
              ("accel_scale_factor_ppm_min", "accel_scale_factor_ppm_max"), "ppm", _PPM,
              "accel_scale_factor", "accel_scale_factor_ppm", "ppm", _PPM,
              "accel SF (ppm)", "accel scale factor β (ppm)", "(6)"),
    Parameter("gyro_scale_factor", "gyro", "scale_factor", "gyro_scale_factor_ppm", "ppm", _PPM,
              ("gyro_scale_factor_ppm_min", "gyro_scale_factor_ppm_max"), "ppm", _PPM,
              "gyro_scale_factor", "gyro_scale_factor_ppm", "ppm", _PPM,
              "gyro SF (ppm)", "gyro scale factor γ (ppm)", "(6)"),
    Parameter("accel_misalignment", "accel", "misalignment", "accel_misalignment_mrad", "mrad", _MRAD,
              ("accel_misalignment_mrad", "accel_misalignment_mrad"), "mrad", _MRAD,
              "misalignment_rad", "misalignment_mrad", "mrad", _MRAD,
              "accel misalign (mrad)", "misalignment (mrad)", "(7)"),
    Parameter("gyro_misalignment", "gyro", "misalignment", "gyro_misalignment_mrad", "mrad", _MRAD,
              ("gyro_misalignment_mrad", "gyro_misalignment_mrad"), "mrad", _MRAD,
              "misalignment_rad", "misalignment_mrad", "mrad", _MRAD,
              "gyro misalign (mrad)", "misalignment (mrad)", "(7)"),
    Parameter("accel_bias", "accel", "bias", "accel_bias_instability_ug", "µg", _UG,
              ("accel_bias_ug_min", "accel_bias_ug_max"), "µg", _UG,
              "accel_bias_m_s2", "accel_bias_ug", "µg", _UG,
              "accel bias (µg)", "accel bias (µg)", "(8)"),
    Parameter("gyro_bias", "gyro", "bias", "gyro_bias_instability_deg_h", "deg/h", _DEG_H,
              ("gyro_bias_deg_h_min", "gyro_bias_deg_h_max"), "deg/h", _DEG_H,
              "gyro_bias_rad_s", "gyro_bias_deg_h", "deg/h", _DEG_H,
              "gyro bias (deg/h)", "gyro bias (deg/h)", "(9)"),
    Parameter("accel_vrw", "accel", "noise", "accel_vrw_m_s_rt_h", "m/s/√h", _M_S_RT_H,
              ("accel_noise_ug_rt_hz_min", "accel_noise_ug_rt_hz_max"), "µg/√Hz", _UG,
              "accel_vrw_m_s2_rt_hz", "accel_vrw_ug_rt_hz", "µg/√Hz", _UG,
              "accel VRW (m/s/√h)", "accel noise (µg/√Hz)", "(10)"),
    Parameter("gyro_arw", "gyro", "noise", "gyro_arw_deg_rt_h", "deg/√h", _DEG_RT_H,
              ("gyro_arw_deg_rt_h_min", "gyro_arw_deg_rt_h_max"), "deg/√h", _DEG_RT_H,
              "gyro_arw_rad_s_rt_hz", "gyro_arw_deg_rt_h", "deg/√h", _DEG_RT_H,
              "gyro ARW (deg/√h)", "gyro ARW (deg/√h)", "(11)"),
)

#: key → Parameter and column → Parameter.
BY_KEY: dict[str, Parameter] = {p.key: p for p in PARAMETERS}
BY_COLUMN: dict[str, Parameter] = {p.column: p for p in PARAMETERS}
#: Catalog columns in check order (the check's margin columns).
COLUMNS: tuple[str, ...] = tuple(p.column for p in PARAMETERS)
#: Family → its catalog columns (accelerometer first).
FAMILIES: dict[str, tuple[str, ...]] = {}
for _p in PARAMETERS:
    FAMILIES.setdefault(_p.family, ())
    FAMILIES[_p.family] += (_p.column,)


def _bounds() -> tuple[Parameter, ...]:
    seen, out = set(), []
    for p in PARAMETERS:
        if p.bound_key not in seen:
            seen.add(p.bound_key)
            out.append(p)
    return tuple(out)


#: One entry per distinct bound (misalignment once), in seed 004 Tables 1–2 order.
BOUNDS: tuple[Parameter, ...] = _bounds()


def grade_value(grade, param: Parameter, use: str = "typical") -> float:
    """A grade's value of ``param`` in the *catalog column's* unit.

    ``use``: ``best`` (range minimum), ``worst`` (maximum) or ``typical`` (geometric mean of
    min and max — the ranges of seed 004 Tables 3–4 span decades, so the log-midpoint).
    """
    lo, hi = sorted(float(getattr(grade, c)) for c in param.grade_columns)
    if use == "best":
        v = lo
    elif use == "worst":
        v = hi
    elif use == "typical":
        v = math.sqrt(lo * hi) if lo > 0 else hi
    else:
        raise ValueError(f"use must be 'best', 'worst' or 'typical', got {use!r}")
    return v * param.grade_to_si / param.to_si
