"""The part check in words and as a record: its table per scenario (:func:`check_summary`, what
:meth:`budget.check.CheckResult.summary` prints), the rotation it judged the gyro's scale factor
and misalignment against (:func:`rotation_line`) and the JSON record of ``sar-budget check --json``
and the dashboard's download (:func:`check_record`). :mod:`budget.check` keeps the margins and
verdicts; this module only presents them."""

from __future__ import annotations

import numpy as np


def check_record(result, scenario, mode: str, grades: dict[str, str | None], *, catalog: str,
                 catalog_note: str | None, scenario_keys) -> dict:
    """The JSON record of one part check (``sar-budget check --json``, the dashboard's download):
    mode, scenario, Tc, the catalog the parts came from, the assumptions the verdicts were
    computed with, the part records, the rotation flown, the lowest sufficient grades
    (:func:`budget.recommend.lowest_sufficient_grades`) and why one is none, the scenario keys taken at their
    defaults, what the scenario holds that the verdicts do not use (``notes``) and the catalog note."""
    first = result.to_dict()["scenarios"][0]
    return {"mode": mode, "scenario": scenario.model_dump(mode="json"), "tc_s": float(scenario.tc_s),
            "catalog": catalog, "assumptions": result.assumptions,
            "parts": first["parts"],
            "rotation": result.rotation[0] if result.rotation else None,
            "lowest_sufficient_grade": dict(grades),
            # why a grade above is None (the binding terms, how far the best grade misses them)
            "lowest_sufficient_grade_why_none": dict(getattr(grades, "why_none", {})),
            "notes": first["notes"],
            "scenario_defaults": scenario.defaults_taken(scenario_keys), "catalog_note": catalog_note or None}


def check_summary(result, scenario_index: int | None = None) -> str:
    """Every scenario of ``result`` (a :class:`~budget.check.CheckResult`), each under a header
    naming it when there are several; ``scenario_index``: that scenario only, its header naming it
    and saying how many others the result holds (one scenario: no header, as before)."""
    n = len(result.scenario_names)
    if scenario_index is not None:
        if not -n <= scenario_index < n:
            raise IndexError(f"scenario_index {scenario_index} out of range for {n} scenario(s)")
        s = scenario_index % n
        head = [] if n == 1 else [_header(result, s) + f" — {n - 1} other scenario(s) in this result: "
                                  "summary() shows every one"]
        return "\n".join(head + [_one(result, s)])
    if n == 1:
        return _one(result, 0)
    return "\n\n".join(_header(result, s) + "\n" + _one(result, s) for s in range(n))


def _header(result, s: int) -> str:
    n = len(result.scenario_names)
    return (f"== scenario {s + 1} of {n}: {result.scenario_names[s]} (Tc = {float(np.ravel(result.tc_s)[s]):.4g} s, "
            f"{result.mode} bounds) ==")


def _one(result, scenario_index: int) -> str:
    """The table and notes of one scenario."""
    wb = max(len(p) for p in result.params) + 2  # the binding column holds any parameter name
    n_par = len(result.params)
    lines = [f"{'part':<22}{'grade':<14}{'verdict':<8}{'terms':>6}{'min margin':>11}  {'binding':<{wb}}"
             f"{'PGA-limited':<12}{'margin':>8}{'beyond PGA':>12}{'P(≤ limit)':>12}"]
    notes = []
    partial = False
    for i, (r, mm) in enumerate(zip(result._part_records(scenario_index), result.min_margin[:, scenario_index])):
        v, pmm = result.pga_limited(i, scenario_index)
        given = n_par - len(r["unspecified"])
        partial |= given < n_par
        lines.append(f"{r['part_id']:<22}{r['grade']:<14}{r['verdict']:<8}{f'{given}/{n_par}':>6}{_number(mm):>11}  "
                     f"{r['binding'] or '-':<{wb}}{v:<12}{_number(pmm):>8}"
                     f"{_degrees(r['fast_phase_residual_deg']):>12}"
                     f"{_probability(r['fast_phase_p_within_limit']):>12}")
        if r["flag"]:
            notes.append(f"  {r['part_id']}: {r['flag_reason']}")
    share = result.fast_phase_share[scenario_index] if scenario_index < len(result.fast_phase_share) else None
    limit = (result.fast_phase_limit_deg[scenario_index] if scenario_index < len(result.fast_phase_limit_deg)
             else 1.0)
    asked = (f"the PGA-limited verdict asks it of {share:g} of apertures, the Monte Carlo's pass target"
             if share is not None else "the PGA-limited verdict holds the rms to the limit")
    lines.append("beyond PGA: predicted rms over apertures of the phase PGA's window cannot see, from the part's "
                 f"VRW and ARW (free inertial over Tc; seed 004's limit {limit:g}°; '-' where either is "
                 "unspecified); P(≤ limit): the share of apertures that stay within the limit (one aperture's "
                 f"residual scatters about the rms: the Monte Carlo judges each trial); {asked}")
    if partial:
        lines.append(f"terms: datasheet terms the verdict rests on, of {n_par}; an unspecified term is not "
                     "checked (it neither passes nor fails: the JSON lists them under 'unspecified'), so a "
                     "'pass' on few terms says little — the Monte Carlo fills them from the grade by default")
    if result.rotation:
        lines.append(rotation_line(result.rotation[scenario_index]))
    if notes:
        lines += ["PGA-limited: seed 004's bounds tightened by what PGA cannot remove (fast phase beyond "
                  "its window, attitude error × lever arm); where the verdicts differ:"] + notes
    if result.scenario_notes:
        lines += list(result.scenario_notes[scenario_index])
    if result.defaults_notes and result.defaults_notes[scenario_index]:
        lines.append(result.defaults_notes[scenario_index])
    # a 0 passes every bound (a perfect term): said, not silently counted as a margin of ∞
    lines += [f"row note, {pid}: {n}" for pid, ns in zip(result.part_ids, result.row_notes) for n in ns]
    return "\n".join(lines)


def rotation_line(rot: dict) -> str:
    """One line: the rotation the gyro scale factor and misalignment were judged against."""
    def term(name: str, key: str) -> str:
        f = rot[f"{key}_bound_change"]
        return f"{name} not exercised (bound infinite)" if not np.isfinite(f) else f"{name} bound × {f:.3g}"
    mis = rot["gyro_misalignment_bound_factor"]
    how = (f" (from the γ bound × {mis:.3g}: a gyro misalignment tilts the platform as a scale factor does)"
           if np.isfinite(mis) else "")
    return (f"rotation: gyro scale factor and misalignment judged against the motion flown — {rot['motion']} — "
            f"equivalent excursion {rot['scale_factor_excursion_rad']:.3g} / {rot['misalignment_excursion_rad']:.3g} "
            f"rad against the bounds' {rot['reference_excursion_rad']:g} rad: "
            + "; ".join((term("gyro SF", "gyro_scale_factor"), term("gyro misalignment", "gyro_misalignment")))
            + how)


def _number(value: float) -> str:
    """A margin for the table: '-' where there is none (nothing specified)."""
    return "-" if np.isnan(value) else f"{value:.3g}"


def _probability(value: float) -> str:
    return "-" if not np.isfinite(value) else f"{value:.3f}"


def _degrees(value: float) -> str:
    return "-" if not np.isfinite(value) else f"{value:.3g}°"
