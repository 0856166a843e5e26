"""Imaging with a known, injected phase error: echoes → image → PGA → metrics before and after.

The phase error ψ(t) (rad per pulse, :mod:`budget.sar.phase`) is put on the scene centre by
moving the TRUE antenna along the line of sight by Δr = −ψλ/(4π) (:func:`los_offset_for_phase`);
the image is formed on the nominal track (no motion compensation), autofocused by PGA
(Wahl et al. 1994) and measured before and after. PGA's estimate is compared with the phase
that was put in, read on the image's azimuth-frequency bins (:func:`phase_on_bins`), after
removal of constant and linear terms (:func:`residual_rms_rad`). This is the demonstration
behind ``sar-budget sar``; the Monte Carlo verdict (:mod:`budget.mc`) instead images the error
of an IMU-measured trajectory.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd

from .acceptance import Acceptance, Evaluation, evaluate
from .echoes import simulate_echoes
from .geometry import SarGeometry
from .image import form_image
from .metrics import TargetMetricsTable, measure_targets
from ..errors import InputError
from .pga import PgaResult, pga
from .phase import los_offset_for_phase, phase_on_bins, residual_phase_rad, residual_rms_rad
from .scene import Scene


@dataclass
class InjectedPhaseTrial:
    """Outcome of :func:`run_injected_phase_trial`: the injected phase per pulse (rad), the
    metrics and acceptance before and after PGA, PGA's result and the rms difference (rad)
    between its estimate and the injected phase (NaN when PGA did not converge)."""

    geometry: SarGeometry
    injected_phase_rad: np.ndarray
    before: TargetMetricsTable
    after: TargetMetricsTable
    evaluation_before: Evaluation
    evaluation_after: Evaluation
    pga: PgaResult
    residual_rms_rad: float
    kernel: str

    def to_dict(self) -> dict:
        """JSON-ready: geometry, PGA, residual, metrics per target before/after, pass flags."""
        return {"geometry": self.geometry.to_dict(), "pga": self.pga.to_dict(),
                "residual_rms_rad": self.residual_rms_rad,
                "before": self.before.to_frame().reset_index().to_dict(orient="records"),
                "after": self.after.to_frame().reset_index().to_dict(orient="records"),
                "passed_before": self.evaluation_before.passed, "passed_after": self.evaluation_after.passed}

    def to_frame(self) -> pd.DataFrame:
        """Target metrics, before and after PGA (column ``stage``)."""
        return pd.concat([self.before.to_frame().assign(stage="before"),
                          self.after.to_frame().assign(stage="after")])

    def summary(self, columns: list[str] | None = None) -> str:
        """Metrics before and after PGA (``columns`` of the metrics table), acceptance and PGA."""
        def table(m: TargetMetricsTable) -> str:
            f = m.to_frame()
            return (f[columns] if columns else f).round(3).to_string()

        ev_b, ev_a, r = self.evaluation_before, self.evaluation_after, self.pga
        lines = ["before PGA:", table(self.before),
                 f"acceptance: {'PASS' if ev_b.passed else 'FAIL'} ({len(ev_b.reasons)} failed checks)", "",
                 f"PGA ({self.kernel}): {r.reason}; {r.usable_lines} range lines; "
                 f"residual vs truth {self.residual_rms_rad:.3g} rad rms", "",
                 "after PGA:", table(self.after),
                 f"acceptance: {'PASS' if ev_a.passed else 'FAIL'} ({len(ev_a.reasons)} failed checks)"]
        lines += ["  " + reason for reason in ev_a.reasons[:10]]
        return "\n".join(lines)


def _check_phase(phase_rad, n_pulses: int) -> np.ndarray:
    """``phase_rad`` as one finite phase per pulse (a scalar is broadcast), else :class:`InputError`
    naming ``phase_rad`` (was a NumPy broadcast error, or NaN reported as an APC offset)."""
    try:
        psi = np.asarray(phase_rad, dtype=float)
    except (TypeError, ValueError):
        psi = None
    if psi is None or psi.shape not in ((), (n_pulses,)):
        raise InputError("not one phase per pulse", field="phase_rad", value=getattr(psi, "shape", phase_rad),
                         expected=f"a number or {n_pulses} phases (rad), one per pulse of the geometry")
    if not np.all(np.isfinite(psi)):
        raise InputError(f"{int(np.sum(~np.isfinite(psi)))} phases are NaN or infinite", field="phase_rad",
                         expected="finite phases in rad")
    return np.broadcast_to(psi, (n_pulses,))


def run_injected_phase_trial(geom: SarGeometry, scene: Scene, phase_rad, rng: np.random.Generator | None, *,
                             method: str = "rda", kernel: str = "ml",
                             acceptance: Acceptance | None = None) -> InjectedPhaseTrial:
    """Image ``scene`` with the phase error ``phase_rad`` (rad, one value per pulse) injected on
    the true track, autofocus with PGA (``kernel`` ml | lumv) and measure (module docstring).
    ``rng`` draws receiver noise and clutter (required when the scene has them)."""
    psi = _check_phase(phase_rad, geom.n_pulses)
    offset = los_offset_for_phase(geom, psi)
    data = simulate_echoes(geom, scene, offset, rng)
    image = form_image(geom, data, None, method=method)
    before = measure_targets(image, geom, scene)
    result = pga(image.data, kernel=kernel)
    after = measure_targets(image.with_data(result.image), geom, scene)
    truth = phase_on_bins(image, geom, residual_phase_rad(geom, offset))
    mask = image.aperture_mask() & result.estimated_bins
    resid = residual_rms_rad(result.phase_error_rad, truth, mask) if result.converged else math.nan
    acc = acceptance or Acceptance()
    return InjectedPhaseTrial(geometry=geom, injected_phase_rad=np.array(psi), before=before, after=after,
                              evaluation_before=evaluate(before, acc),
                              evaluation_after=with_pga_outcome(evaluate(after, acc), result),
                              pga=result, residual_rms_rad=float(resid), kernel=kernel)


def with_pga_outcome(evaluation: Evaluation, result: PgaResult) -> Evaluation:
    """``evaluation`` of the image after PGA, failed when PGA itself failed or stalled — the
    Monte Carlo's rule (:mod:`budget.mc.chain`: ``pga_failed``, ``pga_not_converged``): an image
    PGA did not finish is never scored as focused, whatever its metrics say."""
    if result.converged:
        return evaluation
    why = "found no usable scatterers" if result.failed else "did not converge"
    reason = f"PGA {why} ({result.reason}): the image after PGA is not a focused one"
    return replace(evaluation, passed=False, reasons=[reason, *evaluation.reasons])
