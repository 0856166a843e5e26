"""Image-quality metrics of each point target, in azimuth and range.

For every target of the scene, :func:`measure_targets` finds its peak near the expected image
position, takes the azimuth cut through the (sub-pixel) range of the peak and the range cut
through its azimuth — band-limited interpolation across lines, 16× upsampling along them — and
measures with the definitions of :func:`budget.sar.irf.measure_cut` (all cuts of a stage at once,
:func:`budget.sar.irf.measure_cuts`; :class:`TargetMeter` measures stacks of images):

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
from .irf import CutMeasurements, measure_cuts, upsample_periodic
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

    def summary(self) -> str:
        d = self.to_dict()
        return (f"{d['n_targets']} targets ({d['window_azimuth']} × {d['window_range']} window), worst: "
                f"broadening {d['worst_azimuth_broadening']:.3f} az / {d['worst_range_broadening']:.3f} rg, "
                f"PSLR {max(d['worst_azimuth_pslr_db'], d['worst_range_pslr_db']):.1f} dB, ISLR "
                f"{max(d['worst_azimuth_islr_db'], d['worst_range_islr_db']):.1f} dB, peak loss "
                f"{d['worst_peak_loss_db']:.2f} dB")

    def to_dict(self) -> dict:
        """JSON-safe: the windows, the ISLR extent, the worst value of each metric and every target."""
        f = self.to_frame()
        out = {"n_targets": len(self.targets), "window_azimuth": self.window_azimuth,
               "window_range": self.window_range,
               "islr_extent": "whole line" if self.islr_extent_cells is None else f"±{self.islr_extent_cells} cells"}
        for col in ("azimuth_broadening", "range_broadening", "azimuth_pslr_db", "range_pslr_db",
                    "azimuth_islr_db", "range_islr_db", "peak_loss_db"):
            out[f"worst_{col}"] = float(f[col].max())
        out["worst_abs_azimuth_peak_shift_m"] = float(f["azimuth_peak_shift_m"].abs().max())
        out["worst_abs_range_peak_shift_m"] = float(f["range_peak_shift_m"].abs().max())
        out["targets"] = [{k: float(v) if isinstance(v, (float, np.floating)) else v for k, v in t.as_row().items()}
                          for t in self.targets]
        return out


def _frac_phasor(n: int, pos) -> np.ndarray:
    """Weights v with line(pos) = (spectrum · v) / n for a band-limited periodic line of n samples
    (``pos`` scalar or array: one row of weights per position, last axis n)."""
    m = np.fft.fftfreq(n) * n
    return np.exp(2j * np.pi * m * np.asarray(pos, dtype=float)[..., None] / n) / n


def _frac_kernel(n: int, pos) -> np.ndarray:
    """Weights u with line(pos) = samples · u: u = DFT(v) of :func:`_frac_phasor`, since
    Σ_m (Σ_i x_i e^{−j2πmi/n}) v_m = Σ_i x_i DFT(v)_i — a cut through the image itself, no
    image transform needed."""
    return sfft.fft(_frac_phasor(n, pos), axis=-1)


class _Cuts:
    """Azimuth and range cuts through a peak, band-limited across lines, upsampled along them."""

    def __init__(self, image: SarImage):
        data = np.asarray(image.data)
        self.n_a, self.n_r = data.shape
        self.dx = image.azimuth_spacing_m
        self.dr = float(image.slant_range_m[1] - image.slant_range_m[0])
        self.az0, self.rg0 = float(image.azimuth_m[0]), float(image.slant_range_m[0])
        self.data = data

    def azimuth_line(self, range_m: float) -> np.ndarray:
        """Upsampled azimuth cut at slant range ``range_m``; sample i at az0 + i·dx/16."""
        return upsample_periodic(self.data @ _frac_kernel(self.n_r, (range_m - self.rg0) / self.dr), _UP)

    def range_line(self, azimuth_m: float) -> np.ndarray:
        """Upsampled range cut at ``azimuth_m``; sample j at rg0 + j·dr/16."""
        return upsample_periodic(_frac_kernel(self.n_a, (azimuth_m - self.az0) / self.dx) @ self.data, _UP)


@dataclass(frozen=True)
class TargetMetricArrays:
    """Per-target metrics of a stack of images: every field (B, K) for B images and K targets
    (names as the columns of :meth:`TargetMetricsTable.to_frame`; lengths m, levels dB)."""

    values: dict[str, np.ndarray]
    meter: "TargetMeter"

    def __getitem__(self, name: str) -> np.ndarray:
        return self.values[name]

    def worst(self) -> dict[str, np.ndarray]:
        """Worst value over the targets (and over azimuth/range for PSLR and ISLR), per image (B,)."""
        v = self.values
        return {"azimuth_broadening": v["azimuth_broadening"].max(axis=1),
                "range_broadening": v["range_broadening"].max(axis=1),
                "pslr_db": np.maximum(v["azimuth_pslr_db"], v["range_pslr_db"]).max(axis=1),
                "islr_db": np.maximum(v["azimuth_islr_db"], v["range_islr_db"]).max(axis=1),
                "peak_loss_db": v["peak_loss_db"].max(axis=1)}

    def summary(self, b: int = 0) -> str:
        """:meth:`TargetMetricsTable.summary` of image ``b``."""
        return self.table(b).summary()

    def to_frame(self, b: int = 0) -> pd.DataFrame:
        """:meth:`TargetMetricsTable.to_frame` of image ``b``."""
        return self.table(b).to_frame()

    def to_dict(self) -> dict:
        """JSON-ready: every field as nested lists [image][target]."""
        return {k: np.asarray(v).tolist() for k, v in self.values.items()}

    def table(self, b: int = 0) -> TargetMetricsTable:
        """The metrics of image ``b`` as a :class:`TargetMetricsTable`."""
        m, v = self.meter, self.values
        out = []
        for k in range(m.n_targets):
            axes = {}
            for name in ("azimuth", "range"):
                axes[name] = AxisMetrics(**{f: float(v[f"{name}_{f}"][b, k]) for f in AxisMetrics.__dataclass_fields__})
            out.append(TargetMetrics(index=k, azimuth_m=float(m.x_m[k]), range_m=float(m.r_off_m[k]),
                                     amplitude=float(m.amplitude[k]), peak_amplitude=float(v["peak_amplitude"][b, k]),
                                     peak_loss_db=float(v["peak_loss_db"][b, k]), **axes))
        return TargetMetricsTable(targets=out, window_azimuth=m.window_azimuth.label,
                                  window_range=m.window_range.label, islr_extent_cells=m.islr_extent_cells)


class TargetMeter:
    """:func:`measure_targets` for one geometry, scene and image grid, applied to stacks of images.

    Everything that depends only on the scene and the grid is computed once (target positions in
    samples, search boxes, ideal IRFs, nulls, extents); :meth:`measure` then takes every cut of
    every target and image of a stack together: the pixel rows themselves (first stage) or one
    matrix product per stage give the cuts, one upsampling transform the 16× lines,
    :func:`~budget.sar.irf.measure_cuts` the measurements.
    The three stages of each target are those of the module docstring: range cut at the pixel
    row → azimuth cut at the range peak → range cut at the azimuth peak.
    """

    def __init__(self, geom: SarGeometry, scene: Scene, azimuth_m: np.ndarray, slant_range_m: np.ndarray,
                 window: Window | str | None = None, *, search_cells: float = 6.0,
                 islr_extent_cells: float | None = None, azimuth_search_cells: float | None = None):
        if not isinstance(scene, Scene) or not scene.targets:
            raise InputError("no point targets to measure", field="targets", expected="a scene with ≥ 1 target")
        if islr_extent_cells is not None and not islr_extent_cells > 0:
            raise InputError("ISLR extent must be positive", field="islr_extent_cells", value=islr_extent_cells)
        az, rg = np.asarray(azimuth_m, dtype=float), np.asarray(slant_range_m, dtype=float)
        self.n_a, self.n_r = az.size, rg.size
        self.dx = float(az[1] - az[0])
        self.dr = float(rg[1] - rg[0])
        self.az0, self.rg0 = float(az[0]), float(rg[0])
        self.window_azimuth = geom.window_azimuth if window is None else Window.parse(window)
        self.window_range = geom.window_range if window is None else Window.parse(window)
        self.ideal_az = ideal_irf(self.window_azimuth, islr_extent_cells)
        self.ideal_rg = ideal_irf(self.window_range, islr_extent_cells)
        self.islr_extent_cells = islr_extent_cells
        x, r_off, a = scene.target_arrays()
        self.x_m, self.r_off_m, self.amplitude = x, r_off, np.abs(a)
        self.n_targets = x.size
        self.r_m = geom.ref_range_m + r_off
        self.cell_a = np.array([geom.azimuth_cell_m(rk) for rk in self.r_m])
        self.cell_r = geom.range_cell_m
        centres, half = [], []
        for k, (xk, rk_off, rk, cell_a) in enumerate(zip(x, r_off, self.r_m, self.cell_a)):
            ie, je = (xk - self.az0) / self.dx, (rk - self.rg0) / self.dr
            if not (0 <= ie <= self.n_a - 1 and 0 <= je <= self.n_r - 1):
                raise InputError(f"target {k} at azimuth {xk:g} m, range {rk_off:g} m is outside the image",
                                 row=k, field="targets", expected="targets inside the image grid")
            cells = search_cells if azimuth_search_cells is None else azimuth_search_cells
            ha = max(1, int(min(self.n_a, np.ceil(cells * cell_a / self.dx))))
            hr = max(1, int(np.ceil(search_cells * self.cell_r / self.dr)))
            centres.append((int(round(ie)), int(round(je))))
            half.append([ha, hr])
        # a box never reaches halfway to another target that lies within its range extent, so
        # that each box holds its own target's main lobe, however wide the azimuth search
        for k, (ik, jk) in enumerate(centres):
            for m, (im, jm) in enumerate(centres):
                if m != k and abs(jk - jm) <= half[k][1]:
                    half[k][0] = max(1, min(half[k][0], (abs(ik - im) - 1) // 2))
        self.boxes = [(max(0, i - ha), min(self.n_a, i + ha + 1), max(0, j - hr), min(self.n_r, j + hr + 1))
                      for (i, j), (ha, hr) in zip(centres, half)]
        self.null_az_m = self.ideal_az.first_null_cells * self.cell_a
        self.null_rg_m = self.ideal_rg.first_null_cells * self.cell_r
        self.ext_az_m = None if islr_extent_cells is None else islr_extent_cells * self.cell_a
        self.ext_rg_m = None if islr_extent_cells is None else islr_extent_cells * self.cell_r

    def _range_cuts(self, data: np.ndarray, azimuth_m: np.ndarray | None, j0: np.ndarray,
                    rows: np.ndarray | None = None) -> CutMeasurements:
        """Range cuts of every image (B) and target (K) at ``azimuth_m`` (B, K), measured; with
        ``rows`` (B, K) instead, the cuts through those pixel rows (band-limited interpolation
        at an integer position gives the row itself)."""
        if rows is None:
            lines = np.matmul(_frac_kernel(self.n_a, (azimuth_m - self.az0) / self.dx), data)  # (B, K, n_r)
        else:
            lines = data[np.arange(data.shape[0])[:, None], rows]
        up = upsample_periodic(lines, _UP).reshape(-1, self.n_r * _UP)
        b = lines.shape[0]
        ext = None if self.ext_rg_m is None else self.ext_rg_m
        return measure_cuts(up, self.dr / _UP, self.rg0, expected_index=(j0 * _UP).ravel(), search_half=2 * _UP,
                            null=np.broadcast_to(self.null_rg_m, (b, self.n_targets)).ravel(), extent=ext)

    def _azimuth_cuts(self, data: np.ndarray, range_m: np.ndarray, i0: np.ndarray) -> CutMeasurements:
        """Azimuth cuts of every image (B) and target (K) at slant range ``range_m`` (B, K), measured."""
        kern = _frac_kernel(self.n_r, (range_m - self.rg0) / self.dr)  # (B, K, n_r)
        lines = np.matmul(kern, np.swapaxes(data, -1, -2))  # (B, K, n_a)
        up = upsample_periodic(lines, _UP).reshape(-1, self.n_a * _UP)
        b = range_m.shape[0]
        ext = None if self.ext_az_m is None else np.broadcast_to(self.ext_az_m, (b, self.n_targets)).ravel()
        return measure_cuts(up, self.dx / _UP, self.az0, expected_index=(i0 * _UP).ravel(), search_half=2 * _UP,
                            null=np.broadcast_to(self.null_az_m, (b, self.n_targets)).ravel(), extent=ext)

    def measure(self, data) -> TargetMetricArrays:
        """Metrics of every target in every image of ``data`` (B, n_a, n_r) or (n_a, n_r)."""
        data = np.asarray(data)
        if data.ndim == 2:
            data = data[None]
        if data.ndim != 3 or data.shape[1:] != (self.n_a, self.n_r) or min(data.shape[1:]) < 8:
            raise InputError(f"image has shape {data.shape[-2:]}", field="image",
                             expected=f"2-D, ≥ 8 × 8 pixels, on the grid ({self.n_a}, {self.n_r})")
        if not np.all(np.isfinite(data)):
            raise InputError("image holds NaN or infinite pixels", field="image", expected="finite values")
        b, k_n = data.shape[0], self.n_targets
        i0 = np.empty((b, k_n), dtype=np.int64)
        j0 = np.empty((b, k_n), dtype=np.int64)
        for k, (i_lo, i_hi, j_lo, j_hi) in enumerate(self.boxes):
            box = np.abs(data[:, i_lo:i_hi, j_lo:j_hi]).reshape(b, -1)
            bi, bj = np.unravel_index(np.argmax(box, axis=1), (i_hi - i_lo, j_hi - j_lo))
            i0[:, k], j0[:, k] = i_lo + bi, j_lo + bj
        # range cut at the pixel row → azimuth cut at the range peak → range cut at the azimuth peak
        rc = self._range_cuts(data, None, j0, rows=i0)
        ac = self._azimuth_cuts(data, rc.peak_position.reshape(b, k_n), i0)
        rc = self._range_cuts(data, ac.peak_position.reshape(b, k_n), j0)
        shape = (b, k_n)
        peak = np.maximum(ac.peak_amplitude, rc.peak_amplitude).reshape(shape)
        v = {"peak_amplitude": peak, "peak_loss_db": 20 * np.log10(self.amplitude[None, :] / peak)}
        for name, meas, true_pos, cell, ideal in (("azimuth", ac, self.x_m, self.cell_a, self.ideal_az),
                                                  ("range", rc, self.r_m, np.full(k_n, self.cell_r), self.ideal_rg)):
            width = meas.width_3db.reshape(shape)
            ideal_w = ideal.width_3db_cells * cell
            v[f"{name}_width_3db_m"] = width
            v[f"{name}_ideal_width_3db_m"] = np.broadcast_to(ideal_w, shape)
            v[f"{name}_broadening"] = width / ideal_w[None, :] - 1.0
            v[f"{name}_pslr_db"] = meas.pslr_db.reshape(shape)
            v[f"{name}_ideal_pslr_db"] = np.full(shape, ideal.pslr_db)
            v[f"{name}_islr_db"] = meas.islr_db.reshape(shape)
            v[f"{name}_ideal_islr_db"] = np.full(shape, ideal.islr_db)
            v[f"{name}_peak_shift_m"] = meas.peak_position.reshape(shape) - true_pos[None, :]
            v[f"{name}_cell_m"] = np.broadcast_to(cell, shape)
        return TargetMetricArrays(values=v, meter=self)


def measure_targets(image: SarImage, geom: SarGeometry, scene: Scene, window: Window | str | None = None, *,
                    search_cells: float = 6.0, islr_extent_cells: float | None = None,
                    azimuth_search_cells: float | None = None) -> TargetMetricsTable:
    """Metrics of every target of ``scene`` in ``image`` (see module docstring).

    ``window``: the window the image was formed with (default: the geometry's); ``search_cells``:
    half-size of the peak search box around the true position, in resolution cells;
    ``azimuth_search_cells`` widens it in azimuth only (default: ``search_cells``; ``math.inf``:
    the whole image) — a linear phase error shifts a target along azimuth without defocusing it.
    A box never reaches halfway to another target within its range extent, so a wide azimuth
    search still finds the right target.
    """
    if not isinstance(scene, Scene) or not scene.targets:
        raise InputError("no point targets to measure", field="targets", expected="a scene with ≥ 1 target")
    data = np.asarray(image.data)
    if data.ndim != 2 or min(data.shape) < 8:
        raise InputError(f"image has shape {data.shape}", field="image", expected="2-D, ≥ 8 × 8 pixels")
    if not np.all(np.isfinite(data)):
        raise InputError("image holds NaN or infinite pixels", field="image", expected="finite values")
    meter = TargetMeter(geom, scene, image.azimuth_m, image.slant_range_m, window, search_cells=search_cells,
                        islr_extent_cells=islr_extent_cells, azimuth_search_cells=azimuth_search_cells)
    return meter.measure(data).table(0)


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
