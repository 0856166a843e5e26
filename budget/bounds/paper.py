"""Seed 004 (6)–(11) exactly as printed (Velikanova et al., Giroskopiya i Navigatsiya 2016).

With δr in metres and Tc in seconds:

* (6)  β_max = 0.2 δr/Tc²,  γ_max = 0.1 δr/Tc²
* (7)  φm + φn < arcsin(0.2 δr/Tc²) rad
* (8)  b_a < 1.4e5 δr/Tc² µg
* (9)  b_ω < 8.93e4 δr/Tc³ deg/h
* (10) n_a < 8.8e4 δr/Tc^1.5 µg/√Hz
* (11) n_ω < 784 δr/Tc^2.5 deg/√h

Note: seed 004 Table 2 prints γ_max = 1e-8 at Tc = 100 s; (6) gives 1e-6 (a typo in the table).
"""

from __future__ import annotations

import numpy as np

from .. import units as u
from ..errors import InputError
from .table import BoundsTable


def _inputs(tc_s, range_resolution_m):
    tc = np.atleast_1d(np.asarray(tc_s, dtype=float))
    dr = np.asarray(range_resolution_m, dtype=float)
    if not (np.all(np.isfinite(tc)) and np.all(tc > 0)):
        raise InputError("Tc must be finite and > 0", field="tc_s", value=tc.tolist(), expected="s, > 0")
    if not (np.all(np.isfinite(dr)) and np.all(dr > 0)):
        raise InputError("range resolution δr must be finite and > 0", field="range_resolution_m",
                         value=dr.tolist(), expected="m, > 0")
    tc, dr = np.broadcast_arrays(tc, dr)
    return tc, dr


def paper_bounds(tc_s, range_resolution_m) -> BoundsTable:
    """Seed 004 (6)–(11) for arrays of Tc (s) and δr (m); SI results."""
    tc, dr = _inputs(tc_s, range_resolution_m)
    x2 = dr / tc**2
    arg = np.minimum(0.2 * x2, 1.0)  # arcsin saturates at 90°: any misalignment is then allowed
    return BoundsTable(
        mode="paper", tc_s=tc, range_resolution_m=dr,
        accel_scale_factor=0.2 * x2,
        gyro_scale_factor=0.1 * x2,
        misalignment_rad=np.arcsin(arg),
        accel_bias_m_s2=u.ug_to_m_s2(1.4e5 * x2),
        gyro_bias_rad_s=u.deg_h_to_rad_s(8.93e4 * dr / tc**3),
        accel_vrw_m_s2_rt_hz=u.ug_rt_hz_to_m_s2_rt_hz(8.8e4 * dr / tc**1.5),
        gyro_arw_rad_s_rt_hz=u.deg_rt_h_to_rad_s_rt_hz(784.0 * dr / tc**2.5),
        notes=("seed 004 (6)-(11) as printed; each source alone within one range cell",),
    )
