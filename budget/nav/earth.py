"""Reference error model *with* Earth rate, transport rate and Schuler coupling.

Used to check the flat-earth propagation of :mod:`budget.nav.strapdown` and to show where it
stops being adequate. The standard linear phi-angle error model in a local-level frame (as in
Titterton & Weston, *Strapdown Inertial Navigation Technology*, 2nd ed., error-propagation
chapter), written in ENU and rotated into the along-track frame (x along-track at heading h
from north, y to the left, z up):

* φ̇ = −ω_in × φ + δω_in − C·ε                  (ω_in = ω_ie + ω_en)
* δv̇ = f × φ + C·δf − (2ω_ie + ω_en) × δv − (2δω_ie + δω_en) × v + (0, 0, 2g·δh/R)
* δṗ = δv

with ω_ie = Ω(0, cos L, sin L), ω_en = (−v_N/R, v_E/R, v_E·tan L/R),
δω_ie = Ω(0, −sin L, cos L)·δL, δω_en = (−δv_N/R, δv_E/R, tan L·δv_E/R + v_E·sec²L·δL/R),
δL = δp_N/R. Level flight at constant speed (f = (0, 0, g), C = I). Inputs are held constant
over each sample interval and the state is advanced with the exact transition matrix
(matrix exponential), looping over samples: a slow reference, not for production use.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm

from ..units import G0
from .strapdown import NavErrors, cross

EARTH_RATE_RAD_S = 7.292115e-5
EARTH_RADIUS_M = 6_371_000.0
#: Schuler angular frequency ω_s = √(g/R) (rad/s); period 2π/ω_s ≈ 84.4 min.
SCHULER_RAD_S = math.sqrt(G0 / EARTH_RADIUS_M)
#: Largest :func:`flat_earth_neglect` of a free-inertial coast of Tc the flat-earth propagation is
#: used for (10 %, Tc ≈ 790 s): beyond it the motion engine refuses the run
#: (:data:`budget.motion.flat_earth.MAX_FLAT_EARTH_NEGLECT`, where the rule is stated) and a
#: scenario notes that the bounds' free-inertial error growth overstates the error.
MAX_FLAT_EARTH_NEGLECT = 0.10
#: Longest Tc (s) any navigation in the tool is modelled for: aiding that corrects inside the
#: aperture was measured against the Earth model up to 3000 s
#: (:data:`budget.motion.flat_earth.AIDED_FLAT_EARTH_MAX_TC_S`); the analytic bounds refuse a
#: longer Tc (:func:`budget.bounds.check_bounds_tc`).
AIDED_FLAT_EARTH_MAX_TC_S = 3000.0


def flat_earth_neglect(duration_s: float, speed_m_s: float = 0.0) -> float:
    """Relative size (dimensionless) of what a flat-earth error propagation leaves out over a
    free-inertial coast of ``duration_s`` (s) at ``speed_m_s`` (m/s): the leading terms of the
    model above against the flat one, (ω_s·t)²/12 (Schuler coupling) + Ω·t/3 (Coriolis and
    Earth-rate couplings) + V·t/(3R) (transport rate), as stated in
    :mod:`budget.nav.strapdown`. Against :func:`propagate_errors_earth` for constant sensor
    biases (45° latitude): 0.4 % estimated / 0.5 % measured at 100 s, 6 % / 5 % at 600 s,
    15 % / 13 % at 1000 s; at 3000 s the flat model doubles the Schuler-bounded error."""
    t = float(duration_s)
    return ((SCHULER_RAD_S * t) ** 2 / 12.0 + EARTH_RATE_RAD_S * t / 3.0
            + abs(float(speed_m_s)) * t / (3.0 * EARTH_RADIUS_M))


def navigation_frame_rate(speed_m_s: float, latitude_rad: float, heading_rad: float) -> np.ndarray:
    """ω_in = ω_ie + ω_en (rad/s, (3,)) in the along-track frame of :func:`system_matrix`
    (x along-track at heading ``heading_rad`` from north, y to the left, z up) for level flight
    at ``speed_m_s``: the rate at which the local-level frame turns, which turns an attitude
    error φ at −ω_in × φ (the first term of φ̇ above)."""
    lat, h, r = latitude_rad, heading_rad, EARTH_RADIUS_M
    v_e, v_n = speed_m_s * math.sin(h), speed_m_s * math.cos(h)
    w_enu = EARTH_RATE_RAD_S * np.array([0.0, math.cos(lat), math.sin(lat)]) \
        + np.array([-v_n / r, v_e / r, v_e * math.tan(lat) / r])
    return _along_track_rotation(h) @ w_enu


def _along_track_rotation(h: float) -> np.ndarray:
    """Rows: the along-track frame's axes in ENU at heading ``h`` (rad from north)."""
    return np.array([[math.sin(h), math.cos(h), 0.0],      # x̂ (along-track) in ENU
                     [-math.cos(h), math.sin(h), 0.0],     # ŷ (left)
                     [0.0, 0.0, 1.0]])                     # ẑ (up)


def _enu_derivative(x: np.ndarray, *, speed_m_s: float, latitude_rad: float, heading_rad: float,
                    earth: bool) -> np.ndarray:
    """ẋ (without inputs) for state x = [φ, δv, δp] in ENU (9,)."""
    phi, dv, dp = x[0:3], x[3:6], x[6:9]
    f = np.array([0.0, 0.0, G0])
    out = np.zeros(9)
    out[3:6] = np.cross(f, phi)
    out[6:9] = dv
    if not earth:
        return out
    lat, om, r = latitude_rad, EARTH_RATE_RAD_S, EARTH_RADIUS_M
    v = speed_m_s * np.array([math.sin(heading_rad), math.cos(heading_rad), 0.0])
    w_ie = om * np.array([0.0, math.cos(lat), math.sin(lat)])
    w_en = np.array([-v[1] / r, v[0] / r, v[0] * math.tan(lat) / r])
    d_lat = dp[1] / r
    dw_ie = om * np.array([0.0, -math.sin(lat), math.cos(lat)]) * d_lat
    dw_en = np.array([-dv[1] / r, dv[0] / r,
                      math.tan(lat) * dv[0] / r + v[0] * d_lat / (r * math.cos(lat) ** 2)])
    out[0:3] += -np.cross(w_ie + w_en, phi) + dw_ie + dw_en
    out[3:6] += -np.cross(2 * w_ie + w_en, dv) - np.cross(2 * dw_ie + dw_en, v)
    out[5] += 2.0 * G0 * dp[2] / r
    return out


def system_matrix(speed_m_s: float, latitude_rad: float, heading_rad: float, earth: bool = True) -> np.ndarray:
    """9×9 state matrix in the along-track frame (columns by probing the linear ENU model)."""
    h = heading_rad
    rot = _along_track_rotation(h)
    big = np.kron(np.eye(3), rot)                         # nav ← ENU for the three 3-vectors
    a_enu = np.column_stack([
        _enu_derivative(e, speed_m_s=speed_m_s, latitude_rad=latitude_rad, heading_rad=h, earth=earth)
        for e in np.eye(9)])
    return big @ a_enu @ big.T


def propagate_errors_earth(gyro_err_rad_s: np.ndarray, accel_err_m_s2: np.ndarray, dt_s: float, *,
                           speed_m_s: float, latitude_rad: float = math.radians(45.0),
                           heading_rad: float = 0.0, earth: bool = True, lever_arm_b_m=None,
                           phi0=None, dv0=None, dp0=None) -> NavErrors:
    """Same inputs and output convention as :func:`budget.nav.strapdown.propagate_errors`
    (computed − true, level flight, C = I), with the Earth terms when ``earth`` is True."""
    eps = np.asarray(gyro_err_rad_s, dtype=float)
    dfb = np.asarray(accel_err_m_s2, dtype=float)
    n_trials, n_samples, _ = eps.shape
    a = system_matrix(speed_m_s, latitude_rad, heading_rad, earth)
    b = np.zeros((9, 6))
    b[0:3, 0:3] = -np.eye(3)
    b[3:6, 3:6] = np.eye(3)
    aug = np.zeros((15, 15))
    aug[:9, :9], aug[:9, 9:] = a, b
    m = expm(aug * dt_s)
    phi_t, gam_t = m[:9, :9].T, m[:9, 9:].T
    x = np.zeros((n_trials, 9))
    for key, sl in ((phi0, slice(0, 3)), (dv0, slice(3, 6)), (dp0, slice(6, 9))):
        if key is not None:
            x[:, sl] = np.asarray(key, dtype=float)
    states = np.empty((n_trials, n_samples, 9))
    u = np.concatenate([eps, dfb], axis=2)
    for k in range(n_samples):
        states[:, k] = x
        x = x @ phi_t + u[:, k] @ gam_t
    phi, dv, dp = states[..., 0:3], states[..., 3:6], states[..., 6:9]
    apc = dp + cross(np.asarray(lever_arm_b_m, dtype=float), phi) if lever_arm_b_m is not None else dp.copy()
    return NavErrors(apc_position_m=apc, attitude_rad=phi, velocity_m_s=dv, position_m=dp)
