"""Phase-error theory reproduced through the whole chain (errors injected as line-of-sight motion).

Independent references: numerical integration of the continuous aperture (quadratic error),
Bessel functions (sinusoidal error: paired echoes J1(a)/J0(a) ≈ a/2) and the coherent/incoherent
split of a white phase error (main-lobe energy × e^{−σ²}, the rest spread as sidelobes).
"""

import math

import numpy as np
import pytest
from scipy.special import j0, j1

from budget.presets import get_preset
from budget.sar import PointTarget, SarGeometry, Scene, form_image, los_offset_for_phase, measure_targets, \
    simulate_echoes
from budget.sar.metrics import irf_cuts
from budget.sar.phase import legendre_decomposition, normalised_time, smooth_phase_error


@pytest.fixture(scope="module")
def setup():
    g = SarGeometry.from_scenario(get_preset("airborne_xband"))
    scene = Scene(targets=[PointTarget(azimuth_m=0.0, range_m=0.0)])
    return g, scene


def _image(g, scene, psi):
    return form_image(g, simulate_echoes(g, scene, los_offset_for_phase(g, psi)))


def _qpe_broadening_reference(q_rad: float) -> tuple[float, float]:
    """3 dB broadening and peak loss (dB) of a continuous unweighted aperture with q (2u)² phase."""
    u = np.linspace(-0.5, 0.5, 4001)
    x = np.linspace(0.0, 2.0, 8001)
    kern = np.exp(2j * np.pi * np.outer(x, u))

    def width(q):
        h = np.abs((kern * np.exp(1j * q * (2 * u) ** 2)).sum(axis=1))
        p = h ** 2 / h[0] ** 2
        return 2 * x[np.argmax(p < 0.5)], h[0] / u.size

    w0, _ = width(0.0)
    wq, peak = width(q_rad)
    return wq / w0 - 1.0, -20 * math.log10(peak)


@pytest.mark.slow
def test_quadratic_phase_error_broadening(setup):
    g, scene = setup
    u = normalised_time(g)
    ref_b, ref_loss = _qpe_broadening_reference(math.pi / 2)
    assert ref_b == pytest.approx(0.062, abs=0.003)  # "about 6 %" for π/2 at the aperture edge
    m = measure_targets(_image(g, scene, smooth_phase_error(u, quadratic_rad=math.pi / 2)), g, scene)[0]
    assert m.azimuth.broadening == pytest.approx(ref_b, abs=0.006)
    assert m.peak_loss_db == pytest.approx(ref_loss, abs=0.1)
    assert abs(m.range.broadening) < 0.005  # a phase error alone does not touch range
    m_pi = measure_targets(_image(g, scene, smooth_phase_error(u, quadratic_rad=math.pi)), g, scene)[0]
    assert m_pi.azimuth.broadening > 5 * m.azimuth.broadening and m_pi.azimuth.broadening > 0.3


@pytest.mark.parametrize("amp", [0.1, 0.3])
def test_sinusoidal_phase_error_paired_echoes(setup, amp):
    g, scene = setup
    cycles = 12
    u = normalised_time(g)
    psi = amp * np.sin(math.pi * cycles * u)  # `cycles` full periods over u ∈ [−1, 1]
    img = _image(g, scene, psi)
    c = irf_cuts(img, g, scene, 0)
    cell = float(c["azimuth_cell_m"])
    x, lev = c["azimuth_offset_m"], c["azimuth_db"]
    order = np.argsort(x)
    x, lev = x[order], lev[order]
    peak = np.interp(0.0, x, lev)
    expected = 20 * math.log10(j1(amp) / j0(amp))
    for side in (-1, 1):
        # read the echo exactly `cycles` cells away, where the unweighted main response has a null
        echo = np.interp(side * cycles * cell, x, lev) - peak
        assert echo == pytest.approx(expected, abs=0.3)
        assert echo == pytest.approx(20 * math.log10(amp / 2), abs=0.35)


def _box_energy(img, g, half_cells=1.0):
    """Energy within ±half_cells resolution cells of the image peak, and the total energy."""
    p = np.abs(img.data) ** 2
    i, j = np.unravel_index(np.argmax(p), p.shape)
    box = (np.abs(img.azimuth_m - img.azimuth_m[i]) <= half_cells * g.azimuth_cell_m())[:, None] & \
        (np.abs(img.slant_range_m - img.slant_range_m[j]) <= half_cells * g.range_cell_m)[None, :]
    return p[box].sum(), p.sum()


@pytest.mark.parametrize("seed", [11, 12])
def test_white_phase_error_moves_sigma_squared_to_the_sidelobes(setup, seed):
    """Coherent part keeps e^{−σ²} of the energy; the rest (≈ σ²) spreads as sidelobes."""
    g, scene = setup
    sigma = 0.2
    psi = np.random.default_rng(seed).normal(0.0, sigma, g.n_pulses)
    ideal, noisy = _image(g, scene, np.zeros(g.n_pulses)), _image(g, scene, psi)
    m0, t0 = _box_energy(ideal, g)
    m1, t1 = _box_energy(noisy, g)
    assert t1 == pytest.approx(t0, rel=0.01)  # image formation conserves energy
    f = m0 / t0  # main-lobe share of this geometry's 2-D response
    rise = (t1 - m1) / m1 - (t0 - m0) / m0  # Δ(sidelobe energy / main-lobe energy)
    predicted = (1 - math.exp(-sigma ** 2)) / (math.exp(-sigma ** 2) * f)
    assert rise == pytest.approx(predicted, rel=0.2)
    assert (1 - m1 / m0) == pytest.approx(sigma ** 2, rel=0.2)  # ≈ σ² of the main-lobe energy moved
    loss = measure_targets(noisy, g, scene)[0].peak_loss_db
    assert loss == pytest.approx(10 * math.log10(math.exp(sigma ** 2)), rel=0.3)


def test_legendre_decomposition_of_injected_error(setup):
    g, _ = setup
    u = normalised_time(g)
    psi = smooth_phase_error(u, quadratic_rad=3.0, cubic_rad=1.0)
    c = legendre_decomposition(u, psi, 4)
    # u² = (P0 + 2 P2)/3, u³ = (3 P1 + 2 P3)/5
    assert c == pytest.approx([1.0, 0.6, 2.0, 0.4, 0.0], abs=1e-6)
