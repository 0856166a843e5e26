"""Reproducible random streams that do not depend on how trials are chunked or distributed.

Trial ``i`` of a run with seed ``s`` draws, for each independent use, from
``SeedSequence(s, spawn_key=(i, stream))`` where ``stream`` is that use's id in :data:`STREAMS`
— the one table of stream ids in the package (no id is used twice; a test pins the table).
A run split into any chunks, in any order, on any number of workers gives identical numbers.
Library functions take a ``numpy.random.Generator``; engines that loop over trials use
:func:`trial_generator` to build one per trial (or per block of trials).

Streams of the model-gap workflow are keyed differently — ``spawn_key=(channel index, digest of
the channel model's term names)`` (:mod:`budget.gap.simulate`); the report's shape checks after a
run draw the updated model's realizations from ``spawn_key=(channel index, 0, id)`` with the id in
:data:`GAP_CHECK_STREAMS` (a third key element, so never a realization of the gap itself) — and
seed-paper cases and tests take a ``Generator`` from their caller.
"""

from __future__ import annotations

from types import MappingProxyType

import numpy as np

#: Every random-stream id, by use. Changing an id changes every result drawn from it.
STREAMS = MappingProxyType({
    "motion_imu": 11,               # IMU errors of a block of trials (budget.motion)
    "motion_disturbance": 12,       # random platform motion (budget.motion)
    "motion_initial": 13,           # initial navigation errors (budget.motion)
    "motion_aiding": 14,            # aiding measurement noise, their error states, flexure
    "sar_receiver_noise": 21,       # receiver noise of the echoes (budget.mc.chain)
    "sar_scene": 23,                # layout and clutter of the realistic scene (budget.mc.chain)
    "sar_reference": 24,            # receiver noise of the perfect-IMU reference (budget.mc.reference)
    "prefilter_calibration": 22,    # static record the ARMA pre-filter is fitted on
})


#: The model-gap report's shape checks (budget.gap.two_valued, budget.gap.temperature_curve):
#: the third spawn-key element of their channel streams (:func:`budget.gap.simulate.check_rng`).
GAP_CHECK_STREAMS = MappingProxyType({
    "gap_two_valued": 1,            # slow-part kurtosis of the updated model (budget.gap.two_valued)
    "gap_temperature_curve": 2,     # curved temperature share of the updated model (budget.gap.temperature_curve)
})


def stream_id(name: str) -> int:
    """The id of stream ``name`` (KeyError naming the known streams otherwise)."""
    try:
        return STREAMS[name]
    except KeyError:
        raise KeyError(f"unknown random stream {name!r}; known: {', '.join(STREAMS)}") from None


def trial_seed_sequence(seed: int, trial_index: int, stream: int = 0) -> np.random.SeedSequence:
    """SeedSequence of one trial (``stream`` separates independent uses within a trial)."""
    if seed < 0 or trial_index < 0 or stream < 0:
        raise ValueError("seed, trial_index and stream must be non-negative integers")
    return np.random.SeedSequence(entropy=int(seed), spawn_key=(int(trial_index), int(stream)))


def trial_generator(seed: int, trial_index: int, stream: int = 0) -> np.random.Generator:
    """A ``Generator`` private to one trial."""
    return np.random.Generator(np.random.PCG64(trial_seed_sequence(seed, trial_index, stream)))
