"""What a recorded phase history is: band, aperture and the resolutions they give, in one place.

:func:`describe_acquisition` computes, from the phase history's own fields (frequencies, antenna
track, ranges to the scene centre, and the pulse times and file-name tags when there are any),
SI throughout:

* the band: centre frequency f_c = (f_first + f_last) / 2, bandwidth B = K Δf (K samples Δf
  apart: the band they occupy, one step more than the span f_last − f_first), wavelength
  λ_c = c / f_c;
* the aperture, with the scene centre at the frame origin: the look direction of pulse n is
  l_n = A_n / |A_n|; the synthetic-aperture angle Δθ is the angle between the first and the last
  look directions, atan2(|l_0 × l_N−1|, l_0 · l_N−1) (on a circular pass at elevation ψ this is
  ≈ the azimuth span × cos ψ: the angle the scene sees the antenna turn through); the angle step
  δθ is the median of the same angle between consecutive pulses; the aperture length is the
  track's length, Σ |A_n+1 − A_n|; the mean slant range is the mean of the recorded ranges to the
  scene centre R0_n; the grazing angle ψ is the mean over the pulses of the antenna's elevation
  seen from the scene centre, atan2(z_n, √(x_n² + y_n²)) (flat ground z = 0); the mean platform
  speed is the aperture length over the time from the first to the last pulse, when pulse times
  exist (the AFRL files carry none — the provider's README documents no time field — and the
  summary says so). Everything here comes from the positions; the files' own angles ``th``/``phi``
  are checked against them by the reader (:mod:`budget.sar.geometry_check`: a note naming the
  likely cause, e.g. radians or swapped axes, on the phase history, which the focus result shows);
* the closed-form resolutions (Jakowatz et al. 1996, "Spotlight-Mode Synthetic Aperture Radar:
  A Signal Processing Approach", ch. 2; Carrara et al. 1995, "Spotlight Synthetic Aperture
  Radar: Signal Processing Algorithms", ch. 2): slant range ρ_r = c / (2B), ground range
  ρ_g = c / (2B cos ψ), cross range ρ_x = λ_c / (2Δθ) (in the ground plane when the cross-range
  direction is horizontal, as for a level pass). Each is 2π over the extent of the image's
  spatial-frequency support (4πB/c in slant range, 4πΔθ/λ_c in cross range), so a rectangular
  window gives a 3 dB width of 0.886 ρ (measured in ``tests/test_focus_description.py``) and a
  Taylor window a wider one;
* the unambiguous scene extent the sampling allows (same references): c / (2Δf) in slant range
  (c / (2Δf cos ψ) in ground range) and λ_c / (2δθ) in cross range, 2π over the sampling step of
  the spatial frequency. Image formation refuses windows beyond the sharper limits it checks itself
  (:func:`budget.sar.focus.check_geometry`: the swath about the scene centre, the period at the
  highest frequency);
* with the image grid: its pixel spacing beside the resolutions and its extent beside the
  unambiguous extents, with a note when the spacing exceeds a resolution (the grid undersamples
  the impulse response) or the extent exceeds an unambiguous extent.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np
import pandas as pd

from .phase_history import C_M_S, PhaseHistory

#: A pixel spacing above this fraction of a resolution undersamples the image (spacing > ρ / 1.0).
UNDERSAMPLED_FRACTION = 1.0

#: How each aperture quantity is measured (in :meth:`Acquisition.to_dict`).
METHODS = {
    "aperture_angle_rad": "angle between the first and last look directions from the scene centre (frame origin)",
    "angle_step_rad": "median angle between consecutive pulses' look directions from the scene centre",
    "aperture_length_m": "length of the antenna track, sum of the steps between pulses",
    "mean_slant_range_m": "mean of the recorded ranges to the scene centre (r0)",
    "grazing_angle_rad": "mean elevation of the antenna seen from the scene centre, atan2(z, ground range)",
    "bandwidth_hz": "number of frequency samples × frequency step",
    "centre_frequency_hz": "mid-point of the first and last frequency",
}


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle between unit vectors (rows), rad, accurate at small angles."""
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.einsum("...i,...i->...", a, b))


@dataclass(frozen=True)
class Acquisition:
    """The band, aperture, closed-form resolutions and unambiguous extents of a phase history
    (module docstring), SI; with the image grid's spacing and extent when described with one."""

    files: tuple[str, ...]
    pass_name: str | None
    polarisation: str | None
    pulses: int
    frequency_samples: int
    centre_frequency_hz: float
    bandwidth_hz: float
    frequency_step_hz: float
    wavelength_m: float
    aperture_angle_rad: float
    angle_step_rad: float
    aperture_length_m: float
    platform_speed_m_s: float | None
    mean_slant_range_m: float
    grazing_angle_rad: float
    slant_range_resolution_m: float
    ground_range_resolution_m: float
    cross_range_resolution_m: float
    unambiguous_slant_range_m: float
    unambiguous_ground_range_m: float
    unambiguous_cross_range_m: float
    pixel_spacing_m: float | None = None
    image_ground_range_extent_m: float | None = None
    image_cross_range_extent_m: float | None = None
    notes: tuple[str, ...] = field(default_factory=tuple)

    # --- display ----------------------------------------------------------------------------
    def _speed_text(self) -> str:
        if self.platform_speed_m_s is None:
            return "— (the files carry no pulse times)"
        return f"{self.platform_speed_m_s:.4g} m/s"

    def summary(self) -> str:
        """A few lines: what the data are (band, pass, polarisation), the aperture, the resolutions
        and unambiguous extents, the image grid beside them, and the notes."""
        tags = ", ".join(t for t in (f"pass {self.pass_name}" if self.pass_name else "", self.polarisation or "") if t)
        deg = np.degrees
        lines = [
            f"data: {self.pulses} pulses × {self.frequency_samples} frequency samples from {len(self.files)} file(s)"
            f"{f' ({tags})' if tags else ''}: centre {self.centre_frequency_hz / 1e9:.4f} GHz, bandwidth "
            f"{self.bandwidth_hz / 1e6:.4g} MHz (step {self.frequency_step_hz / 1e6:.4g} MHz), wavelength "
            f"{self.wavelength_m * 100:.4g} cm",
            f"aperture: Δθ {deg(self.aperture_angle_rad):.4g}° (between the first and last look directions from "
            f"the scene centre), δθ {deg(self.angle_step_rad):.3g}° per pulse, length {self.aperture_length_m:.4g} m, "
            f"mean slant range {self.mean_slant_range_m:.5g} m, grazing {deg(self.grazing_angle_rad):.4g}°, "
            f"mean speed {self._speed_text()}",
            f"resolution (closed form): slant range c/(2B) {self.slant_range_resolution_m:.4g} m, ground range "
            f"c/(2B cos ψ) {self.ground_range_resolution_m:.4g} m, cross range λ/(2Δθ) "
            f"{self.cross_range_resolution_m:.4g} m; unambiguous extent: range c/(2Δf) "
            f"{self.unambiguous_slant_range_m:.4g} m slant ({self.unambiguous_ground_range_m:.4g} m ground), "
            f"cross range λ/(2δθ) {self.unambiguous_cross_range_m:.4g} m"]
        if self.pixel_spacing_m is not None:
            lines.append(f"image grid: pixel spacing {self.pixel_spacing_m:.4g} m (resolution "
                         f"{self.ground_range_resolution_m:.4g} m ground range, {self.cross_range_resolution_m:.4g} m "
                         f"cross range); extent {self.image_ground_range_extent_m:.4g} m × "
                         f"{self.image_cross_range_extent_m:.4g} m (unambiguous {self.unambiguous_ground_range_m:.4g} m "
                         f"× {self.unambiguous_cross_range_m:.4g} m)")
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)

    def to_dict(self) -> dict:
        """JSON-ready, SI with the unit in each name; ``methods`` says how the aperture is measured."""
        out = asdict(self)
        out["files"] = list(self.files)
        out["notes"] = list(self.notes)
        out["methods"] = dict(METHODS)
        out["platform_speed_source"] = ("aperture length / (last − first pulse time)" if self.platform_speed_m_s
                                        is not None else "none: the files carry no pulse times")
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per quantity: SI ``value`` and ``unit``, and ``shown`` in display units (GHz,
        MHz, cm, deg); text rows (files, pass, polarisation) have no value."""
        deg = float(np.degrees(1.0))
        rows = [("files", np.nan, "", ", ".join(self.files)),
                ("pass", np.nan, "", self.pass_name or "— (not in the file names)"),
                ("polarisation", np.nan, "", self.polarisation or "— (not in the file names)"),
                ("pulses", float(self.pulses), "", f"{self.pulses}"),
                ("frequency samples", float(self.frequency_samples), "", f"{self.frequency_samples}"),
                ("centre frequency", self.centre_frequency_hz, "Hz", f"{self.centre_frequency_hz / 1e9:.4f} GHz"),
                ("bandwidth B", self.bandwidth_hz, "Hz", f"{self.bandwidth_hz / 1e6:.4g} MHz"),
                ("frequency step Δf", self.frequency_step_hz, "Hz", f"{self.frequency_step_hz / 1e6:.4g} MHz"),
                ("wavelength λ", self.wavelength_m, "m", f"{self.wavelength_m * 100:.4g} cm"),
                ("aperture angle Δθ (first to last look direction)", self.aperture_angle_rad, "rad",
                 f"{self.aperture_angle_rad * deg:.4g}°"),
                ("angle step δθ", self.angle_step_rad, "rad", f"{self.angle_step_rad * deg:.3g}°"),
                ("aperture length", self.aperture_length_m, "m", f"{self.aperture_length_m:.4g} m"),
                ("mean platform speed", np.nan if self.platform_speed_m_s is None else self.platform_speed_m_s,
                 "m/s", self._speed_text()),
                ("mean slant range", self.mean_slant_range_m, "m", f"{self.mean_slant_range_m:.5g} m"),
                ("grazing angle ψ", self.grazing_angle_rad, "rad", f"{self.grazing_angle_rad * deg:.4g}°"),
                ("slant-range resolution c/(2B)", self.slant_range_resolution_m, "m",
                 f"{self.slant_range_resolution_m:.4g} m"),
                ("ground-range resolution c/(2B cos ψ)", self.ground_range_resolution_m, "m",
                 f"{self.ground_range_resolution_m:.4g} m"),
                ("cross-range resolution λ/(2Δθ)", self.cross_range_resolution_m, "m",
                 f"{self.cross_range_resolution_m:.4g} m"),
                ("unambiguous slant range c/(2Δf)", self.unambiguous_slant_range_m, "m",
                 f"{self.unambiguous_slant_range_m:.4g} m"),
                ("unambiguous ground range c/(2Δf cos ψ)", self.unambiguous_ground_range_m, "m",
                 f"{self.unambiguous_ground_range_m:.4g} m"),
                ("unambiguous cross range λ/(2δθ)", self.unambiguous_cross_range_m, "m",
                 f"{self.unambiguous_cross_range_m:.4g} m")]
        for name, v in (("pixel spacing", self.pixel_spacing_m),
                        ("image ground-range extent", self.image_ground_range_extent_m),
                        ("image cross-range extent", self.image_cross_range_extent_m)):
            if v is not None:
                rows.append((name, v, "m", f"{v:.4g} m"))
        return pd.DataFrame(rows, columns=["quantity", "value", "unit", "shown"])


def describe_acquisition(ph: PhaseHistory, grid=None) -> Acquisition:
    """:class:`Acquisition` of ``ph`` (module docstring); with ``grid`` (a
    :class:`~budget.sar.focus.GroundGrid`) also its pixel spacing and extent and the notes on them."""
    f = ph.frequency_hz
    f_c = 0.5 * float(f[0] + f[-1])
    lam = C_M_S / f_c
    b, df = ph.bandwidth_hz, ph.frequency_step_hz
    a = ph.antenna_m
    look = a / np.linalg.norm(a, axis=1)[:, None]
    d_theta = float(_angle(look[0], look[-1]))
    step = _angle(look[:-1], look[1:])
    d_step = float(np.median(step))
    length = float(np.linalg.norm(np.diff(a, axis=0), axis=1).sum())
    elevation = np.arctan2(a[:, 2], np.hypot(a[:, 0], a[:, 1]))
    psi = float(elevation.mean())
    speed = None
    if ph.pulse_time_s is not None:
        speed = length / float(ph.pulse_time_s[-1] - ph.pulse_time_s[0])
    cos_psi = np.cos(psi)
    notes = []
    inf = float("inf")
    rho_g = C_M_S / (2.0 * b * cos_psi) if cos_psi > 0 else inf
    rho_x = lam / (2.0 * d_theta) if d_theta > 0 else inf
    amb_g = C_M_S / (2.0 * df * cos_psi) if cos_psi > 0 else inf
    amb_x = lam / (2.0 * d_step) if d_step > 0 else inf
    spacing = ext_u = ext_v = None
    if grid is not None:
        spacing = float(grid.spacing_m)
        ext_u = float(grid.u_m[-1] - grid.u_m[0])
        ext_v = float(grid.v_m[-1] - grid.v_m[0])
        for axis, rho in (("ground-range", rho_g), ("cross-range", rho_x)):
            if spacing > rho / UNDERSAMPLED_FRACTION:
                notes.append(f"pixel spacing {spacing:.4g} m exceeds the {axis} resolution {rho:.4g} m: the image "
                             "grid undersamples the impulse response (peaks, widths and sharpness read from it are "
                             "approximate)")
        for axis, ext, amb in (("ground-range", ext_u, amb_g), ("cross-range", ext_v, amb_x)):
            if ext > amb:
                notes.append(f"image {axis} extent {ext:.4g} m exceeds the unambiguous {axis} extent {amb:.4g} m: "
                             "scatterers beyond it fold into the image")
    tags = ph.name_tags or {}
    return Acquisition(
        files=tuple(str(s) for s in dict.fromkeys(ph.pulse_source.tolist())),
        pass_name=tags.get("pass"), polarisation=tags.get("polarisation"),
        pulses=ph.n_pulses, frequency_samples=ph.n_frequencies, centre_frequency_hz=f_c, bandwidth_hz=float(b),
        frequency_step_hz=float(df), wavelength_m=lam, aperture_angle_rad=d_theta, angle_step_rad=d_step,
        aperture_length_m=length, platform_speed_m_s=speed, mean_slant_range_m=float(ph.scene_range_m.mean()),
        grazing_angle_rad=psi, slant_range_resolution_m=C_M_S / (2.0 * b), ground_range_resolution_m=rho_g,
        cross_range_resolution_m=rho_x, unambiguous_slant_range_m=C_M_S / (2.0 * df),
        unambiguous_ground_range_m=amb_g, unambiguous_cross_range_m=amb_x, pixel_spacing_m=spacing,
        image_ground_range_extent_m=ext_u, image_cross_range_extent_m=ext_v, notes=tuple(notes))
