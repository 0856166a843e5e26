"""Scenes: point targets, optional clutter and receiver noise.

Target coordinates are image coordinates: ``azimuth_m`` is the along-track position x (the
target is at broadside when the nominal APC passes x) and ``range_m`` the offset of its
closest-approach slant range from the scene-centre range R_c. Targets lie on the ground plane.

Levels are image-domain ratios, so they do not depend on the number of pulses:
* ``snr_db``: peak power of a unit-amplitude target in the ideal image over the mean noise power
  of an image pixel;
* ``clutter_to_target_db``: mean clutter power of an image pixel over the peak power of the
  strongest target (of a unit-amplitude target when there is none). Clutter covers the whole
  imaged area, not only the target area (a clutter-only scene is then uniformly speckled).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from ..errors import InputError, from_validation_error


class PointTarget(BaseModel):
    """A point scatterer: position (m, image coordinates) and complex amplitude."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    azimuth_m: float = Field(..., allow_inf_nan=False)
    range_m: float = Field(..., allow_inf_nan=False, description="offset from the scene-centre slant range")
    amplitude: float = Field(1.0, gt=0, allow_inf_nan=False)
    phase_rad: float = Field(0.0, allow_inf_nan=False)

    @property
    def complex_amplitude(self) -> complex:
        return self.amplitude * complex(math.cos(self.phase_rad), math.sin(self.phase_rad))


class Scene(BaseModel):
    """Point targets plus optional clutter (complex Gaussian) and receiver noise."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    targets: list[PointTarget] = Field(default_factory=list)
    clutter_to_target_db: float | None = Field(None, ge=-80, le=40, allow_inf_nan=False)
    snr_db: float | None = Field(None, ge=-20, le=150, allow_inf_nan=False)
    clutter_density_per_cell: float = Field(2.0, gt=0, le=16, allow_inf_nan=False,
                                            description="clutter scatterers per resolution cell")

    @classmethod
    def build(cls, **kwargs) -> "Scene":
        """Validated construction that raises :class:`InputError` (names the field)."""
        try:
            return cls(**kwargs)
        except ValidationError as err:
            raise from_validation_error(err) from None

    @classmethod
    def default(cls, geom, *, snr_db: float | None = 50.0) -> "Scene":
        """Five strong targets on a diagonal pattern, 10 cells apart in range and in azimuth.

        Distinct range lines and azimuth positions keep each target's cuts clear of the others
        (their sidelobes there are ≤ −30 dB unweighted), which PGA and the metrics rely on.
        """
        da, dr = geom.azimuth_resolution_m, geom.range_resolution_m
        half = 0.5 * min(geom.scene_extent_m[0] / da, geom.scene_extent_m[1] / dr)
        step = min(10.0, (half - 2.0) / 2.0)
        cells = [(-2, -2, 1.0, 0.3), (1, -1, 0.8, 1.9), (0, 0, 1.0, 0.0), (-1, 1, 0.9, -1.2), (2, 2, 0.85, 2.6)]
        targets = [PointTarget(azimuth_m=a * step * da, range_m=r * step * dr, amplitude=amp, phase_rad=ph)
                   for a, r, amp, ph in cells]
        return cls(targets=targets, snr_db=snr_db)

    @classmethod
    def realistic(cls, geom, *, rng: np.random.Generator, clutter_to_target_db: float | None = -25.0,
                  snr_db: float | None = 30.0, n_scatterers: int | None = None,
                  amplitude_spread_db: float = 15.0, separation_cells: float = 2.0) -> "Scene":
        """Many dominant scatterers over distributed clutter and receiver noise: what PGA meets.

        ``n_scatterers`` (default one per 3 range resolution cells of the scene, 16 on a 48-cell
        scene) point targets on distinct range positions ``separation_cells`` resolution cells
        apart (so each range line holds at most one), at uniform random azimuth inside the scene,
        uniform random phase, amplitudes log-uniform over ``amplitude_spread_db`` below the
        strongest, which has amplitude 1 (the reference of ``clutter_to_target_db`` and
        ``snr_db``, module docstring). Same ``rng`` state → same scene.
        """
        if not isinstance(rng, np.random.Generator):
            raise InputError("rng must be a numpy Generator", field="rng", value=type(rng).__name__,
                             expected="numpy.random.Generator")
        if not (0.0 <= amplitude_spread_db <= 60.0) or not (1.0 <= separation_cells <= 64.0):
            raise InputError("invalid scatterer spread or separation", field="amplitude_spread_db/separation_cells",
                             value=(amplitude_spread_db, separation_cells),
                             expected="0 ≤ amplitude_spread_db ≤ 60, 1 ≤ separation_cells ≤ 64")
        da, dr = geom.azimuth_resolution_m, geom.range_resolution_m
        x_half, y_half = 0.5 * geom.scene_extent_m[0] - 2.0 * da, 0.5 * geom.scene_extent_m[1] - 2.0 * dr
        slots = np.arange(-y_half, y_half + 1e-9, separation_cells * dr)
        n = int(round(geom.scene_extent_m[1] / dr / 3.0)) if n_scatterers is None else int(n_scatterers)
        if not 1 <= n <= slots.size:
            raise InputError("too many scatterers for the scene's range positions", field="n_scatterers",
                             value=n, expected=f"1 … {slots.size} (one per {separation_cells:g} range cells; "
                             "raise scene_extent_cells or lower separation_cells)")
        rng_m = np.sort(rng.choice(slots, n, replace=False))
        az_m = rng.uniform(-x_half, x_half, n)
        amp = 10.0 ** (-rng.uniform(0.0, amplitude_spread_db, n) / 20.0)
        amp[np.argmax(amp)] = 1.0
        ph = rng.uniform(-math.pi, math.pi, n)
        targets = [PointTarget(azimuth_m=float(a), range_m=float(r), amplitude=float(m), phase_rad=float(p))
                   for a, r, m, p in zip(az_m, rng_m, amp, ph)]
        return cls.build(targets=targets, clutter_to_target_db=clutter_to_target_db, snr_db=snr_db)

    def without_clutter(self) -> "Scene":
        """The same targets without clutter and without receiver noise (for point-target metrics
        measured on an image focused with an estimate taken from the cluttered one)."""
        return self.model_copy(update={"clutter_to_target_db": None, "snr_db": None})

    def is_empty(self) -> bool:
        return not self.targets and self.clutter_to_target_db is None

    def reference_power(self) -> float:
        """Peak power |a|² of the strongest target (1 without targets)."""
        return max((t.amplitude ** 2 for t in self.targets), default=1.0)

    def summary(self) -> str:
        clutter = "no clutter" if self.clutter_to_target_db is None else f"clutter {self.clutter_to_target_db:g} dB"
        noise = "noise-free" if self.snr_db is None else f"SNR {self.snr_db:g} dB"
        return f"{len(self.targets)} point targets, {clutter}, {noise}"

    def to_dict(self) -> dict:
        """JSON-safe dict: the settings and every target."""
        return self.model_dump()

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame([t.model_dump() for t in self.targets],
                            columns=["azimuth_m", "range_m", "amplitude", "phase_rad"])

    def check_inside(self, geom) -> None:
        """Raise :class:`InputError` if a target lies outside the simulated scene."""
        xa, yr = 0.5 * geom.scene_extent_m[0], 0.5 * geom.scene_extent_m[1]
        for i, t in enumerate(self.targets):
            if abs(t.azimuth_m) > xa + 1e-9 or abs(t.range_m) > yr + 1e-9:
                raise InputError(f"target at azimuth {t.azimuth_m:g} m, range {t.range_m:g} m lies outside "
                                 "the simulated scene", row=i, field="targets",
                                 expected=f"|azimuth_m| ≤ {xa:.4g} m and |range_m| ≤ {yr:.4g} m "
                                 "(raise scene_extent_cells)")

    def target_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(azimuth_m, range_offset_m, complex amplitude) arrays."""
        x = np.array([t.azimuth_m for t in self.targets], dtype=float)
        r = np.array([t.range_m for t in self.targets], dtype=float)
        a = np.array([t.complex_amplitude for t in self.targets], dtype=complex)
        return x, r, a
