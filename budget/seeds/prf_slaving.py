"""Seed 001 (4): PRF slaved to the forward speed, f_PR = k·V, and what happens when it is not.

Seed 001 §1.1: the forward-velocity deviation makes the pulses sample the aperture unevenly;
controlling the PRF by the measured forward speed, f_PR = k·V_ay (4), keeps the along-track
sample spacing 1/k constant and removes the azimuth distortion.

Model (exact stop-and-go geometry, one range bin): the missile flies x(t) = ∫V, with
V(t) = V0 + a t + A sin(2π f t) (along-track acceleration and a speed oscillation). Pulses:

* **fixed PRF**: t_n = n / PRF0; the true positions x(t_n) are uneven;
* **slaved PRF**: pulse n is fired when the *measured* travelled distance reaches n/k
  (k = PRF0/V0), so the true position is x_n = n/k − δX(t_n), with δX the integrated error of the
  aided slave IMU's forward velocity (a constant δv ~ N(0, σ_v) per trial; σ_v defaults to the
  velocity error of the seed 001 master–slave case; for contrast also an unaided slave IMU
  whose speed error has grown to ``unaided_velocity_error_m_s``, e.g. 0.5 mg of accelerometer
  bias over 100 s).

The processor assumes x̃_n = n/k (uniform spacing at the nominal speed). For a target at
along-track x_t and slant range R0 its residual phase is φ_n = 4π/λ [R(x_n − x_t) − R(x̃_n − x_t)],
R(u) = √(R0² + u²), over the pulses with |x̃_n − x_t| ≤ L/2 (L = V0·Tc); the azimuth IRF of
:mod:`budget.sar.point_target` gives PSLR, ISLR, 3 dB width and the peak shift (the image
distortion, in metres: 1 cell = λR0/(2L)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..fileio import json_safe
from ..presets import get_preset
from ..sar.point_target import azimuth_irf_metrics
from ..units import two_way_wavenumber_rad_m
from .params import params_dict


@dataclass(frozen=True)
class PrfParams:
    preset: str = "missile_borne"
    accel_m_s2: float = 2.0
    speed_oscillation_m_s: float = 0.5
    oscillation_hz: float = 1.0
    oversample: float = 2.0
    targets_in_apertures: tuple[float, ...] = (-1.0, 0.0, 1.0)
    velocity_error_m_s: float = 0.0015
    unaided_velocity_error_m_s: float = 0.5
    trials: int = 20
    window: str = "rect"


def travelled(t: np.ndarray, v0: float, p: PrfParams) -> np.ndarray:
    """x(t) = V0 t + a t²/2 + (A / 2πf)(1 − cos 2πft): the true along-track position (m)."""
    w = 2 * math.pi * p.oscillation_hz
    return v0 * t + 0.5 * p.accel_m_s2 * t ** 2 + p.speed_oscillation_m_s / w * (1 - np.cos(w * t))


def _fire_times(x_targets: np.ndarray, v0: float, p: PrfParams) -> np.ndarray:
    """Times at which x(t) = x_targets (Newton iterations; x is monotonic for V > 0)."""
    t = x_targets / v0
    w = 2 * math.pi * p.oscillation_hz
    for _ in range(30):
        v = v0 + p.accel_m_s2 * t + p.speed_oscillation_m_s * np.sin(w * t)
        t = t - (travelled(t, v0, p) - x_targets) / v
    return t


@dataclass
class PrfResult:
    """One row per (case, target): sampling non-uniformity and IRF metrics (median over trials)."""

    params: PrfParams
    table: pd.DataFrame

    def worst(self) -> dict:
        """Per case: worst PSLR (dB), |shift| (m) and width (cells) over the targets."""
        g = self.table.groupby("case")
        return {"worst_pslr_db": g["pslr_db"].max().to_dict(),
                "worst_shift_m": g["shift_m"].apply(lambda s: s.abs().max()).to_dict(),
                "worst_width_cells": g["width_cells"].max().to_dict()}

    def to_dict(self) -> dict:
        """JSON-ready: the parameters, :meth:`worst` and the table."""
        return json_safe({"params": params_dict(self.params), **self.worst(),
                          "table": self.table.to_dict(orient="records")})

    def summary(self) -> str:
        """One line per case: worst PSLR, |shift| and width over the targets."""
        w = self.worst()
        return "\n".join([f"PRF slaving, {self.params.trials} trials (worst over targets):"]
                         + [f"  {c}: PSLR {w['worst_pslr_db'][c]:.2f} dB, shift {w['worst_shift_m'][c]:.3g} m, "
                            f"width {w['worst_width_cells'][c]:.3g} cells" for c in w["worst_pslr_db"]])

    def to_frame(self) -> pd.DataFrame:
        return self.table.copy()


def run_prf_slaving(params: PrfParams = PrfParams(), *, rng: np.random.Generator) -> PrfResult:
    sc = get_preset(params.preset)
    lam, r0, v0 = sc.wavelength_m, sc.slant_range_m, sc.platform_speed_m_s
    L = v0 * sc.tc_s
    bandwidth = 2 * v0 * v0 * sc.tc_s / (lam * r0)            # Doppler bandwidth of one target
    prf0 = params.oversample * bandwidth
    k = prf0 / v0                                              # pulses per metre, seed 001 (4)
    cell_m = lam * r0 / (2 * L)
    span = (max(abs(a) for a in params.targets_in_apertures) + 0.6) * L
    n = np.arange(-int(span * k), int(span * k) + 1)
    x_nominal = n / k                                          # what the processor assumes
    t_fixed = n / prf0
    cases = {
        "constant speed": np.broadcast_to(x_nominal, (1, n.size)),
        "fixed PRF": travelled(t_fixed, v0, params)[None, :],
    }
    t_slaved = _fire_times(x_nominal, v0, params)
    for label, sigma in (("aided", params.velocity_error_m_s),
                         ("unaided", params.unaided_velocity_error_m_s)):
        dv = rng.normal(0.0, sigma, size=(params.trials, 1))
        cases[f"slaved PRF, {label}-IMU speed"] = x_nominal[None, :] - dv * t_slaved[None, :]
    rows = []
    for case, x_true in cases.items():
        for a in params.targets_in_apertures:
            xt = a * L
            sel = np.abs(x_nominal - xt) <= L / 2
            u_true, u_nom = x_true[:, sel] - xt, x_nominal[sel] - xt
            phi = two_way_wavenumber_rad_m(lam) * (np.sqrt(r0 ** 2 + u_true ** 2) - np.sqrt(r0 ** 2 + u_nom ** 2))
            m = azimuth_irf_metrics(phi, params.window)
            dx = x_true[:, sel] - x_nominal[sel]
            rows.append({"case": case, "target_x_m": xt, "pulses": int(sel.sum()),
                         "max_sample_offset_m": float(np.max(np.abs(dx - dx.mean(axis=1, keepdims=True)))),
                         "pslr_db": float(np.median(m.pslr_db)), "islr_db": float(np.median(m.islr_db)),
                         "width_cells": float(np.median(m.width_cells)),
                         "shift_m": float(np.median(m.shift_cells)) * cell_m,
                         "peak_loss_db": float(np.median(m.peak_loss_db))})
    return PrfResult(params, pd.DataFrame(rows))
