"""Model-gap inputs, bad-input errors and the ``sar-budget gap`` CLI contract."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from budget.cli.main import main
from budget.errors import InputError
from budget.gap import log_from_arrays, run_gap
from budget.imu import NoiseModel, simulate_static_log
from budget.units import CHANNELS, rad_s_to_dps

RATE = 100.0
BASE = NoiseModel(rate_hz=RATE, gyro_arw_deg_rt_h=0.5, gyro_bias_instability_deg_h=5.0,
                  accel_vrw_m_s_rt_h=0.05, accel_bias_instability_ug=50.0)
MODEL_JSON = {"rate_hz": RATE, "gyro_arw_deg_rt_h": 0.5, "gyro_bias_instability_deg_h": 5.0,
              "accel_vrw_m_s_rt_h": 0.05, "accel_bias_instability_ug": 50.0}


def write_log(path, model, n, seed, *, drop=(), rate=RATE):
    """Canonical log CSV (deg/s, m/s²) of ``model`` with columns in ``drop`` left out."""
    x = simulate_static_log(model, n, rate, np.random.default_rng(seed))
    cols = {"time_s": np.arange(n) / rate}
    for ch in CHANNELS:
        if ch in drop:
            continue
        if ch.startswith("gyro"):
            cols[f"{ch}_dps"] = rad_s_to_dps(x[ch])
        else:
            cols[f"{ch}_mps2"] = x[ch]
    pd.DataFrame(cols).to_csv(path, index=False, float_format="%.9g")
    return path


def write_model(path, data):
    path.write_text(json.dumps(data))
    return path


@pytest.fixture(scope="module")
def sine_log(tmp_path_factory):
    model = BASE.with_effect({"name": "sinusoid", "channel": "gyro_x",
                              "params": {"frequency_hz": 4.2, "amplitude": 2e-3}})
    return write_log(tmp_path_factory.mktemp("gap") / "log.csv", model, 16_384, 21)


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_cli_contract(sine_log, tmp_path):
    model = write_model(tmp_path / "model.json", MODEL_JSON)
    rep, upd = tmp_path / "report.json", tmp_path / "updated.json"
    code = main(["gap", str(sine_log), "--model", str(model), "--report", str(rep),
                 "--out-model", str(upd), "--seed", "3"])
    assert code == 0
    out = json.loads(rep.read_text())
    assert isinstance(out["gap_before"], float) and isinstance(out["gap_after"], float)
    assert out["gap_after"] < out["gap_before"] / 3
    assert set(out["channels"]) == set(CHANNELS)
    for ch in CHANNELS:
        assert {"gap_before", "gap_after"} <= set(out["channels"][ch])
    eff = out["effects"][0]
    assert {"name", "channel", "params", "gap_before", "gap_after"} <= set(eff)
    assert (eff["name"], eff["channel"]) == ("sinusoid", "gyro_x")
    # SI channel units although the log is in deg/s: amplitude in rad/s
    assert eff["params"]["amplitude"] == pytest.approx(2e-3, rel=0.15)
    assert eff["params"]["frequency_hz"] == pytest.approx(4.2, abs=0.05)
    updated = NoiseModel.load(upd)
    assert [(f.name, f.channel) for f in updated.effects] == [("sinusoid", "gyro_x")]
    assert updated.rate_hz == RATE
    # the updated model explains the log: nothing more is named
    rep2 = tmp_path / "report2.json"
    assert main(["gap", str(sine_log), "--model", str(upd), "--report", str(rep2), "--seed", "4"]) == 0
    assert json.loads(rep2.read_text())["effects"] == []


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_cli_same_seed_same_report(sine_log, tmp_path):
    model = write_model(tmp_path / "model.json", MODEL_JSON)
    outs = []
    for name in ("a.json", "b.json"):
        assert main(["gap", str(sine_log), "--model", str(model), "--report", str(tmp_path / name),
                     "--seed", "5", "--channels", "gyro_x,accel_y"]) == 0
        outs.append(json.loads((tmp_path / name).read_text()))
    assert outs[0]["gap_before"] == outs[1]["gap_before"]
    assert outs[0]["effects"] == outs[1]["effects"]


def test_cli_bad_input_exits_2_with_one_line(sine_log, tmp_path, capsys):
    bad = write_model(tmp_path / "bad.json", {**MODEL_JSON, "effects": [
        {"name": "flicker_walk", "channel": "gyro_x", "params": {}}]})
    code = main(["gap", str(sine_log), "--model", str(bad), "--report", str(tmp_path / "r.json"),
                 "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and "unknown effect" in err and "flicker_walk" in err
    code = main(["gap", str(sine_log), "--part", "NO_SUCH_PART", "--report", str(tmp_path / "r.json")])
    assert code == 2 and "unknown part" in capsys.readouterr().err


def test_different_rates_are_rejected(sine_log, tmp_path):
    other = write_model(tmp_path / "m200.json", {**MODEL_JSON, "rate_hz": 200.0})
    with pytest.raises(InputError, match="different rates.*100 Hz.*200 Hz"):
        run_gap(sine_log, other)


def test_catalog_part_rate_is_an_output_rate(tmp_path):
    """A catalog part at 819.2 Hz accepts a 100 Hz log (noted) but not a 1 kHz one."""
    from budget.catalog.io import get_part
    part = get_part("ADIS16405")
    model = NoiseModel.from_part(part)
    log = write_log(tmp_path / "adis.csv", model.model_copy(update={"rate_hz": RATE}), 16_384, 2)
    rep = run_gap(log, "ADIS16405", channels=["accel_x", "accel_y"], max_steps=0)
    assert any("output rate" in n for n in rep.notes)
    fast = log_from_arrays({c: np.zeros(20_000) + np.random.default_rng(1).standard_normal(20_000)
                            for c in CHANNELS}, 1000.0)
    with pytest.raises(InputError, match="different rates"):
        run_gap(fast, part)


def test_too_short_logs_are_rejected(tmp_path):
    x = simulate_static_log(BASE, 3000, RATE, np.random.default_rng(0))
    with pytest.raises(InputError, match="too short"):
        run_gap(log_from_arrays(x, RATE), BASE)
    # long enough to compute, too short to reach the ADIS16405 gyro bias-instability floor
    # (white 2 deg/√h meets the 25.2 deg/h floor at τ ≈ 23 s; 5000 samples reach τ = 12.5 s)
    from budget.catalog.io import get_part
    part = NoiseModel.from_part(get_part("ADIS16405")).model_copy(update={"rate_hz": RATE})
    x = simulate_static_log(part, 5000, RATE, np.random.default_rng(0))
    with pytest.raises(InputError, match="τ range needed"):
        run_gap(log_from_arrays(x, RATE), part)
    rep = run_gap(log_from_arrays(x, RATE), part, check_tau_range=False, max_steps=0,
                  channels=["gyro_x"])
    assert math.isfinite(rep.gap_before)


def test_missing_channel_is_named(tmp_path):
    """A channel asked for but absent is an error; by default the channels present are compared
    (a single-gyro log is a normal input), and the report says so."""
    log = write_log(tmp_path / "five.csv", BASE, 16_384, 3, drop=("gyro_z",))
    with pytest.raises(InputError, match="gyro_z missing"):
        run_gap(log, BASE, channels=["gyro_x", "gyro_z"])
    rep = run_gap(log, BASE, max_steps=0)
    assert set(rep.channels) == set(CHANNELS) - {"gyro_z"}
    assert any("compared on those channels" in n for n in rep.notes)
    rep = run_gap(log, BASE, channels=["gyro_x", "accel_z"], max_steps=0)
    assert set(rep.channels) == {"gyro_x", "accel_z"}


def test_single_channel_log(tmp_path):
    log = write_log(tmp_path / "one.csv", BASE, 16_384, 4,
                    drop=tuple(c for c in CHANNELS if c != "gyro_y"))
    rep = run_gap(log, BASE, max_steps=2)
    assert set(rep.channels) == {"gyro_y"} and rep.steps == []
    assert any("gyro_y only" in n for n in rep.notes)


def test_unknown_effect_and_temperature_without_channel(tmp_path):
    with pytest.raises(InputError, match="unknown effect"):
        run_gap(log_from_arrays({c: np.random.default_rng(1).normal(0.0, 1e-3, 8192) for c in CHANNELS}, RATE),
                write_model(tmp_path / "m.json", {**MODEL_JSON, "effects": [
                    {"name": "drift", "channel": "gyro_x", "params": {"x": 1}}]}))
    temp_model = BASE.with_effect({"name": "temperature_sensitivity", "channel": "gyro_x",
                                   "params": {"coefficient": 1e-5}})
    x = simulate_static_log(BASE, 8192, RATE, np.random.default_rng(0))
    with pytest.raises(InputError, match="temperature"):
        run_gap(log_from_arrays(x, RATE), temp_model)


def test_allan_table_needs_rate_and_samples_and_uses_adev_only(tmp_path):
    x = simulate_static_log(BASE, 16_384, RATE, np.random.default_rng(6))
    from budget.noise import allan_deviation
    rows = []
    for ch in ("gyro_x", "accel_x"):
        a = allan_deviation(x[ch], RATE)
        unit = "rps" if ch.startswith("gyro") else "mps2"
        rows += [{"channel": f"{ch}_{unit}", "tau_s": t, "adev": v} for t, v in zip(a.tau_s, a.adev)]
    table = tmp_path / "adev.csv"
    pd.DataFrame(rows).to_csv(table, index=False)
    with pytest.raises(InputError, match="rate and length"):
        run_gap(table, BASE)
    rep = run_gap(table, BASE, rate_hz=RATE, samples=16_384, channels=["gyro_x", "accel_x"])
    assert rep.kind == "adev_table" and rep.steps == []
    assert any("only the ADEV signature" in n for n in rep.notes)
    assert set(rep.channels["gyro_x"].terms_before.kind) == {"adev"}


def test_bad_workflow_arguments():
    log = log_from_arrays(simulate_static_log(BASE, 8192, RATE, np.random.default_rng(0)), RATE)
    with pytest.raises(InputError, match="realizations"):
        run_gap(log, BASE, realizations=2)
    with pytest.raises(InputError, match="unknown channel"):
        run_gap(log, BASE, channels=["gyro_w"])
    with pytest.raises(InputError, match="alpha"):
        run_gap(log, BASE, alpha=0.7)


def test_log_from_arrays_checks_its_input():
    with pytest.raises(InputError, match="common length"):
        log_from_arrays({"gyro_x": np.zeros(10), "gyro_y": np.zeros(11)}, RATE)
    with pytest.raises(InputError, match="NaN"):
        log_from_arrays({"gyro_x": np.array([0.0, np.nan, 1.0])}, RATE)
    with pytest.raises(InputError, match="unknown channel"):
        log_from_arrays({"gyro_q": np.zeros(10)}, RATE)


def test_a_channel_without_any_noise_term_in_the_model_is_refused_naming_it(tmp_path):
    """A model with gyro figures only (the accelerometer triad left empty, as some catalog rows
    are) has no spread to judge the accelerometer channels by: refused before any statistic is
    formed, naming those channels; comparing the gyros alone is fine."""
    log = write_log(tmp_path / "log.csv", BASE, 6000, 3)
    gyros_only = NoiseModel(part_id="gyros-only", rate_hz=RATE, gyro_arw_deg_rt_h=0.5,
                            gyro_bias_instability_deg_h=5.0)
    with pytest.raises(InputError) as err:
        run_gap(log, gyros_only, seed=0, max_steps=1, check_tau_range=False)
    text = str(err.value)
    assert err.value.field == "model" and "gyros-only" in text
    assert "accel_x, accel_y, accel_z" in text and "gyro_x" not in text.split("expected")[0]
    rep = run_gap(log, gyros_only, seed=0, max_steps=1, check_tau_range=False,
                  channels=["gyro_x", "gyro_y", "gyro_z"])
    assert set(rep.channels) == {"gyro_x", "gyro_y", "gyro_z"}


def test_channels_narrow_what_the_reader_checks(tmp_path):
    """An accelerometer clipped at its range (3 % of its samples at the top value) refuses the
    log; comparing only the gyros reads and checks only their columns, so it goes ahead."""
    log = write_log(tmp_path / "log.csv", BASE, 16_384, 5)
    df = pd.read_csv(log)
    top = float(np.quantile(df["accel_x_mps2"], 0.97))
    df["accel_x_mps2"] = np.minimum(df["accel_x_mps2"], top)
    df.to_csv(log, index=False, float_format="%.9g")
    with pytest.raises(InputError, match="clipped"):
        run_gap(log, BASE, max_steps=0)
    gyros = ["gyro_x", "gyro_y", "gyro_z"]
    rep = run_gap(log, BASE, channels=gyros, max_steps=0)
    assert set(rep.channels) == set(gyros)


def test_noise_characterize_channels_option(tmp_path, capsys):
    """``noise characterize --channels`` reads and characterises only those columns: a clipped
    accelerometer no longer refuses a gyro characterisation."""
    log = write_log(tmp_path / "log.csv", BASE, 16_384, 6)
    df = pd.read_csv(log)
    df["accel_y_mps2"] = np.minimum(df["accel_y_mps2"], float(np.quantile(df["accel_y_mps2"], 0.97)))
    df.to_csv(log, index=False, float_format="%.9g")
    assert main(["noise", "characterize", str(log)]) == 2
    assert "clipped" in capsys.readouterr().err
    out = tmp_path / "c.json"
    assert main(["noise", "characterize", str(log), "--channels", "gyro_x,gyro_y", "--json", str(out), "-q"]) == 0
    assert set(json.loads(out.read_text())["channels"]) == {"gyro_x", "gyro_y"}


def test_noise_characterize_channels_missing_from_an_allan_table(tmp_path, capsys):
    """``--channels`` on an Allan table keeps only those tables; a channel the table lacks is
    named, with the channels it has."""
    m = 2 ** np.arange(10)
    tau = m / RATE
    rows = ["channel,tau_s,adev"] + [f"gyro_x_rps,{float(t)!r},{float(1e-3 / np.sqrt(t))!r}" for t in tau]
    table = tmp_path / "adev.csv"
    table.write_text("\n".join(rows) + "\n")
    args = ["noise", "characterize", str(table), "--rate-hz", "100", "--samples", "100000"]
    assert main(args + ["--channels", "gyro_y"]) == 2
    err = capsys.readouterr().err
    assert "gyro_y missing from the table" in err and "channels the table has: gyro_x" in err
