"""What the Monte Carlo trials of one setup share, computed once per process (:class:`ChainPlan`).

The chain (:mod:`budget.mc.chain`) forms, measures and autofocuses the trials of a formation
batch together; the plan holds what does not depend on the trial: the batched image former and
the range spectra of the echoes (range-Doppler method), the image grid, its aperture mask, the
target meter — and the clean image of a perfect IMU, which the scene's perfect-IMU reference and
every trial's twin (:func:`budget.mc.chain.run_trials`) share: with no motion error the clean,
noise-free image does not depend on the trial, so it is formed and measured once
(:meth:`ChainPlan.still`). Every number is the one the trial would compute for itself.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from ..rng import trial_generator
from ..sar import SarImage, form_image
from ..sar.image import RdaImageFormer, default_bp_grid
from ..sar.metrics import TargetMetricArrays, TargetMeter
from .noise_kernels import add_band_noise
from .receiver_noise import receiver_noise_draws, receiver_noise_echoes, receiver_noise_scale


@dataclass(frozen=True)
class CleanProducts:
    """What the chain derives from the clean images (B of them) before PGA: the phase histories
    (B, n_a, n_r; the azimuth inverse DFT of the images), the signal energy per azimuth bin
    (B, n_a; centred bins, Σ_r |G|²) and the target metrics (:class:`TargetMetricArrays`)."""

    hist: np.ndarray
    energy: np.ndarray
    metrics: TargetMetricArrays


class ChainPlan:
    """What the trials of one setup share beyond the echoes, computed once per process: the
    batched image former and the range spectra of the echoes (range-Doppler method), the image
    grid (a data-free :class:`~budget.sar.SarImage`), its aperture mask, and the target meter
    (azimuth search half-width ``azimuth_search_cells``, resolution cells)."""

    def __init__(self, setup, azimuth_search_cells: float):
        g, opt = setup.geom, setup.options
        self.separate = setup.clean_echoes is not setup.echoes
        if opt.image_method == "rda":
            self.former = RdaImageFormer(g)
            self.template = self.former.template
            self.clean_spectrum = self.former.range_spectrum(setup.clean_echoes)
            self.pga_spectrum = self.former.range_spectrum(setup.echoes) if self.separate else self.clean_spectrum
        else:
            self.former = None
            az, rg = default_bp_grid(g)
            self.template = SarImage(data=np.zeros((az.size, rg.size), dtype=complex), azimuth_m=az,
                                     slant_range_m=rg, wavelength_m=g.wavelength_m, speed_m_s=g.speed_m_s,
                                     ref_range_m=g.ref_range_m, aperture_time_s=g.aperture_time_s,
                                     method=opt.image_method)
        self.mask = self.template.aperture_mask()
        self.meter = TargetMeter(g, setup.clean_scene, self.template.azimuth_m, self.template.slant_range_m,
                                 azimuth_search_cells=azimuth_search_cells)
        self._still = None

    def noise_scale(self, setup) -> np.ndarray:
        """:func:`receiver_noise_scale` of the setup's SNR, computed once."""
        if getattr(self, "_noise_scale", None) is None:
            self._noise_scale = receiver_noise_scale(setup.geom, setup.snr_db)
        return self._noise_scale

    def form(self, setup, measured: np.ndarray, trials: range, seed: int, stream: int,
             clean: bool = True) -> tuple[np.ndarray | None, np.ndarray | None]:
        """(clean images, PGA images), each (B, n_a, n_r), of the trials ``trials`` imaged with the
        measured offsets (B, n_pulses, 3); the PGA images carry each trial's receiver noise (from
        ``trial_generator(seed, trial, stream)``). The same array twice when PGA sees the clean
        image; ``clean=False`` (range-Doppler only): the clean images are not formed (None), and
        the PGA images are None when they would be the clean ones."""
        g, opt = setup.geom, setup.options
        noise = [] if setup.snr_db is None else [trial_generator(seed, t, stream) for t in trials]
        same = setup.snr_db is None and not self.separate
        if self.former is not None:
            if same:
                images = self.former.form(self.clean_spectrum, measured) if clean else None
                return images, images
            spec = self.pga_spectrum
            if noise:  # image formation is linear: the echoes' spectrum plus each trial's noise
                spec = np.empty((len(noise),) + self.pga_spectrum.shape, dtype=complex)
                scale, band = self.noise_scale(setup), g.range_band_index
                for b, r in enumerate(noise):
                    add_band_noise(spec[b], self.pga_spectrum, receiver_noise_draws(g, r), scale, band)
            if not clean:
                return None, self.former.form(spec, measured)
            # both images along the same measured tracks: their motion-compensation phases once
            both = self.former.form_groups([self.clean_spectrum, spec], measured)
            return both[0], both[1]
        images = np.stack([form_image(g, setup.clean_echoes, m, method=opt.image_method).data for m in measured])
        if same:
            return images, images
        data = ([setup.echoes + receiver_noise_echoes(g, setup.snr_db, r) for r in noise]
                or [setup.echoes] * len(measured))
        return images, np.stack([form_image(g, d, m, method=opt.image_method).data for d, m in zip(data, measured)])

    def clean_products(self, clean: np.ndarray) -> CleanProducts:
        """:class:`CleanProducts` of the clean images ``clean`` (B, n_a, n_r)."""
        hist = sfft.ifft(clean, axis=1)  # phase histories (centred bins after fftshift)
        power = np.abs(hist)
        power *= power  # |G|², as ** 2 squares, without a second image-sized temporary
        energy = np.fft.fftshift(power.sum(axis=2), axes=1)
        return CleanProducts(hist=hist, energy=energy, metrics=self.meter.measure(clean))

    def still(self, setup, n: int) -> tuple[np.ndarray, CleanProducts]:
        """(clean images, :class:`CleanProducts`) of ``n`` trials with no motion error (measured
        offsets all −0.0, as the chain negates zero errors), range-Doppler only: formed and
        measured once per plan, then repeated (the images a read-only broadcast view, the phase
        histories a copy of their own, since the chain corrects them in place)."""
        if self._still is None:
            measured = -np.zeros((1, setup.geom.n_pulses, 3))
            image = self.former.form(self.clean_spectrum, measured)
            self._still = (image, self.clean_products(image))
        image, prod = self._still
        rep = {k: np.repeat(v, n, axis=0) for k, v in prod.metrics.values.items()}
        return (np.broadcast_to(image, (n,) + image.shape[1:]),
                CleanProducts(hist=np.repeat(prod.hist, n, axis=0), energy=np.repeat(prod.energy, n, axis=0),
                              metrics=TargetMetricArrays(values=rep, meter=self.meter)))
