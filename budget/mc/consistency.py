"""Monte Carlo against the analytic bounds: one error term at a multiple of its paper bound.

For a term (accel bias, gyro bias, VRW, ARW — the default four; also the accelerometer and gyro
scale factors and misalignments) a synthetic part carries only that term, at ``scale`` × the
seed 004 bound for the scenario's Tc and δr (6)–(11). Scale factors and misalignments act on the
true rate and specific force: the accelerometer's on gravity in any flight, the gyro's only when
the platform rotates (``McOptions.platform_motion``, :mod:`budget.nav.manoeuvre`), so those two
terms are refused in straight flight rather than reported as passing at every scale. The table reports
P(pass after PGA) per scale and the scale at which it crosses 50 %: a crossing near 1 means the
bound and the simulation agree; far from 1 says by how much they differ and in which direction.

The crossing comes from a probit fit P(pass) = Φ(a + b·log10 s) to the pass counts of every
scale (binomial GLM, statsmodels), over a fine grid (default 0.1…10×, 8 points per decade):
s50 = 10^(−a/b), with a 95 % interval from the delta method on −a/b. When the counts separate
perfectly (no scale with both passes and failures) the fit has no finite slope: the crossing is
then bracketed by the last scale that always passes and the first that always fails, and the
interval is that bracket (``crossing_method`` says which).
"""

from __future__ import annotations

import math
import numbers
import warnings
from collections.abc import Callable, Sequence
from typing import NamedTuple

import numpy as np
import pandas as pd
from pydantic import ValidationError
from scipy.stats import norm

from ..bounds import paper_bounds
from ..errors import InputError
from ..imu.noise_model import NoiseModel
from ..scenario import Scenario
from ..units import ug_rt_hz_to_m_s_rt_h
from .options import McOptions
from .runner import run_mc

class Term(NamedTuple):
    """One error term of the table: the :class:`~budget.imu.noise_model.NoiseModel` field that
    carries it, its paper-bound key in datasheet units (:meth:`budget.bounds.BoundsTable.datasheet`),
    the conversion from that unit to the field's, and its SI field of
    :class:`~budget.bounds.BoundsTable` (None: no PGA-limited rule tightens it; the lever-arm
    misalignment rule is the gyro's, attitude error × lever arm)."""

    model_field: str
    bound_key: str
    to_field: Callable[[float], float]
    bound_si_field: str | None


def _same(x: float) -> float:
    return x


#: term → :class:`Term`
TERMS = {
    "accel_bias": Term("accel_bias_repeatability_ug", "accel_bias_ug", _same, "accel_bias_m_s2"),
    "gyro_bias": Term("gyro_bias_repeatability_deg_h", "gyro_bias_deg_h", _same, "gyro_bias_rad_s"),
    "accel_vrw": Term("accel_vrw_m_s_rt_h", "accel_vrw_ug_rt_hz", ug_rt_hz_to_m_s_rt_h, "accel_vrw_m_s2_rt_hz"),
    "gyro_arw": Term("gyro_arw_deg_rt_h", "gyro_arw_deg_rt_h", _same, "gyro_arw_rad_s_rt_hz"),
    "accel_scale_factor": Term("accel_scale_factor_ppm", "accel_scale_factor_ppm", _same, "accel_scale_factor"),
    "accel_misalignment": Term("accel_misalignment_mrad", "misalignment_mrad", _same, None),
    "gyro_scale_factor": Term("gyro_scale_factor_ppm", "gyro_scale_factor_ppm", _same, "gyro_scale_factor"),
    "gyro_misalignment": Term("gyro_misalignment_mrad", "misalignment_mrad", _same, "misalignment_rad"),
}
#: The table's default terms: the four seed 004 budgets for straight flight with PGA.
DEFAULT_TERMS = ("accel_bias", "gyro_bias", "accel_vrw", "gyro_arw")
#: Terms that act only on a rotating platform (the gyro sees no rate in straight, level flight).
ROTATION_TERMS = ("gyro_scale_factor", "gyro_misalignment")


def single_term_model(scenario: Scenario, term: str, scale: float) -> NoiseModel:
    """A model with only ``term`` at ``scale`` × its paper bound. Biases are turn-on biases
    (a constant drawn per trial, 1σ = the value), the constant bias of seed 004 (8)–(9); scale
    factors and misalignments are drawn per trial and axis with 1σ = the value, like a part's
    datasheet figure."""
    if term not in TERMS:
        raise InputError("unknown error term", field="terms", value=term, expected=", ".join(TERMS))
    field, key, to_field, _ = TERMS[term]
    bound = float(paper_bounds(scenario.tc_s, scenario.range_resolution_m).datasheet()[key][0])
    try:
        return NoiseModel(part_id=f"{term}_x{scale:g}", grade="tactical", source="synthetic",
                          **{field: to_field(scale * bound)})
    except ValidationError as err:
        # on a short aperture (automotive, Tc ≈ 0.1 s) 10× a paper bound can exceed any IMU the
        # noise model accepts (e.g. gyro bias > 10⁶ deg/h): say so, with the bound behind it
        first = err.errors(include_url=False)[0]
        raise InputError(f"{term} at {scale:g}× its paper bound for Tc = {scenario.tc_s:.3g} s is beyond "
                         f"what a noise model accepts: {first.get('msg', 'invalid value')}",
                         field=field, value=to_field(scale * bound),
                         expected="a smaller scale (the paper bound itself is "
                                  f"{to_field(bound):.4g} in the field's unit)") from None


def pga_limited_scale(scenario: Scenario, term: str) -> tuple[float, str]:
    """The PGA-limited bound of ``term`` (:func:`budget.bounds.lever_arm.pga_limited_bounds`:
    seed 004's bound tightened by the lever arm and by what PGA's window cannot see) as a
    multiple of its paper bound, and the rule that tightens it ('' when the paper bound stands).
    For a noise term it is where the fast phase starts to fail apertures: the share within the
    limit is 0.9 there (the bounds' ``fast_residual_share``), so the Monte Carlo's P(pass) should
    still be ≈ 0.9 or more at this scale and cross 0.5 above it (:func:`fast_phase_crossing`); a
    crossing well below 1 that this scale also predicts is explained by that rule."""
    from ..bounds.lever_arm import pga_limited_bounds

    if term not in TERMS:
        raise InputError("unknown error term", field="terms", value=term, expected=", ".join(TERMS))
    si = TERMS[term].bound_si_field
    if si is None:
        return 1.0, ""
    table, rules = pga_limited_bounds(scenario)
    paper = paper_bounds(scenario.tc_s, scenario.range_resolution_m)
    ratio = float(np.asarray(getattr(table, si))[0] / np.asarray(getattr(paper, si))[0])
    return ratio, (rules.get(si, "") if ratio < 1.0 else "")


def fast_phase_share(scenario: Scenario, model) -> float:
    """The analytic share of apertures whose residual beyond PGA's window stays within the
    fast-phase limit for ``model`` on ``scenario`` (its empty terms taken as zero; the check's K,
    window and limit, :meth:`budget.bounds.LeverArmAssumptions.from_scenario`;
    :meth:`budget.bounds.FastPhaseResidual.p_within_limit`): 1 for a model with no VRW or ARW.
    Every trial of the Monte Carlo fails that is beyond it, so it is the ceiling of P(pass) that
    the fast phase alone allows — where PGA's fast-phase stage keeps no band (the realistic scene)."""
    from ..bounds import scenario_fast_phase
    from ..catalog.fill import resolve_unspecified

    return scenario_fast_phase(scenario, resolve_unspecified(model, "zero").model.to_si()).p_within_limit()


def fast_phase_crossing(scenario: Scenario, term: str) -> float:
    """The scale (× the paper bound) of ``term`` alone at which :func:`fast_phase_share` is 0.5:
    the analytic crossing of a noise term's P(pass) where the fast phase is what fails it; inf for
    a term that leaves no random walk (the biases, scale factors, misalignments)."""
    from ..bounds import scenario_fast_phase
    from ..catalog.fill import resolve_unspecified
    from ..quadform import quadratic_form_quantile_imhof

    one = scenario_fast_phase(scenario, resolve_unspecified(single_term_model(scenario, term, 1.0),
                                                            "zero").model.to_si())
    if one.total_deg <= 0:
        return math.inf
    # every source scales with the term: the scale s where the limit is the median of s²·Q
    return float(one.limit_deg / math.sqrt(quadratic_form_quantile_imhof(one.eigenvalues(), 0.5)))


#: Default grid: 0.1× … 10× the paper bound, 8 points per decade (17 scales).
FINE_SCALES = np.logspace(-1.0, 1.0, 17)


def consistency_table(scenario: Scenario, terms: Sequence[str] = DEFAULT_TERMS,
                      scales: Sequence[float] = tuple(FINE_SCALES), trials: int = 64, seed: int = 0,
                      options: McOptions | None = None, workers: int = 1) -> pd.DataFrame:
    """P(pass after PGA) per term and scale, with the 50 % crossing scale per term (probit fit,
    95 % interval ``crossing_lo`` … ``crossing_hi``; see the module docstring). A scale whose
    model no noise model accepts (10× a paper bound on a short aperture can ask for a gyro bias
    above 10⁶ deg/h) is not simulated: its row has ``simulated`` False, P = NaN and a ``note``
    saying why, and the crossing is fitted over the other scales (``crossing_method`` says so).
    ``pga_limited_scale`` is the analytic PGA-limited bound of the term in multiples of its paper
    bound and ``pga_limited_rule`` what tightens it (:func:`pga_limited_scale`): where the crossing
    lies well below 1, a scale there says why (e.g. ARW × the lever arm on ``airborne_xband``).
    ``fast_phase_share``: per scale, the analytic share of apertures within the fast-phase limit
    (:func:`fast_phase_share`, the ceiling the fast phase puts on P(pass)), and
    ``fast_phase_crossing``: the scale where that share is 0.5 (:func:`fast_phase_crossing`; inf
    for a term that leaves no random walk)."""
    if not isinstance(scenario, Scenario):
        raise InputError(f"cannot use a {type(scenario).__name__} as the scenario", field="scenario",
                         value=scenario, expected="a Scenario (budget.consistency_table also takes a "
                                                  "preset name or a scenario file)")
    terms = [terms] if isinstance(terms, str) else list(terms)
    if not terms:
        raise InputError("no error term to check: the list of terms is empty", field="terms",
                         expected=", ".join(TERMS))
    scales = [scales] if isinstance(scales, numbers.Real) else list(scales)
    bad = [v for v in scales if isinstance(v, bool) or not isinstance(v, numbers.Real)
           or not (math.isfinite(v) and v > 0)]
    if bad or not scales:
        raise InputError("a scale must be a finite multiple > 0 of the paper bound" if bad else
                         "no scale to check: the list of scales is empty", field="scales",
                         value=bad[0] if bad else scales,
                         expected="numbers > 0 (1 = the paper bound; default 0.1 … 10, 17 scales)")
    # a single-term model: its other terms are zero by construction, not unspecified
    options = (options or McOptions()).model_copy(update={"keep_trial_metrics": False,
                                                          "unspecified": "zero"})
    for term in terms:
        if term not in TERMS:
            raise InputError("unknown error term", field="terms", value=term, expected=", ".join(TERMS))
        if term in ROTATION_TERMS and not options.platform_motion.rotates:
            raise InputError(f"{term} acts on the angular rate, and the platform does not rotate in "
                             f"'{options.platform_motion.kind}' flight (it would pass at every scale)",
                             field="platform_motion", value=options.platform_motion.kind,
                             expected="oscillation, attitude_change or a custom disturbance with rotation")
    # every model first, so that a scale no noise model accepts is known before any trial runs
    models = {}
    for term in terms:
        for sc in scales:
            try:
                models[term, sc] = single_term_model(scenario, term, sc)
            except InputError as err:
                models[term, sc] = err
    rows = []
    for term in terms:
        done, ks, ns = [], [], []
        for sc in scales:
            model = models[term, sc]
            if isinstance(model, InputError):
                rows.append({"term": term, "scale": sc, "p_pass_after": math.nan, "ci_lo": math.nan,
                             "ci_hi": math.nan, "reasons": {}, "simulated": False,
                             "note": f"not simulated: {model}"})
                continue
            r = run_mc(scenario, model, trials, seed, options=options, workers=workers)
            reasons = {k: v for k, v in r.agg.failure_reasons().items() if v}
            rows.append({"term": term, "scale": sc, "p_pass_after": r.p_pass_after,
                         "ci_lo": r.ci_after[0], "ci_hi": r.ci_after[1], "reasons": reasons,
                         "simulated": True, "note": "", "fast_phase_share": fast_phase_share(scenario, model)})
            done.append(sc)
            ks.append(r.agg.pass_after)
            ns.append(r.trials)
        fit = (probit_crossing(done, ks, ns) if done else
               {"scale": math.nan, "lo": math.nan, "hi": math.nan, "method": "no scale simulated"})
        if done and len(done) < len(scales):
            fit["method"] += f" (over the {len(done)} of {len(scales)} scales a noise model accepts)"
        limited, rule = pga_limited_scale(scenario, term)
        analytic = fast_phase_crossing(scenario, term)
        for row in rows[-len(scales):]:
            row["pga_limited_scale"], row["pga_limited_rule"] = limited, rule
            row["fast_phase_crossing"] = analytic
            row.setdefault("fast_phase_share", math.nan)
            row["crossing_scale"] = fit["scale"]
            row["crossing_lo"], row["crossing_hi"] = fit["lo"], fit["hi"]
            row["crossing_method"] = fit["method"]
    table = pd.DataFrame(rows)
    # how the table was made, as a sweep's: trials and seed survive a CSV export as columns
    table.insert(2, "trials", trials)
    table.insert(3, "seed", seed)
    table.attrs.update({"scenario": scenario.name, "trials": trials, "seed": seed,
                        "options": (options or McOptions()).model_dump(mode="json")})
    return table


def crossing_scale(scales: Sequence[float], p_pass: Sequence[float], level: float = 0.5) -> float:
    """Scale where P(pass) falls through ``level`` (log-linear interpolation); inf if it never
    falls below, nan if it is already below at the smallest scale."""
    s, p = np.asarray(scales, float), np.asarray(p_pass, float)
    if p[0] < level:
        return math.nan
    for i in range(1, len(s)):
        if p[i] < level <= p[i - 1]:
            f = (p[i - 1] - level) / (p[i - 1] - p[i])
            return float(math.exp(math.log(s[i - 1]) + f * (math.log(s[i]) - math.log(s[i - 1]))))
    return math.inf


def probit_crossing(scales: Sequence[float], passes: Sequence[int], trials: Sequence[int],
                    level: float = 0.5, confidence: float = 0.95) -> dict:
    """Scale where P(pass) = ``level`` from a probit fit on log10(scale) (module docstring):
    ``{"scale", "lo", "hi", "method"}``; nan when every scale fails, inf when every one passes,
    nan with the open interval beyond the grid when the fitted crossing lies outside it."""
    s = np.asarray(scales, float)
    k = np.asarray(passes, float)
    n = np.asarray(trials, float)
    x = np.log10(s)
    if np.all(k == 0):
        return {"scale": math.nan, "lo": math.nan, "hi": math.nan, "method": "fails at every scale"}
    if np.all(k == n):
        return {"scale": math.inf, "lo": math.inf, "hi": math.inf, "method": "passes at every scale"}
    mixed = (k > 0) & (k < n)
    z = norm.ppf(level)
    if mixed.any():
        import statsmodels.api as sm
        from statsmodels.genmod.families import Binomial
        from statsmodels.genmod.families.links import Probit
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = sm.GLM(np.column_stack([k, n - k]), sm.add_constant(x),
                             family=Binomial(link=Probit())).fit()
            a, b = (float(v) for v in res.params)
            cov = np.asarray(res.cov_params())
            if b < 0 and np.all(np.isfinite(cov)):
                x50 = (z - a) / b
                # a crossing outside the grid is an extrapolation of one or two mixed counts:
                # report which side of the grid it is on, not a number
                if x50 < x.min():
                    return {"scale": math.nan, "lo": 0.0, "hi": float(s.min()), "method": "below the grid"}
                if x50 > x.max():
                    return {"scale": math.nan, "lo": float(s.max()), "hi": math.inf, "method": "above the grid"}
                grad = np.array([-1.0 / b, -(z - a) / b ** 2])  # d x50 / d(a, b)
                se = float(math.sqrt(max(grad @ cov @ grad, 0.0)))
                q = float(norm.ppf(0.5 + confidence / 2.0))
                return {"scale": 10 ** x50, "lo": 10 ** (x50 - q * se), "hi": 10 ** (x50 + q * se),
                        "method": "probit"}
        except (np.linalg.LinAlgError, ValueError):
            pass
    # perfect separation (or a non-decreasing fit): bracket by the grid
    last_pass = x[k == n].max() if np.any(k == n) else x.min()
    first_fail = x[(k == 0) & (x > last_pass)].min() if np.any((k == 0) & (x > last_pass)) else x.max()
    return {"scale": 10 ** (0.5 * (last_pass + first_fail)), "lo": 10 ** last_pass, "hi": 10 ** first_fail,
            "method": "bracket (separated counts)"}
