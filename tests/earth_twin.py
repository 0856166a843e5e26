"""Test helper: run the motion engine with the Earth model's terms in the truth *and* the filter.

The flat-earth rule of :mod:`budget.motion.flat_earth` is checked by running the same trials twice —
flat, and with Schuler, Earth-rate and transport-rate terms (:mod:`budget.nav.earth`) given to
both the simulated truth and the aiding filter's dynamics — so that the difference measures what
the flat model leaves out, not a filter/truth mismatch.
"""

from __future__ import annotations

import contextlib

import pytest

import budget.aiding.system as system
import budget.motion.engine as engine
from budget.nav.earth import propagate_errors_earth, system_matrix


@contextlib.contextmanager
def earth_in_truth_and_filter(speed_m_s: float, latitude_rad: float, heading_rad: float = 0.0):
    """Within the block, ``simulate_motion`` propagates the truth with
    :func:`~budget.nav.earth.propagate_errors_earth` and the filter's INS dynamics carry the Earth
    model's extra terms (its system matrix with minus without them), at level flight of
    ``speed_m_s`` along ``heading_rad`` at ``latitude_rad``."""
    d_a = (system_matrix(speed_m_s, latitude_rad, heading_rad, True)
           - system_matrix(speed_m_s, latitude_rad, heading_rad, False))
    flat_dynamics = system.ins_dynamics

    def earth_dynamics(layout, imu, f_n, c_bn):
        f = flat_dynamics(layout, imu, f_n, c_bn)
        idx = {"att": 0, "vel": 3, "pos": 6}
        for r, i in idx.items():
            for c, j in idx.items():
                f[..., layout.slice(r), layout.slice(c)] += d_a[i:i + 3, j:j + 3]
        return f

    def earth_truth(g, a, dt, force_n_m_s2=None, c_b_n=None, keep_states=False, lever_arm_b_m=None,
                    frame_rate_n_rad_s=None, **init):
        return propagate_errors_earth(g, a, dt, speed_m_s=speed_m_s, latitude_rad=latitude_rad,
                                      heading_rad=heading_rad, **init)

    mp = pytest.MonkeyPatch()
    try:
        mp.setattr(engine, "propagate_errors", earth_truth)
        mp.setattr(system, "ins_dynamics", earth_dynamics)
        yield
    finally:
        mp.undo()
