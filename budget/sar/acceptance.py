"""Pass/fail of measured impulse responses against acceptance levels.

Defaults (each configurable; the "ideal" values are the window's own, see
:func:`budget.sar.windows.ideal_irf`, so a Taylor-weighted image is judged against Taylor):

* 3 dB broadening ≤ 10 % in azimuth and range;
* PSLR ≤ ideal + 3 dB (rect: −10.3 dB; Taylor −35: ≈ −32 dB), or an absolute ``max_pslr_db``
  (< 0 dB) when the user's spec gives one;
* ISLR ≤ ideal + 3 dB (same extents as the measurement), or an absolute ``max_islr_db``;
* |peak shift| ≤ 1 resolution cell;
* peak loss ≤ 1.5 dB (a quadratic phase error of π/2 at the aperture edge costs ≈ 0.97 dB
  unweighted, one of π ≈ 4.0 dB).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from pydantic import BaseModel, ConfigDict, Field, field_validator

from ..errors import InputError, refuse_bool_numbers
from .metrics import TargetMetricArrays, TargetMetricsTable


class Acceptance(BaseModel):
    """Acceptance levels of the impulse response (see module docstring for the defaults)."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    max_broadening: float = Field(0.10, ge=0, le=10, allow_inf_nan=False, description="width/ideal − 1")
    pslr_margin_db: float = Field(3.0, ge=0, le=40, allow_inf_nan=False, description="allowed PSLR above ideal")
    islr_margin_db: float = Field(3.0, ge=0, le=40, allow_inf_nan=False, description="allowed ISLR above ideal")
    max_peak_shift_cells: float = Field(1.0, ge=0, le=1000, allow_inf_nan=False)
    max_peak_loss_db: float = Field(1.5, ge=0, le=60, allow_inf_nan=False)
    max_pslr_db: float | None = Field(None, lt=0, ge=-80, allow_inf_nan=False,
                                      description="absolute PSLR limit (dB, < 0); replaces ideal + margin")
    max_islr_db: float | None = Field(None, lt=0, ge=-80, allow_inf_nan=False,
                                      description="absolute ISLR limit (dB, < 0); replaces ideal + margin")
    axes: tuple[str, ...] = Field(("azimuth", "range"), description="image axes whose cuts are judged")

    @field_validator("axes")
    @classmethod
    def _axes(cls, v: tuple[str, ...]) -> tuple[str, ...]:
        # an empty list would turn every image check but the peak loss off without a word
        if not v or len(set(v)) != len(v) or not set(v) <= {"azimuth", "range"}:
            raise ValueError("axes must name 'azimuth' and/or 'range', each once, at least one")
        return v


@dataclass(frozen=True)
class Evaluation:
    """Outcome of :func:`evaluate`: ``passed`` and one reason per failed check."""

    passed: bool
    reasons: list[str]
    checks: pd.DataFrame
    acceptance: Acceptance | None = None

    def summary(self) -> str:
        if self.passed:
            return f"passed: all {len(self.checks)} checks within their limits"
        return f"failed {len(self.reasons)} of {len(self.checks)} checks: " + "; ".join(self.reasons)

    def to_dict(self) -> dict:
        """JSON-safe: outcome, reasons, every check and the acceptance it was judged with."""
        return {"passed": self.passed, "n_failed_checks": len(self.reasons), "reasons": list(self.reasons),
                "acceptance": None if self.acceptance is None else self.acceptance.model_dump(),
                "checks": self.checks.to_dict(orient="records")}

    def to_frame(self) -> pd.DataFrame:
        return self.checks


def evaluate(metrics: TargetMetricsTable, acceptance: Acceptance | None = None) -> Evaluation:
    """Check every target and axis against ``acceptance`` (defaults when None)."""
    acc = acceptance or Acceptance()
    if not isinstance(metrics, TargetMetricsTable) or len(metrics) == 0:
        raise InputError("no target metrics to evaluate", field="metrics",
                         expected="the result of measure_targets with ≥ 1 target")
    for ax in acc.axes:
        if ax not in ("azimuth", "range"):
            raise InputError("unknown axis", field="axes", value=ax, expected="'azimuth' and/or 'range'")
    rows, reasons = [], []

    def check(t, axis: str, name: str, value: float, limit: float) -> None:
        ok = bool(value <= limit)
        rows.append({"target": t.index, "axis": axis, "check": name, "value": value, "limit": limit, "passed": ok})
        if not ok:
            reasons.append(f"target {t.index} ({t.azimuth_m:g} m, {t.range_m:g} m) {axis} {name} "
                           f"{value:.4g} > {limit:.4g}")

    for t in metrics:
        check(t, "peak", "peak_loss_db", t.peak_loss_db, acc.max_peak_loss_db)
        for ax in acc.axes:
            m = getattr(t, ax)
            check(t, ax, "broadening", m.broadening, acc.max_broadening)
            check(t, ax, "pslr_db", m.pslr_db, m.ideal_pslr_db + acc.pslr_margin_db
                  if acc.max_pslr_db is None else acc.max_pslr_db)
            check(t, ax, "islr_db", m.islr_db, m.ideal_islr_db + acc.islr_margin_db
                  if acc.max_islr_db is None else acc.max_islr_db)
            check(t, ax, "abs_peak_shift_cells", abs(m.peak_shift_m) / m.cell_m, acc.max_peak_shift_cells)
    return Evaluation(passed=not reasons, reasons=reasons, checks=pd.DataFrame(rows), acceptance=acc)


#: Checks of :func:`failed_checks`, in the order of :func:`evaluate`'s rows.
CHECKS = ("peak_loss", "broadening", "pslr", "islr", "peak_shift")


def failed_checks(metrics: TargetMetricArrays, acceptance: Acceptance | None = None) -> dict[str, np.ndarray]:
    """:func:`evaluate` on a stack of images, without building its table: for each check of
    :data:`CHECKS`, a boolean array (B,) that is True where any target (and any axis of
    ``acceptance.axes``) fails it — the same comparisons value ≤ limit (NaN fails) with the same
    limits as :func:`evaluate`. An image passes :func:`evaluate` when no entry is True."""
    acc = acceptance or Acceptance()
    for ax in acc.axes:
        if ax not in ("azimuth", "range"):
            raise InputError("unknown axis", field="axes", value=ax, expected="'azimuth' and/or 'range'")

    def fails(value: np.ndarray, limit) -> np.ndarray:
        return np.any(~(value <= limit), axis=-1)

    out = {"peak_loss": fails(metrics["peak_loss_db"], acc.max_peak_loss_db)}
    b = out["peak_loss"].shape
    for name in CHECKS[1:]:
        out[name] = np.zeros(b, dtype=bool)
    for ax in acc.axes:
        out["broadening"] |= fails(metrics[f"{ax}_broadening"], acc.max_broadening)
        out["pslr"] |= fails(metrics[f"{ax}_pslr_db"], metrics[f"{ax}_ideal_pslr_db"] + acc.pslr_margin_db
                             if acc.max_pslr_db is None else acc.max_pslr_db)
        out["islr"] |= fails(metrics[f"{ax}_islr_db"], metrics[f"{ax}_ideal_islr_db"] + acc.islr_margin_db
                             if acc.max_islr_db is None else acc.max_islr_db)
        out["peak_shift"] |= fails(np.abs(metrics[f"{ax}_peak_shift_m"]) / metrics[f"{ax}_cell_m"],
                                   acc.max_peak_shift_cells)
    return out
