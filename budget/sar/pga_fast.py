"""PGA's fast-phase stage (:mod:`budget.sar.pga`, "Fast-phase stage"): after convergence, the
phase above the settled window's bandwidth, estimated one DCT octave at a time with the narrowest
window that sees it and kept only where it is significant against its jackknife noise. A band's
loops (its ML sums with and without each group, their integration, the jackknife noise) are
compiled here, in the manner of :mod:`budget.sar.pga_kernels`."""

from __future__ import annotations

import numpy as np

from numba import njit

from .pga_kernels import (_ramp_columns, _ramp_factor, centroid_slope, group_products, group_starts, refine_ramp,
                          weights_and_lines, window_in_place)
from .pga_lines import _SPAN_FRACTION, _bias, _centre, _Lines, _window, dct_lines, fft_lines, ifft_lines
from .residual import highpass_phase

# lines less than 2 range lines apart form one jackknife group


_GROUP_GAP_LINES = 1


_MIN_GROUPS = 3


# the span holds bins whose energy is at least this many times the 5th percentile (signal ≥ noise)
_SPAN_FLOOR = 2.0


#: Depth (dB below the stage's level) of the gap that cuts a bin off from the aperture band
#: (:func:`_joined_to_peak`). Noise alone rarely digs it: the level is at least twice the 5th
#: percentile, ≈ 0.1 × the mean of one line's exponential noise energy, and a bin falls 10 dB
#: below that with probability ≈ 1 % (less for a sum of lines).
_BAND_GAP_DB = 10.0


# Compiled loops of a band (as in :mod:`budget.sar.pga_kernels`).


@njit(cache=True)
def corrected_refine_ramp(shifted: np.ndarray, h_shift: np.ndarray, rows: np.ndarray, rot: np.ndarray,
                          cols: np.ndarray, phi_c: np.ndarray) -> np.ndarray:
    """:func:`refine_ramp` of ``phase_corrected(h_shift, phi_c)``, forming the corrected values of
    the selected lines only (the same products in the same order)."""
    n = h_shift.shape[0]
    half = n // 2
    src = np.empty((n, cols.size), dtype=np.complex128)
    for k in range(n):
        p = phi_c[(k + half) % n]
        e = complex(np.cos(p), -np.sin(p))
        for j in range(cols.size):
            src[k, j] = h_shift[k, cols[j]] * e
    slope = centroid_slope(shifted, rows, rot, cols)
    z = np.empty(cols.size, dtype=np.complex128)
    for j in range(cols.size):
        z[j] = _ramp_factor(slope[j] * n / (2.0 * np.pi), n)
    _ramp_columns(src, src, np.arange(cols.size), z)
    return src


@njit(cache=True)
def band_sums(h: np.ndarray, lo: int, hi: int, starts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(imaginary, real parts) of the ML kernel's sums for the fast-phase bands over the centred
    bins c = lo+1 … hi−1 (rows): column 0 the sum over every group of :func:`group_products`,
    column 1 + g that sum less group g — the arguments whose angles :func:`band_phases` takes,
    summed in the same order, for one vectorised arctan2."""
    prod = group_products(h, lo, hi, starts)
    m, n_g = prod.shape
    im = np.empty((m, n_g + 1))
    re = np.empty((m, n_g + 1))
    for i in range(m):
        t = 0.0 + 0.0j
        for g in range(n_g):
            t += prod[i, g]
        im[i, 0] = t.imag
        re[i, 0] = t.real
        for g in range(n_g):
            r = t - prod[i, g]
            im[i, g + 1] = r.imag
            re[i, g + 1] = r.real
    return im, re


@njit(cache=True)
def accumulate_phases(angles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """From the increments of :func:`band_sums` (rows × (1 + groups), rad): the estimate
    [0, cumsum(column 0)] and the delete-one-group estimates [0, cumsum(columns 1 …)], as
    :func:`band_phases` returns them."""
    m, cols = angles.shape
    est = np.zeros(m + 1)
    jk = np.zeros((m + 1, cols - 1))
    for i in range(m):
        est[i + 1] = est[i] + angles[i, 0]
        for g in range(cols - 1):
            jk[i + 1, g] = jk[i, g] + angles[i, g + 1]
    return est, jk


@njit(cache=True)
def jackknife_noise(coef_jk: np.ndarray, m_lo: int, m_hi: int) -> float:
    """Delete-one-group jackknife variance summed over the DCT indices m_lo < m ≤ m_hi:
    Σ_m (G − 1)/G · Σ_g (a_{m,g} − mean_g a_{m,g})², from the coefficients ``coef_jk`` (DCT index ×
    group G of them)."""
    n_g = coef_jk.shape[1]
    total = 0.0
    for m in range(m_lo + 1, m_hi + 1):
        mean = 0.0
        for g in range(n_g):
            mean += coef_jk[m, g]
        mean /= n_g
        acc = 0.0
        for g in range(n_g):
            dev = coef_jk[m, g] - mean
            acc += dev * dev
        total += (n_g - 1) / n_g * acc
    return total


def _percentile(x: np.ndarray, q: float) -> float:
    """``np.percentile(x, q)`` of a finite 1-D array (linear method), the same arithmetic on the
    two order statistics from one partition, without np.percentile's general machinery."""
    n = x.size
    virtual = (n - 1) * (q / 100)
    below = np.floor(virtual)
    i = n - 1 if virtual >= n - 1 else int(below)
    j = min(i + 1, n - 1)
    part = np.partition(x, [i, j] if j != i else i)
    a, b = part[i], part[j]
    t = virtual - below
    diff = b - a
    return float(b - diff * (1 - t) if t >= 0.5 else a + diff * t)


def _joined_to_peak(energy: np.ndarray, level: float) -> tuple[int, int]:
    """(first, last + 1) of the bins joined to the peak of ``energy`` (centred bins): the run
    around the peak bin in which no bin lies more than :data:`_BAND_GAP_DB` below ``level`` (the
    stage's "bins with signal" level, :func:`_fast_bands`). Only the bins inside it count as
    signal: a spectral line cut off from the aperture band by a deeper gap — the noise-free
    simulated images show one at −29 to −34 dB of the peak, 36–96 Hz outside the band, behind
    bins 15–26 dB below the level — is not the aperture's, and a basis fitted out to it would
    follow no phase of the aperture over the gap. On clutter and noise the bins around the band
    fluctuate about the floor and stay joined."""
    peak = int(np.argmax(energy))
    gaps = np.flatnonzero(energy < level * 10 ** (-_BAND_GAP_DB / 10))
    at = int(np.searchsorted(gaps, peak))  # never the peak: the level is at most twice the peak energy
    return (int(gaps[at - 1]) + 1 if at else 0), (int(gaps[at]) if at < gaps.size else energy.size)


def _groups(lines: np.ndarray) -> np.ndarray:
    """Jackknife group per candidate line (sorted range indices): runs of adjacent range lines
    share one, since their clutter and their scatterer are correlated (range oversampling)."""
    return np.concatenate([[0], np.cumsum(np.diff(lines) > _GROUP_GAP_LINES)])


def _band(d: _Lines, centred: tuple, added: np.ndarray, width: int, lo: int, hi: int, m_lo: int,
          m_hi: int, groups: np.ndarray, band_snr: float) -> tuple[np.ndarray, dict]:
    """The phase in DCT band m_lo < m ≤ m_hi over the bins lo … hi−1, estimated with the ML kernel
    at window ``width`` on the ``centred`` lines (:func:`_centre` on the converged estimate)
    corrected with the bands ``added`` so far (centred bins), and kept only if significant: band
    power P = Σ a_m² against its delete-one-group jackknife variance V = Σ v_m (Efron & Stein
    1981; groups of adjacent lines), kept when P ≥ ``band_snr`` · V and then scaled by the Wiener
    gain 1 − V/P. Returns (phase to add, centred bins; the band's record)."""
    n = d.hist.shape[0]
    h_shift, shifted, pw = centred
    rows, rot, inside = _window(n, width)
    scr, w_line, cols = weights_and_lines(pw, rows, d.c_line, _bias(d, rows))
    record = {"window": int(width), "m_lo": int(m_lo), "m_hi": int(m_hi), "band_rms_rad": 0.0,
              "noise_rms_rad": float("nan"), "gain": 0.0, "noise_from": "jackknife"}
    keep = w_line > 0
    if cols.size == 0:
        return np.zeros(n), record
    # step 2's centroid refinement and step 3's window (:func:`_refine`) on the lines corrected
    # with the bands added so far, forming only the lines that carry weight
    if np.any(added):
        win = corrected_refine_ramp(shifted, h_shift, rows, rot, cols, added)
    else:
        win = refine_ramp(shifted, h_shift, rows, rot, cols)
    win = fft_lines(win, out=win)
    window_in_place(win, inside, w_line, cols)
    hist_w = ifft_lines(win, out=win)
    # lines of zero weight carry nothing: their groups are not data
    starts = group_starts(groups, keep)  # groups are runs of sorted lines
    n_g = starts.size
    # Σ G(k) G*(k−1) over the groups inside the span, and without each group: their angles
    # integrate to the estimate over the span and its delete-one-group versions
    im, re = band_sums(hist_w, lo, hi, starts)
    est, jk = accumulate_phases(np.arctan2(im, re, out=im))
    # orthonormal DCT-II over the span (index m ↔ m/2 cycles), the band's coefficients
    coef = dct_lines(est)[m_lo + 1:m_hi + 1]
    if n_g >= _MIN_GROUPS:
        noise = float(jackknife_noise(dct_lines(jk), m_lo, m_hi))
    else:
        # one or two scatterers (a calibration reflector): no jackknife; the closed form — white
        # per-bin phase noise of variance 1/(2 Σ SCR) (Jakowatz & Wahl 1993), σ² per orthonormal
        # DCT coefficient — covers first-order clutter only (no neighbours' sidelobes)
        noise = (m_hi - m_lo) * 0.5 / max(float(np.sum(scr[keep])), 1e-300)
        record["noise_from"] = "closed_form"
    power = float(np.sum(coef ** 2))
    span = hi - lo
    record.update(band_rms_rad=float(np.sqrt(power / span)), noise_rms_rad=float(np.sqrt(noise / span)))
    out = np.zeros(n)
    if power > 0 and power >= band_snr * noise:
        record["gain"] = 1.0 - noise / power
        full = np.zeros(hi - lo)
        full[m_lo + 1:m_hi + 1] = coef
        out[lo:hi] = record["gain"] * dct_lines(full, inverse=True)
    return out, record


def _fast_bands(d: _Lines, phi_c: np.ndarray, width: int, lines: np.ndarray,
                band_snr: float, aperture: tuple[int, int] | None = None) -> tuple[np.ndarray, list[dict]]:
    """The fast-phase stage: the bands beyond the settled window ``width`` estimated one octave at
    a time, band (m_{j−1}, m_j] of the DCT over the span at window 2^j·W, the narrowest window that
    sees it (m_j = ⌊2^j W · span/n⌋: W samples see W/2 cycles per n bins), and first the handover
    band (0, m_0] at window 2W (:mod:`budget.sar.pga`, "Fast-phase stage"), each kept only where
    significant (:func:`_band`). The span and the interval of the cut-back hold only bins joined
    to the peak (:func:`_joined_to_peak`); ``aperture`` = (first, last + 1) of the processed
    aperture's centred bins, when the caller knows it, is the cut-back's interval instead
    (:mod:`budget.sar.pga`, "Fast-phase stage": the lines' energy cannot locate the aperture's
    ends under receiver noise). Returns the estimate with the kept bands added, and the
    records."""
    n = d.hist.shape[0]
    energy = np.fft.fftshift(d.energy)
    peak = energy.max()
    # the noise floor: twice the 5th percentile (out-of-band bins of a noisy image are noise
    # only, and a basis stretched over them cannot follow the in-band phase); the level of the
    # bins with signal: within the iterations' band_db of the peak energy — below it no bin
    # carries a gradient — and above the floor; only bins joined to the peak count
    # (:func:`_joined_to_peak`), so both intervals below lie inside [j_lo, j_hi)
    floor = _SPAN_FLOOR * _percentile(energy, 5.0)
    level = max(10 ** (-d.band_db / 10) * peak, floor)
    j_lo, j_hi = _joined_to_peak(energy, level)
    joined = energy[j_lo:j_hi]
    # the span: bins within 10 dB of the peak energy that also hold at least as much signal as
    # noise
    idx = np.nonzero(joined >= max(_SPAN_FRACTION * peak, floor))[0] + j_lo
    groups = _groups(lines)
    if idx.size < 16:
        return phi_c, []
    lo, hi = int(idx[0]), int(idx[-1]) + 1
    span = hi - lo
    w, m_prev = width, int(width * span // n)
    # Beyond the settled window the accumulated estimate holds what the early, wider windows put
    # there — on clutter mostly their clutter × clutter random walk, largest at the weighted
    # aperture's ends, where the lines have least energy and the increments are not smoothed.
    # It must pass the same test as any other phase there: drop it over every bin with signal
    # (at or above the level; weighted by the lines' energy, so bins with little signal do not
    # steer the fit) and let the bands below re-estimate over the span what is significant.
    full = np.nonzero(joined >= level)[0] + j_lo
    c_lo, c_hi = (int(full[0]), int(full[-1]) + 1) if aperture is None else aperture
    phi_c = phi_c.copy()
    phi_c[c_lo:c_hi] -= highpass_phase(phi_c[c_lo:c_hi], width * (c_hi - c_lo) / (2.0 * n), energy[c_lo:c_hi])
    records = []
    centred = _centre(d, phi_c)  # the lines centred once, on the converged estimate
    added = np.zeros(n)
    handover = m_prev > 0
    while m_prev < span - 1 and w < n:
        w = min(2 * w, n)
        m_hi = min(int(w * span // n), span - 1)
        if handover:
            # the handover band (0, m_prev] at the first band's window: the cut-back above worked
            # over another interval, and what it took away above K there has a part at m ≤ m_prev
            # over the span, which the bands above m_prev could never give back. A band of its
            # own, so that it is kept only where significant.
            add, rec = _band(d, centred, added, w, lo, hi, 0, m_prev, groups, band_snr)
            added += add
            records.append(rec)
            handover = False
        add, rec = _band(d, centred, added, w, lo, hi, m_prev, m_hi, groups, band_snr)
        added += add
        records.append(rec)
        m_prev = m_hi
    return phi_c + added, records
