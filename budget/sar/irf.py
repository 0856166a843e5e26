"""One-dimensional impulse-response measurements on a (periodic) image line.

Definitions (the results depend on them; the same ones measure the ideal of
:func:`budget.sar.windows.ideal_irf`):

* 3 dB width: distance between the first crossings of half the peak power on either side of the
  peak (linear interpolation of power on a ≥ 16× upsampled line);
* PSLR: highest power outside the main lobe over the peak power; the main lobe runs from the peak
  to the first local minimum on each side (searched up to 3 ideal first-null distances);
* ISLR: energy with null < |x − x_peak| ≤ extent over energy with |x − x_peak| ≤ null, where
  ``null`` is the IDEAL first-null distance of the window (so defocus that spills the main lobe
  counts as sidelobe energy) and ``extent`` defaults to the whole line (one period of a circular
  image, equivalent to an infinite extent; pass a number of metres to restrict it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from ..errors import InputError


def upsample_periodic(line: np.ndarray, factor: int) -> np.ndarray:
    """Band-limited interpolation of a periodic line by zero-padding its spectrum (same scale);
    a stack of lines (…, n) is interpolated along its last axis."""
    line = np.asarray(line)
    n = line.shape[-1]
    spec = sfft.fft(line, axis=-1)
    spec *= factor  # the scale of the inverse DFT of n·factor samples
    out = np.zeros(line.shape[:-1] + (n * factor,), dtype=complex)
    h = (n + 1) // 2
    out[..., :h] = spec[..., :h]
    out[..., n * factor - (n - h):] = spec[..., h:]
    if n % 2 == 0:  # split the Nyquist bin between ±N/2
        out[..., h] = 0.5 * spec[..., h]
        out[..., n * factor - (n - h)] = 0.5 * spec[..., h]
    return sfft.ifft(out, axis=-1, overwrite_x=True)


@dataclass(frozen=True)
class CutMeasurement:
    """Measurements of one cut; positions in the cut's units (m)."""

    peak_position: float
    peak_amplitude: float
    width_3db: float
    pslr_db: float
    islr_db: float


def measure_cut(cut: np.ndarray, spacing: float, origin: float, *, expected_index: float,
                search_half: int, null: float, extent: float | None = None) -> CutMeasurement:
    """Measure a finely sampled periodic cut |cut|² (sample i at ``origin + i·spacing``).

    The peak is searched within ±``search_half`` samples of ``expected_index``; ``null`` and
    ``extent`` are distances in the cut's units (see module docstring).
    """
    p = np.abs(cut) ** 2
    n = p.size
    win = np.mod(np.arange(int(np.floor(expected_index)) - search_half,
                           int(np.floor(expected_index)) + search_half + 2), n)
    ip = int(win[np.argmax(p[win])])
    # parabolic refinement of the peak on the amplitude
    a_m, a_0, a_p = np.sqrt(p[(ip - 1) % n]), np.sqrt(p[ip]), np.sqrt(p[(ip + 1) % n])
    den = a_m - 2 * a_0 + a_p
    delta = 0.5 * (a_m - a_p) / den if den < 0 else 0.0
    peak_amp = a_0 - 0.25 * (a_m - a_p) * delta
    centre = ip + delta
    half = p[ip] / 2.0
    null_s = null / spacing

    def crossing(direction: int) -> float:
        limit = n // 2
        k = 1
        while k < limit and p[(ip + direction * k) % n] >= half:
            k += 1
        if k >= limit:
            return float(limit)
        p1, p0 = p[(ip + direction * k) % n], p[(ip + direction * (k - 1)) % n]
        return (k - 1) + (p0 - half) / (p0 - p1)

    width = (crossing(+1) + crossing(-1)) * spacing

    def first_min(direction: int) -> int:
        limit = max(2, int(np.ceil(3.0 * null_s)))
        prev = p[ip]
        for k in range(1, min(limit, n // 2)):
            cur = p[(ip + direction * k) % n]
            if cur > prev:
                return k - 1
            prev = cur
        return min(limit, n // 2)

    k_right, k_left = first_min(+1), first_min(-1)
    ext_s = n / 2.0 if extent is None else min(extent / spacing, n / 2.0)
    # PSLR: highest sample outside the measured main lobe, within the extent
    q = p.copy()
    q[np.mod(np.arange(ip - k_left, ip + k_right + 1), n)] = 0.0
    if extent is not None and ext_s < n / 2.0:
        far = np.mod(np.arange(ip + int(np.floor(ext_s)) + 1, ip + n - int(np.floor(ext_s))), n)
        q[far] = 0.0
    pslr = 10 * np.log10(q.max() / peak_amp ** 2) if q.max() > 0 else -np.inf
    # ISLR: energy around the sub-pixel centre, main lobe ±ideal null, sidelobes to the extent
    lim = int(np.ceil(ext_s + 1))
    k = np.arange(int(np.floor(centre)) - lim, int(np.floor(centre)) + lim + 1)
    dist = np.abs(k - centre)
    pk = p[np.mod(k, n)]
    if extent is None:
        e_main = pk[dist <= null_s].sum()
        e_side = p.sum() - e_main
    else:
        e_main = pk[dist <= null_s].sum()
        e_side = pk[(dist > null_s) & (dist <= ext_s)].sum()
    islr = 10 * np.log10(e_side / e_main) if e_side > 0 else -np.inf
    return CutMeasurement(peak_position=origin + centre * spacing, peak_amplitude=float(peak_amp),
                          width_3db=float(width), pslr_db=float(pslr), islr_db=float(islr))


@dataclass(frozen=True)
class CutMeasurements:
    """:class:`CutMeasurement` of a stack of cuts: one array entry per cut."""

    peak_position: np.ndarray
    peak_amplitude: np.ndarray
    width_3db: np.ndarray
    pslr_db: np.ndarray
    islr_db: np.ndarray

    def __getitem__(self, i: int) -> CutMeasurement:
        return CutMeasurement(peak_position=float(self.peak_position[i]), peak_amplitude=float(self.peak_amplitude[i]),
                              width_3db=float(self.width_3db[i]), pslr_db=float(self.pslr_db[i]),
                              islr_db=float(self.islr_db[i]))


#: Samples looked at first for the half-power crossing (the rest of the half line only when needed).
_CROSSING_LOOKAHEAD = 256


def _first_true(flags: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(index of the first True along the last axis, whether there is one)."""
    return np.argmax(flags, axis=-1), flags.any(axis=-1)


def measure_cuts(cuts: np.ndarray, spacing, origin, *, expected_index, search_half: int, null,
                 extent=None) -> CutMeasurements:
    """:func:`measure_cut` of every row of ``cuts`` (L, n) at once (same definitions, module
    docstring): ``spacing``, ``origin``, ``expected_index`` and ``null`` are scalars or one value
    per cut; ``extent`` None (whole line) or scalars/arrays (NaN or inf: whole line)."""
    cuts = np.asarray(cuts)
    p = cuts.real ** 2 + cuts.imag ** 2 if np.iscomplexobj(cuts) else cuts ** 2
    if p.ndim != 2:
        raise InputError(f"cuts have shape {p.shape}", field="cuts", expected="a 2-D stack (L, n) of cuts")
    n_l, n = p.shape
    rows = np.arange(n_l)
    spacing = np.broadcast_to(np.asarray(spacing, dtype=float), (n_l,))
    origin = np.broadcast_to(np.asarray(origin, dtype=float), (n_l,))
    null_s = np.broadcast_to(np.asarray(null, dtype=float), (n_l,)) / spacing
    base = np.floor(np.broadcast_to(np.asarray(expected_index, dtype=float), (n_l,))).astype(np.int64)
    win = np.mod(base[:, None] + np.arange(-search_half, search_half + 2)[None, :], n)
    ip = win[rows, np.argmax(p[rows[:, None], win], axis=1)]
    # parabolic refinement of the peak on the amplitude
    a_m, a_0, a_p = np.sqrt(p[rows, (ip - 1) % n]), np.sqrt(p[rows, ip]), np.sqrt(p[rows, (ip + 1) % n])
    den = a_m - 2 * a_0 + a_p
    delta = np.where(den < 0, 0.5 * (a_m - a_p) / np.where(den < 0, den, -1.0), 0.0)
    peak_amp = a_0 - 0.25 * (a_m - a_p) * delta
    centre = ip + delta
    half = p[rows, ip] / 2.0
    limit = n // 2

    def crossing(direction: int) -> np.ndarray:
        # first k in 1 … limit−1 with p[ip + direction·k] < half (limit when none)
        k_found = np.full(n_l, limit, dtype=np.int64)
        todo = rows
        for span in (min(_CROSSING_LOOKAHEAD, limit - 1), limit - 1):
            ks = np.arange(1, span + 1)
            seg = p[todo[:, None], np.mod(ip[todo, None] + direction * ks[None, :], n)]
            first, found = _first_true(seg < half[todo, None])
            k_found[todo[found]] = first[found] + 1
            todo = todo[~found]
            if todo.size == 0 or span >= limit - 1:
                break
        k = k_found
        out = np.full(n_l, float(limit))
        ok = k < limit
        p1 = p[rows, np.mod(ip + direction * k, n)]
        p0 = p[rows, np.mod(ip + direction * (k - 1), n)]
        with np.errstate(divide="ignore", invalid="ignore"):
            out[ok] = (k[ok] - 1) + (p0[ok] - half[ok]) / (p0[ok] - p1[ok])
        return out

    width = (crossing(+1) + crossing(-1)) * spacing
    lim_min = np.maximum(2, np.ceil(3.0 * null_s).astype(np.int64))
    k_stop = np.minimum(lim_min, limit)  # the loop of measure_cut runs k = 1 … k_stop − 1

    def first_min(direction: int) -> np.ndarray:
        ks = np.arange(0, int(k_stop.max()))
        seq = p[rows[:, None], np.mod(ip[:, None] + direction * ks[None, :], n)]
        rising = (seq[:, 1:] > seq[:, :-1]) & (ks[None, 1:] < k_stop[:, None])
        first, found = _first_true(rising)
        return np.where(found, first, k_stop)  # rising at k = first + 1 → main lobe ends at k − 1

    k_right, k_left = first_min(+1), first_min(-1)
    if extent is None:
        ext_arr = np.full(n_l, np.inf)
    else:
        ext_arr = np.broadcast_to(np.asarray(extent, dtype=float), (n_l,)).copy()
        ext_arr[~np.isfinite(ext_arr)] = np.inf
    finite_ext = np.isfinite(ext_arr)
    ext_s = np.where(finite_ext, np.minimum(ext_arr / spacing, n / 2.0), n / 2.0)
    # PSLR: highest sample outside the measured main lobe, within the extent
    q = p.copy()
    lobe = np.arange(-int(k_left.max()), int(k_right.max()) + 1)
    inside = (lobe[None, :] >= -k_left[:, None]) & (lobe[None, :] <= k_right[:, None])
    q[np.broadcast_to(rows[:, None], inside.shape)[inside], np.mod(ip[:, None] + lobe[None, :], n)[inside]] = 0.0
    cut_far = finite_ext & (ext_s < n / 2.0)
    if np.any(cut_far):
        d = np.mod(np.arange(n)[None, :] - ip[:, None], n)
        fe = np.floor(ext_s).astype(np.int64)
        far = (d >= fe[:, None] + 1) & (d <= n - fe[:, None] - 1) & cut_far[:, None]
        q = np.where(far, 0.0, q)
    q_max = q.max(axis=1)
    with np.errstate(divide="ignore"):
        pslr = np.where(q_max > 0, 10 * np.log10(q_max / np.where(q_max > 0, peak_amp ** 2, 1.0)), -np.inf)
    # ISLR: energy around the sub-pixel centre, main lobe ±ideal null, sidelobes to the extent
    fc = np.floor(centre).astype(np.int64)
    lim = np.ceil(ext_s + 1).astype(np.int64)
    m_off = np.arange(-int(np.ceil(null_s.max())) - 1, int(np.ceil(null_s.max())) + 2)
    km = fc[:, None] + m_off[None, :]
    in_main = (np.abs(km - centre[:, None]) <= null_s[:, None]) & (np.abs(m_off)[None, :] <= lim[:, None])
    e_main = np.where(in_main, p[rows[:, None], np.mod(km, n)], 0.0).sum(axis=1)
    e_side = p.sum(axis=1) - e_main
    if np.any(finite_ext):
        sel = np.nonzero(finite_ext)[0]
        big = int(lim[sel].max())
        off = np.arange(-big, big + 1)
        kk = fc[sel, None] + off[None, :]
        dist = np.abs(kk - centre[sel, None])
        side = (dist > null_s[sel, None]) & (dist <= ext_s[sel, None]) & (np.abs(off)[None, :] <= lim[sel, None])
        e_side[sel] = np.where(side, p[sel[:, None], np.mod(kk, n)], 0.0).sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        islr = np.where(e_side > 0, 10 * np.log10(e_side / e_main), -np.inf)
    return CutMeasurements(peak_position=origin + centre * spacing, peak_amplitude=peak_amp, width_3db=width,
                           pslr_db=pslr, islr_db=islr)
