"""Seed 001: missile-borne slave IMU at the antenna corrected by transferred master-INS data.

Song & Wang (seed 001, §2.2 and §3): the M-SINS/SAR/CNS solution at the missile's centre of
mass is moved through a rigid lever arm (l = 2 m, θl = −20°, φl = 15°) to the slave IMU (S-IMU)
at the antenna phase centre and corrects it at 1 Hz with a linear Kalman filter (states:
misalignment, velocity and position error, gyro and accelerometer constant drifts). Simulation
conditions of the paper: S-IMU gyro constant drift 0.05 deg/h, random drift 0.005 deg/h;
accelerometer bias 0.5 mg, random 0.05 mg; 100 Hz; corrections at 1 Hz with
R = diag((0.02 m/s)²×3, (2 m)²×3); initial errors 10 m, 0.01 m/s, 50″; Gaussian noise of
0.1 m and 0.01 m/s added to the S-IMU solution; 200 m/s, 1200 s of flight.
Result to reproduce: within each imaging period the position error varies < 5 cm, the velocity
error < 0.001 m/s and the attitude error < 1″.

Modelling choices (the paper does not state them):
* "random drift" is white noise of the given σ per 100 Hz sample (ARW = σ·√dt), as in the
  usual Chinese SINS simulations; constant drift/bias are random constants of that 1σ;
* the master data errors are white with the filter's R (the filter's own assumption), and the
  0.1 m / 0.01 m/s solution noise enters the measurement, so the simulated measurement noise is
  √(2² + 0.1²) m and √(0.02² + 0.01²) m/s, used in R as well;
* the transfer uses the master attitude (rigid arm), so the lever arm cancels in the measurement;
* "variation within an imaging period" = peak-to-peak of the real-time filter's error over a
  window of that length, per axis, over sliding windows (step 0.1 s) in the last quarter of the
  flight; we report its median, 95th percentile and maximum over windows, axes and trials.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from .. import units as u
from ..aiding.chain import run_aided
from ..aiding.ins_error_model import ImuErrorModel, NominalTrajectory
from ..aiding.measurements import ARCSEC_RAD
from ..aiding.system import InitialUncertainty, build_system, simulate_truth
from ..aiding_spec import MasterInsAiding
from ..fileio import json_safe
from ..presets import get_preset
from .params import params_dict


@dataclass(frozen=True)
class MasterSlaveParams:
    """Seed 001 §3 conditions (defaults) and the size of the run."""

    speed_m_s: float = 200.0
    imu_rate_hz: float = 100.0
    duration_s: float = 1200.0
    trials: int = 10
    gyro_drift_deg_h: float = 0.05
    gyro_random_deg_h: float = 0.005
    accel_bias_mg: float = 0.5
    accel_random_mg: float = 0.05
    correction_rate_hz: float = 1.0
    sigma_position_m: float = 2.0
    sigma_velocity_m_s: float = 0.02
    solution_noise_position_m: float = 0.1
    solution_noise_velocity_m_s: float = 0.01
    initial_position_m: float = 10.0
    initial_velocity_m_s: float = 0.01
    initial_attitude_arcsec: float = 50.0
    imaging_periods_s: tuple[float, ...] = (1.0, 2.0, 3.0)
    evaluate_from_fraction: float = 0.75


def window_variation(err: np.ndarray, window: int, stride: int, start: int) -> np.ndarray:
    """Peak-to-peak of err (T, N, 3) over sliding windows of ``window`` samples → (T, W, 3)."""
    seg = np.lib.stride_tricks.sliding_window_view(err[:, start:], window, axis=1)[:, ::stride]
    return seg.max(axis=-1) - seg.min(axis=-1)


@dataclass
class MasterSlaveResult:
    """``table``: one row per (quantity, imaging period) with median/p95/max variation;
    ``final_rms``: RMS absolute error at the end of the flight (pos m, vel m/s, att arcsec)."""

    params: MasterSlaveParams
    table: pd.DataFrame
    final_rms: dict

    def to_dict(self) -> dict:
        """JSON-ready: the parameters, worst-period p95 variation per quantity, final RMS, table."""
        worst = self.table.groupby("quantity")["p95"].max().to_dict()
        return json_safe({"params": params_dict(self.params), "trials": self.params.trials,
                          "duration_s": self.params.duration_s, "p95_variation_worst_period": worst,
                          "final_rms": self.final_rms, "table": self.table.to_dict(orient="records")})

    def summary(self) -> str:
        """A few lines: trials, duration, the worst-period p95 variation per quantity, final RMS."""
        worst = self.table.groupby("quantity")["p95"].max()
        lines = [f"master–slave, {self.params.trials} trials over {self.params.duration_s:g} s; "
                 "p95 variation within an imaging period (worst period):"]
        lines += [f"  {q}: {v:.3g}" for q, v in worst.items()]
        lines.append("final rms: " + ", ".join(f"{k} {v:.3g}" for k, v in self.final_rms.items()))
        return "\n".join(lines)

    def to_frame(self) -> pd.DataFrame:
        return self.table.copy()


def run_master_slave(params: MasterSlaveParams = MasterSlaveParams(), *,
                     rng: np.random.Generator) -> MasterSlaveResult:
    dt = 1.0 / params.imu_rate_hz
    n = int(round(params.duration_s / dt)) + 1
    imu = ImuErrorModel(
        gyro_bias_rad_s=u.deg_h_to_rad_s(params.gyro_drift_deg_h),
        gyro_arw_rad_s_rt_hz=u.deg_h_to_rad_s(params.gyro_random_deg_h) * math.sqrt(dt),
        accel_bias_m_s2=u.mg_to_m_s2(params.accel_bias_mg),
        accel_vrw_m_s2_rt_hz=u.mg_to_m_s2(params.accel_random_mg) * math.sqrt(dt))
    aid = MasterInsAiding(
        rate_hz=params.correction_rate_hz,
        sigma_position_m=math.hypot(params.sigma_position_m, params.solution_noise_position_m),
        sigma_velocity_m_s=math.hypot(params.sigma_velocity_m_s, params.solution_noise_velocity_m_s),
        lever_arm_m=get_preset("missile_borne").lever_arm_m)
    traj = NominalTrajectory.straight_level(params.speed_m_s, dt, n)
    init = InitialUncertainty(params.initial_position_m, params.initial_velocity_m_s,
                              params.initial_attitude_arcsec * ARCSEC_RAD)
    system = build_system(traj, imu, [aid], init)
    truth = simulate_truth(system, params.trials, rng)
    res = run_aided(system, truth, rng)
    start = int(params.evaluate_from_fraction * (n - 1))
    stride = max(1, int(round(0.1 / dt)))
    rows = []
    for name, arr, scale in (("position_m", res.position_error_m, 1.0),
                             ("velocity_m_s", res.velocity_error_m_s, 1.0),
                             ("attitude_arcsec", res.attitude_error_rad, 1.0 / ARCSEC_RAD)):
        for period in params.imaging_periods_s:
            w = int(round(period / dt))
            var = window_variation(arr * scale, w, stride, start)
            rows.append({"quantity": name, "period_s": period, "median": float(np.median(var)),
                         "p95": float(np.percentile(var, 95)), "max": float(var.max())})
    last = lambda a: float(np.sqrt(np.mean(a[:, -1] ** 2)))
    final = {"position_m": last(res.position_error_m), "velocity_m_s": last(res.velocity_error_m_s),
             "attitude_arcsec": last(res.attitude_error_rad) / ARCSEC_RAD}
    return MasterSlaveResult(params, pd.DataFrame(rows), final)
