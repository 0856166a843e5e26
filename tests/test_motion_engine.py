"""simulate_motion end to end: reproducibility, closed forms through the whole chain, CLI."""

from __future__ import annotations

import json
import math

import numpy as np
import plotly.graph_objects as go
import pytest

from budget.cli.main import main
from budget.errors import InputError
from budget.imu.noise_model import NoiseModel
from budget.motion import aperture_samples, simulate_motion
from budget.motion.geometry import los_unit_vector
from budget.nav.platform import Disturbance
from budget.plots.motion import plot_metric_histograms, plot_phase_error, plot_position_error
from budget.presets import get_preset
from budget.scenario import Scenario
from budget.units import G0

# Tc ≈ 1 s at 200 Hz keeps the tests fast.
SCEN = Scenario(name="test_xband", carrier_frequency_hz=10e9, slant_range_m=1000.0, azimuth_resolution_m=0.3,
                range_resolution_m=0.3, platform_speed_m_s=50.0, depression_deg=25.0, squint_deg=5.0,
                lever_arm_m=(0.4, -0.1, 0.3), imu_rate_hz=200.0)
MODEL = NoiseModel(gyro_arw_deg_rt_h=0.3, gyro_bias_instability_deg_h=2.0, gyro_bias_repeatability_deg_h=5.0,
                   accel_vrw_m_s_rt_h=0.05, accel_bias_instability_ug=100.0, accel_bias_repeatability_ug=500.0,
                   accel_scale_factor_ppm=500.0, accel_misalignment_mrad=0.5, gyro_misalignment_mrad=0.5)
FIELDS = ("constant_rad", "linear_edge_rad", "quadratic_edge_rad", "cubic_edge_rad", "residual_rms_deg",
          "peak_range_error_m", "position_error_m", "range_error_m")


def _same(a, b, n=None):
    for f in FIELDS:
        x, y = getattr(a, f), getattr(b, f)
        np.testing.assert_array_equal(x[:n] if n else x, y[:n] if n else y, err_msg=f)


def test_reproducible_whatever_chunking_workers_or_trial_count():
    ref = simulate_motion(SCEN, MODEL, 200, seed=42)
    _same(ref, simulate_motion(SCEN, MODEL, 200, seed=42, chunk_size=64))
    _same(ref, simulate_motion(SCEN, MODEL, 200, seed=42, chunk_size=100, workers=2))
    _same(ref, simulate_motion(SCEN, MODEL, 130, seed=42, chunk_size=64), n=130)
    other = simulate_motion(SCEN, MODEL, 200, seed=43)
    assert not np.array_equal(ref.quadratic_edge_rad, other.quadratic_edge_rad)
    n = aperture_samples(SCEN)
    assert n == round(SCEN.tc_s * 200) + 1
    assert ref.position_error_m.shape == (200, n, 3) and ref.range_error_m.shape == (200, 1, n)


def test_random_disturbance_is_also_chunk_invariant():
    dist = Disturbance(random=[{"axis": "heave", "frequency_hz": [0.1, 3.0], "psd_m2_per_hz": [1e-3, 1e-4]},
                               {"axis": "roll", "frequency_hz": [0.1, 1.0], "psd_rad2_per_hz": [1e-4, 1e-5]}])
    a = simulate_motion(SCEN, MODEL, 70, seed=5, disturbance=dist)
    b = simulate_motion(SCEN, MODEL, 70, seed=5, disturbance=dist, chunk_size=64, workers=2)
    _same(a, b)


def test_accel_bias_through_the_whole_chain():
    """Bias b only, scene point far away (constant LOS u): Δr = (u·b)·t²/2 and the edge QPE is
    (4π/λ)·(u·b)·T²/8 = π·Δr(T)/λ; the position error (true − measured) is −b·t²/2."""
    scen = SCEN.model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0)})
    u = los_unit_vector(scen.depression_deg, scen.squint_deg)
    res = simulate_motion(scen, NoiseModel(accel_bias_repeatability_ug=1000.0), 500, seed=1, targets=1e9 * u)
    t = res.time_s
    e = res.position_error_m
    b = -2 * e[:, -1] / t[-1] ** 2
    np.testing.assert_allclose(e, -b[:, None, :] * (t**2 / 2)[None, :, None], rtol=1e-10, atol=1e-15)
    np.testing.assert_allclose(b.std(axis=0), 1000e-6 * G0, rtol=0.15)  # 500 trials: SE 3 %
    dr_end = (b @ u) * t[-1] ** 2 / 2
    # the LOS turns by L/R = 50 m / 1e9 m over the aperture: |e|·5e-8 ≈ 1e-9 m
    close = dict(rtol=1e-6, atol=2e-9)
    np.testing.assert_allclose(res.range_error_m[:, 0, -1], dr_end, **close)
    lam = scen.wavelength_m
    np.testing.assert_allclose(res.quadratic_edge_rad[:, 0] * lam / math.pi, dr_end, **close)
    np.testing.assert_allclose(res.peak_range_error_m[:, 0], np.abs(dr_end), **close)
    np.testing.assert_allclose(res.peak_range_cells[:, 0] * scen.range_resolution_m, np.abs(dr_end), **close)
    assert np.all(np.abs(res.cubic_edge_rad) < 1e-6 * np.abs(res.quadratic_edge_rad).max())


def test_heave_with_accel_scale_factor():
    """Scale factor β on the true specific force g + ḧ: the z error is β·(g·t²/2 + h(t) − h(0) − ḣ(0)·t)
    (computed − true); tolerance covers the O(ω·dt·t) rectangle-rule error on the sinusoid."""
    amp, f = 0.5, 0.5
    dist = Disturbance(sinusoids=[{"axis": "heave", "frequency_hz": f, "amplitude_m": amp}])
    scen = SCEN.model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0), "imu_rate_hz": 1000.0})
    res = simulate_motion(scen, NoiseModel(accel_scale_factor_ppm=2000.0), 64, seed=2, disturbance=dist)
    t = res.time_s
    w = 2 * math.pi * f
    h = amp * np.sin(w * t)
    shape = G0 * t**2 / 2 + h - h[0] - amp * w * t
    ez = -res.position_error_m[:, :, 2]
    beta = ez[:, -1] / shape[-1]
    tol = np.abs(beta).max() * amp * (w * t[-1] / 1000.0 * w * t[-1])
    np.testing.assert_allclose(ez, beta[:, None] * shape[None, :], rtol=0, atol=tol)
    assert np.abs(beta).std() > 0 and np.abs(beta).max() < 5 * 2000e-6


def test_perfect_imu_has_no_motion_error_even_with_disturbance():
    dist = Disturbance(sinusoids=[{"axis": "roll", "frequency_hz": 0.4, "amplitude_rad": 0.05},
                                  {"axis": "sway", "frequency_hz": 0.2, "amplitude_m": 0.3}])
    res = simulate_motion(SCEN, NoiseModel(), 10, seed=0, disturbance=dist)
    assert not res.position_error_m.any() and not res.range_error_m.any()


def test_initial_errors_and_several_targets():
    targets = np.array([[0.0, 3000.0, -1000.0], [200.0, 2500.0, -1200.0]])
    res = simulate_motion(SCEN, NoiseModel(), 300, seed=3, targets=targets,
                          initial_errors={"velocity_sigma_m_s": (0.0, 0.01, 0.0)})
    assert res.quadratic_edge_rad.shape == (300, 2)
    e = res.position_error_m
    dv = -(e[:, -1, 1] - e[:, 0, 1]) / res.time_s[-1]
    np.testing.assert_allclose(dv.std(), 0.01, rtol=0.2)
    np.testing.assert_allclose(e[:, :, 1], -dv[:, None] * res.time_s[None, :], atol=1e-14)


def test_result_summary_frame_json_and_plots():
    res = simulate_motion(SCEN, MODEL, 20, seed=4)
    s = res.to_dict()
    assert s["trials"] == 20 and s["tc_s"] == pytest.approx(SCEN.tc_s) and s["seed"] == 4
    assert set(s["statistics"]["quadratic_edge_rad"]) == {"rms", "median", "p95"}
    frame = res.to_frame()
    assert len(frame) == 20 and {"trial", "target", "residual_rms_deg", "peak_range_cells"} <= set(frame)
    j = res.to_dict()
    for key in ("trials", "tc_s", "peak_range_error_m", "quadratic_edge_rad", "cubic_edge_rad", "residual_rms_deg"):
        assert key in j
    assert len(j["residual_rms_deg"]) == 20
    assert isinstance(res.summary(), str) and "quadratic_edge_rad" in res.summary()
    for fig in (plot_position_error(res), plot_phase_error(res), plot_metric_histograms(res)):
        assert isinstance(fig, go.Figure) and len(fig.data) > 0
    lean = simulate_motion(SCEN, MODEL, 20, seed=4, keep_series=False)
    np.testing.assert_array_equal(lean.quadratic_edge_rad, res.quadratic_edge_rad)
    with pytest.raises(ValueError, match="keep_series"):
        plot_position_error(lean)


def test_engine_input_errors():
    with pytest.raises(InputError, match="n_trials"):
        simulate_motion(SCEN, MODEL, 0, seed=1)
    with pytest.raises(InputError, match="seed"):
        simulate_motion(SCEN, MODEL, 5, seed=-1)
    fast = Disturbance(sinusoids=[{"axis": "heave", "frequency_hz": 150.0, "amplitude_m": 0.01}])
    with pytest.raises(InputError, match="IMU rate"):
        simulate_motion(SCEN, MODEL, 5, seed=1, disturbance=fast)
    short = SCEN.model_copy(update={"imu_rate_hz": 2.0})
    with pytest.raises(InputError, match="at least 5 samples"):
        simulate_motion(short, MODEL, 5, seed=1)
    with pytest.raises(InputError, match="keep_series=False"):
        simulate_motion(SCEN, MODEL, 10_000_000, seed=1)


def test_cli_motion_json(tmp_path, capsys):
    scen_path = tmp_path / "s.json"
    SCEN.save(scen_path)
    model_path = tmp_path / "m.json"
    MODEL.save(model_path)
    out = tmp_path / "out.json"
    rc = main(["motion", "--scenario", str(scen_path), "--model", str(model_path), "--trials", "12",
               "--seed", "7", "--json", str(out)])
    assert rc == 0
    data = json.loads(out.read_text())
    assert data["trials"] == 12 and data["tc_s"] == pytest.approx(SCEN.tc_s)
    for key in ("peak_range_error_m", "quadratic_edge_rad", "cubic_edge_rad", "residual_rms_deg"):
        assert len(data[key]) == 12
    ref = simulate_motion(SCEN, MODEL, 12, seed=7)
    np.testing.assert_allclose(data["quadratic_edge_rad"], ref.quadratic_edge_rad[:, 0])

    cat = tmp_path / "parts.csv"
    cat.write_text("part_id,grade,source,gyro_arw_deg_rt_h,accel_vrw_m_s_rt_h\nMYIMU,tactical,test,0.2,0.04\n")
    rc = main(["motion", "--preset", "airborne_xband", "--part", "MYIMU", "--catalog", str(cat),
               "--trials", "5", "--seed", "1"])
    assert rc == 0 and "MYIMU" in capsys.readouterr().out

    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"effects": [{"name": "white_noise", "channel": "gyro_q", "params": {"density": 1}}]}))
    capsys.readouterr()
    rc = main(["motion", "--scenario", str(scen_path), "--model", str(bad), "--trials", "5"])
    err = capsys.readouterr().err
    assert rc == 2 and "unknown channel 'gyro_q'" in err and err.count("\n") == 1
    assert main(["motion", "--preset", "airborne_xband", "--model", str(model_path), "--trials", "0"]) == 2


def test_presets_run():
    for name in ("automotive_77ghz", "sas_100khz"):
        res = simulate_motion(get_preset(name), MODEL, 4, seed=0, keep_series=False)
        assert np.all(np.isfinite(res.residual_rms_deg))


def test_bad_disturbance_or_initial_errors_dicts():
    with pytest.raises(InputError, match="velocity_sigma_m_s"):
        simulate_motion(SCEN, MODEL, 2, seed=0, initial_errors={"velocity_sigma_m_s": (0.0, -1.0, 0.0)})
    with pytest.raises(InputError, match="sinusoids"):
        simulate_motion(SCEN, MODEL, 2, seed=0, disturbance={"sinusoids": [{"axis": "heave"}]})
