"""Large heading misalignment: a nonlinear error model, DDF2 and linear KF with RTS smoothing.

Seed 002 (their (1)–(5) and the DDF2 of Nørgaard, Poulsen & Ravn 2000): with a large
misalignment the error dynamics are no longer linear in the attitude error, and a smoother built
on the small-angle model loses accuracy; they propose a second-order divided-difference filter
(DDF2) forward pass with an RTS backward pass linearised by weighted statistical regression.

Model (horizontal channel of a level vehicle; errors = estimate − truth). State
x = [δp_x, δp_y, δv_x, δv_y, ψ, ε] — position, velocity, heading error, gyro-z bias. The INS
rotates the body specific force with its erroneous heading, Ĉ = R_z(−ψ) C, so

    δv̇_h = (R(−ψ) − I) f_h + w_a,   ψ̇ = −ε + w_g,   ε̇ = 0,   δṗ = δv

exactly (R(−ψ) ≈ I − ψ[e_z×] gives the small-angle [f×]φ of :mod:`.ins_error_model`).
Discretised with a step-midpoint rule over dt (f_h held, ψ at the midpoint). Measurements:
position and velocity matching to a master (linear: z = [δp, δv] + v).

* **KF-RTS**: the small-angle model, one covariance for all trials (linear, as in
  :mod:`.kalman`/:mod:`.rts`).
* **DDF2-RTS**: the DDF2 time update (Stirling interpolation, step h = √3) of the nonlinear
  model with a per-trial covariance; linear measurement update (Joseph form); the backward pass
  uses the DDF2 cross-covariance C_{k,k+1} = S_x S⁽¹⁾ᵀ as the statistical linearisation:
  A_k = C (P⁻_{k+1})⁻¹ (Särkkä 2008's sigma-point RTS form).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

H_DDF = np.sqrt(3.0)   # optimal interval length for Gaussian priors (Nørgaard et al. 2000)
N_STATE = 6


@dataclass(frozen=True)
class HeadingModel:
    """Nominal horizontal specific force ``f_h`` (N, 2) m/s² on a grid of ``dt_s``; white noise
    densities of accel (m/s/√s) and gyro (rad/√s)."""

    dt_s: float
    f_h: np.ndarray
    accel_noise: float
    gyro_noise: float

    @property
    def n_samples(self) -> int:
        return self.f_h.shape[0]

    def step(self, x: np.ndarray, k: int) -> np.ndarray:
        """Noise-free nonlinear transition of x (..., 6) from sample k to k+1."""
        dt = self.dt_s
        f = self.f_h[k]
        psi_mid = x[..., 4] - 0.5 * dt * x[..., 5]
        c, s = np.cos(psi_mid), np.sin(psi_mid)
        # (R(−ψ) − I) f with R(−ψ) = [[c, s], [−s, c]]
        acc = np.stack([(c - 1) * f[0] + s * f[1], -s * f[0] + (c - 1) * f[1]], axis=-1)
        out = x.copy()
        out[..., 0:2] = x[..., 0:2] + dt * x[..., 2:4] + 0.5 * dt * dt * acc
        out[..., 2:4] = x[..., 2:4] + dt * acc
        out[..., 4] = x[..., 4] - dt * x[..., 5]
        return out

    def jacobian_at_zero(self, k: int) -> np.ndarray:
        """Φ of the small-angle model at sample k (the KF's linear model)."""
        dt, (fx, fy) = self.dt_s, self.f_h[k]
        A = np.eye(N_STATE)
        A[0, 2] = A[1, 3] = dt
        dacc_dpsi = np.array([fy, -fx])           # derivative of (R(−ψ) − I) f at ψ = 0
        A[0:2, 4] = 0.5 * dt * dt * dacc_dpsi
        A[2:4, 4] = dt * dacc_dpsi
        A[0:2, 5] = -0.25 * dt ** 3 * dacc_dpsi
        A[2:4, 5] = -0.5 * dt * dt * dacc_dpsi
        A[4, 5] = -dt
        return A

    def process_noise(self) -> np.ndarray:
        """Qd of the white accelerometer and gyro noise over one step (first order in dt)."""
        dt, qa, qg = self.dt_s, self.accel_noise ** 2, self.gyro_noise ** 2
        Q = np.zeros((N_STATE, N_STATE))
        for i in (0, 1):
            Q[i, i], Q[i, i + 2], Q[i + 2, i], Q[i + 2, i + 2] = qa * dt ** 3 / 3, qa * dt ** 2 / 2, qa * dt ** 2 / 2, qa * dt
        Q[4, 4] = qg * dt
        return Q


def simulate_heading_truth(model: HeadingModel, P0: np.ndarray, trials: int,
                           rng: np.random.Generator) -> np.ndarray:
    """True errors (T, N, 6) from the nonlinear model, x0 ~ N(0, P0)."""
    Lq = np.linalg.cholesky(model.process_noise() + 1e-30 * np.eye(N_STATE))
    x = rng.standard_normal((trials, N_STATE)) @ np.linalg.cholesky(P0).T
    out = np.empty((trials, model.n_samples, N_STATE))
    out[:, 0] = x
    for k in range(model.n_samples - 1):
        x = model.step(x, k) + rng.standard_normal((trials, N_STATE)) @ Lq.T
        out[:, k + 1] = x
    return out


def _rts_gain(C: np.ndarray, P_prior: np.ndarray) -> np.ndarray:
    return np.linalg.solve(P_prior, np.swapaxes(C, -1, -2)).swapaxes(-1, -2)


def kf_rts(model: HeadingModel, z: np.ndarray, every: int, R: np.ndarray, P0: np.ndarray) -> np.ndarray:
    """Linear (small-angle) KF + RTS; z (T, E, 4) at samples every·j (j ≥ 1). Returns x̂ˢ (T, N, 6)."""
    T, N = z.shape[0], model.n_samples
    H = np.hstack([np.eye(4), np.zeros((4, 2))])
    Q = model.process_noise()
    x, P = np.zeros((T, N_STATE)), P0.copy()
    xs, Ps, Pp, As = np.empty((T, N, N_STATE)), np.empty((N, 6, 6)), np.empty((N, 6, 6)), np.empty((N, 6, 6))
    for k in range(N):
        if k > 0:
            A = model.jacobian_at_zero(k - 1)
            x, P = x @ A.T, A @ P @ A.T + Q
            As[k - 1] = A
        Pp[k] = P
        if k > 0 and k % every == 0 and k // every <= z.shape[1]:
            S = H @ P @ H.T + R
            K = np.linalg.solve(S, H @ P).T
            x = x + (z[:, k // every - 1] - x @ H.T) @ K.T
            IKH = np.eye(N_STATE) - K @ H
            P = IKH @ P @ IKH.T + K @ R @ K.T
        xs[:, k], Ps[k] = x, P
    for k in range(N - 2, -1, -1):
        G = _rts_gain(Ps[k] @ As[k].T, Pp[k + 1])
        xs[:, k] = xs[:, k] + (xs[:, k + 1] - xs[:, k] @ As[k].T) @ G.T
    return xs


def _ddf2_predict(model: HeadingModel, x: np.ndarray, P: np.ndarray, k: int, Q: np.ndarray):
    """DDF2 time update for every trial: x (T, n), P (T, n, n) → x̄, P̄, cross-cov C (T, n, n)."""
    n, h2 = N_STATE, H_DDF ** 2
    S = np.linalg.cholesky(P)                                   # (T, n, n), columns s_j
    pts = x[:, None, :] + H_DDF * np.swapaxes(S, 1, 2)          # (T, n, n): x + h s_j
    mts = x[:, None, :] - H_DDF * np.swapaxes(S, 1, 2)
    fp, fm, f0 = model.step(pts, k), model.step(mts, k), model.step(x, k)
    S1 = np.swapaxes((fp - fm) / (2 * H_DDF), 1, 2)             # columns S⁽¹⁾_j
    S2 = np.swapaxes(np.sqrt(h2 - 1) / (2 * h2) * (fp + fm - 2 * f0[:, None, :]), 1, 2)
    xbar = (h2 - n) / h2 * f0 + (fp + fm).sum(axis=1) / (2 * h2)
    Pbar = S1 @ np.swapaxes(S1, 1, 2) + S2 @ np.swapaxes(S2, 1, 2) + Q
    C = S @ np.swapaxes(S1, 1, 2)                               # cov(x_k, x_{k+1})
    return xbar, 0.5 * (Pbar + np.swapaxes(Pbar, 1, 2)), C


def ddf2_rts(model: HeadingModel, z: np.ndarray, every: int, R: np.ndarray, P0: np.ndarray) -> np.ndarray:
    """DDF2 forward filter + statistically linearised RTS; per-trial covariance. x̂ˢ (T, N, 6)."""
    T, N = z.shape[0], model.n_samples
    H = np.hstack([np.eye(4), np.zeros((4, 2))])
    Q = model.process_noise()
    x, P = np.zeros((T, N_STATE)), np.broadcast_to(P0, (T, 6, 6)).copy()
    xf, Pf = np.empty((T, N, 6)), np.empty((T, N, 6, 6))
    xp, Pp, Cs = np.empty((T, N, 6)), np.empty((T, N, 6, 6)), np.empty((T, N, 6, 6))
    for k in range(N):
        if k > 0:
            x, P, Cs[:, k - 1] = _ddf2_predict(model, x, P, k - 1, Q)
        xp[:, k], Pp[:, k] = x, P
        if k > 0 and k % every == 0 and k // every <= z.shape[1]:
            S = H @ P @ H.T + R
            K = np.swapaxes(np.linalg.solve(S, H @ P), 1, 2)     # (T, n, m)
            x = x + np.einsum("tij,tj->ti", K, z[:, k // every - 1] - x @ H.T)
            IKH = np.eye(N_STATE) - K @ H
            P = IKH @ P @ np.swapaxes(IKH, 1, 2) + K @ R @ np.swapaxes(K, 1, 2)
            P = 0.5 * (P + np.swapaxes(P, 1, 2))
        xf[:, k], Pf[:, k] = x, P
    xs = xf[:, -1].copy()
    out = np.empty_like(xf)
    out[:, -1] = xs
    for k in range(N - 2, -1, -1):
        G = _rts_gain(Cs[:, k], Pp[:, k + 1])
        xs = xf[:, k] + np.einsum("tij,tj->ti", G, xs - xp[:, k + 1])
        out[:, k] = xs
    return out
