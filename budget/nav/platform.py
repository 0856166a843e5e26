"""True platform motion over the aperture: straight flight at V plus optional disturbances.

Frame (local level, right-handed, used throughout ``budget.nav`` and ``budget.motion``):
x along-track (velocity direction), y horizontal cross-track toward the imaged side, z up
(so the scene lies on the left of the flight direction). Attitude: body-to-nav DCM
C = Rz(yaw)·Ry(pitch)·Rx(roll) (rotations about the nav z, y, x axes; seed 000 (6) writes the
same three elementary rotations). Gravity g_n = (0, 0, −G0).

Disturbances are displacements of the IMU reference point (surge x, sway y, heave z, m) and
Euler angles (roll, pitch, yaw, rad), either sinusoidal (ship or vehicle motion) or random with
a given one-sided PSD. Everything true is derived from the same analytic series, so position,
velocity, acceleration, attitude and body rates are mutually consistent:
specific force f_n = a_n − g_n, body specific force f_b = Cᵀ·f_n, body rate from the Euler
rates ω_b = (ṙ − ẏ·sin p, ṗ·cos r + ẏ·sin r·cos p, −ṗ·sin r + ẏ·cos r·cos p).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from ..errors import InputError, from_validation_error, refuse_bool_numbers
from ..structured import read_structured
from ..units import G0

TRANSLATION_AXES = ("surge", "sway", "heave")
#: Highest disturbance frequency simulated, as a fraction of the IMU rate: the motion error of a
#: scale factor or misalignment on a component at f is then right to (πf/rate)²/6 ≤ 1.6 %
#: (:func:`true_motion`); Nyquist alone would allow a 90 Hz motion at 200 Hz, simulated at 32 %.
MAX_FREQUENCY_FRACTION = 0.1
#: Largest displacement amplitude (sinusoid peak, random rms) of a disturbance, m.
MAX_DISPLACEMENT_M = 1000.0
#: Largest attitude amplitude (sinusoid peak, random rms) of a disturbance, rad: beyond it the
#: attitude leaves the range a "disturbance" of straight flight describes.
MAX_ANGLE_RAD = 1.0
ROTATION_AXES = ("roll", "pitch", "yaw")
Axis = Literal["surge", "sway", "heave", "roll", "pitch", "yaw"]


class SinusoidalMotion(BaseModel):
    """A·sin(2πft + φ) on one axis: ``amplitude_m`` for surge/sway/heave, ``amplitude_rad`` for
    roll/pitch/yaw (peak)."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    axis: Axis
    frequency_hz: float = Field(..., gt=0, allow_inf_nan=False)
    amplitude_m: float | None = Field(None, ge=0, le=MAX_DISPLACEMENT_M, allow_inf_nan=False)
    amplitude_rad: float | None = Field(None, ge=0, le=MAX_ANGLE_RAD, allow_inf_nan=False)
    phase_rad: float = Field(0.0, allow_inf_nan=False)

    @model_validator(mode="after")
    def _unit_matches_axis(self) -> "SinusoidalMotion":
        _check_unit(self.axis, self.amplitude_m, self.amplitude_rad, "amplitude")
        return self

    @property
    def amplitude(self) -> float:
        return float(self.amplitude_m if self.axis in TRANSLATION_AXES else self.amplitude_rad)


class RandomMotion(BaseModel):
    """Gaussian random motion on one axis with a one-sided PSD given as a table.

    ``psd_m2_per_hz`` (translations) or ``psd_rad2_per_hz`` (rotations) at ``frequency_hz``
    (increasing, > 0); interpolated log-log between points, zero outside the table. Each trial
    draws its own realisation.
    """

    model_config = ConfigDict(extra="forbid", frozen=True)
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    axis: Axis
    frequency_hz: tuple[float, ...] = Field(..., min_length=2)
    psd_m2_per_hz: tuple[float, ...] | None = None
    psd_rad2_per_hz: tuple[float, ...] | None = None

    @model_validator(mode="after")
    def _check_table(self) -> "RandomMotion":
        _check_unit(self.axis, self.psd_m2_per_hz, self.psd_rad2_per_hz, "psd")
        psd = self.psd
        f = np.asarray(self.frequency_hz)
        if len(psd) != len(f):
            raise ValueError("frequency_hz and the PSD column must have the same length")
        if not (np.all(np.isfinite(f)) and np.all(f > 0) and np.all(np.diff(f) > 0)):
            raise ValueError("frequency_hz must be finite, > 0 and strictly increasing (Hz)")
        p = np.asarray(psd)
        if not (np.all(np.isfinite(p)) and np.all(p > 0)):
            raise ValueError("PSD values must be finite and > 0 (use fewer points to model a band)")
        limit, unit = (MAX_DISPLACEMENT_M, "m") if self.axis in TRANSLATION_AXES else (MAX_ANGLE_RAD, "rad")
        if self.rms > limit:
            raise ValueError(f"the {self.axis} PSD table integrates to {self.rms:.3g} {unit} rms; "
                             f"expected ≤ {limit:g} {unit} (as for a sinusoid's amplitude)")
        return self

    @property
    def rms(self) -> float:
        """Root of the PSD integrated over the table (m or rad rms; log-log interpolation)."""
        f = np.geomspace(self.frequency_hz[0], self.frequency_hz[-1], 4097)
        return float(math.sqrt(np.trapezoid(self.psd_at(f), f)))

    @property
    def psd(self) -> tuple[float, ...]:
        return self.psd_m2_per_hz if self.axis in TRANSLATION_AXES else self.psd_rad2_per_hz

    def psd_at(self, f_hz: np.ndarray) -> np.ndarray:
        """One-sided PSD at ``f_hz`` (log-log interpolation, 0 outside the table)."""
        f = np.asarray(f_hz, dtype=float)
        lf, lp = np.log(self.frequency_hz), np.log(self.psd)
        inside = (f >= self.frequency_hz[0]) & (f <= self.frequency_hz[-1])
        out = np.zeros(f.shape)
        out[inside] = np.exp(np.interp(np.log(f[inside]), lf, lp))
        return out


def _check_unit(axis: str, trans, rot, what: str) -> None:
    if axis in TRANSLATION_AXES and (trans is None or rot is not None):
        raise ValueError(f"{axis} is a translation: give {what}_m{'' if what == 'amplitude' else '2_per_hz'} only")
    if axis in ROTATION_AXES and (rot is None or trans is not None):
        raise ValueError(f"{axis} is a rotation: give {what}_rad{'' if what == 'amplitude' else '2_per_hz'} only")


class Disturbance(BaseModel):
    """Platform disturbance: any number of sinusoidal and random components (they add)."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    sinusoids: tuple[SinusoidalMotion, ...] = ()
    random: tuple[RandomMotion, ...] = ()

    @model_validator(mode="after")
    def _not_empty(self) -> "Disturbance":
        if not (self.sinusoids or self.random):
            raise ValueError("a disturbance needs at least one component (sinusoids and/or random)")
        return self

    @property
    def is_random(self) -> bool:
        return bool(self.random)

    @property
    def has_rotation(self) -> bool:
        return any(c.axis in ROTATION_AXES for c in (*self.sinusoids, *self.random))

    def max_frequency_hz(self) -> float:
        return max([s.frequency_hz for s in self.sinusoids] + [r.frequency_hz[-1] for r in self.random],
                   default=0.0)

    def check_imu_rate(self, imu_rate_hz: float) -> None:
        """Refuse (:class:`InputError` naming ``imu_rate_hz``) content above
        :data:`MAX_FREQUENCY_FRACTION` of the IMU rate: the one rule the Monte Carlo and the
        analytic check (:func:`budget.bounds.rotation.motion_excursion`) share."""
        f_max = self.max_frequency_hz()
        if f_max > MAX_FREQUENCY_FRACTION * imu_rate_hz:
            raise InputError(f"disturbance content up to {f_max:g} Hz needs an IMU rate of at least "
                             f"{f_max / MAX_FREQUENCY_FRACTION:g} Hz (10× its highest frequency: the motion error "
                             "of a scale factor or misalignment on it is then right to 1.6 %)", field="imu_rate_hz",
                             value=imu_rate_hz)

    @classmethod
    def load(cls, path: str | Path) -> "Disturbance":
        """Read a disturbance JSON (or YAML) file with the limits of :func:`~budget.structured.read_structured`;
        problems raise :class:`InputError` naming file and field."""
        path = Path(path)
        data = read_structured(path, "a disturbance")
        try:
            return cls.model_validate(data)
        except ValidationError as err:
            raise from_validation_error(err, file=path) from None


@dataclass
class TrueMotion:
    """True kinematics at the IMU samples. Arrays are (N, …) if deterministic, (T, N, …) if random.

    ``position_m``: IMU position in the nav frame, origin at the nominal position at the
    aperture centre. ``c_b_n``: body→nav DCM (None = identity throughout). ``force_n_m_s2`` and
    ``force_b_m_s2``: specific force; ``rate_b_rad_s``: body angular rate. With an IMU interval
    (:func:`true_motion`'s ``imu_dt_s``) the body rate and body specific force are those of each
    interval's midpoint, what the IMU sample of that interval stands for; the rest is at the samples.
    """

    time_s: np.ndarray
    position_m: np.ndarray
    force_n_m_s2: np.ndarray
    force_b_m_s2: np.ndarray
    rate_b_rad_s: np.ndarray
    c_b_n: np.ndarray | None


def _random_coefficients(comp: RandomMotion, n_trials: int, duration_s: float,
                         rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One realisation per trial of ``comp`` as a random Fourier series on the grid
    f_k = k/(2·duration): (f (K,), a (T, K), b (T, K)) with amplitudes √(S(f_k)·Δf)·N(0, 1)."""
    df = 1.0 / (2.0 * duration_s)
    kmax = int(math.floor(comp.frequency_hz[-1] / df)) + 1
    f = df * np.arange(1, kmax + 1)
    amp = np.sqrt(comp.psd_at(f) * df)
    keep = amp > 0
    f, amp = f[keep], amp[keep]
    a = rng.standard_normal((n_trials, f.size)) * amp
    b = rng.standard_normal((n_trials, f.size)) * amp
    return f, a, b


def _fourier_series(f: np.ndarray, a: np.ndarray, b: np.ndarray,
                    time_s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Displacement Σ a_k cos ω_k t + b_k sin ω_k t and its first two derivatives, each (T, N)."""
    w = 2.0 * math.pi * f
    arg = np.outer(w, time_s)  # (K, N)
    cos_, sin_ = np.cos(arg), np.sin(arg)
    x = a @ cos_ + b @ sin_
    xd = (b * w) @ cos_ - (a * w) @ sin_
    xdd = -((a * w**2) @ cos_ + (b * w**2) @ sin_)
    return x, xd, xdd


def _euler_to_dcm(r, p, y) -> np.ndarray:
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    c = np.empty(r.shape + (3, 3))
    c[..., 0, 0] = cy * cp
    c[..., 0, 1] = cy * sp * sr - sy * cr
    c[..., 0, 2] = cy * sp * cr + sy * sr
    c[..., 1, 0] = sy * cp
    c[..., 1, 1] = sy * sp * sr + cy * cr
    c[..., 1, 2] = sy * sp * cr - cy * sr
    c[..., 2, 0] = -sp
    c[..., 2, 1] = cp * sr
    c[..., 2, 2] = cp * cr
    return c


def true_motion(speed_m_s: float, time_s: np.ndarray, disturbance: Disturbance | None = None,
                n_trials: int = 1, rng: np.random.Generator | None = None,
                imu_dt_s: float | None = None) -> TrueMotion:
    """True kinematics of straight flight at ``speed_m_s`` plus ``disturbance``.

    ``time_s`` (N,) runs over the aperture; the nominal position is x = V·(t − t_mid). With a
    random disturbance the arrays get a leading trial axis and ``rng`` is required.
    ``imu_dt_s``: the IMU sample interval. The strapdown propagation holds sample k over
    [t_k, t_k + dt) (:func:`budget.nav.strapdown.propagate_errors`), so the IMU sample of that
    interval must describe the interval, not its start: the returned ``rate_b_rad_s`` and
    ``force_b_m_s2`` are then taken at the interval midpoints t_k + dt/2 (the same realisation).
    Taken at t_k, a scale factor on a rate that is not zero at the start integrates to a constant
    tilt γ·ω(0)·dt/2 that gravity turns into a position error growing as t² (relative error
    ≈ ω²·T·dt/4: 4.8× the true error for a 5 Hz roll at 200 Hz over 3 s). At the midpoints the
    error of a component at f is ≈ (πf·dt)²/6 (the propagation's own discretisation; 1.6 % at
    f = rate/10): :data:`MAX_FREQUENCY_FRACTION` bounds it.
    """
    time_s = np.asarray(time_s, dtype=float)
    n = time_s.size
    t_mid = 0.5 * (time_s[0] + time_s[-1])
    rand = disturbance is not None and disturbance.is_random
    if rand and rng is None:
        raise ValueError("a random disturbance needs a numpy.random.Generator")
    coeffs = [(c.axis, _random_coefficients(c, n_trials, time_s[-1] - time_s[0], rng))
              for c in disturbance.random] if rand else []
    lead = (n_trials,) if rand else ()
    shape = lead + (n, 3)
    disp, vel, acc = _axis_series(disturbance, coeffs, time_s, lead)
    pos = np.empty(shape)
    pos[..., 0] = speed_m_s * (time_s - t_mid) + disp["surge"]
    pos[..., 1] = disp["sway"]
    pos[..., 2] = disp["heave"]
    f_n, w_b, f_b, c_b_n = _body_kinematics(disturbance, disp, vel, acc, shape)
    if imu_dt_s is not None and disturbance is not None:
        d_m, v_m, a_m = _axis_series(disturbance, coeffs, time_s + 0.5 * imu_dt_s, lead)
        _, w_b, f_b, _ = _body_kinematics(disturbance, d_m, v_m, a_m, shape)
    return TrueMotion(time_s=time_s, position_m=pos, force_n_m_s2=f_n, force_b_m_s2=f_b,
                      rate_b_rad_s=w_b, c_b_n=c_b_n)


def _axis_series(disturbance: Disturbance | None, coeffs: list, time_s: np.ndarray,
                 lead: tuple) -> tuple[dict, dict, dict]:
    """Displacement, velocity and acceleration of every axis at ``time_s`` (sinusoids and the
    random components' drawn series), each (…, N)."""
    n = time_s.size
    disp = {ax: np.zeros(lead + (n,)) for ax in (*TRANSLATION_AXES, *ROTATION_AXES)}
    vel = {ax: np.zeros(lead + (n,)) for ax in disp}
    acc = {ax: np.zeros(lead + (n,)) for ax in disp}
    if disturbance is None:
        return disp, vel, acc
    for s in disturbance.sinusoids:
        w = 2.0 * math.pi * s.frequency_hz
        arg = w * time_s + s.phase_rad
        disp[s.axis] = disp[s.axis] + s.amplitude * np.sin(arg)
        vel[s.axis] = vel[s.axis] + s.amplitude * w * np.cos(arg)
        acc[s.axis] = acc[s.axis] - s.amplitude * w**2 * np.sin(arg)
    for axis, (f, a, b) in coeffs:
        x, xd, xdd = _fourier_series(f, a, b, time_s)
        disp[axis] = disp[axis] + x
        vel[axis] = vel[axis] + xd
        acc[axis] = acc[axis] + xdd
    return disp, vel, acc


def _body_kinematics(disturbance: Disturbance | None, disp: dict, vel: dict, acc: dict, shape: tuple):
    """(f_n, ω_b, f_b, C_b^n or None) from the axis series (module docstring)."""
    f_n = np.empty(shape)
    f_n[..., 0], f_n[..., 1], f_n[..., 2] = acc["surge"], acc["sway"], acc["heave"] + G0
    r, p, y = disp["roll"], disp["pitch"], disp["yaw"]
    if disturbance is not None and disturbance.has_rotation:
        c_b_n = _euler_to_dcm(r, p, y)
        rd, pd, yd = vel["roll"], vel["pitch"], vel["yaw"]
        w_b = np.empty(shape)
        w_b[..., 0] = rd - yd * np.sin(p)
        w_b[..., 1] = pd * np.cos(r) + yd * np.sin(r) * np.cos(p)
        w_b[..., 2] = -pd * np.sin(r) + yd * np.cos(r) * np.cos(p)
        f_b = np.einsum("...ji,...j->...i", c_b_n, f_n)
        return f_n, w_b, f_b, c_b_n
    return f_n, np.zeros(shape), f_n.copy(), None
