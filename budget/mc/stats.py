"""Streaming statistics for Monte Carlo verdicts: memory independent of the number of trials.

* :func:`wilson_interval` — the Wilson score interval of a binomial proportion (95 % default).
* :class:`StreamingQuantiles` — quantiles from a fixed log/linear histogram (bounded memory,
  mergeable across chunks and workers, exact counts; quantiles accurate to one bin: 0.5 % of the
  value on the log grid).
* :class:`WorstTrials` — keeps the k worst trials (by a score) for inspection.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.stats import norm


def wilson_interval(successes: int, n: int, confidence: float = 0.95) -> tuple[float, float]:
    """Wilson score interval for ``successes`` out of ``n`` (returns (nan, nan) for n = 0)."""
    if n <= 0:
        return (math.nan, math.nan)
    if not 0 <= successes <= n:
        raise ValueError("successes must be within 0 … n")
    z = float(norm.ppf(0.5 + confidence / 2.0))
    p = successes / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    # at p̂ = 0 (1) the bound is exactly 0 (1): centre and half are equal there, but their rounded
    # difference is a few 1e-17, which a summary then prints as a probability
    lo = 0.0 if successes == 0 else max(0.0, centre - half)
    hi = 1.0 if successes == n else min(1.0, centre + half)
    return (lo, hi)


@dataclass
class StreamingQuantiles:
    """Histogram-based quantiles of a signed metric with bounded memory.

    Values are binned on a symmetric log grid: |x| from ``lo`` to ``hi`` with ``per_decade`` bins
    per decade, plus a zero bin and under/overflow bins. Non-finite values are counted apart.
    """

    lo: float = 1e-6
    hi: float = 1e6
    per_decade: int = 200
    counts: np.ndarray = field(init=False)
    n: int = 0
    n_nonfinite: int = 0
    vmin: float = math.inf
    vmax: float = -math.inf

    def __post_init__(self):
        self._edges = np.logspace(math.log10(self.lo), math.log10(self.hi),
                                  int(round(math.log10(self.hi / self.lo) * self.per_decade)) + 1)
        nb = len(self._edges) - 1
        # layout: [neg overflow, neg bins reversed..., zero, pos bins..., pos overflow]
        self.counts = np.zeros(2 * nb + 3, dtype=np.int64)
        self._nb = nb

    def _index(self, x: np.ndarray) -> np.ndarray:
        a = np.abs(x)
        k = np.searchsorted(self._edges, a, side="right") - 1  # -1 below lo, nb at/above hi
        k = np.clip(k, -1, self._nb)
        pos = self._nb + 2 + k  # zero bin at nb+1 for k=-1
        neg = self._nb - k
        idx = np.where(x >= 0, pos, neg)
        return np.where(a < self.lo, self._nb + 1, idx)

    def add(self, values) -> None:
        x = np.asarray(values, dtype=float).ravel()
        fin = np.isfinite(x)
        self.n_nonfinite += int((~fin).sum())
        x = x[fin]
        if x.size == 0:
            return
        self.n += x.size
        self.vmin = min(self.vmin, float(x.min()))
        self.vmax = max(self.vmax, float(x.max()))
        np.add.at(self.counts, self._index(x), 1)

    def merge(self, other: "StreamingQuantiles") -> None:
        self.counts += other.counts
        self.n += other.n
        self.n_nonfinite += other.n_nonfinite
        self.vmin = min(self.vmin, other.vmin)
        self.vmax = max(self.vmax, other.vmax)

    def _bin_value(self, i: int) -> float:
        nb = self._nb
        if i == nb + 1:
            return 0.0
        if i >= nb + 2:
            k = i - nb - 2
            return self.vmax if k >= nb else math.sqrt(self._edges[k] * self._edges[k + 1])
        k = nb - i
        return self.vmin if k >= nb else -math.sqrt(self._edges[k] * self._edges[k + 1])

    def quantile(self, q: float) -> float:
        """The ``q``-quantile (0 … 1) to within one bin; nan when empty."""
        if self.n == 0:
            return math.nan
        target = q * (self.n - 1)
        cum = np.cumsum(self.counts)
        i = int(np.searchsorted(cum, target + 1))
        v = self._bin_value(i)
        return float(min(max(v, self.vmin), self.vmax))


@dataclass
class WorstTrials:
    """The ``k`` trials with the largest ``score`` (ties broken by the lower trial index)."""

    k: int = 5
    _heap: list = field(default_factory=list)

    def offer(self, score: float, trial: int, payload) -> None:
        if not math.isfinite(score):
            score = math.inf
        item = (score, -trial, trial, payload)
        if len(self._heap) < self.k:
            heapq.heappush(self._heap, item)
        elif item[:2] > self._heap[0][:2]:
            heapq.heapreplace(self._heap, item)

    def merge(self, other: "WorstTrials") -> None:
        for score, _, trial, payload in other._heap:
            self.offer(score, trial, payload)

    def items(self) -> list[tuple[float, int, object]]:
        return [(s, t, p) for s, _, t, p in sorted(self._heap, key=lambda x: (-x[0], x[2]))]
