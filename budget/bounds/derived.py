"""Seed 004's bounds re-derived from physics with every assumption explicit.

Each source alone must keep its position error over Tc within its share of one range cell δr
(reconstructed from seed 004):

* accel scale factor β:  β·a·Tc²/2 ≤ s_β δr          → β ≤ 2 s_β δr/(a Tc²)
* gyro scale factor γ:   tilt γΘ couples g: g γ Θ Tc²/2 ≤ s_γ δr → γ ≤ 2 s_γ δr/(g Θ Tc²)
* misalignment φ:        couples a: a sin φ Tc²/2 ≤ s_φ δr → φ ≤ arcsin(2 s_φ δr/(a Tc²))
* accel bias b:          b Tc²/2 ≤ s_b δr             → b ≤ 2 s_b δr/Tc²
* gyro bias ε:           g ε Tc³/6 ≤ s_b δr           → ε ≤ 6 s_b δr/(g Tc³)
* VRW N:                 k N √(Tc³/3) ≤ s_n δr        → N ≤ s_n δr/(k √(Tc³/3))
* ARW N_θ:               k g N_θ √(Tc⁵/20) ≤ s_n δr   → N_θ ≤ s_n δr/(k g √(Tc⁵/20))

Defaults (a = g, Θ = 1 rad, s_β = s_φ = 1, s_γ = 1/2, s_b = 1/√2, s_n = 1, k = 2, each
source alone) give 0.204, 0.102, arcsin(0.204…), 1.44e5 µg, 8.92e4 deg/h, 8.83e4 µg/√Hz and
784 deg/√h: the paper's coefficients within its rounding (≤ 2 %).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from ..units import G0
from .paper import _inputs
from .table import BoundsTable

#: The sources seed 004 budgets separately.
N_SOURCES = 7


class DerivedAssumptions(BaseModel):
    """Assumptions behind the derived bounds; the defaults reproduce seed 004 (6)–(11)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    accel_level_m_s2: float = Field(G0, gt=0, allow_inf_nan=False,
                                    description="specific force seen by scale factor and misalignment")
    attitude_excursion_rad: float = Field(1.0, gt=0, allow_inf_nan=False,
                                          description="attitude change Θ seen by the gyro scale factor")
    gravity_m_s2: float = Field(G0, gt=0, allow_inf_nan=False)
    share_scale_factor: float = Field(1.0, gt=0, le=1)
    share_gyro_scale_factor: float = Field(0.5, gt=0, le=1)
    share_misalignment: float = Field(1.0, gt=0, le=1)
    share_bias: float = Field(1.0 / math.sqrt(2.0), gt=0, le=1)
    share_noise: float = Field(1.0, gt=0, le=1)
    k_sigma: float = Field(2.0, gt=0, le=6, description="noise: k·σ of position error ≤ its share")
    combine: Literal["each", "linear", "rss"] = Field(
        "each", description="each source alone (paper), δr/n (linear) or δr/√n (rss) over 7 sources")

    def combine_factor(self) -> float:
        return {"each": 1.0, "linear": 1.0 / N_SOURCES, "rss": 1.0 / math.sqrt(N_SOURCES)}[self.combine]


def derived_bounds(tc_s, range_resolution_m, a: DerivedAssumptions | None = None) -> BoundsTable:
    """Bounds from the physics above for arrays of Tc (s) and δr (m); SI results."""
    a = a or DerivedAssumptions()
    tc, dr = _inputs(tc_s, range_resolution_m)
    dr = dr * a.combine_factor()
    g = a.gravity_m_s2
    mis_arg = np.minimum(2.0 * a.share_misalignment * dr / (a.accel_level_m_s2 * tc**2), 1.0)
    return BoundsTable(
        mode="derived", tc_s=tc, range_resolution_m=np.asarray(range_resolution_m, float) * np.ones_like(tc),
        accel_scale_factor=2.0 * a.share_scale_factor * dr / (a.accel_level_m_s2 * tc**2),
        gyro_scale_factor=2.0 * a.share_gyro_scale_factor * dr / (g * a.attitude_excursion_rad * tc**2),
        misalignment_rad=np.arcsin(mis_arg),
        accel_bias_m_s2=2.0 * a.share_bias * dr / tc**2,
        gyro_bias_rad_s=6.0 * a.share_bias * dr / (g * tc**3),
        accel_vrw_m_s2_rt_hz=a.share_noise * dr / (a.k_sigma * np.sqrt(tc**3 / 3.0)),
        gyro_arw_rad_s_rt_hz=a.share_noise * dr / (a.k_sigma * g * np.sqrt(tc**5 / 20.0)),
        notes=(f"derived: {a.model_dump()}",),
        assumptions=a.model_dump(mode="json"),
    )
