"""Streaming statistics of the Monte Carlo: Wilson interval, bounded-memory quantiles, worst trials."""

import math

import numpy as np
import pytest

from budget.mc.stats import StreamingQuantiles, WorstTrials, wilson_interval


def test_wilson_textbook_values():
    # Wilson (1927) score interval, z = 1.95996: 8/10 → [0.4902, 0.9433]; 0/10 → [0, 0.2775]
    assert wilson_interval(8, 10) == pytest.approx((0.4902, 0.9433), abs=1e-4)
    assert wilson_interval(0, 10) == pytest.approx((0.0, 0.2775), abs=1e-4)
    lo, hi = wilson_interval(500, 1000)
    assert lo < 0.5 < hi and hi - lo == pytest.approx(2 * 1.95996 * math.sqrt(0.25 / 1000), rel=0.01)
    assert all(math.isnan(v) for v in wilson_interval(0, 0))


@pytest.mark.parametrize("n", [1, 7, 64, 128, 1000, 4096])
def test_wilson_bounds_exact_at_zero_and_all(n):
    # p̂ = 0 → lower bound exactly 0, p̂ = 1 → upper bound exactly 1 (z²/(n + z²) on the other side),
    # never a rounding residue such as 2.8e-17 that a summary prints as a probability
    z2 = 1.959963984540054 ** 2
    lo, hi = wilson_interval(0, n)
    assert lo == 0.0 and hi == pytest.approx(z2 / (n + z2), rel=1e-12)
    lo, hi = wilson_interval(n, n)
    assert hi == 1.0 and lo == pytest.approx(n / (n + z2), rel=1e-12)


def test_wilson_coverage():
    # over many binomial draws the 95 % interval covers p about 95 % of the time
    rng = np.random.default_rng(3)
    p, n = 0.2, 60
    k = rng.binomial(n, p, 4000)
    cover = np.mean([wilson_interval(int(x), n)[0] <= p <= wilson_interval(int(x), n)[1] for x in k])
    assert 0.93 <= cover <= 0.97


def test_streaming_quantiles_match_numpy_and_merge():
    rng = np.random.default_rng(0)
    x = np.concatenate([rng.normal(0, 3, 20000), rng.lognormal(0, 2, 20000)])
    whole = StreamingQuantiles()
    whole.add(x)
    parts = [StreamingQuantiles() for _ in range(4)]
    for p, chunk in zip(parts, np.array_split(x, 4)):
        p.add(chunk)
    merged = parts[0]
    for p in parts[1:]:
        merged.merge(p)
    for q in (0.05, 0.5, 0.95):
        ref = np.quantile(x, q)
        # one log bin = 10**(1/200) − 1 = 1.2 % of the value
        assert whole.quantile(q) == pytest.approx(ref, rel=0.02, abs=1e-5)
        assert merged.quantile(q) == whole.quantile(q)
    whole.add([np.nan, np.inf])
    assert whole.n_nonfinite == 2 and whole.counts.nbytes < 100_000


def test_worst_trials_keeps_largest():
    w = WorstTrials(k=3)
    for i, s in enumerate([1, 5, 3, 9, 2, 9]):
        w.offer(s, i, {"i": i})
    assert [t for _, t, _ in w.items()] == [3, 5, 1]
