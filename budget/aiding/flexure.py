"""Lever arm with flexure: a structural bending mode as a noise-driven damped oscillator.

Between two points of a flexible airframe (IMU on the fuselage and antenna on the wing, or a
master and a slave IMU, seed 002) the lever arm is l + d(t). Each body axis of d follows

    d̈ + 2ζω ḋ + ω² d = w,   E[w(t) w(s)] = q δ(t − s),   ω = 2π f,

whose stationary variance is var d = q / (4ζω³) (solve F P + P Fᵀ + Q = 0), so
q = 4ζω³ σ² gives the configured 1σ amplitude σ. Then var ḋ = ω² σ², cov(d, ḋ) = 0 and the
autocorrelation is R(τ) = σ² e^{−ζω|τ|} (cos ω_d τ + ζω/ω_d sin ω_d|τ|), ω_d = ω√(1 − ζ²) — the
second-order Gauss–Markov model used for wing flexure in transfer alignment.

State of one mode: [d_x, d_y, d_z, ḋ_x, ḋ_y, ḋ_z] (m, m/s), body frame.

d is a motion error the IMU cannot see when the IMU is not on the flexing part: the antenna
phase centre is p_imu + C_bn (l + d), so it adds C_bn d to the antenna position error
(:func:`antenna_flexure_error`) unless an aid observes it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..aiding_spec import FlexureConfig
from .ins_error_model import van_loan
from .lti import sample_initial, sample_lti


def flexure_blocks(mode: FlexureConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Continuous F (6, 6), noise density Qc (6, 6) and stationary covariance P∞ (6, 6)."""
    w = 2.0 * np.pi * mode.frequency_hz
    z = mode.damping_ratio
    sig2 = np.asarray(mode.amplitude_m, dtype=float) ** 2
    i3 = np.eye(3)
    F = np.zeros((6, 6))
    F[:3, 3:] = i3
    F[3:, :3] = -w * w * i3
    F[3:, 3:] = -2.0 * z * w * i3
    Qc = np.zeros((6, 6))
    Qc[3:, 3:] = np.diag(4.0 * z * w ** 3 * sig2)
    P = np.zeros((6, 6))
    P[:3, :3] = np.diag(sig2)
    P[3:, 3:] = np.diag(w * w * sig2)
    return F, Qc, P


def flexure_autocorrelation(mode: FlexureConfig, lag_s) -> np.ndarray:
    """Closed-form autocorrelation of d per axis, (len(lag), 3) in m² (see module docstring)."""
    lag = np.abs(np.asarray(lag_s, dtype=float))[:, None]
    w = 2.0 * np.pi * mode.frequency_hz
    z = mode.damping_ratio
    wd = w * np.sqrt(1.0 - z * z)
    sig2 = np.asarray(mode.amplitude_m, dtype=float) ** 2
    return sig2 * np.exp(-z * w * lag) * (np.cos(wd * lag) + z * w / wd * np.sin(wd * lag))


@dataclass(frozen=True)
class FlexureHistory:
    """Simulated flexure: displacement (T, N, 3) m and rate (T, N, 3) m/s, body frame."""

    dt_s: float
    displacement_m: np.ndarray
    velocity_m_s: np.ndarray

    def to_dict(self) -> dict:
        """JSON-ready: sample interval (s), trials, samples and the RMS per body axis."""
        return {"dt_s": float(self.dt_s), "trials": int(self.displacement_m.shape[0]),
                "samples": int(self.displacement_m.shape[1]),
                "rms_displacement_m": np.sqrt(np.mean(self.displacement_m ** 2, axis=(0, 1))).tolist(),
                "rms_velocity_m_s": np.sqrt(np.mean(self.velocity_m_s ** 2, axis=(0, 1))).tolist()}

    def summary(self) -> str:
        """One line: trials, samples and the RMS displacement and rate per body axis."""
        d = self.to_dict()
        fmt = lambda v: "(" + ", ".join(f"{x:.3g}" for x in v) + ")"
        return (f"flexure: {d['trials']} trials × {d['samples']} samples at {self.dt_s:g} s; rms displacement "
                f"{fmt(d['rms_displacement_m'])} m, rate {fmt(d['rms_velocity_m_s'])} m/s")

    def to_frame(self):
        import pandas as pd
        t = np.arange(self.displacement_m.shape[1]) * self.dt_s
        rms = np.sqrt(np.mean(self.displacement_m ** 2, axis=0))
        return pd.DataFrame({"time_s": t, "rms_dx_m": rms[:, 0], "rms_dy_m": rms[:, 1],
                             "rms_dz_m": rms[:, 2]})


def simulate_flexure(mode: FlexureConfig, dt_s: float, n_samples: int, trials: int,
                     rng: np.random.Generator) -> FlexureHistory:
    """Exact discrete samples of the mode, started from its stationary distribution."""
    F, Qc, P = flexure_blocks(mode)
    phi, qd = van_loan(F, Qc, dt_s)
    x = sample_lti(phi, qd, sample_initial(P, trials, rng), n_samples, rng)
    return FlexureHistory(dt_s=float(dt_s), displacement_m=x[..., :3], velocity_m_s=x[..., 3:])


def antenna_flexure_error(displacement_m: np.ndarray, c_bn=None) -> np.ndarray:
    """Antenna position error from unseen flexure: C_bn d, (T, N, 3) in the n frame (m).

    ``c_bn`` (N, 3, 3) or (3, 3); identity (level flight along x) when omitted.
    """
    d = np.asarray(displacement_m, dtype=float)
    if c_bn is None:
        return d.copy()
    c = np.asarray(c_bn, dtype=float)
    if c.ndim == 2:
        return d @ c.T
    return np.einsum("nij,tnj->tni", c, d)
