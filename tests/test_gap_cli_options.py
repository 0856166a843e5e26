"""``sar-budget gap --low-frequency / --decorrelate``: passed through to ``run_gap``, recorded in
the report, and refused on an Allan table (where they would have nothing to act on)."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from budget.cli.main import main
from budget.errors import InputError
from budget.gap import run_gap
from budget.gap.whitening import SPECTRAL_KINDS
from budget.imu import NoiseModel, simulate_static_log
from budget.units import CHANNELS, rad_s_to_dps

RATE = 100.0
N = 16_384
MODEL_JSON = {"rate_hz": RATE, "gyro_arw_deg_rt_h": 0.5, "gyro_bias_instability_deg_h": 5.0,
              "accel_vrw_m_s_rt_h": 0.05, "accel_bias_instability_ug": 50.0}
BASE = NoiseModel.model_validate(MODEL_JSON)
CHANS = ["gyro_x", "accel_x"]
# max_steps 0: the statistics of the log against the base model, which is what the options change
ARGS = ["--seed", "2", "--channels", ",".join(CHANS), "--max-steps", "0", "--quiet"]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("gapopt")
    x = simulate_static_log(BASE, N, RATE, np.random.default_rng(31))
    cols = {"time_s": np.arange(N) / RATE}
    for ch in CHANNELS:
        cols[f"{ch}_dps" if ch.startswith("gyro") else f"{ch}_mps2"] = (
            rad_s_to_dps(x[ch]) if ch.startswith("gyro") else x[ch])
    log = d / "log.csv"
    pd.DataFrame(cols).to_csv(log, index=False, float_format="%.9g")
    model = d / "model.json"
    model.write_text(json.dumps(MODEL_JSON))
    return log, model


def _cli(files, tmp_path, name, *flags, capsys=None):
    log, model = files
    rep = tmp_path / f"{name}.json"
    assert main(["gap", str(log), "--model", str(model), "--report", str(rep), *ARGS, *flags]) == 0
    out = capsys.readouterr().out if capsys is not None else ""
    return json.loads(rep.read_text()), out


def _py(files, **opts):
    log, model = files
    return run_gap(log, model, seed=2, channels=CHANS, max_steps=0, **opts)


@pytest.fixture(scope="module")
def default_py(files):
    return _py(files)


def test_default_records_both_options_off(files, tmp_path, capsys, default_py):
    out, text = _cli(files, tmp_path, "default", capsys=capsys)
    assert out["options"] == {"low_frequency": False, "decorrelate": False, "slow_modes": True}
    assert "psd_low" not in out["input"]["signatures"]
    assert "options:" not in text
    # the CLI is the Python call with the same arguments
    assert out["gap_before"] == pytest.approx(default_py.gap_before, rel=1e-12)
    assert default_py.options == {"low_frequency": False, "decorrelate": False, "slow_modes": True}
    assert "walk" in out["input"]["signatures"]


def test_low_frequency_adds_the_low_bands_and_leaves_the_other_terms(files, tmp_path, capsys,
                                                                    default_py):
    out, text = _cli(files, tmp_path, "lf", "--low-frequency", capsys=capsys)
    assert out["options"] == {"low_frequency": True, "decorrelate": False, "slow_modes": True}
    assert "psd_low" in out["input"]["signatures"]
    assert "options: low-frequency bands" in text and "(not the default)" in text
    py = _py(files, low_frequency=True)
    assert out["gap_before"] == pytest.approx(py.gap_before, rel=1e-12)
    for ch in CHANS:
        t0, t1 = default_py.channels[ch].terms_before, py.channels[ch].terms_before
        extra = t1.n_terms - t0.n_terms
        # the bands are added after the default terms; the same realizations (same seed) give
        # the other terms exactly as without the option
        assert extra >= 3 and set(t1.kind[t0.n_terms:]) == {"psd_low"}
        assert "psd_low" not in set(t0.kind)
        np.testing.assert_array_equal(t1.z[:t0.n_terms], t0.z)
        assert out["channels"][ch]["n_terms"] == t1.n_terms
        assert out["channels"][ch]["gap_before"] != pytest.approx(t0.gap, rel=1e-9)


def test_decorrelate_changes_the_sum_not_the_reported_z(files, tmp_path, capsys, default_py):
    out, text = _cli(files, tmp_path, "dec", "--decorrelate", capsys=capsys)
    assert out["options"] == {"low_frequency": False, "decorrelate": True, "slow_modes": True}
    assert "psd_low" not in out["input"]["signatures"]
    assert "options: spectral terms summed decorrelated" in text
    py = _py(files, decorrelate=True)
    assert out["gap_before"] == pytest.approx(py.gap_before, rel=1e-12)
    assert out["gap_before"] != pytest.approx(default_py.gap_before, rel=1e-6)
    for ch in CHANS:
        t0, t1 = default_py.channels[ch].terms_before, py.channels[ch].terms_before
        # the same statistics, reported as measured ...
        assert t1.n_terms == t0.n_terms == out["channels"][ch]["n_terms"]
        np.testing.assert_array_equal(t1.z, t0.z)
        assert t0.zw is None and t1.zw is not None
        # ... summed as innovations of the spectral block; the other terms as they are
        spectral = np.isin(t1.kind, SPECTRAL_KINDS)
        np.testing.assert_array_equal(t1.zw[~spectral], t1.z[~spectral])
        assert not np.allclose(t1.zw[spectral], t1.z[spectral])
        assert t1.gap == pytest.approx(float(np.sum(t1.zw ** 2)) / t1.n_terms, rel=1e-12)
        assert out["channels"][ch]["gap_before"] == pytest.approx(t1.gap, rel=1e-12)


def test_both_options_together(files, tmp_path, capsys):
    out, text = _cli(files, tmp_path, "both", "--low-frequency", "--decorrelate", capsys=capsys)
    assert out["options"] == {"low_frequency": True, "decorrelate": True, "slow_modes": True}
    line = next(ln for ln in text.splitlines() if ln.startswith("options:"))
    assert "--low-frequency" in line and "--decorrelate" in line
    py = _py(files, low_frequency=True, decorrelate=True)
    assert out["gap_before"] == pytest.approx(py.gap_before, rel=1e-12)
    assert py.channels["gyro_x"].terms_before.zw is not None
    assert "psd_low" in set(py.channels["gyro_x"].terms_before.kind)


def test_no_slow_modes_removes_the_slow_mode_terms_only(files, tmp_path, capsys, default_py):
    """--no-slow-modes leaves out the slow-mode statistic and the early statistic (both read the
    record's slowest modes) and nothing else."""
    out, text = _cli(files, tmp_path, "nsm", "--no-slow-modes", capsys=capsys)
    assert out["options"] == {"low_frequency": False, "decorrelate": False, "slow_modes": False}
    assert "walk" not in out["input"]["signatures"] and "early" not in out["input"]["signatures"]
    assert "options: slow modes left out (--no-slow-modes)" in text
    py = _py(files, slow_modes=False)
    assert out["gap_before"] == pytest.approx(py.gap_before, rel=1e-12)
    for ch in CHANS:
        t0, t1 = default_py.channels[ch].terms_before, py.channels[ch].terms_before
        keep = ~np.isin(t0.kind, ("walk", "early"))
        assert np.count_nonzero(~keep) == 2 and not {"walk", "early"} & set(t1.kind)
        # the other statistics as with them: the same realizations (same seed)
        np.testing.assert_array_equal(t1.z, t0.z[keep])


def test_cross_validation_records_the_options(files, tmp_path):
    log, model = files
    rep = tmp_path / "cv.json"
    assert main(["gap", str(log), "--model", str(model), "--report", str(rep), "--test-log", str(log),
                 *ARGS, "--decorrelate"]) == 0
    out = json.loads(rep.read_text())
    assert out["options"] == {"low_frequency": False, "decorrelate": True, "slow_modes": True}
    assert out["cross_validation"]["options"]["decorrelate"] is True
    assert out["cross_validation"]["options"]["low_frequency"] is False
    assert out["cross_validation"]["options"]["slow_modes"] is True


@pytest.fixture(scope="module")
def allan_table(tmp_path_factory):
    from budget.noise import allan_deviation
    x = simulate_static_log(BASE, N, RATE, np.random.default_rng(6))
    a = allan_deviation(x["gyro_x"], RATE)
    path = tmp_path_factory.mktemp("gapopt_tab") / "adev.csv"
    pd.DataFrame({"channel": "gyro_x_rps", "tau_s": a.tau_s, "adev": a.adev}).to_csv(path, index=False)
    return path


@pytest.mark.parametrize("flags, named", [(["--low-frequency"], ["--low-frequency"]),
                                          (["--decorrelate"], ["--decorrelate"]),
                                          (["--low-frequency", "--decorrelate"],
                                           ["--low-frequency", "--decorrelate"])])
def test_options_on_an_allan_table_are_refused(allan_table, files, tmp_path, capsys, flags, named):
    _, model = files
    rep = tmp_path / "r.json"
    code = main(["gap", str(allan_table), "--model", str(model), "--report", str(rep),
                 "--rate-hz", str(RATE), "--samples", str(N), "--channels", "gyro_x", "--quiet", *flags])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err
    assert "needs a log" in err and "Allan table" in err
    assert all(n in err for n in named)
    assert not rep.exists()
    # without the options the same table runs (ADEV only)
    assert main(["gap", str(allan_table), "--model", str(model), "--report", str(rep),
                 "--rate-hz", str(RATE), "--samples", str(N), "--channels", "gyro_x", "--quiet",
                 "--max-steps", "0"]) == 0
    # an Allan table has no record: no slow modes either
    assert json.loads(rep.read_text())["options"] == {"low_frequency": False, "decorrelate": False,
                                                      "slow_modes": False}


def test_python_call_refuses_them_on_a_table_too(allan_table):
    with pytest.raises(InputError, match="low_frequency .*needs a log"):
        run_gap(allan_table, BASE, rate_hz=RATE, samples=N, channels=["gyro_x"], low_frequency=True)
