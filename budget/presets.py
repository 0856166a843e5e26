"""Preset scenarios from the seed papers (representative values where a paper prints none).

Each preset says where its numbers come from. ``get_preset(name)`` returns a
:class:`~budget.scenario.Scenario`; ``PRESETS`` lists them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

from .errors import InputError
from .scenario import Scenario


def _lever(length_m: float, theta_deg: float, phi_deg: float) -> tuple[float, float, float]:
    """Lever arm from length, elevation θ and azimuth φ (seed 001 gives l, θl, φl)."""
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return (length_m * math.cos(t) * math.cos(p), length_m * math.cos(t) * math.sin(p),
            length_m * math.sin(t))


PRESETS: dict[str, Scenario] = {
    # Seed 000 flies a STIM300 in a small airborne X-band SAR with moderate resolution; it prints
    # no geometry, so the numbers are those of a typical UAV X-band strip-map (Tc ≈ 3 s).
    "airborne_xband": Scenario(
        name="airborne_xband", medium="radar", carrier_frequency_hz=9.6e9, slant_range_m=5_000.0,
        azimuth_resolution_m=0.5, range_resolution_m=0.5, platform_speed_m_s=50.0,
        depression_deg=30.0, window_broadening=1.0, lever_arm_m=(0.5, 0.0, 0.3),
        platform_rate_deg_s=1.0, imu_rate_hz=200.0),
    # Seed 004: airborne SAR with R up to 100 km and V up to 200 m/s (Tc of tens of seconds).
    "airborne_xband_long_range": Scenario(
        name="airborne_xband_long_range", medium="radar", carrier_frequency_hz=9.6e9,
        slant_range_m=100_000.0, azimuth_resolution_m=0.3, range_resolution_m=0.3,
        platform_speed_m_s=200.0, depression_deg=10.0, platform_rate_deg_s=1.0, imu_rate_hz=200.0),
    # Seed 004: automotive short range 24 GHz, R ≤ 50 m, V = 15–40 m/s, δℓ = δr = 0.1 m.
    "automotive_24ghz": Scenario(
        name="automotive_24ghz", medium="radar", carrier_frequency_hz=24e9, slant_range_m=50.0,
        azimuth_resolution_m=0.1, range_resolution_m=0.1, platform_speed_m_s=20.0,
        depression_deg=5.0, platform_rate_deg_s=5.0, imu_rate_hz=200.0),
    # Seed 004: automotive long range 77 GHz, R ≤ 500 m.
    "automotive_77ghz": Scenario(
        name="automotive_77ghz", medium="radar", carrier_frequency_hz=77e9, slant_range_m=500.0,
        azimuth_resolution_m=0.1, range_resolution_m=0.1, platform_speed_m_s=20.0,
        depression_deg=2.0, platform_rate_deg_s=5.0, imu_rate_hz=200.0),
    # Seed 001: missile-borne SAR, 200 m/s, slave IMU at the antenna, lever arm l = 2 m,
    # θl = −20°, φl = 15°, IMU at 100 Hz. Band and range are representative (X band, 10 km).
    "missile_borne": Scenario(
        name="missile_borne", medium="radar", carrier_frequency_hz=10e9, slant_range_m=10_000.0,
        azimuth_resolution_m=1.0, range_resolution_m=1.0, platform_speed_m_s=200.0,
        depression_deg=45.0, lever_arm_m=_lever(2.0, -20.0, 15.0), platform_rate_deg_s=5.0,
        imu_rate_hz=100.0),
    # Seed 003: towed synthetic-aperture sonar, c ≈ 1500 m/s, ~100 kHz; range, speed and
    # resolution representative of a small SAS (Tc ≈ 10 s).
    "sas_100khz": Scenario(
        name="sas_100khz", medium="sonar", carrier_frequency_hz=100e3, slant_range_m=100.0,
        azimuth_resolution_m=0.05, range_resolution_m=0.05, platform_speed_m_s=1.5,
        depression_deg=20.0, platform_accel_m_s2=9.80665, platform_rate_deg_s=1.0,
        imu_rate_hz=100.0),
}


def get_preset(name: str) -> Scenario:
    try:
        return PRESETS[name]
    except KeyError:
        raise InputError(f"unknown preset {name!r}", field="preset",
                         expected=", ".join(PRESETS)) from None


def is_scenario_file(source) -> bool:
    """True if ``source`` is what :func:`load_scenario` reads as a file path: a Path, or a string
    ending in .json/.yaml/.yml that is not a preset's name."""
    return isinstance(source, Path) or (isinstance(source, str) and source not in PRESETS and
                                        Path(source).suffix.lower() in (".json", ".yaml", ".yml"))


def load_scenario(source) -> Scenario:
    """A scenario from a :class:`Scenario`, a preset name, a JSON/YAML path or a mapping of keys
    (the one reader of every function that takes a scenario, :func:`budget.load_scenario`)."""
    if isinstance(source, Scenario):
        return source
    if isinstance(source, Mapping):
        return Scenario.from_dict(dict(source), source="scenario mapping")
    if is_scenario_file(source):
        return Scenario.load(source)
    if isinstance(source, str):
        return get_preset(source)
    raise InputError(f"cannot use a {type(source).__name__} as a scenario", field="scenario",
                     expected="a Scenario, a preset name (" + ", ".join(sorted(PRESETS)) +
                              "), a .json/.yaml path or a mapping of scenario keys")
