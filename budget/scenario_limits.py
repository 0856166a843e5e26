"""Plausibility limits of a scenario's inputs (SI), each with its reason, and the carrier bands
used to guess the unit a carrier was written in: what :class:`budget.scenario.Scenario` checks a
file against and names in its errors and notes."""

from __future__ import annotations

from .units import C_LIGHT, G0

#: Physically plausible ranges (SI) of the scenario inputs and of Tc, with the reason: a value
#: outside is refused with the reason rather than turned into absurd bounds or margins.
PLAUSIBLE: dict[str, tuple[float, float, str]] = {
    "propagation_speed_m_s": (100.0, C_LIGHT, "between slow acoustic media and the speed of light"),
    "slant_range_m": (0.01, 1e9, "1 cm … 10⁶ km (beyond lunar-radar distances)"),
    "azimuth_resolution_m": (1e-5, 1e5, "10 µm … 100 km"),
    "range_resolution_m": (1e-5, 1e5, "10 µm … 100 km"),
    "platform_speed_m_s": (1e-3, 2e4, "1 mm/s … 20 km/s (faster than any orbit)"),
    "platform_accel_m_s2": (0.0, 1e4, "≤ 10⁴ m/s² (about 1000 g)"),
    "platform_rate_deg_s": (0.0, 1e4, "≤ 10⁴ deg/s"),
}
#: Carrier frequency per medium (Hz): radar 1 MHz … 10 THz, sonar 10 Hz … 5 MHz.
PLAUSIBLE_CARRIER_HZ = {"radar": (1e6, 1e13), "sonar": (10.0, 5e6)}
#: Synthetic-aperture time Tc (s) that a budget can mean something for.
PLAUSIBLE_TC_S = (1e-5, 1e5)
#: Propagation speed per medium (m/s): radio waves are slowed at most ~9× (water, ε ≈ 80), sound
#: travels at most ~12 km/s (diamond); outside, the medium and the speed do not belong together.
RADAR_MIN_SPEED_M_S, SONAR_MAX_SPEED_M_S = 1e7, 2e4
#: IMU → antenna lever arm (m) beyond which a scenario carries a note (:meth:`Scenario.notes`):
#: longer than the installations that carry an IMU for motion compensation (the presets: ≤ 2 m),
#: and what a lever arm written in cm becomes (an entry of 50 for 0.5 m reads as 50 m); still
#: simulated as given.
LONG_LEVER_ARM_M = 20.0
#: Specific force (m/s²) beyond which ``platform_accel_m_s2`` carries a unit note
#: (:meth:`Scenario.notes`): 100 g. Missile manoeuvres reach tens of g (≈ 30–60 g for agile
#: air-to-air missiles), aircraft ≤ 10 g, so 100 g is above any platform that flies a synthetic
#: aperture, while 1 g written in cm/s² (980.665) or mm/s² (9806.65) lies above it; still used as given.
HIGH_PLATFORM_ACCEL_M_S2 = 100.0 * G0
#: What a lever arm is written as.
LEVER_ARM_EXPECTED = "three numbers [x, y, z] in m (IMU → antenna phase centre, body frame)"
#: Exact straight-track aperture ÷ seed 004 (5)'s small-angle V·Tc beyond which a scenario carries
#: a note (:meth:`Scenario.notes`): 1.05 is an angular aperture of about 35° at broadside.
WIDE_APERTURE_RATIO = 1.05
#: Centripetal share V²/r_E of g beyond which level flight's specific force is no longer ≈ g
#: (V ≈ 2.5 km/s) and a scenario carries a note (an orbiting platform is in free fall).
ORBITAL_SPECIFIC_FORCE_SHARE = 0.1
#: Wavelength (m) the limits above allow: 1 µm (radar at 10 THz slowed to 10⁷ m/s) … 2 km (sonar
#: at 10 Hz and 20 km/s); what a wavelength given alone (``bounds --wavelength``) is checked against.
PLAUSIBLE_WAVELENGTH_M = (
    min(RADAR_MIN_SPEED_M_S / PLAUSIBLE_CARRIER_HZ["radar"][1],
        PLAUSIBLE["propagation_speed_m_s"][0] / PLAUSIBLE_CARRIER_HZ["sonar"][1]),
    max(C_LIGHT / PLAUSIBLE_CARRIER_HZ["radar"][0], SONAR_MAX_SPEED_M_S / PLAUSIBLE_CARRIER_HZ["sonar"][0]))


#: Carrier bands (Hz) a synthetic aperture is flown in: radar VHF (foliage-penetrating SAR flies
#: 20–90 MHz) … W band and beyond (20 MHz … 300 GHz), sonar 1 kHz … 1 MHz. Used only to guess the
#: unit a carrier was written in, and to note a carrier outside them.
TYPICAL_CARRIER_HZ = {"radar": (2e7, 3e11), "sonar": (1e3, 1e6)}


def carrier_unit_hint(medium: str, f0_hz: float) -> str:
    """Why a carrier ``f0_hz`` (Hz) is implausible for ``medium``, in words: the unit
    (kHz, MHz, GHz) whose reading puts it in the medium's typical band (a GHz figure written into
    the Hz key: 9.6 → 9.6e+09 Hz), and, for a radar carrier in the sonar band, the other medium."""
    lo, hi = TYPICAL_CARRIER_HZ[medium]
    guesses = [f"{f0_hz * k:.4g} Hz if it was in {unit}"
               for unit, k in (("kHz", 1e3), ("MHz", 1e6), ("GHz", 1e9)) if lo <= f0_hz * k <= hi]
    text = "carrier_frequency_hz is in Hz" + (f" ({'; '.join(guesses)})" if guesses else "")
    lo, hi = PLAUSIBLE_CARRIER_HZ["sonar"]
    if medium == "radar" and lo <= f0_hz <= hi:
        text += "; or did you mean medium 'sonar'?"
    return text
