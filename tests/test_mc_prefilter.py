"""Seed 000's ARMA-Kalman pre-filter in the Monte Carlo chain: what it does to motion, and refusal.

Checks against theory: on white noise the paper's filter (R = data variance, Q = δ₁) is a
steady-state linear filter whose output variance follows from its gain, and for AR(1) its DC
gain has a scalar closed form — ≈ 0.5 when φ ≈ 0 (it halves motion); a filter whose DC gain
departs from 1 by more than 1 % is refused with the gains named; the DC gains are in the
CLI's JSON; a constant true signal passes unchanged (the record mean is removed and restored).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from budget.catalog.io import get_part
from budget.cli.main import main
from budget.errors import InputError
from budget.imu import NoiseModel
from budget.mc import run_mc
from budget.mc.options import McOptions
from budget.motion import simulate_motion
from budget.noise.arma import ArmaFit
from budget.noise.kalman import ArmaKalman
from budget.noise.kalman_response import frequency_response
from budget.noise.prefilter import DC_GAIN_TOLERANCE, ImuPrefilter, calibrate_prefilter
from budget.presets import get_preset

RATE = 100.0


def _ar1(phi: float, sigma2: float, data_variance: float) -> ArmaFit:
    return ArmaFit(p=1, q=0, phi=np.array([phi]), theta=np.array([]), sigma2=sigma2, n=10_000,
                   method="test", data_variance=data_variance, stderr=np.zeros(1))


@pytest.mark.parametrize("phi", [0.0, 0.5, 0.99])
def test_ar1_dc_gain_matches_the_scalar_riccati_closed_form(phi):
    """Scalar steady state: P⁻ = φ²P⁺ + Q, K = P⁻/(P⁻ + R), P⁺ = (1 − K)P⁻; the filter
    x̂_k = φ(1 − K)x̂_{k−1} + K z_k has DC gain K/(1 − φ(1 − K)). With the paper's R = var(z)
    = Q/(1 − φ²): φ = 0 gives exactly 0.5."""
    q = 1.0
    r = q / (1 - phi ** 2)
    kf = ArmaKalman(_ar1(phi, q, r))
    p = q
    for _ in range(10_000):
        k = p / (p + r)
        p = phi ** 2 * (1 - k) * p + q
    k = p / (p + r)
    theory = k / (1 - phi * (1 - k))
    assert frequency_response(kf, RATE, [0.0]).dc_gain == pytest.approx(theory, rel=1e-9)
    if phi == 0.0:
        assert theory == pytest.approx(0.5, abs=1e-12)


def test_prefilter_variance_matches_its_steady_state_gain_and_keeps_constants():
    model = NoiseModel(rate_hz=RATE, gyro_arw_deg_rt_h=2.0, accel_vrw_m_s_rt_h=0.2)
    pre = calibrate_prefilter(model, RATE, samples=1 << 14, seed=3)
    kf = pre.filters["gyro_x"]
    assert kf is not None and kf.fit.p >= 1
    # The steady-state filter x̂_k = A x̂_{k−1} + K z_k on white z of variance s²: output variance
    # s²·Σ_j (H A^j K)² (impulse response), compared with the simulated ratio.
    h, x = [], kf.K_ss.copy()
    for _ in range(400):
        h.append(float(kf.H @ x))
        x = kf.A_ss @ x
    ratio_theory = float(np.sum(np.square(h)))
    rng = np.random.default_rng(5)
    err = rng.normal(0.0, 1e-3, (8, 4000, 3))
    true = np.tile([0.0, 0.0, 0.3], (4000, 1))  # a constant true rate on gyro_z
    g, a = pre.apply(err, err.copy(), true, None)
    out = g[:, 200:, 0]  # past the start-up transient
    assert np.var(out) / 1e-6 == pytest.approx(ratio_theory, rel=0.05)  # 31k samples: SE ≈ 1.5 %
    assert ratio_theory < 0.9  # the filter does lower the sample scatter
    # a constant true signal passes untouched: the error left is the same as with no true signal
    g0, _ = pre.apply(err, err.copy(), None, None)
    np.testing.assert_allclose(g[:, :, 2], g0[:, :, 2], rtol=0, atol=1e-12)


def test_catalog_part_filters_halve_motion_and_are_refused():
    """On a catalog part the white channels get a flat gain ≈ 0.5 (DC included): refused, and
    the message names the gains. The response table reports every channel."""
    part = get_part("STIM300")
    pre = calibrate_prefilter(part, 200.0, samples=4096, seed=1)
    gains = pre.dc_gains(200.0)
    assert set(gains) == set(pre.filters)
    low = min(gains, key=gains.get)
    assert gains[low] < 0.6   # white channels: the flat ≈ 0.5 of the closed form above
    frame = pre.response_frame(200.0)
    assert list(frame["channel"]) == list(pre.filters) and frame["dc_gain"].between(0, 1.1).all()
    with pytest.raises(InputError, match=rf"DC gain .*{low} {gains[low]:.3f}") as exc:
        pre.check_dc_gain(200.0)
    assert exc.value.field == "prefilter"
    s = get_preset("airborne_xband")
    with pytest.raises(InputError, match="DC gain"):
        simulate_motion(s, part, 64, 1, prefilter=pre, keep_series=False)
    with pytest.raises(InputError, match="DC gain"):
        run_mc(get_preset("automotive_77ghz"), part, 8, 1,
               options=McOptions(prefilter="kalman", prefilter_calibration_samples=4096))


def test_a_filter_with_unit_dc_gain_is_accepted_and_deterministic():
    """Noise-free channels are left alone (gain 1): such a filter passes the check."""
    model = NoiseModel(rate_hz=RATE, gyro_arw_deg_rt_h=2.0)
    pre = calibrate_prefilter(model, RATE, samples=4096)
    assert pre.filters["accel_x"] is None and pre.filters["gyro_y"] is not None
    unit = ImuPrefilter("kalman", {ch: None for ch in pre.filters})
    assert unit.check_dc_gain(RATE) == {ch: 1.0 for ch in pre.filters}
    assert DC_GAIN_TOLERANCE == 0.01
    with pytest.raises(InputError, match="pre-filter"):
        calibrate_prefilter(model, RATE, kind="median")
    with pytest.raises(InputError, match="1024"):
        calibrate_prefilter(model, RATE, samples=100)
    s = get_preset("automotive_77ghz")
    a = simulate_motion(s, model, 64, 1, prefilter=unit, keep_series=False)
    b = simulate_motion(s, model, 64, 1, keep_series=False)
    np.testing.assert_array_equal(a.residual_rms_deg, b.residual_rms_deg)
    assert a.prefilter == "kalman" and b.prefilter == "none"


@pytest.mark.slow
def test_cli_json_carries_the_dc_gains(tmp_path, capsys):
    """A model whose only noisy channels are strongly coloured (a slow Gauss–Markov bias on the
    accelerometers, φ → 1) keeps DC gain 1 within 1 %: the run goes ahead and the JSON reports
    the gains; a catalog part is refused with the gains in the error."""
    model = {"rate_hz": 200.0, "effects": [
        {"name": "gauss_markov", "channel": f"accel_{ax}", "params": {"sigma": 5e-3, "tau_s": 200.0}}
        for ax in "xyz"]}
    mpath = tmp_path / "m.json"
    mpath.write_text(json.dumps(model))
    spath = tmp_path / "s.json"
    get_preset("automotive_77ghz").save(spath)
    assert main(["mc", "--scenario", str(spath), "--model", str(mpath), "--trials", "8", "--seed", "2",
                 "--prefilter", "rts", "--json", "-"]) == 0
    out = json.loads(capsys.readouterr().out)
    gains = out["prefilter_dc_gain"]
    assert out["prefilter"] == "rts" and set(gains) == {"gyro_x", "gyro_y", "gyro_z",
                                                           "accel_x", "accel_y", "accel_z"}
    assert all(abs(g - 1.0) <= 0.01 for g in gains.values())
    assert out["aiding"] == "none"
    code = main(["mc", "--scenario", str(spath), "--part", "MPU-6050", "--trials", "8", "--prefilter",
                 "kalman", "--json", "-"])
    assert code != 0 and "DC gain" in capsys.readouterr().err
