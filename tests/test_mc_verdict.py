"""Monte Carlo verdict: determinism, consistency with the analytic bounds, backends, CLI."""

import json
import threading

import numpy as np
import pandas as pd
import pytest

from budget.catalog.io import get_part
from budget.cli.main import main
from budget.errors import InputError
from budget.mc import McOptions, run_mc
from budget.mc.consistency import consistency_table, crossing_scale, single_term_model
from budget.mc.stats import wilson_interval
from budget.mc.sweep import cheapest_passing, not_simulated, sweep
from budget.presets import get_preset
from budget.scenario import Scenario

#: Seed 004's assumptions: IMU at the antenna phase centre (no lever arm), straight flight.
#: L band keeps δr/λ ≈ 2, so the fast-phase criterion does not dominate (see README).
LBAND = Scenario(name="lband_uav", carrier_frequency_hz=1.3e9, slant_range_m=1000,
                 azimuth_resolution_m=0.5, range_resolution_m=0.5, platform_speed_m_s=50,
                 depression_deg=30, imu_rate_hz=100)


def _fingerprint(r):
    d = r.to_dict()
    return (d["p_pass_before"], d["p_pass_after"], d["failure_reasons"],
            d["metrics_after"]["pslr_db"], d["metrics_after"]["residual_phase_rms_deg"])


@pytest.mark.slow
def test_same_seed_same_numbers_any_workers_or_backend():
    s, p = get_preset("automotive_77ghz"), get_part("ADIS16405")
    serial = run_mc(s, p, 128, 7)
    procs = run_mc(s, p, 128, 7, workers=2, backend="processes")
    assert _fingerprint(serial) == _fingerprint(procs)
    other = run_mc(s, p, 128, 8)
    assert _fingerprint(other) != _fingerprint(serial)
    # the first 64 trials of a 128-trial run are the 64-trial run
    short = run_mc(s, p, 64, 7).to_dict()["metrics_after"]["pslr_db"]
    assert short == serial.to_dict()["metrics_after"]["pslr_db"][:64]


@pytest.mark.slow
@pytest.mark.parametrize("term", ["accel_bias", "gyro_bias", "accel_vrw", "gyro_arw"])
def test_single_term_at_0p1_passes_at_10x_fails(term):
    table = consistency_table(LBAND, terms=[term], scales=(0.1, 10.0), trials=24, seed=5)
    p01, p10 = table["p_pass_after"].tolist()
    assert p01 >= 0.9, table
    assert p10 <= 0.2, table


def test_single_term_model_sits_at_the_bound():
    m = single_term_model(LBAND, "accel_vrw", 2.0)
    from budget.bounds import paper_bounds
    bound = paper_bounds(LBAND.tc_s, 0.5).datasheet()["accel_vrw_ug_rt_hz"][0]
    assert m.accel_vrw_m_s_rt_h * 1699.527 == pytest.approx(2 * bound, rel=1e-5)


def test_crossing_scale():
    assert crossing_scale([0.1, 1, 10], [1.0, 0.5, 0.0]) == pytest.approx(1.0)
    assert crossing_scale([0.1, 1, 10], [1.0, 1.0, 0.0]) == pytest.approx(10 ** 0.5)
    assert np.isnan(crossing_scale([0.1, 1], [0.2, 0.0]))
    assert crossing_scale([0.1, 1], [1.0, 0.9]) == np.inf


def test_automotive_industrial_part_passes_seed004():
    # seed 004: automotive SAR (Tc < 1 s) → industrial IMUs suffice
    r = run_mc(get_preset("automotive_24ghz"), get_part("ADIS16405"), 64, 1)
    assert r.p_pass_after >= 0.95 and r.ci_after[0] > 0.9


def test_progress_and_cancel():
    seen = []
    cancel = threading.Event()

    def progress(done, total):
        seen.append(done)
        cancel.set()

    r = run_mc(get_preset("automotive_77ghz"), get_part("STIM300"), 256, 1, progress=progress, cancel=cancel)
    assert r.cancelled and r.trials == 64 and seen == [64]


def test_sweep_and_cheapest():
    parts = [get_part("ADIS16405"), get_part("STIM300")]
    # 24 GHz: the industrial part passes there (README verdict table; at 77 GHz it is 0.72 since
    # the Taylor window and the PGA-residual criterion)
    df = sweep(parts, [get_preset("automotive_24ghz")], 64, 2)
    assert len(df) == 2 and {"p_pass_after", "ci_after_lo", "fail_range_migration"} <= set(df.columns)
    best = cheapest_passing(df, 0.9)
    assert best.loc[0, "part_id"] == "ADIS16405"  # industrial is the cheaper grade
    assert best.loc[0, "decided_on"] == "ci_after_lo"  # decided on the lower Wilson bound


def test_sweep_keeps_going_past_a_scenario_it_cannot_simulate():
    """The long-range preset needs ≈ 21,700 pulses (Tc 26 s at 836 Hz), beyond the simulator's
    16,384: its cells are kept, marked "not simulated" with the reason, and the study goes on."""
    parts = [get_part("STIM300")]
    df = sweep(parts, [get_preset("airborne_xband_long_range"), get_preset("automotive_24ghz")], 8, 2)
    assert list(df["status"])[1] == "simulated" and len(df) == 2
    skipped = df.iloc[0]
    assert skipped["status"].startswith("not simulated") and "pulses" in skipped["status"]
    assert skipped["trials"] == 0 and pd.isna(skipped["p_pass_after"])
    assert not_simulated(df) == {"airborne_xband_long_range": skipped["status"]}
    best = cheapest_passing(df, 0.5).set_index("scenario")
    assert pd.isna(best.loc["airborne_xband_long_range", "part_id"])
    assert best.loc["airborne_xband_long_range", "basis"].startswith("not simulated")


def test_cheapest_passing_says_when_the_study_is_too_small_to_show_the_target():
    """32 failure-free trials give a lower Wilson bound of 0.893: a 0.9 target cannot be shown,
    and the basis says so with the number of trials needed (35, from the Wilson bound itself)."""
    table = pd.DataFrame([{"scenario": "x", "part_id": "A", "grade": "tactical", "price_usd": 1.0,
                           "trials": 32, "p_pass_after": 1.0, "ci_after_lo": wilson_interval(32, 32)[0]}])
    basis = cheapest_passing(table, 0.9).loc[0, "basis"]
    assert "32/32 gives 0.893" in basis and "at least 35 failure-free trials" in basis
    assert wilson_interval(35, 35)[0] >= 0.9 > wilson_interval(34, 34)[0]
    for bad in (0.0, 1.5, float("nan")):
        with pytest.raises(InputError):
            cheapest_passing(table, bad)


def test_bad_inputs():
    s, p = get_preset("automotive_77ghz"), get_part("STIM300")
    with pytest.raises(InputError, match="trials"):
        run_mc(s, p, 0, 1)
    with pytest.raises(InputError, match="backend"):
        run_mc(s, p, 8, 1, backend="mpi")
    with pytest.raises(InputError):
        run_mc(get_preset("airborne_xband_long_range"), p, 8, 1)  # aperture beyond simulation limits
    with pytest.raises(InputError):
        Scenario.from_dict(get_preset("airborne_xband").model_dump() | {"platform_speed_m_s": 0})
    with pytest.raises(Exception):
        McOptions(chunk_trials=100)


def test_cli_mc_json(tmp_path, capsys):
    path = tmp_path / "s.json"
    get_preset("automotive_77ghz").save(path)
    assert main(["mc", "--scenario", str(path), "--part", "ADIS16405", "--trials", "64", "--seed", "3",
                 "--json", "-"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert {"trials", "seed", "tc_s", "p_pass_before", "p_pass_after", "ci_after", "failure_reasons",
            "metrics_after"} <= set(d)
    assert d["trials"] == 64 and len(d["ci_after"]) == 2
    assert {"azimuth_broadening", "range_broadening", "pslr_db", "islr_db",
            "residual_phase_rms_deg"} <= set(d["metrics_after"])
    assert all(len(v) == 64 for v in d["metrics_after"].values())
    assert main(["mc", "--scenario", str(path), "--part", "NOPE", "--trials", "8"]) == 2


def test_cli_sweep_warns_about_a_scenario_it_cannot_simulate(tmp_path, capsys):
    out = tmp_path / "t.csv"
    assert main(["sweep", "--preset", "airborne_xband_long_range", "--part", "STIM300", "--trials", "8",
                 "--out", str(out), "-q"]) == 0
    cap = capsys.readouterr()
    assert "warning: scenario 'airborne_xband_long_range' not simulated" in cap.err and "pulses" in cap.err
    assert pd.read_csv(out)["status"].str.startswith("not simulated").all()
    assert "None" not in cap.out and "not simulated" in cap.out  # no part: '-', and the basis says why
    assert main(["sweep", "--preset", "automotive_24ghz", "--part", "STIM300", "--target", "5",
                 "--out", str(out)]) == 2
    assert "target" in capsys.readouterr().err


@pytest.mark.slow
def test_dask_backend_matches_serial():
    distributed = pytest.importorskip("dask.distributed", reason="dask[distributed] not installed")
    s, p = get_preset("automotive_77ghz"), get_part("ADIS16405")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        d = run_mc(s, p, 128, 7, backend="dask", client=client, workers=2)
    a, b = _fingerprint(d), _fingerprint(run_mc(s, p, 128, 7))
    assert a[:3] == b[:3]  # verdicts and failure counts identical
    # metrics equal to rounding: Dask workers pin BLAS to one thread, which changes the
    # summation order inside the linear algebra by ~1e-15
    np.testing.assert_allclose(a[3], b[3], rtol=1e-9)
    np.testing.assert_allclose(a[4], b[4], rtol=1e-9)


def test_consistency_table_skips_scales_no_noise_model_accepts():
    """On the 77 GHz preset (Tc ≈ 0.16 s) 10× the paper's VRW bound is ≈ 150 m/s/√h, beyond the
    100 m/s/√h a noise model accepts: that scale is reported as not simulated, with the reason,
    instead of ending the study with a validation error after the other scales have run."""
    from budget.bounds import paper_bounds
    s = get_preset("automotive_77ghz")
    bound = paper_bounds(s.tc_s, s.range_resolution_m).datasheet()["accel_vrw_ug_rt_hz"][0] / 1699.527
    assert 10 * bound > 100.0  # the premise: 10× is beyond the model's range, 0.1× within it
    with pytest.raises(InputError) as err:
        single_term_model(s, "accel_vrw", 10.0)
    assert err.value.field == "accel_vrw_m_s_rt_h" and "paper bound" in str(err.value)
    table = consistency_table(s, terms=["accel_vrw"], scales=(0.1, 10.0), trials=4, seed=1)
    low, high = table.iloc[0], table.iloc[1]
    assert low["simulated"] and 0.0 <= low["p_pass_after"] <= 1.0 and low["note"] == ""
    assert not high["simulated"] and np.isnan(high["p_pass_after"])
    assert "not simulated" in high["note"] and "accel_vrw_m_s_rt_h" in high["note"]
    assert "1 of 2 scales" in high["crossing_method"]
