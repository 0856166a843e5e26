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
  image, equivalent to an infinite extent; pass a number of metres to restrict it). Each sample
  stands for one sample interval centred on it (midpoint rule), so a sample that a boundary
  crosses counts with the fraction of its interval inside,

      f_main(d) = clip(null_s − d + ½, 0, 1),   d = |k − centre| (samples),          (1)

  and likewise at the extent. (Counting such a sample whole or not at all made the ISLR of a
  defocused response jump by up to 0.5 dB as the peak moved by a sixteenth of a cell: −0.37 dB
  with the boundary on a sample, +0.1 dB half-way, for a Taylor response with π/2 of quadratic
  phase at the aperture edge.)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from ..errors import InputError
from .irf_kernels import measure_rows, parabolic_peak


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
    delta, peak_amp = parabolic_peak(float(p[(ip - 1) % n]), float(p[ip]), float(p[(ip + 1) % n]))
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
    f_main = np.clip(null_s - dist + 0.5, 0.0, 1.0)  # eq. (1)
    e_main = (pk * f_main).sum()
    if extent is None:
        e_side = p.sum() - e_main
    else:
        e_side = (pk * (np.clip(ext_s - dist + 0.5, 0.0, 1.0) - f_main).clip(0.0)).sum()
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


def measure_cuts(cuts: np.ndarray, spacing, origin, *, expected_index, search_half: int, null,
                 extent=None) -> CutMeasurements:
    """:func:`measure_cut` of every row of ``cuts`` (L, n) at once (same definitions, module
    docstring): ``spacing``, ``origin``, ``expected_index`` and ``null`` are scalars or one value
    per cut; ``extent`` None (whole line) or scalars/arrays (NaN or inf: whole line). The loop over
    the cuts is compiled (:func:`budget.sar.irf_kernels.measure_rows`)."""
    cuts = np.asarray(cuts)
    if cuts.ndim != 2:
        raise InputError(f"cuts have shape {cuts.shape}", field="cuts", expected="a 2-D stack (L, n) of cuts")
    n_l = cuts.shape[0]

    def per_cut(x) -> np.ndarray:
        return np.ascontiguousarray(np.broadcast_to(np.asarray(x, dtype=float), (n_l,)))

    ext = np.full(n_l, np.inf) if extent is None else per_cut(extent).copy()
    ext[~np.isfinite(ext)] = np.inf
    pos, amp, width, pslr, islr = measure_rows(
        np.ascontiguousarray(cuts, dtype=complex), per_cut(spacing), per_cut(origin), per_cut(expected_index),
        int(search_half), per_cut(null), ext)
    return CutMeasurements(peak_position=pos, peak_amplitude=amp, width_3db=width, pslr_db=pslr, islr_db=islr)
