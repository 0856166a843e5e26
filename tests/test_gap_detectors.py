"""Closed forms behind the new detectors, against independent computations.

* band-limited vibration: the complex closed-form AVAR against the direct lag sum of its AR(2)
  autocorrelation and against simulated series; its PSD integrates to its variance;
* heavy tails: the Student-t fourth cumulant against 6/(ν − 4) (ν > 4) and the tail
  probability of the differences against Monte Carlo;
* the lattice test: values floored by an independent quantizer (``tests/gap_truth.py``) give
  the quantum, continuous values give none;
* Allan tables whose τ come from measured time stamps.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

import gap_truth as gt
from budget.errors import InputError
from budget.gap import theory as th
from budget.gap.signatures import lattice_step
from budget.imu.effects import student_t_noise, vibration, vibration_acov, vibration_psd
from budget.noise import read_adev_table

DT = 0.01


def _direct_avar(rho, m):
    out = []
    for mi in m:
        k = np.arange(-(mi - 1), mi)
        out.append(np.sum((mi - np.abs(k)) * (rho(k) - rho(k + mi))) / mi ** 2)
    return np.array(out)


@pytest.mark.parametrize("f0,w", [(12.0, 1.5), (0.5, 0.05), (40.0, 8.0)])
def test_vibration_avar_closed_form(f0, w):
    m = 2 ** np.arange(0, 14)
    direct = _direct_avar(lambda k: vibration_acov(k, f0, w, DT), m)
    assert np.allclose(th.avar_vibration(m, DT, f0, w), direct, rtol=1e-9, atol=1e-15)


def test_vibration_generator_matches_its_theory():
    rng = np.random.default_rng(11)
    x = vibration(6, 100_000, 12.0, 1.5, 2e-3, DT, rng)
    assert np.std(x) == pytest.approx(2e-3, rel=0.03)
    m = np.array([1, 2, 4, 8, 16, 64])
    phase = np.concatenate([np.zeros((6, 1)), np.cumsum(x, axis=1)], axis=1)
    got = np.mean([[np.mean((p[2 * k:] - 2 * p[k:-k] + p[:-2 * k]) ** 2) / (2 * k * k) for k in m]
                   for p in phase], axis=0)
    assert np.allclose(got, 4e-6 * th.avar_vibration(m, DT, 12.0, 1.5), rtol=0.08)
    f = np.fft.rfftfreq(1 << 16, DT)
    var = np.sum(vibration_psd(f, 12.0, 1.5, DT)) * (f[1] - f[0])
    assert var == pytest.approx(1.0, rel=2e-3)  # one-sided PSD of the unit-variance resonator


def test_student_t_cumulant_and_tails():
    for nu in (6.0, 10.0):
        assert th.student_t_cum4(nu, 10 ** 9) == pytest.approx(6.0 / (nu - 4.0) * (nu / (nu - 2.0)) ** 2,
                                                             rel=0.02)
    rng = np.random.default_rng(5)
    n, nu, scale, g = 2_000_000, 4.0, 1.0, 0.7
    t = rng.standard_t(nu, (2, n)) * scale
    d = g * rng.standard_normal(n) + t[0] - t[1]
    for lim in (6.0, 12.0):
        mc = float(np.mean(np.abs(d) > lim))
        assert th.student_t_tails(nu, scale, g * g, lim) == pytest.approx(mc, rel=0.15)
    x = student_t_noise(1, 400_000, 1e-3, 5.0, DT, rng)[0]
    assert np.std(x) == pytest.approx(1e-3 / math.sqrt(DT), rel=0.03)


def test_lattice_of_a_quantized_output():
    rng = np.random.default_rng(3)
    dens, _ = gt.base_levels("gyro_x")
    x = dens * math.sqrt(gt.RATE) * rng.standard_normal(50_000)
    q = 2e-5
    y = gt.quantized(x, q, 7.3e-5, rng)
    step = lattice_step(np.diff(y))
    assert step == pytest.approx(math.sqrt(12.0) * q * gt.RATE, rel=1e-9)
    assert lattice_step(np.diff(x)) is None
    counts = np.round(x / 1e-4) * 1e-4 * 0.1  # raw counts in a printed decimal unit
    assert lattice_step(np.diff(counts)) == pytest.approx(1e-5, rel=1e-6)


def _table(path, taus, adev):
    rows = ["channel,tau_s,adev"] + [f"gyro_x_rps,{float(t)!r},{float(a)!r}" for t, a in zip(taus, adev)]
    path.write_text("\n".join(rows) + "\n")
    return path


def test_allan_table_with_measured_tau_is_accepted_with_a_note(tmp_path):
    m = np.array([1, 2, 4, 8, 16, 32, 64])
    jitter = np.array([0.999999, 1.04, 1.10, 0.97, 1.0, 1.02, 1.0])
    tau = m * jitter / 100.0
    adev = 1e-3 / np.sqrt(tau)  # white noise: slope −1/2
    out = read_adev_table(_table(tmp_path / "t.csv", tau, adev), 100.0, 100_000)["gyro_x"]
    whole = np.rint(m * jitter)  # nearest whole number of samples (32 × 1.02 → 33)
    assert np.array_equal(out.m, whole)
    # moved along the slope: the white line 1e-3/√τ at the whole-sample τ
    assert np.allclose(out.adev, 1e-3 / np.sqrt(whole / 100.0), rtol=2e-3)
    assert out.notes and "not a whole number" in out.notes[0] and "10.00%" in out.notes[0]
    with pytest.raises(InputError, match="not a whole number"):
        read_adev_table(_table(tmp_path / "u.csv", tau * np.array([1.3, 1, 1, 1, 1, 1, 1]), adev),
                        100.0, 100_000)


def test_rounding_the_rate_adds_a_uniform_white_error_of_variance_step2_over_12():
    """The generator's rate rounding on Gaussian noise of σ = δ/2: the error is uniform (variance
    δ²/12 within 2 %, Sheppard; excess kurtosis −1.2 within 0.1) and white (lag-1 correlation
    below 0.02) — the shape the ``rate_quantization`` candidate assumes."""
    from budget.imu.effects import rate_quantization_error

    rng = np.random.default_rng(8)
    step = 1e-3
    x = 0.5 * step * rng.standard_normal((1, 400_000)) + 3.3e-4
    e = rate_quantization_error(x, step, rng)[0]
    assert np.var(e) == pytest.approx(step ** 2 / 12.0, rel=0.02)
    assert stats.kurtosis(e) == pytest.approx(-1.2, abs=0.1)
    assert abs(np.corrcoef(e[:-1], e[1:])[0, 1]) < 0.02
    out = x[0] + e  # on the lattice kδ − U·δ
    k = (out - out[0]) / step
    assert np.allclose(k, np.round(k), atol=1e-6)


def test_a_rate_rounded_to_two_sigma_lsb_is_named_rate_quantization_not_heavy_tails():
    """A gyro whose output rate is rounded (np.round here, not the package's generator) to an
    LSB of 2σ of its white noise, on 10 min of the benchmark's base model: the lattice is found,
    the integrated-output quantization is rejected by simulation, and ``rate_quantization`` is
    named first at the LSB — not ``heavy_tailed`` (the uniform error's tails are light)."""
    from budget.gap import log_from_arrays, run_gap
    from budget.imu import NoiseModel

    n = 60_000
    logs, _, _ = gt.make(None, n, 1)
    dens, _ = gt.base_levels("gyro_x")
    lsb = 2.0 * dens * math.sqrt(gt.RATE)
    logs["gyro_x"] = lsb * np.round((logs["gyro_x"] + 7.3e-5 + 3e-4) / lsb)
    rep = run_gap(log_from_arrays(logs, gt.RATE), NoiseModel.model_validate(gt.base_model_dict()),
                  seed=0, max_steps=2)
    assert rep.steps and (rep.steps[0].name, rep.steps[0].channel) == ("rate_quantization", "gyro_x"), \
        rep.summary()
    assert rep.steps[0].params["step"] == pytest.approx(lsb, rel=1e-6)
    assert "heavy_tailed" not in [s.name for s in rep.steps]
