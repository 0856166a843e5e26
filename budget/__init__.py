"""sar-imu-budget: IMU grade selection and error budgets for synthetic-aperture radar and sonar.

Top-level API (imported on first use, so ``import budget`` stays fast)::

    import budget
    s = budget.load_scenario("airborne_xband")          # preset name, JSON/YAML path or Scenario
    budget.check_parts(["ADIS16405", "STIM300"], s)      # analytic check → CheckResult
    budget.run_mc(s, "STIM300", trials=64, seed=1)       # Monte Carlo verdict → McResult
    table = budget.sweep(["ADIS16405", "STIM300"], ["airborne_xband", "automotive_77ghz"])
    budget.cheapest_passing(table)                       # per scenario

Names accepted wherever an object is expected: preset names for scenarios, ``part_id`` for
parts (:mod:`budget.api`). Everything else lives in the sub-packages (``budget.bounds``,
``budget.mc``, ``budget.noise``, ``budget.gap`` …).

Contract (what every module of the package assumes)
---------------------------------------------------
Units
    SI and radians inside the library. Datasheet units appear only at the edges (catalog CSV,
    CLI, dashboard) and are converted in one place, :mod:`budget.units`. A field or argument
    carries its unit as a suffix: ``_m``, ``_s``, ``_hz``, ``_rad``, ``_m_s`` (m/s), ``_m_s2``,
    ``_rad_s``; datasheet fields ``_deg_h``, ``_deg_rt_h``, ``_ug``, ``_m_s_rt_h``, ``_ppm``,
    ``_mrad``. Identities (tested): 1 deg/√h = 1/60 deg/s/√Hz; 1 m/s/√h = 1/60 m/s²/√Hz
    = 1699.5 µg/√Hz (g = 9.80665 m/s²); 1 deg/h = 4.848e-6 rad/s.
Frames
    Navigation frame: x along the nominal track (the platform flies along +x at speed V), y to
    the imaged side, z up; the line of sight (LOS) points from the antenna to the scene at the
    depression angle, squint 0 = broadside (:func:`budget.motion.geometry.los_unit_vector`).
    Body frame = navigation frame in straight, level flight (a platform motion of
    :mod:`budget.nav.manoeuvre` rotates it, C = Rz(yaw)·Ry(pitch)·Rx(roll),
    :mod:`budget.nav.platform`); the IMU sits at the origin of the body frame and the antenna
    phase centre (APC) at the lever arm ``lever_arm_m``.
Channels
    ``gyro_x``, ``gyro_y``, ``gyro_z`` (rad/s inside, ``_dps`` in logs) and ``accel_x``,
    ``accel_y``, ``accel_z`` (m/s² inside, ``_mps2`` in logs); :data:`budget.units.CHANNELS`.
Array shapes
    Monte Carlo series are ``(trials, samples, 3)`` (sample 0 at the aperture start); image
    data are ``(azimuth, range)`` with azimuth along axis 0.
Signs
    APC error = true − measured (what the IMU believes); aided/estimated error = estimate −
    truth; computed − true for strapdown error states (:mod:`budget.nav.strapdown`). Phase
    (seed 003 (12)), time dependence e^{+jωt}: the echo from range R carries exp(−j4πR/λ), so a
    range increase Δr turns the echo phase by ψ = −4πΔr/λ (:func:`budget.units.range_to_phase`,
    used by :mod:`budget.sar`); the motion, bounds and aiding modules report the phase error
    φ = 4πΔr/λ of a range error Δr = R_true − R_assumed
    (:func:`budget.units.range_error_to_phase_error`): the focused echo carries e^{−jφ}.
    Constant and linear phase only shift the image.
Randomness
    Library functions take a :class:`numpy.random.Generator`; trial engines draw trial ``i``
    from ``SeedSequence(seed, spawn_key=(i, stream))`` with the stream ids of
    :data:`budget.rng.STREAMS`, so the same seed gives the same numbers for any chunking,
    worker count or backend; the model-gap workflow keys its channel streams by channel and model
    structure, its report checks by :data:`budget.rng.GAP_CHECK_STREAMS` (:mod:`budget.rng`).
Errors
    Bad input raises :class:`budget.errors.InputError` naming file, row, field and what was
    expected; the CLI and the dashboard turn every failure into such a message.
Results
    Result objects offer ``summary()``, ``to_frame()`` and ``to_dict()`` and carry the options
    they were computed with.

Sources cited as "seed 000" … "seed 004" are the papers listed in the README ("Sources").
"""

from __future__ import annotations

__version__ = "0.1.0"

#: Names served by :mod:`budget.api` (lazily, PEP 562).
_API = ("load_scenario", "load_scenarios", "load_catalog", "load_part", "load_parts", "check_parts",
        "run_mc", "sweep", "sweep_over", "vary_scenario", "cheapest_passing", "compute_bounds",
        "consistency_table", "real_scene_verdict",
        "DEFAULT_TRIALS", "DEFAULT_SEED")
_OTHER = {"Scenario": ("budget.scenario", "Scenario"), "McOptions": ("budget.mc.options", "McOptions"),
          "InputError": ("budget.errors", "InputError"), "PRESETS": ("budget.presets", "PRESETS"),
          "build_report": ("budget.report", "build_report")}

__all__ = ["__version__", *_API, *_OTHER]


def __getattr__(name: str):
    import importlib

    if name in _API:
        return getattr(importlib.import_module("budget.api"), name)
    if name in _OTHER:
        mod, attr = _OTHER[name]
        return getattr(importlib.import_module(mod), attr)
    raise AttributeError(f"module 'budget' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
