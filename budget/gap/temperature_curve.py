"""A slow effect named where the record's slow part follows the temperature along a curve.

The registry's temperature effects are linear in the (possibly lagged) temperature. A bias
curved in T — a quadratic sensitivity with a turnover inside the logged range, c₂·(T − T₀)² —
is none of them; on a warm-up log its slow, smooth excursion is what a random walk or a
long Gauss–Markov term also explains, and the workflow names one of those (on five one-hour
logs of ``tests/gap_outside.py``: a rate random walk 5/5). What sets it apart is that the slow
part is a function of the temperature column.

After the run, on every channel of a log with a temperature column where a slow effect
(:data:`SLOW`) was named, this module forms the record's slow part (block means, 256 blocks)
and the share of its variance that (T − T̄)² explains beyond [1, t, T] (least squares; the
linear part is the registry's ``temperature_sensitivity``), and compares it with the same
share on realizations of the *updated* model driven by the same temperature (a walk can follow
any smooth curve by chance; the realizations say how often). When the record's share lies above
every realization and more than :data:`Z_LIMIT` of their standard deviations above their mean,
the report says so in a note.
"""

from __future__ import annotations

import numpy as np

from ..imu import NoiseModel
from .simulate import model_statistic

#: Effects whose slow excursion a curved temperature response can pass for.
SLOW = ("rate_random_walk", "gauss_markov", "bias_instability", "rate_ramp", "warmup_transient",
        "bias_step", "temperature_sensitivity", "temperature_lag")
REALIZATIONS = 32
Z_LIMIT = 3.0
BLOCKS = 256


def curved_share(x: np.ndarray, temp_c: np.ndarray, blocks: int = BLOCKS) -> float:
    """Share of the block means' variance (after [1, t, T]) that (T − T̄)² explains."""
    n = min(np.asarray(x).size, np.asarray(temp_c).size)
    b = max(1, n // blocks)
    nb = n // b
    y = np.asarray(x, float)[:nb * b].reshape(nb, b).mean(axis=1)
    t = np.asarray(temp_c, float)[:nb * b].reshape(nb, b).mean(axis=1)
    tc = t - t.mean()
    lin = np.column_stack([np.ones(nb), np.linspace(-1.0, 1.0, nb), tc])
    r1 = y - lin @ np.linalg.lstsq(lin, y, rcond=None)[0]
    quad = np.column_stack([lin, tc * tc - np.mean(tc * tc)])
    r2 = y - quad @ np.linalg.lstsq(quad, y, rcond=None)[0]
    ss1 = float(r1 @ r1)
    return 0.0 if ss1 <= 0 else 1.0 - float(r2 @ r2) / ss1


def check(model: NoiseModel, channel: str, x: np.ndarray, rate_hz: float, temp_c: np.ndarray, seed: int,
          named: tuple[str, ...], true_value: float = 0.0) -> dict:
    """The measured curved share on ``channel`` against ``model``'s realizations (dict with
    ``curved``: True when it is beyond them)."""
    meas = curved_share(x, temp_c)
    sims, mean, sd = model_statistic(model, channel, lambda s: curved_share(s, temp_c), np.asarray(x).size,
                                     rate_hz, seed, "gap_temperature_curve", REALIZATIONS,
                                     true_value=true_value, temp_c=temp_c)
    z = (meas - mean) / sd if sd > 0 else 0.0
    return {"channel": channel, "named": list(named), "share": meas, "model_mean": mean, "model_sd": sd,
            "z": float(z), "realizations": REALIZATIONS,
            "curved": bool(z > Z_LIMIT and meas > float(sims.max()))}


def note(found: dict) -> str:
    return (f"{found['channel']}: the slow part follows the temperature along a curve: (T − T̄)² beyond a "
            f"constant, a trend and a linear sensitivity explains {100 * found['share']:.0f} % of the "
            f"variance of its block means, where the updated model gives {100 * found['model_mean']:.0f} ± "
            f"{100 * found['model_sd']:.0f} % ({found['realizations']} realizations, z = {found['z']:.1f}) "
            f"— a temperature sensitivity curved in T (e.g. a turnover) is outside the registry (linear "
            f"sensitivity and lag only); {', '.join(found['named'])} named there "
            f"{'is' if len(found['named']) == 1 else 'are'} the nearest it has, not the cause")
