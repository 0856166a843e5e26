"""Is a "static" log one regime? Noise-level changes and bias steps, per channel.

An Allan fit assumes one stationary noise process over the whole record. A log in which the
vehicle started moving, a fan or heater switched on, or the bias jumped mixes two regimes, and
the fit silently averages them. :func:`check_stationarity` looks for the two signatures that
*slow* noise terms cannot produce, and warns (it never refuses: the user decides); a third, a
brief burst that comes back (a knock), is searched for by the log reader
(:mod:`budget.noise.transients`):

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
