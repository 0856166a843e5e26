"""Error-state INS model: state layout, continuous dynamics F, noise, Van Loan discretisation.

Frame and sign conventions (used by every module of :mod:`budget.aiding`)
--------------------------------------------------------------------------
* Navigation frame n: local level, flat earth over the aperture (no earth rate, no transport
  rate, no Schuler loop — the same model as the motion engine): x along-track, y cross-track
  toward the scene, z up. Body frame b: x forward, y left, z up, so ``C_bn = I`` in straight and
  level flight along x.
* Errors are *estimate minus truth*: δp = p̂ − p, δv = v̂ − v, sensor errors δf = f̂ − f and
  δω = ω̂ − ω.
* Attitude error φ (rad, n frame): Ĉ_b^n = (I − [φ×]) C_b^n (Titterton & Weston's φ-angle).
* Gravity g_n = (0, 0, −g); the specific force in level flight is f_n = (0, 0, +g).

Continuous error dynamics (task brief; Titterton & Weston (12.13) on a flat earth)::

    δṗ = δv
    δv̇ = −φ × f_n + C_b^n δf = [f_n×] φ + C_b^n (b_a + m_a + w_a)
    φ̇  = −C_b^n δω         = −C_b^n (b_g + m_g + w_g)

with b_g, b_a random constants (turn-on bias, optionally a random walk driven by the rate/
acceleration random walk K), m_g, m_a first-order Gauss–Markov biases (ṁ = −m/τ + w,
stationary σ) and w_g, w_a white noise (ARW, VRW). Sensor noise is isotropic (the same on every
axis), so the rotated noise C w has the same covariance as w and Q does not depend on attitude.

Check of the signs against seed 004's bound derivation: a gyro bias b about the along-track axis in level flight
gives φ_x = −b t, δv_y = −g b t²/2, δp_y = −g b t³/6 (magnitude g b Tc³/6 as in the derivation
of seed 004 (9)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import expm

from ..catalog.schema import ImuErrorsSI
from .. import units as u
from ..units import G0


def skew(v) -> np.ndarray:
    """[v×] for v of shape (..., 3): the matrix with [v×] u = v × u."""
    v = np.asarray(v, dtype=float)
    out = np.zeros(v.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


@dataclass(frozen=True)
class StateLayout:
    """Ordered named blocks of the error state; ``slice(name)`` gives the block's indices."""

    blocks: tuple[tuple[str, int], ...]

    @property
    def n(self) -> int:
        return sum(size for _, size in self.blocks)

    def has(self, name: str) -> bool:
        return any(b == name for b, _ in self.blocks)

    def slice(self, name: str) -> slice:
        start = 0
        for b, size in self.blocks:
            if b == name:
                return slice(start, start + size)
            start += size
        raise KeyError(f"no state block {name!r}; blocks are {[b for b, _ in self.blocks]}")

    def labels(self) -> list[str]:
        return [f"{b}_{i}" for b, size in self.blocks for i in range(size)]

    def with_blocks(self, extra: list[tuple[str, int]]) -> "StateLayout":
        names = [b for b, _ in self.blocks] + [b for b, _ in extra]
        if len(set(names)) != len(names):
            raise ValueError(f"duplicate state block names in {names}")
        return StateLayout(self.blocks + tuple(extra))


@dataclass(frozen=True)
class ImuErrorModel:
    """Filter/truth model of one IMU's errors, SI, per axis (the same on all three axes).

    ``*_bias_*`` random constant 1σ (turn-on bias left after alignment, rad/s or m/s²);
    ``*_gm_sigma_*``/``*_gm_tau_s`` first-order Gauss–Markov bias (stationary σ, correlation
    time); ``gyro_arw_rad_s_rt_hz`` (rad/√s) and ``accel_vrw_m_s2_rt_hz`` (m/s/√s) white noise;
    ``*_rrw_*`` random walk of the constant bias (rad/s/√s, m/s²/√s).
    """

    gyro_bias_rad_s: float = 0.0
    gyro_gm_sigma_rad_s: float = 0.0
    gyro_gm_tau_s: float = 100.0
    gyro_arw_rad_s_rt_hz: float = 0.0
    gyro_rrw_rad_s_rt_s: float = 0.0
    accel_bias_m_s2: float = 0.0
    accel_gm_sigma_m_s2: float = 0.0
    accel_gm_tau_s: float = 100.0
    accel_vrw_m_s2_rt_hz: float = 0.0
    accel_rrw_m_s2_rt_s: float = 0.0

    def __post_init__(self):
        for name, value in self.__dict__.items():
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"ImuErrorModel.{name} must be finite and ≥ 0, got {value!r}")
        if self.gyro_gm_tau_s <= 0 or self.accel_gm_tau_s <= 0:
            raise ValueError("Gauss–Markov correlation times must be > 0 s")

    @classmethod
    def from_imu_errors(cls, imu: ImuErrorsSI, *, gm_tau_s: float = 100.0) -> "ImuErrorModel":
        """From catalog SI errors: turn-on bias → random constant, bias instability → GM.

        The bias-instability floor B_adev (the Allan floor, 0.664·B) is modelled as a first-order
        Gauss–Markov process of σ = B_adev and correlation time ``gm_tau_s``; a GM process has
        its Allan-deviation maximum ≈ 0.62 σ at ≈ 1.9 τ, so this is a slightly pessimistic
        filter model of flicker noise (the usual choice).
        """
        return cls(
            gyro_bias_rad_s=imu.gyro_turn_on_bias_rad_s,
            gyro_gm_sigma_rad_s=imu.gyro_bias_instability_adev_rad_s, gyro_gm_tau_s=gm_tau_s,
            gyro_arw_rad_s_rt_hz=imu.gyro_arw_rad_s_rt_hz, gyro_rrw_rad_s_rt_s=imu.gyro_rrw_rad_s_rt_s,
            accel_bias_m_s2=imu.accel_turn_on_bias_m_s2,
            accel_gm_sigma_m_s2=imu.accel_bias_instability_adev_m_s2, accel_gm_tau_s=gm_tau_s,
            accel_vrw_m_s2_rt_hz=imu.accel_vrw_m_s2_rt_hz)

    @classmethod
    def from_datasheet(cls, *, gyro_bias_deg_h: float = 0.0, gyro_arw_deg_rt_h: float = 0.0,
                       accel_bias_ug: float = 0.0, accel_vrw_ug_rt_hz: float = 0.0, gyro_gm_deg_h: float = 0.0,
                       **si) -> "ImuErrorModel":
        """From datasheet units — gyro bias and Gauss–Markov σ deg/h, ARW deg/√h, accelerometer bias
        µg, VRW µg/√Hz — converted by :mod:`budget.units`; further SI fields (``gyro_gm_tau_s`` …)
        as keywords."""
        return cls(gyro_bias_rad_s=u.deg_h_to_rad_s(gyro_bias_deg_h),
                   gyro_gm_sigma_rad_s=u.deg_h_to_rad_s(gyro_gm_deg_h),
                   gyro_arw_rad_s_rt_hz=u.deg_rt_h_to_rad_s_rt_hz(gyro_arw_deg_rt_h),
                   accel_bias_m_s2=u.ug_to_m_s2(accel_bias_ug),
                   accel_vrw_m_s2_rt_hz=u.ug_rt_hz_to_m_s2_rt_hz(accel_vrw_ug_rt_hz), **si)

    def blocks(self) -> list[tuple[str, int]]:
        """INS state blocks: pos, vel, att always; bias blocks only when they have variance."""
        out = [("pos", 3), ("vel", 3), ("att", 3)]
        if self.gyro_bias_rad_s > 0 or self.gyro_rrw_rad_s_rt_s > 0:
            out.append(("gyro_bias", 3))
        if self.accel_bias_m_s2 > 0 or self.accel_rrw_m_s2_rt_s > 0:
            out.append(("accel_bias", 3))
        if self.gyro_gm_sigma_rad_s > 0:
            out.append(("gyro_gm", 3))
        if self.accel_gm_sigma_m_s2 > 0:
            out.append(("accel_gm", 3))
        return out


@dataclass(frozen=True)
class NominalTrajectory:
    """The error-free reference motion the error model is linearised about (shared by all trials).

    ``f_n`` specific force (N, 3) m/s², ``c_bn`` body→nav rotation (N, 3, 3), ``v_n`` velocity
    (N, 3) m/s on the grid t_k = k·dt_s, k = 0 … N−1.
    """

    dt_s: float
    f_n: np.ndarray
    c_bn: np.ndarray
    v_n: np.ndarray
    constant: bool = field(default=False)

    @property
    def n_samples(self) -> int:
        return int(self.f_n.shape[0])

    @property
    def time_s(self) -> np.ndarray:
        return np.arange(self.n_samples) * self.dt_s

    @classmethod
    def straight_level(cls, speed_m_s: float, dt_s: float, n_samples: int) -> "NominalTrajectory":
        """Straight and level flight along x at ``speed_m_s`` (f_n = (0, 0, g), C_bn = I)."""
        if not (dt_s > 0 and n_samples >= 2):
            raise ValueError("need dt_s > 0 and at least 2 samples")
        f = np.broadcast_to(np.array([0.0, 0.0, G0]), (n_samples, 3))
        c = np.broadcast_to(np.eye(3), (n_samples, 3, 3))
        v = np.broadcast_to(np.array([speed_m_s, 0.0, 0.0]), (n_samples, 3))
        return cls(dt_s=float(dt_s), f_n=f, c_bn=c, v_n=v, constant=True)

    @classmethod
    def from_arrays(cls, dt_s: float, f_n, c_bn, v_n) -> "NominalTrajectory":
        f_n, c_bn, v_n = (np.asarray(a, dtype=float) for a in (f_n, c_bn, v_n))
        n = f_n.shape[0]
        if f_n.shape != (n, 3) or c_bn.shape != (n, 3, 3) or v_n.shape != (n, 3) or n < 2:
            raise ValueError("f_n (N,3), c_bn (N,3,3) and v_n (N,3) must share N ≥ 2")
        if not (np.all(np.isfinite(f_n)) and np.all(np.isfinite(c_bn)) and np.all(np.isfinite(v_n))):
            raise ValueError("nominal trajectory arrays must be finite")
        return cls(dt_s=float(dt_s), f_n=f_n, c_bn=c_bn, v_n=v_n, constant=False)


def ins_dynamics(layout: StateLayout, imu: ImuErrorModel, f_n: np.ndarray, c_bn: np.ndarray):
    """Continuous F (…, n, n) for specific force f_n (…, 3) and attitude c_bn (…, 3, 3).

    Only the INS rows are filled; augmented blocks (measurement-error states) are added by
    :func:`budget.aiding.system.build_system`.
    """
    f_n = np.asarray(f_n, dtype=float)
    lead = f_n.shape[:-1]
    n = layout.n
    F = np.zeros(lead + (n, n))
    p, v, a = layout.slice("pos"), layout.slice("vel"), layout.slice("att")
    F[..., p, v] = np.eye(3)
    F[..., v, a] = skew(f_n)                       # −φ × f = [f×] φ
    if layout.has("accel_bias"):
        F[..., v, layout.slice("accel_bias")] = c_bn
    if layout.has("gyro_bias"):
        F[..., a, layout.slice("gyro_bias")] = -c_bn
    if layout.has("accel_gm"):
        s = layout.slice("accel_gm")
        F[..., v, s] = c_bn
        F[..., s, s] = -np.eye(3) / imu.accel_gm_tau_s
    if layout.has("gyro_gm"):
        s = layout.slice("gyro_gm")
        F[..., a, s] = -c_bn
        F[..., s, s] = -np.eye(3) / imu.gyro_gm_tau_s
    return F


def ins_noise(layout: StateLayout, imu: ImuErrorModel) -> np.ndarray:
    """Continuous process-noise spectral density G Qc Gᵀ (n, n) of the INS blocks (SI²/Hz)."""
    Q = np.zeros((layout.n, layout.n))
    i3 = np.eye(3)
    Q[layout.slice("vel"), layout.slice("vel")] = imu.accel_vrw_m_s2_rt_hz ** 2 * i3
    Q[layout.slice("att"), layout.slice("att")] = imu.gyro_arw_rad_s_rt_hz ** 2 * i3
    if layout.has("gyro_bias"):
        s = layout.slice("gyro_bias")
        Q[s, s] = imu.gyro_rrw_rad_s_rt_s ** 2 * i3
    if layout.has("accel_bias"):
        s = layout.slice("accel_bias")
        Q[s, s] = imu.accel_rrw_m_s2_rt_s ** 2 * i3
    if layout.has("gyro_gm"):
        s = layout.slice("gyro_gm")
        Q[s, s] = 2.0 * imu.gyro_gm_sigma_rad_s ** 2 / imu.gyro_gm_tau_s * i3
    if layout.has("accel_gm"):
        s = layout.slice("accel_gm")
        Q[s, s] = 2.0 * imu.accel_gm_sigma_m_s2 ** 2 / imu.accel_gm_tau_s * i3
    return Q


def ins_initial_covariance(layout: StateLayout, imu: ImuErrorModel, *, position_m, velocity_m_s,
                           attitude_rad) -> np.ndarray:
    """Diagonal P0 of the INS blocks: σ (scalar or 3-vector) for pos/vel/att, biases from ``imu``."""
    P = np.zeros((layout.n, layout.n))

    def put(name, sigma):
        s = layout.slice(name)
        P[s, s] = np.diag(np.broadcast_to(np.asarray(sigma, dtype=float), (3,)) ** 2)

    put("pos", position_m)
    put("vel", velocity_m_s)
    put("att", attitude_rad)
    if layout.has("gyro_bias"):
        put("gyro_bias", imu.gyro_bias_rad_s)
    if layout.has("accel_bias"):
        put("accel_bias", imu.accel_bias_m_s2)
    if layout.has("gyro_gm"):
        put("gyro_gm", imu.gyro_gm_sigma_rad_s)
    if layout.has("accel_gm"):
        put("accel_gm", imu.accel_gm_sigma_m_s2)
    return P


def expm_batched(M: np.ndarray, order: int = 12) -> np.ndarray:
    """Matrix exponential of a stack (…, m, m): scaling and squaring with a Taylor series.

    The stack is scaled by 2^-s so that its largest ∞-norm is ≤ 0.5; the truncation error of
    the order-12 series is then < 0.5¹³/13! ≈ 2e-14 (relative), and s squarings follow.
    Several times faster than looping :func:`scipy.linalg.expm` over short time steps.
    """
    norm = float(np.max(np.abs(M).sum(axis=-1))) if M.size else 0.0
    s = max(0, int(math.ceil(math.log2(norm / 0.5)))) if norm > 0.5 else 0
    A = M / (2.0 ** s)
    E = np.broadcast_to(np.eye(M.shape[-1]), M.shape).copy()
    term = E.copy()
    for k in range(1, order + 1):
        term = term @ A / k
        E += term
    for _ in range(s):
        E = E @ E
    return E


def van_loan(F: np.ndarray, Qc: np.ndarray, dt_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact discretisation of ẋ = F x + w, E[w wᵀ] = Qc δ(τ), over dt_s (Van Loan, 1978).

    exp([[−F, Qc], [0, Fᵀ]] dt) = [[·, Φ⁻¹ Qd], [0, Φᵀ]] → Φ = e^{F dt}, Qd = ∫ Φ(s) Qc Φ(s)ᵀ ds.
    ``F`` may be batched (…, n, n); ``Qc`` (n, n) or batched alike.
    """
    F = np.asarray(F, dtype=float)
    n = F.shape[-1]
    Qc = np.broadcast_to(np.asarray(Qc, dtype=float), F.shape)
    M = np.zeros(F.shape[:-2] + (2 * n, 2 * n))
    M[..., :n, :n] = -F
    M[..., :n, n:] = Qc
    M[..., n:, n:] = np.swapaxes(F, -1, -2)
    E = expm(M * dt_s) if M.ndim == 2 else expm_batched(M * dt_s)
    phi = np.swapaxes(E[..., n:, n:], -1, -2)
    qd = phi @ E[..., :n, n:]
    qd = 0.5 * (qd + np.swapaxes(qd, -1, -2))
    return phi, qd
