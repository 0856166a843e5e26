"""Realizations of the model for one channel, reduced to signatures as they are drawn.

Each channel is simulated on its own: a :class:`~budget.imu.NoiseModel` holding only that
channel's terms (the catalog-implied white noise, flicker and random walk of
:meth:`NoiseModelSI.channel_effects` plus its explicit effects) goes through
:func:`budget.imu.generate_imu_errors` at the log's rate and length, in pairs of trials so that
memory stays at a few series. The static true signal of the channel (the measured mean) is
passed as the true rate / specific force, so the quantizer sees the same constant input as
the sensor did; it is removed again with the mean. With a temperature channel the measured
temperature drives the temperature effects.

Random streams: channel ``index`` draws from ``SeedSequence(seed, spawn_key=(index, key))``
where ``key`` is a digest of the channel model's *structure* (the names of its terms, in
order, not their values). So the same seed and the same channel model give the same
realizations in any run (a second pass with the updated model starts exactly where the first
ended), and two models that differ only in a parameter value share their random numbers
(common random numbers: a smooth objective when a parameter is refined by simulation).
"""

from __future__ import annotations

import hashlib

import numpy as np

from ..imu import NoiseModel, generate_imu_errors
from ..rng import GAP_CHECK_STREAMS
from ..units import ACCEL_CHANNELS, CHANNELS, GYRO_CHANNELS
from .signatures import Signature, SignatureGrid, overlapping_avar, series_signature

#: Trials drawn per generator call (the circulant generator works in pairs).
CHUNK = 2


def channel_model(model: NoiseModel, channel: str, rate_hz: float) -> NoiseModel:
    """A model holding only ``channel``'s terms, as explicit effects, at ``rate_hz``."""
    effects = model.to_si().channel_effects(channel)
    return NoiseModel(rate_hz=rate_hz, effects=tuple(effects))


def structure_key(model: NoiseModel, channel: str) -> int:
    """Stable 32-bit digest of the ordered term names of ``channel`` in ``model``."""
    names = ",".join(f.name for f in model.to_si().channel_effects(channel))
    return int.from_bytes(hashlib.sha256(names.encode()).digest()[:4], "little")


def channel_rng(seed: int, channel: str, key: int) -> np.random.Generator:
    ss = np.random.SeedSequence(int(seed), spawn_key=(CHANNELS.index(channel), int(key)))
    return np.random.default_rng(ss)


def check_rng(seed: int, channel: str, check: str) -> np.random.Generator:
    """The stream of a report check's realizations on ``channel``: ``spawn_key=(channel index, 0,
    id)``, ``id`` = :data:`budget.rng.GAP_CHECK_STREAMS` [``check``] (three key elements: never
    the stream of a realization of the gap itself)."""
    ss = np.random.SeedSequence(int(seed), spawn_key=(CHANNELS.index(channel), 0, GAP_CHECK_STREAMS[check]))
    return np.random.default_rng(ss)


def model_statistic(model: NoiseModel, channel: str, statistic, n_samples: int, rate_hz: float, seed: int,
                    check: str, realizations: int, *, true_value: float = 0.0,
                    temp_c: np.ndarray | None = None) -> tuple[np.ndarray, float, float]:
    """A report check's null: ``statistic(series)`` on ``realizations`` series of ``channel`` under
    ``model`` (the updated model) from the check's own stream (:func:`check_rng`); returns the
    values, their mean and their standard deviation."""
    sims = np.array([statistic(s) for s in simulate_series(
        model, channel, realizations, n_samples, rate_hz, check_rng(seed, channel, check),
        true_value=true_value, temp_c=temp_c)])
    return sims, float(sims.mean()), float(sims.std(ddof=1))


def simulate_series(model: NoiseModel, channel: str, n_real: int, n_samples: int, rate_hz: float,
                    rng: np.random.Generator, *, true_value: float = 0.0,
                    temp_c: np.ndarray | None = None):
    """Yield ``n_real`` simulated series (N,) of ``channel`` (rad/s or m/s²), a pair at a time."""
    cm = channel_model(model, channel, rate_hz)
    triad = GYRO_CHANNELS if channel in GYRO_CHANNELS else ACCEL_CHANNELS
    axis = triad.index(channel)
    has_quant = any(f.name == "quantization" for f in cm.effects)
    true = None
    if has_quant and true_value != 0.0:
        true = np.zeros((n_samples, 3))
        true[:, axis] = true_value
    done = 0
    while done < n_real:
        k = min(CHUNK, n_real - done)
        kw = {"true_rate_rad_s": true} if triad is GYRO_CHANNELS else {"true_force_m_s2": true}
        err = generate_imu_errors(cm, k, n_samples, rate_hz, rng, temp_c=temp_c, **kw)
        block = err.gyro_rad_s if triad is GYRO_CHANNELS else err.accel_m_s2
        for t in range(k):
            yield block[t, :, axis]
        done += k


def simulate_signatures(model: NoiseModel, channel: str, grid: SignatureGrid, n_real: int,
                        seed: int, true_value: float = 0.0) -> list[Signature]:
    """Signatures of ``n_real`` realizations of ``channel`` under ``model``."""
    rng = channel_rng(seed, channel, structure_key(model, channel))
    n = grid.n_samples
    out = []
    for x in simulate_series(model, channel, n_real, n, grid.rate_hz, rng, true_value=true_value,
                             temp_c=grid.temp_c):
        if grid.has_psd:
            out.append(series_signature(x, grid))
        else:
            out.append(_adev_only(x, grid))
    return out


def _adev_only(x: np.ndarray, grid: SignatureGrid) -> Signature:
    return Signature(overlapping_avar(x, grid.m))
