"""Error-state Kalman filter vectorised over Monte Carlo trials (Joseph-form update).

Why one covariance serves every trial
-------------------------------------
In a linear(ised) Kalman filter the covariance recursion

    P⁻_k = Φ P⁺_{k−1} Φᵀ + Qd,   K = P⁻ Hᵀ (H P⁻ Hᵀ + R)⁻¹,   P⁺ = (I − K H) P⁻ (I − K H)ᵀ + K R Kᵀ

does not depend on the measurements, only on Φ, Qd, H, R and P0. All trials of a Monte Carlo
run share the nominal trajectory, the sensor schedule and the noise levels, so P and K are
computed **once** per step and the gain is applied to the state estimates of all T trials as a
batch: x̂ (T, n) ← x̂ Φᵀ, x̂ ← x̂ + (z − x̂ Hᵀ) Kᵀ. A run of T trials then costs one n×n covariance
recursion plus (T, n)×(n, n) products — the Monte Carlo costs almost nothing per extra trial.
(The Joseph form keeps P symmetric positive definite in finite precision even when the gain is
not exactly optimal.)

The filter is run open loop (feed-forward): it estimates the INS error; the corrected solution
error is x − x̂. For the linear error model this is identical to closed-loop correction.

Latency: a measurement valid at sample k with latency L arrives at k + L. The filter processes
it at its validity time (the estimate x̂_k after all measurements — what post-processing uses
and what the consistency tests check); the *real-time* output at sample i only contains the
corrections of measurements with k + L ≤ i (the others are subtracted, propagated by Φ).
That is the exact output of a real-time filter that buffers and re-processes late data.

Blended (feed-forward) output: with ``blend_steps`` = τ/dt, each correction that has arrived is
not applied at once but fed to the navigation solution through two first-order stages of time
constant τ (critically damped: a correction Δ reaches the output as Δ·[1 − (1 + t/τ)e^{−t/τ}],
mean delay 2τ, continuous in value and slope). The pending parts d₁, d₂ propagate with the
error model; per step, with a = e^{−dt/τ}: d₂ ← a·Φd₂ + (1 − a)·Φd₁, d₁ ← a·Φd₁, and
d₁ ← d₁ + Δx̂ when an update arrives. The navigation output is x̂ − d₁ − d₂: no steps and no
kinks at the fixes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from .system import AidedSystem, TransitionCache

#: at most this many steps between checkpoints kept for the smoother (bounds its memory)
MAX_INTERVAL = 2000


@dataclass
class FilterOutput:
    """Result of :func:`run_kalman`.

    ``estimate`` (T, N, s) — x̂ of the stored components (``store_index`` into the filter
    state) after all measurements valid up to each sample; ``realtime`` (T, N, s) the same
    honouring latency (``estimate`` itself when no measurement has latency); ``p_diag`` (N, n)
    the variances; checkpoints (for the smoother and NEES): sample indices, x̂⁺ (T, C, n),
    P⁺ (C, n, n), P⁻ (C, n, n); ``innovations`` name → (ν (T, E, m), S (E, m, m));
    ``blended`` (T, N, s) the feed-forward output (``None`` unless ``blend_steps`` was given).
    """

    store_index: np.ndarray
    estimate: np.ndarray
    realtime: np.ndarray
    p_diag: np.ndarray
    checkpoints: np.ndarray
    x_post: np.ndarray
    p_post: np.ndarray
    p_prior: np.ndarray
    innovations: dict = field(default_factory=dict)
    blended: np.ndarray | None = None

    def to_dict(self) -> dict:
        """JSON-ready: trials, samples, states, checkpoints and the updates per measurement."""
        T, N, _ = self.estimate.shape
        return {"trials": T, "samples": N, "states": int(self.p_diag.shape[1]),
                "store_index": np.asarray(self.store_index).tolist(),
                "checkpoints": int(self.checkpoints.size), "blended": self.blended is not None,
                "updates": {k: int(v[0].shape[1]) for k, v in self.innovations.items()}}

    def summary(self) -> str:
        """One line: trials, samples, states and the updates per measurement."""
        d = self.to_dict()
        ups = ", ".join(f"{k} {v}" for k, v in d["updates"].items()) or "none"
        return (f"Kalman filter: {d['trials']} trials × {d['samples']} samples, {d['states']} states, "
                f"{d['checkpoints']} checkpoints; updates: {ups}")

    def to_frame(self) -> pd.DataFrame:
        """Predicted 1σ of every state per sample (columns ``sigma_<index>``)."""
        return pd.DataFrame(np.sqrt(np.clip(self.p_diag, 0, None)),
                            columns=[f"sigma_{i}" for i in range(self.p_diag.shape[1])])


def store_indices(system: AidedSystem, store=("pos", "vel", "att")) -> np.ndarray:
    lay = system.layout["filter"]
    return np.concatenate([np.arange(lay.n)[lay.slice(b)] for b in store])


def _events(system: AidedSystem) -> dict[int, list]:
    ev: dict[int, list] = {}
    for m in system.measurements:
        for j, k in enumerate(system.epochs[m.name]):
            ev.setdefault(int(k), []).append((m, j))
    return ev


def joseph_update(P: np.ndarray, H: np.ndarray, R: np.ndarray):
    """Gain K, innovation covariance S and Joseph-form P⁺ for one (shared) update."""
    PHt = P @ H.T
    S = H @ PHt + R
    S = 0.5 * (S + S.T)
    K = np.linalg.solve(S, PHt.T).T
    IKH = np.eye(P.shape[0]) - K @ H
    Pn = IKH @ P @ IKH.T + K @ R @ K.T
    return K, S, 0.5 * (Pn + Pn.T)


def run_kalman(system: AidedSystem, z: dict[str, np.ndarray], *, store=("pos", "vel", "att"),
               x0: np.ndarray | None = None, blend_steps: float | None = None) -> FilterOutput:
    """Run the filter over all samples for every trial; ``z`` from
    :func:`~budget.aiding.system.simulate_measurements` (name → (T, E, m)). ``blend_steps``
    (τ/dt > 0) also forms the feed-forward output (module docstring)."""
    N = system.n_samples
    lay = system.layout["filter"]
    n = lay.n
    T = next(iter(z.values())).shape[0] if z else (1 if x0 is None else x0.shape[0])
    for name, arr in z.items():
        if arr.shape[0] != T or not np.all(np.isfinite(arr)):
            raise ValueError(f"measurements {name!r} must be finite with {T} trials")
    sel = store_indices(system, store)
    x = np.zeros((T, n)) if x0 is None else np.array(x0, dtype=float)
    P = system.P0("filter").copy()
    trans = TransitionCache(system, "filter")
    events = _events(system)
    lat = {m.name: m.latency_steps(system.dt_s) for m in system.measurements}
    any_latency = any(v > 0 for v in lat.values())
    est = np.empty((T, N, sel.size))
    rt = np.empty((T, N, sel.size)) if any_latency else est
    p_diag = np.empty((N, n))
    ck_k, ck_x, ck_post, ck_prior = [], [], [], []
    innov = {m.name: (np.empty((T, len(system.epochs[m.name]), m.size)),
                      np.empty((len(system.epochs[m.name]), m.size, m.size)))
             for m in system.measurements}
    pending: list[list] = []  # [expiry sample, correction (T, n)]
    blend = None if blend_steps is None else np.empty((T, N, sel.size))
    keep = 1.0 if blend_steps is None else float(np.exp(-1.0 / blend_steps))
    d = np.zeros((T, n))   # arrived corrections waiting in the first blend stage
    d2 = np.zeros((T, n))  # … and in the second
    last_ck = 0
    for k in range(N):
        if k > 0:
            phi, qd = trans.get(k - 1)
            x = x @ phi.T
            P = phi @ P @ phi.T + qd
            for p in pending:
                p[1] = p[1] @ phi.T
            if blend is not None:
                d = d @ phi.T
                d2 = (d2 @ phi.T) * keep + d * (1.0 - keep)
                d *= keep
        prior = P
        for m, j in events.get(k, ()):
            H = system.H("filter", m, k)
            R = system.R_filter(m, k)
            K, S, P = joseph_update(P, H, R)
            nu = z[m.name][:, j] - x @ H.T
            dx = nu @ K.T
            x = x + dx
            innov[m.name][0][:, j] = nu
            innov[m.name][1][j] = S
            if lat[m.name] > 0:
                pending.append([k + lat[m.name], dx])
            elif blend is not None:
                d = d + dx
        if k in events or k == 0 or k == N - 1 or k - last_ck >= MAX_INTERVAL:
            ck_k.append(k)
            ck_x.append(x.copy())
            ck_post.append(P.copy())
            ck_prior.append(prior.copy())
            last_ck = k
        est[:, k] = x[:, sel]
        if any_latency:
            if blend is not None:  # corrections arriving now join the blend
                for p in pending:
                    if p[0] <= k:
                        d = d + p[1]
            pending = [p for p in pending if p[0] > k]
            xr = x - sum(p[1] for p in pending) if pending else x
            rt[:, k] = xr[:, sel]
        if blend is not None:
            blend[:, k] = rt[:, k] - d[:, sel] - d2[:, sel]
        p_diag[k] = np.diag(P)
    return FilterOutput(store_index=sel, estimate=est, realtime=rt, p_diag=p_diag,
                        checkpoints=np.array(ck_k), x_post=np.stack(ck_x, axis=1),
                        p_post=np.stack(ck_post), p_prior=np.stack(ck_prior), innovations=innov,
                        blended=blend)
