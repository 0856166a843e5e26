"""Sampling geometry of the point-target simulator: pulses, range bins, windows, scene frame.

Frame (local level): x along-track (velocity), y horizontal cross-track toward the imaged side,
z up. The nominal antenna phase centre (APC) flies p(t) = (V t, 0, h) for t ∈ [−T/2, T/2]; the
scene lies on the plane z = 0 with its centre at (0, y_c, 0), slant range R_c (the scenario's
``slant_range_m``) at depression ψ: h = R_c sin ψ, y_c = R_c cos ψ.

Squint: a squinted scenario is simulated as its broadside equivalent in the frame of its own line
of sight, flying the cross-LOS speed V·cos s with the same Tc (:mod:`budget.sar.squint`);
:meth:`SarGeometry.imaging_frame` rotates navigation-frame APC errors into it.

Mode: every target is seen over the whole aperture (spotlight, or one strip-map aperture without
antenna pattern), so all targets share one slow-time phase history — the model of PGA.

Sampling:
* aperture time T = Tc of seed 004 (5) (``scenario.tc_s``, which holds the window factor a_w);
  Doppler bandwidth of one target B_a = 2V²T/(λR_c) = a_w V/δℓ;
* PRF ≥ ``oversample`` · (B_a + 2V X_s/(λR_c)) (X_s: azimuth scene extent, whose targets add
  Doppler offsets), rounded up so that the pulse count is FFT-friendly; T stays exact;
* range bandwidth B_r = a_w c/(2δr), sample rate f_s = ``oversample`` · B_r, band = the odd number
  M of DFT bins closest to B_r, so B_eff = M f_s / N_r;
* swath = scene extent + range-cell migration + motion margin + pulse tails.

The phase history of every target is exact at every simulated pulse (stop-and-go); nothing is
decimated. Scenarios that would need more than ``max_pulses`` pulses, or an image of more than
``max_pixels`` pulses × range bins, raise :class:`InputError` (a Monte Carlo keeps about a dozen
geometry-only arrays of the image's size: :data:`MAX_PIXELS` bounds that to ≈ 1 GB).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy.fft import next_fast_len

from ..errors import InputError
from ..scenario import Scenario
from .squint import broadside_equivalent, left_out_fraction, squint_note, to_imaging_frame
from .windows import Window, scenario_window

MIN_PULSES = 16
#: Largest image simulated (pulses × range bins): 2²² pixels, 67 MB per complex copy, 60× the
#: largest preset's (0.066 M); the Monte Carlo's geometry-only arrays then stay below ≈ 1 GB.
MAX_PIXELS = 1 << 22
#: Azimuth room of the range-Doppler image beyond each edge of the scene, resolution cells.
IMAGE_MARGIN_CELLS = 16.0


@dataclass(frozen=True)
class SarGeometry:
    """Everything the simulator, the image formers and the metrics need (SI units)."""

    scenario_name: str
    medium: str
    carrier_frequency_hz: float
    c_m_s: float
    speed_m_s: float
    ref_range_m: float
    depression_rad: float
    prf_hz: float
    pulse_times_s: np.ndarray = field(repr=False)
    range_sample_rate_hz: float
    range_axis_m: np.ndarray = field(repr=False)
    band_bins: int
    scene_extent_m: tuple[float, float]  # (azimuth, slant range), full widths
    window_azimuth: Window
    window_range: Window
    azimuth_resolution_m: float
    range_resolution_m: float
    #: azimuth excursion of a defocused response the image and the PRF hold beyond the scene's
    #: edges, resolution cells (0: the default 16-cell image margin; :mod:`budget.mc.defocus`)
    defocus_room_cells: float = 0.0
    #: squint of the scenario (rad): the geometry is its broadside equivalent (speed V·cos s) and
    #: motion errors enter through :meth:`imaging_frame` (:mod:`budget.sar.squint`)
    squint_rad: float = 0.0

    # --- derived -------------------------------------------------------------------------
    @property
    def wavelength_m(self) -> float:
        return self.c_m_s / self.carrier_frequency_hz

    @property
    def n_pulses(self) -> int:
        return int(self.pulse_times_s.size)

    @property
    def n_range(self) -> int:
        return int(self.range_axis_m.size)

    @property
    def aperture_time_s(self) -> float:
        """T = N / PRF (s): the time the N pulses stand for."""
        return self.n_pulses / self.prf_hz

    @property
    def aperture_length_m(self) -> float:
        return self.speed_m_s * self.aperture_time_s

    @property
    def height_m(self) -> float:
        return self.ref_range_m * math.sin(self.depression_rad)

    @property
    def ground_range_m(self) -> float:
        return self.ref_range_m * math.cos(self.depression_rad)

    @property
    def range_bin_m(self) -> float:
        return self.c_m_s / (2.0 * self.range_sample_rate_hz)

    @property
    def range_bandwidth_hz(self) -> float:
        """B_eff = M · f_s / N_r: the band actually simulated (Hz)."""
        return self.band_bins * self.range_sample_rate_hz / self.n_range

    @property
    def range_cell_m(self) -> float:
        """One range resolution cell c/(2 B_eff) (m); the 3 dB width is 0.886 cells unweighted."""
        return self.c_m_s / (2.0 * self.range_bandwidth_hz)

    def azimuth_cell_m(self, slant_range_m: float | None = None) -> float:
        """One azimuth cell λR/(2 V T) (m) at ``slant_range_m`` (default R_c)."""
        r = self.ref_range_m if slant_range_m is None else slant_range_m
        return self.wavelength_m * r / (2.0 * self.speed_m_s * self.aperture_time_s)

    @property
    def azimuth_fm_rate_hz_s(self) -> float:
        """K_a = 2V²/(λR_c) (Hz/s)."""
        return 2.0 * self.speed_m_s ** 2 / (self.wavelength_m * self.ref_range_m)

    @property
    def doppler_bandwidth_hz(self) -> float:
        """B_a = K_a T (Hz), Doppler band of one target over the aperture."""
        return self.azimuth_fm_rate_hz_s * self.aperture_time_s

    @property
    def azimuth_axis_m(self) -> np.ndarray:
        """Azimuth positions V t of the pulses (the range-Doppler image's azimuth axis)."""
        return self.speed_m_s * self.pulse_times_s

    @property
    def n_azimuth(self) -> int:
        """Azimuth samples of the range-Doppler image: the pulses, zero-padded when the aperture
        V·T is shorter than the scene plus 16 cells, or :attr:`defocus_room_cells` when more,
        each side (same parity as n_pulses)."""
        dx = self.speed_m_s / self.prf_hz
        room = max(IMAGE_MARGIN_CELLS, self.defocus_room_cells)
        need = self.scene_extent_m[0] + 2.0 * room * self.azimuth_cell_m()
        if self.n_pulses * dx >= need:
            return self.n_pulses
        n = next_fast_len(int(math.ceil(need / dx)))
        while (n - self.n_pulses) % 2:
            n = next_fast_len(n + 1)
        return n

    @property
    def image_azimuth_axis_m(self) -> np.ndarray:
        """Azimuth positions of the range-Doppler image samples (pulse positions, extended)."""
        n = self.n_azimuth
        return self.speed_m_s * (np.arange(n) - (n - 1) / 2.0) / self.prf_hz

    @property
    def range_band_freqs_hz(self) -> np.ndarray:
        """The M in-band range frequencies (baseband, symmetric)."""
        m = np.arange(self.band_bins) - (self.band_bins - 1) // 2
        return m * self.range_sample_rate_hz / self.n_range

    @property
    def range_band_index(self) -> np.ndarray:
        """DFT indices (numpy order) of the in-band range frequencies."""
        m = np.arange(self.band_bins) - (self.band_bins - 1) // 2
        return np.mod(m, self.n_range)

    def nominal_apc_m(self) -> np.ndarray:
        """Nominal APC positions (n_pulses, 3), m."""
        p = np.zeros((self.n_pulses, 3))
        p[:, 0] = self.azimuth_axis_m
        p[:, 2] = self.height_m
        return p

    def scene_point_m(self, azimuth_m, slant_range_m) -> np.ndarray:
        """Ground point(s) (…, 3) at along-track ``azimuth_m`` and closest-approach ``slant_range_m``."""
        x = np.asarray(azimuth_m, dtype=float)
        r = np.asarray(slant_range_m, dtype=float)
        y = np.sqrt(np.maximum(r ** 2 - self.height_m ** 2, 0.0))
        x, y = np.broadcast_arrays(x, y)
        return np.stack([x, y, np.zeros_like(x)], axis=-1)

    @property
    def scene_centre_m(self) -> np.ndarray:
        return np.array([0.0, self.ground_range_m, 0.0])

    def check_offset(self, offset_m, name: str) -> np.ndarray:
        """Validate an APC offset array: None → zeros; else finite, shape (n_pulses, 3), metres."""
        if offset_m is None:
            return np.zeros((self.n_pulses, 3))
        a = np.asarray(offset_m, dtype=float)
        if a.shape != (self.n_pulses, 3):
            raise InputError(f"APC offset has shape {a.shape}", field=name,
                             expected=f"an array of shape ({self.n_pulses}, 3) in metres (x, y, z per pulse)")
        if not np.all(np.isfinite(a)):
            raise InputError("APC offset holds NaN or infinite values", field=name,
                             expected="finite metres")
        return a

    def imaging_frame(self, error_m: np.ndarray) -> np.ndarray:
        """APC errors (…, 3) in the navigation frame (x along the velocity) in this geometry's
        frame: rotated by the squint (:func:`budget.sar.squint.to_imaging_frame`); unchanged at
        broadside."""
        return to_imaging_frame(error_m, self.squint_rad)

    @property
    def squint_note(self) -> str:
        """What a squinted scenario's simulation assumed; empty at broadside."""
        return squint_note(self.squint_rad, self.speed_m_s,
                           left_out_fraction(self.squint_rad, self.depression_rad, self.wavelength_m,
                                             self.azimuth_cell_m()))

    def summary(self) -> str:
        """A few lines: scenario, wavelength, aperture, PRF, samples, cells and windows."""
        d = self.to_dict()
        return (f"{d['scenario']} ({d['medium']}): λ = {d['wavelength_m']:.4g} m, v = {d['speed_m_s']:g} m/s, "
                f"R0 = {d['ref_range_m']:g} m\n"
                f"aperture {d['aperture_time_s']:.3g} s / {d['aperture_length_m']:.3g} m, PRF {d['prf_hz']:.4g} Hz, "
                f"{d['n_pulses']} pulses × {d['n_range']} range bins\n"
                f"cells {d['azimuth_cell_m']:.3g} m (azimuth) × {d['range_cell_m']:.3g} m (range); windows "
                f"{d['window_azimuth']} / {d['window_range']}" + (f"\n{self.squint_note}" if self.squint_rad else ""))

    def to_frame(self) -> pd.DataFrame:
        """One row: every quantity of :meth:`to_dict` (scene extent as two columns)."""
        d = self.to_dict()
        ext = d.pop("scene_extent_m")
        return pd.DataFrame([{**d, "scene_extent_azimuth_m": ext[0], "scene_extent_range_m": ext[1]}])

    def to_dict(self) -> dict:
        """JSON-ready geometry: scenario, wavelength, speed, ranges, aperture, sampling, cells, windows (SI)."""
        return {
            "scenario": self.scenario_name, "medium": self.medium,
            "wavelength_m": self.wavelength_m, "speed_m_s": self.speed_m_s,
            "ref_range_m": self.ref_range_m, "height_m": self.height_m,
            "aperture_time_s": self.aperture_time_s, "aperture_length_m": self.aperture_length_m,
            "prf_hz": self.prf_hz, "doppler_bandwidth_hz": self.doppler_bandwidth_hz,
            "n_pulses": self.n_pulses, "n_range": self.n_range,
            "range_bandwidth_hz": self.range_bandwidth_hz, "range_bin_m": self.range_bin_m,
            "azimuth_cell_m": self.azimuth_cell_m(), "range_cell_m": self.range_cell_m,
            "scene_extent_m": self.scene_extent_m,
            "window_azimuth": self.window_azimuth.label, "window_range": self.window_range.label,
            "squint_deg": math.degrees(self.squint_rad),
        }

    # --- construction --------------------------------------------------------------------
    @classmethod
    def from_scenario(cls, scenario: Scenario, *, scene_extent_cells: float = 48.0,
                      oversample: float = 1.25, window: Window | str | None = None,
                      motion_margin_cells: float = 8.0, max_pulses: int = 16384,
                      max_range_bins: int = 4096, max_pixels: int | None = None,
                      defocus_room_cells: float = 0.0) -> "SarGeometry":
        """Sampling for ``scenario``; raises :class:`InputError` naming the field and the limit.

        ``scene_extent_cells``: width of the square target area in resolution cells (δℓ × δr).
        ``defocus_room_cells``: how far (resolution cells) a motion error may move a response in
        azimuth beyond the scene's edges and stay in the image and inside the PRF's Doppler
        band (:mod:`budget.mc.defocus`); 0 leaves the sampling as without it.
        ``oversample``: PRF over the total Doppler band and f_s over B_r (> 1).
        ``window``: azimuth and range window; default rect when ``window_broadening`` < 1.1,
        else Taylor −35 dB, n̄ = 4. ``motion_margin_cells``: extra swath each side for APC offsets.
        """
        if not isinstance(scenario, Scenario):
            raise InputError("expected a Scenario", field="scenario", value=type(scenario).__name__)
        if not (1.0 < oversample <= 8.0):
            raise InputError("oversampling out of range", field="oversample", value=oversample,
                             expected="1 < oversample ≤ 8")
        if not (4.0 <= scene_extent_cells <= 512.0):
            raise InputError("scene extent out of range", field="scene_extent_cells",
                             value=scene_extent_cells, expected="4 … 512 resolution cells")
        if not (math.isfinite(defocus_room_cells) and 0.0 <= defocus_room_cells <= 1024.0):
            raise InputError("defocus room out of range", field="defocus_room_cells",
                             value=defocus_room_cells, expected="0 … 1024 azimuth cells")
        if not (0.0 <= motion_margin_cells <= 256.0):
            raise InputError("motion margin out of range", field="motion_margin_cells",
                             value=motion_margin_cells, expected="0 … 256 range cells")
        if not scenario.platform_speed_m_s > 0:
            raise InputError("platform speed must be positive", field="platform_speed_m_s",
                             value=scenario.platform_speed_m_s, expected="> 0 m/s")
        window = scenario_window(scenario) if window is None else Window.parse(window)
        squint_rad = math.radians(scenario.squint_deg)
        scenario = broadside_equivalent(scenario)  # a squinted aperture in its own LOS frame
        c, f0, v = scenario.c_m_s, scenario.carrier_frequency_hz, scenario.platform_speed_m_s
        lam, r_c = scenario.wavelength_m, scenario.slant_range_m
        a_w = scenario.window_broadening
        # --- range ---
        b_r = a_w * c / (2.0 * scenario.range_resolution_m)
        if b_r > 0.5 * f0:
            raise InputError(f"range resolution needs a bandwidth of {b_r:.4g} Hz, more than half the "
                             f"carrier {f0:.4g} Hz", field="range_resolution_m",
                             value=scenario.range_resolution_m,
                             expected=f"≥ {a_w * c / f0:.4g} m (fractional bandwidth ≤ 0.5)")
        fs = oversample * b_r
        dr = c / (2.0 * fs)
        x_s = scene_extent_cells * scenario.azimuth_resolution_m
        y_s = scene_extent_cells * scenario.range_resolution_m
        if y_s > 0.2 * r_c:
            raise InputError(f"the simulated scene ({scene_extent_cells:g} range cells of "
                             f"{scenario.range_resolution_m:g} m = {y_s:.4g} m) exceeds 20 % of the "
                             "slant range", field="slant_range_m", value=r_c,
                             expected=f"slant_range_m ≥ {5.0 * y_s:.4g} m, or a range resolution "
                             f"≤ {0.2 * r_c / scene_extent_cells:.4g} m")
        tc = scenario.tc_s
        half_len = 0.5 * (v * tc + x_s)
        if half_len / r_c > 0.35:
            raise InputError(f"aperture half-angle {math.degrees(math.atan(half_len / r_c)):.1f}° exceeds 20°",
                             field="azimuth_resolution_m", value=scenario.azimuth_resolution_m,
                             expected="a coarser azimuth resolution (small-angle deramp used by PGA)")
        rcm = math.hypot(r_c, half_len) - r_c
        margin = math.ceil((rcm + motion_margin_cells * scenario.range_resolution_m) / dr) + 24
        n_r = next_fast_len(int(math.ceil(y_s / dr)) + 2 * margin)
        if n_r > max_range_bins:
            raise InputError(f"swath needs {n_r} range bins", field="range_resolution_m",
                             value=scenario.range_resolution_m, expected=f"≤ {max_range_bins} bins "
                             "(coarser range resolution or smaller scene_extent_cells)")
        m = int(round(b_r / fs * n_r))
        m = m if m % 2 == 1 else m + 1
        range_axis = r_c + (np.arange(n_r) - n_r // 2) * dr
        # --- azimuth ---
        k_a = 2.0 * v ** 2 / (lam * r_c)
        b_a = k_a * tc
        span = 2.0 * v * x_s / (lam * r_c)
        n_min = int(math.ceil(tc * oversample * (b_a + span)))
        # a response moved e cells (a Doppler of e/Tc) must not wrap: the band B_a + span plus
        # the room on both sides within the PRF
        n_min = max(n_min, int(math.ceil(tc * (b_a + span) + 2.0 * defocus_room_cells)))
        if n_min > max_pulses:
            raise InputError(f"the aperture needs {n_min} pulses (Tc = {tc:.3g} s × PRF "
                             f"{oversample * (b_a + span):.4g} Hz)", field="azimuth_resolution_m",
                             value=scenario.azimuth_resolution_m,
                             expected=f"at most {max_pulses} pulses the simulator forms (a coarser "
                             "azimuth resolution, shorter range or slower platform; the analytic "
                             "bounds and the part check need no simulation)")
        n_own = int(math.ceil(tc * oversample * b_a))  # pulses of one target's own Doppler band
        if n_own < MIN_PULSES:
            raise InputError(f"the aperture holds only {n_own} pulses at the Doppler bandwidth "
                             f"(time-bandwidth product {tc * b_a:.3g})", field="azimuth_resolution_m",
                             value=scenario.azimuth_resolution_m,
                             expected=f"at least {MIN_PULSES} pulses (finer azimuth resolution or longer range)")
        n_p = next_fast_len(n_min)
        max_pixels = MAX_PIXELS if max_pixels is None else max_pixels
        if n_p * n_r > max_pixels:
            raise InputError(f"the image would be {n_p} pulses × {n_r} range bins = {n_p * n_r / 1e6:.3g} M "
                             f"pixels ({16 * n_p * n_r / 1e9:.2g} GB per complex copy; a Monte Carlo holds about "
                             "a dozen)", field="azimuth_resolution_m", value=scenario.azimuth_resolution_m,
                             expected=f"at most {max_pixels / 1e6:.3g} M pixels (coarser azimuth or range "
                             "resolution, or a shorter range)")
        prf = n_p / tc
        times = (np.arange(n_p) - (n_p - 1) / 2.0) / prf
        for arr in (times, range_axis):
            arr.setflags(write=False)
        return cls(scenario_name=scenario.name, medium=scenario.medium, carrier_frequency_hz=f0,
                   c_m_s=c, speed_m_s=v, ref_range_m=r_c, depression_rad=math.radians(scenario.depression_deg),
                   prf_hz=prf, pulse_times_s=times, range_sample_rate_hz=fs, range_axis_m=range_axis,
                   band_bins=m, scene_extent_m=(x_s, y_s), window_azimuth=window, window_range=window,
                   azimuth_resolution_m=scenario.azimuth_resolution_m,
                   range_resolution_m=scenario.range_resolution_m,
                   defocus_room_cells=float(defocus_room_cells), squint_rad=squint_rad)
