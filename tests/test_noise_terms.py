"""IEEE-952 term fit on synthetic data with known terms, Allan tables, real ADIS16405 data."""

import math

import numpy as np
import pytest

from budget import units as u
from budget.errors import InputError
from budget.noise import (allan_deviation, characterize, fit_noise_terms, read_adev_table,
                          read_log)
from budget.noise.adev_table import edf_from_interval
from budget.noise.allan import edf_simple
from budget.noise.synth import imu_noise
from budget.noise.terms import adev_model

RATE = 100.0


def test_adev_model_closed_form():
    tau = np.array([0.5, 2.0])
    expect = np.sqrt(3 * 0.1 ** 2 / tau ** 2 + 0.2 ** 2 / tau + 2 * math.log(2) / math.pi * 0.3 ** 2
                     + 0.4 ** 2 * tau / 3 + 0.5 ** 2 * tau ** 2 / 2)
    np.testing.assert_allclose(adev_model(tau, 0.1, 0.2, 0.3, 0.4, 0.5), expect)


@pytest.mark.parametrize("seed", [1, 2])
def test_recovers_white_flicker_random_walk(seed):
    """N ± 3 %, B ± 30 %, K ± 60 %.

    K rests on the last few octaves of one 5.8 h record, whose random-walk sample path
    scatters a lot, and B trades off against it: over seeds 1–12 the estimates were
    0.52–1.15 × K and 0.92–1.26 × B (N within ±1 %).
    """
    true = dict(N=1e-3, B=2e-4, K=3e-5)
    y = imu_noise(2 ** 21, RATE, np.random.default_rng(seed), **true)
    fit = fit_noise_terms(allan_deviation(y, RATE))
    assert fit.N == pytest.approx(true["N"], rel=0.03)
    assert fit.B == pytest.approx(true["B"], rel=0.30)
    assert fit.K == pytest.approx(true["K"], rel=0.60)
    assert fit.resolved["N"] and fit.resolved["B"] and fit.resolved["K"]
    assert fit.R is None or not fit.resolved["R"]


def test_recovers_quantization_white_ramp():
    """Q ± 5 %, N ± 10 %, R ± 20 %; no flicker or random walk resolved."""
    true = dict(Q=1e-4, N=1e-4, R=1e-7)
    y = imu_noise(2 ** 20, RATE, np.random.default_rng(7), **true)
    fit = fit_noise_terms(allan_deviation(y, RATE))
    assert fit.Q == pytest.approx(true["Q"], rel=0.05)
    assert fit.N == pytest.approx(true["N"], rel=0.10)
    assert fit.R == pytest.approx(true["R"], rel=0.20)
    assert not (fit.resolved["B"] or fit.resolved["K"])


def test_subset_of_terms_and_summary():
    y = np.random.default_rng(0).normal(0, 0.05, 100_000)
    fit = fit_noise_terms(allan_deviation(y, RATE), terms=("N",))
    assert fit.N == pytest.approx(0.05 / math.sqrt(RATE), rel=0.01)
    assert fit.Q is None and fit.B is None and "absent" in fit.summary()
    assert list(fit.to_frame()["term"]) == ["Q", "N", "B", "K", "R"]
    with pytest.raises(InputError, match="unknown noise term"):
        fit_noise_terms(allan_deviation(y, RATE), terms=("X",))


def _write_table(path, r, unit_tag, factor, ci=True):
    lines = ["channel,tau_s,adev" + (",lci,uci" if ci else "")]
    for i in range(r.tau_s.size):
        row = [f"gyro_x_{unit_tag}", repr(float(r.tau_s[i])), repr(float(r.adev[i] / factor))]
        if ci:
            row += [repr(float(r.lo[i] / factor)), repr(float(r.hi[i] / factor))]
        lines.append(",".join(row))
    path.write_text("\n".join(lines) + "\n")
    return path


def test_table_round_trip_recovers_edf_and_units(tmp_path):
    y = imu_noise(50_000, RATE, np.random.default_rng(3), N=1e-3, B=1e-4)
    r = allan_deviation(y, RATE, ci=0.95)
    p = _write_table(tmp_path / "t.csv", r, "dps", u.DEG)
    t = read_adev_table(p, RATE, 50_000)["gyro_x"]
    np.testing.assert_allclose(t.adev, r.adev, rtol=1e-12)
    np.testing.assert_allclose(t.edf, r.edf, rtol=1e-6)
    assert t.unit == "rad/s" and t.samples == 50_000
    # without intervals the EDF comes from the formula with the slope-based noise type
    p2 = _write_table(tmp_path / "t2.csv", r, "dps", u.DEG, ci=False)
    t2 = read_adev_table(p2, RATE, 50_000)["gyro_x"]
    np.testing.assert_allclose(t2.edf, edf_simple(50_001, t2.m, t2.alpha))


def test_gaussian_interval_with_negative_lower_bound():
    """lci ≤ 0 (symmetric interval adev ± z·s): ν = z²/(2h²), h = half-width / adev."""
    nu = edf_from_interval(np.array([1.0]), np.array([-0.1]), np.array([2.1]), 0.95)
    assert nu[0] == pytest.approx(1.959964 ** 2 / (2 * 1.1 ** 2), rel=1e-5)


@pytest.mark.parametrize("text, kw, match", [
    ("channel,tau_s\ngyro_x_dps,1\n", {}, "missing"),
    ("channel,tau_s,adev,foo\ngyro_x_dps,1,1,1\n", {}, "unknown"),
    ("channel,tau_s,adev\ngyro_x_deg,0.01,1\n", {}, "not understood"),
    ("channel,tau_s,adev\ngyro_x_dps,0.015,1\n", {}, "whole number"),
    ("channel,tau_s,adev\ngyro_x_dps,600,1\n", {}, "longer than half"),
    ("channel,tau_s,adev\ngyro_x_dps,0.02,1\ngyro_x_dps,0.01,1\n", {}, "must increase"),
    ("channel,tau_s,adev\ngyro_x_dps,0.01,-1\n", {}, "positive"),
    ("channel,tau_s,adev,lci,uci\ngyro_x_dps,0.01,1,1.2,1.5\n", {}, "lci ≤ adev"),
    ("channel,tau_s,adev\ngyro_x_dps,0.01,1\ngyro_x_rps,0.02,1\n", {}, "two unit tags"),
    ("channel,tau_s,adev\ngyro_x_dps,0.01,1\n", {"rate_hz": None}, "rate"),
    ("channel,tau_s,adev\ngyro_x_dps,0.01,1\n", {"samples": 0}, "record length"),
    # every short τ 8 % long: a curve taken at another rate (≈ 92.6 Hz), not time-stamp scatter
    ("channel,tau_s,adev\n" + "".join(f"gyro_x_dps,{1.08 * m / RATE!r},{1 / m}\n" for m in (1, 2, 4, 8, 16)),
     {}, r"every short-τ row alike.*about 92\.59"),
])
def test_table_errors(tmp_path, text, kw, match):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    args = {"rate_hz": RATE, "samples": 100_000} | kw
    with pytest.raises(InputError, match=match):
        read_adev_table(p, args["rate_hz"], args["samples"])


def test_characterize_synthetic_log_row_units(tmp_path):
    """Catalog row: ARW = N·60 deg/√h, BI = 0.664·B deg/h, VRW = N·60 m/s/√h, BI µg (worst axis)."""
    rng = np.random.default_rng(9)
    n = 2 ** 16
    Ng = [u.deg_rt_h_to_rad_s_rt_hz(v) for v in (0.3, 0.5, 0.4)]
    Na = u.m_s_rt_h_to_m_s2_rt_hz(0.05)
    t = np.arange(n) / RATE
    cols = {"time_s": t}
    for i, ax in enumerate("xyz"):
        cols[f"gyro_{ax}_rps"] = imu_noise(n, RATE, rng, N=Ng[i])
    for ax in "xyz":
        cols[f"accel_{ax}_mps2"] = imu_noise(n, RATE, rng, N=Na)
    import pandas as pd
    path = tmp_path / "log.csv"
    pd.DataFrame(cols).to_csv(path, index=False)
    c = characterize(read_log(path), part_id="SYN-1", grade="tactical")
    assert c.part.gyro_arw_deg_rt_h == pytest.approx(0.5, rel=0.05)  # the worst axis
    assert c.part.accel_vrw_m_s_rt_h == pytest.approx(0.05, rel=0.05)
    assert c.part.bias_instability_convention == "adev_min"
    assert set(c.channels) == {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"}
    js = c.to_dict()
    assert set(js["channels"]["gyro_y"]) == {"Q", "N", "B", "K", "R"}
    assert js["channels"]["gyro_y"]["N"] == pytest.approx(Ng[1], rel=0.05)
    assert "worst axis" in js["combine_rule"]


# ---- real data: ADIS16405 (datasheet ARW 2.0 deg/√h, BI 25.2 deg/h, VRW 0.2 m/s/√h, 200 µg)

DATASHEET = {"gyro_arw_deg_rt_h": 2.0, "gyro_bias_instability_deg_h": 25.2,
             "accel_vrw_m_s_rt_h": 0.2, "accel_bias_instability_ug": 200.0}


@pytest.mark.shared_data
def test_adis_table_matches_datasheet_within_factor_1_5(shared_data):
    tabs = read_adev_table(shared_data / "adev" / "adis16405.csv", 100.0, 1_000_000)
    c = characterize(tabs, part_id="ADIS16405-measured")
    for key, ref in DATASHEET.items():
        val = getattr(c.part, key)
        assert ref / 1.5 <= val <= ref * 1.5, (key, val, ref)
    assert c.part.grade == "industrial"


@pytest.mark.shared_data
def test_adis_partial_log_arw(shared_data):
    log = read_log(shared_data / "logs" / "adis16405_static_2.csv.gz", max_rows=200_000)
    c = characterize(log, grade="industrial")
    assert 2.0 / 1.5 <= c.part.gyro_arw_deg_rt_h <= 2.0 * 1.5
    assert 0.2 / 1.5 <= c.part.accel_vrw_m_s_rt_h <= 0.2 * 1.5


@pytest.mark.slow
@pytest.mark.shared_data
def test_full_log_allan_equals_published_table(shared_data):
    """The published curve of static_1 is the same data: our ADEV reproduces it (9 digits)."""
    tabs = read_adev_table(shared_data / "adev" / "adis16405.csv", 100.0, 1_000_000)
    log = read_log(shared_data / "logs" / "adis16405_static_1.csv.gz")
    for ch in ("gyro_x", "accel_z"):
        t = tabs[ch]
        r = allan_deviation(log.channels[ch], log.rate_hz, t.tau_s)
        np.testing.assert_allclose(r.adev, t.adev, rtol=2e-5)


def test_table_other_layouts_read_as_the_long_one(tmp_path):
    """Header names in other spellings (Channel, Tau, ADEV), the Allan variance instead of the
    deviation, and the wide layout (tau_s + one column per channel) give the same curve."""
    y = imu_noise(50_000, RATE, np.random.default_rng(3), N=1e-3, B=1e-4)
    r = allan_deviation(y, RATE)
    ref = read_adev_table(_write_table(tmp_path / "t.csv", r, "dps", u.DEG, ci=False), RATE, 50_000)["gyro_x"]
    dev = [float(a) for a in r.adev / u.DEG]
    taus = [repr(float(x)) for x in r.tau_s]
    texts = {
        "names": "Channel,Tau,ADEV\n" + "".join(f"gyro_x_dps,{t},{a!r}\n" for t, a in zip(taus, dev)),
        "avar": "channel,tau_s,avar\n" + "".join(f"gyro_x_dps,{t},{a * a!r}\n" for t, a in zip(taus, dev)),
        "wide": "tau_s,gyro_x_dps,gyro_y_rps\n" + "".join(f"{t},{a!r},{a * u.DEG!r}\n" for t, a in zip(taus, dev)),
    }
    for name, text in texts.items():
        p = tmp_path / f"{name}.csv"
        p.write_text(text)
        tabs = read_adev_table(p, RATE, 50_000)
        np.testing.assert_allclose(tabs["gyro_x"].adev, ref.adev, rtol=1e-12, err_msg=name)
        np.testing.assert_allclose(tabs["gyro_x"].edf, ref.edf, rtol=1e-12, err_msg=name)
    np.testing.assert_allclose(tabs["gyro_y"].adev, ref.adev, rtol=1e-12)  # rad/s column of the wide table


@pytest.mark.parametrize("text, match", [
    ("tau_s,gyro_x,accel_y_mps2\n0.01,1,1\n", "column 'gyro_x' is not a channel with its unit"),
    ("channel,tau_s,adev,avar\ngyro_x_dps,0.01,1,1\n", "both adev and avar"),
    ("channel,tau_s,avar\ngyro_x_dps,0.01,-1\n", "positive"),
    ("tau_s,gyro_x_dps\n0.01,1\n0.02,x\n", "row 3, field gyro_x_dps"),
    ("Tau,TAU_S,adev,channel\n0.01,0.01,1,gyro_x_dps\n", "two header names"),
])
def test_table_layout_errors_name_the_file_row_and_column(tmp_path, text, match):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    with pytest.raises(InputError, match=match) as err:
        read_adev_table(p, RATE, 100_000)
    assert "bad.csv" in str(err.value)


def test_any_table_with_a_tau_column_is_read_as_a_table_not_a_log(tmp_path):
    """A table in a layout the reader refuses still goes to the table reader (a layout error),
    not to the log reader (which would misread it as a 24-sample log)."""
    from budget.noise.measurement import read_measurement
    p = tmp_path / "other.csv"
    p.write_text("tau_s,adev,weight\n0.01,1,1\n")  # (n is read: allantools writes it)
    with pytest.raises(InputError, match="not an Allan table layout"):
        read_measurement(p, rate_hz=RATE, samples=100_000)
