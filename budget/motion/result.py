"""Result of a motion-error simulation: per-trial series and phase metrics."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..scenario import Scenario
from ..units import range_error_to_phase_error

#: Per-trial metrics, each (T, K) (trials × scene points).
METRICS = ("constant_rad", "linear_edge_rad", "quadratic_edge_rad", "cubic_edge_rad",
           "residual_rms_deg", "peak_range_error_m", "peak_range_cells")


@dataclass
class MotionResult:
    """Motion errors of ``n_trials`` simulated apertures.

    Sign conventions: ``position_error_m`` is the APC position error *true − IMU-measured*
    (seed 000 (7)), (T, N, 3) in the local-level frame (x along-track, y toward the imaged side,
    z up), ``None`` if not kept. ``range_error_m`` (T, K, N) is R_true − R_assumed to each scene
    point (positive = true path longer); phase = 4π·range_error/λ. Metrics (T, K) are described
    in :mod:`budget.motion.phase`; ``peak_range_error_m`` = max |range error| over the aperture and
    ``peak_range_cells`` the same in range-resolution cells δr. ``time_s`` holds the IMU sample
    times (0 … (N−1)/rate, N = round(Tc·rate) + 1); ``tc_s`` is the scenario's Tc.
    ``aiding`` says how the trajectory was aided (``none``: free-inertial; otherwise sensors,
    correction mode and warm-up — the APC error is then relative to its aperture-start value)
    and ``prefilter`` which IMU pre-filter ran (``none``, ``kalman``, ``rts``). ``options``: the
    other inputs of :func:`~budget.motion.simulate_motion` (disturbance, initial errors, aiding plan,
    first trial), JSON-ready. ``earth_model`` names the error-propagation model (flat earth) and
    the estimated size of the Schuler, Earth-rate and transport-rate terms it leaves out over
    the aperture (:func:`budget.nav.earth.flat_earth_neglect`). ``notes``: what the run was
    simulated with that the user may not have set — IMU rate, lever arm, platform motion, and
    how empty datasheet terms were resolved (:mod:`budget.motion.notes`).
    """

    scenario: Scenario
    model_label: str
    seed: int
    time_s: np.ndarray
    targets_m: np.ndarray
    constant_rad: np.ndarray
    linear_edge_rad: np.ndarray
    quadratic_edge_rad: np.ndarray
    cubic_edge_rad: np.ndarray
    residual_rms_deg: np.ndarray
    peak_range_error_m: np.ndarray
    peak_range_cells: np.ndarray
    position_error_m: np.ndarray | None = None
    range_error_m: np.ndarray | None = None
    aiding: str = "none"
    prefilter: str = "none"
    options: dict = field(default_factory=dict)
    earth_model: str = "flat earth"
    notes: dict = field(default_factory=dict)

    @property
    def n_trials(self) -> int:
        return int(self.constant_rad.shape[0])

    @property
    def tc_s(self) -> float:
        return self.scenario.tc_s

    @property
    def wavelength_m(self) -> float:
        return self.scenario.wavelength_m

    def phase_error_rad(self) -> np.ndarray:
        """Phase error series 4π·Δr/λ (T, K, N); needs the kept range-error series."""
        if self.range_error_m is None:
            raise ValueError("series were not kept (simulate_motion(..., keep_series=True))")
        return range_error_to_phase_error(self.range_error_m, self.wavelength_m)

    def statistics(self) -> dict[str, dict[str, float]]:
        """Per metric (scene point 0): rms, median and 95th percentile of |x| over the trials."""
        out = {}
        for name in METRICS:
            a = np.abs(getattr(self, name)[:, 0])
            out[name] = {"rms": float(np.sqrt(np.mean(a**2))), "median": float(np.median(a)),
                         "p95": float(np.percentile(a, 95))}
        return out

    def summary(self) -> str:
        """Trials, aperture and a table of :meth:`statistics` (one line per metric)."""
        stats = self.statistics()
        span = float(self.time_s[-1]) if self.time_s.size else 0.0
        aperture = "" if abs(span - self.tc_s) <= 0.01 * self.tc_s else \
            f" (simulated over {span:.4g} s: whole IMU intervals)"
        lines = [f"{self.scenario.name} / {self.model_label}: {self.n_trials} trials, Tc = {self.tc_s:.3g} s{aperture}, "
                 f"{self.time_s.size} samples, λ = {self.wavelength_m:.4g} m (seed {self.seed}); "
                 f"aiding: {self.aiding}; IMU pre-filter: {self.prefilter}",
                 f"earth model: {self.earth_model}",
                 *self.notes.values(),
                 f"{'metric (|x|)':<22}{'rms':>12}{'median':>12}{'p95':>12}"]
        for name in METRICS:
            m = stats[name]
            lines.append(f"{name:<22}{m['rms']:>12.4g}{m['median']:>12.4g}{m['p95']:>12.4g}")
        return "\n".join(lines)

    def to_frame(self) -> pd.DataFrame:
        """One row per trial and scene point with every metric."""
        t, k = self.constant_rad.shape
        data = {"trial": np.repeat(np.arange(t), k), "target": np.tile(np.arange(k), t)}
        for name in METRICS:
            data[name] = getattr(self, name).reshape(-1)
        return pd.DataFrame(data)

    def to_dict(self) -> dict:
        """The CLI's JSON: inputs (scenario, model, seed, aiding, pre-filter, ``options``), the
        :meth:`statistics` and per-trial lists for scene point 0."""
        return {"trials": self.n_trials, "tc_s": self.tc_s, "seed": self.seed,
                "scenario": self.scenario.name, "model": self.model_label,
                "aiding": self.aiding, "prefilter": self.prefilter, "earth_model": self.earth_model,
                "notes": dict(self.notes),
                "aperture_simulated_s": float(self.time_s[-1]) if self.time_s.size else 0.0,
                "n_samples": int(self.time_s.size), "wavelength_m": self.wavelength_m,
                "range_resolution_m": self.scenario.range_resolution_m,
                "scenario_spec": self.scenario.model_dump(mode="json"), "options": dict(self.options),
                "targets_m": np.asarray(self.targets_m).tolist(), "statistics": self.statistics(),
                "peak_range_error_m": self.peak_range_error_m[:, 0].tolist(),
                "peak_range_cells": self.peak_range_cells[:, 0].tolist(),
                "quadratic_edge_rad": self.quadratic_edge_rad[:, 0].tolist(),
                "cubic_edge_rad": self.cubic_edge_rad[:, 0].tolist(),
                "residual_rms_deg": self.residual_rms_deg[:, 0].tolist(),
                "linear_edge_rad": self.linear_edge_rad[:, 0].tolist()}
