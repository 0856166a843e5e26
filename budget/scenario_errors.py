"""The errors a scenario file gets, in words a user can act on: an unknown key with the key meant
or the derived quantity it names, a required key missing with its unit and a typical value, text
where a number is expected with the number to write, and the file named in errors raised after
loading. :class:`budget.scenario.Scenario` is imported where needed (it imports this module)."""

from __future__ import annotations

import difflib
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from pydantic import ValidationError

from .errors import InputError
from .units import unit_of_name, value_text_hint

if TYPE_CHECKING:
    from .scenario import Scenario

#: Quantities a user may try to give but that are derived (never stored), and what sets them.
DERIVED_KEYS = {
    "wavelength_m": "the wavelength is derived: λ = c/f0 from carrier_frequency_hz (and "
                    "propagation_speed_m_s)",
    "tc_s": "Tc is derived: a_w λ R / (2 δℓ V sin θ) from the geometry keys",
    "aperture_length_m": "the aperture length is derived: V·Tc",
}


#: What each required scenario key is (its unit is in its name; a typical value is read from the
#: preset :data:`TYPICAL_PRESET`): the expectation of a "required key missing" error.
REQUIRED_KEYS = {
    "carrier_frequency_hz": "the carrier frequency f0",
    "slant_range_m": "the slant range R from the antenna to the scene centre",
    "azimuth_resolution_m": "the azimuth (along-track) resolution δℓ",
    "range_resolution_m": "the range resolution δr = c/(2B), B the bandwidth",
    "platform_speed_m_s": "the platform speed V over ground",
}
#: The preset whose values a missing required key's message gives as typical.
TYPICAL_PRESET = "airborne_xband"


def _missing_key_error(key: str) -> InputError:
    """A required key missing from a scenario: what the key is, its unit and a typical value."""
    what = REQUIRED_KEYS.get(key)
    unit = key_unit(key)
    if what is None or unit is None:
        return InputError("required key missing", field=key, expected=f"{key} (every scenario needs it)")
    from .presets import PRESETS  # the presets are Scenarios: imported when first needed
    typical = getattr(PRESETS[TYPICAL_PRESET], key)
    return InputError("required key missing", field=key,
                      expected=f"{key}: {what}, in {unit} (e.g. {typical:g} in preset {TYPICAL_PRESET}); "
                               "every scenario gives it")


def scenario_errors(err: ValidationError) -> list[InputError]:
    """Each error of a scenario's validation as an :class:`InputError`: the one a validator
    raised as it is; an unknown key with the key meant; text where a number is expected with the
    number to write (:func:`_number_text_hint`); a missing required key with what it is, its
    unit and a typical value (:func:`_missing_key_error`)."""
    out = []
    for x in err.errors(include_url=False):
        field = ".".join(str(p) for p in x.get("loc", ())) or None
        cause = (x.get("ctx") or {}).get("error")
        if isinstance(cause, InputError):
            if cause.field is None and field:
                cause.field = field
                cause.args = (cause._format(),)
            out.append(cause)
            continue
        kind, value = x.get("type"), x.get("input")
        if kind == "missing" and field:
            out.append(_missing_key_error(field))
            continue
        value = None if isinstance(value, dict) else value
        msg = x.get("msg", "invalid value").removeprefix("Value error, ")
        expected = None
        if kind == "extra_forbidden" and field:
            msg = _unknown_key_text(field)
            expected = ("only the scenario keys (sar-budget scenario write --preset NAME F.yaml writes a file "
                        "with every key)")
        elif kind == "float_parsing" and isinstance(value, str) and field:
            hint = _number_text_hint(field, value)
            if hint is not None:
                msg, expected = hint
        out.append(InputError(msg[:400], field=field, value=value, expected=expected))
    return out


def _unknown_key_text(key: str) -> str:
    """'unknown key' with what the user probably meant: a derived quantity or a close key."""
    if key in DERIVED_KEYS:
        return f"unknown key: {DERIVED_KEYS[key]}"
    close = difflib.get_close_matches(key, list(_scenario_keys()), n=1, cutoff=0.75)
    return f"unknown key (did you mean {close[0]!r}?)" if close else "unknown key"


def key_unit(field: str | None) -> str | None:
    """SI unit of the scenario key ``field`` (``lever_arm_m.0`` → ``m``), from its suffix, or None."""
    base = (field or "").split(".")[0]
    return unit_of_name(base) if base in _scenario_keys() else None


def _number_text_hint(field: str, text: str) -> tuple[str, str] | None:
    """(reason, what to write) for text given to the number key ``field``
    (:func:`budget.units.value_text_hint`), or None for a key without a unit."""
    unit = key_unit(field)
    return None if unit is None else value_text_hint(field.split(".")[0], text, unit)


def scenario_field(field: str | None) -> bool:
    """True if an error's ``field`` is a key of the scenario (``slant_range_m``,
    ``aiding.0.rate_hz``, the derived ``tc_s``) — an error about the scenario's values. The bare
    ``aiding`` and ``name`` are left out: API arguments of that name exist elsewhere."""
    if not field:
        return False
    base = field.split(".")[0].split(" ")[0]
    if field in ("aiding", "name"):
        return False
    return base in _scenario_keys() or base == "tc_s"


def name_scenario_file(err: InputError, source) -> InputError:
    """An error raised *after* a scenario file was loaded (the simulator's limits, the motion
    engine's sampling, the bounds) names the scenario's field but not the file: name ``source``
    (a path) in it when the field is a scenario key and no file is named yet."""
    if isinstance(err, InputError) and err.file is None and isinstance(source, (str, Path)) \
            and str(source) and scenario_field(err.field):
        err.rename_file(source)
    return err


def _scenario_keys():
    """The keys a scenario file may have (its model's fields)."""
    from .scenario import Scenario
    return Scenario.model_fields


def refuse_shared_names(given: Sequence[tuple[Scenario, object]], what: str = "sweep's rows, heat map and cheapest part") -> None:
    """Two scenarios under one name (a preset and an edited copy that kept its name, say) give rows
    nobody can tell apart (one overwrote the other's numbers): refused, naming both — as a repeat
    when equal (a preset and a file holding it), as a clash when they differ (and in which keys).
    ``given``: (scenario, its file or None) pairs; the one rule of :func:`budget.mc.sweep.sweep`
    and :func:`budget.check.check_parts` (``what``: whose rows are keyed by the name)."""
    from .errors import _equal
    from .presets import PRESETS

    seen: dict[str, tuple[Scenario, object, int]] = {}
    for k, (sc, src) in enumerate(given):
        first = seen.setdefault(sc.name, (sc, src, k))
        if first[0] is sc:
            continue
        # "preset" only for the preset itself: an edited copy that kept the preset's name is not one
        where = [f"scenarios[{i}] (" + (f"file {w}" if w is not None
                                         else "preset" if x.name in PRESETS and _equal(x, PRESETS[x.name])
                                         else "a Scenario object or mapping") + ")" for x, w, i in (first, (sc, src, k))]
        if _equal(first[0], sc):
            raise InputError(f"scenario {sc.name!r} given more than once ({where[0]} and {where[1]}, equal)",
                             field="scenarios", value=sc.name,
                             expected="each scenario once (a repeat adds identical rows and runs the same trials again)")
        diff = [f for f in type(sc).model_fields if getattr(sc, f) != getattr(first[0], f)][:4]
        raise InputError(f"two different scenarios are named {sc.name!r}: {where[0]} and {where[1]}, which differ "
                         f"in {', '.join(diff) or 'their keys'}", field="scenarios", value=sc.name,
                         expected=f"a distinct name for each scenario (its 'name' key): the {what} are keyed by it")
