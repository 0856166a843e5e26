"""What a motion run was simulated with, in words, beside its numbers: the IMU rate, the lever
arm (the scenario's, or the default 0), the platform's motion and the datasheet terms left empty
and how they were resolved. The Monte Carlo verdict states the first two the same way
(:mod:`budget.mc.notes`)."""

from __future__ import annotations

import math

from ..scenario import Scenario
from .cost import aperture_samples


#: Fewer IMU samples than this over the aperture and a motion run says its fast phase is low.
FEW_SAMPLES = 100


def imu_rate_note(scenario: Scenario, part_rate_hz: float | None) -> str:
    """The rate the IMU is simulated at (the scenario's ``imu_rate_hz``) and, when the part states
    another output rate, that it is not used and why that is harmless for the catalog's terms."""
    text = (f"IMU simulated at the scenario's imu_rate_hz = {scenario.imu_rate_hz:g} Hz"
            if "imu_rate_hz" in scenario.model_fields_set else
            f"IMU simulated at imu_rate_hz = {scenario.imu_rate_hz:g} Hz, the default (the scenario gives "
            "no imu_rate_hz)")
    if part_rate_hz is not None and abs(part_rate_hz - scenario.imu_rate_hz) > 1e-9 * scenario.imu_rate_hz:
        text += (f" (the part's own output rate, {part_rate_hz:g} Hz, is not used: noise densities and "
                 "bias terms are per √Hz and per second, so the motion error they make over Tc does not "
                 "depend on the sampling rate while the aperture holds enough samples; quantization, tones "
                 "and a pre-filter do — set imu_rate_hz to the part's rate to simulate it at that rate)")
    n = aperture_samples(scenario)
    if n < FEW_SAMPLES:
        text += (f"; only {n} IMU samples span the aperture (Tc = {scenario.tc_s:.3g} s): the simulated error "
                 "has no content between samples, so its phase beyond PGA's window is below what the noise "
                 "densities make in continuous time (VRW and ARW, ADIS16405, measured against 2 kHz: 0.49× "
                 "at 10 samples, 0.82× at 32, 0.94× at 98) — raise imu_rate_hz (the part's output rate)")
    return text


def lever_arm_note(scenario: Scenario) -> str:
    """The lever arm d (m, body frame, IMU → antenna phase centre) the trials were flown with,
    and whether the scenario gave it or it is the default 0 (seed 004's IMU at the antenna: no
    attitude error × lever arm in the verdict)."""
    d = [float(v) for v in scenario.lever_arm_m]
    arm = "[" + ", ".join(f"{v:g}" for v in d) + "] m"
    if "lever_arm_m" not in scenario.model_fields_set:
        return (f"lever arm IMU → antenna {arm}: the default (the scenario gives no lever_arm_m), seed "
                "004's IMU at the antenna phase centre; attitude error × lever arm is not in these trials")
    return (f"lever arm IMU → antenna {arm} (|d| = {math.sqrt(sum(v * v for v in d)):.3g} m, "
            "the scenario's lever_arm_m)")


def platform_note(disturbance) -> str:
    """The platform's motion a motion run flew: straight, level, unrotated flight unless a
    ``disturbance`` (:class:`~budget.nav.platform.Disturbance`) was given."""
    if disturbance is None:
        return ("platform in straight, level, unrotated flight (no disturbance given): the gyros see no "
                "rotation, so gyro scale factor and misalignment have no effect here")
    return "platform disturbance as given (options.disturbance)"
