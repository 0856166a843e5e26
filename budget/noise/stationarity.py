"""Is a "static" log one regime? Noise-level changes and bias steps, per channel.

An Allan fit assumes one stationary noise process over the whole record. A log in which the
vehicle started moving, a fan or heater switched on, or the bias jumped mixes two regimes, and
the fit silently averages them. :func:`check_stationarity` looks for the two signatures that
*slow* noise terms cannot produce, and warns (it never refuses: the user decides); a third, a
brief burst that comes back (a knock), is searched for by the log reader
(:func:`transient_issue`, below):

**Noise level** (kind ``noise_level_change``). The first differences x[k+1] − x[k] of a static
record are dominated by the white (ARW/VRW, quantization) noise; the slow terms — rate random
walk, bias instability (flicker), Gauss–Markov, a temperature ramp — add an increment per sample
that is stationary too, and of order K·√Δt or B·√Δt, far below the white part at any rate a log
is taken at. So the level of the differences is the same in every part of a one-regime record,
whatever its slow terms. The record is cut into :data:`SEGMENTS` = 8 segments; in each, the
level is the rms of the differences about their median, after winsorizing at
:data:`WINSOR_SIGMAS` = 6 robust (MAD-based) standard deviations of the whole channel, so that
spikes do not count. (A plain MAD per segment is not used: on a channel quantized to about one
LSB — the ADIS16405 accelerometers — the MAD jumps between whole LSBs; the winsorized rms is
continuous and still robust.) A warning needs both

* an effect a user would care about: max/min of the segment levels ≥ :data:`LEVEL_RATIO` = 1.25
  (25 % in rms, 56 % in variance). Two halves whose rms differ by 25 % give a fitted ARW/VRW
  13 % above the quieter and 10 % below the noisier regime — about the tolerance of a datasheet
  figure; smaller differences stay within it and are not worth a warning; and
* significance given the segment sizes: ln(v_max/v_min) above :data:`LEVEL_Z` = 5 standard
  errors, each segment's standard error measured from the scatter of its 16 sub-block mean
  squares (so correlation and non-Gaussian tails of the differences are measured, not assumed).
  On 150 simulated one-regime records at each of 2,048, 4,096 and 36,000 samples (30 of 360,000)
  the largest z was 4.2 and none met both conditions; short records reach a ratio of 1.3 by
  chance, which the z test stops. On an hour at 100 Hz the standard error is < 1 %, so there
  the 1.25× effect size decides: the real 2.8-h ADIS16405 logs reach z = 23 at a ratio of only
  1.12 (``accel_y`` of log 1: its sample-to-sample noise rises by ~10 % after the first ~40 min
  and stays — real and significant, but below what would change a catalog figure).

The change is located at the maximum of the CUSUM of the winsorized squared differences (the
classic single variance change point) and the warning names the rows before and after it.

**Bias step** (kind ``bias_step``). The record is cut into :data:`STEP_BLOCKS` = 64 blocks and
each block is summarised by its level m_j: the mean after winsorizing at
:data:`BLOCK_WINSOR_SIGMAS` = 5 robust standard deviations about the block median (robust to
spikes; a plain median is not used because on a channel quantized to about one LSB it snaps to
the lattice and jumps by a whole LSB when a slow drift crosses half of one). The local jump at a boundary is
r_j = (m_{j+1} − m_j) − ½[(m_j − m_{j−1}) + (m_{j+2} − m_{j+1})]: the jump between two blocks
minus the local trend of the neighbouring jumps. A step Δ between blocks j and j+1 gives
r_j ≈ Δ (its neighbours −Δ/2). Stationary slow noise — rate random walk, flicker, Gauss–Markov —
moves the block levels too, but by stationary increments: their jumps are Gaussian with one
scale, which is measured from the record itself as 1.4826·MAD of all the r_j (the series' own
wandering at block scale, white, flicker and random walk together). A linear temperature ramp
is removed by the local trend; a slow warm-up (time constant ≫ a block) bends it only slightly.
Four block grids, each shifted by a quarter block, are tried (a step inside a block of one grid
splits its jump over two boundaries; it lies near a boundary of another). A step is warned about
when |r_j| ≥ :data:`STEP_SIGMAS` = 8 of those scales. The largest of ~60 Gaussian jumps is about
3 scales; over the four grids, on 150 simulated one-regime records of each kind (white +
flicker + random walk, white- or random-walk-dominated, quantized, with Gauss–Markov terms or
spikes) the largest was 5.8, on the two real 2.8-h ADIS16405 logs 5.9 (a one-block bump of
``gyro_x`` in log 2, not a step) — 8 leaves room for the MAD of 60 values coming out 25 % low. A random walk, however
strong, scales the MAD with it and cannot reach 8. The step's row is refined inside the two
blocks by the largest (balanced) difference of means left and right.

What a step means for the fit, and the detection limit: a step Δ in a record of duration T has
the Allan variance Δ²τ/(3T), i.e. it is read as rate random walk K = Δ/√T and lifts the long-τ
end of the curve (bias instability and RRW come out too large). The smallest step warned about
is 8 × the record's own block-to-block wandering, which on a tactical gyro is set by its bias
instability more than by its white noise: for ARW 0.15 deg/√h, bias instability 1 deg/h, 1 h at
100 Hz, a step of 5 × the 1-s Allan deviation (≈ 45 deg/h) was warned about at 16 of 16
simulated positions, 4 × at 14 and 3 × at 2. A
smaller step is within what the part's own bias does at that time scale and a record of this
length cannot tell it from bias instability (it is then fitted as such, with the record's
length as the only remedy).

**Transient events** (kind ``transient``; :func:`transient_stats`, called by
:func:`budget.noise.logs.read_log`). A knock, a touch of the bench or a door slammed gives a burst
of a few samples to about a second, far beyond the record's own noise, after which the level comes
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
  come back (|after − before| > half its offset) is a bias step, left to :func:`bias_step_issue`.

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

Logs shorter than :data:`MIN_SAMPLES` samples are not checked (segments too short to compare).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .log_checks import LogIssue

#: Number of segments whose noise level is compared.
SEGMENTS = 8
#: Warn when the largest segment rms of the first differences is this many times the smallest.
LEVEL_RATIO = 1.25
#: … and the log-ratio of the two mean squares exceeds this many standard errors.
LEVEL_Z = 5.0
#: Sub-blocks per segment for the standard error of its mean square.
SUB_BLOCKS = 16
#: Differences beyond this many robust standard deviations (of the whole channel) are clipped.
WINSOR_SIGMAS = 6.0
#: Number of blocks whose levels are compared for bias steps.
STEP_BLOCKS = 64
#: Samples further than this many robust standard deviations from their block's median are
#: clipped before the block's mean is taken.
BLOCK_WINSOR_SIGMAS = 5.0
#: Block grids tried, each shifted by 1/STEP_PHASES of a block (a step inside a block of one
#: grid splits its jump over two boundaries; it lies within 1/8 block of a boundary of another).
STEP_PHASES = 4
#: A bias step must exceed this many robust scales of the local jumps of the block levels.
STEP_SIGMAS = 8.0
#: Shorter logs are not checked.
MIN_SAMPLES = 2048

_MAD = 1.482602218505602  # σ / MAD of a Gaussian


@dataclass(frozen=True)
class _Rows:
    """Rows of the record: spreadsheet rows of the file (header = row 1) unless repaired."""

    first: int
    label: str

    def span(self, a: int, b: int) -> str:
        """Rows of samples a … b−1 (0-based, b exclusive)."""
        return f"{self.label} {a + self.first:,}–{b - 1 + self.first:,}"

    def at(self, k: int) -> str:
        return f"{self.label[:-1]} {k + self.first:,}"


def record_rows(repaired: bool) -> _Rows:
    """How findings name a sample: its spreadsheet row (first sample = row 2), or its sample number
    in a repaired record (rows dropped)."""
    return _Rows(1, "samples") if repaired else _Rows(2, "rows")


def _robust_sigma(x: np.ndarray) -> float:
    """1.4826·MAD, or the standard deviation when more than half the values are equal
    (a quantized channel whose MAD is 0)."""
    med = np.median(x)
    mad = float(np.median(np.abs(x - med)))
    return _MAD * mad if mad > 0 else float(np.std(x))


def _level(w: np.ndarray) -> float:
    """Mean of ``w`` after winsorizing at :data:`BLOCK_WINSOR_SIGMAS` about its median."""
    med = float(np.median(w))
    clip = BLOCK_WINSOR_SIGMAS * _robust_sigma(w - med)
    return med + float(np.clip(w - med, -clip, clip).mean())


def _fmt(v: float, unit: str, large: bool = False) -> str:
    """A value in the channel's SI unit, with its datasheet unit beside it: deg/h and µg for a
    bias level, deg/s and g for a large excursion (``large``: a knock)."""
    from .. import units as u

    text = f"{v:.3g} {unit}"
    if unit == "rad/s":
        text += f" ({float(u.rad_s_to_dps(v)):.3g} deg/s)" if large else f" ({float(u.rad_s_to_deg_h(v)):.3g} deg/h)"
    elif unit == "m/s²":
        text += f" ({v / u.G0:.3g} g)" if large else f" ({float(u.m_s2_to_ug(v)):.3g} µg)"
    return text


@dataclass(frozen=True)
class LevelStats:
    """Noise levels of the :data:`SEGMENTS` segments (rms of the winsorized first differences)."""

    levels: np.ndarray  # rms per segment (channel unit)
    rel_se: np.ndarray  # relative standard error of each segment's mean square
    segment: int  # differences per segment
    ratio: float  # max/min of ``levels``
    z: float  # ln(v_max/v_min) in standard errors
    q: np.ndarray  # the winsorized squared differences (for locating the change)

    @property
    def flagged(self) -> bool:
        return self.ratio >= LEVEL_RATIO and self.z >= LEVEL_Z


def level_stats(x: np.ndarray) -> LevelStats | None:
    """The statistics of the noise-level check (module doc); None if the channel has no
    differences to compare."""
    d = np.diff(np.asarray(x, float))
    s = _robust_sigma(d)
    m = d.size // SEGMENTS
    if not s > 0 or m < 2 * SUB_BLOCKS:
        return None
    q = np.square(np.clip(d - np.median(d), -WINSOR_SIGMAS * s, WINSOR_SIGMAS * s))
    seg = q[:m * SEGMENTS].reshape(SEGMENTS, m)
    v = seg.mean(axis=1)
    if not np.all(v > 0):
        return None
    sub = m // SUB_BLOCKS
    subs = seg[:, :sub * SUB_BLOCKS].reshape(SEGMENTS, SUB_BLOCKS, sub).mean(axis=2)
    rse = subs.std(axis=1, ddof=1) / np.sqrt(SUB_BLOCKS) / v
    hi, lo = int(np.argmax(v)), int(np.argmin(v))
    z = float(np.log(v[hi] / v[lo]) / max(float(np.hypot(rse[hi], rse[lo])), 1e-300))
    return LevelStats(np.sqrt(v), rse, m, float(np.sqrt(v[hi] / v[lo])), z, q)


def noise_level_issue(x: np.ndarray, channel: str, unit: str, rows: _Rows) -> LogIssue | None:
    """The noise-level check of the module doc on one channel, or None."""
    st = level_stats(x)
    if st is None or not st.flagged:
        return None
    q, m = st.q, st.segment
    hi, lo = int(np.argmax(st.levels)), int(np.argmin(st.levels))
    c = np.cumsum(q - q.mean())  # CUSUM of the squared differences: one variance change point
    k = int(np.argmax(np.abs(c[:-1]))) + 1  # differences 0 … k−1 before, k … after: sample k
    before, after = float(np.sqrt(q[:k].mean())), float(np.sqrt(q[k:].mean()))
    msg = (f"noise level not constant: the rms of sample-to-sample differences is "
           f"{_fmt(st.levels[lo], unit)} in {rows.span(lo * m, (lo + 1) * m + 1)} but "
           f"{_fmt(st.levels[hi], unit)} in {rows.span(hi * m, (hi + 1) * m + 1)} "
           f"(×{st.ratio:.2f}, {st.z:.0f} standard errors); it changes near {rows.at(k)} "
           f"({_fmt(before, unit)} before, {_fmt(after, unit)} after); expected one level "
           f"throughout a static record at constant conditions (less than ×{LEVEL_RATIO:g} "
           f"between its {SEGMENTS} parts) — was the unit moved, or a fan, heater or motor "
           "switched on? The Allan fit mixes both regimes: characterise the parts separately")
    return LogIssue("noise_level_change", "warning", msg, 1, (k + rows.first,), channel)


@dataclass(frozen=True)
class StepStats:
    """The largest local jump of the block levels, in robust scales of all the jumps."""

    size: float  # |r_j| / scale
    scale: float  # 1.4826·MAD of the r_j (channel unit)
    block: int  # samples per block
    start: int  # first sample of the block pair that holds the jump

    @property
    def flagged(self) -> bool:
        return self.size >= STEP_SIGMAS


def step_stats(x: np.ndarray) -> StepStats | None:
    """The statistics of the bias-step check (module doc); None if there is nothing to compare."""
    x = np.asarray(x, float)
    L = x.size // STEP_BLOCKS
    if L < 1:
        return None
    best = None
    for off in range(0, L, max(1, L // STEP_PHASES)):  # grids shifted by a quarter block
        nb = (x.size - off) // L
        blocks = x[off:off + nb * L].reshape(nb, L)
        med = np.median(blocks, axis=1)
        resid = blocks - med[:, None]
        clip = BLOCK_WINSOR_SIGMAS * _robust_sigma(resid.ravel())
        # block level: mean after winsorizing about the block median (robust to spikes, and
        # continuous on a quantized channel, where a median snaps to the LSB lattice)
        med = med + np.clip(resid, -clip, clip).mean(axis=1)
        # jump between blocks j and j+1 minus the local trend: the mean of the two neighbouring
        # jumps (j−1 → j and j+1 → j+2), which a step at j does not enter
        dm = np.diff(med)
        r = dm[1:-1] - 0.5 * (dm[:-2] + dm[2:])
        scale = _robust_sigma(r)
        if not scale > 0:
            continue
        j = int(np.argmax(np.abs(r)))  # r[j] is the jump between blocks j+1 and j+2
        size = float(abs(r[j])) / scale
        if best is None or size > best.size:
            best = StepStats(size, scale, L, off + (j + 1) * L)
    return best


def bias_step_issue(x: np.ndarray, channel: str, unit: str, rows: _Rows) -> LogIssue | None:
    """The bias-step check of the module doc on one channel, or None."""
    x = np.asarray(x, float)
    st = step_stats(x)
    if st is None or not st.flagged:
        return None
    L = st.block
    w = x[st.start:st.start + 2 * L]
    cs = np.cumsum(w)
    kk = np.arange(1, w.size)
    left = cs[:-1] / kk
    right = (cs[-1] - cs[:-1]) / (w.size - kk)
    score = np.abs(right - left) * np.sqrt(kk * (w.size - kk) / w.size)
    k = st.start + int(np.argmax(score)) + 1  # first sample after the step
    a, b = max(0, k - 2 * L), min(x.size, k + 2 * L)
    lvl_b, lvl_a = _level(x[a:k]), _level(x[k:b])
    msg = (f"bias step: the level jumps by {_fmt(lvl_a - lvl_b, unit)} near {rows.at(k)} (mean "
           f"{_fmt(lvl_b, unit)} in {rows.span(a, k)}, {_fmt(lvl_a, unit)} in {rows.span(k, b)}), "
           f"{st.size:.0f}× the {_fmt(st.scale, unit)} by which the record's own block-to-block "
           f"wandering moves ({L:,}-sample block levels); expected a continuous bias (no jump "
           f"beyond {STEP_SIGMAS:g}×) in a static record — a knock, a power or mode change, a "
           "moved unit? The Allan fit reads the step as rate random walk: characterise the "
           "parts separately")
    return LogIssue("bias_step", "warning", msg, 1, (k + rows.first,), channel)


def check_stationarity(channels: dict[str, np.ndarray], units: dict[str, str] | None = None, *,
                       repaired: bool = False) -> list[LogIssue]:
    """Warnings (:class:`LogIssue`, severity ``warning``) for channels whose noise level changes
    or whose bias steps within the record; empty for a one-regime log or one shorter than
    :data:`MIN_SAMPLES`. Rows are spreadsheet rows of the file (first sample = row 2), or, when
    the log was ``repaired`` (rows dropped), sample numbers of the repaired record."""
    from ..units import channel_si_unit

    rows = record_rows(repaired)
    out: list[LogIssue] = []
    for ch, x in channels.items():
        x = np.asarray(x, float)
        if x.size < MIN_SAMPLES or not np.all(np.isfinite(x)) or np.ptp(x) == 0:
            continue
        unit = (units or {}).get(ch) or channel_si_unit(ch)
        for check in (noise_level_issue, bias_step_issue):
            issue = check(x, ch, unit, rows)
            if issue is not None:
                out.append(issue)
    return out


# --------------------------------------------------------------------------------------------
# Transient events ("knocks") below full scale
# --------------------------------------------------------------------------------------------

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
    (< :data:`MIN_SAMPLES`), not finite or constant."""
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
