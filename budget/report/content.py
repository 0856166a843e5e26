"""What a report holds: scenario, bounds in every mode, the analytic check, Monte Carlo P(pass)
with intervals, the check-vs-MC comparison, figures, and provenance (version, seed, options).

:func:`build_report` computes what is not given (the check always; the Monte Carlo per part
unless ``mc_results`` are passed, e.g. by the dashboard which already ran them).
"""

from __future__ import annotations

import datetime as _dt
import math
import platform
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..errors import InputError

#: P(pass after PGA) at or above which a part counts as passing the Monte Carlo verdict when the
#: two verdicts are compared (the sweep's default target).
MC_PASS_TARGET = 0.9
BOUND_MODES = ("paper", "derived", "no-autofocus")


def mc_dict(result) -> dict:
    """JSON-safe dict of an :class:`~budget.mc.McResult` (its :meth:`~budget.mc.McResult.to_dict`)."""
    return result.to_dict()


def check_vs_mc(record: Mapping, mc, target: float = MC_PASS_TARGET) -> dict:
    """Does the analytic verdict (a part record of :meth:`CheckResult.to_dict`) agree with the Monte Carlo?

    Compares the check's ``pass``/``fail`` with P(pass after PGA) ≥ ``target`` and its 95 %
    interval: a disagreement is stated only when the interval lies wholly on the other side of
    ``target``. The check's own flag (its seed 004 verdict differs from its fast-phase /
    lever-arm verdict, ``flag``/``flag_reason``) is carried as ``check_flag`` and
    ``check_flag_reason``: it predicts such a disagreement without a simulation. When the check
    passes and the Monte Carlo fails, ``space_variance`` (:mod:`budget.mc.space_variance`, None
    when the result does not carry its scenario) and ``filled_terms_share``
    (:func:`filled_terms_share`) hold the figures the ``reason`` rests on.
    """
    # the PGA-limited verdict (the mode's bounds and what PGA cannot remove, lever arm included)
    # is the one that predicts a verdict after PGA; seed 004's alone is kept beside it
    limited = record.get("pga_limited_verdict")
    analytic = limited if limited in ("pass", "fail") else record.get("verdict")
    basis = "PGA-limited check" if limited in ("pass", "fail") else "analytic check"
    p, (lo, hi) = mc.p_pass_after, mc.ci_after
    mc_verdict = "pass" if lo >= target else "fail" if hi < target else "undecided"
    out = {"part_id": record.get("part_id"), "check_verdict": analytic, "check_basis": basis,
           "seed004_verdict": record.get("verdict"), "mc_p_pass_after": p,
           "mc_ci_after": [lo, hi], "mc_verdict": mc_verdict, "target": target,
           "check_flag": bool(record.get("flag", False)), "check_flag_reason": record.get("flag_reason")}
    if analytic not in ("pass", "fail") or mc_verdict == "undecided":
        out.update(agree=None, reason="not comparable (check unknown or MC interval straddles the target)")
    elif analytic == mc_verdict:
        out.update(agree=True, reason="")
    else:
        why = _disagreement_causes(record, mc, analytic, out, limited=basis == "PGA-limited check")
        out.update(agree=False, reason=f"{basis} says {analytic}, Monte Carlo P(pass after PGA) = "
                                       f"{p:.2f} [{lo:.2f}, {hi:.2f}] (target {target:g}): " + " ".join(why))
    return out


def check_vs_mc_text(versus: Mapping) -> str:
    """:func:`check_vs_mc`'s record in one line, naming which check the Monte Carlo was compared
    with (``check_basis``: the PGA-limited check, the verdict that predicts one after PGA; the
    check table's ``verdict`` column is the ``--mode`` one): what ``sar-budget mc`` prints."""
    basis = versus.get("check_basis") or "analytic check"
    if versus.get("agree") is False:
        return f"check vs Monte Carlo: DISAGREE — {versus.get('reason')}"
    head = "agree" if versus.get("agree") else versus.get("reason")
    return (f"check vs Monte Carlo: {head} ({basis} {versus.get('check_verdict')}, "
            f"MC {versus.get('mc_verdict')})")


#: Check columns that act only through the platform's rotation (none in straight, level flight).
_ROTATION_TERMS = ("gyro_scale_factor_ppm", "gyro_misalignment_mrad")
#: Rise of the part's combined use of the bounds (:func:`filled_terms_share`) from its filled
#: datasheet terms at or above which they are named as a possible cause of a disagreement: below
#: it the motion error they add is within a tenth of what the given terms make.
FILLED_SHARE_MATERIAL = 0.1


def filled_terms_share(mc) -> float | None:
    """How much the datasheet terms the Monte Carlo filled (``budget.catalog.fill``) add to what
    the part spends of seed 004's paper bounds at the run's Tc and δr.

    Each checked term j spends u_j = spec_j / bound_j (1 / margin: 1 is the whole budget, a
    range error of δr); the part spends U = √(Σ_j u_j²), the terms' errors taken as independent.
    Returns U_simulated / U_given − 1 — the part as simulated (``mc.model_spec``, fills in)
    against the part as given (the filled columns empty) — over the terms the simulation
    exercises (the gyro scale factor and misalignment only when it flies a rotation); ``inf`` when
    nothing else is given; None when the result does not say what it simulated or filled.
    """
    from ..bounds import paper_bounds
    from ..catalog.schema import PartSpec
    from ..check import PARAM_NAMES, bound_matrix, spec_matrix

    filled = ((getattr(mc, "extra", None) or {}).get("unspecified_terms") or {}).get("filled") or []
    spec, scenario = getattr(mc, "model_spec", None), getattr(mc, "scenario", None)
    if not filled or not isinstance(spec, Mapping) or scenario is None:
        return None
    try:
        simulated = PartSpec.model_validate(dict(spec))
        given = simulated.model_copy(update={f["column"]: None for f in filled})
        bounds = bound_matrix(paper_bounds(np.array([scenario.tc_s]), scenario.range_resolution_m))[0]
    except (ValueError, TypeError, KeyError, InputError):
        return None
    options = getattr(mc, "options", None)
    rotates = options is not None and options.platform_motion.rotates
    keep = np.array([rotates or name not in _ROTATION_TERMS for name in PARAM_NAMES])
    with np.errstate(divide="ignore", invalid="ignore"):
        use = np.nan_to_num(spec_matrix([simulated, given]) / bounds[None, :], nan=0.0)[:, keep]
    u_sim, u_given = np.sqrt(np.sum(use ** 2, axis=1))
    if u_given == 0.0:
        return math.inf if u_sim > 0.0 else 0.0
    return float(u_sim / u_given - 1.0)


def _rise(share: float) -> str:
    """The rise :func:`filled_terms_share` in words."""
    what = "they raise the part's use of the paper bounds, √Σ(spec/bound)²,"
    if math.isinf(share):
        return f"{what} from nothing"
    return f"{what} {1 + share:.3g}-fold" if share >= 1 else f"{what} by {100 * share:.2g} %"


#: Datasheet columns whose error reaches the fast phase PGA cannot remove (white noise, flicker,
#: random walk): a fill of any other column cannot cause a ``residual_phase_noise`` failure.
_FAST_PHASE_COLUMNS = ("gyro_arw_deg_rt_h", "accel_vrw_m_s_rt_h", "gyro_bias_instability_deg_h",
                       "accel_bias_instability_ug", "gyro_rrw_deg_h_rt_h")


def _disagreement_causes(record: Mapping, mc, analytic: str, out: dict | None = None, *,
                         limited: bool = False) -> list[str]:
    """Sentences naming what is known to differ between the check and the Monte Carlo for this
    part — each from a fact of the two results, none by default: the MC's main failure reason,
    space variance over the simulated scene's range depth when it is material
    (:mod:`budget.mc.space_variance`; the bounds assume one phase error for the whole scene),
    datasheet terms the MC filled (the check leaves them out) when they add materially to the
    part's use of the bounds (:func:`filled_terms_share`), the check's own flag, the
    straight-level flight of the simulation (its ``platform_motion``) when the check's binding
    term needs rotation. ``out`` (the comparison dict) receives the figures: ``space_variance``
    and ``filled_terms_share``."""
    from ..mc.space_variance import FOCUS_REASONS, space_variance_of

    figures = {} if out is None else out
    reasons = mc.agg.failure_reasons() if hasattr(mc, "agg") else {}
    top = max(reasons, key=reasons.get) if reasons and max(reasons.values()) > 0 else None
    why = []
    if analytic == "pass":
        why.append(f"the Monte Carlo fails mostly on {top} ({reasons[top]} of {mc.trials} trials)."
                   if top else "the Monte Carlo fails.")
        sv = space_variance_of(mc)
        figures["space_variance"] = None if sv is None else sv.to_dict()
        filled = ((getattr(mc, "extra", None) or {}).get("unspecified_terms") or {}).get("filled") or []
        share = filled_terms_share(mc)
        figures["filled_terms_share"] = share
        # scale factors, misalignments, turn-on biases: PGA removes the low-order phase they make
        off_fast_phase = top == "residual_phase_noise" and not any(f["column"] in _FAST_PHASE_COLUMNS for f in filled)
        fills_matter = bool(filled) and (share is None or share >= FILLED_SHARE_MATERIAL) and not off_fast_phase
        listing = ", ".join(f"{f['column']} = {f['value']:.4g} {f['unit']}" for f in filled)
        if fills_matter:
            why.append("It filled datasheet terms the check leaves out (unspecified there): " + listing
                       + ("" if share is None else f" ({_rise(share)})")
                       + " — run it with unspecified='zero' to see their share.")
        # a space-variant residual defocuses the edge lines: named when the trials fail mostly on
        # focus, not on range migration or on what PGA's window cannot see
        if sv is not None and sv.material and top in FOCUS_REASONS:
            why.append(sv.sentence(sole=not fills_matter))
        if filled and not fills_matter:
            cause = "none of them reaches the fast phase PGA cannot remove" if off_fast_phase else _rise(share)
            why.append(f"The datasheet terms it filled ({listing}) are not the cause: {cause}.")
        if top == "residual_phase_noise" and not record.get("flag") and not limited:
            why.append("The check's bounds in this mode do not limit the fast phase error PGA cannot "
                       "remove; the PGA-limited check does.")
    else:
        why.append("the simulated chain passes where a bound fails.")
        options = getattr(mc, "options", None)
        rotates = options is not None and options.platform_motion.rotates
        if record.get("binding") in _ROTATION_TERMS and not rotates:
            why.append(f"The check's binding term, {record['binding']}, acts through the platform's "
                       "rotation, and the Monte Carlo flies straight, level and unrotated: it cannot "
                       "fail on it (McOptions.platform_motion flies a rotation).")
    if record.get("flag"):
        why.append(f"The check flags it too: {record['flag_reason']}.")
    return why


@dataclass
class Report:
    """A report's content; :meth:`html` renders it (:mod:`budget.report.html`)."""

    scenario: object
    mode: str
    bounds: pd.DataFrame
    check: object
    mc: dict = field(default_factory=dict)
    comparisons: list = field(default_factory=list)
    figures: dict = field(default_factory=dict)
    provenance: dict = field(default_factory=dict)
    #: the assumptions given per mode (completed from the scenario for the bounds: its
    #: platform_accel_m_s2), None when none were given
    assumptions: Mapping | None = None

    def check_frame(self) -> pd.DataFrame:
        recs = self.check.to_dict()["scenarios"][0]["parts"]
        return pd.DataFrame([{"part_id": r["part_id"], "grade": r["grade"], "verdict": r["verdict"],
                              "binding": r["binding"], **r["margins"],
                              "beyond PGA (° rms)": r["fast_phase_residual_deg"],
                              "apertures within the limit": r["fast_phase_p_within_limit"],
                              "flag (seed 004 vs fast phase / lever arm)": r.get("flag_reason") or ""}
                             for r in recs])

    def mc_frame(self) -> pd.DataFrame:
        return pd.DataFrame([{"part_id": pid, "trials": r.trials, "p_pass_before": r.p_pass_before,
                              "ci_before_lo": r.ci_before[0], "ci_before_hi": r.ci_before[1],
                              "p_pass_after": r.p_pass_after, "ci_after_lo": r.ci_after[0],
                              "ci_after_hi": r.ci_after[1], **{f"fail_{k}": v for k, v in
                                                               r.agg.failure_reasons().items()}}
                             for pid, r in self.mc.items()])

    def to_frame(self) -> pd.DataFrame:
        """Check and Monte Carlo side by side, one row per part."""
        check = self.check_frame()[["part_id", "grade", "verdict", "binding"]]
        if not self.mc:
            return check
        return check.merge(self.mc_frame(), on="part_id", how="left")

    def to_dict(self) -> dict:
        return {"scenario": self.scenario.model_dump(mode="json"), "derived": self.scenario.derived(),
                "scenario_defaults": self.scenario.defaults_taken(),
                "mode": self.mode, "bounds": self.bounds.to_dict(orient="records"),
                "check": self.check.to_dict()["scenarios"][0]["parts"],
                "mc": {pid: mc_dict(r) for pid, r in self.mc.items()},
                "check_vs_mc": self.comparisons, "provenance": self.provenance}

    def summary(self) -> str:
        s = self.scenario
        lines = [f"report: scenario {s.name} (Tc = {s.tc_s:.4g} s), {len(self.check.part_ids)} parts, "
                 f"{self.mode} bounds, Monte Carlo on {len(self.mc)} part(s)"]
        lines += [f"  {c['part_id']}: check {c['check_verdict']}, MC P(pass) {c['mc_p_pass_after']:.2f} — "
                  + ("agree" if c["agree"] else "DISAGREE: " + c["reason"] if c["agree"] is False
                     else c["reason"]) for c in self.comparisons]
        return "\n".join(lines)

    def html(self) -> str:
        from .html import render_html

        return render_html(self)

    def save(self, path) -> None:
        """Write the HTML (opens offline: plotly.js is embedded), atomically."""
        from ..fileio import atomic_write_text

        atomic_write_text(path, self.html())


def bounds_frame(scenario, assumptions: Mapping | None = None) -> pd.DataFrame:
    """One row per bound, one column per mode (datasheet units), at the scenario's Tc."""
    from ..bounds import BOUND_FIELDS, compute_bounds
    from ..plots.bounds import BOUND_LABELS

    data = {"parameter": [BOUND_LABELS[k] for k in BOUND_FIELDS], "key": list(BOUND_FIELDS)}
    refused = {}
    for m in BOUND_MODES:
        try:  # the scenario's own assumptions (its platform_accel_m_s2), completed by the given ones
            a = scenario_mode_assumptions(m, scenario, assumptions)
        except InputError as err:  # platform_accel_m_s2 = 0: that mode's column is empty, and why
            data[m], refused[m] = [math.nan] * len(BOUND_FIELDS), str(err)
            continue
        t = compute_bounds(np.array([scenario.tc_s]), scenario.range_resolution_m, m,
                           wavelength_m=scenario.wavelength_m, assumptions=a)
        ds = t.datasheet()
        data[m] = [float(np.ravel(ds[k])[0]) for k in BOUND_FIELDS]
    frame = pd.DataFrame(data)
    frame.attrs["refused"] = refused
    return frame


def scenario_mode_assumptions(mode: str, scenario, assumptions: Mapping | None = None):
    """The assumptions the report computes ``mode``'s bounds with: the given ones for that mode,
    completed from the scenario (:func:`budget.bounds.scenario_assumptions`: its
    ``platform_accel_m_s2``, as ``sar-budget bounds --scenario`` and the check take it)."""
    from ..bounds import scenario_assumptions

    return scenario_assumptions(mode, scenario, (assumptions or {}).get(mode))


def provenance(trials: int | None, seed: int | None, options=None, extra: Mapping | None = None) -> dict:
    """Version, seed, trials, options and platform: what is needed to reproduce the numbers."""
    import numpy
    import scipy

    from .. import __version__

    out = {"sar_imu_budget_version": __version__, "created_utc": _dt.datetime.now(_dt.timezone.utc)
           .strftime("%Y-%m-%d %H:%M:%S"), "seed": seed, "trials": trials,
           "mc_options": None if options is None else options.model_dump(mode="json"),
           "python": platform.python_version(), "numpy": numpy.__version__, "scipy": scipy.__version__,
           "platform": platform.platform(terse=True)}
    out.update(extra or {})
    return out


def build_report(scenario, parts: Sequence | None = None, *, mc_parts: Sequence | None = None,
                 trials: int | None = None, seed: int | None = None, options=None, mode: str = "paper",
                 assumptions: Mapping | None = None, mc_results: Mapping | None = None,
                 progress: Callable[[str], Callable[[int, int], None] | None] | None = None,
                 catalog: Mapping | str | Path | None = None) -> Report:
    """Assemble a :class:`Report` for ``scenario`` (object or preset name).

    ``parts``: checked analytically (ids or objects; default the whole catalog); ids are looked up
    in ``catalog`` (a mapping, a user CSV merged over the shipped parts, or None: shipped,
    :func:`budget.catalog.io.as_catalog`). ``mc_parts``:
    parts run through the Monte Carlo (default: none unless ``mc_results`` are given);
    ``mc_results``: already computed ``{part_id: McResult}`` (not re-run). ``progress(part_id)``
    may return a ``progress(done, total)`` callback for each Monte Carlo run.
    """
    from ..api import load_part, load_parts, load_scenario
    from ..catalog.io import as_catalog, catalog_note
    from ..check import check_parts
    from ..mc.options import DEFAULT_SEED, DEFAULT_TRIALS, McOptions
    from ..mc.runner import run_mc

    s = load_scenario(scenario)
    if mode not in BOUND_MODES:
        raise InputError("unknown bounds mode", field="mode", value=mode, expected=", ".join(BOUND_MODES))
    cat = as_catalog(catalog)
    plist = list(cat.values()) if parts is None else load_parts(parts, cat)
    options = options or McOptions()
    motion = options.rotation_for_check if (mc_parts or mc_results) else None
    check = check_parts(plist, s, mode, (assumptions or {}).get(mode), platform_motion=motion)
    trials = DEFAULT_TRIALS if trials is None else trials
    seed = DEFAULT_SEED if seed is None else seed
    mc = dict(mc_results or {})
    for p in mc_parts or ():
        part = load_part(p, cat)
        pid = getattr(part, "part_id", None) or "model"
        if pid not in mc:
            cb = progress(pid) if progress else None
            mc[pid] = run_mc(s, part, trials, seed, options=options, progress=cb)
    if mc:
        first = next(iter(mc.values()))
        trials, seed = first.trials, first.seed
    recs = {r["part_id"]: r for r in check.to_dict()["scenarios"][0]["parts"]}
    comparisons = [check_vs_mc(recs.get(pid, {"part_id": pid, "verdict": "not checked"}), r)
                   for pid, r in mc.items()]
    # which rows come from a user catalog, above all one replacing a shipped part of the same id
    user = getattr(cat, "user_file", None)
    ids = list(dict.fromkeys([*check.part_ids, *mc]))
    origin = {"catalog": catalog_note(ids, user) if user is not None else "shipped"}
    rep = Report(scenario=s, mode=mode, bounds=bounds_frame(s, assumptions), check=check, mc=mc,
                 comparisons=comparisons, assumptions=assumptions,
                 provenance=provenance(trials if mc else None, seed if mc else None, options if mc else None,
                                       extra=origin))
    rep.figures = _figures(rep)
    return rep


def _figures(rep: Report) -> dict:
    from ..catalog.io import load_grades
    from ..plots.bounds import bounds_vs_tc_figure
    from ..plots.check import margin_heatmap_figure

    s = rep.scenario
    tc_range = (min(0.1, s.tc_s / 2), max(100.0, 2 * s.tc_s))
    modes = tuple(m for m in BOUND_MODES if m not in rep.bounds.attrs.get("refused", {}))
    figs = {"bounds vs Tc": bounds_vs_tc_figure(s.range_resolution_m, load_grades(), modes=modes,
                                                tc_range_s=tc_range, current_tc_s=s.tc_s,
                                                wavelength_m=s.wavelength_m,
                                                assumptions={m: scenario_mode_assumptions(m, s, rep.assumptions)
                                                             for m in modes}),
            "check margins": margin_heatmap_figure(rep.check)}
    if rep.mc:
        from ..plots.mc import pass_probability_figure

        figs["P(pass) before/after PGA"] = pass_probability_figure(rep.mc)
    return figs
