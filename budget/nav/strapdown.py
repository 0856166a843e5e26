"""Linearised strapdown error propagation over the aperture (flat earth, local-level frame).

Conventions (seed 000 (8)–(10)); every δ here is *computed − true*:

* attitude error φ (nav frame): computed DCM C̃ = (I − [φ×])·C, so φ̇ = −C·ε_b and
  φ(t) = φ0 − ∫ C·ε dt (seed 000 (9));
* velocity error: δv̇ = C·δf_b + f_n × φ, identical to seed 000 (10)
  δa = δa_σ + φ × (g − a) because f_n = a − g;
* position error δṗ = δv; at the antenna phase centre with body lever arm d (IMU → APC):
  δp_APC = δp + (C·d) × φ, the linearised (A[θ̂] − A[θ])·d of seed 000 (7).

Discretisation: each sensor sample k stands for the interval [t_k, t_k + dt) (an IMU output is
an increment over its interval). φ is integrated by the rectangle rule (exact for piecewise
constant rates), the force error uses φ at the interval midpoint, δv by the rectangle rule and
δp by the trapezoid rule — exact for a bias and for gyro-bias tilt up to a g·b·t·dt²/12 term.
Cumulative sums over axis 1; no loop over samples.

Why flat earth is enough: the neglected terms are the Schuler coupling (period 84.4 min, relative
effect ≈ (ω_s·Tc)²/12 = 0.18 % at Tc = 120 s), Coriolis and Earth-rate couplings
(≈ Ω·Tc/3 ≈ 0.3 % at 120 s) and transport-rate terms (≈ V·Tc/(3R) ≈ 0.13 % at 200 m/s, 120 s).
``budget.nav.earth`` integrates the model with those terms; the tests compare both: < 2 % apart
for Tc ≤ 2 min, tens of % at 30 min.

One Earth term is kept, because it is first order in an *initial* error rather than a small
correction to one: the local-level frame turns at ω_in = ω_ie + ω_en (Earth and transport rate),
which turns an initial attitude error at −ω_in × φ0. For an initial heading error ψ this is a
tilt rate Ω·cos L·ψ (0.15 deg/h for ψ = 10 mrad at the equator) plus up to V·ψ/R about the
other horizontal axis (0.065 deg/h at 200 m/s): the flat model without it gives *no* position
error for a heading error in level flight, with it the g·|ω_in × φ0|·t³/6 the full model gives.
``frame_rate_n_rad_s`` (ω_in in the nav frame, :func:`budget.nav.earth.navigation_frame_rate`)
adds it as a constant nav-frame rate −ω_in × φ0 per trial (a gyro-equivalent −Cᵀ(ω_in × φ0)).
What still differs from the full model for a heading error alone is O(Ω·t) (the frame rate
acting on the tilt the term builds, Coriolis, the transport rate of the velocity error) and
O((ω_s·t)²) (Schuler), bounded relative to the error by
(|ω_in| + |2ω_ie + ω_en| + V/(R·cos L))·t/4 + (ω_s·t)²/20: at 45° latitude and 200 m/s 0.27 %
at 30 s and 1.2 % at 120 s (measured against ``budget.nav.earth``: ≤ 0.16 % and ≤ 0.66 %).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from ..units import G0

_vec = tuple[float, float, float]


class InitialErrors(BaseModel):
    """1σ initial errors per nav axis (x along-track, y cross-track, z up), drawn per trial."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    position_sigma_m: _vec = Field((0.0, 0.0, 0.0))
    velocity_sigma_m_s: _vec = Field((0.0, 0.0, 0.0))
    attitude_sigma_rad: _vec = Field((0.0, 0.0, 0.0))

    @model_validator(mode="after")
    def _finite_non_negative(self) -> "InitialErrors":
        for name in ("position_sigma_m", "velocity_sigma_m_s", "attitude_sigma_rad"):
            v = getattr(self, name)
            if not all(np.isfinite(v)) or min(v) < 0:
                raise ValueError(f"{name} must hold three finite numbers ≥ 0")
        return self

    def draw(self, n_trials: int, rng: np.random.Generator) -> dict[str, np.ndarray | None]:
        """Per-trial draws ``{'dp0', 'dv0', 'phi0'}`` of shape (T, 3) (None where σ = 0)."""
        out = {}
        for key, name in (("dp0", "position_sigma_m"), ("dv0", "velocity_sigma_m_s"),
                          ("phi0", "attitude_sigma_rad")):
            sig = np.asarray(getattr(self, name))
            out[key] = rng.standard_normal((n_trials, 3)) * sig if sig.any() else None
        return out


#: 1σ initial errors of a coarse alignment (1 m, 0.1 m/s, 1 mrad per axis): the default start of
#: an aided run's warm-up, and the aiding filter's initial 1σ there (it converges in the warm-up).
COARSE_ALIGNMENT = InitialErrors(position_sigma_m=(1.0, 1.0, 1.0), velocity_sigma_m_s=(0.1, 0.1, 0.1),
                                 attitude_sigma_rad=(1e-3, 1e-3, 1e-3))


@dataclass
class NavErrors:
    """Computed − true errors, (T, N, 3): ``apc_position_m`` always; the others if kept."""

    apc_position_m: np.ndarray
    attitude_rad: np.ndarray | None = None
    velocity_m_s: np.ndarray | None = None
    position_m: np.ndarray | None = None


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b over the last axis with broadcasting (faster than ``np.cross`` for small blocks)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def _shifted_cumsum(x: np.ndarray) -> np.ndarray:
    """S_k = Σ_{j<k} x_j along axis 1 (S_0 = 0)."""
    out = np.empty_like(x)
    out[:, 0] = 0.0
    np.cumsum(x[:, :-1], axis=1, out=out[:, 1:])
    return out


def propagate_errors(gyro_err_rad_s: np.ndarray, accel_err_m_s2: np.ndarray, dt_s: float, *,
                     force_n_m_s2: np.ndarray | None = None, c_b_n: np.ndarray | None = None,
                     lever_arm_b_m=None, phi0=None, dv0=None, dp0=None,
                     frame_rate_n_rad_s=None, keep_states: bool = False) -> NavErrors:
    """Propagate body-frame sensor errors (T, N, 3) into navigation errors (computed − true).

    ``force_n_m_s2``: true specific force in the nav frame, (N, 3) or (T, N, 3); default
    (0, 0, +G0) (level unaccelerated flight). ``c_b_n``: body→nav DCM (N|T,N, 3, 3); default
    identity. ``lever_arm_b_m``: IMU → APC in the body frame (m). ``phi0``/``dv0``/``dp0``:
    initial errors (T, 3) or (3,). ``frame_rate_n_rad_s``: the nav frame's rate ω_in (3,) rad/s
    (Earth + transport rate); with ``phi0`` it adds the attitude rate −ω_in × φ0 (module
    docstring); default None (none). Returns :class:`NavErrors`; states at t_k = k·dt.
    """
    eps = np.asarray(gyro_err_rad_s, dtype=float)
    dfb = np.asarray(accel_err_m_s2, dtype=float)
    if eps.ndim != 3 or eps.shape[2] != 3 or dfb.shape != eps.shape:
        raise ValueError("gyro and accel errors must both have shape (trials, samples, 3)")
    if c_b_n is not None:
        eps = np.matmul(c_b_n, eps[..., None])[..., 0]
        dfb = np.matmul(c_b_n, dfb[..., None])[..., 0]

    # Scale the inputs once so that each cumulative sum gives a state directly.
    rot_step = eps * -dt_s                                   # −ε·dt: attitude increment
    if phi0 is not None and frame_rate_n_rad_s is not None:  # − ω_in × φ0: the frame turning φ0
        rot_step -= cross(np.asarray(frame_rate_n_rad_s, dtype=float),
                          np.asarray(phi0, dtype=float).reshape(-1, 1, 3)) * dt_s
    phi = _shifted_cumsum(rot_step)                          # φ_k − φ0
    if phi0 is not None:
        phi += np.asarray(phi0, dtype=float).reshape(-1, 1, 3)
    step = dfb * dt_s**2                                     # dt × velocity increment C·δf·dt
    if force_n_m_s2 is None:  # f = (0, 0, g): f × φ̄ = (−g·φ̄_y, g·φ̄_x, 0), φ̄ = φ − ε·dt/2
        gdt2 = G0 * dt_s**2
        step[..., 0] -= gdt2 * (phi[..., 1] + 0.5 * rot_step[..., 1])
        step[..., 1] += gdt2 * (phi[..., 0] + 0.5 * rot_step[..., 0])
    else:
        step += cross(np.asarray(force_n_m_s2, dtype=float), phi + 0.5 * rot_step) * dt_s**2
    del rot_step

    vel_dt = _shifted_cumsum(step)                           # dt·(δv_k − δv0)
    if dv0 is not None:
        vel_dt += dt_s * np.asarray(dv0, dtype=float).reshape(-1, 1, 3)
    vel = vel_dt / dt_s if keep_states else None
    # Position increment over interval j by the trapezoid rule: dt·(v_j + v_{j+1})/2
    # = dt·v_j + dt²·δf_j/2.
    step *= 0.5
    step += vel_dt
    del vel_dt
    pos = _shifted_cumsum(step)
    del step
    if dp0 is not None:
        pos += np.asarray(dp0, dtype=float).reshape(-1, 1, 3)

    apc = pos.copy() if keep_states else pos
    if lever_arm_b_m is not None and np.any(lever_arm_b_m):
        d = np.asarray(lever_arm_b_m, dtype=float)
        if c_b_n is None:  # (d × φ) component by component, in place
            apc[..., 0] += d[1] * phi[..., 2] - d[2] * phi[..., 1]
            apc[..., 1] += d[2] * phi[..., 0] - d[0] * phi[..., 2]
            apc[..., 2] += d[0] * phi[..., 1] - d[1] * phi[..., 0]
        else:
            apc += cross(np.matmul(c_b_n, d), phi)
    if keep_states:
        return NavErrors(apc_position_m=apc, attitude_rad=phi, velocity_m_s=vel, position_m=pos)
    return NavErrors(apc_position_m=apc)
