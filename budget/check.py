"""Check catalog parts against the Tc-driven bounds (the grade recommendation per Tc, on the same
margins, is :mod:`budget.recommend`).

Margin of a parameter = bound / spec (≥ 1 passes). The verdict of a part is ``pass`` when every
*specified* parameter has margin ≥ 1; unspecified (empty) datasheet values are listed in
``unspecified`` and never counted as passing or failing; a part with no specified parameter at
all gets the verdict ``unknown``. ``binding`` is the specified parameter
with the smallest margin.

Which spec meets which bound is the one parameter table :data:`budget.parameters.PARAMETERS`
(seed 004 Tables 1–4 compare the same quantities): scale factors with β_max, γ_max (6),
misalignments with φm + φn (7), the bias columns with b_a (8) and b_ω (9), VRW with n_a (10),
ARW with n_ω (11).

The bias columns are compared with the bias bounds as seed 004's Tables 3–4 do, in the row's
bias convention (:class:`~budget.catalog.schema.PartSpec`): an in-run Allan minimum as given,
an IEEE-952 B as its Allan minimum 0.664·B, a total or turn-on 1σ bias as given (the bounds
are for a constant bias, so that figure is the natural one). A separately given turn-on bias
(repeatability) is constant over the aperture too and is added in quadrature
(:meth:`PartSpec.bias_figure`): the Monte Carlo simulates it, so the check counts it.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from .bounds import BoundsTable, compute_bounds
from .catalog.fill import row_warnings
from .catalog.schema import PartSpec
from .errors import InputError, refuse_repeats
from .parameters import PARAMETERS
from .scenario import Scenario

#: Part columns checked, in margin order (from the parameter table).
PARAM_NAMES = tuple(p.column for p in PARAMETERS)


def spec_matrix(parts: Sequence[PartSpec]) -> np.ndarray:
    """(P, 8) SI specs in :data:`PARAM_NAMES` order; NaN where the datasheet gives no value.
    Bias columns in the row's convention (:meth:`PartSpec.bias_figure`)."""
    out = np.full((len(parts), len(PARAMETERS)), np.nan)
    for i, p in enumerate(parts):
        for j, prm in enumerate(PARAMETERS):
            v = p.bias_figure(prm.column) if prm.family == "bias" else getattr(p, prm.column)
            if v is not None:
                out[i, j] = float(v) * prm.to_si
    return out


def bound_matrix(bounds: BoundsTable) -> np.ndarray:
    """(S, 8) SI bounds in :data:`PARAM_NAMES` order for the S scenarios (Tc values) of ``bounds``."""
    cols = [np.ravel(np.asarray(getattr(bounds, prm.bound), dtype=float)) for prm in PARAMETERS]
    return np.stack(cols, axis=-1)


def margins(specs: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """(P, S, 8) margins bound/spec; +inf for a zero spec, NaN for an unspecified one."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return bounds[None, :, :] / specs[:, None, :]


@dataclass(frozen=True)
class CheckResult:
    """Margins of P parts against S scenarios (``margins`` shape (P, S, 8))."""

    part_ids: tuple[str, ...]
    grades: tuple[str, ...]
    scenario_names: tuple[str, ...]
    tc_s: np.ndarray
    margins: np.ndarray
    params: tuple[str, ...] = PARAM_NAMES
    bias_conventions: tuple[str, ...] = ()
    #: (P, S, 8) margins against the bounds tightened by what PGA cannot remove (fast phase and
    #: attitude error × lever arm, :func:`budget.bounds.lever_arm.pga_limited_bounds`), and per
    #: scenario the rule that tightens each SI bound field; None when not computed.
    pga_margins: np.ndarray | None = None
    pga_rules: tuple[dict, ...] = ()
    #: the bounds the margins were computed against (``paper`` | ``derived`` | ``no-autofocus``)
    mode: str = "paper"
    #: the bound assumptions (``model_dump`` of a ``DerivedAssumptions`` …); None for the defaults
    assumptions: dict | None = None
    #: (P, S) predicted rms (deg) of the true phase beyond PGA's window from the part's VRW and ARW
    #: (:func:`budget.bounds.fast_phase_residual`, weighted as the verdict images; seed 004's limit
    #: 1°); NaN when the part leaves either unspecified; None when not computed
    fast_phase_deg: np.ndarray | None = None
    #: (P, S) probability that one aperture's residual beyond PGA's window is within the limit
    #: (:meth:`budget.bounds.FastPhaseResidual.p_within_limit`: the rms above is over apertures,
    #: and one aperture's scatters about it); NaN where the rms is NaN; None when not computed
    fast_phase_p_within: np.ndarray | None = None
    #: per scenario, the limit (deg) on that combined residual: the PGA-limited verdict fails a part
    #: whose VRW and ARW each pass their own tightened bound but together exceed it
    fast_phase_limit_deg: tuple[float, ...] = ()
    #: per scenario, the share of apertures asked to be within that limit (None: its rms over
    #: apertures is held to it), and (P, S) the factor by which a part's VRW and ARW together could
    #: grow with that share still met (:meth:`budget.bounds.FastPhaseResidual.share_margin`: ≥ 1
    #: exactly when :attr:`fast_phase_p_within` ≥ the share); None when not computed
    fast_phase_share: tuple[float | None, ...] = ()
    fast_phase_margin: np.ndarray | None = None
    #: per scenario, the rotation the gyro scale factor and misalignment were judged against
    #: (:meth:`budget.bounds.rotation.RotationExcursion.to_dict`) when a platform motion was given;
    #: empty: the bounds' own assumption (seed 004: an attitude change of 1 rad)
    rotation: tuple[dict, ...] = ()
    #: per scenario, the scenario checked against (``Scenario.model_dump(mode="json")``: Tc, δr,
    #: λ, lever arm …), so that a result read later says what it was computed for
    scenarios: tuple[dict, ...] = ()
    #: per scenario, the scenario keys the check rests on that the scenario did not set, with the
    #: value taken (:meth:`Scenario.defaults_taken` of :func:`check_scenario_keys`), and the same
    #: in words (:meth:`Scenario.defaults_note`; '' when every key was set)
    scenario_defaults: tuple[dict, ...] = ()
    defaults_notes: tuple[str, ...] = ()
    #: per scenario, what it holds that the verdicts do not use as the file might suggest (a
    #: ``platform_accel_m_s2`` seed 004's bounds replace by g: :func:`budget.bounds.accel_level_note`)
    scenario_notes: tuple[tuple[str, ...], ...] = ()
    #: per part, what its row asks a reader to look at (:func:`budget.catalog.fill.row_warnings`:
    #: figures given as 0, figures of another grade than its grade column); () when nothing
    row_notes: tuple[tuple[str, ...], ...] = ()
    #: where the part ids were looked up (:func:`budget.mc.provenance.catalog_source`; None: not
    #: said), per part the figures checked (:func:`part_figures`) and their origin (:func:`part_origins`)
    catalog: str | None = None
    part_figures: tuple[dict, ...] = ()
    part_origins: tuple[str, ...] = ()
    #: (S, 8) True where the mode's bound does not constrain (:func:`unconstraining_bounds`: a
    #: misalignment bound capped at 90°, a scale-factor bound ≥ 100 % or not exercised): never
    #: named ``binding``, nor counted in ``min_margin``; None: every bound constrains
    unconstraining: np.ndarray | None = None

    def fast_phase(self, i: int, s: int) -> float:
        """Predicted rms (deg) beyond PGA's window of part ``i`` on scenario ``s`` (NaN: unknown)."""
        return float("nan") if self.fast_phase_deg is None else float(self.fast_phase_deg[i, s])

    def fast_phase_p(self, i: int, s: int) -> float:
        """Probability that one aperture of part ``i`` on scenario ``s`` leaves at most the limit
        beyond PGA's window (NaN: unknown)."""
        return float("nan") if self.fast_phase_p_within is None else float(self.fast_phase_p_within[i, s])

    def _share_margin(self, i: int, s: int) -> float:
        return float("nan") if self.fast_phase_margin is None else float(self.fast_phase_margin[i, s])

    def flag(self, i: int, s: int) -> tuple[bool, str | None]:
        """True (and why) when seed 004's verdict and the fast-phase / lever-arm verdict differ."""
        if self.pga_margins is None:
            return False, None
        spec = self.specified[i, s]
        if not spec.any():
            return False, None
        paper_ok = bool(self.passed[i, s])
        pm = np.where(spec, self.pga_margins[i, s], np.inf)
        mm, combined = self._pga_min_margin(i, s)
        pga_ok = mm >= 1.0
        if paper_ok == pga_ok:
            return False, None
        if paper_ok and combined:
            alone = "; ".join(f"{label} alone: margin {pm[PARAM_NAMES.index(col)]:.3g}"
                              for label, col in (("VRW", "accel_vrw_m_s_rt_h"), ("ARW", "gyro_arw_deg_rt_h"))
                              if col in PARAM_NAMES and np.isfinite(pm[PARAM_NAMES.index(col)]))
            return True, (f"passes the {self.mode} bounds (min margin {self.min_margin[i, s]:.3g}) but its VRW and "
                          f"ARW together leave {self.fast_phase(i, s):.3g}° rms beyond PGA's window "
                          f"({self._combined_words(i, s)}{'; ' + alone if alone else ''}): margin {mm:.3g}")
        j = int(np.argmin(pm))
        si = PARAMETERS[j].bound
        rule = (self.pga_rules[s] if s < len(self.pga_rules) else {}).get(si, "fast phase / lever arm")
        if paper_ok:
            return True, (f"passes the {self.mode} bounds (min margin {self.min_margin[i, s]:.3g}) but fails "
                          f"{self.params[j]} by {rule}: margin {pm[j]:.3g}")
        b = int(np.argmin(np.where(self.specified[i, s], self.margins[i, s], np.inf)))
        return True, (f"fails the {self.mode} bounds ({self.params[b]}: margin {self.min_margin[i, s]:.3g}) but "
                      f"passes seed 004's bounds tightened by fast phase and lever arm (min margin {mm:.3g})")

    def _pga_min_margin(self, i: int, s: int) -> tuple[float, bool]:
        """(min margin against the PGA-limited bounds and the combined fast-phase limit, True when
        the combined limit is the one that binds): :func:`pga_limited_margin`."""
        fp = self.fast_phase(i, s)
        combined = float("nan")
        if s < len(self.fast_phase_limit_deg) and np.isfinite(fp) and fp > 0:
            combined = (float(self.fast_phase_margin[i, s]) if self.fast_phase_margin is not None
                        else self.fast_phase_limit_deg[s] / fp)
        return pga_limited_margin(self.pga_margins[i, s], combined)

    def _combined_words(self, i: int, s: int) -> str:
        """The combined fast-phase limit in words: the limit and, when asked, the share."""
        share = self.fast_phase_share[s] if s < len(self.fast_phase_share) else None
        if share is None:
            return f"limit {self.fast_phase_limit_deg[s]:g}° rms"
        return (f"{self.fast_phase_p(i, s):.3g} of apertures within {self.fast_phase_limit_deg[s]:g}°, "
                f"{share:g} asked")

    def pga_limited(self, i: int, s: int) -> tuple[str, float]:
        """(verdict, min margin) against seed 004's bounds tightened by what PGA cannot remove
        (:func:`budget.bounds.lever_arm.pga_limited_bounds`) and against the limit on VRW and ARW
        together (their combined rms beyond PGA's window, :attr:`fast_phase_deg`, at most
        :attr:`fast_phase_limit_deg`: each term's tightened bound spends the whole limit on that
        term alone); ("unknown", nan) when not computed or nothing is specified."""
        spec = self.specified[i, s]
        if self.pga_margins is None or not spec.any():
            return "unknown", float("nan")
        mm, _ = self._pga_min_margin(i, s)
        return ("pass" if mm >= 1.0 else "fail"), mm

    @property
    def specified(self) -> np.ndarray:
        return ~np.isnan(self.margins)

    @property
    def passed(self) -> np.ndarray:
        """(P, S) True where every specified parameter has margin ≥ 1."""
        m = np.where(self.specified, self.margins, np.inf)
        return np.all(m >= 1.0, axis=-1)

    @property
    def _constraining(self) -> np.ndarray:  # (P, S, 8) specified terms whose bound constrains
        return self.specified & ~(False if self.unconstraining is None else self.unconstraining[None])

    @property
    def min_margin(self) -> np.ndarray:
        """(P, S) smallest margin over the specified terms whose bound constrains (:attr:`unconstraining`);
        NaN where none is specified (verdict "unknown", as :meth:`pga_limited`'s), ∞ where only
        non-constraining bounds are."""
        m = np.min(np.where(self._constraining, self.margins, np.inf), axis=-1)
        return np.where(self.specified.any(axis=-1), m, np.nan)

    @property
    def binding_index(self) -> np.ndarray:
        """(P, S) index of the binding term: the smallest margin of a constraining bound."""
        return np.argmin(np.where(self._constraining, self.margins, np.inf), axis=-1)

    def binding(self, i: int, s: int) -> str | None:
        """The binding term of part ``i`` on scenario ``s``; None where nothing is specified or
        every specified term's bound does not constrain (:attr:`unconstraining`)."""
        return self.params[int(self.binding_index[i, s])] if self._constraining[i, s].any() else None

    def _part_records(self, scenario_index: int = 0) -> list[dict]:
        """Per-part dicts for one scenario: ``part_id, grade, verdict, binding, margins, unspecified``."""
        out = []
        for i, pid in enumerate(self.part_ids):
            m = self.margins[i, scenario_index]
            flagged, why = self.flag(i, scenario_index)
            limited, limited_margin = self.pga_limited(i, scenario_index)
            spec = ~np.isnan(m)
            out.append({
                "part_id": pid,
                "grade": self.grades[i],
                "verdict": ("unknown" if not spec.any() else
                            "pass" if self.passed[i, scenario_index] else "fail"),
                "binding": self.binding(i, scenario_index),
                "margins": {p: float(m[j]) for j, p in enumerate(self.params) if spec[j]},
                "unspecified": [p for j, p in enumerate(self.params) if not spec[j]],
                "bias_convention": self.bias_conventions[i] if self.bias_conventions else None,
                "row_notes": list(self.row_notes[i]) if self.row_notes else [],
                "flag": flagged,
                "flag_reason": why,
                "pga_limited_verdict": limited,
                "pga_limited_min_margin": limited_margin,
                "fast_phase_residual_deg": self.fast_phase(i, scenario_index),
                "fast_phase_p_within_limit": self.fast_phase_p(i, scenario_index),
                "fast_phase_share_margin": self._share_margin(i, scenario_index),
            })
        return out

    def to_dict(self) -> dict:
        """JSON-ready: the bounds ``mode``, the checked ``params`` and per scenario (``name``, ``tc_s``,
        the whole ``scenario``) one record per part under ``parts`` (``part_id, grade, verdict, binding, margins`` as
        bound/spec, ``unspecified``, ``bias_convention``, ``flag``, ``flag_reason``,
        ``pga_limited_verdict``, ``pga_limited_min_margin``: :meth:`pga_limited`;
        ``fast_phase_residual_deg``: :meth:`fast_phase`; ``fast_phase_p_within_limit``:
        :meth:`fast_phase_p`; ``fast_phase_share_margin``: :attr:`fast_phase_margin`), with the
        scenario's ``fast_phase_limit_deg`` and ``fast_phase_share``; ``catalog`` (where the ids were
        looked up) and ``part_figures`` (per part: ``part_id``, ``figures`` in datasheet units,
        their ``digest`` and ``origin``, :mod:`budget.mc.provenance`)."""
        return {"mode": self.mode, "assumptions": self.assumptions, "params": list(self.params),
                "catalog": self.catalog, "part_figures": self._figures(),
                "scenarios": [{"name": name, "tc_s": float(tc), "parts": self._part_records(s),
                               "rotation": self.rotation[s] if self.rotation else None,
                               "scenario": self.scenarios[s] if self.scenarios else None,
                               "scenario_defaults": (self.scenario_defaults[s] if self.scenario_defaults
                                                     else None),
                               "notes": list(self.scenario_notes[s]) if self.scenario_notes else [],
                               "fast_phase_limit_deg": (self.fast_phase_limit_deg[s]
                                                        if s < len(self.fast_phase_limit_deg) else None),
                               "fast_phase_share": self.fast_phase_share[s] if s < len(self.fast_phase_share) else None}
                              for s, (name, tc) in enumerate(zip(self.scenario_names, np.ravel(self.tc_s)))]}

    def _figures(self) -> list[dict]:
        return [{"part_id": i, "figures": f, "digest": figures_digest(f), "origin": o} for i, f, o in
                zip(self.part_ids, self.part_figures, self.part_origins or [None] * len(self.part_ids))]

    def to_frame(self) -> pd.DataFrame:
        """Tidy table: one row per part × scenario with the margins and the verdict.

        ``margin_<column>`` is bound/spec for the catalog column ``<column>`` — a dimensionless
        ratio (pass at ≥ 1), named by the datasheet column it compares, whose unit suffix is that
        column's, not the margin's (``attrs["margin_columns"]`` says so); ``part_digest`` names the
        figures checked (:meth:`to_dict`'s ``part_figures``), ``attrs["catalog"]`` the catalog."""
        P, S, _ = self.margins.shape
        idx = pd.MultiIndex.from_product([range(P), range(S)], names=["p", "s"])
        df = pd.DataFrame(self.margins.reshape(P * S, -1), columns=[f"margin_{p}" for p in self.params],
                          index=idx).reset_index()
        df.insert(0, "part_id", [self.part_ids[p] for p in df["p"]])
        df.insert(1, "grade", [self.grades[p] for p in df["p"]])
        df.insert(2, "scenario", [self.scenario_names[s] for s in df["s"]])
        df.insert(3, "tc_s", [float(np.ravel(self.tc_s)[s]) for s in df["s"]])
        any_spec = self.specified.any(axis=-1).reshape(-1)
        df["verdict"] = np.where(~any_spec, "unknown", np.where(self.passed.reshape(-1), "pass", "fail"))
        # no specified term: no binding one (None, as in to_dict and '-' in summary)
        df["binding"] = [self.binding(int(p), int(s)) for p, s in zip(df["p"], df["s"])]
        df["min_margin"] = self.min_margin.reshape(-1)
        flags = [self.flag(int(p), int(s)) for p, s in zip(df["p"], df["s"])]
        df["flag"] = [f for f, _ in flags]
        df["flag_reason"] = [r for _, r in flags]
        limited = [self.pga_limited(int(p), int(s)) for p, s in zip(df["p"], df["s"])]
        df["pga_limited_verdict"] = [v for v, _ in limited]
        df["pga_limited_min_margin"] = [m for _, m in limited]
        df["fast_phase_residual_deg"] = [self.fast_phase(int(p), int(s)) for p, s in zip(df["p"], df["s"])]
        df["fast_phase_p_within_limit"] = [self.fast_phase_p(int(p), int(s)) for p, s in zip(df["p"], df["s"])]
        df["fast_phase_share_margin"] = [self._share_margin(int(p), int(s)) for p, s in zip(df["p"], df["s"])]
        if self.part_figures:
            df["part_digest"] = [d["digest"] for d in self._figures() for _ in range(S)]
        df.attrs.update({"catalog": self.catalog, "margin_columns": "margin_<column> = bound / spec of the "
                         "catalog column <column>: dimensionless (≥ 1 passes); the unit suffix is the column's"})
        return df.drop(columns=["p", "s"])

    def summary(self, scenario_index: int | None = None) -> str:
        """The verdict against the ``mode`` bounds, beside the PGA-limited one (fast phase and
        lever arm); every disagreement is explained below the table. Every scenario, each under
        a header naming it (``scenario_index``: that scenario only, its header saying how many
        others there are): :func:`budget.check_text.check_summary`."""
        from .check_text import check_summary

        return check_summary(self, scenario_index)


def pga_limited_margin(term_margins: np.ndarray, combined_margin: float) -> tuple[float, bool]:
    """The PGA-limited verdict's margin (pass at ≥ 1): the smallest of the per-term margins against
    the PGA-limited bounds (bound/spec, NaN = unspecified, left out) and the combined fast-phase
    share margin of VRW and ARW together (:meth:`budget.bounds.FastPhaseResidual.share_margin`;
    NaN = not computable, left out), and True when the combined one is the smallest. The one
    criterion of :meth:`CheckResult.pga_limited` and of the PGA-limited grade recommendation
    (:func:`budget.recommend.recommend_grade` with ``scenario``)."""
    m = np.asarray(term_margins, dtype=float)
    mm = float(np.min(np.where(np.isnan(m), np.inf, m))) if m.size else float("inf")
    if np.isfinite(combined_margin) and combined_margin < mm:
        return float(combined_margin), True
    return mm, False


def fast_phase_matrix(parts: Sequence[PartSpec], scen: Sequence[Scenario],
                       limited_assumptions: Sequence) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(P, S) :func:`budget.bounds.fast_phase_residual` totals (deg), their probabilities of one
    aperture within the limit and their share margins, NaN where a part leaves its VRW or ARW
    unspecified (a zero there would understate it)."""
    from .bounds import scenario_fast_phase

    out = np.full((len(parts), len(scen)), np.nan)
    prob = np.full_like(out, np.nan)
    margin = np.full_like(out, np.nan)
    for i, p in enumerate(parts):
        if p.accel_vrw_m_s_rt_h is None or p.gyro_arw_deg_rt_h is None:
            continue
        si = PartSpec.to_si(p)  # the catalog row's SI errors (a NoiseModel's to_si adds its effects)
        for s, (sc, a) in enumerate(zip(scen, limited_assumptions)):
            fr = scenario_fast_phase(sc, si, a)
            out[i, s], prob[i, s], margin[i, s] = fr.total_deg, fr.p_within_limit(), fr.share_margin()
    return out, prob, margin


def _apply_rotation(bmat: np.ndarray, pmat: np.ndarray, scen: Sequence[Scenario], mode: str, assumptions,
                    platform_motion, lever: Sequence) -> tuple[dict, ...]:
    """Rescale, in place, the gyro scale-factor and gyro misalignment bounds of every scenario to
    the rotation ``platform_motion`` flies (:meth:`budget.bounds.rotation.RotationExcursion.bounds`):
    the mode's γ bound, written for an attitude change Θ_ref (seed 004: 1 rad;
    ``attitude_excursion_rad`` of the derived and no-autofocus assumptions), times Θ_ref/Θ_eq; a
    gyro misalignment leaks rotation into another axis as a scale factor does into its own, so its
    bound is the γ bound times Θ_ref/Θ_eq(misalignment) — not the misalignment bound of the
    straight-flight check (seed 004 (7), a full range cell where γ has half). In the PGA-limited
    matrix the lever-arm limit of both becomes δr/(|d|·Θ_peak), Θ_peak the largest attitude change
    flown. Returns the excursions' dicts, each with ``<term>_bound_change``: the factor by which
    the check's bound of the term moved (new ÷ the mode's own)."""
    from .bounds import paper_bounds, scenario_assumptions
    from .bounds.rotation import motion_excursion

    j_sf, j_gm = PARAM_NAMES.index("gyro_scale_factor_ppm"), PARAM_NAMES.index("gyro_misalignment_mrad")
    lever_mode = mode in ("lever-arm", "lever_arm")
    out = []
    for s, (sc, la) in enumerate(zip(scen, lever)):
        used = None if lever_mode else scenario_assumptions(mode, sc, assumptions)
        ref = float(getattr(used, "attitude_excursion_rad", 1.0))
        exc = motion_excursion(platform_motion, sc, reference_rad=ref)
        # the lever-arm mode's γ bound already holds its own 1-rad lever-arm limit: start from seed 004's
        gamma = (float(paper_bounds(sc.tc_s, sc.range_resolution_m).gyro_scale_factor[0]) if lever_mode
                 else bmat[s, j_sf])
        d = la.lever_m
        by_turn = sc.range_resolution_m / (d * exc.peak_tilt_rad) if d > 0 and exc.peak_tilt_rad > 0 else np.inf
        rec = exc.to_dict()
        for j, (term, bound) in zip((j_sf, j_gm), exc.bounds(gamma).items()):
            before = bmat[s, j]
            bmat[s, j] = bound
            pmat[s, j] = min(bmat[s, j], by_turn)
            if lever_mode:
                bmat[s, j] = pmat[s, j]
            rec[f"{term}_bound_change"] = float(bmat[s, j] / before) if before > 0 else np.inf
        out.append(rec)
    return tuple(out)


def check_scenario_keys(mode: str = "paper", platform_motion=None) -> tuple[str, ...]:
    """The defaulted scenario keys (:data:`budget.scenario.DEFAULTED_KEYS`) a check in ``mode``
    rests on: its bounds' (:func:`budget.bounds.scenario_keys`), the line of sight and lever arm
    of the PGA-limited verdict, and the turn rate an ``oscillation`` platform motion flies."""
    from .bounds import scenario_keys

    keys = scenario_keys(mode) + ("depression_deg", "lever_arm_m")
    kind = getattr(platform_motion, "kind", platform_motion)
    if kind == "oscillation":
        keys += ("platform_rate_deg_s",)
    return tuple(dict.fromkeys(keys))


#: Most part × scenario pairs one check takes (:func:`check_parts`; the shipped catalog has 20 parts).
MAX_CHECKS = 10_000


def check_parts(parts: Iterable[PartSpec], scenarios: Sequence[Scenario] | Scenario,
                mode: str = "paper", assumptions=None, platform_motion=None, *, catalog: str | None = None,
                sources: Sequence | None = None) -> CheckResult:
    """Check parts against each scenario's bounds (Tc and δr from the scenario).

    ``platform_motion`` (a :class:`~budget.nav.manoeuvre.PlatformMotion` or its dict): judge the
    gyro scale factor and gyro misalignment against the rotation the platform flies over each
    aperture, as the Monte Carlo flies it (:func:`_apply_rotation`), instead of the bounds' own
    1-rad attitude change; None keeps the bounds as they are. ``catalog``: where the part ids were
    looked up, in words (recorded); ``sources``: the file of each scenario (None: preset or
    object), to name them when two different scenarios share a name (refused, as the sweep does:
    :func:`budget.scenario_errors.refuse_shared_names`). A bound that does not constrain is not named binding; the
    scenario's own notes (:meth:`Scenario.notes`) and the bounds' limit notes are in
    ``scenario_notes``."""
    parts = list(parts)
    scen = [scenarios] if isinstance(scenarios, Scenario) else list(scenarios)
    if not parts or not scen:
        what = "part" if not parts else "scenario"
        raise InputError(f"no {what} to check", field=f"{what}s",
                         expected=f"at least one {what}")
    refuse_repeats(parts, lambda p: getattr(p, "part_id", None), field="parts", what="part")
    from .scenario_errors import refuse_shared_names
    refuse_shared_names(list(zip(scen, sources or [None] * len(scen))), "check's rows")
    if len(parts) * len(scen) > MAX_CHECKS:
        # the exact share of apertures within the fast-phase limit (an eigen-decomposition and a
        # quadrature per part with VRW and ARW) costs ≈ 0.05–0.2 s per part and scenario: a
        # 200,000-row user catalog ran for hours with nothing said
        raise InputError(f"{len(parts):,} parts × {len(scen)} scenario(s) to check, more than {MAX_CHECKS:,} "
                         f"(≈ 0.05–0.2 s each: about {len(parts) * len(scen) * 0.1 / 3600:.2g} h)", field="parts",
                         value=len(parts), expected=f"at most {MAX_CHECKS:,} part × scenario pairs: the parts of "
                         "interest (--part ID ID …), or a smaller user catalog")
    tc = np.array([s.tc_s for s in scen])
    dr = np.array([s.range_resolution_m for s in scen])
    from .bounds import check_bounds_tc
    check_bounds_tc(tc, field="tc_s (derived)")  # the bounds' free-inertial, flat-earth growth
    if mode in ("no-autofocus", "no_autofocus", "derived", "lever-arm", "lever_arm"):
        # per scenario: λ, the acceleration level, the lever arm and turn rate
        from .bounds import scenario_assumptions
        rows = [bound_matrix(compute_bounds(t, d, mode, wavelength_m=s.wavelength_m,
                                            assumptions=scenario_assumptions(mode, s, assumptions)))[0]
                for t, d, s in zip(tc, dr, scen)]
        bmat = np.array(rows)
    else:
        bmat = bound_matrix(compute_bounds(tc, dr, mode, assumptions=assumptions))
    # the analytic verdict beside seed 004's: fast phase and lever arm (flag where they differ)
    from .bounds.lever_arm import LeverArmAssumptions, pga_limited_bounds
    assumed = [LeverArmAssumptions.from_scenario(s) for s in scen]
    limited = [pga_limited_bounds(s, a) for s, a in zip(scen, assumed)]
    pmat = np.array([bound_matrix(t)[0] for t, _ in limited])
    rotation: tuple[dict, ...] = ()
    if platform_motion is not None:
        rotation = _apply_rotation(bmat, pmat, scen, mode, assumptions, _platform_motion(platform_motion), assumed)
    specs = spec_matrix(parts)
    free = unconstraining_bounds(bmat)
    keys = check_scenario_keys(mode, _platform_motion(platform_motion) if platform_motion is not None else None)
    fast_deg, fast_p, fast_margin = fast_phase_matrix(parts, scen, assumed)
    return CheckResult(tuple(p.part_id for p in parts), tuple(p.grade for p in parts),
                       tuple(s.name for s in scen), tc, margins(specs, bmat),
                       bias_conventions=tuple(p.bias_instability_convention for p in parts),
                       pga_margins=margins(specs, pmat), pga_rules=tuple(r for _, r in limited), mode=mode,
                       assumptions=assumptions_dict(assumptions),
                       fast_phase_deg=fast_deg, fast_phase_p_within=fast_p,
                       fast_phase_limit_deg=tuple(float(a.fast_residual_limit_deg) for a in assumed),
                       fast_phase_share=tuple(a.fast_residual_share for a in assumed), fast_phase_margin=fast_margin,
                       rotation=rotation, scenarios=tuple(sc.model_dump(mode="json") for sc in scen),
                       scenario_defaults=tuple(sc.defaults_taken(keys) for sc in scen),
                       defaults_notes=tuple(sc.defaults_note(keys) for sc in scen),
                       scenario_notes=tuple(_scenario_notes(sc, mode, assumptions) + _limit_notes(bmat[s], free[s])
                                            for s, sc in enumerate(scen)),
                       row_notes=_row_notes(parts), catalog=catalog, unconstraining=free,
                       part_figures=tuple(part_figures(p) for p in parts), part_origins=part_origins(parts))


def _scenario_notes(scenario: Scenario, mode: str, assumptions) -> tuple[str, ...]:
    """The scenario's own notes (:meth:`Scenario.notes`: what its numbers hold that the tool does not
    model, e.g. a spaceborne speed) and what it holds that the check's verdicts (``mode``'s and the
    PGA-limited one beside it) do not use as the file might suggest (:func:`budget.bounds.accel_level_note`)."""
    from .bounds import accel_level_note

    note = accel_level_note(scenario, mode, assumptions, pga_limited=True)
    return tuple(scenario.notes()) + ((note,) if note else ())


def part_figures(part) -> dict:
    """What a verdict rests on of a catalog row, JSON-ready: ``grade``, bias convention and every
    numeric column given (datasheet units; empty ones left out); a noise model's own dump."""
    from .catalog.schema import PART_NUMERIC_COLUMNS

    if not isinstance(part, PartSpec):
        return part.to_dict() if hasattr(part, "to_dict") else {}
    return {"grade": part.grade, "bias_instability_convention": part.bias_instability_convention,
            **{k: float(getattr(part, k)) for k in PART_NUMERIC_COLUMNS if getattr(part, k) is not None}}


def figures_digest(figures: dict) -> str:
    """12 hex digits of SHA-256 over ``figures`` (sorted keys): equal digests, equal figures."""
    return hashlib.sha256(json.dumps(figures, sort_keys=True, default=str).encode()).hexdigest()[:12]


def part_origins(parts) -> tuple[str, ...]:
    """Per part: "shipped" (the shipped row, same figures), "user row replacing the shipped one" (a
    shipped id, other figures), "not in the shipped catalog" or "noise model"."""
    from .catalog.io import read_parts, shipped_catalog_dir
    shipped = read_parts(shipped_catalog_dir() / "parts.csv")
    return tuple("noise model" if not isinstance(p, PartSpec) else "not in the shipped catalog"
                 if p.part_id not in shipped else "shipped" if part_figures(shipped[p.part_id]) == part_figures(p)
                 else "user row replacing the shipped one" for p in parts)


def unconstraining_bounds(bmat: np.ndarray) -> np.ndarray:
    """(S, 8) True where a bound (SI, :func:`bound_matrix` order) does not constrain any sensor, as
    :meth:`budget.bounds.BoundsTable.limit_notes` says: a misalignment bound capped at 90° (seed 004
    (7)'s arcsin argument reaches 1) or a scale-factor bound of 100 % or more (∞: not exercised)."""
    fam = np.array([p.family for p in PARAMETERS])
    return (((fam == "misalignment") & (bmat >= np.pi / 2 * (1 - 1e-12)))
            | ((fam == "scale_factor") & (bmat >= 1.0)))


def _limit_notes(bounds_si: np.ndarray, free: np.ndarray) -> tuple[str, ...]:
    """One line per bound of one scenario that does not constrain (:func:`unconstraining_bounds`)."""
    def why(prm, v: float) -> str:
        return ("capped at 90°: its arcsin argument reaches 1, so any misalignment meets it" if prm.family ==
                "misalignment" else "not exercised (infinite)" if not np.isfinite(v) else "≥ 100 %: no real sensor nears it")
    return tuple(f"{p.label.split(' (')[0]} bound {v:.4g} {p.bound_unit} {why(p, v)} — it does not constrain and is "
                 "not named binding" for p, v in ((PARAMETERS[j], bounds_si[j] / PARAMETERS[j].bound_to_si)
                                                  for j in np.flatnonzero(free)))


def _row_notes(parts: Sequence[PartSpec]) -> tuple[tuple[str, ...], ...]:
    """:func:`budget.catalog.fill.row_warnings` of each part, the grades table read once."""
    from .catalog.io import load_grades

    grades = load_grades()
    return tuple(row_warnings(p, grades) for p in parts)


def _platform_motion(value):
    """A :class:`~budget.nav.manoeuvre.PlatformMotion` from itself or its dict; a bad one raises
    :class:`InputError` naming the field."""
    from pydantic import ValidationError

    from .errors import from_validation_error
    from .nav.manoeuvre import PlatformMotion
    try:
        return PlatformMotion.model_validate(value)
    except ValidationError as err:
        raise from_validation_error(err) from None


def assumptions_dict(assumptions) -> dict | None:
    """JSON-ready form of bound assumptions (a pydantic model or a mapping); None stays None."""
    if assumptions is None:
        return None
    return assumptions.model_dump(mode="json") if hasattr(assumptions, "model_dump") else dict(assumptions)


def check_arrays(specs: np.ndarray, tc_s: np.ndarray, range_resolution_m: np.ndarray,
                 mode: str = "paper") -> tuple[np.ndarray, np.ndarray]:
    """Vectorised core for trade studies: (P, 8) SI specs × S scenarios → (pass (P, S), min margin)."""
    bmat = bound_matrix(compute_bounds(tc_s, range_resolution_m, mode))
    m = margins(specs, bmat)
    m = np.where(np.isnan(m), np.inf, m)
    mm = m.min(axis=-1)
    return mm >= 1.0, mm


def __getattr__(name: str):
    if name == "rotation_line":  # lives with the check's text (budget.check_text); imported from here too
        from .check_text import rotation_line
        return rotation_line
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
