"""Trade studies: parts × scenarios → a tidy DataFrame, and the cheapest part that passes.

Each cell runs :func:`~budget.mc.runner.run_mc` with per-trial lists off (streaming aggregation:
memory does not grow with the number of trials). Same seed for every cell: common random
numbers make the comparison between parts sharper.

A scenario the simulator cannot sample (e.g. an aperture of more pulses than
:meth:`budget.sar.SarGeometry.from_scenario` allows) does not stop the study: its cells are
kept with ``status`` "not simulated: <reason>" and empty probabilities, and
:func:`cheapest_passing` says so for that scenario. Every other cell has ``status`` "simulated".
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence

import pandas as pd

from ..catalog.schema import GRADE_RANK
from ..errors import InputError, refuse_repeats
from ..presets import PRESETS
from ..sar.geometry import SarGeometry
from ..sar.residual import DEFAULT_PASS_SHARE
from ..scenario import Scenario, name_scenario_file
from ..scenario_errors import refuse_shared_names as _refuse_shared_names
from .notes import (SIMULATED_DEFAULT_KEYS, aiding_defaults_note, platform_motion_note, resolution_reached,
                    scenario_notes_text)
from .options import McOptions
from .provenance import figures_digest, part_figures, part_origins
from .result import DECISION_RULE
from .runner import check_options, check_run_counts, model_label, run_mc
from .stats import wilson_interval


#: Columns every row of a :func:`sweep` table has (:func:`_cell`), which :func:`cheapest_passing` reads.
TABLE_KEYS = ("scenario", "part_id", "grade", "price_usd")


#: The defaulted scenario keys a Monte Carlo cell rests on: Tc's, the line of sight, the lever arm
#: and the IMU rate the trials are simulated at (:data:`budget.scenario.DEFAULTED_KEYS`).
SWEEP_DEFAULT_KEYS = SIMULATED_DEFAULT_KEYS + ("lever_arm_m", "imu_rate_hz")


def scenario_defaults_text(scen: Scenario) -> str:
    """The ``scenario_defaults`` column: the keys of :data:`SWEEP_DEFAULT_KEYS` the scenario did not
    set and the value used (:meth:`Scenario.defaults_note`), or that every one was set — a CSV row
    says what its verdict rests on without the Monte Carlo's summary beside it."""
    text = "; ".join(t for t in (scen.defaults_note(SWEEP_DEFAULT_KEYS), aiding_defaults_note(scen)) if t)
    return text or "none: every key the verdict uses is in the scenario"


def _cell(scen: Scenario, part, options: McOptions | None = None) -> dict:
    """The columns that name a cell: scenario, its Tc and δr, the resolution the verdict's image
    reaches with its window (:func:`budget.mc.notes.resolution_reached`; e.g. 0.355 m for 0.3 m asked
    with Taylor at a_w = 1), the scenario's own notes, and the part with its figures (JSON, datasheet
    units), their digest and origin (:mod:`budget.mc.provenance`)."""
    figures = part_figures(part)
    out = {"scenario": scen.name, "tc_s": scen.tc_s, "range_resolution_m": scen.range_resolution_m}
    if options is not None:
        reached = resolution_reached(scen, options)
        out.update({"azimuth_resolution_reached_m": reached["azimuth_m"],
                    "range_resolution_reached_m": reached["range_m"]})
    return out | {"scenario_notes": scenario_notes_text(scen),
                  "part_id": model_label(part), "grade": getattr(part, "grade", None),
                  "price_usd": getattr(part, "price_usd", None),
                  "part_figures": json.dumps(figures, sort_keys=True, default=str),
                  "part_digest": figures_digest(figures), "part_origin": part_origins([part])[0]}


def sweep(parts: Sequence, scenarios: Sequence[Scenario], trials: int, seed: int, *,
          options: McOptions | None = None, workers: int = 1, backend: str = "auto", client=None,
          progress=None, cancel=None, sources: Sequence | None = None, catalog_source: str | None = None,
          target: float = DEFAULT_PASS_SHARE) -> pd.DataFrame:
    """One row per part × scenario: P(pass) before/after PGA with Wilson CIs, reasons, p50/p95,
    ``twin_passes`` (trials passed against their perfect-IMU twin, :func:`budget.mc.chain.run_trials`),
    ``pga_second_pass_kept`` (trials on which PGA kept its second pass, :mod:`budget.sar.pga`),
    ``seed`` (the one seed of every cell; ``table.attrs`` also hold it and the options in full),
    ``platform_motion`` (what the platform flew, :mod:`budget.nav.manoeuvre`), ``scene``,
    ``window`` and ``navigation`` (what the verdict was judged on: points or realistic scene, the
    azimuth window, free-inertial or the aiding mode),
    ``unspecified_terms`` (how the part's empty datasheet terms were resolved — each value filled
    from its grade, with its unit, or taken as 0 — as the Monte Carlo's own summary line says),
    ``scenario_defaults`` (the scenario keys the cell rests on that the scenario did not set, with
    the value taken: :func:`scenario_defaults_text`) and ``status`` ("simulated", or "not simulated: <reason>" for a scenario beyond the
    simulator's sampling limits; module docstring), ``verdict`` ("pass", "fail" or "undecided" at
    P(pass after PGA) ≥ ``target`` on the 95 % Wilson interval — :data:`budget.mc.result.DECISION_RULE`,
    the rule of :func:`cheapest_passing` and ``McResult.verdict``; "not simulated"),
    ``azimuth_resolution_reached_m`` / ``range_resolution_reached_m`` (what the verdict's window
    resolves, :func:`budget.mc.notes.resolution_reached`), ``scenario_notes`` (:meth:`Scenario.notes`),
    ``reference_pslr_limit_db`` / ``reference_islr_limit_db`` / ``reference_residual_limit_deg`` (the
    perfect-IMU reference's limits on a cluttered or noisy scene, formed on the part's own image,
    so they move with the image its defocus asked for: :func:`budget.mc.chain.scene_reference`;
    NaN without one), ``part_figures`` /
    ``part_digest`` / ``part_origin`` (the figures judged, :mod:`budget.mc.provenance`) and
    ``catalog`` (``catalog_source``: where the part ids were looked up, also in ``attrs``).
    ``sources``: the file each scenario was read
    from (None for a preset or an object), one per scenario: an input error raised while that
    scenario runs then names its file."""
    parts, scenarios = list(parts), list(scenarios)
    sources = [None] * len(scenarios) if sources is None else list(sources)
    if len(sources) != len(scenarios):
        raise InputError(f"{len(sources)} sources for {len(scenarios)} scenarios", field="sources",
                         expected="one source (a path or None) per scenario")
    if not parts:
        raise InputError("no part to sweep: the list of parts is empty", field="parts",
                         expected="at least one part — a catalog part_id (e.g. 'STIM300'), a part "
                                  "or a noise model (budget.sweep: None = every catalog part with a "
                                  "noise figure)")
    if not scenarios:
        raise InputError("no scenario to sweep: the list of scenarios is empty", field="scenarios",
                         expected="at least one scenario — a preset name (e.g. 'airborne_xband'), "
                                  "a .json/.yaml path or a Scenario")
    cost = "adds identical rows and runs the same trials again"
    refuse_repeats(parts, model_label, field="parts", what="part", cost=cost)
    given = list(zip(scenarios, sources))  # a preset has no source file
    preset = [src is None and sc.name in PRESETS for sc, src in given]
    refuse_repeats([sc for (sc, _), p in zip(given, preset) if p], lambda sc: sc.name, field="presets",
                   what="preset", cost=cost)
    refuse_repeats([g for g, p in zip(given, preset) if not p], lambda g: g[0].name, field="scenarios",
                   what="scenario", cost=cost)
    _refuse_shared_names(given)
    trials, seed, workers = check_run_counts(trials, seed, workers, backend)  # before any cell runs
    options = check_options(options).model_copy(update={"keep_trial_metrics": False})
    rows = []
    total = len(parts) * len(scenarios)
    done = 0
    for scen, source in zip(scenarios, sources):
        try:  # the sampling limits, checked once per scenario (cheap: no echoes are formed)
            SarGeometry.from_scenario(scen, window=options.window_for(scen))
        except InputError as e:
            status = f"not simulated: {name_scenario_file(e, source)}"
            for part in parts:
                # the P(pass) columns are there, empty: a table of unsimulated cells only still
                # has the columns its plots and cheapest_passing read
                rows.append(_cell(scen, part) | {"trials": 0, "seed": seed, "p_pass_before": math.nan,
                                                 "p_pass_after": math.nan, "ci_after_lo": math.nan,
                                                 "ci_after_hi": math.nan, "status": status,
                                                 "verdict": "not simulated", "catalog": catalog_source,
                                                 "platform_motion": platform_motion_note(scen, options.platform_motion),
                                                 "scenario_defaults": scenario_defaults_text(scen)})
                done += 1
                if progress:
                    progress(done, total)
            continue
        for part in parts:
            if cancel is not None and cancel.is_set():
                return _table(rows, seed, options, catalog_source, target)
            try:
                r = run_mc(scen, part, trials, seed, options=options, workers=workers, backend=backend,
                           client=client, cancel=cancel)
            except InputError as err:  # a value of this scenario the simulator cannot use
                raise name_scenario_file(err, source) from None
            pct = r.percentiles("after")
            limits = (r.judged_on.get("reference") or {}).get("limits", {})
            row = _cell(scen, part, options) | {
                "trials": r.trials, "seed": seed, "p_pass_before": r.p_pass_before, "p_pass_after": r.p_pass_after,
                "ci_after_lo": r.ci_after[0], "ci_after_hi": r.ci_after[1], "status": "simulated",
                "verdict": r.verdict(target), "catalog": catalog_source,
                "reference_pslr_limit_db": limits.get("pslr_db", math.nan),
                "reference_islr_limit_db": limits.get("islr_db", math.nan),
                "reference_residual_limit_deg": limits.get("residual_phase_rms_deg", math.nan),
                "twin_passes": r.agg.twin_pass, "pga_second_pass_kept": r.agg.pga_second_pass_kept,
                "platform_motion": r.judged_on.get("platform_motion"),
                # what the verdict was judged on, as columns: a CSV export loses ``attrs``
                "scene": r.judged_on.get("scene"), "window": r.judged_on.get("window"),
                "navigation": r.judged_on.get("navigation"),
                "unspecified_terms": (r.unspecified_summary()
                                      or f"no unspecified datasheet terms ({options.unspecified})"),
                "scenario_defaults": scenario_defaults_text(scen)}
            row.update({f"fail_{k}": v for k, v in r.agg.failure_reasons().items()})
            for m, q in pct.items():
                row[f"{m}_p50"], row[f"{m}_p95"] = q["p50"], q["p95"]
            rows.append(row)
            done += 1
            if progress:
                progress(done, total)
    return _table(rows, seed, options, catalog_source, target)


def _table(rows: list[dict], seed: int, options: McOptions, catalog: str | None = None,
           target: float = DEFAULT_PASS_SHARE) -> pd.DataFrame:
    """The sweep's rows as a DataFrame that says how it was made: ``seed`` is a column (it
    survives a CSV export) and ``attrs`` hold the seed, the Monte Carlo options in full, the
    catalog, each part's figures (``parts``: part_id → figures) and the verdict rule."""
    table = pd.DataFrame(rows)
    parts = {} if not len(table) else {
        pid: json.loads(f) for pid, f in table.groupby("part_id", sort=False)["part_figures"].first().items()}
    table.attrs.update({"seed": seed, "options": options.model_dump(mode="json"), "catalog": catalog,
                        "parts": parts, "verdict_rule": f"{DECISION_RULE} (target {target:g})"})
    return table


def not_simulated(table: pd.DataFrame) -> dict[str, str]:
    """Scenario name → reason, for the scenarios of a :func:`sweep` table that were not simulated."""
    if "status" not in table:
        return {}
    skipped = table.loc[table["status"] != "simulated"]
    return {str(k): str(v) for k, v in skipped.groupby("scenario", sort=False)["status"].first().items()}


def trials_needed(target: float) -> int:
    """Fewest trials whose all-pass outcome has a lower 95 % Wilson bound ≥ ``target`` (< 1)."""
    if not 0.0 < target < 1.0:
        raise InputError("target probability must be in (0, 1)", field="target", value=target)
    n = 1
    while wilson_interval(n, n)[0] < target:
        n += 1
    return n


def cheapest_passing(table: pd.DataFrame, target: float = DEFAULT_PASS_SHARE, *, use_lower_ci: bool = True) -> pd.DataFrame:
    """Per scenario, the cheapest part with P(pass after PGA) ≥ ``target``; ``None`` where none passes.

    "Cheapest" means the public list price (``price_usd``) when every passing part has one;
    otherwise grade is the fallback — the lowest grade passes for the cheapest, list price
    breaking ties within a grade (a part without a price after those with one). The ``basis``
    column says which rule chose the row; ``cheapest_priced`` / ``cheapest_priced_usd`` name
    the cheapest passing part that has a list price (if any), so a price is never hidden.

    "Passes" is decided on the lower 95 % Wilson bound ``ci_after_lo`` by default (column
    ``decided_on``): p̂ = 0.9 from 64 trials is only [0.80, 0.95]; with no failure, 64 trials give
    a lower bound of 0.94, so a target of 0.9 needs ≥ 35 failure-free trials.
    ``use_lower_ci=False`` decides on the point estimate p̂ (not advised).
    """
    if not isinstance(table, pd.DataFrame):
        raise InputError(f"the table is not a sweep table (type {type(table).__name__})", field="table",
                         value=table, expected="the pandas.DataFrame budget.sweep returns")
    missing = [c for c in TABLE_KEYS if c not in table]
    if len(table) and missing:
        raise InputError(f"the table has no column {', '.join(missing)}", field="table",
                         value=list(table.columns), expected="the pandas.DataFrame budget.sweep returns "
                                                             f"(columns {', '.join(TABLE_KEYS)}, …)")
    if not (isinstance(target, (int, float)) and 0.0 < target <= 1.0):  # NaN fails both comparisons
        raise InputError("target probability out of range", field="target", value=target,
                         expected="0 < target ≤ 1 (P(pass after PGA) wanted)")
    col = "ci_after_lo" if use_lower_ci else "p_pass_after"
    out = []
    if not len(table):  # a sweep cancelled before its first cell
        return pd.DataFrame(out)
    for scen, g in table.groupby("scenario", sort=False):
        ok = g[pd.to_numeric(g[col], errors="coerce") >= target].copy() if col in g else g.iloc[:0].copy()
        status = g["status"] if "status" in g else pd.Series(["simulated"] * len(g), index=g.index)
        skipped = status[status != "simulated"]
        if ok.empty:
            basis = (skipped.iloc[0] if len(skipped) == len(g) else f"no part reaches P(pass) ≥ {target:g}"
                     + (f" ({len(skipped)} of {len(g)} cells not simulated)" if len(skipped) else ""))
            trials = pd.to_numeric(g["trials"], errors="coerce").max() if "trials" in g else float("nan")
            if use_lower_ci and len(skipped) < len(g) and trials > 0:
                best_lo = wilson_interval(int(trials), int(trials))[0]
                if best_lo < target:  # the study was too small to show the target at all
                    basis += (f" on the lower 95 % Wilson bound: with {int(trials)} trials even "
                              f"{int(trials)}/{int(trials)} gives {best_lo:.3f}; "
                              + (f"at least {trials_needed(target)} failure-free trials are needed"
                                 if target < 1.0 else "no finite number of trials shows P = 1"))
            out.append({"scenario": scen, "part_id": None, "grade": None, "price_usd": None,
                        "p_pass_after": None, "basis": basis,
                        "cheapest_priced": None, "cheapest_priced_usd": None,
                        "ci_after_lo": None, "decided_on": col})
            continue
        ok["_rank"] = [-GRADE_RANK.get(x, 0) for x in ok["grade"]]
        ok["_price"] = pd.to_numeric(ok["price_usd"], errors="coerce").fillna(float("inf"))
        priced = ok[ok["_price"] < float("inf")].sort_values("_price")
        if len(priced) == len(ok):
            best, basis = priced.iloc[0], "price_usd (every passing part has a list price)"
        else:
            best = ok.sort_values(["_rank", "_price"], kind="stable").iloc[0]
            basis = (f"grade (no list price for {len(ok) - len(priced)} of {len(ok)} passing parts); "
                     "lowest grade passing, list price breaks ties")
        out.append({"scenario": scen, "part_id": best["part_id"], "grade": best["grade"],
                    "price_usd": None if best["_price"] == float("inf") else float(best["_price"]),
                    "p_pass_after": best["p_pass_after"], "basis": basis,
                    "cheapest_priced": priced.iloc[0]["part_id"] if len(priced) else None,
                    "cheapest_priced_usd": float(priced.iloc[0]["_price"]) if len(priced) else None,
                    "ci_after_lo": best["ci_after_lo"], "decided_on": col})
    return pd.DataFrame(out)
