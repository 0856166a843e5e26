"""Analytic sensor-error bounds driven by the synthetic-aperture time Tc (seed 004).

* :mod:`.paper` — seed 004 (6)–(11) exactly, as printed.
* :mod:`.derived` — the same bounds from physics, every assumption explicit.
* :mod:`.no_autofocus` — what each error may be when no autofocus runs.
* :mod:`.fast_phase` — the limits on what autofocus cannot remove.
* :mod:`.lever_arm` — seed 004's bounds together with attitude error × lever arm.
* :mod:`.rotation` — the rotation a gyro scale factor and misalignment see in the motion flown
  (the equivalent excursion that replaces seed 004's 1 rad).
"""

from collections.abc import Mapping

import numpy as np
from pydantic import ValidationError

from ..errors import InputError, from_validation_error
from .table import BOUND_FIELDS, BoundsTable
from .paper import paper_bounds
from .derived import DerivedAssumptions, derived_bounds
from .no_autofocus import NoAutofocusAssumptions, no_autofocus_bounds
from .fast_phase import (fast_phase_limits, fast_phase_residual, scenario_fast_phase, FastPhaseLimits,
                         FastPhaseResidual)
from .legendre import random_walk_constants
from .lever_arm import LeverArmAssumptions, lever_arm_bounds, lever_arm_terms
from .rotation import RotationExcursion, motion_excursion, rotation_excursion

__all__ = ["BOUND_FIELDS", "BoundsTable", "paper_bounds", "DerivedAssumptions", "derived_bounds",
           "NoAutofocusAssumptions", "no_autofocus_bounds", "fast_phase_limits", "FastPhaseLimits",
           "fast_phase_residual", "scenario_fast_phase", "FastPhaseResidual",
           "random_walk_constants", "compute_bounds", "check_bounds_tc", "max_bounds_tc_s", "LeverArmAssumptions", "lever_arm_bounds",
           "lever_arm_terms", "MODES", "scenario_assumptions", "coerce_assumptions", "scenario_keys", "RotationExcursion",
           "motion_excursion", "rotation_excursion", "accel_level_note", "for_scenario"]

#: Bound modes of :func:`compute_bounds` (and ``sar-budget bounds --mode``).
MODES = ("paper", "derived", "no-autofocus", "lever-arm")


def scenario_assumptions(mode: str, scenario, assumptions=None):
    """The assumptions ``mode`` is computed with for ``scenario``: ``assumptions`` when given;
    otherwise, for ``derived`` and ``no-autofocus``, the defaults with the acceleration level the
    scale factor and misalignment see taken from the scenario (``platform_accel_m_s2``; g, seed
    004's value, in the presets); for ``lever-arm`` the scenario's installation (its
    ``lever_arm_m``, ``platform_rate_deg_s`` and verdict window,
    :meth:`LeverArmAssumptions.from_scenario`, as ``sar-budget bounds --scenario`` uses); None for
    ``paper`` (no assumption)."""
    if assumptions is None and mode in ("lever-arm", "lever_arm"):
        return LeverArmAssumptions.from_scenario(scenario)
    if isinstance(assumptions, Mapping) and mode in _ASSUMPTION_CLASSES:
        # a partial dict ({"combine": "rss"}) completes the scenario's own assumptions, so that
        # its platform_accel_m_s2 (or lever arm) is not silently replaced by the class default
        base = scenario_assumptions(mode, scenario, None)
        return coerce_assumptions(mode, {**base.model_dump(), **assumptions})
    if assumptions is not None or mode not in ("derived", "no-autofocus", "no_autofocus"):
        return coerce_assumptions(mode, assumptions)
    a = float(scenario.platform_accel_m_s2)
    if not a > 0:
        raise InputError("the derived and no-autofocus bounds need the specific force the scale factor and "
                         "misalignment see", field="platform_accel_m_s2", value=a,
                         expected="> 0 m/s² (g = 9.80665 in level flight)")
    cls = DerivedAssumptions if mode == "derived" else NoAutofocusAssumptions
    return cls(accel_level_m_s2=a)


#: The assumptions class of each bounds mode that takes assumptions.
_ASSUMPTION_CLASSES = {"derived": DerivedAssumptions, "no-autofocus": NoAutofocusAssumptions,
                       "no_autofocus": NoAutofocusAssumptions, "lever-arm": LeverArmAssumptions,
                       "lever_arm": LeverArmAssumptions}


def coerce_assumptions(mode: str, assumptions):
    """``assumptions`` for ``mode`` as its class (:class:`DerivedAssumptions`,
    :class:`NoAutofocusAssumptions`, :class:`LeverArmAssumptions`): a dict is validated into it (a
    bad key or value is an :class:`InputError` naming ``assumptions.<key>`` and what it accepts);
    an instance of the class, None, or any value for ``paper`` is returned as it is."""
    cls = _ASSUMPTION_CLASSES.get(mode)
    if cls is None or assumptions is None or isinstance(assumptions, cls):
        return assumptions
    if not isinstance(assumptions, Mapping):
        raise InputError(f"{mode} bounds take a {cls.__name__} or a dict of its fields",
                         field="assumptions", value=type(assumptions).__name__,
                         expected=f"{cls.__name__}(...) or a dict with keys from: {', '.join(cls.model_fields)}")
    try:
        return cls.model_validate(dict(assumptions))
    except ValidationError as err:
        e = from_validation_error(err)
        e.field = f"assumptions.{e.field}" if e.field else "assumptions"
        if e.reason.startswith("Extra inputs"):
            e.reason = "unknown key"
            e.expected = f"keys of {cls.__name__}: {', '.join(cls.model_fields)}"
        e.args = (e._format(),)
        raise e from None


def scenario_keys(mode: str) -> tuple[str, ...]:
    """The defaulted scenario keys (:data:`budget.scenario.DEFAULTED_KEYS`) the bounds of ``mode``
    are computed from: those of Tc, and what :func:`scenario_assumptions` takes from the scenario."""
    from ..scenario import TC_KEYS

    if mode in ("derived", "no-autofocus", "no_autofocus"):
        return TC_KEYS + ("platform_accel_m_s2",)
    if mode in ("lever-arm", "lever_arm"):
        return TC_KEYS + ("lever_arm_m", "platform_rate_deg_s")
    return TC_KEYS


def max_bounds_tc_s() -> float:
    """Longest Tc (s) the bounds are computed for: their error growth (b·t²/2, g·ε·t³/6, the random
    walks) is a free-inertial coast on a flat Earth, which the Schuler, Earth-rate and transport-rate
    terms change by more than 10 % beyond Tc ≈ 790 s (a scenario notes it, :meth:`Scenario.notes`):
    the flat model overstates the Schuler-bounded error, 2× at 3000 s. Nothing in the tool models
    the navigation beyond 3000 s (the Monte Carlo refuses it, aided or not:
    :data:`budget.nav.earth.AIDED_FLAT_EARTH_MAX_TC_S`)."""
    from ..nav.earth import AIDED_FLAT_EARTH_MAX_TC_S
    return AIDED_FLAT_EARTH_MAX_TC_S


def check_bounds_tc(tc_s, field: str = "tc_s") -> None:
    """Refuse a Tc beyond :func:`max_bounds_tc_s` (an :class:`InputError` naming ``field``), where
    the bounds' flat-earth, free-inertial error growth would be a silently wrong number."""
    tc = np.atleast_1d(np.asarray(tc_s, dtype=float))
    hi = max_bounds_tc_s()
    long = tc[np.isfinite(tc) & (tc > hi)]
    if long.size:
        raise InputError(f"an aperture time Tc = {long.max():.4g} s is beyond the bounds' navigation model: "
                         "their error growth (b·t²/2, g·ε·t³/6) is a free-inertial coast on a flat Earth, "
                         "which overstates the Schuler-bounded error by more than 10 % beyond ≈ 790 s "
                         "and 2× at 3000 s", field=field,
                         value=float(long[0]) if long.size == 1 else [float(t) for t in long],
                         expected=f"Tc ≤ {hi:g} s (check the units of frequency, range, resolution and speed)")


def compute_bounds(tc_s, range_resolution_m, mode: str = "paper", *, wavelength_m=None,
                   assumptions=None) -> BoundsTable:
    """Bounds in ``mode`` ``paper`` | ``derived`` | ``no-autofocus`` | ``lever-arm`` for arrays of
    Tc and δr (``lever-arm`` needs the wavelength and a :class:`LeverArmAssumptions`); a Tc beyond
    :func:`max_bounds_tc_s` is refused (:func:`check_bounds_tc`)."""
    check_bounds_tc(tc_s)
    if mode == "paper":
        return paper_bounds(tc_s, range_resolution_m)
    assumptions = coerce_assumptions(mode, assumptions)
    if mode == "derived":
        return derived_bounds(tc_s, range_resolution_m, assumptions or DerivedAssumptions())
    if mode in ("no-autofocus", "no_autofocus"):
        if wavelength_m is None:
            raise InputError("no-autofocus bounds need the wavelength (they limit phase, not range "
                             "cells)", field="wavelength_m", expected="λ in m")
        return no_autofocus_bounds(tc_s, wavelength_m, assumptions or NoAutofocusAssumptions())
    if mode in ("lever-arm", "lever_arm"):
        if wavelength_m is None:
            raise InputError("lever-arm bounds need the wavelength (their fast-phase limit is a "
                             "phase)", field="wavelength_m", expected="λ in m")
        return lever_arm_bounds(tc_s, range_resolution_m, wavelength_m, assumptions or LeverArmAssumptions())
    raise InputError("unknown bounds mode", field="mode", value=mode,
                     expected="paper, derived, no-autofocus or lever-arm")


#: Modes whose bounds take the specific force from their assumptions (the scenario's
#: ``platform_accel_m_s2`` by default); seed 004's paper bounds, and the lever-arm and PGA-limited
#: bounds built on them, take g.
ACCEL_LEVEL_MODES = ("derived", "no-autofocus", "no_autofocus")


def accel_level_note(scenario, mode: str, assumptions=None, *, pga_limited: bool = False) -> str:
    """What the bounds of ``mode`` do with a ``platform_accel_m_s2`` the scenario sets to other
    than g ('' when it sets none, or g): seed 004's paper bounds (and the lever-arm mode built on
    them) take the specific force as g whatever the file says; the derived and no-autofocus bounds
    use the file's value (or the ``assumptions``' ``accel_level_m_s2`` when given). ``pga_limited``:
    a PGA-limited verdict is shown beside the mode's (``sar-budget check``), and it takes g too."""
    from ..units import G0

    if "platform_accel_m_s2" not in scenario.model_fields_set:
        return ""
    a = float(scenario.platform_accel_m_s2)
    if a == G0:
        return ""
    given = f"{scenario.name}: platform_accel_m_s2 = {a:.6g} m/s² ({a / G0:.3g} g) in the scenario"
    g_taken = f"take the specific force as g = {G0:g} m/s² whatever the file says"
    if mode in ACCEL_LEVEL_MODES:
        used = float(getattr(scenario_assumptions(mode, scenario, assumptions), "accel_level_m_s2", a))
        text = (f"{given}: the {mode} bounds of the accel scale factor and misalignment use it"
                if used == a else f"{given} is not used: the {mode} assumptions given take {used:.6g} m/s²")
        return text + (f" (seed 004's paper bounds, and the PGA-limited verdict built on them, {g_taken})"
                       if pga_limited else f" (seed 004's paper bounds {g_taken})")
    whose = ("the lever-arm bounds (seed 004's paper bounds tightened by the lever arm)"
             if mode in ("lever-arm", "lever_arm") else "seed 004's paper bounds")
    if pga_limited:
        whose += " and the PGA-limited verdict built on them"
    derived = ("--mode derived (or no-autofocus) uses the file's value" if a > 0 else
               "--mode derived (or no-autofocus) would use the file's value and refuses 0 (free fall: it needs "
               "the specific force the scale factor and misalignment see, > 0)")
    return f"{given} is not used: {whose} {g_taken}; {derived}"


def for_scenario(table: BoundsTable, scenario, mode: str, assumptions=None) -> BoundsTable:
    """``table`` (the bounds of ``mode`` at ``scenario``'s Tc) carrying the scenario, the keys it
    left at their defaults (:func:`scenario_keys`) and what it holds that the bounds do not use
    (:func:`accel_level_note`): what ``budget.compute_bounds`` and ``sar-budget bounds --scenario``
    print and write."""
    from dataclasses import replace

    keys = scenario_keys(mode)
    note = accel_level_note(scenario, mode, assumptions)
    return replace(table, scenario=scenario.model_dump(mode="json"), scenario_defaults=scenario.defaults_taken(keys),
                   defaults_note=scenario.defaults_note(keys), scenario_notes=(note,) if note else ())
