"""The Monte Carlo chain's shortcuts give the numbers of the plain path bit for bit.

* :meth:`RdaImageFormer.form_groups` (two data sets along the same tracks, motion-compensation
  phases formed once) equals :meth:`RdaImageFormer.form` of each set alone;
* :meth:`ChainPlan.still` (the perfect-IMU clean image formed and measured once, repeated)
  equals forming and measuring the clean images of zero-error trials;
* perfect-IMU trials (the scene reference's and the twins' path) give the same outcomes through
  :meth:`ChainPlan.still` as through the plain formation;
* the compiled cut measurement's PSLR (its runs read without a modulo) equals the scalar
  :func:`budget.sar.irf.measure_cut` (to its last bits), also when the runs wrap around the line.
"""

from __future__ import annotations

import numpy as np
import pytest

from budget.mc import McOptions
from budget.mc.chain import SAR_STREAM, ChainSetup, chain_plan, run_trials
from budget.mc.plan import ChainPlan
from budget.presets import get_preset
from budget.sar.irf import measure_cut, measure_cuts, upsample_periodic


@pytest.fixture(scope="module")
def realistic():
    return ChainSetup.build(get_preset("airborne_xband"), McOptions(scene="realistic"))


def _tracks(geom, n: int, seed: int) -> np.ndarray:
    u = 2.0 * geom.pulse_times_s / geom.aperture_time_s
    c = np.random.default_rng(seed).standard_normal((n, 3, 3)) * 0.01
    return c[:, 0, None, :] * u[None, :, None] ** 2 + c[:, 1, None, :] * u[None, :, None] ** 3 + c[:, 2, None, :]


def test_form_groups_equals_form_alone(realistic):
    plan = chain_plan(realistic)
    tracks = _tracks(realistic.geom, 3, 1)
    noisy = plan.former.range_spectrum(np.stack([realistic.echoes] * 3))
    both = plan.former.form_groups([plan.clean_spectrum, noisy], tracks)
    assert np.array_equal(both[0], plan.former.form(plan.clean_spectrum, tracks))
    assert np.array_equal(both[1], plan.former.form(noisy, tracks))


def test_still_products_equal_plain_ones(realistic):
    plan = chain_plan(realistic)
    measured = -np.zeros((3, realistic.geom.n_pulses, 3))
    clean, prod = plan.still(realistic, 3)
    plain = plan.form(realistic, measured, range(3), 1, SAR_STREAM)[0]
    ref = plan.clean_products(plain)
    assert np.array_equal(clean, plain)
    assert np.array_equal(prod.hist, ref.hist) and np.array_equal(prod.energy, ref.energy)
    for k, v in ref.metrics.values.items():
        assert np.array_equal(prod.metrics[k], v, equal_nan=True), k


def test_perfect_imu_trials_equal_through_the_plain_path(realistic, monkeypatch):
    zero = np.zeros((4, realistic.geom.n_pulses, 3))
    fast = run_trials(realistic, zero, range(8, 12), 5, np.zeros(4), relative=False)

    def plain(self, setup, n):  # the still image formed again, as every trial formed it before
        measured = -np.zeros((n, setup.geom.n_pulses, 3))
        images = self.form(setup, measured, range(n), 0, SAR_STREAM)[0]
        return images, self.clean_products(images)

    monkeypatch.setattr(ChainPlan, "still", plain)
    slow = run_trials(realistic, zero, range(8, 12), 5, np.zeros(4), relative=False)
    for a, b in zip(fast, slow):
        assert a.reasons == b.reasons and a.passed_before == b.passed_before and a.passed_after == b.passed_after
        for when in ("before", "after"):
            x, y = getattr(a, when), getattr(b, when)
            assert x.keys() == y.keys()
            assert all(x[k] == y[k] or (np.isnan(x[k]) and np.isnan(y[k])) for k in x), when


@pytest.mark.parametrize("extent", [None, 3.0, 40.0])
def test_cut_pslr_equals_scalar_measure_cut_across_the_wrap(extent):
    """Peaks near either end of the periodic line (the PSLR's runs wrap around it), narrow and
    wide main lobes, finite extents shorter and longer than half the line: every field equal."""
    rng = np.random.default_rng(11)
    n, up = 96, 16
    x = np.arange(n)
    centres = np.concatenate([rng.uniform(0, 3, 5), rng.uniform(n - 3, n, 5), rng.uniform(20, 70, 4)])
    lines = []
    for c in centres:
        d = (x - c + n / 2) % n - n / 2
        width = rng.uniform(0.8, 6.0)
        lines.append(np.sinc(d / width) * np.exp(1j * rng.uniform(0, 2.0) * d ** 2 / n)
                     + 0.01 * (rng.standard_normal(n) + 1j * rng.standard_normal(n)))
    cuts = upsample_periodic(np.array(lines), up)
    expected = np.array([float(np.argmax(np.abs(c))) for c in cuts])
    null = rng.uniform(0.3, 3.0, centres.size)
    got = measure_cuts(cuts, 0.5 / up, 10.0, expected_index=expected, search_half=2 * up, null=null, extent=extent)
    for k in range(centres.size):
        ref = measure_cut(cuts[k], 0.5 / up, 10.0, expected_index=expected[k], search_half=2 * up, null=null[k],
                          extent=extent)
        one = got[k]
        for name in ("peak_position", "peak_amplitude", "width_3db", "pslr_db", "islr_db"):
            # the scalar form squares |cut|, the compiled one re² + im²: equal to the last bits
            assert getattr(one, name) == pytest.approx(getattr(ref, name), rel=1e-9, abs=1e-12), name
