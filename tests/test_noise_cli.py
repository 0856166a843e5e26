"""``sar-budget noise characterize|arma``: JSON keys, appending to a catalog, bad input exit 2."""

import json

import numpy as np
import pandas as pd
import pytest

from budget.cli.main import main
from budget.noise.synth import imu_noise, simulate_arma
from budget.units import DEG


@pytest.fixture()
def log_csv(tmp_path):
    rng = np.random.default_rng(21)
    n, rate = 20_000, 100.0
    cols = {"time_s": np.round(np.arange(n) / rate, 4)}
    for ax in "xyz":
        cols[f"gyro_{ax}_dps"] = imu_noise(n, rate, rng, N=0.02, B=0.002) + 0.1
    cols["gyro_z_dps"] = simulate_arma([0.8397, 0.1288], [0.9596], 1e-6, n, rng)
    for ax in "xyz":
        cols[f"accel_{ax}_mps2"] = imu_noise(n, rate, rng, N=0.003, B=0.0005)
    path = tmp_path / "static.csv"
    pd.DataFrame(cols).to_csv(path, index=False)
    return path


def _json(capsys):
    return json.loads(capsys.readouterr().out)


def test_characterize_log_json(log_csv, capsys):
    assert main(["noise", "characterize", str(log_csv), "--grade", "tactical", "--json", "-"]) == 0
    out = _json(capsys)
    assert set(out["channels"]) == {"gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"}
    for terms in out["channels"].values():
        assert set(terms) == {"Q", "N", "B", "K", "R"}
    # N in rad/s/√Hz: 0.02 deg/s/√Hz white noise → 0.02·π/180
    assert out["channels"]["gyro_x"]["N"] == pytest.approx(0.02 * DEG, rel=0.05)
    assert out["part"]["gyro_arw_deg_rt_h"] == pytest.approx(0.02 * 60, rel=0.1)
    assert "worst axis" in out["combine_rule"]


def test_characterize_table_and_append(tmp_path, capsys):
    table = tmp_path / "adev.csv"
    # out to τ = 328 s of a 10⁴ s record: the floor 0.664·B = 0.002 deg/s crosses the white level
    # at τ = 100 s (a term the table does not resolve is left empty in the row: with τ ≤ 20 s, or
    # a 1000 s record, B is fitted but not resolved)
    tau = 2.0 ** np.arange(0, 16) / 100.0
    adev = np.sqrt(0.02 ** 2 / tau + (0.664 * 0.003) ** 2)
    lines = ["channel,tau_s,adev"] + [f"gyro_z_dps,{float(t)!r},{float(a)!r}" for t, a in zip(tau, adev)]
    table.write_text("\n".join(lines) + "\n")
    cat = tmp_path / "my_catalog.csv"
    args = ["noise", "characterize", str(table), "--rate-hz", "100", "--samples", "1000000",
            "--grade", "tactical", "--as-part", "MY-GYRO", "--append", str(cat), "--json", "-"]
    assert main(args) == 0
    out = _json(capsys)
    assert out["part"]["part_id"] == "MY-GYRO"
    assert out["part"]["gyro_arw_deg_rt_h"] == pytest.approx(1.2, rel=0.02)
    assert out["part"]["gyro_bias_instability_deg_h"] == pytest.approx(0.664 * 0.003 * 3600, rel=0.05)
    from budget.catalog.io import read_parts
    assert "MY-GYRO" in read_parts(cat)
    assert main(args) == 2  # duplicate id without --replace
    assert "already" in capsys.readouterr().err


def test_characterize_table_needs_rate_and_samples(tmp_path, capsys):
    """Both or neither: a table given neither is a digitised curve (tests/test_adev_limits.py)."""
    table = tmp_path / "adev.csv"
    table.write_text("channel,tau_s,adev\ngyro_z_dps,0.01,0.1\n")
    assert main(["noise", "characterize", str(table), "--rate-hz", "100"]) == 2
    err = capsys.readouterr().err
    assert "--rate-hz F --samples N" in err and "neither for a digitised datasheet curve" in err


def test_arma_json_keys(log_csv, capsys):
    assert main(["noise", "arma", str(log_csv), "--channel", "gyro_z", "--json", "-"]) == 0
    out = _json(capsys)
    assert [c["order"] for c in out["candidates"]] == ["white", "AR(1)", "AR(2)", "AR(3)", "ARMA(1,1)", "ARMA(2,1)"]
    assert {"order", "aic", "fpe", "params"} <= set(out["candidates"][0])
    assert out["selected"] == "ARMA(2,1)"
    assert out["variance_after"] < out["variance_before"]
    assert out["filter"]["response_gain"][0] < 1.0  # DC motion attenuated, reported


def test_bad_log_exit_2_one_line(tmp_path, capsys):
    p = tmp_path / "bad.csv"
    p.write_text("time_s,gyro_z_dps\n0,1\n0.01,\n0.02,3\n" + "".join(f"{0.01 * k:.2f},1\n" for k in range(3, 200)))
    assert main(["noise", "arma", str(p), "--channel", "gyro_z"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "missing_value [gyro_z_dps]" in err and "(rows 3)" in err
    assert "--repair" in err
    assert main(["noise", "characterize", "/nonexistent.csv"]) == 2
