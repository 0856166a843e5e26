"""The lowest sufficient IMU grade per synthetic-aperture time Tc: each grade's typical values
(seed 004 Tables 3–4, :func:`budget.parameters.grade_value`) held to the Tc-driven bounds with the
margins of the part check (:mod:`budget.check`: bound / value ≥ 1 passes; on the PGA-limited
bounds with the check's combined VRW + ARW limit too, :func:`budget.check.pga_limited_margin`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from .bounds import compute_bounds
from .catalog.schema import GRADE_RANK, GradeSpec, PartSpec
from .check import PARAM_NAMES, assumptions_dict, bound_matrix, fast_phase_matrix, margins, pga_limited_margin
from .errors import InputError
from .parameters import FAMILIES, PARAMETERS, grade_value

#: What "sufficient" means per term (seed 004's bounds, or a ready table without its scenario) and
#: with the check's combined fast-phase limit (PGA-limited bounds given with their scenario).
CRITERION_TERMS = "each checked term within its bound"
CRITERION_COMBINED = ("each checked term within its PGA-limited bound and VRW and ARW together within the "
                      "fast-phase limit (the check's PGA-limited verdict, budget.check.pga_limited_margin)")
CRITERION_PGA_TERMS_ONLY = ("each checked term within its PGA-limited bound alone — VRW and ARW together are "
                            "not checked (pass scenario= for the check's combined limit): may be too lenient")


def _use(use: str) -> str:
    if use not in ("best", "worst", "typical"):
        raise InputError("unknown grade value", field="use", value=use, expected="'best', 'worst' or 'typical'")
    return use


def grade_part(grade: GradeSpec, use: str = "best", include: Sequence[str] = ("bias", "noise")) -> PartSpec:
    """A catalog part holding ``grade``'s ``use`` values (:func:`budget.parameters.grade_value`) of
    the ``include`` families, the other terms empty; the bias as a total 1σ (as
    :func:`grade_spec_matrix` compares it with the bias bounds: seed 004 Tables 3–4). What the
    recommendation checks a grade as, and what a user can give :func:`budget.check.check_parts`."""
    values = {prm.column: grade_value(grade, prm, _use(use)) for prm in PARAMETERS if prm.family in include}
    return PartSpec(part_id=f"{grade.grade}-grade-{use}", vendor="grades.csv", grade=grade.grade,
                    model=f"{grade.grade} grade, {use} typical values ({', '.join(include)})",
                    source="seed 004 Tables 3-4 (catalog/grades.csv)", bias_instability_convention="total_1sigma",
                    verified="unverified", **values)


def grade_spec_matrix(grades: Sequence[GradeSpec], use: str = "best") -> np.ndarray:
    """(G, 8) SI values of each grade (``best`` = range minimum, ``worst`` = maximum, ``typical``
    = geometric mean), :func:`budget.parameters.grade_value`."""
    _use(use)
    out = np.empty((len(grades), len(PARAMETERS)))
    for i, g in enumerate(grades):
        for j, prm in enumerate(PARAMETERS):
            out[i, j] = grade_value(g, prm, use) * prm.to_si
    return out


@dataclass(frozen=True)
class GradeRecommendation:
    """Lowest sufficient grade per Tc (s) and δr (m), with the options it was found with."""

    tc_s: np.ndarray
    range_resolution_m: np.ndarray
    grade: tuple[str | None, ...]
    include: tuple[str, ...]
    use: str
    mode: str = "paper"
    #: the bounds' wavelength (m, ``no-autofocus`` and ``lever-arm``) and assumptions (``model_dump``)
    wavelength_m: float | None = None
    assumptions: dict | None = None
    #: per Tc, why no grade suffices (:func:`grade_shortfall`: the binding terms and how far the best
    #: grade misses them); None where a grade suffices
    why_none: tuple[str | None, ...] = ()
    #: what "sufficient" meant (:data:`CRITERION_TERMS`, :data:`CRITERION_COMBINED` or
    #: :data:`CRITERION_PGA_TERMS_ONLY`)
    criterion: str = CRITERION_TERMS

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"tc_s": np.ravel(self.tc_s), "range_resolution_m": np.ravel(self.range_resolution_m),
                             "lowest_sufficient_grade": list(self.grade)})

    def to_dict(self) -> dict:
        """JSON-ready: the options (``mode``, ``include``, ``use``, ``wavelength_m``, ``assumptions``)
        and one row per Tc."""
        return {"mode": self.mode, "include": list(self.include), "use": self.use, "criterion": self.criterion,
                "wavelength_m": self.wavelength_m, "assumptions": self.assumptions,
                "rows": [{"tc_s": float(t), "range_resolution_m": float(d), "lowest_sufficient_grade": g,
                          "why_none": self._why(i)}
                         for i, (t, d, g) in enumerate(zip(np.ravel(self.tc_s), np.ravel(self.range_resolution_m),
                                                           self.grade))]}

    def _why(self, i: int) -> str | None:
        return self.why_none[i] if i < len(self.why_none) else None

    def summary(self) -> str:
        why = [f"Tc = {t:.4g} s: no grade suffices — {self._why(i)}" for i, t in enumerate(np.ravel(self.tc_s))
               if self._why(i)]
        head = (f"lowest sufficient grade ({self.mode} bounds, {self.use} typical values; checked: "
                f"{', '.join(self.include)}; sufficient: {self.criterion})")
        return "\n".join([head, self.to_frame().to_string(index=False), *why])


def grade_shortfall(margins_best: np.ndarray, bounds_si: np.ndarray, grade: GradeSpec, cols: Sequence[int],
                    use: str = "best", rules: Mapping[str, str] | None = None, mode: str = "paper") -> str:
    """Why no grade suffices, in words: every checked term (``cols``, :data:`PARAM_NAMES` order) whose
    bound ``grade`` — the best grade — misses (margin < 1), smallest margin first: the bound (its
    rule: ``rules[bound field]`` when a PGA-limited rule tightened it, else seed 004's equation of
    ``mode``), the grade's ``use`` value and the factor by which it is too large; in the grade's units
    (``grades.csv``)."""
    misses = sorted((float(margins_best[j]), j) for j in cols if margins_best[j] < 1.0)
    parts = []
    for margin, j in misses:
        prm = PARAMETERS[j]
        term = prm.label.split(" (")[0]
        rule = (rules or {}).get(prm.bound)
        source = (f"{rule.split(' (')[0].replace(' ', '-')} limit" if rule else
                  f"seed 004 {prm.equation} bound" if mode in ("paper", "pga-limited") else f"{mode} bound")
        bound = bounds_si[j] / prm.grade_to_si
        value = grade_value(grade, prm, use) * prm.to_si / prm.grade_to_si
        parts.append(f"the {source} on {term}, {bound:.3g} {prm.grade_unit}, is below the {grade.grade} grade's "
                     f"{use} {value:.3g} {prm.grade_unit} ({1.0 / margin:.3g}× too large)")
    return "; ".join(parts)


def recommend_grade(tc_s, range_resolution_m, grades: Sequence[GradeSpec], *, mode: str = "paper",
                    include: Sequence[str] = ("bias", "noise"), use: str = "best", wavelength_m=None,
                    assumptions=None, bounds=None, rules: Mapping[str, str] | None = None,
                    scenario=None) -> GradeRecommendation:
    """Lowest grade (highest rank) whose typical values meet the bounds of ``mode``, per Tc.

    ``wavelength_m`` (m) is needed by the ``no-autofocus`` and ``lever-arm`` modes, ``assumptions``
    is passed to :func:`budget.bounds.compute_bounds` (default assumptions when ``None``).
    ``bounds``: a ready :class:`~budget.bounds.BoundsTable` instead (e.g. the PGA-limited table of
    :func:`budget.bounds.lever_arm.pga_limited_bounds`); its ``mode`` is reported, and ``rules``
    (that function's second value: the rule tightening each bound field) names the binding limits
    in ``why_none``. Where no grade suffices, ``why_none`` says which terms the best grade misses and
    by how much (:func:`grade_shortfall`).

    ``scenario`` (with ``bounds`` from :func:`budget.bounds.lever_arm.pga_limited_bounds` of it, one
    Tc): a grade must also meet the check's limit on VRW and ARW together — their combined phase
    beyond PGA's window (:func:`budget.check.pga_limited_margin`, the criterion of the check's
    PGA-limited verdict) — so that the grade recommended passes that check at its own values
    (each term alone within its tightened bound is not enough: the industrial grade's best VRW
    and ARW on a Ku-band UAV scenario). Without it a PGA-limited table is applied per term, said in
    ``criterion`` and warned.

    Defaults follow seed 004's reading of its Tables 1–4: scale factor and misalignment are
    left out because calibration removes most of them (the paper says so), and a grade counts
    as sufficient when the best of its typical range meets the bound (``use="best"``).
    ``None`` where no grade suffices.
    """
    if isinstance(include, str):
        include = (include,)
    unknown = set(include) - set(FAMILIES)
    if unknown:
        raise InputError(f"unknown parameter families {sorted(unknown)}", field="include", value=sorted(unknown),
                         expected=", ".join(sorted(FAMILIES)))
    _use(use)
    tc = np.atleast_1d(np.asarray(tc_s, float))
    dr = np.broadcast_to(np.asarray(range_resolution_m, float), tc.shape)
    cols = [PARAM_NAMES.index(p) for fam in include for p in FAMILIES[fam]]
    ordered = sorted(grades, key=lambda g: GRADE_RANK[g.grade])
    if bounds is None:
        bounds = compute_bounds(tc, dr, mode, wavelength_m=wavelength_m, assumptions=assumptions)
    else:
        mode = bounds.mode
        if np.size(bounds.tc_s) != tc.size:
            raise ValueError(f"bounds hold {np.size(bounds.tc_s)} aperture times, tc_s {tc.size}")
    bmat = bound_matrix(bounds)
    full = margins(grade_spec_matrix(ordered, use), bmat)
    m = full[:, :, cols]
    ok = np.all(m >= 1.0, axis=-1)  # (G, S)
    criterion, combined = CRITERION_TERMS, None
    if scenario is not None:
        if tc.size != 1:
            raise InputError(f"one scenario for {tc.size} aperture times", field="scenario",
                             expected="one Tc (the scenario's) with a scenario")
        from .bounds.lever_arm import LeverArmAssumptions

        parts = [grade_part(g, use, include) for g in ordered]
        combined = fast_phase_matrix(parts, [scenario], [LeverArmAssumptions.from_scenario(scenario)])[2]
        ok = np.array([[pga_limited_margin(m[g, 0], combined[g, 0])[0] >= 1.0] for g in range(len(ordered))])
        criterion = CRITERION_COMBINED
    elif mode == "pga-limited":
        import warnings

        criterion = CRITERION_PGA_TERMS_ONLY
        warnings.warn(f"recommend_grade on PGA-limited bounds without scenario=: {criterion}", UserWarning,
                      stacklevel=2)
    out, why = [], []
    for s in range(tc.size):
        passing = [ordered[g].grade for g in range(len(ordered)) if ok[g, s]]
        out.append(passing[-1] if passing else None)
        text = None
        if not passing and ordered:
            text = grade_shortfall(full[0, s], bmat[s], ordered[0], cols, use, rules, mode)
            if combined is not None and combined[0, s] < 1.0:
                text = "; ".join(t for t in (text, f"the {ordered[0].grade} grade's {use} VRW and ARW together "
                                             f"leave too much phase beyond PGA's window (combined fast-phase "
                                             f"margin {combined[0, s]:.3g})") if t)
        why.append(text)
    return GradeRecommendation(tc, np.asarray(dr), tuple(out), tuple(include), use, mode,
                               None if wavelength_m is None else float(wavelength_m),
                               assumptions_dict(assumptions), tuple(why), criterion)


class SufficientGrades(dict):
    """``{mode: grade, "pga_limited": grade}`` (a dict, as it always was) with ``why_none``: per key
    whose grade is None, why no grade suffices (:func:`grade_shortfall`)."""

    def __init__(self, grades: Mapping[str, str | None], why_none: Mapping[str, str] | None = None):
        super().__init__(grades)
        self.why_none: dict[str, str] = {k: v for k, v in (why_none or {}).items() if v}

    def text(self, key: str) -> str:
        """The grade of ``key``, or 'none' with the reason: a line of ``sar-budget check``."""
        grade = self.get(key)
        if grade:
            return grade
        why = self.why_none.get(key)
        return f"none — {why}" if why else "none"


def lowest_sufficient_grades(scenario, mode: str = "paper", grades: Sequence[GradeSpec] | None = None,
                             assumptions=None) -> SufficientGrades:
    """``{mode: grade, "pga_limited": grade}``: the lowest grade whose typical bias and noise
    figures meet ``mode``'s bounds for ``scenario`` (``assumptions``: the mode's, default the
    scenario's own, :func:`budget.bounds.scenario_assumptions`) and the PGA-limited bounds
    (:func:`budget.bounds.lever_arm.pga_limited_bounds`); None where no grade suffices, and then
    ``why_none[key]`` names the binding terms and how far the best grade misses them
    (:class:`SufficientGrades`). What ``sar-budget check`` prints and writes, and the dashboard's
    Check page shows. The PGA-limited grade meets the check's combined VRW + ARW limit too
    (:func:`recommend_grade` with ``scenario``): at its own values it passes the check's
    PGA-limited verdict. ``scenario``: a :class:`~budget.scenario.Scenario`, a preset name, a
    scenario file or a mapping (:func:`budget.load_scenario`); ``grades``: None = ``grades.csv``."""
    from .bounds import scenario_assumptions
    from .bounds.lever_arm import pga_limited_bounds
    from .catalog.io import load_grades
    from .presets import load_scenario

    scenario = load_scenario(scenario)
    grades = list(load_grades().values() if grades is None else grades)
    rec = recommend_grade([scenario.tc_s], scenario.range_resolution_m, grades, mode=mode,
                          wavelength_m=scenario.wavelength_m,
                          assumptions=scenario_assumptions(mode, scenario, assumptions))
    table, rules = pga_limited_bounds(scenario)
    limited = recommend_grade([scenario.tc_s], scenario.range_resolution_m, grades, bounds=table, rules=rules,
                              scenario=scenario)
    return SufficientGrades({mode: rec.grade[0], "pga_limited": limited.grade[0]},
                            {mode: rec.why_none[0], "pga_limited": limited.why_none[0]})
