"""Monte Carlo against the analytic bounds: one error term at a multiple of its paper bound.

For a term (accel bias, gyro bias, VRW, ARW) a synthetic part carries only that term, at
``scale`` × the seed 004 bound for the scenario's Tc and δr (6)–(11). The table reports
P(pass after PGA) per scale and the scale at which it crosses 50 % (log-interpolated): a
crossing near 1 means the bound and the simulation agree; far from 1 says by how much they
differ and in which direction.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from ..bounds import paper_bounds
from ..imu.noise_model import NoiseModel
from ..scenario import Scenario
from .options import McOptions
from .runner import run_mc

#: term → (NoiseModel field, paper-bound key in datasheet units, conversion bound → field unit)
TERMS = {
    "accel_bias": ("accel_bias_repeatability_ug", "accel_bias_ug", 1.0),
    "gyro_bias": ("gyro_bias_repeatability_deg_h", "gyro_bias_deg_h", 1.0),
    "accel_vrw": ("accel_vrw_m_s_rt_h", "accel_vrw_ug_rt_hz", 1.0 / 1699.5270216298807),
    "gyro_arw": ("gyro_arw_deg_rt_h", "gyro_arw_deg_rt_h", 1.0),
}


def single_term_model(scenario: Scenario, term: str, scale: float) -> NoiseModel:
    """A model with only ``term`` at ``scale`` × its paper bound. Biases are turn-on biases
    (a constant drawn per trial, 1σ = the value), the constant bias of seed 004 (8)–(9)."""
    field, key, conv = TERMS[term]
    bound = float(paper_bounds(scenario.tc_s, scenario.range_resolution_m).datasheet()[key][0])
    return NoiseModel(part_id=f"{term}_x{scale:g}", grade="tactical", source="synthetic",
                      **{field: scale * bound * conv})


def consistency_table(scenario: Scenario, terms: Sequence[str] = tuple(TERMS),
                      scales: Sequence[float] = (0.1, 1.0, 10.0), trials: int = 64, seed: int = 0,
                      options: McOptions | None = None, workers: int = 1) -> pd.DataFrame:
    """P(pass after PGA) per term and scale, with the 50 % crossing scale per term."""
    options = (options or McOptions()).model_copy(update={"keep_trial_metrics": False})
    rows = []
    for term in terms:
        ps = []
        for sc in scales:
            r = run_mc(scenario, single_term_model(scenario, term, sc), trials, seed,
                       options=options, workers=workers)
            reasons = {k: v for k, v in r.agg.failure_reasons().items() if v}
            rows.append({"term": term, "scale": sc, "p_pass_after": r.p_pass_after,
                         "ci_lo": r.ci_after[0], "ci_hi": r.ci_after[1], "reasons": reasons})
            ps.append(r.p_pass_after)
        cross = crossing_scale(scales, ps)
        for row in rows[-len(scales):]:
            row["crossing_scale"] = cross
    return pd.DataFrame(rows)


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
