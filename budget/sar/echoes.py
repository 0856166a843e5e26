"""Range-compressed echoes from the TRUE antenna trajectory (stop-and-go, exact ranges).

For pulse n the APC is at p_n = p_nom(t_n) + δp_true,n and target k at P_k returns, after
range compression with window W over the M in-band frequencies f_m,

    D_n(f_m) = Σ_k a_k W(f_m) exp(−j 4π (f0 + f_m) |p_n − P_k| / c) · exp(+j 4π f_m r_0 / c),

(r_0: first range bin), transformed to range with the inverse DFT and scaled so that an
isolated unit target peaks at 1. The range history of each target is exact at every pulse, so an
APC error larger than a range cell moves the echo through range cells.

Clutter: ``clutter_density_per_cell`` complex Gaussian scatterers per resolution cell at random
positions over the whole imaged area (image azimuth extent × swath), gridded on a range grid 16× finer than a range bin before the DFT (the
carrier phase stays exact; the envelope is placed within ±1/32 bin). Noise: complex white
Gaussian receiver noise through the same range window.
"""

from __future__ import annotations

import numpy as np
import scipy.fft as sfft

from ..errors import InputError
from ..units import range_to_phase, two_way_wavenumber_at_frequency_rad_m, two_way_wavenumber_rad_m
from .geometry import SarGeometry
from .scene import Scene
from .windows import ideal_irf

_GRID_UPSAMPLE = 16
#: Largest (pulses × bins × targets) envelope of the point targets formed at once (complex:
#: 16 bytes each, 256 MB); more targets are summed in groups, with the same products.
ENVELOPE_ELEMENTS = 1 << 24
#: Most clutter phase evaluations (pulses × clutter points) a scene may ask for: about a minute and
#: a half at the ≈ 10⁷ per second this loop reaches, 40× the presets' largest (2.5·10⁷).
MAX_CLUTTER_EVALUATIONS = 1_000_000_000


def _check_rng(rng, scene: Scene) -> np.random.Generator | None:
    needs = scene.snr_db is not None or scene.clutter_to_target_db is not None
    if rng is None and needs:
        raise InputError("a random generator is required for noise or clutter", field="rng",
                         expected="numpy.random.Generator")
    if rng is not None and not isinstance(rng, np.random.Generator):
        raise InputError("rng must be a numpy Generator", field="rng", value=type(rng).__name__,
                         expected="numpy.random.Generator")
    return rng


def simulate_echoes(geom: SarGeometry, scene: Scene, true_offset_m=None,
                    rng: np.random.Generator | None = None) -> np.ndarray:
    """Range-compressed complex data (n_pulses, n_range) of ``scene`` seen from the true APC.

    ``true_offset_m``: APC offsets from the nominal track, (n_pulses, 3) m, or None (ideal).
    """
    if not isinstance(scene, Scene):
        raise InputError("expected a Scene", field="scene", value=type(scene).__name__)
    if scene.is_empty():
        raise InputError("the scene has no targets and no clutter", field="targets",
                         expected="at least one target, or clutter_to_target_db")
    scene.check_inside(geom)
    rng = _check_rng(rng, scene)
    apc = geom.nominal_apc_m() + geom.check_offset(true_offset_m, "true_offset_m")
    f_m = geom.range_band_freqs_hz
    r0 = float(geom.range_axis_m[0])
    k_f = two_way_wavenumber_at_frequency_rad_m(f_m, geom.c_m_s)
    spec = np.zeros((geom.n_pulses, geom.band_bins), dtype=complex)
    if scene.targets:
        x, r, a = scene.target_arrays()
        pts = geom.scene_point_m(x, geom.ref_range_m + r)
        rng_nk = np.linalg.norm(apc[:, None, :] - pts[None, :, :], axis=-1)
        carrier = a[None, :] * np.exp(1j * range_to_phase(rng_nk, geom.wavelength_m))
        # targets in groups, so the (pulses, bins, targets) envelope stays below ENVELOPE_ELEMENTS
        group = max(1, ENVELOPE_ELEMENTS // (geom.n_pulses * geom.band_bins))
        for k0 in range(0, rng_nk.shape[1], group):
            rk = rng_nk[:, k0:k0 + group]
            # exp(−j 4π f_m (R − r0)/c) with f_m = m Δf on symmetric m: powers of one phasor
            # (cumulative product: one complex exponential per target and pulse instead of M)
            step = np.exp(-1j * (k_f[1] - k_f[0]) * (rk - r0))
            env = np.empty((geom.n_pulses, geom.band_bins, rk.shape[1]), dtype=complex)
            env[:, 0] = np.exp(-1j * k_f[0] * (rk - r0))
            env[:, 1:] = step[:, None, :]
            np.cumprod(env, axis=1, out=env)
            spec += np.einsum("nmk,nk->nm", env, carrier[:, k0:k0 + group])
    if scene.clutter_to_target_db is not None:
        spec += _clutter_spectrum(geom, scene, apc, rng)
    w_r = geom.window_range.samples(geom.band_bins)
    spec *= w_r[None, :]
    if scene.snr_db is not None:
        w_a = geom.window_azimuth.samples(geom.n_pulses)
        var_rc = (w_a.sum() ** 2 / (w_a ** 2).sum()) / 10.0 ** (scene.snr_db / 10.0)
        s2 = var_rc * w_r.sum() ** 2 / (w_r ** 2).sum()
        noise = rng.standard_normal((geom.n_pulses, geom.band_bins, 2)) @ np.array([1.0, 1j])
        spec += np.sqrt(s2 / 2.0) * noise * w_r[None, :]
    full = np.zeros((geom.n_pulses, geom.n_range), dtype=complex)
    full[:, geom.range_band_index] = spec
    return sfft.ifft(full, axis=1) * (geom.n_range / w_r.sum())


def _clutter_spectrum(geom: SarGeometry, scene: Scene, apc: np.ndarray,
                      rng: np.random.Generator) -> np.ndarray:
    """In-band range spectrum (n_pulses, M) of random clutter, unwindowed."""
    cell_a, cell_r = geom.azimuth_cell_m(), geom.range_cell_m
    # the whole imaged area: image azimuth extent × swath less the pulse-tail margins
    x_s = geom.n_azimuth * geom.speed_m_s / geom.prf_hz - 2.0 * cell_a
    r_lo, r_hi = geom.range_axis_m[12], geom.range_axis_m[-13]
    y_s = r_hi - r_lo
    n_q = int(np.ceil(scene.clutter_density_per_cell * x_s * y_s / (cell_a * cell_r)))
    if n_q * geom.n_pulses > MAX_CLUTTER_EVALUATIONS:
        work = n_q * geom.n_pulses
        raise InputError(f"the clutter of this scene needs {geom.n_pulses} pulses × {n_q / 1e6:.3g} M clutter "
                         f"points = {work:.2g} phase evaluations (≈ {work / 1e7 / 60:.0f} min to simulate)",
                         field="scene", value="clutter",
                         expected=f"≤ {MAX_CLUTTER_EVALUATIONS:.0e} (the points scene: scene='points', "
                                  "--scene points; a smaller image: coarser resolution or a shorter aperture; "
                                  "or, calling the simulator with a Scene of your own, a lower "
                                  "clutter_density_per_cell — the Monte Carlo's realistic scene fixes it)")
    xq = rng.uniform(-0.5 * x_s, 0.5 * x_s, n_q)
    rq = rng.uniform(r_lo, r_hi, n_q)
    # mean pixel power = density · σ² · ∫∫|h|² dA  (h: ideal IRF with unit peak)
    a_irf = (cell_a * ideal_irf(geom.window_azimuth).noise_bandwidth
             * cell_r * ideal_irf(geom.window_range).noise_bandwidth)
    density = n_q / (x_s * y_s)
    sigma2 = 10.0 ** (scene.clutter_to_target_db / 10.0) * scene.reference_power() / (density * a_irf)
    amp = np.sqrt(sigma2 / 2.0) * (rng.standard_normal(n_q) + 1j * rng.standard_normal(n_q))
    pts = geom.scene_point_m(xq, rq)
    n_fine = geom.n_range * _GRID_UPSAMPLE
    step = geom.range_bin_m / _GRID_UPSAMPLE
    out = np.empty((geom.n_pulses, geom.band_bins), dtype=complex)
    band = np.mod(np.arange(geom.band_bins) - (geom.band_bins - 1) // 2, n_fine)
    chunk = max(1, 4_000_000 // max(n_q, 1))
    r0 = float(geom.range_axis_m[0])
    for s in range(0, geom.n_pulses, chunk):
        p = apc[s:s + chunk]
        rng_nq = np.sqrt((p[:, 0, None] - pts[None, :, 0]) ** 2 + (p[:, 1, None] - pts[None, :, 1]) ** 2
                         + (p[:, 2, None] - pts[None, :, 2]) ** 2)
        ph = -two_way_wavenumber_rad_m(geom.wavelength_m) * rng_nq  # range_to_phase as one product
        b = amp[None, :] * (np.cos(ph) + 1j * np.sin(ph))
        idx = np.rint((rng_nq - r0) / step).astype(np.int64)
        ok = (idx >= 0) & (idx < n_fine)
        flat = (np.arange(p.shape[0])[:, None] * n_fine + idx)[ok]
        size = p.shape[0] * n_fine
        grid = (np.bincount(flat, b.real[ok], minlength=size)
                + 1j * np.bincount(flat, b.imag[ok], minlength=size)).reshape(p.shape[0], n_fine)
        out[s:s + chunk] = sfft.fft(grid, axis=1)[:, band]
    return out
