"""Unit conversions: the one place where datasheet units meet SI.

Everything inside the library is SI (m, s, rad, m/s², rad/s). Datasheet units appear
only at the edges (catalog CSV, CLI, dashboard) and are converted here, nowhere else.

Identities (tested in ``tests/test_units.py``):

* 1 deg/√h  = 1/60 deg/s/√Hz
* 1 m/s/√h  = 1/60 m/s²/√Hz = 1699.5 µg/√Hz (g = 9.80665 m/s²)
* 1 deg/h   = 4.848e-6 rad/s
* 1 ppm     = 1e-6

Channel conventions (IEEE Std 952 coefficients, SI):

=====================  =====================  ===================
term                   gyro (SI)              accelerometer (SI)
=====================  =====================  ===================
quantization Q         rad                    m/s
white noise N (ARW)    rad/s/√Hz = rad/√s     m/s²/√Hz = m/s/√s
bias instability B     rad/s                  m/s²
rate random walk K     rad/s/√s               m/s²/√s
rate ramp R            rad/s²                 m/s³
=====================  =====================  ===================
"""

from __future__ import annotations

import math

import numpy as np

#: Standard gravity, m/s² (CGPM 1901).
G0 = 9.80665
#: Speed of light in vacuum, m/s.
C_LIGHT = 299_792_458.0
#: Nominal speed of sound in sea water, m/s (seed 003 (12)).
C_SOUND_WATER = 1500.0

DEG = math.pi / 180.0
HOUR = 3600.0
SQRT_HOUR = 60.0
#: International foot, m (Honeywell and Northrop Grumman datasheets give VRW in ft/s/√h).
FOOT = 0.3048

# --- angles ---------------------------------------------------------------


def deg_to_rad(x):
    return x * DEG


def rad_to_deg(x):
    return x / DEG


def mrad_to_rad(x):
    return x * 1e-3


def rad_to_mrad(x):
    return x * 1e3


def ppm_to_ratio(x):
    return x * 1e-6


def ratio_to_ppm(x):
    return x * 1e6


# --- gyro -------------------------------------------------------------------


def deg_h_to_rad_s(x):
    """Rate in deg/h → rad/s (1 deg/h = 4.848e-6 rad/s)."""
    return x * DEG / HOUR


def rad_s_to_deg_h(x):
    return x * HOUR / DEG


def dps_to_rad_s(x):
    return x * DEG


def rad_s_to_dps(x):
    return x / DEG


def deg_rt_h_to_rad_s_rt_hz(x):
    """Angle random walk deg/√h → rad/s/√Hz (= rad/√s): divide by 60 then to rad."""
    return x * DEG / SQRT_HOUR


def rad_s_rt_hz_to_deg_rt_h(x):
    return x * SQRT_HOUR / DEG


def deg_h_rt_h_to_rad_s_rt_s(x):
    """Rate random walk deg/h/√h → rad/s/√s (IEEE-952 K)."""
    return x * DEG / HOUR / SQRT_HOUR


def rad_s_rt_s_to_deg_h_rt_h(x):
    return x * HOUR * SQRT_HOUR / DEG


def deg_h_rt_hz_to_deg_rt_h(x):
    """Angle random walk deg/h/√Hz (KVH datasheets) → deg/√h: 1 deg/h/√Hz = 1/60 deg/√h."""
    return x / SQRT_HOUR


# --- accelerometer ----------------------------------------------------------


def ug_to_m_s2(x):
    """Micro-g → m/s² with g = 9.80665 m/s²."""
    return x * 1e-6 * G0


def m_s2_to_ug(x):
    return x / (1e-6 * G0)


def mg_to_m_s2(x):
    return x * 1e-3 * G0


def g_to_m_s2(x):
    return x * G0


def m_s_rt_h_to_m_s2_rt_hz(x):
    """Velocity random walk m/s/√h → m/s²/√Hz (= m/s/√s): divide by 60."""
    return x / SQRT_HOUR


def m_s2_rt_hz_to_m_s_rt_h(x):
    return x * SQRT_HOUR


def ug_rt_hz_to_m_s2_rt_hz(x):
    return x * 1e-6 * G0


def m_s2_rt_hz_to_ug_rt_hz(x):
    return x / (1e-6 * G0)


def m_s_rt_h_to_ug_rt_hz(x):
    """1 m/s/√h = 1699.5 µg/√Hz."""
    return m_s2_rt_hz_to_ug_rt_hz(m_s_rt_h_to_m_s2_rt_hz(x))


def ug_rt_hz_to_m_s_rt_h(x):
    return m_s2_rt_hz_to_m_s_rt_h(ug_rt_hz_to_m_s2_rt_hz(x))


def mg_rt_hz_to_m_s_rt_h(x):
    """Velocity random walk mg/√Hz (VectorNav, KVH datasheets) → m/s/√h: 1 mg/√Hz = 0.5884 m/s/√h."""
    return ug_rt_hz_to_m_s_rt_h(x * 1e3)


def ft_s_rt_h_to_m_s_rt_h(x):
    """Velocity random walk ft/s/√h (Honeywell, Northrop Grumman datasheets) → m/s/√h (× 0.3048)."""
    return x * FOOT


# --- IMU channel unit tags used in log and Allan-deviation column names -------

#: Suffix of a channel column → factor to SI (rad/s for gyros, m/s² for accelerometers).
CHANNEL_UNIT_TO_SI: dict[str, float] = {
    "dps": DEG,
    "rps": 1.0,
    "dph": DEG / HOUR,
    "mps2": 1.0,
    "g": G0,
    "mg": 1e-3 * G0,
    "ug": 1e-6 * G0,
    "mdps": 1e-3 * DEG,
    "mrps": 1e-3,
}
#: The tags of :data:`CHANNEL_UNIT_TO_SI` a gyro and an accelerometer channel may carry.
CHANNEL_UNIT_TAGS: dict[str, tuple[str, ...]] = {"gyro": ("dps", "rps", "dph", "mdps", "mrps"),
                                                 "accel": ("mps2", "g", "mg", "ug")}

#: The package's own unit-suffix spelling (``gyro_arw_deg_rt_h``, ``accel_vrw_m_s_rt_h``) for the
#: same units: a column ``gyro_x_rad_s`` or ``accel_z_m_s2`` reads as ``gyro_x_rps``/``accel_z_mps2``.
CHANNEL_UNIT_ALIASES: dict[str, str] = {"rad_s": "rps", "deg_s": "dps", "deg_h": "dph", "m_s2": "mps2",
                                        "mrad_s": "mrps"}

GYRO_CHANNELS = ("gyro_x", "gyro_y", "gyro_z")
ACCEL_CHANNELS = ("accel_x", "accel_y", "accel_z")
CHANNELS = GYRO_CHANNELS + ACCEL_CHANNELS


def channel_si_unit(channel: str) -> str:
    """SI unit of a channel's signal: ``rad/s`` (``gyro_*``) or ``m/s²`` (``accel_*``)."""
    return "rad/s" if channel.startswith("gyro") else "m/s²"


def split_channel_column(name: str) -> tuple[str, str]:
    """``'gyro_x_dps'`` → ``('gyro_x', 'dps')``; the package's suffix spelling is read as the
    same unit (``'gyro_x_rad_s'`` → ``('gyro_x', 'rps')``, :data:`CHANNEL_UNIT_ALIASES`), and so
    is a unit written in brackets after the channel (``'gyro_x [deg/s]'``, ``'acc_z (m/s^2)'``,
    :func:`header_channel_unit`); raises ``ValueError`` naming what is expected."""
    base, written = split_header_unit(name)
    if written is not None:
        ch = CHANNEL_NAME_ALIASES.get(base.lower(), base.lower())
        if ch in CHANNELS:
            return ch, header_channel_unit(ch, written, name)
        if base.startswith(("gyro_", "accel_")):  # gyro_x_dps [deg/s]: two units, must agree
            ch, tag = _split_tagged(base)
            said = header_channel_unit(ch, written, name)
            if said != tag:
                raise ValueError(f"column {name!r} names two units, {tag} in its name and "
                                 f"{written!r} in brackets: write one")
            return ch, tag
    return _split_tagged(name)


def _split_tagged(name: str) -> tuple[str, str]:
    for ch in CHANNELS:
        if name.startswith(ch + "_"):
            unit = name[len(ch) + 1 :]
            unit = CHANNEL_UNIT_ALIASES.get(unit, unit)
            if unit in CHANNEL_UNIT_TAGS["gyro" if ch.startswith("gyro") else "accel"]:
                return ch, unit
            break
    raise ValueError(
        f"channel column {name!r} not understood: expected <channel>_<unit> with channel in "
        f"{', '.join(CHANNELS)} and unit {'|'.join(CHANNEL_UNIT_TAGS['gyro'])} (or deg_s|rad_s|deg_h) "
        f"for a gyro, {'|'.join(CHANNEL_UNIT_TAGS['accel'])} (or m_s2) for an accelerometer, or "
        "<channel> [unit] (gyro_x [deg/s], accel_z (m/s^2))"
    )


# --- a unit written in a column header: ``gyro_x [deg/s]``, ``adev (deg/h)``, ``tau [s]`` -----

#: Units a column header may write in brackets for a channel (compared in lower case, without
#: spaces: ``rad s^-1`` as public datasets write it is ``rads^-1``) → its tag in
#: :data:`CHANNEL_UNIT_TO_SI`, the one table of factors to SI.
HEADER_CHANNEL_UNITS: dict[str, dict[str, str]] = {
    "gyro": {"deg/s": "dps", "°/s": "dps", "deg/sec": "dps", "dps": "dps", "degs^-1": "dps",
             "rad/s": "rps", "rad/sec": "rps", "rps": "rps", "rads^-1": "rps", "rad·s⁻¹": "rps",
             "deg/h": "dph", "deg/hr": "dph", "°/h": "dph", "°/hr": "dph", "dph": "dph",
             "deg/hour": "dph", "°/hour": "dph", "degree/hour": "dph", "degrees/hour": "dph",
             "degree/h": "dph", "degrees/h": "dph",
             "mdps": "mdps", "mdeg/s": "mdps", "m°/s": "mdps", "mdeg/sec": "mdps",
             "mrad/s": "mrps", "mrad/sec": "mrps", "mrps": "mrps", "mrads^-1": "mrps"},
    "accel": {"m/s^2": "mps2", "m/s²": "mps2", "m/s2": "mps2", "m/s/s": "mps2", "mps2": "mps2",
              "ms^-2": "mps2", "m·s⁻²": "mps2", "g": "g", "mg": "mg",
              # micro-g with the micro sign (U+00B5), the Greek mu (U+03BC) or a u
              "ug": "ug", "µg": "ug", "μg": "ug"},
}
#: Other spellings of a channel before a bracketed unit (``acc_z [m/s^2]``).
CHANNEL_NAME_ALIASES: dict[str, str] = {f"acc_{a}": f"accel_{a}" for a in "xyz"}


def split_header_unit(name: str) -> tuple[str, str | None]:
    """``'gyro_x [deg/s]'`` → ``('gyro_x', 'deg/s')``, ``'adev (deg/h)'`` → ``('adev', 'deg/h')``:
    a header name and the unit written after it in square or round brackets; ``(name, None)``
    when there is none."""
    import re

    m = re.fullmatch(r"\s*(.*?)\s*(?:\[([^\[\]]*)\]|\(([^()]*)\))\s*", str(name))
    if m is None or not m.group(1):
        return str(name).strip(), None
    return m.group(1), (m.group(2) if m.group(2) is not None else m.group(3)).strip()


def _unit_key(text: str) -> str:
    return text.strip().lower().replace(" ", "")


def header_channel_unit(channel: str, written: str, column: str | None = None) -> str:
    """The :data:`CHANNEL_UNIT_TO_SI` tag of the unit ``written`` in a header for ``channel``
    (``'deg/h'`` on ``gyro_z`` → ``'dph'``); ``ValueError`` listing the accepted units when it is
    none of them (an accelerometer unit on a gyro included)."""
    kind = "gyro" if channel.startswith("gyro") else "accel"
    key = _unit_key(written)
    tag = HEADER_CHANNEL_UNITS[kind].get(key)
    if tag is None:
        where = f"column {column!r}" if column else channel
        density = ("; a noise density (per √Hz, √h) is no sample's unit: the column holds samples"
                   if is_density_unit(key) else "")
        raise ValueError(f"{where}: unit {written!r} not understood for {channel}{density}; accepted: "
                         + ", ".join(HEADER_CHANNEL_UNITS[kind]))
    return tag


def is_density_unit(written: str) -> bool:
    """True when the unit ``written`` is a noise density or random walk (``µg/√Hz``,
    ``deg/√h``, ``mg/rtHz``, ``deg/s/sqrt(Hz)``): a datasheet figure, never the unit of a sample."""
    key = _unit_key(written)
    return any(mark in key for mark in ("√", "sqrt", "rthz", "rt-hz", "/rth", "hz^", "hz**", "/hz"))


def header_time_factor(written: str, column: str | None = None) -> float:
    """Factor to seconds of the time unit ``written`` in a header (``tau [ms]`` → 1e-3), from
    :data:`VALUE_UNITS` ``["s"]``; ``ValueError`` listing the accepted units."""
    factor = VALUE_UNITS["s"].get(_unit_key(written))
    if factor is None:
        where = f"column {column!r}: " if column else ""
        raise ValueError(f"{where}time unit {written!r} not understood; accepted: "
                         + ", ".join(VALUE_UNITS["s"]))
    return factor


#: A temperature unit written in a log header or a column-name suffix → (scale, offset) with
#: °C = scale·value + offset.
TEMPERATURE_UNITS: dict[str, tuple[float, float]] = {
    **{k: (1.0, 0.0) for k in ("c", "°c", "degc", "deg_c", "degreesc", "celsius", "℃")},
    **{k: (1.0, -273.15) for k in ("k", "kelvin")},
    **{k: (5.0 / 9.0, -160.0 / 9.0) for k in ("f", "°f", "degf", "deg_f", "degreesf", "fahrenheit", "℉")},
}


def temperature_to_c(written: str, column: str | None = None) -> tuple[float, float]:
    """(scale, offset) turning a temperature in the unit ``written`` into °C
    (°C = scale·value + offset): ``'°C'`` → (1, 0), ``'K'`` → (1, −273.15), ``'degF'`` →
    (5/9, −160/9); ``ValueError`` listing the accepted units."""
    # a degree sign as other encodings leave it: º (ordinal), Â° (UTF-8 read as Latin-1), the
    # replacement character (Latin-1 read as UTF-8)
    key = _unit_key(written).replace("â°", "°").replace("º", "°").replace("\ufffd", "°")
    if key not in TEMPERATURE_UNITS:
        where = f"column {column!r}: " if column else ""
        raise ValueError(f"{where}temperature unit {written!r} not understood; accepted: "
                         "°C (C, degC, celsius), K (kelvin), °F (F, degF, fahrenheit)")
    return TEMPERATURE_UNITS[key]


# --- range and phase (two-way propagation, seed 003 (12)) -------------------------------------
#
# Sign convention of the package (the simulator's, :mod:`budget.sar.echoes`): time dependence
# e^{+jωt}, so an echo from range R carries exp(−j 4π R / λ) (exp(−j 4π f R / c) at frequency
# f). A range increase Δr therefore changes the echo phase by ψ = −4π Δr / λ
# (:func:`range_to_phase`), and focusing multiplies by exp(+j 4π R_assumed / λ). The motion,
# bounds and aiding modules report the *phase error* φ = 4π Δr / λ of a range error
# Δr = R_true − R_assumed (:func:`range_error_to_phase_error`): the focused echo carries e^{−jφ},
# i.e. φ = −ψ. Their limits compare |φ| with the phase limits, so only its magnitude matters
# there; the series keep the sign.


def two_way_wavenumber_rad_m(wavelength_m):
    """Two-way wavenumber 4π / λ: radians of echo phase per metre of range, rad/m (a magnitude;
    the sign is that of :func:`range_to_phase`)."""
    return 4.0 * math.pi / wavelength_m


def two_way_wavenumber_at_frequency_rad_m(frequency_hz, c_m_s):
    """Two-way wavenumber 4π f / c at frequency ``frequency_hz`` (scalar or array) and
    propagation speed ``c_m_s`` (:data:`C_LIGHT`, :data:`C_SOUND_WATER`), rad/m."""
    return 4.0 * math.pi * frequency_hz / c_m_s


def range_to_phase(delta_r_m, wavelength_m):
    """Echo phase change ψ = −4π Δr / λ (rad) of a two-way range increase Δr (m), seed 003 (12),
    with the package's e^{+jωt} convention (the echo from range R carries exp(−j 4π R / λ))."""
    return -4.0 * math.pi * np.asarray(delta_r_m) / wavelength_m


def phase_to_range(phase_rad, wavelength_m):
    """Inverse of :func:`range_to_phase`: the range increase Δr = −ψ λ / (4π) (m) that changes
    the echo phase by ψ (rad)."""
    return -np.asarray(phase_rad) * wavelength_m / (4.0 * math.pi)


def range_error_to_phase_error(range_error_m, wavelength_m):
    """Phase error φ = 4π Δr / λ (rad) of a range error Δr = R_true − R_assumed (m): the focused
    echo carries e^{−jφ}, φ = −:func:`range_to_phase` (Δr)."""
    return -range_to_phase(range_error_m, wavelength_m)


def phase_error_to_range_error(phase_error_rad, wavelength_m):
    """Inverse of :func:`range_error_to_phase_error`: Δr = φ · λ / (4π) (m). For a phase limit
    (|φ| ≤ limit) it is the largest line-of-sight range error allowed."""
    return phase_error_rad * (wavelength_m / (4.0 * math.pi))


# --- a unit written after a number in a value (scenario files) ---------------------------------

#: Units a user may write after a number where a key's name already carries the SI unit
#: (``platform_speed_m_s: 90 km/h``), by that SI unit: unit text (lower case) → factor to it.
VALUE_UNITS: dict[str, dict[str, float]] = {
    "Hz": {"hz": 1.0, "khz": 1e3, "mhz": 1e6, "ghz": 1e9, "thz": 1e12},
    "m": {"m": 1.0, "km": 1e3, "cm": 1e-2, "mm": 1e-3, "nmi": 1852.0, "ft": 0.3048},
    "m/s": {"m/s": 1.0, "km/h": 1.0 / 3.6, "kmh": 1.0 / 3.6, "kn": 1852.0 / 3600.0,
            "kt": 1852.0 / 3600.0, "kts": 1852.0 / 3600.0, "knots": 1852.0 / 3600.0, "mph": 0.44704},
    "m/s²": {"m/s²": 1.0, "m/s2": 1.0, "m/s^2": 1.0, "g": G0},
    "deg": {"deg": 1.0, "°": 1.0, "degrees": 1.0, "rad": 1.0 / DEG, "mrad": 1e-3 / DEG},
    "deg/s": {"deg/s": 1.0, "°/s": 1.0, "dps": 1.0, "rad/s": 1.0 / DEG},
    "s": {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6, "ns": 1e-9, "min": 60.0,
          "h": 3600.0},
    "arcsec": {"arcsec": 1.0, "deg": 3600.0, "°": 3600.0, "mrad": 3.6e3 * 1e-3 / DEG, "rad": 3600.0 / DEG},
}
#: Unit of an input key by the suffix of its name (longest first): ``slant_range_m`` → m.
NAME_SUFFIX_UNITS = (("_m_s2", "m/s²"), ("_deg_s", "deg/s"), ("_m_s", "m/s"), ("_arcsec", "arcsec"),
                     ("_hz", "Hz"), ("_deg", "deg"), ("_m", "m"), ("_s", "s"))


def unit_of_name(name: str) -> str | None:
    """The unit a key's name carries (:data:`NAME_SUFFIX_UNITS`), or None."""
    return next((unit for suffix, unit in NAME_SUFFIX_UNITS if name.endswith(suffix)), None)


def value_text_hint(name: str, text: str, unit: str, noun: str = "key") -> tuple[str, str]:
    """(reason, what to write) for ``text`` given where the number key ``name`` (unit ``unit``)
    expects a number: the unit is in the name, and for a number written with one of that
    quantity's units (``16.7 GHz``) the number to write (1.67e+10) — never taken silently.
    ``noun``: how messages call the key (``key`` in a scenario, ``field`` in its aiding list)."""
    split = split_value_unit(text)
    if split is None:
        return "not a number", f"a plain number in {unit} (the unit is in the {noun}'s name, {name})"
    number, written = split
    si = value_unit_to_si(number, written, unit)
    reason = f"a unit written in the value: the unit is in the {noun}'s name, {name} = {unit}"
    return reason, (f"the number alone in {unit}: {si:.6g} for {text.strip()}" if si is not None else
                    f"the number alone in {unit} ({written!r} is not a unit of {unit})")


def split_value_unit(text: str) -> tuple[float, str] | None:
    """``'16.7 GHz'`` → ``(16.7, 'GHz')``: a number followed by a unit, or None."""
    import re

    m = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z°µ].*?)\s*", text)
    return (float(m.group(1)), m.group(2)) if m else None


def value_unit_to_si(number: float, unit: str, si_unit: str) -> float | None:
    """``number`` ``unit`` in ``si_unit`` (a key of :data:`VALUE_UNITS`), or None if ``unit`` is
    not one of that quantity's units (e.g. a speed written in Hz)."""
    factor = VALUE_UNITS.get(si_unit, {}).get(unit.strip().lower())
    return None if factor is None else number * factor
