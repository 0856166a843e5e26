"""Held-out scenarios and catalog edits as a radar engineer writes them (Ka-band UAV, slow 24 GHz
automotive, P-band foliage penetration, 30 kHz sonar …): the numbers against hand calculations
from seed 004 (5)–(11), and every default a result rests on stated by the library (API), not
only by the CLI.

Hand figures: Tc = a_w λ R / (2 δℓ V sin θ) (seed 004 (5)), λ = c/f0; paper bounds
accel bias 1.4e5 δr/Tc² µg, gyro bias 8.93e4 δr/Tc³ deg/h, ARW 784 δr/Tc^2.5 deg/√h."""

from __future__ import annotations

import json
import math

import pytest

import budget
from budget.cli.main import main

from budget.mc import McOptions

#: The scene does not matter to these tests (what a result says, which part a catalog gives):
#: PGA's best case, the five noise-free points, keeps them fast.
POINTS = McOptions(scene="points")

C = 299_792_458.0

#: a Ka-band (35 GHz) UAV at 2 km, Taylor-like a_w = 1.2, lever arm given; no squint or medium key
KA_UAV = {"name": "ka_uav", "carrier_frequency_hz": 35e9, "slant_range_m": 2000.0,
          "azimuth_resolution_m": 0.15, "range_resolution_m": 0.15, "platform_speed_m_s": 40.0,
          "depression_deg": 30.0, "window_broadening": 1.2, "lever_arm_m": [0.3, 0.0, 0.2],
          "platform_rate_deg_s": 2.0, "imu_rate_hz": 400.0}
#: a 24 GHz automotive radar crawling at 2 m/s past a kerb 30 m away; no lever arm, window or rate
AUTO24_SLOW = {"name": "auto24_slow", "carrier_frequency_hz": 24.125e9, "slant_range_m": 30.0,
               "azimuth_resolution_m": 0.05, "range_resolution_m": 0.1, "platform_speed_m_s": 2.0,
               "depression_deg": 3.0}


def _write(tmp_path, name, data) -> str:
    p = tmp_path / name
    p.write_text(json.dumps(data))
    return str(p)


def test_ka_uav_tc_and_paper_bounds_match_the_hand_calculation(tmp_path):
    s = budget.load_scenario(_write(tmp_path, "ka.json", KA_UAV))
    lam = C / 35e9
    tc = 1.2 * lam * 2000.0 / (2 * 0.15 * 40.0)  # sin θ = 1 at broadside
    assert s.tc_s == pytest.approx(tc, rel=1e-12)
    assert tc == pytest.approx(1.7131, abs=1e-4)
    row = budget.compute_bounds(s, "paper").to_dict()["rows"][0]
    assert row["accel_bias_ug"] == pytest.approx(1.4e5 * 0.15 / tc**2, rel=1e-3)     # 7156 µg
    assert row["gyro_bias_deg_h"] == pytest.approx(8.93e4 * 0.15 / tc**3, rel=1e-3)  # 2664 deg/h
    assert row["gyro_arw_deg_rt_h"] == pytest.approx(784 * 0.15 / tc**2.5, rel=1e-3)  # 30.6 deg/√h


def test_api_bounds_state_the_scenario_defaults_the_cli_states(tmp_path, capsys):
    path = _write(tmp_path, "auto24.json", AUTO24_SLOW)
    table = budget.compute_bounds(path, "derived")
    d = table.to_dict()
    # derived mode rests on Tc's keys and the specific force: the file sets none of medium, squint,
    # window, platform_accel_m_s2
    assert d["scenario_defaults"] == {"medium": "radar", "squint_deg": 0.0, "window_broadening": 1.0,
                                      "platform_accel_m_s2": 9.80665}
    assert "taken at their defaults" in table.summary()
    assert "platform_accel_m_s2 = 9.80665" in table.summary()
    assert table.to_frame().attrs["scenario_defaults"] == d["scenario_defaults"]
    # the CLI's JSON says the same
    assert main(["bounds", "--scenario", path, "--mode", "derived", "--json", "-"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert cli["scenario_defaults"] == d["scenario_defaults"]
    # a scenario with every key of the mode written states none
    full = {**AUTO24_SLOW, "medium": "radar", "squint_deg": 0.0, "window_broadening": 1.0,
            "platform_accel_m_s2": 9.80665}
    t2 = budget.compute_bounds(_write(tmp_path, "full.json", full), "derived")
    assert t2.to_dict()["scenario_defaults"] == {}
    assert "taken at their defaults" not in t2.summary()
    # hand: a_w = 1 default, λ = c/24.125 GHz, Tc = λ R / (2 δℓ V); derived accel bias √2 δr/Tc²
    tc = (C / 24.125e9) * 30.0 / (2 * 0.05 * 2.0)
    assert d["rows"][0]["accel_bias_ug"] == pytest.approx(math.sqrt(2) * 0.1 / tc**2 / 9.80665 * 1e6, rel=1e-9)


def test_api_check_states_the_scenario_defaults_once(tmp_path, capsys):
    path = _write(tmp_path, "auto24.json", AUTO24_SLOW)
    res = budget.check_parts(["STIM300"], path)
    # paper check: Tc's keys, and the line of sight and lever arm of the PGA-limited verdict
    expected = {"medium": "radar", "squint_deg": 0.0, "window_broadening": 1.0, "lever_arm_m": [0.0, 0.0, 0.0]}
    got = res.to_dict()["scenarios"][0]["scenario_defaults"]
    assert {k: list(v) if isinstance(v, tuple) else v for k, v in got.items()} == expected
    assert "lever_arm_m = [0, 0, 0] m (IMU at the antenna phase centre)" in res.summary()
    # the CLI prints it once (the summary's line), and its JSON agrees
    assert main(["check", "--scenario", path, "--part", "STIM300"]) == 0
    assert capsys.readouterr().out.count("taken at their defaults") == 1
    assert main(["check", "--scenario", path, "--part", "STIM300", "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out)["scenario_defaults"] == expected


def test_sweep_rows_state_the_scenario_defaults_their_verdict_rests_on(tmp_path):
    path = _write(tmp_path, "auto24.json", AUTO24_SLOW)
    full = {**KA_UAV, "medium": "radar", "squint_deg": 0.0}
    table = budget.sweep(["HG9900"], [path, _write(tmp_path, "ka.json", full)], trials=2, seed=1, options=POINTS)
    auto, ka = table["scenario_defaults"].tolist()
    # the slow automotive file leaves out medium, squint, window, lever arm and IMU rate
    for text in ("medium = radar", "squint_deg = 0 (broadside)", "window_broadening = 1",
                 "lever_arm_m = [0, 0, 0] m", "imu_rate_hz = 200 Hz"):
        assert text in auto
    assert "depression_deg" not in auto  # the file sets it
    assert ka.startswith("none")


#: a user's own STIM300 unit: its datasheet figures written over the shipped row (same id)
OWN_STIM300 = ("part_id,vendor,model,grade,gyro_arw_deg_rt_h,accel_vrw_m_s_rt_h,gyro_bias_instability_deg_h,"
               "accel_bias_instability_ug,source\n"
               "STIM300,Safran,STIM300 serial 1234,tactical,0.2,0.1,0.5,50,acceptance test sheet of unit 1234\n"
               "MY-IMU,Acme,M1,tactical,0.1,0.05,1,100,Acme datasheet rev B\n")


def test_a_user_row_replacing_a_shipped_part_is_named_by_check_mc_and_report(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("SAR_BUDGET_CATALOG", raising=False)
    cat = tmp_path / "mine.csv"
    cat.write_text(OWN_STIM300)
    # airborne_xband by hand: λ = c/9.6 GHz, Tc = λ R / (2 δℓ V) = 3.1228 s, δr = 0.5 m;
    # paper ARW bound 784 δr / Tc^2.5 against the user's 0.2 deg/√h (the shipped row says 0.15)
    tc = (C / 9.6e9) * 5000.0 / (2 * 0.5 * 50.0)
    assert main(["check", "--preset", "airborne_xband", "--catalog", str(cat), "--part", "STIM300", "MY-IMU",
                 "--json", "-"]) == 0
    out = json.loads(capsys.readouterr().out)
    stim = next(r for r in out["parts"] if r["part_id"] == "STIM300")
    assert stim["margins"]["gyro_arw_deg_rt_h"] == pytest.approx(784 * 0.5 / tc**2.5 / 0.2, rel=1e-3)
    assert "replaces the shipped one of: STIM300" in out["catalog_note"]
    assert "from the user catalog only: MY-IMU" in out["catalog_note"]
    assert main(["check", "--preset", "airborne_xband", "--catalog", str(cat), "--part", "STIM300"]) == 0
    assert "replaces the shipped one of: STIM300" in capsys.readouterr().out
    # the shipped catalog alone: no catalog line
    assert main(["check", "--preset", "airborne_xband", "--part", "STIM300"]) == 0
    assert "catalog:" not in capsys.readouterr().out
    # the Monte Carlo says it too, also when the catalog comes from the environment variable
    monkeypatch.setenv("SAR_BUDGET_CATALOG", str(cat))
    assert main(["mc", "--preset", "airborne_xband", "--part", "STIM300", "--trials", "2", "--workers", "1",
                 "-q", "--json", "-"]) == 0
    note = json.loads(capsys.readouterr().out)["catalog_note"]
    assert "replaces the shipped one of: STIM300" in note and "$SAR_BUDGET_CATALOG" in note
    monkeypatch.delenv("SAR_BUDGET_CATALOG")
    rep = budget.build_report("airborne_xband", ["STIM300", "HG9900"], catalog=str(cat))
    assert "replaces the shipped one of: STIM300" in rep.to_dict()["provenance"]["catalog"]
    assert budget.build_report("airborne_xband", ["HG9900"]).to_dict()["provenance"]["catalog"] == "shipped"


#: a C-band spaceborne-like strip-map: 5.405 GHz, 850 km slant range, 7.5 km/s, 5 m resolution
C_BAND_SPACE = {"name": "cband_space", "medium": "radar", "carrier_frequency_hz": 5.405e9,
                "slant_range_m": 850e3, "azimuth_resolution_m": 5.0, "range_resolution_m": 5.0,
                "platform_speed_m_s": 7500.0, "depression_deg": 55.0}


def test_an_orbital_scenario_notes_its_specific_force_once_per_run(tmp_path):
    import warnings

    from budget.nav.earth import EARTH_RADIUS_M

    path = _write(tmp_path, "cband.json", C_BAND_SPACE)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        s = budget.load_scenario(path)
        budget.run_mc(s, "HG9900", trials=2, seed=3, workers=1, options=POINTS)
    notes = [str(w.message) for w in caught if "level flight around the Earth" in str(w.message)]
    assert len(notes) == 1  # when the scenario is read, not again when the simulator rebuilds it
    # hand: Tc = λ R / (2 δℓ V) = 0.6286 s; g − V²/r_E = 9.80665 − 7500²/6.371e6 ≈ 0.978 m/s²
    assert s.tc_s == pytest.approx((C / 5.405e9) * 850e3 / (2 * 5.0 * 7500.0), rel=1e-12)
    assert f"{9.80665 - 7500.0**2 / EARTH_RADIUS_M:.3g} m/s²" in notes[0]


def test_no_autofocus_bounds_from_bare_tc_do_not_report_a_range_resolution_nobody_gave(capsys):
    # Ka band λ = 8.6 mm: without autofocus the edge quadratic phase ≤ π/4 gives a constant
    # acceleration error b ≤ λ/(2 Tc²) (b Tc²/8 of edge quadratic range, 4π/λ of phase)
    assert main(["bounds", "--tc", "0.5", "2", "--wavelength", "0.0086", "--mode", "no-autofocus",
                 "--json", "-"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["range_resolution_m"] is None  # not given, and not used by these bounds
    for row, tc in zip(out["bounds"]["rows"], (0.5, 2.0)):
        assert row["accel_bias_ug"] == pytest.approx(0.0086 / (2 * tc**2) / 9.80665 * 1e6, rel=1e-9)
    # given, it is reported as given
    assert main(["bounds", "--tc", "0.5", "--wavelength", "0.0086", "--range-resolution", "0.3",
                 "--mode", "no-autofocus", "--json", "-"]) == 0
    assert json.loads(capsys.readouterr().out)["range_resolution_m"] == 0.3


def test_scenario_show_marks_the_keys_left_at_their_defaults(tmp_path, capsys):
    path = _write(tmp_path, "auto24.json", AUTO24_SLOW)
    assert main(["scenario", "show", "--scenario", path]) == 0
    rows = {line.split()[0]: line for line in capsys.readouterr().out.splitlines() if line.startswith("  ")}
    for key in ("squint_deg", "window_broadening", "lever_arm_m", "imu_rate_hz", "medium"):
        assert rows[key].endswith("(default)"), rows[key]
    for key in ("slant_range_m", "depression_deg", "platform_speed_m_s"):
        assert "(default)" not in rows[key], rows[key]
    # Tc by hand: λ R / (2 δℓ V) with a_w = 1 (the default) = 1.864 s
    assert float(rows["tc_s"].split()[1]) == pytest.approx((C / 24.125e9) * 30.0 / (2 * 0.05 * 2.0), rel=1e-5)


#: a Ku-band seeker: 16 GHz, 8 km, 300 m/s, 30° squint, a 3 g manoeuvre's specific force
MISSILE_KU = {"name": "missile_ku", "carrier_frequency_hz": 16e9, "slant_range_m": 8000.0,
              "azimuth_resolution_m": 1.0, "range_resolution_m": 1.0, "platform_speed_m_s": 300.0,
              "squint_deg": 30.0, "depression_deg": 40.0, "platform_accel_m_s2": 30.0,
              "platform_rate_deg_s": 10.0, "lever_arm_m": [1.0, 0.0, 0.0], "imu_rate_hz": 400.0}


def test_bound_assumptions_as_a_dict_complete_the_scenarios_own(tmp_path):
    from budget.errors import InputError

    path = _write(tmp_path, "missile.json", MISSILE_KU)
    # hand: Tc = λ R / (2 δℓ V sin 60°) = 0.28848 s; derived β ≤ 2 δr / (a Tc²) with the
    # scenario's a = 30 m/s²; combine 'rss' shares δr among 7 sources: δr/√7
    tc = (C / 16e9) * 8000.0 / (2 * 1.0 * 300.0 * math.sin(math.radians(60.0)))
    beta = 2 * 1.0 / (30.0 * tc**2)
    each = budget.compute_bounds(path, "derived").to_dict()["rows"][0]
    rss = budget.compute_bounds(path, "derived", assumptions={"combine": "rss"}).to_dict()["rows"][0]
    assert each["accel_scale_factor_ppm"] == pytest.approx(beta * 1e6, rel=1e-9)
    assert rss["accel_scale_factor_ppm"] == pytest.approx(beta * 1e6 / math.sqrt(7), rel=1e-9)
    # the check takes the same dict
    res = budget.check_parts(["STIM300"], path, mode="derived", assumptions={"combine": "rss"})
    assert res.to_dict()["scenarios"][0]["tc_s"] == pytest.approx(tc, rel=1e-12)
    # lever-arm: the scenario's lever arm and turn rate kept, k·σ changed
    lever = budget.compute_bounds(path, "lever-arm", assumptions={"k_sigma": 3}).assumptions
    assert lever["lever_arm_m"] == [1.0, 0.0, 0.0] and lever["platform_rate_deg_s"] == 10.0
    assert lever["k_sigma"] == 3.0
    # a bad key, value or type: one clear InputError, never an AttributeError
    with pytest.raises(InputError, match=r"assumptions\.combin: unknown key.*keys of DerivedAssumptions"):
        budget.compute_bounds(path, "derived", assumptions={"combin": "rss"})
    with pytest.raises(InputError, match=r"assumptions\.k_sigma"):
        budget.compute_bounds(path, "derived", assumptions={"k_sigma": -1})
    with pytest.raises(InputError, match=r"field assumptions: derived bounds take"):
        budget.compute_bounds(path, "derived", assumptions=5)
    with pytest.raises(InputError, match=r"assumptions\.quadratic_edge_limit_rad"):
        budget.check_parts(["STIM300"], path, mode="no-autofocus", assumptions={"quadratic_edge_limit_rad": "x"})


def test_a_user_row_without_a_bias_convention_is_told_which_one_it_got(tmp_path):
    head = "part_id,vendor,model,grade,gyro_bias_instability_deg_h,gyro_arw_deg_rt_h,accel_bias_instability_ug,"
    body = "tactical,1.0,0.15,1000,0.05,Honeywell-style brochure: bias 1 deg/h and 1 mg (1 sigma)"
    bare = tmp_path / "bare.csv"
    bare.write_text(head + "accel_vrw_m_s_rt_h,source\nHW-1,Acme,H1," + body + "\n")
    stated = tmp_path / "stated.csv"
    stated.write_text(head + "accel_vrw_m_s_rt_h,source,bias_instability_convention\nHW-1,Acme,H1,"
                      + body + ",total_1sigma\n")
    ka = _write(tmp_path, "ka.json", KA_UAV)
    r = budget.run_mc(ka, "HW-1", trials=2, seed=1, workers=1, catalog=str(bare), options=POINTS)
    text = r.unspecified_summary()
    assert "bias_instability_convention not given" in text
    assert "gyro_bias_instability_deg_h = 1 deg/h" in text and "accel_bias_instability_ug = 1000 µg" in text
    r2 = budget.run_mc(ka, "HW-1", trials=2, seed=1, workers=1, catalog=str(stated), options=POINTS)
    assert "bias_instability_convention" not in r2.unspecified_summary()
    # the shipped rows all state theirs
    r3 = budget.run_mc(ka, "STIM300", trials=2, seed=1, workers=1, options=POINTS)
    assert "bias_instability_convention" not in r3.unspecified_summary()


@pytest.mark.parametrize("header, meant", [
    ("accel_bias_instability_µg", "accel_bias_instability_ug"),   # the micro sign of a datasheet
    ("gyro_arw_deg_sqrt_hr", "gyro_arw_deg_rt_h"),
    ("Gyro_ARW_deg_rt_h", "gyro_arw_deg_rt_h"),
    ("accel_vrw_m_s_rt_hr", "accel_vrw_m_s_rt_h"),
])
def test_a_datasheet_spelled_header_is_refused_with_the_column_it_meant(tmp_path, header, meant):
    from budget.catalog.io import read_parts
    from budget.errors import InputError

    p = tmp_path / "mine.csv"
    p.write_text(f"part_id,vendor,model,grade,{header},source\nX-1,Acme,X,tactical,0.1,sheet\n")
    with pytest.raises(InputError, match=rf"row 1, field {header}: unknown column \(did you mean '{meant}'\?\)"):
        read_parts(p)


def test_an_unrelated_header_gets_no_guess(tmp_path):
    from budget.catalog.io import read_parts
    from budget.errors import InputError

    p = tmp_path / "mine.csv"
    p.write_text("part_id,vendor,model,grade,my_comment,source\nX-1,Acme,X,tactical,hello,sheet\n")
    with pytest.raises(InputError, match=r"field my_comment: unknown column; expected one of part_id"):
        read_parts(p)


def test_an_aided_scenario_states_the_aiding_keys_it_left_out(tmp_path):
    # a helicopter at 10 m/s, 1 km, X band: Tc = λ R / (2 δℓ V) = 5.2 s; a 5 Hz GNSS of 0.5 m given
    # with neither latency, antenna lever arm nor a correlated error, and no mode or warm-up
    heli = {"name": "heli", "carrier_frequency_hz": 9.6e9, "slant_range_m": 1000.0,
            "azimuth_resolution_m": 0.3, "range_resolution_m": 0.3, "platform_speed_m_s": 10.0,
            "depression_deg": 20.0, "lever_arm_m": [0.0, 1.0, -0.5],
            "aiding": [{"type": "gnss", "rate_hz": 5.0, "sigma_m": 0.5}]}
    path = _write(tmp_path, "heli.json", heli)
    s = budget.load_scenario(path)
    assert s.tc_s == pytest.approx((C / 9.6e9) * 1000.0 / (2 * 0.3 * 10.0), rel=1e-12)
    r = budget.run_mc(s, "HG9900", trials=2, seed=1, workers=1, options=POINTS)
    note = r.judged_on["aiding_defaults"]
    for text in ("aiding_mode = frozen", "aiding_warmup_s = 60", "latency_s = 0",
                 "correlated_sigma_m = 0.0 (white position noise only)", "lever_arm_m = [0.0, 0.0, 0.0]"):
        assert text in note, text
    assert "rate_hz" not in note and "sigma_m = " not in note.replace("correlated_sigma_m", "")
    assert note in r.summary()
    row = budget.sweep(["HG9900"], [path], trials=2, seed=1, options=POINTS)
    assert "aiding_mode = frozen" in row["scenario_defaults"].iloc[0]
    # every aiding key written: nothing to state
    full = {**heli, "aiding_mode": "smoothed", "aiding_warmup_s": 30.0,
            "aiding": [{"type": "gnss", "rate_hz": 5.0, "sigma_m": 0.5, "latency_s": 0.1,
                        "lever_arm_m": [0.0, 0.0, 0.5], "correlated_sigma_m": 0.2, "correlation_time_s": 300.0}]}
    r2 = budget.run_mc(_write(tmp_path, "heli_full.json", full), "HG9900", trials=2, seed=1, workers=1, options=POINTS)
    assert "aiding_defaults" not in r2.judged_on


def test_no_autofocus_table_shows_the_unused_range_resolution_as_not_used(tmp_path):
    # a 30 kHz sonar: λ = 1500/30e3 = 0.05 m, Tc = λ R / (2 δℓ V) = 0.05·200/(2·0.1·2) = 25 s;
    # without autofocus b ≤ λ/(2 Tc²) = 4e-5 m/s² = 4.079 µg
    sonar = {"name": "sas30k", "medium": "sonar", "carrier_frequency_hz": 30e3, "slant_range_m": 200.0,
             "azimuth_resolution_m": 0.1, "range_resolution_m": 0.1, "platform_speed_m_s": 2.0,
             "depression_deg": 15.0}
    table = budget.compute_bounds(_write(tmp_path, "sonar.json", sonar), "no-autofocus")
    assert table.to_dict()["rows"][0]["accel_bias_ug"] == pytest.approx(0.05 / (2 * 25.0**2) / 9.80665 * 1e6, rel=1e-9)
    text = table.summary()
    assert "NaN" not in text and "δr is not used" in text
    assert "propagation_speed_m_s = 1500 m/s (sonar)" in text  # the default speed of sound, stated


def test_sweep_names_a_user_row_replacing_a_shipped_part(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("SAR_BUDGET_CATALOG", raising=False)
    cat = tmp_path / "mine.csv"
    cat.write_text(OWN_STIM300)
    out = tmp_path / "t.csv"
    assert main(["sweep", "--preset", "automotive_77ghz", "--part", "STIM300", "--catalog", str(cat),
                 "--trials", "2", "--out", str(out), "-q"]) == 0
    assert "replaces the shipped one of: STIM300" in capsys.readouterr().out


def _taylor_3db_width_cells() -> float:
    """3 dB width (cells of 1/bandwidth) of a Taylor −35 dB, n̄ = 4 aperture, from scipy's window
    and a zero-padded FFT: independent of the project's own window code."""
    import numpy as np
    from scipy.signal.windows import taylor

    n, m = 1024, 1024 * 64
    h = np.abs(np.fft.fft(taylor(n, nbar=4, sll=35, norm=False), m)) ** 2
    h /= h[0]
    k = int(np.argmax(h < 0.5))
    return 2 * (k - 1 + (0.5 - h[k - 1]) / (h[k] - h[k - 1])) * n / m


def test_mc_states_the_resolution_its_taylor_image_reaches_with_an_unweighted_a_w(tmp_path):
    # a 24 GHz radar at 2 m/s, 30 m: the file leaves window_broadening at 1 (an unweighted main
    # lobe), the Monte Carlo images with Taylor (−35 dB, n̄ = 4): one cell is δℓ/1, and the
    # image resolves w·δℓ, w = 1.184 cells, not the 0.05 m asked for
    w = _taylor_3db_width_cells()
    assert w == pytest.approx(1.184, abs=0.002)
    r = budget.run_mc(_write(tmp_path, "auto24.json", AUTO24_SLOW), "HG9900", trials=2, seed=1, workers=1, options=POINTS)
    note = r.judged_on["window_resolution"]
    assert f"azimuth {w * 0.05:.3g} m and range {w * 0.1:.3g} m" in note
    assert f"window_broadening = {w:.3g}" in note and note in r.summary()
    # a_w = 1.2 written for the Taylor window (the Ka-band file): within 5 %, nothing to say
    r2 = budget.run_mc(_write(tmp_path, "ka.json", KA_UAV), "HG9900", trials=2, seed=1, workers=1, options=POINTS)
    assert "window_resolution" not in r2.judged_on


def test_the_html_report_states_what_the_monte_carlo_was_judged_against(tmp_path):
    import html as html_lib

    rep = budget.build_report(_write(tmp_path, "auto24.json", AUTO24_SLOW), ["HG9900"], mc_parts=["HG9900"],
                              trials=2, seed=1)
    judged = rep.mc["HG9900"].judged_on
    page = html_lib.unescape(rep.html())
    # the acceptance (what "pass" meant), the default lever arm and the resolution the Taylor
    # image reaches with a_w = 1 (1.18 × δℓ) are on the page, not only in the CLI's summary
    for key in ("acceptance", "lever_arm", "window_resolution"):
        assert judged[key] in page, key
    assert f"azimuth {_taylor_3db_width_cells() * 0.05:.3g} m" in page


def test_a_speed_of_sound_written_as_null_is_stated_as_the_default_it_takes(tmp_path, capsys):
    # `scenario write` puts `propagation_speed_m_s: null` in the file; a sonar then runs on 1500 m/s:
    # λ = 1500 / 100 kHz = 0.015 m and Tc = λ R / (2 δℓ V) = 0.015·100/(2·0.05·1.5) = 10 s
    out = tmp_path / "sas.yaml"
    assert main(["scenario", "write", "--preset", "sas_100khz", str(out)]) == 0
    assert "propagation_speed_m_s: null" in out.read_text()
    capsys.readouterr()
    s = budget.load_scenario(str(out))
    assert s.tc_s == pytest.approx(1500.0 / 100e3 * 100.0 / (2 * 0.05 * 1.5), rel=1e-12)
    assert s.defaults_taken() == {"propagation_speed_m_s": 1500.0}
    assert main(["bounds", "--scenario", str(out)]) == 0
    assert "propagation_speed_m_s = 1500 m/s (sonar)" in capsys.readouterr().out
    # written out, it is the user's own
    given = tmp_path / "sas_c.yaml"
    given.write_text(out.read_text().replace("propagation_speed_m_s: null", "propagation_speed_m_s: 1480.0"))
    assert budget.load_scenario(str(given)).defaults_taken() == {}


def test_the_report_marks_a_null_speed_of_sound_as_default(tmp_path):
    import html as html_lib

    out = tmp_path / "sas.yaml"
    assert main(["scenario", "write", "--preset", "sas_100khz", str(out)]) == 0
    page = html_lib.unescape(budget.build_report(str(out), ["HG9900"]).html())
    assert "default (1500 m/s, sonar)" in page


def test_bounds_cli_json_states_the_defaults_once_inside_and_beside_the_table(tmp_path, capsys):
    path = _write(tmp_path, "ka.json", KA_UAV)
    assert main(["bounds", "--scenario", path, "--json", "-"]) == 0
    out = json.loads(capsys.readouterr().out)
    # paper mode rests on Tc's keys: the Ka-band file leaves out medium and squint
    assert out["scenario_defaults"] == out["bounds"]["scenario_defaults"] == {"medium": "radar", "squint_deg": 0.0}
    assert main(["bounds", "--scenario", path]) == 0
    assert capsys.readouterr().out.count("taken at their defaults") == 1
