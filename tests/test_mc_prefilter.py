"""Seed 000's ARMA-Kalman pre-filter in the Monte Carlo chain (issue: does it change the verdict?).

Checks against theory: on white noise the paper's filter (R = data variance, Q = δ₁) is a
steady-state linear filter whose output variance follows from its gain; a constant true signal
passes unchanged (the aperture mean is removed and restored); the trial chain stays
deterministic; aiding and pre-filtering together are refused with a clear error.
"""

from __future__ import annotations

import numpy as np
import pytest

from budget.catalog.io import get_part
from budget.errors import InputError
from budget.imu import NoiseModel
from budget.mc import run_mc
from budget.mc.options import McOptions
from budget.motion import simulate_motion
from budget.noise.prefilter import calibrate_prefilter
from budget.presets import get_preset
from budget.scenario import Scenario

RATE = 100.0


def test_prefilter_variance_matches_its_steady_state_gain_and_keeps_constants():
    model = NoiseModel(rate_hz=RATE, gyro_arw_deg_rt_h=2.0, accel_vrw_m_s_rt_h=0.2)
    pre = calibrate_prefilter(model, RATE, samples=1 << 15, seed=3)
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


def test_noise_free_channels_are_left_alone_and_bad_kinds_rejected():
    model = NoiseModel(rate_hz=RATE, gyro_arw_deg_rt_h=2.0)
    pre = calibrate_prefilter(model, RATE, samples=4096)
    assert pre.filters["accel_x"] is None and pre.filters["gyro_y"] is not None
    with pytest.raises(InputError, match="pre-filter"):
        calibrate_prefilter(model, RATE, kind="median")
    with pytest.raises(InputError, match="1024"):
        calibrate_prefilter(model, RATE, samples=100)


def test_motion_engine_with_prefilter_is_deterministic_and_lowers_fast_phase():
    s = get_preset("airborne_xband")
    part = get_part("ADIS16405")
    pre = calibrate_prefilter(part, s.imu_rate_hz, seed=1)
    a = simulate_motion(s, part, 64, 1, prefilter=pre, keep_series=False)
    b = simulate_motion(s, part, 64, 1, prefilter=pre, keep_series=False)
    free = simulate_motion(s, part, 64, 1, keep_series=False)
    np.testing.assert_array_equal(a.residual_rms_deg, b.residual_rms_deg)
    # ADIS16405 fails X band on fast phase; the filter lowers the fast (sample-scale) phase noise
    assert np.median(a.residual_rms_deg) < 0.95 * np.median(free.residual_rms_deg)


def test_mc_option_reports_the_prefilter_and_refuses_it_with_aiding():
    s = get_preset("automotive_77ghz")
    part = get_part("MPU-6050")
    res = run_mc(s, part, 64, 2, options=McOptions(prefilter="kalman"))
    assert res.to_json_dict()["prefilter"] == "kalman" and "pre-filter: kalman" in res.summary()
    again = run_mc(s, part, 64, 2, options=McOptions(prefilter="kalman"))
    assert again.p_pass_after == res.p_pass_after
    aided = Scenario.model_validate(s.model_dump() | {"aiding": [{"type": "gnss", "sigma_m": 0.02, "rate_hz": 10.0}]})
    with pytest.raises(InputError, match="aiding"):
        run_mc(aided, part, 64, 2, options=McOptions(prefilter="rts"))


def test_cli_prefilter_flag(tmp_path, capsys):
    import json

    from budget.cli.main import main

    path = tmp_path / "s.json"
    get_preset("automotive_77ghz").save(path)
    assert main(["mc", "--scenario", str(path), "--part", "MPU-6050", "--trials", "64", "--seed", "2",
                 "--prefilter", "rts", "--json", "-"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["prefilter"] == "rts" and 0.0 <= out["p_pass_after"] <= 1.0
