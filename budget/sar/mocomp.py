"""Motion compensation of range-compressed data with the MEASURED trajectory (fast image former).

Two steps, as in real strip-map/spotlight processors:

1. first order (bulk, range-invariant): the line-of-sight range change to the scene centre C,
   Δr_c(t) = |p_meas(t) − C| − |p_nom(t) − C|, is removed by a range shift and a phase,
   D(t, f) · exp(+j 4π (f0 + f) Δr_c(t) / c);
2. second order (range-dependent phase): for each range bin r the change to the ground point at
   azimuth 0 and closest range r, Δr(t, r) − Δr_c(t), is removed by a phase exp(+j 4π(·)/λ);
   the envelope is not shifted again (the differential shift is a small fraction of a bin for
   offsets of metres).

What remains for a target at azimuth x ≠ 0 is δp · (u_target(t) − u_ref(t, r)), the motion
error times the change of line of sight across the scene: space-variant, not compensated here
(backprojection compensates it exactly per pixel). With measured = true it is the only error
left; with measured ≠ true the residual true − measured enters the data exactly like a real one.
"""

from __future__ import annotations

import numpy as np

from .geometry import SarGeometry


def los_range_change_m(geom: SarGeometry, offset_m: np.ndarray, ground_points_m: np.ndarray) -> np.ndarray:
    """|p_nom + δp − P| − |p_nom − P| for every pulse and point: (n_pulses, n_points), m."""
    nom = geom.nominal_apc_m()
    d_off = np.linalg.norm((nom + offset_m)[:, None, :] - ground_points_m[None], axis=-1)
    d_nom = np.linalg.norm(nom[:, None, :] - ground_points_m[None], axis=-1)
    return d_off - d_nom


def motion_compensate(geom: SarGeometry, data: np.ndarray, measured_offset_m: np.ndarray) -> np.ndarray:
    """First- and second-order motion compensation to the nominal track (see module docstring)."""
    if not np.any(measured_offset_m):
        return data
    centre = geom.scene_centre_m[None, :]
    dr_c = los_range_change_m(geom, measured_offset_m, centre)[:, 0]
    f = np.fft.fftfreq(geom.n_range, 1.0 / geom.range_sample_rate_hz)
    spec = np.fft.fft(data, axis=1)
    spec *= np.exp(4j * np.pi * (geom.carrier_frequency_hz + f)[None, :] * dr_c[:, None] / geom.c_m_s)
    out = np.fft.ifft(spec, axis=1)
    refs = geom.scene_point_m(np.zeros(geom.n_range), geom.range_axis_m)
    dr = los_range_change_m(geom, measured_offset_m, refs) - dr_c[:, None]
    out *= np.exp(4j * np.pi * dr / geom.wavelength_m)
    return out
