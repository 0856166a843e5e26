"""The seed-paper cases at reduced size, checked against the papers' stated outcomes.

Full-size runs: ``examples/seed00*_*.py``. Thresholds below are the papers' figures (seed 001:
< 5 cm, < 0.001 m/s, < 1″ per imaging period) or their qualitative claims (seed 002: the
smoother is better; seed 003: fused best; seed 001 (4): slaving the PRF removes the distortion).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import fresnel

from budget.sar.point_target import azimuth_irf_metrics
from budget.seeds.master_slave import MasterSlaveParams, run_master_slave
from budget.seeds.prf_slaving import PrfParams, run_prf_slaving
from budget.seeds.sonar_fusion import SonarParams, run_sonar_fusion
from budget.seeds.transfer_alignment import TransferParams, run_transfer_alignment
from budget.presets import get_preset


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_seed001_master_slave_variation_within_imaging_period():
    tc = get_preset("missile_borne").tc_s   # 0.75 s: the preset's imaging period
    r = run_master_slave(MasterSlaveParams(trials=3, imaging_periods_s=(tc, 2.0)),
                         rng=np.random.default_rng(11))
    t = r.table.set_index(["quantity", "period_s"])
    assert t.loc[("position_m", tc), "p95"] < 0.05          # seed 001: < 5 cm
    assert t.loc[("position_m", 2.0), "median"] < 0.05
    assert t.loc[("velocity_m_s", 2.0), "p95"] < 0.001      # < 0.001 m/s
    assert t.loc[("attitude_arcsec", 2.0), "p95"] < 1.0     # < 1″
    # the corrections bound the absolute error near the master's accuracy (R: 2 m, 0.02 m/s)
    assert r.final_rms["position_m"] < 2.0 and r.final_rms["velocity_m_s"] < 0.02


def test_seed002_smoother_beats_filter():
    p = TransferParams(trials=6, rate_hz=20, duration_s=160, imaging_s=40, turn_period_s=20)
    r = run_transfer_alignment(p, rng=np.random.default_rng(12))
    imp = r.improvement(flexure_modelled=True)
    assert imp["heading_arcsec_predicted"] > 0.2       # the smoother's own σ: exact, no sampling
    assert imp["level_arcsec_rmse"] > 0.15
    assert imp["position_m_rmse"] > 0.3
    t = r.table.set_index(["method", "flexure_modelled"])
    # modelling the flexure as states helps the smoother's heading
    assert t.loc[("rts", True), "heading_arcsec_predicted"] < t.loc[("rts", False), "heading_arcsec_predicted"]


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_seed003_fused_compensation_is_best():
    r = run_sonar_fusion(SonarParams(trials=6, warmup_s=60.0), rng=np.random.default_rng(13))
    t = r.table.set_index(["case", "estimator"])
    rts = {c: t.loc[(c, "rts")] for c in ("gps", "dvl", "fused")}
    # focus: fused is (equal-)best — within 0.5 dB of the best single-sensor PSLR and ISLR
    for metric in ("pslr_db", "islr_db"):
        assert rts["fused"][metric] <= min(v[metric] for v in rts.values()) + 0.5
    # … and clearly better focused than GPS-only
    assert rts["fused"]["islr_db"] < rts["gps"]["islr_db"] - 3.0
    # placement: fused has the smallest whole LOS error; DVL-only drifts far away
    assert r.best("los_error_rms_m") == "fused"
    assert rts["dvl"]["los_error_rms_m"] > 10 * rts["fused"]["los_error_rms_m"]
    # INS-only is defocused: far worse than any aided case
    for c in rts:
        assert t.loc[("ins", "none"), "islr_db"] > rts[c]["islr_db"] + 5
    # the ideal is the window's own IRF (Taylor −35 dB)
    assert r.ideal["median_pslr_db"] < -34.5


def test_seed001_prf_slaving_removes_sampling_distortion():
    r = run_prf_slaving(PrfParams(trials=5), rng=np.random.default_rng(14))
    t = r.table.set_index(["case", "target_x_m"])
    ideal = azimuth_irf_metrics(np.zeros(64)).pslr_db[0]
    edge = max(t.index.get_level_values(1))
    slaved = t.loc["slaved PRF, aided-IMU speed"]
    fixed = t.loc["fixed PRF"]
    assert np.all(np.abs(slaved["pslr_db"] - ideal) < 0.05)
    assert np.all(np.abs(slaved["shift_m"]) < 0.01)
    assert fixed.loc[edge, "pslr_db"] > ideal + 2.0          # asymmetric sidelobes rise
    assert abs(fixed.loc[edge, "shift_m"]) > 0.3              # azimuth distortion (m)
    assert fixed.loc[edge, "max_sample_offset_m"] > 0.1
    unaided = t.loc["slaved PRF, unaided-IMU speed"]
    assert unaided.loc[edge, "pslr_db"] > slaved.loc[edge, "pslr_db"]


@pytest.mark.parametrize("quad_rad", [0.0, np.pi / 4, np.pi / 2])
def test_point_target_quadratic_phase_peak_loss_is_fresnel(quad_rad):
    """Edge quadratic phase β on a rect window: peak = |∫₀¹ e^{jβx²} dx| =
    √(π/2β)·|C(z) + jS(z)|, z = √(2β/π) (Fresnel integrals)."""
    P = 1024
    x = (np.arange(P) - (P - 1) / 2) / (P / 2)
    m = azimuth_irf_metrics(quad_rad * x ** 2)
    if quad_rad == 0:
        expect = 0.0
        assert abs(m.pslr_db[0] + 13.26) < 0.02 and abs(m.width_cells[0] - 0.886) < 0.005
    else:
        S, C = fresnel(np.sqrt(2 * quad_rad / np.pi))
        expect = -20 * np.log10(np.sqrt(np.pi / (2 * quad_rad)) * abs(C + 1j * S))
    assert abs(m.peak_loss_db[0] - expect) < 0.01


def test_seed002_ddf2_smoother_helps_only_at_large_misalignment():
    from budget.seeds.large_misalignment import MisalignmentParams, run_large_misalignment
    p = MisalignmentParams(heading_sigma_deg=(0.5, 10.0), trials=8, duration_s=160.0, imaging_s=40.0)
    r = run_large_misalignment(p, rng=np.random.default_rng(15)).table.set_index("heading_sigma_deg")
    assert abs(r.loc[0.5, "ddf2_gain"]) < 0.05        # small angles: the linear model is exact enough
    assert r.loc[10.0, "ddf2_gain"] > 0.5             # 10°: the small-angle smoother breaks down
