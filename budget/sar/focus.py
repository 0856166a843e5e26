"""Ground-plane image formation from a recorded phase history, by backprojection.

For pixel p on the ground plane z = 0 and a phase history in the convention of
:mod:`budget.sar.phase_history` (eq. 1), the image is the matched filter

    I(p) = Σ_n w_n Σ_k v_k S(n, f_k) exp(+j 4π f_k ΔR_n(p) / c),    ΔR_n(p) = |A_n − p| − R0_n,   (2)

(w_n, v_k the azimuth and range windows; Soumekh 1999, "Synthetic Aperture Radar Signal
Processing", §4.5; Jakowatz et al. 1996, "Spotlight-Mode SAR", §3.7). The sum over k is done once
per pulse by an inverse FFT, zero-padded ``upsample``× so the profile can be read by linear
interpolation at ΔR_n(p): with f_k = f_r + (k − K/2) Δf,

    I(p) = Σ_n w_n exp(j 4π f_r ΔR_n(p) / c) · q_n(ΔR_n(p)),
    q_n(r) = Σ_k v_k S(n, f_k) e^{j2π(k−K/2)Δf·2r/c},

with f_r the reference frequency; q_n is at baseband, so linear interpolation of the 8×
oversampled profile loses < 2 % amplitude. A unit scatterer peaks at 1. ΔR is computed as
N / (R0 + √(R0² + N)), N = |A − p|² − R0² separable on the grid, which keeps ~10 µm precision at
10 km in float32 (see :func:`_backproject_rows`).

The grid: û is the ground projection of the aperture-centre antenna direction A_c (ground range,
positive towards the radar), v̂ = ±ẑ × û the cross-range axis (sign chosen so the azimuth frequency
of the pulses increases with pulse number); pixels p = u û + v v̂, the array is (n_v, n_u) with
azimuth along axis 0 as :func:`budget.sar.pga.pga` expects.

Deramp (what makes PGA applicable): the image is multiplied by exp(−j k_r (|A_c − p| − |A_c|)),
k_r = 4π f_r / c: the aperture-centre pulse's spherical phase. Near a scatterer, pulse n then reads
as the plane wave exp(−j k_r (Â_n − Â_c)·p) everywhere in the scene, so along azimuth it sits at the
spatial frequency (the inverse DFT along axis 0, Σ_v I(v) e^{+jωv}, peaks there; rad/m)

    ω_n = k_r (Â_n − Â_c) · v̂,                                                                   (3)

the same for every scatterer (without the deramp a scatterer y metres off-centre sees the aperture
turned by ≈ y/R and its spectrum moves by ≈ k_r y / R, 30 bins at 50 m for the Gotcha geometry).
A per-pulse phase error ψ_n therefore appears on the image's azimuth-frequency bin ω_n: PGA's
estimate on bins maps to pulses by interpolation at ω_n. Approximations: (3) is taken at f_r (over
the band the bin of pulse n moves by ± (B / 2f_r) ω_n, ±3 % of the aperture at its edges, which
smooths the estimate), and the deramp uses the aperture-centre pulse only.

Sharpness: entropy H = −Σ p ln p of the normalised intensity p = |I|² / Σ|I|² (lower is sharper;
Fienup & Miller 2003, JOSA A 20(4), eq. 4) and contrast std(|I|²) / mean(|I|²)
(:mod:`budget.sar.sharpness`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from pydantic import BaseModel, ConfigDict, Field

from ..errors import InputError, from_validation_error
from ..units import two_way_wavenumber_at_frequency_rad_m as _wavenumber
from .phase_history import C_M_S, PhaseHistory
from .geometry import MIN_PULSES
from .sharpness import image_contrast, image_entropy
from .windows import Window

_PIXEL_BLOCK, _PULSE_BLOCK = 16384, 16  # 262 144 pixel-pulses per step: temporaries stay in cache


class FocusOptions(BaseModel):
    """What the user chooses: the ground window (m), the grid spacing (m) and the windows."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    range_extent_m: float = Field(100.0, gt=0, le=5000, allow_inf_nan=False, description="ground-range size")
    azimuth_extent_m: float = Field(100.0, gt=0, le=5000, allow_inf_nan=False, description="cross-range size")
    range_centre_m: float = Field(0.0, ge=-5000, le=5000, allow_inf_nan=False)
    azimuth_centre_m: float = Field(0.0, ge=-5000, le=5000, allow_inf_nan=False)
    spacing_m: float = Field(0.25, gt=0.005, le=50, allow_inf_nan=False, description="pixel spacing, both axes")
    range_window: str = "taylor-35-4"
    azimuth_window: str = "taylor-35-4"
    upsample: int = Field(8, ge=2, le=64, description="range-profile oversampling for interpolation")
    max_pixels: int = Field(4_000_000, ge=16)
    workers: int = Field(2, ge=1, le=16, description="threads for backprojection")

    @classmethod
    def build(cls, **kw) -> "FocusOptions":
        from pydantic import ValidationError
        try:
            opt = cls(**{k: v for k, v in kw.items() if v is not None})
        except ValidationError as err:
            raise from_validation_error(err) from None
        Window.parse(opt.range_window), Window.parse(opt.azimuth_window)
        return opt


@dataclass
class GroundGrid:
    """Pixel axes u (ground range, m) and v (cross range, m) and their unit vectors (scene frame)."""

    u_m: np.ndarray = field(repr=False)
    v_m: np.ndarray = field(repr=False)
    u_hat: np.ndarray
    v_hat: np.ndarray
    reference_antenna_m: np.ndarray

    @property
    def spacing_m(self) -> float:
        return float(self.v_m[1] - self.v_m[0])

    def points_m(self) -> np.ndarray:
        """Pixel positions (n_v · n_u, 3) on z = 0, row-major as the image array."""
        return (self.v_m[:, None, None] * self.v_hat + self.u_m[None, :, None] * self.u_hat).reshape(-1, 3)


@dataclass
class GroundImage:
    """Deramped complex image ``data`` (n_v, n_u), azimuth along axis 0, with what maps it to pulses."""

    data: np.ndarray = field(repr=False)
    grid: GroundGrid
    reference_frequency_hz: float
    pulse_bin_rad_m: np.ndarray = field(repr=False)  # ω_n of eq. (3), one per pulse
    label: str = ""

    @property
    def bin_rad_m(self) -> np.ndarray:
        """Azimuth spatial frequency of each bin of PGA's estimate (centred order), rad/m."""
        n = self.data.shape[0]
        return 2.0 * np.pi * np.fft.fftshift(np.fft.fftfreq(n, self.grid.spacing_m))

    def with_data(self, data: np.ndarray, label: str) -> "GroundImage":
        return GroundImage(data=data, grid=self.grid, reference_frequency_hz=self.reference_frequency_hz,
                           pulse_bin_rad_m=self.pulse_bin_rad_m, label=label)

    def magnitude_db(self, reference: float | None = None) -> np.ndarray:
        """20 log10 |I| re. ``reference`` (default the image peak), floored at −300 dB."""
        mag = np.abs(self.data)
        ref = float(mag.max()) if reference is None else float(reference)
        return 20.0 * np.log10(np.maximum(mag, 1e-15 * max(ref, 1e-300)) / max(ref, 1e-300))

    def summary(self) -> str:
        """One line: label, size, pixel spacing (m), entropy, contrast and peak magnitude."""
        d = self.to_dict()
        return (f"{d['label']}: {d['shape'][0]} × {d['shape'][1]} pixels at {d['spacing_m']:g} m; entropy "
                f"{d['entropy']:.5g}, contrast {d['contrast']:.4g}, peak {d['peak']:.4g}")

    def to_frame(self) -> pd.DataFrame:
        """Magnitude (dB re. peak); index cross range v (m), columns ground range u (m)."""
        return pd.DataFrame(self.magnitude_db(), index=pd.Index(self.grid.v_m, name="azimuth_m"),
                            columns=pd.Index(self.grid.u_m, name="range_m"))

    def to_dict(self) -> dict:
        """JSON-ready: label, shape, pixel spacing (m), entropy, contrast and peak magnitude."""
        return {"label": self.label, "shape": list(self.data.shape), "spacing_m": self.grid.spacing_m,
                "entropy": image_entropy(self.data), "contrast": image_contrast(self.data),
                "peak": float(np.abs(self.data).max())}


def _reference_antenna(ph: PhaseHistory) -> np.ndarray:
    n = ph.n_pulses
    return ph.antenna_m[n // 2] if n % 2 else 0.5 * (ph.antenna_m[n // 2 - 1] + ph.antenna_m[n // 2])


def _unit(a: np.ndarray) -> np.ndarray:
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def pulse_bins(ph: PhaseHistory, v_hat: np.ndarray, reference_antenna_m: np.ndarray) -> np.ndarray:
    """ω_n of eq. (3), rad/m, at the reference frequency."""
    k_r = _wavenumber(ph.reference_frequency_hz, C_M_S)
    return k_r * ((_unit(ph.antenna_m) - _unit(reference_antenna_m)) @ v_hat)


def ground_grid(ph: PhaseHistory, options: FocusOptions) -> GroundGrid:
    """The ground grid of ``options`` in the aperture-centred frame (module docstring)."""
    a_c = _reference_antenna(ph)
    g = np.array([a_c[0], a_c[1], 0.0])
    if np.linalg.norm(g) < 1e-6 * np.linalg.norm(a_c):
        raise InputError("the aperture centre is straight above the scene centre", field="antenna_m",
                         expected="a side-looking geometry")
    u_hat = g / np.linalg.norm(g)
    v_hat = np.cross([0.0, 0.0, 1.0], u_hat)
    w = pulse_bins(ph, v_hat, a_c)
    if w[-1] < w[0]:
        v_hat = -v_hat
    d = options.spacing_m
    n_u = int(round(options.range_extent_m / d)) + 1
    n_v = int(round(options.azimuth_extent_m / d)) + 1
    if n_u < 2 or n_v < 16:
        raise InputError(f"grid of {n_v} × {n_u} pixels", field="spacing_m",
                         expected="at least 16 azimuth and 2 range pixels (smaller spacing or larger extent)")
    if n_u * n_v > options.max_pixels:
        raise InputError(f"grid of {n_v} × {n_u} = {n_u * n_v} pixels", field="spacing_m",
                         expected=f"at most {options.max_pixels} pixels (larger spacing or smaller extent)")
    u = options.range_centre_m + (np.arange(n_u) - n_u // 2) * d
    v = options.azimuth_centre_m + (np.arange(n_v) - n_v // 2) * d
    return GroundGrid(u_m=u, v_m=v, u_hat=u_hat, v_hat=v_hat, reference_antenna_m=a_c)


def max_spacing_m(ph: PhaseHistory, grid_u_hat: np.ndarray, grid_v_hat: np.ndarray,
                  reference_antenna_m: np.ndarray) -> tuple[float, float]:
    """Largest (azimuth, range) pixel spacing that samples the complex deramped image without
    aliasing: 2π / (extent of its spatial-frequency support), m."""
    f = np.array([ph.frequency_hz[0], ph.frequency_hz[-1]])
    k = _wavenumber(f[:, None, None], C_M_S) * _unit(ph.antenna_m)[None]  # (2, n, 3)
    k = k - _wavenumber(ph.reference_frequency_hz, C_M_S) * _unit(reference_antenna_m)
    kv, ku = k @ grid_v_hat, k @ grid_u_hat
    return float(2.0 * np.pi / max(np.ptp(kv), 1e-12)), float(2.0 * np.pi / max(np.ptp(ku), 1e-12))


def range_profiles(ph: PhaseHistory, window: Window, upsample: int) -> tuple[np.ndarray, float]:
    """Baseband range profiles q_n (n_pulses, n_fft) (module docstring), index n_fft/2 ↔ ΔR = 0,
    and the profile's sample spacing in ΔR, m."""
    k = ph.n_frequencies
    n_fft = int(2 ** np.ceil(np.log2(k * upsample)))
    v = window.samples(k)
    spec = np.zeros((ph.n_pulses, n_fft), dtype=np.complex64)
    spec[:, (np.arange(k) - k // 2) % n_fft] = ph.samples * (v / v.sum()).astype(np.float32)
    q = np.fft.fftshift(np.fft.ifft(spec, axis=1), axes=1) * n_fft
    step = C_M_S / (2.0 * ph.frequency_step_hz * n_fft)
    return q.astype(np.complex64), step


def _backproject_rows(ph: PhaseHistory, q: np.ndarray, step: float, w_az: np.ndarray, grid: GroundGrid,
                      rows: slice, k_r: float) -> np.ndarray:
    """Eq. (2) on the grid rows ``rows`` (all columns), looping over blocks of pulses.

    The grid is separable: with p = v v̂ + u û, |A − p|² − R0² = f(v) + g(u),
    f = v² − 2v A·v̂ + |A|² − R0², g = u² − 2u A·û (float64 on the axes, then float32), and
    ΔR = N / (R0 + √(R0² + N)) with N = f + g: float32 keeps ΔR to ~1e-7 relative (0.003 rad at
    70 m) because the rounding of the square root only enters the denominator, ≈ 2 R0."""
    v, u = grid.v_m[rows], grid.u_m
    n_ext = q.shape[1]
    acc = np.zeros(v.size * u.size, dtype=np.complex64)
    for s in range(0, ph.n_pulses, _PULSE_BLOCK):
        a = ph.antenna_m[s:s + _PULSE_BLOCK]
        r0 = ph.scene_range_m[s:s + _PULSE_BLOCK]
        f = v[None, :] ** 2 - 2.0 * v[None, :] * (a @ grid.v_hat)[:, None] + ((a ** 2).sum(axis=1) - r0 ** 2)[:, None]
        g = u[None, :] ** 2 - 2.0 * u[None, :] * (a @ grid.u_hat)[:, None]
        n_sq = (f.astype(np.float32)[:, :, None] + g.astype(np.float32)[:, None, :]).reshape(a.shape[0], -1)
        r0_32 = r0.astype(np.float32)[:, None]
        den = n_sq + r0_32 ** 2
        np.sqrt(den, out=den)
        den += r0_32
        d_r = np.divide(n_sq, den, out=n_sq)
        # profile index; the profile is zero-padded by 2 samples each side, so clipped indices
        # (pixels beyond its unambiguous span) read zeros
        x = d_r * np.float32(1.0 / step)
        x += np.float32(n_ext // 2)
        i0 = x.astype(np.int32)
        frac = x - i0
        np.clip(i0, 0, n_ext - 2, out=i0)
        i0 += (np.arange(a.shape[0], dtype=np.int32) * n_ext)[:, None]
        flat = q[s:s + _PULSE_BLOCK].ravel()
        val = flat[i0]
        nxt = flat[i0 + 1]
        nxt -= val
        nxt *= frac
        val += nxt
        d_r *= np.float32(k_r)
        rot = np.empty(val.shape, dtype=np.complex64)
        np.cos(d_r, out=rot.real)
        np.sin(d_r, out=rot.imag)
        val *= rot
        acc += w_az[s:s + _PULSE_BLOCK] @ val
    return acc


def backproject(ph: PhaseHistory, grid: GroundGrid, options: FocusOptions) -> np.ndarray:
    """Raw (not deramped) image of eq. (2) on ``grid``, (n_v, n_u) complex64; unit scatterer → 1.

    Blocks of grid rows run on ``options.workers`` threads (NumPy releases the GIL in its loops)."""
    q, step = range_profiles(ph, Window.parse(options.range_window), options.upsample)
    q = np.pad(q, ((0, 0), (2, 2)))  # zeros beyond the span; index n_ext // 2 is still ΔR = 0
    w_az = Window.parse(options.azimuth_window).samples(ph.n_pulses)
    w_az = (w_az / w_az.sum()).astype(np.float32)
    k_r = _wavenumber(ph.reference_frequency_hz, C_M_S)
    n_rows = max(1, _PIXEL_BLOCK // grid.u_m.size)
    blocks = [slice(r, min(r + n_rows, grid.v_m.size)) for r in range(0, grid.v_m.size, n_rows)]

    def one(rows: slice) -> np.ndarray:
        return _backproject_rows(ph, q, step, w_az, grid, rows, k_r)

    if options.workers > 1 and len(blocks) > 1:
        from concurrent.futures import ThreadPoolExecutor
        with ThreadPoolExecutor(max_workers=options.workers) as pool:
            parts = list(pool.map(one, blocks))
    else:
        parts = [one(b) for b in blocks]
    return np.concatenate(parts).reshape(grid.v_m.size, grid.u_m.size)


def deramp(grid: GroundGrid, reference_frequency_hz: float) -> np.ndarray:
    """exp(−j k_r (|A_c − p| − |A_c|)) on the grid (n_v, n_u), see module docstring."""
    a_c = grid.reference_antenna_m
    pix = grid.points_m()
    rng = np.linalg.norm(pix - a_c, axis=1) - np.linalg.norm(a_c)
    k_r = _wavenumber(reference_frequency_hz, C_M_S)
    return np.exp(-1j * k_r * rng).reshape(grid.v_m.size, grid.u_m.size).astype(np.complex64)


#: Largest stack of range profiles (pulses × FFT length, complex64) :func:`backproject` may build,
#: bytes; the FFT and its copies take about four times this at the peak.
MAX_PROFILE_BYTES = 512 * 2 ** 20

#: Most pixel-pulse products (pixels × pulses) one image may cost: ≈ 10⁷ per second on 2 threads
#: (469 Gotcha pulses on 401 × 401 pixels, 75 M, take ≈ 7 s), so this is ≈ 8 minutes.
MAX_PIXEL_PULSES = 5_000_000_000


#: Fewest pulses an image is formed from (the simulator's own minimum, :data:`~budget.sar.geometry.MIN_PULSES`).
MIN_FOCUS_PULSES = MIN_PULSES


def check_cost(ph: PhaseHistory, options: FocusOptions) -> None:
    """Refuse, before any array is built, an image whose range profiles would exceed
    :data:`MAX_PROFILE_BYTES` or whose backprojection would exceed :data:`MAX_PIXEL_PULSES`."""
    n_fft = int(2 ** np.ceil(np.log2(ph.n_frequencies * options.upsample)))
    size = ph.n_pulses * n_fft * 8
    if size > MAX_PROFILE_BYTES:
        raise InputError(f"{ph.n_pulses} pulses × {n_fft} range samples need {size / 2 ** 30:.3g} GiB of range "
                         "profiles (≈ 4× that at the peak)", field="pulses",
                         expected=f"at most {MAX_PROFILE_BYTES // (8 * n_fft)} pulses at "
                                  f"{ph.n_frequencies} frequencies (fewer files, or a shorter aperture)")
    n_u = int(round(options.range_extent_m / options.spacing_m)) + 1
    n_v = int(round(options.azimuth_extent_m / options.spacing_m)) + 1
    work = n_u * n_v * ph.n_pulses
    if work > MAX_PIXEL_PULSES:
        raise InputError(f"{n_v} × {n_u} pixels × {ph.n_pulses} pulses = {work:.3g} pixel-pulses "
                         f"(≈ {work / 1e7 / 60:.0f} min to backproject)", field="pulses",
                         expected=f"at most {MAX_PIXEL_PULSES:.2g} (fewer pulses, a smaller window or a larger "
                                  "spacing)")


def _unambiguous_azimuth_m(ph: PhaseHistory, grid: GroundGrid) -> float:
    """Cross-range period of the image, m: 2π / (median step of the azimuth spatial frequency
    between consecutive pulses at the highest frequency, eq. 3). A scatterer at v also appears
    at v ± this (the pulses sample the aperture too sparsely beyond it: every other pulse
    dropped halves it)."""
    k_max = _wavenumber(float(ph.frequency_hz[-1]), C_M_S)
    step = np.abs(np.diff(_unit(ph.antenna_m) @ grid.v_hat))
    med = float(np.median(step)) if step.size else 0.0
    return float("inf") if not med > 0 else 2.0 * np.pi / (k_max * med)


def check_geometry(ph: PhaseHistory, grid: GroundGrid, options: FocusOptions) -> None:
    """Refuse a window the phase history cannot image (:class:`InputError` saying what to change):

    * fewer than :data:`MIN_FOCUS_PULSES` pulses (with a constant and a linear term removed, a
      phase over 2–5 pulses has nothing left to autofocus or to compare);
    * an antenna that does not move across the pulses (no synthetic aperture);
    * an antenna inside or at the edge of the window (the ranges are far too short: positions and
      ``r0`` in km, say);
    * pixels beyond the recorded range swath, |ΔR_n(p)| > c / (4 Δf) (the profile's unambiguous
      half-span): they would be blank. When the scene centre itself (the origin) is beyond it the
      positions and the ranges R0 disagree — another frame origin or another unit;
    * a cross-range extent beyond :func:`_unambiguous_azimuth_m`: the image would hold ghosts of
      its own scatterers (aliased azimuth: pulses dropped)."""
    if ph.n_pulses < MIN_FOCUS_PULSES:
        raise InputError(f"{ph.n_pulses} pulses are too few for an image to autofocus or to compare: with a "
                         "constant and a linear term removed, a phase over so few pulses has (almost) nothing "
                         "left to differ in", field="pulses", value=ph.n_pulses,
                         expected=f"at least {MIN_FOCUS_PULSES} pulses (more files, or a longer aperture)")
    w = pulse_bins(ph, grid.v_hat, grid.reference_antenna_m)
    if not np.ptp(w) > 0:
        raise InputError("the antenna does not move across the pulses (no synthetic aperture)",
                         field="antenna_m", expected="antenna positions along a track, m")
    corners = np.array([[u, v] for u in (grid.u_m[0], grid.u_m[-1], 0.0) for v in (grid.v_m[0], grid.v_m[-1], 0.0)])
    pix = corners[:, :1] * grid.u_hat + corners[:, 1:] * grid.v_hat  # (9, 3) on z = 0
    reach = float(np.max(np.linalg.norm(pix[:-1], axis=1)))
    ground = np.linalg.norm(ph.antenna_m[:, :2], axis=1)
    if float(ground.min()) <= reach:
        raise InputError(f"the antenna passes {ground.min():.4g} m (ground range) from the scene centre, inside the "
                         f"image window (which reaches {reach:.4g} m): positions and r0 in m expected (in km?)",
                         field="antenna_m", expected="an antenna far outside the imaged window, positions in m")
    half = C_M_S / (4.0 * ph.frequency_step_hz)
    d_r = np.linalg.norm(ph.antenna_m[:, None, :] - pix[None], axis=2) - ph.scene_range_m[:, None]  # (n, 9)
    centre = d_r[:, -1]
    if float(np.max(np.abs(centre))) > half:
        ratio = float(np.median(np.linalg.norm(ph.antenna_m, axis=1) / ph.scene_range_m))
        unit = ""
        for factor, name in ((1e-3, "positions in km, ranges in m"), (1e3, "positions in m, ranges in km")):
            if abs(ratio / factor - 1.0) < 0.05:
                unit = f" ({name}?)"
        raise InputError(f"the antenna's distance to the frame origin differs from the recorded range r0 by "
                         f"{np.median(centre):.4g} m (median over the pulses){unit}: the data are not deramped to "
                         f"this origin, which lies outside the ±{half:.4g} m range swath the "
                         f"{ph.frequency_step_hz:.4g} Hz frequency step records", field="antenna_m, scene_range_m",
                         expected="positions in m in a frame centred on the scene centre, r0 = their distance to it")
    if float(np.max(np.abs(d_r))) > half:
        far = float(np.max(np.abs(d_r)))
        raise InputError(f"pixels up to {far:.4g} m in slant range from the scene centre, beyond the ±{half:.4g} m "
                         f"swath the {ph.frequency_step_hz:.4g} Hz frequency step records (c/4Δf): they would be blank",
                         field="range_extent_m", value=options.range_extent_m,
                         expected="a window within the swath (smaller range extent or centre offsets)")
    period = _unambiguous_azimuth_m(ph, grid)
    extent = float(grid.v_m[-1] - grid.v_m[0])
    if extent > period:
        raise InputError(f"the pulses sample the aperture too sparsely for a {extent:.4g} m cross-range window: the "
                         f"image repeats every {period:.4g} m (aliased azimuth: pulses dropped?), so it would show "
                         "ghosts of its own scatterers", field="azimuth_extent_m", value=options.azimuth_extent_m,
                         expected=f"at most {period:.4g} m, or the pulses at their full rate")


def form_ground_image(ph: PhaseHistory, options: FocusOptions | None = None, label: str = "") -> GroundImage:
    """Backprojected, deramped ground image of ``ph`` on the grid of ``options`` (module docstring).

    Refused before any work (:class:`InputError`): a cost beyond :func:`check_cost`'s limits, a
    window :func:`check_geometry` refuses, a spacing that aliases the image."""
    options = options or FocusOptions()
    check_cost(ph, options)
    grid = ground_grid(ph, options)
    check_geometry(ph, grid, options)
    d_az, d_rg = max_spacing_m(ph, grid.u_hat, grid.v_hat, grid.reference_antenna_m)
    if options.spacing_m > d_az or options.spacing_m > d_rg:
        raise InputError("pixel spacing too coarse: the image would alias", field="spacing_m",
                         value=options.spacing_m,
                         expected=f"at most {min(d_az, d_rg):.4g} m (azimuth {d_az:.4g} m, range {d_rg:.4g} m)")
    raw = backproject(ph, grid, options)
    data = raw * deramp(grid, ph.reference_frequency_hz)
    return GroundImage(data=data, grid=grid, reference_frequency_hz=ph.reference_frequency_hz,
                       pulse_bin_rad_m=pulse_bins(ph, grid.v_hat, grid.reference_antenna_m), label=label)
