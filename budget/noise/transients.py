"""Transient events in a static log: a knock, a touch of the bench, a burst that comes back.

Kind ``transient`` (:func:`transient_stats`, called by :func:`budget.noise.logs.read_log`). A
knock, a touch of the bench or a door slammed gives a burst of a few samples to about a second, far beyond the record's own noise, after which the level comes
back. Below full scale it falls between the saturated runs the reader refuses
(:func:`budget.noise.log_values.clipped`, ≥ 4 samples at the range limit) and the bursts of
≤ 3 samples :mod:`budget.noise.spikes` replaces — and it is not small: on an hour at 400 Hz of a
gyro with ARW 0.2 deg/√h and a bias-instability floor of 2 deg/h, 8 samples at 50 deg/s read an
ARW of 1.26 deg/√h and a bias instability of 430 deg/h, 40 samples at 5 deg/s 184 deg/h, with
only a misfit warning pointing at a tone. The search:

* **taming**: a sample further than :data:`TRANSIENT_CLIP` = 5 robust σ from its local level, the
  running median of :data:`TRANSIENT_BASE` = 7 samples (that of :mod:`budget.noise.spikes`), is
  replaced by that median, so that heavy-tailed single samples (Student-t ν = 4) and spikes or
  bursts of up to 3 samples add nothing (they are :mod:`budget.noise.spikes`' concern); an event
  of 4 samples or more moves the median with it and passes whole;
* **window statistic**: at every sample k and window L = 4, 8, 16, … samples up to
  :data:`TRANSIENT_MAX_S` = 1 s (and 1/64 of the record), y_k = mean(x[k:k+L]) −
  ½[mean(x[k−L:k]) + mean(x[k+L:k+2L])], the matched filter of an L-sample box against its two
  neighbours — it removes any level and linear trend, so bias instability, random walk and
  warm-up ramps do not enter, and its variance is the record's own (Allan-like) variance at
  τ = L/rate, which is measured: σ_y(L) = 1.4826·MAD of y over the record (an event of at most
  a second barely moves that median);
* **threshold** T = :data:`TRANSIENT_MARGIN` (1.4) × z_α, z_α the two-sided Gaussian level whose
  chance over the ≈ Σ n/L independent positions of a noise-only channel is :data:`TRANSIENT_ALPHA`
  = 10⁻³ (T = 8.5 for an hour at 400 Hz, 8.9 for six hours, 8.4 for the 2.8-h ADIS16405 logs at
  100 Hz, 7.7 for 7.5 min at 100 Hz). The margin is for noise that is not Gaussian: on 30 one-hour
  records at 400 Hz of each of white + flicker, Student-t (ν = 4) white + flicker, + a slow rate
  random walk (100 deg/h/√h), + a 7 Hz tone of 0.5 and of 2 × the white noise's σ per sample, no
  event was found; the largest |y|/σ_y reached 0.76–0.78 T, t(4) 0.88 T — with a margin of 1.25 it
  came within 2 % of T;
* **event**: positions with |y| ≥ T·σ_y (at any L) whose windows overlap form one event; its rows
  run from its first to its last sample beyond 5 robust σ of the local level (or, for a long low
  event, the window of largest excess); it is named with its mean offset and peak (against the
  median level of the record on both sides) and its z. A burst after which the level does not
  come back (|after − before| > half its offset) is a bias step, left to
  :func:`budget.noise.stationarity.bias_step_issue`.

**Detection limit.** The smallest mean offset an event of L samples must have is
``TransientStats.limit`` = T·σ_y(L) of the window (a box lying between two windows is caught
through the smaller one). On the hour at 400 Hz above (σ = 0.067 deg/s per sample): 0.35 deg/s
(5.2 σ) for 4 samples, 0.25 (3.7 σ) for 8, 0.12 (1.8 σ) for 32, 0.044 deg/s (0.66 σ) for 256
(0.64 s). **Caught** (claimed): a box of L = 4 … 400 samples whose offset is ≥ 1.5 × the limit of
the largest window not longer than it — 36 of 36 positions for boxes of 4, 6, 12, 40, 100 and 400
samples; at 1 × the limit 21 of 36, at 0.5 × none. The audit's knocks read z = 373 and 209 σ_y,
far above it. An event below the limit carries a small part of the record's variance at its time
scale (≈ z²·L/n: z = T, L = 256 of an hour at 400 Hz gives 1.3 %), and moves the fitted terms by
about as much.

**Refused or warned** (:func:`budget.noise.logs.read_log`). An event whose share of the record's
variance of y at its window (the Allan-like variance at τ = L/rate, before taming) is
≥ :data:`TRANSIENT_SHARE` = 20 % lifts the Allan deviation there to ≥ 1.12× what the rest of the
record gives — beyond the ≈ 13 % a datasheet figure is good to (the noise-level check's effect
size) — and so decides the fit, like a saturated run: the log is refused, naming the channel, rows
and size, with the remedy (cut the rows, characterise the record before or after them, or leave
the channel out). Refused, not repaired: which rows to drop (and whether the unit moved) is the
user's call, as for a saturated run. A smaller event is found but does not decide the figures: a
warning, like a bias step (on the first 200 s of ADIS16405 log 1 the settling at 6.8 s carries
13 % of accel_z's variance at 40 ms: its deviation there 7 % high, a warning). The real 2.8-h ADIS16405 logs read no event on their gyros (largest
|y|/σ_y 0.8 T) and warnings on accel_z: the bench settling in the first 7 s of log 1 (at 3.3 and
6.8 s accel_z rings between −9.3 and −10.5 m/s² for 6–8 samples against a noise of 0.045 m/s²,
gyro_y reads −1.5 deg/s in the same rows; 1.8–1.9 T) and a 4-sample burst at 99.4 s of log 2 (1.03 T; accel_x
reads 7.0 and accel_y 4.9 σ_y in the same rows, so it is no chance peak of one channel). The
MPU-6050 log reads none (0.68 T).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .log_checks import LogIssue
from .stationarity import MIN_SAMPLES, _fmt, _robust_sigma, _Rows

#: Shortest window (samples) of the transient search: one more than the burst of adjacent spikes
#: :mod:`budget.noise.spikes` replaces (3).
TRANSIENT_MIN = 4
#: Longest window: this many seconds of record (and at most 1/64 of it).
TRANSIENT_MAX_S = 1.0
#: Family-wise false-alarm rate per channel of a noise-only record (Gaussian model).
TRANSIENT_ALPHA = 1e-3
#: The Gaussian level is multiplied by this margin: a robust scale of non-Gaussian noise
#: (Student-t ν = 4, a quantized channel) understates its far tail (module doc, measured).
TRANSIENT_MARGIN = 1.4
#: Samples further than this many robust σ from the running median of :data:`TRANSIENT_BASE`
#: samples are replaced by it before the search (heavy-tailed single samples and spikes of up to
#: 3 samples cannot add up to an event; 4 or more move the median and pass).
TRANSIENT_CLIP = 5.0
TRANSIENT_BASE = 7
#: An event carrying at least this share of the record's variance at its own time scale decides
#: the Allan fit there: the log is refused (below: a warning).
TRANSIENT_SHARE = 0.2
#: Values evenly spaced through a series from which its robust scale is estimated.
_SCALE_VALUES = 1 << 16
#: Events named in a message.
_LISTED = 3


def _tamed(x: np.ndarray) -> tuple[np.ndarray, float]:
    """(``x`` with every sample further than :data:`TRANSIENT_CLIP` robust σ from its local level,
    the running median of :data:`TRANSIENT_BASE` = 7 samples, replaced by that median; the robust
    σ of the samples about it). A heavy-tailed noise sample, a spike or a burst of up to three
    (what :mod:`budget.noise.spikes` replaces) then adds nothing to a window; an event of 4 samples
    or more moves the median with it and passes whole."""
    from .transient_kernels import median7

    med = median7(x)
    r = x - med
    s = _robust_sigma(r[::max(1, x.size // _SCALE_VALUES)])
    far = np.abs(r) >= TRANSIENT_CLIP * s
    r[far] = 0.0  # replaced by the median: a burst of ≤ 3 samples adds nothing
    r += med
    return r, s


def transient_windows(n: int, rate_hz: float) -> list[int]:
    """The window lengths searched: 4, 8, 16, … samples up to :data:`TRANSIENT_MAX_S` of record
    (and 1/64 of the record)."""
    top = max(TRANSIENT_MIN, min(int(round(TRANSIENT_MAX_S * rate_hz)), n // 64))
    out, L = [], TRANSIENT_MIN
    while L <= top:
        out.append(L)
        L *= 2
    return out


def transient_threshold(n: int, windows: list[int]) -> float:
    """The threshold on |y|/σ_y (module doc): :data:`TRANSIENT_MARGIN` × the two-sided Gaussian
    level whose chance, over the ≈ Σ n/L independent window positions, is :data:`TRANSIENT_ALPHA`."""
    from scipy.special import ndtri

    tests = sum(n / L for L in windows)
    return TRANSIENT_MARGIN * float(-ndtri(TRANSIENT_ALPHA / (2.0 * max(tests, 1.0))))


def _hat(cs: np.ndarray, L: int) -> np.ndarray:
    """y_k = mean(x[k:k+L]) − ½[mean(x[k−L:k]) + mean(x[k+L:k+2L])] for k = L … n−2L, from the
    cumulative sum ``cs`` (cs[0] = 0); element i is k = L + i."""
    B = cs[L:] - cs[:-L]
    return (B[L:-L] - 0.5 * (B[:-2 * L] + B[2 * L:])) / L


@dataclass(frozen=True)
class Transient:
    """One transient event of a channel: samples ``start`` … ``stop`` − 1 (0-based) of its core
    (the window of largest excess), its window ``L`` (samples), ``z`` (|y|/σ_y), the mean offset of
    the core from its two neighbouring windows and the largest deviation in it (channel unit),
    and its ``share`` of the record's variance of y at that window (the Allan-like variance at
    τ = L/rate)."""

    start: int
    stop: int
    L: int
    z: float
    offset: float
    peak: float
    share: float


@dataclass(frozen=True)
class TransientStats:
    """The search of one channel: the events found (largest z first), the threshold, the largest
    z of each window (``zmax``) and the smallest mean offset of an L-sample box the search catches
    at each window (``limit``: threshold × σ_y, channel unit)."""

    events: tuple[Transient, ...]
    threshold: float
    windows: tuple[int, ...]
    zmax: tuple[float, ...]
    limit: tuple[float, ...]


def transient_stats(x: np.ndarray, rate_hz: float) -> TransientStats | None:
    """The transient search of the module doc on one channel; None when it is too short
    (< :data:`budget.noise.stationarity.MIN_SAMPLES`), not finite or constant."""
    x = np.asarray(x, float)
    n = x.size
    if n < MIN_SAMPLES or not np.all(np.isfinite(x)) or np.ptp(x) == 0:
        return None
    x = x - float(np.median(x[::max(1, n // _SCALE_VALUES)]))
    cs = np.empty(n + 1)
    cs[0] = 0.0
    tamed, sigma = _tamed(x)
    np.cumsum(tamed, out=cs[1:])
    del tamed
    windows = transient_windows(n, rate_hz)
    thr = transient_threshold(n, windows)
    hits, zmax, limit = [], [], []
    from .transient_kernels import hat_max

    for L in windows:
        # σ_y from evenly spaced positions, the largest |y| in one compiled pass; y itself only
        # where something reaches the threshold
        k = np.arange(L, n - 2 * L + 1, max(1, (n - 3 * L) // _SCALE_VALUES))
        y = ((cs[k + L] - cs[k]) - 0.5 * ((cs[k] - cs[k - L]) + (cs[k + 2 * L] - cs[k + L]))) / L
        s = _robust_sigma(y)
        top = float(hat_max(cs, L))
        zmax.append(top / s if s > 0 else 0.0)
        limit.append(thr * s)
        if s > 0 and top >= thr * s:
            a = np.abs(_hat(cs, L))
            idx = np.flatnonzero(a >= thr * s)
            hits.append((L, idx + L, a[idx] / s))
    events: list[Transient] = []
    if hits:
        # positions whose windows (left neighbour, box, right neighbour) overlap form one event
        cover = np.zeros(n + 1, dtype=np.int64)
        for L, k, _ in hits:
            np.add.at(cover, k - L, 1)
            np.add.at(cover, np.minimum(k + 2 * L, n), -1)
        inside = np.cumsum(cover[:-1]) > 0
        edges = np.flatnonzero(np.diff(np.concatenate(([0], inside.astype(np.int8), [0]))))
        raw = np.empty(n + 1)
        raw[0] = 0.0
        np.cumsum(x, out=raw[1:])
        total = {}
        for a0, b0 in zip(edges[::2], edges[1::2]):
            best = None
            for L, k, z in hits:  # k ascending: the positions of this event by bisection
                i0, i1 = np.searchsorted(k, a0), np.searchsorted(k, b0)
                if i1 > i0:
                    j = i0 + int(np.argmax(z[i0:i1]))
                    if best is None or z[j] > best[2]:
                        best = (L, int(k[j]), float(z[j]))
            L, k, z = best
            if a0 == 0 and b0 >= n:
                continue  # the whole record: nothing to come back to (a regime, not an event)
            m = max(4 * L, 64)
            before = float(np.median(x[max(0, a0 - m):a0])) if a0 > 0 else None
            after = float(np.median(x[b0:b0 + m])) if b0 < n else None
            before = after if before is None else before
            after = before if after is None else after
            base = 0.5 * (before + after)
            dev = x[a0:b0] - base
            strong = np.flatnonzero(np.abs(dev) >= TRANSIENT_CLIP * sigma)
            # the event's rows: from its first to its last sample beyond 5 σ of the local noise, or
            # (a long, low event) the window of largest excess
            start, stop = (a0 + int(strong[0]), a0 + int(strong[-1]) + 1) if strong.size else (k, k + L)
            ev = x[start:stop] - base
            offset = float(ev.mean())
            if abs(after - before) > 0.5 * abs(offset):
                continue  # the level does not come back: a bias step (bias_step_issue), not a transient
            if L not in total:
                yr = _hat(raw, L)
                total[L] = (yr, float(yr @ yr))
            yr, tot = total[L]
            part = yr[max(0, a0 - L):max(0, b0 - L)]
            share = min(1.0, float(part @ part) / tot) if tot > 0 else 0.0
            peak = float(ev[int(np.argmax(np.abs(ev)))])
            events.append(Transient(start, stop, L, z, offset, peak, share))
    events.sort(key=lambda e: -e.z)
    return TransientStats(tuple(events), thr, tuple(windows), tuple(zmax), tuple(limit))


def transient_issue(x: np.ndarray, rate_hz: float, channel: str, unit: str, rows: _Rows,
                    ) -> tuple[LogIssue | None, bool]:
    """(the finding, whether it refuses the log) for one channel: None when no transient event is
    found. The event that carries the largest share of the variance at its window decides:
    ≥ :data:`TRANSIENT_SHARE` refuses (module doc, "Refused or warned")."""
    st = transient_stats(x, rate_hz)
    if st is None or not st.events:
        return None, False
    worst = max(st.events, key=lambda e: e.share)
    refuse = worst.share >= TRANSIENT_SHARE
    # largest z first; an event that refuses the log is named first
    ev = ((worst,) + tuple(e for e in st.events if e is not worst)) if refuse else st.events
    listed = "; ".join(
        f"{rows.span(e.start, e.stop) if e.stop - e.start > 1 else rows.at(e.start)} "
        f"({e.stop - e.start} sample{'s' if e.stop - e.start > 1 else ''}, {(e.stop - e.start) / rate_hz:.3g} s): "
        f"mean offset {_fmt(e.offset, unit, large=True)}, peak {_fmt(e.peak, unit, large=True)}; {e.z:.0f} σ of the record's "
        f"own noise in a {e.L}-sample window (threshold {st.threshold:.2g} σ), {100 * e.share:.2g} % of its "
        "variance at that window"
        for e in ev[:_LISTED])
    more = f"; +{len(ev) - _LISTED} more" if len(ev) > _LISTED else ""
    msg = (f"{len(ev)} transient event(s) — a burst far beyond the record's own noise that returns to "
           f"the previous level (a knock, a touch, a door?): {listed}{more}")
    if refuse:
        msg += (f"; {'it' if len(ev) == 1 else 'the first'} carries ≥ {100 * TRANSIENT_SHARE:g} % of the record's variance at its time scale and "
                "would decide the Allan fit there (ARW and bias instability come out too large)")
    else:
        msg += (f"; below {100 * TRANSIENT_SHARE:g} % of the record's variance at its time scale it does "
                "not decide the Allan fit: kept")
    return LogIssue("transient", "error" if refuse else "warning", msg, len(ev),
                    tuple(int(e.start) + rows.first for e in ev[:_LISTED]), channel), refuse
