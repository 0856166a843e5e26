"""Image-quality metrics of each point target, in azimuth and range.

For every target of the scene, :func:`measure_targets` finds its peak near the expected image
position, takes the azimuth cut through the (sub-pixel) range of the peak and the range cut
through its azimuth — band-limited interpolation across lines, 16× upsampling along them — and
measures with :func:`budget.sar.irf.measure_cut`:

* ``width_3db_m`` and ``broadening`` = width / ideal − 1, the ideal being the window's own
  (window-aware): ``ideal_irf(window).width_3db_cells`` × one cell (azimuth λr/(2VT), range
  c/(2B));
* ``pslr_db``, ``islr_db`` (main lobe ± the ideal first null, sidelobes over the whole line
  unless ``islr_extent_cells`` is given), with the ideal values beside them;
* ``peak_shift_m`` (measured − true position) and ``peak_loss_db`` = 20 log10(|a| / peak)
  (positive: loss), |a| being the target amplitude (a unit target peaks at 1 in an ideal image).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd
import scipy.fft as sfft

from ..errors import InputError
from .geometry import SarGeometry
from .image import SarImage
from .irf import CutMeasurement, measure_cut, upsample_periodic
from .scene import Scene
from .windows import Window, ideal_irf

_UP = 16


@dataclass(frozen=True)
class AxisMetrics:
    """Metrics of one cut (azimuth or range) of one target."""

    width_3db_m: float
    ideal_width_3db_m: float
    broadening: float
    pslr_db: float
    ideal_pslr_db: float
    islr_db: float
    ideal_islr_db: float
    peak_shift_m: float
    cell_m: float


@dataclass(frozen=True)
class TargetMetrics:
    """Metrics of one target: position, peak, and the two cuts."""

    index: int
    azimuth_m: float
    range_m: float
    amplitude: float
    peak_amplitude: float
    peak_loss_db: float
    azimuth: AxisMetrics
    range: AxisMetrics

    def as_row(self) -> dict:
        row = {"target": self.index, "azimuth_m": self.azimuth_m, "range_m": self.range_m,
               "amplitude": self.amplitude, "peak_amplitude": self.peak_amplitude,
               "peak_loss_db": self.peak_loss_db}
        for name in ("azimuth", "range"):
            for k, v in asdict(getattr(self, name)).items():
                row[f"{name}_{k}"] = v
        return row


@dataclass(frozen=True)
class TargetMetricsTable:
    """Per-target metrics with ``summary()`` and ``to_frame()``."""

    targets: list[TargetMetrics]
    window_azimuth: str
    window_range: str
    islr_extent_cells: float | None

    def __iter__(self):
        return iter(self.targets)

    def __len__(self) -> int:
        return len(self.targets)

    def __getitem__(self, i: int) -> TargetMetrics:
        return self.targets[i]

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame([t.as_row() for t in self.targets]).set_index("target")

    def summary(self) -> dict:
        f = self.to_frame()
        out = {"n_targets": len(self.targets), "window_azimuth": self.window_azimuth,
               "window_range": self.window_range,
               "islr_extent": "whole line" if self.islr_extent_cells is None else f"±{self.islr_extent_cells} cells"}
        for col in ("azimuth_broadening", "range_broadening", "azimuth_pslr_db", "range_pslr_db",
                    "azimuth_islr_db", "range_islr_db", "peak_loss_db"):
            out[f"worst_{col}"] = float(f[col].max())
        out["worst_abs_azimuth_peak_shift_m"] = float(f["azimuth_peak_shift_m"].abs().max())
        out["worst_abs_range_peak_shift_m"] = float(f["range_peak_shift_m"].abs().max())
        return out


def _frac_phasor(n: int, pos: float) -> np.ndarray:
    """Weights v with line(pos) = (spectrum · v) / n for a band-limited periodic line of n samples."""
    m = np.fft.fftfreq(n) * n
    return np.exp(2j * np.pi * m * pos / n) / n


def _axis(meas: CutMeasurement, true_pos: float, cell: float, ideal) -> AxisMetrics:
    ideal_w = ideal.width_3db_cells * cell
    return AxisMetrics(width_3db_m=meas.width_3db, ideal_width_3db_m=ideal_w,
                       broadening=meas.width_3db / ideal_w - 1.0, pslr_db=meas.pslr_db,
                       ideal_pslr_db=ideal.pslr_db, islr_db=meas.islr_db, ideal_islr_db=ideal.islr_db,
                       peak_shift_m=meas.peak_position - true_pos, cell_m=cell)


class _Cuts:
    """Azimuth and range cuts through a peak, band-limited across lines, upsampled along them."""

    def __init__(self, image: SarImage):
        data = np.asarray(image.data)
        self.n_a, self.n_r = data.shape
        self.dx = image.azimuth_spacing_m
        self.dr = float(image.slant_range_m[1] - image.slant_range_m[0])
        self.az0, self.rg0 = float(image.azimuth_m[0]), float(image.slant_range_m[0])
        self.spec_r = sfft.fft(data, axis=1)  # azimuth cuts at a fractional range
        self.spec_a = sfft.fft(data, axis=0)  # range cuts at a fractional azimuth

    def azimuth_line(self, range_m: float) -> np.ndarray:
        """Upsampled azimuth cut at slant range ``range_m``; sample i at az0 + i·dx/16."""
        return upsample_periodic(self.spec_r @ _frac_phasor(self.n_r, (range_m - self.rg0) / self.dr), _UP)

    def range_line(self, azimuth_m: float) -> np.ndarray:
        """Upsampled range cut at ``azimuth_m``; sample j at rg0 + j·dr/16."""
        return upsample_periodic(self.spec_a.T @ _frac_phasor(self.n_a, (azimuth_m - self.az0) / self.dx), _UP)


def measure_targets(image: SarImage, geom: SarGeometry, scene: Scene, window: Window | str | None = None, *,
                    search_cells: float = 6.0, islr_extent_cells: float | None = None,
                    azimuth_search_cells: float | None = None) -> TargetMetricsTable:
    """Metrics of every target of ``scene`` in ``image`` (see module docstring).

    ``window``: the window the image was formed with (default: the geometry's); ``search_cells``:
    half-size of the peak search box around the true position, in resolution cells;
    ``azimuth_search_cells`` widens it in azimuth only (default: ``search_cells``) — a linear phase
    error shifts a target along azimuth without defocusing it, and the default scene puts one
    target per range line, so a wide azimuth search still finds the right target.
    """
    if not isinstance(scene, Scene) or not scene.targets:
        raise InputError("no point targets to measure", field="targets", expected="a scene with ≥ 1 target")
    data = np.asarray(image.data)
    if data.ndim != 2 or min(data.shape) < 8:
        raise InputError(f"image has shape {data.shape}", field="image", expected="2-D, ≥ 8 × 8 pixels")
    if not np.all(np.isfinite(data)):
        raise InputError("image holds NaN or infinite pixels", field="image", expected="finite values")
    if islr_extent_cells is not None and not islr_extent_cells > 0:
        raise InputError("ISLR extent must be positive", field="islr_extent_cells", value=islr_extent_cells)
    w_az = geom.window_azimuth if window is None else Window.parse(window)
    w_rg = geom.window_range if window is None else Window.parse(window)
    ideal_az, ideal_rg = ideal_irf(w_az, islr_extent_cells), ideal_irf(w_rg, islr_extent_cells)
    cuts = _Cuts(image)
    n_a, n_r, dx, dr, az0, rg0 = cuts.n_a, cuts.n_r, cuts.dx, cuts.dr, cuts.az0, cuts.rg0
    cell_r = geom.range_cell_m
    x, r_off, a = scene.target_arrays()
    out = []
    for k, (xk, rk_off, ak) in enumerate(zip(x, r_off, a)):
        rk = geom.ref_range_m + rk_off
        cell_a = geom.azimuth_cell_m(rk)
        ie, je = (xk - az0) / dx, (rk - rg0) / dr
        if not (0 <= ie <= n_a - 1 and 0 <= je <= n_r - 1):
            raise InputError(f"target {k} at azimuth {xk:g} m, range {rk_off:g} m is outside the image",
                             row=k, field="targets", expected="targets inside the image grid")
        ha = max(1, int(np.ceil((azimuth_search_cells or search_cells) * cell_a / dx)))
        hr = max(1, int(np.ceil(search_cells * cell_r / dr)))
        i_lo, i_hi = max(0, int(round(ie)) - ha), min(n_a, int(round(ie)) + ha + 1)
        j_lo, j_hi = max(0, int(round(je)) - hr), min(n_r, int(round(je)) + hr + 1)
        box = np.abs(data[i_lo:i_hi, j_lo:j_hi])
        bi, bj = np.unravel_index(int(np.argmax(box)), box.shape)
        i0, j0 = i_lo + bi, j_lo + bj
        ext_a = None if islr_extent_cells is None else islr_extent_cells * cell_a
        ext_r = None if islr_extent_cells is None else islr_extent_cells * cell_r

        az_pos = az0 + i0 * dx
        # range cut at the pixel row → azimuth cut at the range peak → range cut at the azimuth peak
        rc = measure_cut(cuts.range_line(az_pos), dr / _UP, rg0, expected_index=j0 * _UP,
                         search_half=2 * _UP, null=ideal_rg.first_null_cells * cell_r, extent=ext_r)
        ac = measure_cut(cuts.azimuth_line(rc.peak_position), dx / _UP, az0, expected_index=i0 * _UP,
                         search_half=2 * _UP, null=ideal_az.first_null_cells * cell_a, extent=ext_a)
        rc = measure_cut(cuts.range_line(ac.peak_position), dr / _UP, rg0, expected_index=j0 * _UP,
                         search_half=2 * _UP, null=ideal_rg.first_null_cells * cell_r, extent=ext_r)
        peak = max(ac.peak_amplitude, rc.peak_amplitude)
        out.append(TargetMetrics(
            index=k, azimuth_m=float(xk), range_m=float(rk_off), amplitude=float(abs(ak)),
            peak_amplitude=float(peak), peak_loss_db=float(20 * np.log10(abs(ak) / peak)),
            azimuth=_axis(ac, xk, cell_a, ideal_az), range=_axis(rc, rk, cell_r, ideal_rg)))
    return TargetMetricsTable(targets=out, window_azimuth=w_az.label, window_range=w_rg.label,
                              islr_extent_cells=islr_extent_cells)


def irf_cuts(image: SarImage, geom: SarGeometry, scene: Scene, index: int = 0) -> dict[str, np.ndarray]:
    """Upsampled azimuth and range cuts (dB re. the target amplitude) through target ``index``.

    Returns offsets from the measured peak (m) and levels (dB), for plotting.
    """
    if not 0 <= index < len(scene.targets):
        raise InputError("no such target", field="index", value=index,
                         expected=f"0 … {len(scene.targets) - 1}")
    one = Scene(targets=[scene.targets[index]])
    m = measure_targets(image, geom, one)[0]
    cuts = _Cuts(image)
    x_pk = m.azimuth_m + m.azimuth.peak_shift_m
    r_pk = geom.ref_range_m + m.range_m + m.range.peak_shift_m
    az = np.abs(cuts.azimuth_line(r_pk))
    rg = np.abs(cuts.range_line(x_pk))
    ref = max(m.amplitude, 1e-300)
    az_x = cuts.az0 + np.arange(az.size) * cuts.dx / _UP - x_pk
    rg_x = cuts.rg0 + np.arange(rg.size) * cuts.dr / _UP - r_pk
    floor = 1e-12 * ref
    return {"azimuth_offset_m": az_x, "azimuth_db": 20 * np.log10(np.maximum(az, floor) / ref),
            "range_offset_m": rg_x, "range_db": 20 * np.log10(np.maximum(rg, floor) / ref),
            "azimuth_cell_m": np.array(m.azimuth.cell_m), "range_cell_m": np.array(m.range.cell_m)}
