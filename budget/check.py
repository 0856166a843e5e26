"""Check catalog parts against the Tc-driven bounds, and recommend a grade per Tc.

Margin of a parameter = bound / spec (≥ 1 passes). The verdict of a part is ``pass`` when every
*specified* parameter has margin ≥ 1; unspecified (empty) datasheet values are listed in
``unspecified`` and never counted as passing or failing; a part with no specified parameter at
all gets the verdict ``unknown``. ``binding`` is the specified parameter
with the smallest margin.

Which spec meets which bound (seed 004 Tables 1–4 compare the same quantities):

=============================  ==========================
part column                    bound
=============================  ==========================
accel_scale_factor_ppm         β_max, (6)
gyro_scale_factor_ppm          γ_max, (6)
accel_misalignment_mrad        φm + φn, (7)
gyro_misalignment_mrad         φm + φn, (7)
accel_bias_instability_ug      b_a, (8)
gyro_bias_instability_deg_h    b_ω, (9)
accel_vrw_m_s_rt_h             n_a, (10)
gyro_arw_deg_rt_h              n_ω, (11)
=============================  ==========================

The in-run bias instability is compared with the bias bounds, as seed 004's Tables 3–4 do; the
turn-on bias (repeatability) is removed by alignment/calibration before imaging and is reported,
not checked.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from . import units as u
from .bounds import BoundsTable, compute_bounds
from .catalog.schema import GRADE_RANK, GradeSpec, PartSpec
from .scenario import Scenario

#: part column → (bound attribute of BoundsTable, conversion of the part value to SI)
CHECK_PARAMETERS: dict[str, tuple[str, callable]] = {
    "accel_scale_factor_ppm": ("accel_scale_factor", u.ppm_to_ratio),
    "gyro_scale_factor_ppm": ("gyro_scale_factor", u.ppm_to_ratio),
    "accel_misalignment_mrad": ("misalignment_rad", u.mrad_to_rad),
    "gyro_misalignment_mrad": ("misalignment_rad", u.mrad_to_rad),
    "accel_bias_instability_ug": ("accel_bias_m_s2", u.ug_to_m_s2),
    "gyro_bias_instability_deg_h": ("gyro_bias_rad_s", u.deg_h_to_rad_s),
    "accel_vrw_m_s_rt_h": ("accel_vrw_m_s2_rt_hz", u.m_s_rt_h_to_m_s2_rt_hz),
    "gyro_arw_deg_rt_h": ("gyro_arw_rad_s_rt_hz", u.deg_rt_h_to_rad_s_rt_hz),
}
PARAM_NAMES = tuple(CHECK_PARAMETERS)
#: Parameter families (for grade recommendation and for "calibrated" checks).
FAMILIES = {
    "scale_factor": ("accel_scale_factor_ppm", "gyro_scale_factor_ppm"),
    "misalignment": ("accel_misalignment_mrad", "gyro_misalignment_mrad"),
    "bias": ("accel_bias_instability_ug", "gyro_bias_instability_deg_h"),
    "noise": ("accel_vrw_m_s_rt_h", "gyro_arw_deg_rt_h"),
}


def spec_matrix(parts: Sequence[PartSpec]) -> np.ndarray:
    """(P, 8) SI specs in :data:`PARAM_NAMES` order; NaN where the datasheet gives no value."""
    out = np.full((len(parts), len(PARAM_NAMES)), np.nan)
    for i, p in enumerate(parts):
        for j, (name, (_, conv)) in enumerate(CHECK_PARAMETERS.items()):
            v = getattr(p, name)
            if v is not None:
                out[i, j] = conv(float(v))
    return out


def bound_matrix(bounds: BoundsTable) -> np.ndarray:
    """(S, 8) SI bounds in :data:`PARAM_NAMES` order for the S scenarios (Tc values) of ``bounds``."""
    cols = [np.ravel(np.asarray(getattr(bounds, attr), dtype=float))
            for attr, _ in CHECK_PARAMETERS.values()]
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

    @property
    def specified(self) -> np.ndarray:
        return ~np.isnan(self.margins)

    @property
    def passed(self) -> np.ndarray:
        """(P, S) True where every specified parameter has margin ≥ 1."""
        m = np.where(self.specified, self.margins, np.inf)
        return np.all(m >= 1.0, axis=-1)

    @property
    def min_margin(self) -> np.ndarray:
        return np.nanmin(np.where(self.specified, self.margins, np.inf), axis=-1)

    @property
    def binding_index(self) -> np.ndarray:
        return np.argmin(np.where(self.specified, self.margins, np.inf), axis=-1)

    def records(self, scenario_index: int = 0) -> list[dict]:
        """Per-part dicts for one scenario: ``part_id, grade, verdict, binding, margins, unspecified``."""
        out = []
        for i, pid in enumerate(self.part_ids):
            m = self.margins[i, scenario_index]
            spec = ~np.isnan(m)
            b = int(self.binding_index[i, scenario_index])
            out.append({
                "part_id": pid,
                "grade": self.grades[i],
                "verdict": ("unknown" if not spec.any() else
                            "pass" if self.passed[i, scenario_index] else "fail"),
                "binding": self.params[b] if spec.any() else None,
                "margins": {p: float(m[j]) for j, p in enumerate(self.params) if spec[j]},
                "unspecified": [p for j, p in enumerate(self.params) if not spec[j]],
            })
        return out

    def to_frame(self) -> pd.DataFrame:
        """Tidy table: one row per part × scenario with the margins and the verdict."""
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
        df["binding"] = [self.params[b] for b in self.binding_index.reshape(-1)]
        df["min_margin"] = self.min_margin.reshape(-1)
        return df.drop(columns=["p", "s"])

    def summary(self, scenario_index: int = 0) -> str:
        lines = [f"{'part':<22}{'grade':<14}{'verdict':<8}{'min margin':>11}  binding"]
        for r, mm in zip(self.records(scenario_index), self.min_margin[:, scenario_index]):
            lines.append(f"{r['part_id']:<22}{r['grade']:<14}{r['verdict']:<8}{mm:>11.3g}  "
                         f"{r['binding'] or '-'}")
        return "\n".join(lines)


def check_parts(parts: Iterable[PartSpec], scenarios: Sequence[Scenario] | Scenario,
                mode: str = "paper", assumptions=None) -> CheckResult:
    """Check parts against each scenario's bounds (Tc and δr from the scenario)."""
    parts = list(parts)
    scen = [scenarios] if isinstance(scenarios, Scenario) else list(scenarios)
    tc = np.array([s.tc_s for s in scen])
    dr = np.array([s.range_resolution_m for s in scen])
    if mode in ("no-autofocus", "no_autofocus"):
        rows = [bound_matrix(compute_bounds(t, d, mode, wavelength_m=s.wavelength_m,
                                            assumptions=assumptions))[0]
                for t, d, s in zip(tc, dr, scen)]
        bmat = np.array(rows)
    else:
        bmat = bound_matrix(compute_bounds(tc, dr, mode, assumptions=assumptions))
    return CheckResult(tuple(p.part_id for p in parts), tuple(p.grade for p in parts),
                       tuple(s.name for s in scen), tc, margins(spec_matrix(parts), bmat))


def check_arrays(specs: np.ndarray, tc_s: np.ndarray, range_resolution_m: np.ndarray,
                 mode: str = "paper") -> tuple[np.ndarray, np.ndarray]:
    """Vectorised core for trade studies: (P, 8) SI specs × S scenarios → (pass (P, S), min margin)."""
    bmat = bound_matrix(compute_bounds(tc_s, range_resolution_m, mode))
    m = margins(specs, bmat)
    m = np.where(np.isnan(m), np.inf, m)
    mm = m.min(axis=-1)
    return mm >= 1.0, mm


def grade_spec_matrix(grades: Sequence[GradeSpec], use: str = "best") -> np.ndarray:
    """(G, 8) SI typical values of each grade (``best`` = range minimum, ``worst`` = maximum)."""
    if use not in ("best", "worst"):
        raise ValueError("use must be 'best' or 'worst'")
    pick = 0 if use == "best" else 1
    out = np.empty((len(grades), len(PARAM_NAMES)))
    for i, g in enumerate(grades):
        vals = {
            "accel_scale_factor_ppm": (g.accel_scale_factor_ppm_min, g.accel_scale_factor_ppm_max),
            "gyro_scale_factor_ppm": (g.gyro_scale_factor_ppm_min, g.gyro_scale_factor_ppm_max),
            "accel_misalignment_mrad": (g.accel_misalignment_mrad,) * 2,
            "gyro_misalignment_mrad": (g.gyro_misalignment_mrad,) * 2,
            "accel_bias_instability_ug": (g.accel_bias_ug_min, g.accel_bias_ug_max),
            "gyro_bias_instability_deg_h": (g.gyro_bias_deg_h_min, g.gyro_bias_deg_h_max),
            # grades.csv gives accel noise in µg/√Hz; convert to the part column's m/s/√h first
            "accel_vrw_m_s_rt_h": tuple(u.ug_rt_hz_to_m_s_rt_h(v) for v in
                                        (g.accel_noise_ug_rt_hz_min, g.accel_noise_ug_rt_hz_max)),
            "gyro_arw_deg_rt_h": (g.gyro_arw_deg_rt_h_min, g.gyro_arw_deg_rt_h_max),
        }
        for j, (name, (_, conv)) in enumerate(CHECK_PARAMETERS.items()):
            out[i, j] = conv(sorted(vals[name])[pick])
    return out


@dataclass(frozen=True)
class GradeRecommendation:
    tc_s: np.ndarray
    range_resolution_m: np.ndarray
    grade: tuple[str | None, ...]
    include: tuple[str, ...]
    use: str

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"tc_s": np.ravel(self.tc_s), "range_resolution_m": np.ravel(self.range_resolution_m),
                             "lowest_sufficient_grade": list(self.grade)})

    def summary(self) -> str:
        return (f"lowest sufficient grade ({self.use} typical values; checked: {', '.join(self.include)})\n"
                + self.to_frame().to_string(index=False))


def recommend_grade(tc_s, range_resolution_m, grades: Sequence[GradeSpec], *, mode: str = "paper",
                    include: Sequence[str] = ("bias", "noise"), use: str = "best") -> GradeRecommendation:
    """Lowest grade (highest rank) whose typical values meet the bounds, per Tc.

    Defaults follow seed 004's reading of its Tables 1–4: scale factor and misalignment are
    left out because calibration removes most of them (the paper says so), and a grade counts
    as sufficient when the best of its typical range meets the bound (``use="best"``).
    ``None`` where no grade suffices.
    """
    unknown = set(include) - set(FAMILIES)
    if unknown:
        raise ValueError(f"unknown parameter families {sorted(unknown)}; expected {sorted(FAMILIES)}")
    tc = np.atleast_1d(np.asarray(tc_s, float))
    dr = np.broadcast_to(np.asarray(range_resolution_m, float), tc.shape)
    cols = [PARAM_NAMES.index(p) for fam in include for p in FAMILIES[fam]]
    ordered = sorted(grades, key=lambda g: GRADE_RANK[g.grade])
    m = margins(grade_spec_matrix(ordered, use), bound_matrix(compute_bounds(tc, dr, mode)))[:, :, cols]
    ok = np.all(m >= 1.0, axis=-1)  # (G, S)
    out = []
    for s in range(tc.size):
        passing = [ordered[g].grade for g in range(len(ordered)) if ok[g, s]]
        out.append(passing[-1] if passing else None)
    return GradeRecommendation(tc, np.asarray(dr), tuple(out), tuple(include), use)
