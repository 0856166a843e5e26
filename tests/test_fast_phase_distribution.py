"""One aperture's residual beyond PGA's window, not only its rms: the weighted-χ² distribution
of :func:`budget.sar.residual.random_walk_highpass_eigenvalues` and
:meth:`budget.bounds.FastPhaseResidual.p_within_limit`, against random walks sampled here
(cumulative sums of Gaussian increments, high-passed one by one) — the covariance route and the
sampling route share only ``highpass_phase``."""

from __future__ import annotations

import math

import numpy as np
import pytest

from budget.bounds import FastPhaseResidual
from budget.quadform import quadratic_form_quantile_imhof, quadratic_form_sf_imhof
from budget.sar.residual import (highpass_phase, random_walk_highpass_cross, random_walk_highpass_eigenvalues,
                                 random_walk_highpass_rms, random_walk_mixture_eigenvalues, random_walk_rms_quantile)
from budget.sar.windows import Window

N = 300
WALKS = 4000


def _sampled_residuals(power: int, window: str, seed: int, cutoff: float = 2.5) -> tuple[np.ndarray, np.ndarray]:
    """(r, w): the residuals beyond ``cutoff`` cycles (WALKS, N) of WALKS sampled walks of unit
    density integrated ``power`` times over [0, 1] s, and the energy weight w (N,)."""
    rng = np.random.default_rng(seed)
    e = np.cumsum(rng.standard_normal((WALKS, N)) * math.sqrt(1.0 / N), axis=1)
    for _ in range(power):
        e = np.cumsum(e, axis=1) / N
    w = Window.parse(window).samples(N) ** 2 if window != "rect" else np.ones(N)
    return highpass_phase(e.T, cutoff, None if window == "rect" else w).T, w  # every walk, one column each


def _sampled_mean_squares(power: int, window: str, seed: int, cutoff: float = 2.5) -> np.ndarray:
    """Energy-weighted mean square beyond ``cutoff`` cycles of WALKS sampled walks of unit density
    integrated ``power`` times over [0, 1] s."""
    r, w = _sampled_residuals(power, window, seed, cutoff)
    return (r ** 2 * w).sum(axis=1) / w.sum()


@pytest.mark.parametrize("kind,power,window", [("rw", 0, "rect"), ("vrw", 1, "taylor"), ("arw", 2, "taylor"),
                                               ("vrw", 1, "rect")])
def test_residual_distribution_against_sampled_walks(kind, power, window):
    """P(r̄ ≤ x·rms) for x = 0.5 … 2.5 against the share of 4,000 sampled walks: within 0.025
    (binomial 1σ ≤ 0.008, ≈ 3σ; the grids differ, 300 against 400 points)."""
    ms = _sampled_mean_squares(power, window, seed=23)
    lam = random_walk_highpass_eigenvalues(kind, 2.5, window=window)
    assert lam.sum() == pytest.approx(1.0) and np.all(np.diff(lam) <= 1e-15)
    rms2 = random_walk_highpass_rms(kind, 2.5, window=window) ** 2
    assert np.mean(ms) == pytest.approx(rms2, rel=0.06)
    for x in (0.5, 1.0, 1.5, 2.0, 2.5):
        predicted = 1.0 - quadratic_form_sf_imhof(lam * rms2, (x * x) * rms2)
        assert predicted == pytest.approx(np.mean(ms <= x * x * rms2), abs=0.025), x


def test_a_random_walks_residual_is_dominated_by_few_modes():
    """Why the rms is not a per-aperture limit: on the Taylor window beyond 2.5 cycles one mode
    carries 63 % (ARW) and 43 % (VRW) of the mean square, so at rms = limit a third of the
    apertures exceed it, and even at rms = limit/2 a few per cent do."""
    arw = random_walk_highpass_eigenvalues("arw", 2.5, window="taylor")
    vrw = random_walk_highpass_eigenvalues("vrw", 2.5, window="taylor")
    assert 0.55 < arw[0] < 0.7 and 0.35 < vrw[0] < 0.5
    at_limit = FastPhaseResidual(vrw_deg=0.0, arw_gravity_deg=1.0, arw_lever_arm_deg=0.0,
                                 pga_bandwidth_cycles=2.5, aperture_window="taylor(-35 dB, n̄=4)")
    assert 0.55 < at_limit.p_within_limit() < 0.8
    half = FastPhaseResidual(vrw_deg=0.0, arw_gravity_deg=0.5, arw_lever_arm_deg=0.0,
                             pga_bandwidth_cycles=2.5, aperture_window="taylor")
    assert 0.97 < half.p_within_limit() < 0.999
    none = FastPhaseResidual(vrw_deg=0.0, arw_gravity_deg=0.0, arw_lever_arm_deg=0.0,
                             pga_bandwidth_cycles=2.5, aperture_window="rect")
    assert none.p_within_limit() == 1.0


def test_two_independent_sources_combine_as_one_weighted_sum():
    """VRW and ARW (two sensors, independent): their phases add, and one aperture's mean square
    is that of the sum, r̄² = ⟨(r_v + r_a)²⟩ — cross term included, zero on average but not per
    aperture. P(r̄ ≤ limit) from the eigenvalues of the summed covariance against 4,000 sampled
    pairs (0.025, ≈ 3σ), at 0.6° and 0.5° rms: 0.848 against 0.856 (the sampled mean squares
    added without the cross term give 0.880)."""
    rv, w = _sampled_residuals(1, "taylor", seed=5)
    ra, _ = _sampled_residuals(2, "taylor", seed=6)
    v = (rv ** 2 * w).sum(axis=1) / w.sum()
    a = (ra ** 2 * w).sum(axis=1) / w.sum()
    sv, sa = 0.6 / math.sqrt(np.mean(v)), 0.5 / math.sqrt(np.mean(a))
    total = ((sv * rv + sa * ra) ** 2 * w).sum(axis=1) / w.sum()
    res = FastPhaseResidual(vrw_deg=0.6, arw_gravity_deg=0.5, arw_lever_arm_deg=0.0, pga_bandwidth_cycles=2.5,
                            aperture_window="taylor")
    assert res.eigenvalues().sum() == pytest.approx(0.6 ** 2 + 0.5 ** 2, rel=1e-9)
    assert res.p_within_limit() == pytest.approx(np.mean(total <= 1.0), abs=0.025)


def test_two_independent_walks_of_one_kind_scatter_as_one():
    """Two gyro axes' tilt seen on a squinted line of sight: two independent ARW walks of equal
    rms add to one walk of their combined rms, so one aperture's residual scatters exactly as a
    single axis's (the same weights). Against 4,000 sampled pairs at 0.55° rms together: P(r̄ ≤ 1°)
    within 0.02 (≈ 3σ at P ≈ 0.98; measured 0.979 against 0.978). Pooling the two axes' own
    weights — their mean squares added without the cross term, as this module's distribution did
    before — gives 0.996: four times fewer apertures beyond the limit than there are."""
    from budget.quadform import quadratic_form_sf_imhof as sf

    r1, w = _sampled_residuals(2, "taylor", seed=71, cutoff=2.0)
    r2, _ = _sampled_residuals(2, "taylor", seed=72, cutoff=2.0)
    c = random_walk_highpass_rms("arw", 2.0, n=400, window="taylor")
    coef = 0.55 / c / math.sqrt(2.0)
    total = ((coef * (r1 + r2)) ** 2 * w).sum(axis=1) / w.sum()
    two = FastPhaseResidual(vrw_deg=0.0, arw_gravity_deg=0.55, arw_lever_arm_deg=0.0, pga_bandwidth_cycles=2.0,
                            aperture_window="taylor", arw_axes=((coef, 0.0), (coef, 0.0), (0.0, 0.0)))
    one = FastPhaseResidual(vrw_deg=0.0, arw_gravity_deg=0.55, arw_lever_arm_deg=0.0, pga_bandwidth_cycles=2.0,
                            aperture_window="taylor", arw_axes=((coef * math.sqrt(2.0), 0.0), (0.0, 0.0), (0.0, 0.0)))
    assert two.p_within_limit() == pytest.approx(one.p_within_limit(), abs=1e-9)
    sampled = np.mean(total <= 1.0)
    assert two.p_within_limit() == pytest.approx(sampled, abs=0.02)
    pooled = np.concatenate([random_walk_mixture_eigenvalues({"arw": coef}, 2.0, window="taylor")] * 2)
    assert 1.0 - sf(pooled, 1.0) - sampled > 0.015


@pytest.mark.parametrize("k", [1, 2, 3, 7])
def test_imhof_is_exact_for_equal_weights(k):
    """Equal λ: Q/λ is χ²_k, whose tail scipy gives exactly (1e-6 absolute, over six decades of t)."""
    from scipy import stats
    for t in (1e-6, 1e-4, 0.01, 0.3, 1.0, 4.0, 15.0, 40.0, 1e3, 1e5):
        assert quadratic_form_sf_imhof(np.full(k, 0.37), t) == pytest.approx(stats.chi2.sf(t / 0.37, k), abs=1e-6)


@pytest.mark.parametrize("kind", ["rw", "vrw", "arw"])
def test_imhof_is_a_distribution_over_sixteen_decades(kind):
    """On a walk's weights, from far below its mean to far above: within [0, 1], non-increasing,
    no quadrature warning (the far tails come from Chernoff's bounds)."""
    import warnings
    lam = random_walk_highpass_eigenvalues(kind, 2.0, window="rect")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sf = [quadratic_form_sf_imhof(lam, t) for t in np.logspace(-8, 8, 49)]
    assert sf[0] == 1.0 and sf[-1] == 0.0 and np.all(np.diff(sf) <= 1e-9)


def test_fast_phase_crossing_is_where_the_share_is_a_half():
    """The analytic crossing of a noise term (its scale × the paper bound where half the
    apertures stay within the limit), checked by the share at that scale; none for a bias."""
    import math

    from budget.mc.consistency import fast_phase_crossing, fast_phase_share, single_term_model
    from budget.presets import get_preset
    s = get_preset("automotive_77ghz").model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0)})
    c = fast_phase_crossing(s, "gyro_arw")
    assert 0.1 < c < 0.4
    assert fast_phase_share(s, single_term_model(s, "gyro_arw", c)) == pytest.approx(0.5, abs=1e-4)
    assert fast_phase_share(s, single_term_model(s, "gyro_arw", 0.5 * c)) > 0.9
    assert math.isinf(fast_phase_crossing(s, "gyro_bias"))
    assert fast_phase_share(s, single_term_model(s, "gyro_bias", 10.0)) == 1.0


@pytest.mark.parametrize("k,p", [(1, 0.01), (1, 0.9), (2, 0.5), (5, 0.999), (30, 0.9)])
def test_imhof_quantile_is_exact_for_equal_weights(k, p):
    """The inverse of Imhof's inversion against scipy's χ²_k quantile (equal λ), 1e-4 relative."""
    from scipy import stats
    assert quadratic_form_quantile_imhof(np.full(k, 0.37), p) == pytest.approx(0.37 * stats.chi2.ppf(p, k), rel=1e-4)


def test_imhof_quantile_refuses_what_has_none():
    for lam, p in ((np.zeros(3), 0.5), (np.ones(3), 1.0), (np.ones(3), 0.0), (np.array([1.0, np.nan]), 0.5)):
        with pytest.raises(ValueError):
            quadratic_form_quantile_imhof(lam, p)


@pytest.mark.parametrize("kind,power,window", [("rw", 0, "rect"), ("vrw", 1, "taylor"), ("arw", 2, "taylor")])
def test_rms_quantile_against_sampled_walks(kind, power, window):
    """The rms over apertures × :func:`random_walk_rms_quantile` (share 0.9, K = 2) is met by 0.9 of
    4,000 sampled walks: within 0.015 (binomial 1σ 0.0047, ≈ 3σ)."""
    ms = _sampled_mean_squares(power, window, seed=31, cutoff=2.0)
    rms = random_walk_highpass_rms(kind, 2.0, window=window)
    m = random_walk_rms_quantile(kind, 0.9, 2.0, window=window)
    assert 1.15 < m < 1.5  # the rms itself is met by far fewer than 0.9 of apertures
    assert np.mean(np.sqrt(ms) <= m * rms) == pytest.approx(0.9, abs=0.015)


@pytest.mark.parametrize("vrw,arw,lever", [(0.5, 0.0, 0.0), (0.3, 0.4, 0.0), (0.6, 0.1, 0.05), (1.2, 0.3, 0.2),
                                           (0.05, 0.05, 0.05), (2.0, 0.0, 0.1)])
def test_share_margin_is_the_exact_quantile(vrw, arw, lever):
    """:meth:`FastPhaseResidual.share_margin` (Liu's quantile corrected by one or two exact
    evaluations) against the root of Imhof's inversion: 0.2 % relative for margins 0.5–2, 5 %
    beyond (0.37–9.5 here); every source scaled by the exact root puts the asked share within the
    limit and reads a margin of 1 (1e-4); share None gives the rms."""
    res = FastPhaseResidual(vrw_deg=vrw, arw_gravity_deg=arw, arw_lever_arm_deg=lever, pga_bandwidth_cycles=2.0,
                            aperture_window="taylor")
    lam = res.eigenvalues()
    m = res.share_margin()
    exact = 1.0 / math.sqrt(quadratic_form_quantile_imhof(lam, 0.9))
    near = 0.5 <= exact <= 2.0
    assert m == pytest.approx(exact, rel=2e-3 if near else 5e-2)
    # scaled by the exact margin, the part sits where the verdict turns: there the margin is 1
    at = FastPhaseResidual(vrw_deg=vrw * exact, arw_gravity_deg=arw * exact, arw_lever_arm_deg=lever * exact,
                           pga_bandwidth_cycles=2.0, aperture_window="taylor")
    assert at.p_within_limit() == pytest.approx(0.9, abs=1e-4)
    assert at.share_margin() == pytest.approx(1.0, abs=1e-4)
    rms = FastPhaseResidual(vrw_deg=vrw, arw_gravity_deg=arw, arw_lever_arm_deg=lever, pga_bandwidth_cycles=2.0,
                            aperture_window="taylor", share=None)
    assert rms.share_margin() == pytest.approx(1.0 / rms.total_deg)


def _sampled_paths(window: str, seed: int, cutoff: float = 2.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """WALKS unit walks φ (one white noise each) and their double integral ∬φ, high-passed beyond
    ``cutoff`` cycles, with the energy weight: (r_rw, r_arw, w)."""
    rng = np.random.default_rng(seed)
    phi = np.cumsum(rng.standard_normal((WALKS, N)) * math.sqrt(1.0 / N), axis=1)
    tilt = np.cumsum(np.cumsum(phi, axis=1) / N, axis=1) / N
    w = Window.parse(window).samples(N) ** 2 if window != "rect" else np.ones(N)
    weight = None if window == "rect" else w
    return highpass_phase(phi.T, cutoff, weight).T, highpass_phase(tilt.T, cutoff, weight).T, w


@pytest.mark.parametrize("window", ["rect", "taylor"])
def test_one_noise_two_paths_cross_term_against_sampled_walks(window):
    """A walk and its double integral from the same noise, beyond 2 cycles: their correlation
    (≈ −0.7) from the covariance against 4,000 sampled pairs (±0.03, ≈ 3σ), and the mixture's
    weights: Σλ is the mixture's mean square, and P(r̄ ≤ x·rms) matches the sampled share (0.025)."""
    r0, r2, w = _sampled_paths(window, seed=41)
    sampled = np.mean((r0 * r2 * w).sum(axis=1) / w.sum())
    rho = random_walk_highpass_cross("arw", "rw", 2.0, window=window) / (
        random_walk_highpass_rms("arw", 2.0, window=window) * random_walk_highpass_rms("rw", 2.0, window=window))
    assert -0.8 < rho < -0.6
    rho_sampled = sampled / math.sqrt(np.mean((r0 * r0 * w).sum(axis=1) / w.sum())
                                      * np.mean((r2 * r2 * w).sum(axis=1) / w.sum()))
    assert rho == pytest.approx(rho_sampled, abs=0.03)
    # equal rms on both paths, added: the mixture of one noise
    a, b = 1.0 / random_walk_highpass_rms("arw", 2.0, window=window), 1.0 / random_walk_highpass_rms("rw", 2.0, window=window)
    lam = random_walk_mixture_eigenvalues({"arw": a, "rw": b}, 2.0, window=window)
    assert lam.sum() == pytest.approx(2.0 + 2.0 * rho, rel=0.01)
    ms = (((a * r2 + b * r0) ** 2) * w).sum(axis=1) / w.sum()
    assert np.mean(ms) == pytest.approx(lam.sum(), rel=0.08)
    rms2 = lam.sum()
    for x in (0.5, 1.0, 1.5, 2.0):
        assert 1.0 - quadratic_form_sf_imhof(lam, x * x * rms2) == pytest.approx(np.mean(ms <= x * x * rms2), abs=0.025)


def test_residual_of_one_gyro_axis_seen_through_gravity_and_a_lever_arm():
    """FastPhaseResidual with the geometry (:attr:`arw_axes`): its ARW rms is Σ_i A_i² c_arw² + B_i² c_rw²
    + 2 A_i B_i c_x over the axes, between the paths' difference and sum, and its weights sum to it;
    without the geometry the two are taken independent."""
    c2, c0 = random_walk_highpass_rms("arw", 2.0, window="taylor"), random_walk_highpass_rms("rw", 2.0, window="taylor")
    cx = random_walk_highpass_cross("arw", "rw", 2.0, window="taylor")
    axes = ((0.5 / c2, 0.4 / c0), (0.0, -0.3 / c0), (0.0, 0.0))
    res = FastPhaseResidual(vrw_deg=0.2, arw_gravity_deg=0.5, arw_lever_arm_deg=0.5, pga_bandwidth_cycles=2.0,
                            aperture_window="taylor", arw_axes=axes)
    expected = 0.5 ** 2 + 0.4 ** 2 + 0.3 ** 2 + 2.0 * (0.5 / c2) * (0.4 / c0) * cx
    assert res.arw_deg == pytest.approx(math.sqrt(expected), rel=1e-9)
    assert res.total_deg == pytest.approx(math.hypot(0.2, res.arw_deg), rel=1e-12)
    assert res.eigenvalues().sum() == pytest.approx(res.total_deg ** 2, rel=0.01)  # 400 against 800 points
    alone = FastPhaseResidual(vrw_deg=0.2, arw_gravity_deg=0.5, arw_lever_arm_deg=0.5, pga_bandwidth_cycles=2.0,
                              aperture_window="taylor")
    assert alone.total_deg == pytest.approx(math.sqrt(0.2 ** 2 + 0.5 ** 2 + 0.5 ** 2))


@pytest.mark.parametrize("share", [0.0, 1.0, 1.5, -0.1, float("nan"), True])
def test_a_share_outside_zero_one_is_a_clear_error(share):
    """The share of apertures asked to meet the limit: strictly between 0 and 1 (or None), named
    in the error wherever a user gives it."""
    from pydantic import ValidationError

    from budget.bounds import LeverArmAssumptions, fast_phase_limits
    from budget.errors import InputError
    with pytest.raises(InputError, match="share"):
        fast_phase_limits(0.03, [1.0], share=share)
    with pytest.raises(ValidationError, match="fast_residual_share"):
        LeverArmAssumptions(fast_residual_share=share)


def test_sources_of_an_unknown_kind_are_a_clear_error_and_no_source_is_empty():
    from budget.sar.residual import random_walk_sources_eigenvalues
    with pytest.raises(ValueError, match="unknown kind.*'rw', 'vrw' or 'arw'"):
        random_walk_sources_eigenvalues([{"arw": 1.0}, {"flicker": 1.0}], 2.0)
    assert random_walk_sources_eigenvalues([], 2.0).size == 0
    assert random_walk_sources_eigenvalues([{"arw": 0.0, "rw": 0.0}], 2.0).size == 0
    # one walk alone: its own kernel's weights (Σλ = 1, from B's singular values) × its mean square
    lam = random_walk_sources_eigenvalues([{"arw": 2.0}], 2.0, window="taylor")
    own = random_walk_highpass_eigenvalues("arw", 2.0, window="taylor")
    ms = random_walk_highpass_rms("arw", 2.0, n=400, window="taylor") ** 2
    np.testing.assert_allclose(lam[:20], 4.0 * ms * own[:20], rtol=1e-8, atol=1e-12 * lam[0])
    assert lam.sum() == pytest.approx(4.0 * ms, rel=1e-9)
    # a scale of the sources scales the weights; one source is the one-noise mixture
    one = random_walk_sources_eigenvalues([{"arw": 2.0, "rw": -1.0}], 2.0, window="taylor")
    np.testing.assert_array_equal(random_walk_mixture_eigenvalues({"arw": 2.0, "rw": -1.0}, 2.0, window="taylor"), one)
    np.testing.assert_allclose(random_walk_sources_eigenvalues([{"arw": 6.0, "rw": -3.0}], 2.0, window="taylor"),
                               9.0 * one, rtol=1e-12)
