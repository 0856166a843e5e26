"""Image formation entry point and the :class:`SarImage` result.

Phase convention (what makes PGA applicable): the focused image I(x, r) is multiplied by the
known deramp exp(−j 2π x² / (λ r)). In the Fresnel approximation a target at (x_k, r) then reads

    J(x) = a_k e^{−j2π x_k²/(λr)} Σ_n w_n e^{jψ(t_n)} exp(−j 2π (2 V t_n / (λ r)) (x − x_k)),

so the inverse DFT of J along azimuth is the (windowed) slow-time phase history, bin ν ↔
t = ν λ r / (2V) for every target: a slow-time phase error ψ(t) is one space-invariant azimuth
blur — the model of PGA (Wahl et al. 1994). The second factor exp(−j 4π (r − R_c)/λ) removes
the carrier that focusing leaves along range (a target reads a_k p(r − r_k) e^{j4π(r − r_k)/λ}),
so both image spectra are at baseband and band-limited interpolation applies along both axes;
a target's pixel then has phase arg a_k − 2π x_k²/(λ r_k) − 4π (r_k − R_c)/λ. The magnitude is
unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.fft as sfft

from ..errors import InputError
from ..units import range_to_phase
from .backprojection import backproject
from .geometry import SarGeometry
from .mocomp import MotionCompensator, motion_compensate
from .rda import RangeDopplerPlan, range_doppler


@dataclass
class SarImage:
    """Complex image ``data`` (n_az, n_r), azimuth along axis 0, with its axes in metres."""

    data: np.ndarray = field(repr=False)
    azimuth_m: np.ndarray = field(repr=False)
    slant_range_m: np.ndarray = field(repr=False)
    wavelength_m: float
    speed_m_s: float
    ref_range_m: float
    aperture_time_s: float
    method: str

    @property
    def range_offset_m(self) -> np.ndarray:
        return self.slant_range_m - self.ref_range_m

    @property
    def azimuth_spacing_m(self) -> float:
        return float(self.azimuth_m[1] - self.azimuth_m[0])

    def slow_time_of_bins_s(self, slant_range_m: float | None = None) -> np.ndarray:
        """Slow time t of each azimuth-frequency bin (centred order, as PGA's estimate), s."""
        r = self.ref_range_m if slant_range_m is None else slant_range_m
        nu = np.fft.fftshift(np.fft.fftfreq(self.data.shape[0], self.azimuth_spacing_m))
        return nu * self.wavelength_m * r / (2.0 * self.speed_m_s)

    def aperture_mask(self) -> np.ndarray:
        """Bins (centred order) inside the aperture |t| ≤ T/2."""
        return np.abs(self.slow_time_of_bins_s()) <= 0.5 * self.aperture_time_s

    def with_data(self, data: np.ndarray, method: str | None = None) -> "SarImage":
        return SarImage(data=data, azimuth_m=self.azimuth_m, slant_range_m=self.slant_range_m,
                        wavelength_m=self.wavelength_m, speed_m_s=self.speed_m_s,
                        ref_range_m=self.ref_range_m, aperture_time_s=self.aperture_time_s,
                        method=method or self.method)

    def magnitude_db(self) -> np.ndarray:
        mag = np.abs(self.data)
        return 20 * np.log10(np.maximum(mag, 1e-12 * max(mag.max(), 1e-300)))

    def summary(self) -> str:
        d = self.to_dict()
        return (f"{d['method']} image {d['shape'][0]} × {d['shape'][1]} (azimuth × range), peak "
                f"{d['peak']:.4g} at azimuth {d['peak_azimuth_m']:.3f} m, range offset {d['peak_range_m']:.3f} m")

    def to_dict(self) -> dict:
        """JSON-safe description (method, shape, spans in m, peak and its position); no pixels."""
        mag = np.abs(self.data)
        i, j = np.unravel_index(int(np.argmax(mag)), mag.shape)
        return {"method": self.method, "shape": list(self.data.shape),
                "azimuth_span_m": [float(self.azimuth_m[0]), float(self.azimuth_m[-1])],
                "range_span_m": [float(self.range_offset_m[0]), float(self.range_offset_m[-1])],
                "peak": float(mag[i, j]), "peak_azimuth_m": float(self.azimuth_m[i]),
                "peak_range_m": float(self.range_offset_m[j])}

    def to_frame(self) -> pd.DataFrame:
        """Magnitude in dB, index azimuth_m, columns range offset (m)."""
        return pd.DataFrame(self.magnitude_db(), index=pd.Index(self.azimuth_m, name="azimuth_m"),
                            columns=pd.Index(self.range_offset_m, name="range_m"))


def deramp_phase(wavelength_m: float, azimuth_m: np.ndarray, slant_range_m: np.ndarray,
                 ref_range_m: float) -> np.ndarray:
    """exp(−j 2π x²/(λ r) − j 4π (r − R_c)/λ) on the grid (n_az, n_r); see module docstring."""
    x, r = azimuth_m[:, None], slant_range_m[None, :]
    return np.exp(-2j * np.pi * x ** 2 / (wavelength_m * r) + 1j * range_to_phase(r - ref_range_m, wavelength_m))


def default_bp_grid(geom: SarGeometry, margin_cells: float = 8.0) -> tuple[np.ndarray, np.ndarray]:
    """Scene area plus a margin, on the range-Doppler image's sample positions."""
    xa = 0.5 * geom.scene_extent_m[0] + margin_cells * geom.azimuth_cell_m()
    yr = 0.5 * geom.scene_extent_m[1] + margin_cells * geom.range_cell_m
    az = geom.image_azimuth_axis_m
    rg = geom.range_axis_m
    return az[np.abs(az) <= xa].copy(), rg[np.abs(rg - geom.ref_range_m) <= yr].copy()


def form_image(geom: SarGeometry, data, measured_offset_m=None, method: str = "rda", *,
               grid: tuple[np.ndarray, np.ndarray] | None = None) -> SarImage:
    """Focus range-compressed ``data`` (n_pulses, n_range) using the MEASURED APC offsets.

    ``method``: "rda" (range-Doppler with first/second-order motion compensation, full grid) or
    "backprojection" (exact per-pixel ranges from the measured trajectory, on ``grid`` =
    (azimuth_m, slant_range_m) arrays or by default the scene plus 8 cells).
    """
    arr = np.asarray(data)
    if arr.shape != (geom.n_pulses, geom.n_range):
        raise InputError(f"data has shape {arr.shape}", field="data",
                         expected=f"({geom.n_pulses}, {geom.n_range}) range-compressed samples")
    if not np.all(np.isfinite(arr)):
        raise InputError("data holds NaN or infinite samples", field="data", expected="finite complex samples")
    meas = geom.check_offset(measured_offset_m, "measured_offset_m")
    arr = arr.astype(complex, copy=False)
    if method == "rda":
        img = range_doppler(geom, motion_compensate(geom, arr, meas))
        az, rg = geom.image_azimuth_axis_m, geom.range_axis_m.copy()
    elif method == "backprojection":
        az, rg = default_bp_grid(geom) if grid is None else (np.asarray(grid[0], float), np.asarray(grid[1], float))
        if az.ndim != 1 or rg.ndim != 1 or az.size < 2 or rg.size < 2:
            raise InputError("backprojection grid must be two 1-D arrays of ≥ 2 positions", field="grid")
        lo, hi = geom.range_axis_m[0], geom.range_axis_m[-1]
        if rg.min() < lo or rg.max() > hi:
            raise InputError("backprojection grid leaves the swath", field="grid",
                             expected=f"slant ranges within [{lo:.6g}, {hi:.6g}] m")
        img = backproject(geom, arr, meas, az, rg)
    else:
        raise InputError("unknown image formation method", field="method", value=method,
                         expected="'rda' or 'backprojection'")
    img = img * deramp_phase(geom.wavelength_m, az, rg, geom.ref_range_m)
    return SarImage(data=img, azimuth_m=az, slant_range_m=rg, wavelength_m=geom.wavelength_m,
                    speed_m_s=geom.speed_m_s, ref_range_m=geom.ref_range_m,
                    aperture_time_s=geom.aperture_time_s, method=method)


class RdaImageFormer:
    """``form_image(geom, data, measured, "rda")`` for one geometry and a stack of measured
    trajectories (B, n_pulses, 3): the same motion compensation, range-Doppler focusing and
    deramp, with every geometry-only factor computed once (:class:`~budget.sar.mocomp.MotionCompensator`,
    :class:`~budget.sar.rda.RangeDopplerPlan`, the deramp of the module docstring) and the
    transforms of the B images done together along the trailing axes.

    Data enter as range spectra (:meth:`range_spectrum`): echoes that every trajectory shares are
    transformed once. ``template`` is a :class:`SarImage` with zero data on the image grid
    (axes, aperture time) for what depends only on the grid.
    """

    def __init__(self, geom: SarGeometry):
        self.geom = geom
        self.mocomp = MotionCompensator(geom)
        self.rda = RangeDopplerPlan(geom)
        self.azimuth_m = geom.image_azimuth_axis_m
        self.slant_range_m = geom.range_axis_m.copy()
        self.deramp = deramp_phase(geom.wavelength_m, self.azimuth_m, self.slant_range_m, geom.ref_range_m)
        self.template = SarImage(data=np.zeros((self.azimuth_m.size, self.slant_range_m.size), dtype=complex),
                                 azimuth_m=self.azimuth_m, slant_range_m=self.slant_range_m,
                                 wavelength_m=geom.wavelength_m, speed_m_s=geom.speed_m_s,
                                 ref_range_m=geom.ref_range_m, aperture_time_s=geom.aperture_time_s, method="rda")

    def range_spectrum(self, data) -> np.ndarray:
        """DFT along range of range-compressed data (…, n_pulses, n_range), checked like :func:`form_image`."""
        arr = np.asarray(data)
        g = self.geom
        if arr.shape[-2:] != (g.n_pulses, g.n_range):
            raise InputError(f"data has shape {arr.shape}", field="data",
                             expected=f"(…, {g.n_pulses}, {g.n_range}) range-compressed samples")
        if not np.all(np.isfinite(arr)):
            raise InputError("data holds NaN or infinite samples", field="data", expected="finite complex samples")
        return sfft.fft(arr.astype(complex, copy=False), axis=-1)

    def form(self, range_spectrum: np.ndarray, measured_offset_m: np.ndarray) -> np.ndarray:
        """Image data (B, n_azimuth, n_range) of data with range spectrum ``range_spectrum``
        ((n_pulses, n_range) shared or (B, n_pulses, n_range)) focused with the B measured APC
        offsets ``measured_offset_m`` (B, n_pulses, 3), m."""
        return self.form_groups([range_spectrum], measured_offset_m)[0]

    def form_groups(self, range_spectra, measured_offset_m: np.ndarray) -> np.ndarray:
        """:meth:`form` of G data sets along the same B trajectories: (G, B, n_azimuth, n_range),
        group g from ``range_spectra[g]``; the motion compensation's phases are formed once for
        the G sets (:meth:`~budget.sar.mocomp.MotionCompensator.apply_groups`), the transforms run
        on the G·B stack. Every number is that of :meth:`form` on each set alone."""
        off = np.asarray(measured_offset_m, dtype=float)
        if off.ndim != 3 or off.shape[1:] != (self.geom.n_pulses, 3) or not np.all(np.isfinite(off)):
            raise InputError(f"APC offsets have shape {off.shape}", field="measured_offset_m",
                             expected=f"finite (B, {self.geom.n_pulses}, 3) metres")
        # the azimuth window is applied in the motion compensation's pass over the data
        data = self.mocomp.apply_groups(range_spectra, off, self.rda.window[:, 0])
        img = self.rda(data.reshape((-1,) + data.shape[2:]), windowed=True)
        img *= self.deramp
        return img.reshape(data.shape[:2] + img.shape[1:])
