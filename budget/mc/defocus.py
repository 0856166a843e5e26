"""How much room in azimuth the simulated image needs for the defocus a part's errors cause.

A motion error whose line-of-sight range Δr(t) changes at a rate dΔr/dt adds a Doppler shift
f_D(t) = (2/λ)·dΔr/dt to every scatterer (the two-way phase 4πΔr/λ, seed 004). Azimuth position
and Doppler map one to one in the image, x = f_D·λR/(2V), and one azimuth resolution cell
δℓ = λR/(2V·Tc) is a Doppler of 1/Tc (seed 004 (5) with a_w = 1), so the energy of a point
moves up to

    e = Tc · max_t |f_D(t)|   azimuth cells                                          (1)

from where it belongs: a constant line-of-sight acceleration a over the aperture, Δr = a·t²/2
from the aperture start, gives e = 2·a·Tc²/λ.

PGA can only estimate the phase of energy that is in the image. The range-Doppler image spans
the aperture V·Tc or, when that is shorter, the scene plus a margin on each side
(:attr:`budget.sar.SarGeometry.n_azimuth`; :data:`budget.sar.geometry.IMAGE_MARGIN_CELLS`),
and its PRF holds the scene's Doppler band with 25 % to spare: simulation choices the user never
makes. When a draw's
excursion outgrows the room beyond the scene, the defocused response of the scene's outer
points leaves the image (or wraps in Doppler) and PGA fails on the simulation, not on the IMU.
Measured on ``automotive_77ghz`` (accelerometer bias at 0.5× its paper bound, lever arm 0, 32
trials, seed 1): the aperture spans 97 cells, so the image holds 28 cells beyond the points
scene's outer targets (20 cells from its centre); every trial with e ≥ 28 failed (13 of 32) and
every one with e ≤ 23 passed. Doubling the scene's width pads the image to ≈ 44 cells of room
beyond the same targets, and the first failure moved to e = 42 (6 of 32); at four times the
width all 32 passed; a PRF 4× higher changed nothing.

:func:`defocus_room` sizes the room from a pilot of the motion engine: :data:`ROOM_PER_EXCURSION`
× the :data:`PILOT_QUANTILE` th percentile of e over :data:`PILOT_TRIALS` draws of the part's
errors, at most :data:`MAX_ROOM_CELLS` and within the simulator's pulse and pixel limits
(:attr:`budget.sar.SarGeometry.defocus_room_cells`: the image is padded and the PRF raised only
where the default sampling holds less). The scene and its points stay as they were, and a part
whose excursion fits the default sampling is simulated exactly as without the room. The pilot's
draws are fixed (:data:`PILOT_SEED`), so the image depends on the scenario, the options and the
part, never on the run's seed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..motion import simulate_motion
from ..sar import SarGeometry
from ..sar.geometry import MAX_PIXELS

#: Room per cell of excursion (1): the failures above began where e reached the room beyond the
#: outer targets (28 of 28, 42 of ≈ 44 cells); 1.5 leaves a margin.
ROOM_PER_EXCURSION = 1.5
#: Most room the automatic choice gives, cells each side (a part whose errors need more fails on
#: range migration or on the image anyway).
MAX_ROOM_CELLS = 128.0
#: Draws of the pilot and the percentile of their excursions the room is sized for.
PILOT_TRIALS = 64
PILOT_QUANTILE = 99.0
#: Seed of the pilot's draws (its own, so that the image does not follow the run's seed).
PILOT_SEED = 20_261_206


def excursion_cells(range_error_m: np.ndarray, time_s: np.ndarray, wavelength_m: float,
                    tc_s: float) -> np.ndarray:
    """(1): largest azimuth excursion, in resolution cells, of each row of ``range_error_m``
    ((T, N) line-of-sight range error, m, on the times ``time_s``, s)."""
    r = np.asarray(range_error_m, dtype=float)
    t = np.asarray(time_s, dtype=float)
    if r.ndim != 2 or t.ndim != 1 or r.shape[1] != t.size or t.size < 2:
        raise InputError("range error and time do not match", field="range_error_m",
                         value=f"{r.shape} against {t.shape}", expected="(trials, N) and (N,) with N ≥ 2")
    doppler_hz = 2.0 / wavelength_m * np.gradient(r, t, axis=1)
    return tc_s * np.max(np.abs(doppler_hz), axis=1)


def room_for(excursion: float) -> tuple[float, bool]:
    """(cells, capped): the room each side that holds an excursion of ``excursion`` cells, in
    whole multiples of 4 cells, at most :data:`MAX_ROOM_CELLS`."""
    need = ROOM_PER_EXCURSION * float(excursion)
    if not math.isfinite(need):
        return MAX_ROOM_CELLS, True
    cells = 4.0 * math.ceil(max(need, 0.0) / 4.0)
    return min(cells, MAX_ROOM_CELLS), cells > MAX_ROOM_CELLS


@dataclass(frozen=True)
class RoomChoice:
    """The defocus room of the simulated image for one part: ``cells`` each side
    (:attr:`budget.sar.SarGeometry.defocus_room_cells`), ``excursion_cells`` the pilot's
    :data:`PILOT_QUANTILE` th percentile of (1), ``capped`` when the room the excursion asks
    for is beyond what the simulation builds, ``n_pulses`` and ``n_azimuth`` the sampling it
    gives, ``widened`` whether that differs from the sampling without it."""

    cells: float
    excursion_cells: float
    capped: bool
    n_pulses: int
    n_azimuth: int
    widened: bool

    def note(self) -> str:
        """What the verdict's image held and why (said in every result)."""
        pilot = f"{PILOT_QUANTILE:g}th percentile of {PILOT_TRIALS} pilot draws"
        size = f"{self.n_pulses} pulses, {self.n_azimuth} azimuth samples"
        if self.capped:
            return (f"simulated image sized for {self.cells:g} cells of defocus beyond the scene ({size}), "
                    f"the most the simulation builds: the part's errors move a point's energy by up to "
                    f"{self.excursion_cells:.0f} cells ({pilot}); a trial whose defocus leaves the image "
                    "fails on the simulation's size as much as on the IMU")
        if self.widened:
            return (f"simulated image widened ({size}) to hold the part's defocus: its errors move a "
                    f"point's energy by up to {self.excursion_cells:.0f} azimuth cells ({pilot})")
        return (f"the part's errors move a point's energy by up to {self.excursion_cells:.1f} azimuth "
                f"cells ({pilot}), within the simulated image")

    def to_dict(self) -> dict:
        return {"defocus_room_cells": self.cells, "excursion_cells_p99": self.excursion_cells,
                "capped": self.capped, "n_pulses": self.n_pulses, "n_azimuth": self.n_azimuth,
                "widened": self.widened, "note": self.note()}


def defocus_room(scenario, model, *, disturbance=None, window=None) -> RoomChoice:
    """The defocus room for ``model`` (a resolved noise model or part, as the chain simulates
    it) on ``scenario``, from a pilot of the motion engine with the scenario's aiding and the
    ``disturbance`` flown (module docstring). The IMU pre-filter is left out: it only lowers the
    errors, so the pilot errs towards more room. Room the simulator cannot form (its pulse
    limit, or :data:`budget.sar.geometry.MAX_PIXELS` for the image; ``window`` as the chain
    weights) is cut by 16 cells at a time until it can, and the choice is then ``capped``."""
    plain = SarGeometry.from_scenario(scenario, window=window)  # a scenario it cannot form says so first
    # the engine's notes (an aperture cut to whole IMU intervals …) are the run's: the Monte Carlo
    # states them once (budget.mc.runner.run_mc), not once for the pilot and again for the trials
    pilot = simulate_motion(scenario, model, PILOT_TRIALS, PILOT_SEED, keep_series=True,
                            disturbance=disturbance, warn_notes=False)
    e = excursion_cells(pilot.range_error_m[:, 0, :], pilot.time_s, scenario.wavelength_m,
                        scenario.tc_s)
    worst = float(np.percentile(e, PILOT_QUANTILE))
    cells, capped = room_for(worst)
    while True:
        try:
            geom = SarGeometry.from_scenario(scenario, window=window, defocus_room_cells=cells)
            if cells == 0.0 or geom.n_azimuth * geom.n_range <= MAX_PIXELS:
                break
        except InputError:
            pass
        cells, capped = max(0.0, cells - 16.0), True
    widened = (geom.n_pulses, geom.n_azimuth) != (plain.n_pulses, plain.n_azimuth)
    return RoomChoice(cells, worst, capped, int(geom.n_pulses), int(geom.n_azimuth), widened)
