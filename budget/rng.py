"""Reproducible random streams that do not depend on how trials are chunked or distributed.

Trial ``i`` of a run with seed ``s`` always draws from ``SeedSequence(s, spawn_key=(i,))``, so a
run split into any chunks, in any order, on any number of workers gives identical numbers.
Library functions take a ``numpy.random.Generator``; engines that loop over trials use these
helpers to build one per trial (or per block).
"""

from __future__ import annotations

import numpy as np


def trial_seed_sequence(seed: int, trial_index: int, stream: int = 0) -> np.random.SeedSequence:
    """SeedSequence of one trial (``stream`` separates independent uses within a trial)."""
    if seed < 0 or trial_index < 0 or stream < 0:
        raise ValueError("seed, trial_index and stream must be non-negative integers")
    return np.random.SeedSequence(entropy=int(seed), spawn_key=(int(trial_index), int(stream)))


def trial_generator(seed: int, trial_index: int, stream: int = 0) -> np.random.Generator:
    """A ``Generator`` private to one trial."""
    return np.random.Generator(np.random.PCG64(trial_seed_sequence(seed, trial_index, stream)))


def trial_generators(seed: int, start: int, stop: int, stream: int = 0) -> list[np.random.Generator]:
    """Generators of trials ``start … stop-1``."""
    return [trial_generator(seed, i, stream) for i in range(start, stop)]
