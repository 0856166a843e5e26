"""The fast Monte Carlo path: batched image formation, vectorised metrics, and determinism.

* the batched range-Doppler former equals :func:`budget.sar.form_image` (the per-trial former,
  whose steps are written out independently) to 1e-10 of the image peak;
* the vectorised cut measurement equals the scalar :func:`budget.sar.irf.measure_cut` on the
  same cuts;
* the batched trial chain equals a per-trial chain written here from the public per-trial
  functions (form_image → measure_targets → evaluate → pga → phase correction → residual);
* the same seed gives the same per-trial numbers whatever the worker count and chunk size.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from budget.catalog.io import get_part
from budget.mc import McOptions, run_mc
from budget.mc.runner import work_units
from budget.mc.chain import (AZ_SEARCH_CELLS, FORMATION_BATCH, REASONS, ChainSetup, _pga_kwargs, pga_min_window,
                             apply_phase_estimate, run_trial_errors, run_trials)
from budget.presets import get_preset
from budget.sar import evaluate, form_image, measure_targets, pga, phase_on_bins, residual_phase_rad
from budget.sar.image import RdaImageFormer
from budget.sar.irf import measure_cut, measure_cuts, upsample_periodic
from budget.sar.residual import pga_bandwidth_cycles, pga_residual_rms_rad, phase_history_energy

POINTS = McOptions(scene="points")


def _smooth_offsets(geom, rng: np.random.Generator, n: int, scale_m: float) -> np.ndarray:
    """n random smooth APC offset tracks (n, n_pulses, 3): random quadratic + cubic + sinusoid."""
    u = 2.0 * geom.pulse_times_s / geom.aperture_time_s
    out = np.empty((n, geom.n_pulses, 3))
    for i in range(n):
        c = rng.standard_normal((4, 3)) * scale_m
        f = rng.uniform(0.5, 3.0, 3)
        out[i] = c[0] * u[:, None] ** 2 + c[1] * u[:, None] ** 3 + c[2] * np.sin(np.pi * f * u[:, None]) + c[3]
    return out


@pytest.mark.parametrize("preset", ["airborne_xband", "automotive_24ghz"])
def test_batched_formation_equals_form_image(preset):
    """automotive_24ghz exercises the zero-padding and the residual-migration interpolator."""
    setup = ChainSetup.build(get_preset(preset), POINTS)
    g = setup.geom
    offsets = _smooth_offsets(g, np.random.default_rng(7), 3, 0.02)
    former = RdaImageFormer(g)
    batched = former.form(former.range_spectrum(setup.clean_echoes), offsets)
    for k in range(offsets.shape[0]):
        ref = form_image(g, setup.clean_echoes, offsets[k]).data
        assert batched.shape[1:] == ref.shape
        assert np.max(np.abs(batched[k] - ref)) <= 1e-10 * np.max(np.abs(ref))
    # batching does not couple the trials: one alone gives the same image
    alone = former.form(former.range_spectrum(setup.clean_echoes), offsets[1:2])[0]
    assert np.max(np.abs(alone - batched[1])) <= 1e-12 * np.max(np.abs(alone))


@pytest.mark.parametrize("extent", [None, 40.0])
def test_vectorised_cuts_equal_scalar_measure_cut(extent):
    """Random band-limited lines around a sinc main lobe, some defocused: every field equal."""
    rng = np.random.default_rng(3)
    n, up = 135, 16
    x = np.arange(n)
    lines = []
    for k in range(12):
        centre = rng.uniform(40, 95)
        width = rng.uniform(1.0, 4.0)
        line = np.sinc((x - centre) / width) * np.exp(1j * rng.uniform(0, 0.3) * (x - centre) ** 2 / n)
        lines.append(line + 0.01 * (rng.standard_normal(n) + 1j * rng.standard_normal(n)))
    cuts = upsample_periodic(np.array(lines), up)
    expected = np.array([int(round(np.argmax(np.abs(c)))) for c in cuts], dtype=float) + rng.integers(-8, 8, 12)
    null = rng.uniform(0.8, 1.6, 12)
    got = measure_cuts(cuts, 0.5 / up, 10.0, expected_index=expected, search_half=2 * up, null=null, extent=extent)
    for k in range(12):
        ref = measure_cut(cuts[k], 0.5 / up, 10.0, expected_index=expected[k], search_half=2 * up, null=null[k],
                          extent=extent)
        one = got[k]
        for name in ("peak_position", "peak_amplitude", "width_3db", "pslr_db", "islr_db"):
            assert getattr(one, name) == pytest.approx(getattr(ref, name), rel=1e-9, abs=1e-12), name


def _per_trial_reference(setup: ChainSetup, error_m: np.ndarray, peak_range_cells: float) -> dict:
    """The trial chain of one trial from the public per-trial functions (points scene, no noise)."""
    g, opt = setup.geom, setup.options
    measured = -error_m
    img = form_image(g, setup.clean_echoes, measured, method=opt.image_method)
    ev_before = evaluate(measure_targets(img, g, setup.clean_scene, azimuth_search_cells=AZ_SEARCH_CELLS),
                         opt.acceptance)
    floor = pga_min_window(img.aperture_mask().size, int(img.aperture_mask().sum()))  # 4 resolution cells
    res = pga(img.data, **_pga_kwargs(opt, floor), aperture_bins=img.aperture_mask())
    estimate = np.zeros(img.data.shape[0]) if res.usable_lines == 0 else np.asarray(res.phase_error_rad, float)
    after = img.with_data(apply_phase_estimate(img.data, estimate))
    m_after = measure_targets(after, g, setup.clean_scene, azimuth_search_cells=AZ_SEARCH_CELLS)
    ev_after = evaluate(m_after, opt.acceptance)
    truth = phase_on_bins(img, g, residual_phase_rad(g, None, measured))
    mask, energy = img.aperture_mask(), phase_history_energy(img.data)
    cutoff = pga_bandwidth_cycles(res.final_window, mask.size, int(mask.sum()))
    resid = math.degrees(pga_residual_rms_rad(estimate, truth, mask, energy, cutoff))
    reasons = {key for r in ev_after.reasons for key in ("broadening", "pslr", "islr", "peak_loss") if key in r}
    if peak_range_cells > opt.max_range_migration_cells:
        reasons.add("range_migration")
    if not resid <= opt.max_residual_phase_rms_deg:
        reasons.add("residual_phase_noise")
    if res.usable_lines == 0:
        reasons.add("pga_failed")
    elif not res.converged:
        reasons.add("pga_not_converged")
    ts = list(m_after)
    return {"passed_before": ev_before.passed and peak_range_cells <= opt.max_range_migration_cells,
            "reasons": [r for r in REASONS if r in reasons], "residual_phase_rms_deg": resid,
            "azimuth_broadening": max(t.azimuth.broadening for t in ts),
            "pslr_db": max(max(t.azimuth.pslr_db, t.range.pslr_db) for t in ts),
            "islr_db": max(max(t.azimuth.islr_db, t.range.islr_db) for t in ts),
            "peak_loss_db": max(t.peak_loss_db for t in ts)}


def test_batched_chain_equals_per_trial_chain():
    """Four trials through the batched chain (one batch) against the per-trial reference: the
    small offsets pass, the large ones fail — the verdicts and the metrics agree."""
    setup = ChainSetup.build(get_preset("airborne_xband"), POINTS)
    g = setup.geom
    rng = np.random.default_rng(11)
    errors = np.concatenate([_smooth_offsets(g, rng, 2, 2e-4), _smooth_offsets(g, rng, 2, 5e-3)])
    cells = np.array([0.1, 0.2, 0.3, 1.5])
    batch = run_trials(setup, errors, range(8, 12), 1, cells)
    verdicts = set()
    for k, o in enumerate(batch):
        ref = _per_trial_reference(setup, errors[k], float(cells[k]))
        assert o.passed_before == ref["passed_before"]
        assert o.reasons == ref["reasons"]
        verdicts.add(o.passed_after)
        for name in ("residual_phase_rms_deg", "azimuth_broadening", "pslr_db", "islr_db", "peak_loss_db"):
            assert o.after[name] == pytest.approx(ref[name], rel=1e-7, abs=1e-9), name
        one = run_trial_errors(setup, errors[k], 8 + k, 1, float(cells[k]))  # a batch of one
        assert one.reasons == o.reasons
        for name, v in o.after.items():
            assert one.after[name] == pytest.approx(v, rel=1e-9, abs=1e-12, nan_ok=True), name
    assert verdicts == {True, False}  # the four trials cover both outcomes


def _numbers(result) -> dict:
    agg = result.agg
    return {"n": agg.n, "pass_before": agg.pass_before, "pass_after": agg.pass_after,
            "converged": agg.pga_converged, "reasons": dict(agg.reasons),
            "trial_metrics": {k: list(v) for k, v in agg.trial_metrics.items()}}


@pytest.mark.slow
def test_same_seed_same_numbers_any_workers_and_chunks():
    """130 trials (two full chunks and a partial one, a partial formation batch at the end) with
    receiver noise (one random stream per trial): identical per-trial numbers serially with
    64- and 128-trial chunks and with 2 worker processes (which share each chunk in pieces)."""
    assert 64 % FORMATION_BATCH == 0
    assert len(work_units(130, 64, 2)) > len(work_units(130, 64, 1))  # 2 workers share chunks out
    scen = get_preset("automotive_24ghz")
    part = get_part("STIM300")
    opt = McOptions(scene="points", snr_db=40.0)
    a = _numbers(run_mc(scen, part, 130, 5, options=opt))
    b = _numbers(run_mc(scen, part, 130, 5, options=opt.model_copy(update={"chunk_trials": 128})))
    c = _numbers(run_mc(scen, part, 130, 5, options=opt, workers=2))
    assert a["n"] == 130 and len(a["trial_metrics"]["trial"]) == 130
    for other in (b, c):
        for key in ("n", "pass_before", "pass_after", "converged", "reasons"):
            assert other[key] == a[key], key
        assert other["trial_metrics"].keys() == a["trial_metrics"].keys()
        for key, values in a["trial_metrics"].items():
            np.testing.assert_array_equal(np.asarray(other["trial_metrics"][key]), np.asarray(values), err_msg=key)
