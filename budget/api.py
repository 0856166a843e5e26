"""The package's top-level API: what a script or notebook calls as ``budget.<name>``.

Each function takes the objects of the library *or* their names — a preset name where a
:class:`~budget.scenario.Scenario` is expected, a catalog ``part_id`` where a part is expected, a
path to a scenario file — and resolves them first, so a wrong type or name is an
:class:`~budget.errors.InputError` naming the argument and what it accepts, never an
``AttributeError`` from deep inside. The work itself is done by the library modules named in
each docstring; these are thin front doors.

Every function that names parts takes ``catalog=``: a mapping from :func:`load_catalog`, a path
to a user parts CSV (merged over the shipped parts, as the CLI's ``--catalog``) or ``None`` (the
shipped catalog, and ``$SAR_BUDGET_CATALOG``); :func:`budget.catalog.io.as_catalog` is the one
conversion. A user row with a shipped ``part_id`` replaces the shipped row (as on the CLI).
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

from .errors import InputError

#: Default Monte Carlo trials and seed of the top-level API (the CLI and the dashboard use the
#: same ones, from :mod:`budget.mc.options`).
from .mc.options import DEFAULT_SEED, DEFAULT_TRIALS
from .sar.residual import DEFAULT_PASS_SHARE


def load_scenario(source) -> "Scenario":  # noqa: F821 — imported lazily below
    """A scenario from a :class:`Scenario`, a preset name, a JSON/YAML path or a mapping of keys
    (:func:`budget.presets.load_scenario`)."""
    from .presets import load_scenario as _load

    return _load(source)


def _is_file(source) -> bool:
    """True if ``source`` is what :func:`load_scenario` reads as a file path."""
    from .presets import is_scenario_file

    return is_scenario_file(source)


def _scenario_sources(sources) -> list:
    """One scenario source or a sequence of them, as a list."""
    from pydantic import BaseModel

    # a Scenario (a pydantic model, itself iterable over its fields) is one source, not many
    if isinstance(sources, (str, Path, Mapping, BaseModel)) or not isinstance(sources, Iterable):
        return [sources]
    return list(sources)


def load_scenarios(sources) -> list:
    """:func:`load_scenario` for one source or a sequence of them."""
    return [load_scenario(s) for s in _scenario_sources(sources)]


def load_catalog(user_csv: str | Path | None = None) -> dict:
    """Shipped parts merged with a user CSV (``part_id`` → :class:`PartSpec`; a user row with a
    shipped id replaces it); :func:`budget.catalog.io.load_catalog`."""
    from .catalog.io import load_catalog as _load

    return _load(user_csv)


def load_part(part, catalog: Mapping | str | Path | None = None):
    """The IMU of a command: :func:`budget.imu.resolve.resolve_part` (a part id of ``catalog``, a
    noise-model file or an object; clear errors for unknown ids and bad files)."""
    from .catalog.io import as_catalog
    from .imu.resolve import resolve_part

    # a catalog given is checked even where no id needs it (a wrong file is not passed over in silence)
    return resolve_part(part, None if catalog is None else as_catalog(catalog))


def load_parts(parts=None, catalog: Mapping | str | Path | None = None) -> list:
    """Parts from ids (of ``catalog``) or objects; ``None`` = every part of ``catalog`` with a
    noise figure (as the CLI's sweep, ``--catalog`` included)."""
    from .catalog.io import as_catalog

    if parts is None:
        return [p for p in as_catalog(catalog).values()
                if p.gyro_arw_deg_rt_h is not None or p.accel_vrw_m_s_rt_h is not None]
    from pydantic import BaseModel

    if isinstance(parts, (str, BaseModel)) or not isinstance(parts, Iterable):
        parts = [parts]
    parts = list(parts)
    # read once for all ids; a catalog argument given is checked even if no id needs it
    cat = as_catalog(catalog) if catalog is not None or any(isinstance(p, str) for p in parts) else None
    return [load_part(p, cat) for p in parts]


def check_parts(parts=None, scenarios="airborne_xband", mode: str = "paper", assumptions=None,
                platform_motion=None, *, catalog: Mapping | str | Path | None = None):
    """Analytic check of parts × scenarios against the seed 004 bounds (:func:`budget.check.check_parts`).

    ``parts``: ids or objects (``None`` = the whole catalog, as ``sar-budget check``); ``catalog``:
    where ids are looked up (a mapping, a user CSV merged over the shipped parts, or None: shipped);
    ``scenarios``: one or several
    scenarios, preset names or files; ``platform_motion``: the rotation the gyro scale factor and
    misalignment are judged against (a ``PlatformMotion`` or its dict, e.g. ``{"kind":
    "oscillation"}``; None: the bounds' own 1-rad attitude change).
    """
    from .catalog.io import as_catalog
    from .check import check_parts as _check
    from .mc.provenance import catalog_source

    plist = list(as_catalog(catalog).values()) if parts is None else load_parts(parts, catalog)
    given = _scenario_sources(scenarios)
    return _check(plist, [load_scenario(s) for s in given], mode, assumptions, platform_motion=platform_motion,
                  catalog=catalog_source(catalog, ids_given=_names_parts(parts)),
                  sources=[s if _is_file(s) else None for s in given])


def _names_parts(parts) -> bool:
    """True when ``parts`` looks anything up in a catalog (None, or a part id among them)."""
    if parts is None or isinstance(parts, str):
        return True
    return isinstance(parts, Iterable) and any(isinstance(p, str) for p in parts)


def _mc_keywords(kwargs: dict, engine) -> dict:
    """``kwargs`` with every :class:`~budget.mc.options.McOptions` field given by name
    (``scene="points"``, ``window="taylor"`` …) moved into ``options`` (a validated copy of the
    given ``options``, or of the defaults); any other keyword that is not one of ``engine``'s
    own (its keyword-only parameters, read off its signature; ``sources`` is this module's) is
    refused by name."""
    import inspect

    from pydantic import ValidationError

    from .errors import from_validation_error
    from .mc.options import McOptions, acceptance_spec_options
    from .sar.acceptance import Acceptance

    own = tuple(n for n, p in inspect.signature(engine).parameters.items()
                if p.kind is p.KEYWORD_ONLY and n != "sources")
    fields = {k: kwargs.pop(k) for k in list(kwargs) if k in McOptions.model_fields}
    unknown = [k for k in kwargs if k not in own]
    if unknown:
        raise InputError(f"unknown keyword(s) {', '.join(unknown)}", field=unknown[0],
                         expected=", ".join(own) + ", or a McOptions field: "
                         + ", ".join(McOptions.model_fields))
    if fields:
        base = kwargs.get("options")
        if base is not None and not isinstance(base, McOptions):
            raise InputError(f"options is not McOptions (type {type(base).__name__})", field="options",
                             expected="budget.mc.McOptions or None")
        data = {**(base.model_dump(exclude_unset=True) if base is not None else {}), **fields}
        spec = fields.get("acceptance")
        if isinstance(spec, (Mapping, Acceptance)):
            # a partial acceptance completes the options' own (given) or the verdict's defaults —
            # as ``sar-budget mc --acceptance`` does — never Acceptance's (1-cell peak shift)
            keep = base.acceptance if base is not None and "acceptance" in base.model_fields_set else None
            given = spec if isinstance(spec, Mapping) else spec.model_dump(include=set(spec.model_fields_set))
            data.update(acceptance_spec_options(given, keep))
        try:
            kwargs["options"] = McOptions(**data)
        except ValidationError as err:
            raise from_validation_error(err) from None
    return kwargs


def run_mc(scenario, part, trials: int = DEFAULT_TRIALS, seed: int = DEFAULT_SEED, *,
           catalog: Mapping | str | Path | None = None, **kwargs):
    """Monte Carlo verdict of one part on one scenario (:func:`budget.mc.runner.run_mc`).

    ``scenario`` and ``part`` may be names (``part`` an id of ``catalog``: a mapping, a user CSV
    merged over the shipped parts, or None: shipped); keyword arguments (``options``,
    ``workers``, ``progress``, ``keep_detail`` …) are passed on, and a
    :class:`~budget.mc.options.McOptions` field given by name (``scene="points"``) sets that
    option (over ``options`` when both are given).
    """
    from .mc.runner import run_mc as _run
    from .scenario import name_scenario_file

    kwargs = _mc_keywords(kwargs, _run)
    s = load_scenario(scenario)
    imu = load_part(part, catalog)
    from .mc.provenance import catalog_source

    try:
        result = _run(s, imu, trials, seed, **kwargs)
    except InputError as err:  # a scenario file's value the simulator cannot use: name the file
        raise name_scenario_file(err, scenario if _is_file(scenario) else None) from None
    result.extra["catalog"] = catalog_source(catalog, ids_given=isinstance(part, str))  # in to_dict()
    return result


def sweep(parts=None, scenarios: Sequence | str = "airborne_xband", trials: int = DEFAULT_TRIALS,
          seed: int = DEFAULT_SEED, *, catalog: Mapping | str | Path | None = None, **kwargs):
    """Trade study parts × scenarios → tidy :class:`pandas.DataFrame`, one row per pair
    (:func:`budget.mc.sweep.sweep`; columns ``scenario, part_id, grade, p_pass_after, ci_after_lo,
    ci_after_hi`` …). Names are accepted for parts and scenarios; part ids are looked up in
    ``catalog`` (a mapping, a user CSV merged over the shipped parts, or None: shipped), and
    ``parts=None`` is every part of that catalog with a noise figure (as ``sar-budget sweep
    --catalog``)."""
    from .mc.sweep import sweep as _sweep

    from .mc.provenance import catalog_source

    kwargs = _mc_keywords(kwargs, _sweep)
    given = _scenario_sources(scenarios)
    return _sweep(load_parts(parts, catalog), [load_scenario(s) for s in given], trials, seed,
                  sources=[s if _is_file(s) else None for s in given],
                  catalog_source=catalog_source(catalog, ids_given=_names_parts(parts)), **kwargs)


def real_scene_verdict(data, part, trials: int = 8, seed: int = 1, *,
                       catalog: Mapping | str | Path | None = None, **kwargs):
    """A part's verdict on a recorded scene (:func:`budget.mc.real_scene.real_scene_verdict`):
    its motion error injected into the phase history per trial, focused, PGA, judged on what PGA
    adds to its own floor. ``data``: a :class:`~budget.sar.phase_history.PhaseHistory` or the
    AFRL files of one aperture, in aperture order (:func:`budget.sar.afrl.read_afrl`); ``part``
    as in :func:`run_mc`; keyword arguments (``options``, ``progress``) are passed on."""
    from .mc.real_scene import real_scene_verdict as _verdict
    from .sar.phase_history import PhaseHistory

    if not isinstance(data, PhaseHistory):
        from .sar.afrl import read_afrl

        data = read_afrl([data] if isinstance(data, (str, Path)) else list(data))
    return _verdict(data, load_part(part, catalog), trials, seed, **kwargs)


def cheapest_passing(table, target: float = DEFAULT_PASS_SHARE, **kwargs):
    """Per scenario, the cheapest part of a :func:`sweep` table with P(pass after PGA) ≥ ``target``."""
    from .mc.sweep import cheapest_passing as _cheapest

    return _cheapest(table, target, **kwargs)


def compute_bounds(scenario, mode: str = "paper", assumptions=None):
    """The bounds of one scenario (or preset name) at its Tc (:func:`budget.bounds.compute_bounds`),
    as ``sar-budget bounds --scenario`` computes them: without ``assumptions``, ``derived`` and
    ``no-autofocus`` take the scenario's ``platform_accel_m_s2`` and ``lever-arm`` its lever arm,
    turn rate and verdict window (:func:`budget.bounds.scenario_assumptions`). The table carries
    the scenario and the keys it left at their defaults (``scenario``, ``scenario_defaults`` in
    ``to_dict()``; the defaults in words at the end of ``summary()``) and what it holds that the
    bounds do not use (``scenario_notes``: a ``platform_accel_m_s2`` seed 004's paper bounds replace by
    g, :func:`budget.bounds.accel_level_note`), as the CLI states them."""
    from .bounds import check_bounds_tc, compute_bounds as _bounds, for_scenario, scenario_assumptions

    s = load_scenario(scenario)
    check_bounds_tc(s.tc_s, field="tc_s (derived)")
    table = _bounds([s.tc_s], s.range_resolution_m, mode, wavelength_m=s.wavelength_m,
                    assumptions=scenario_assumptions(mode, s, assumptions))
    return for_scenario(table, s, mode, assumptions)


def consistency_table(scenario, terms=None, scales=None, trials: int = DEFAULT_TRIALS, seed: int = DEFAULT_SEED,
                      **kwargs):
    """P(pass after PGA) of one error term at multiples of its paper bound, and the scale where it
    crosses 50 % (:func:`budget.mc.consistency.consistency_table`; ``terms`` default the four
    seed 004 budgets, ``scales`` 0.1 … 10 ×). ``scenario`` may be a preset name or a file;
    ``options``, ``workers`` are passed on."""
    from .mc.consistency import DEFAULT_TERMS, FINE_SCALES, consistency_table as _table

    s = load_scenario(scenario)
    return _table(s, DEFAULT_TERMS if terms is None else terms,
                  tuple(FINE_SCALES) if scales is None else scales, trials, seed, **kwargs)


#: Scenario quantities a trade study may vary (``vary_scenario``), with their axis labels.
VARIABLE_FIELDS = {"slant_range_m": "slant range R (m)", "platform_speed_m_s": "platform speed V (m/s)",
                   "azimuth_resolution_m": "azimuth resolution δℓ (m)",
                   "carrier_frequency_hz": "carrier frequency f0 (Hz)"}


def vary_scenario(base, field: str, values) -> list:
    """Copies of ``base`` (scenario or preset name) with ``field`` set to each of ``values``,
    named ``<base>@<field>=<value>``; each is validated (Tc follows, seed 004 (5))."""
    from .scenario import Scenario

    s = load_scenario(base)
    if field not in Scenario.model_fields or field in ("name", "medium"):
        raise InputError(f"cannot vary {field!r}", field="field",
                         expected="a numeric scenario key, e.g. " + ", ".join(VARIABLE_FIELDS))
    if isinstance(getattr(s, field), (tuple, list, str, bool)):  # lever_arm_m, aiding, aiding_mode
        raise InputError(f"cannot vary {field!r}: it is not one number", field="field", value=field,
                         expected="a numeric scenario key, e.g. " + ", ".join(VARIABLE_FIELDS) +
                                  " (other values: one scenario each, e.g. budget.load_scenario("
                                  f"{{**s.model_dump(), 'name': ..., {field!r}: ...}}), given to budget.sweep)")
    values = list(values) if isinstance(values, Iterable) and not isinstance(values, str) else [values]
    if not values:
        raise InputError(f"no value of {field} to vary over: the list is empty", field="values",
                         expected=f"at least one value of {field}")
    out = []
    for v in values:
        if isinstance(v, bool) or not isinstance(v, numbers.Real):
            raise InputError(f"not a number for {field}", field="values", value=v,
                             expected=f"numbers of {field} (SI unit in its name)")
        # the keys the base left out stay out, so each copy still states the defaults it takes
        # 12 significant digits: two values that differ get two names (":g" gave 5000 for 5000.0000001)
        data = {**s.model_dump(exclude_unset=True), field: float(v), "name": f"{s.name}@{field}={float(v):.12g}"}
        out.append(Scenario.from_dict(data, source=f"{field}={v}"))
    return out


def sweep_over(parts, base, field: str, values, trials: int = DEFAULT_TRIALS, seed: int = DEFAULT_SEED,
               *, catalog: Mapping | str | Path | None = None, **kwargs):
    """:func:`sweep` over :func:`vary_scenario` copies; the table gains a ``field`` column (and
    has ``tc_s``), ready for P(pass) vs slant range, speed or Tc. ``parts`` and ``catalog`` as
    in :func:`sweep`."""
    scens = vary_scenario(base, field, values)
    table = sweep(parts, scens, trials, seed, catalog=catalog, **kwargs)
    by_name = {sc.name: getattr(sc, field) for sc in scens}
    if len(table) and field not in table.columns:  # range_resolution_m is a column of every sweep
        table.insert(1, field, table["scenario"].map(by_name))
    return table
