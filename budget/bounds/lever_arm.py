"""Bounds with the lever arm: attitude error × lever arm d, beside seed 004's bounds.

Seed 004 assumes the IMU sits at the antenna phase centre (d = 0). With a lever arm d the
attitude error φ(t) moves the antenna directly, δR = φ × d (seed 000 (7): (A[θ̂] − A[θ]) d), with
no integration. Each source alone, whole error along the line of sight (|φ × d| ≤ |φ|·|d|, a
worst case), k·σ for random terms, Θ = platform rotation over the aperture
(``platform_rate_deg_s`` · Tc):

* ARW N (rad/√s): φ is a random walk, |δR| ≈ N·√t·|d|.
  - range migration: k·N·√Tc·|d| ≤ δr                         → N ≤ δr/(k √Tc |d|);
  - what PGA cannot remove (:mod:`budget.sar.residual`, the definition the Monte Carlo uses):
    c_rw(K)·m_q·N·√Tc·|d| ≤ λ/(4π)·1°, with c_rw(K) the exact rms of a unit random walk beyond K
    cycles per aperture and m_q the quantile of one aperture's rms over it that a share q of
    apertures meets (:func:`budget.sar.residual.random_walk_rms_quantile`: 1.22 at q = 0.9, Taylor
    window; ``fast_residual_share=None``: m = 1, the rms)   → N ≤ λ·1°/(4π c_rw m_q √Tc |d|);
* gyro bias b: φ = b·t, δR = b·t·|d| — linear in time, so only a shift of the image, but it
  migrates through range cells: b·Tc·|d| ≤ δr                   → b ≤ δr/(Tc |d|);
* misalignment φm: a constant φm·|d| moves the antenna by a fixed offset (geolocation) until the
  platform turns: as d rotates by Θ the offset changes by ≈ φm·|d|·Θ ≤ δr → φm ≤ δr/(|d| Θ);
* gyro scale factor γ: the attitude error γ·Θ seen through d: γ·Θ·|d| ≤ δr → γ ≤ δr/(Θ |d|).

Accelerometer terms do not see the lever arm. The table (mode ``lever_arm``) is the smaller of
the paper bound (seed 004 (6)–(11)) and the lever-arm limit per term; :func:`lever_arm_terms`
says which one binds.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

import numpy as np
import pandas as pd
from pydantic import BaseModel, ConfigDict, Field, field_validator

from ..errors import InputError, refuse_bool_numbers
from ..sar.residual import (DEFAULT_PASS_SHARE, DEFAULT_PGA_BANDWIDTH_CYCLES, random_walk_highpass_rms,
                            random_walk_rms_quantile)
from ..sar.windows import verdict_window
from ..units import phase_error_to_range_error
from .paper import _inputs, paper_bounds
from .table import BOUND_FIELDS, BoundsTable


#: one lever-arm component (m): finite, within the scenario's 1 km
_LeverComponent = Annotated[float, Field(ge=-1e3, le=1e3, allow_inf_nan=False)]


class LeverArmAssumptions(BaseModel):
    """Installation and limits of the lever-arm bounds (SI; the defaults of the verdict)."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    lever_arm_m: tuple[_LeverComponent, _LeverComponent, _LeverComponent] = (0.0, 0.0, 0.0)
    platform_rate_deg_s: float = Field(0.0, ge=0, allow_inf_nan=False,
                                       description="platform turn rate during the aperture")
    k_sigma: float = Field(2.0, gt=0, le=6, description="random terms: k·σ ≤ the limit")
    fast_residual_limit_deg: float = Field(1.0, gt=0, allow_inf_nan=False,
                                           description="what PGA cannot remove, rms (seed 004: 1°)")
    fast_residual_share: float | None = Field(
        DEFAULT_PASS_SHARE, gt=0, lt=1, allow_inf_nan=False,
        description="share of apertures whose residual must be within that limit (the Monte Carlo's pass "
                    "target); None: its rms over apertures within it")
    pga_bandwidth_cycles: float = Field(DEFAULT_PGA_BANDWIDTH_CYCLES, ge=0, le=1000, allow_inf_nan=False)
    aperture_window: Literal["rect", "taylor"] = Field(
        "rect", description="azimuth weighting whose energy weights what PGA cannot remove, as in the "
                            "Monte Carlo (rect: unweighted, conservative; from_scenario: the verdict's window)")

    @classmethod
    def from_scenario(cls, scenario, **kw) -> "LeverArmAssumptions":
        """The scenario's installation, and the window its Monte Carlo verdict images with
        (:func:`budget.sar.windows.verdict_window`: Taylor for radar), unless given."""
        kw.setdefault("aperture_window", verdict_window(scenario).kind)
        return cls(lever_arm_m=tuple(scenario.lever_arm_m),
                   platform_rate_deg_s=scenario.platform_rate_deg_s, **kw)

    @property
    def lever_m(self) -> float:
        return float(math.sqrt(sum(v * v for v in self.lever_arm_m)))


def _limits(tc, dr, wavelength_m: float, a: LeverArmAssumptions) -> dict[str, np.ndarray]:
    """Lever-arm-only limits (SI) per term; inf where the lever arm imposes none."""
    d = a.lever_m
    inf = np.full_like(tc, np.inf)
    if d == 0.0:
        return {"gyro_arw_migration": inf, "gyro_arw_fast": inf, "gyro_bias": inf,
                "misalignment": inf, "misalignment_uncapped": inf, "gyro_scale_factor": inf}
    theta = math.radians(a.platform_rate_deg_s) * tc
    with np.errstate(divide="ignore"):
        by_turn = np.where(theta > 0, dr / (d * theta), np.inf)
    fast_m = phase_error_to_range_error(math.radians(a.fast_residual_limit_deg), wavelength_m)
    c_rw = random_walk_highpass_rms("rw", float(a.pga_bandwidth_cycles), window=a.aperture_window)
    if a.fast_residual_share is not None:  # the limit met on that share of apertures, not in rms
        c_rw *= random_walk_rms_quantile("rw", a.fast_residual_share, float(a.pga_bandwidth_cycles),
                                         a.aperture_window)
    # an angle's limit stops at 90°, as seed 004 (7)'s arcsin does: beyond it any misalignment
    # meets it (inf stays inf: no turn, no limit at all)
    mis = np.where(np.isfinite(by_turn), np.minimum(by_turn, MISALIGNMENT_CAP_RAD), np.inf)
    return {"gyro_arw_migration": dr / (a.k_sigma * np.sqrt(tc) * d),
            "gyro_arw_fast": fast_m / (c_rw * np.sqrt(tc) * d),
            "gyro_bias": dr / (tc * d),
            "misalignment": mis,
            "misalignment_uncapped": by_turn,
            "gyro_scale_factor": by_turn}


#: Largest misalignment limit (rad): 90°, where seed 004 (7)'s arcsin saturates; a lever-arm
#: limit δr/(|d| Θ) beyond it is capped there (any misalignment then meets it) and noted.
MISALIGNMENT_CAP_RAD = math.pi / 2


def lever_arm_limit_notes(tc_s, range_resolution_m, wavelength_m: float,
                          a: LeverArmAssumptions | None = None) -> tuple[str, ...]:
    """Where a lever-arm limit stops constraining, as :meth:`BoundsTable.limit_notes` says it for
    seed 004's: the misalignment limit δr/(|d| Θ) reaching 90° (capped there: any misalignment
    meets it) and a gyro scale-factor limit δr/(Θ |d|) of 100 % or more."""
    a = a or LeverArmAssumptions()
    tc, dr = _inputs(tc_s, range_resolution_m)
    lim = _limits(tc, dr, float(wavelength_m), a)
    raw, sf = np.ravel(lim["misalignment_uncapped"]), np.ravel(lim["gyro_scale_factor"])
    out = []
    for t, m, g in zip(np.ravel(tc), raw, sf):
        if np.isfinite(m) and m >= MISALIGNMENT_CAP_RAD:
            out.append(f"lever-arm misalignment limit capped at 90° ({1e3 * MISALIGNMENT_CAP_RAD:.4g} mrad) at "
                       f"Tc = {t:.4g} s: δr/(|d|·Θ) = {1e3 * m:.4g} mrad is beyond π/2, so any misalignment "
                       "meets it — the lever arm does not constrain the misalignment there")
        if np.isfinite(g) and g >= 1.0:
            out.append(f"lever-arm gyro scale factor limit ≥ 100 % at Tc = {t:.4g} s ({g * 1e6:.4g} ppm): it "
                       "does not constrain any real sensor")
    return tuple(out)


def lever_arm_bounds(tc_s, range_resolution_m, wavelength_m: float,
                     a: LeverArmAssumptions | None = None) -> BoundsTable:
    """min(seed 004 bound, lever-arm limit) per term for arrays of Tc (s) and δr (m); SI."""
    a = a or LeverArmAssumptions()
    lam = float(wavelength_m)
    if not (math.isfinite(lam) and lam > 0):
        raise InputError("wavelength must be finite and > 0", field="wavelength_m", value=lam,
                         expected="λ in m, > 0")
    tc, dr = _inputs(tc_s, range_resolution_m)
    p = paper_bounds(tc, dr)
    lim = _limits(tc, dr, lam, a)
    arw = np.minimum(lim["gyro_arw_migration"], lim["gyro_arw_fast"])
    return BoundsTable(
        mode="lever_arm", tc_s=tc, range_resolution_m=dr,
        accel_scale_factor=p.accel_scale_factor,
        gyro_scale_factor=np.minimum(p.gyro_scale_factor, lim["gyro_scale_factor"]),
        misalignment_rad=np.minimum(p.misalignment_rad, lim["misalignment"]),
        accel_bias_m_s2=p.accel_bias_m_s2,
        gyro_bias_rad_s=np.minimum(p.gyro_bias_rad_s, lim["gyro_bias"]),
        accel_vrw_m_s2_rt_hz=p.accel_vrw_m_s2_rt_hz,
        gyro_arw_rad_s_rt_hz=np.minimum(p.gyro_arw_rad_s_rt_hz, arw),
        notes=(f"lever arm |d| = {a.lever_m:.4g} m, platform rate {a.platform_rate_deg_s:g} deg/s, "
               f"λ = {lam:.4g} m: min(seed 004 (6)-(11), attitude error × lever arm); "
               f"{a.model_dump()}",),
        assumptions={"wavelength_m": lam, **a.model_dump(mode="json")},
    )


def lever_arm_terms(tc_s: float, range_resolution_m: float, wavelength_m: float,
                    a: LeverArmAssumptions | None = None) -> pd.DataFrame:
    """Per gyro term at one Tc: paper bound, lever-arm limit (datasheet units), which binds and
    by what factor — so a user sees when the lever arm, not seed 004's bound, decides."""
    a = a or LeverArmAssumptions()
    tc, dr = _inputs(tc_s, range_resolution_m)
    paper = paper_bounds(tc, dr)
    lim = _limits(tc, dr, float(wavelength_m), a)
    rows = []
    spec = (("gyro_arw_deg_rt_h", "range migration k·N·√Tc·|d| ≤ δr", lim["gyro_arw_migration"]),
            ("gyro_arw_deg_rt_h", f"PGA residual of N·√t·|d| ≤ {a.fast_residual_limit_deg:g}°"
             + (f" on {a.fast_residual_share:g} of apertures" if a.fast_residual_share is not None else " rms"),
             lim["gyro_arw_fast"]),
            ("gyro_bias_deg_h", "b·Tc·|d| ≤ δr", lim["gyro_bias"]),
            ("misalignment_mrad", "φm·|d|·Θ ≤ δr", lim["misalignment"]),
            ("gyro_scale_factor_ppm", "γ·Θ·|d| ≤ δr", lim["gyro_scale_factor"]))
    for key, rule, value in spec:
        si, conv = BOUND_FIELDS[key]
        pb = float(conv(np.asarray(getattr(paper, si)))[0])
        lv = float(conv(np.asarray(value))[0]) if np.isfinite(value[0]) else math.inf
        rows.append({"term": key, "lever_arm_rule": rule, "paper_bound": pb, "lever_arm_limit": lv,
                     "binding": "lever arm" if lv < pb else "paper",
                     "paper_over_lever": pb / lv if lv > 0 else math.inf})
    frame = pd.DataFrame(rows)
    # where a limit stops constraining (capped at 90°, ≥ 100 %): said beside the table
    frame.attrs["notes"] = list(lever_arm_limit_notes(tc, dr, float(wavelength_m), a))
    return frame


__all__ = ["MISALIGNMENT_CAP_RAD", "LeverArmAssumptions", "lever_arm_bounds", "lever_arm_limit_notes",
           "lever_arm_terms"]


def pga_limited_bounds(scenario, a: LeverArmAssumptions | None = None) -> tuple[BoundsTable, dict]:
    """Seed 004's bounds for ``scenario`` tightened by what PGA cannot remove: the lever-arm
    limits above and the fast-phase VRW/ARW limits (:func:`budget.bounds.fast_phase_limits`,
    the same definition as the Monte Carlo). Returns the table (mode ``pga-limited``) and, per
    bound field it tightens, the rule that does (``{si_field: rule}``). A Tc beyond the bounds'
    navigation model is refused (:func:`budget.bounds.check_bounds_tc`), as in every other mode."""
    from dataclasses import replace

    from . import check_bounds_tc
    from .fast_phase import fast_phase_limits

    check_bounds_tc(scenario.tc_s, field="tc_s (derived)")
    a = a or LeverArmAssumptions.from_scenario(scenario)
    tc, dr, lam = np.array([scenario.tc_s]), scenario.range_resolution_m, scenario.wavelength_m
    paper = paper_bounds(tc, dr)
    lever = lever_arm_bounds(tc, dr, lam, a)
    fast = fast_phase_limits(lam, tc, noise_rms_deg=a.fast_residual_limit_deg,
                             pga_bandwidth_cycles=a.pga_bandwidth_cycles, aperture_window=a.aperture_window,
                             share=a.fast_residual_share)
    vrw = np.minimum(lever.accel_vrw_m_s2_rt_hz, fast.vrw_m_s2_rt_hz)
    arw = np.minimum(lever.gyro_arw_rad_s_rt_hz, fast.arw_rad_s_rt_hz)
    table = replace(lever, mode="pga-limited", accel_vrw_m_s2_rt_hz=vrw, gyro_arw_rad_s_rt_hz=arw,
                    notes=lever.notes + (f"fast phase: residual beyond {a.pga_bandwidth_cycles:g} cycles "
                                         f"≤ {a.fast_residual_limit_deg:g}° rms ({a.aperture_window}-weighted "
                                         "aperture energy) " + (f"on {a.fast_residual_share:g} of apertures"
                                                                if a.fast_residual_share is not None else
                                                                "in rms over apertures"),))
    rules = {}
    for si in ("gyro_scale_factor", "misalignment_rad", "gyro_bias_rad_s"):
        if np.any(getattr(lever, si) < getattr(paper, si)):
            rules[si] = "lever arm"
    if np.any(fast.vrw_m_s2_rt_hz < paper.accel_vrw_m_s2_rt_hz):
        rules["accel_vrw_m_s2_rt_hz"] = "fast phase (beyond PGA's window)"
    arw_lever = lever.gyro_arw_rad_s_rt_hz < paper.gyro_arw_rad_s_rt_hz
    arw_fast = fast.arw_rad_s_rt_hz < np.minimum(paper.gyro_arw_rad_s_rt_hz, lever.gyro_arw_rad_s_rt_hz)
    if np.any(arw_fast):
        rules["gyro_arw_rad_s_rt_hz"] = "fast phase (beyond PGA's window)"
    elif np.any(arw_lever):
        rules["gyro_arw_rad_s_rt_hz"] = "lever arm (attitude noise × lever arm beyond PGA's window)"
    return table, rules


__all__.append("pga_limited_bounds")
