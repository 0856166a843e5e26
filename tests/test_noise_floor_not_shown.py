"""A bias instability resolved from the rounding of an Allan curve between its white-noise and
random-walk slopes, with no floor the curve flattens to, carries a caution in `characterize`.

The records are drawn here (white rate noise plus a rate random walk, and a flicker floor from
an FFT-shaped 1/f spectrum), not by the package's generator. On 40 two-hour records without any
flicker (ARW 0.15 deg/√h, RRW 10 deg/h/√h, crossover at 93 s) the fit resolved a bias
instability on one (seed 4 below); its floor is at most 38 % of the fitted variance at any τ.
"""

from __future__ import annotations

import math

import numpy as np

from budget.noise.allan import allan_deviation
from budget.noise.characterize import FLOOR_SHARE, characterize

DEG = math.pi / 180
FS, HOURS = 50.0, 2.0
N_ARW = 0.15 * DEG / 60            # rad/√s
K_RRW = 10 * DEG / 3600 / 60       # rad/s/√s
WORDS = "never flattens"


def _record(seed: int, floor_deg_h: float = 0.0) -> np.ndarray:
    n = int(FS * 3600 * HOURS)
    rng = np.random.default_rng([2026, seed])
    x = N_ARW * math.sqrt(FS) * rng.standard_normal(n) + np.cumsum(K_RRW / math.sqrt(FS) * rng.standard_normal(n))
    if floor_deg_h:
        b = floor_deg_h * DEG / 3600 / math.sqrt(2 * math.log(2) / math.pi)
        f = np.fft.rfftfreq(n, 1 / FS)
        s = np.zeros_like(f)
        s[1:] = b ** 2 / (math.pi * f[1:])     # one-sided PSD of IEEE-952 flicker rate noise
        spec = np.sqrt(n * s * FS / 2) * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / math.sqrt(2)
        x += np.fft.irfft(spec, n)
    return x


def _characterize(x):
    return characterize({"gyro_x": allan_deviation(x, FS, channel="gyro_x", unit="rad/s")}, grade="tactical")


def test_a_bias_instability_read_off_the_curves_rounding_is_cautioned():
    c = _characterize(_record(4))
    assert c.channels["gyro_x"].resolved["B"]          # the false resolution the note is for
    note = [m for m in c.notes if WORDS in m]
    assert len(note) == 1 and note[0].startswith("gyro_x:")
    share = float(note[0].split("at most ")[1].split("%")[0]) / 100
    assert share <= FLOOR_SHARE


def test_a_floor_the_curve_flattens_to_has_no_caution():
    # a 3 deg/h floor, above the white-noise / random-walk curve's own 1.32 deg/h minimum
    c = _characterize(_record(4, floor_deg_h=3.0))
    t = c.channels["gyro_x"]
    assert t.resolved["B"]
    assert abs(math.sqrt(2 * math.log(2) / math.pi) * t.values["B"] / (3.0 * DEG / 3600) - 1) < 0.2
    assert not [m for m in c.notes if WORDS in m]
