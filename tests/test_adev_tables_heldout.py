"""Allan tables in the layouts other tools write, checked against curves of known coefficients.

Every expectation comes from the coefficients the curve was made with or from a closed form
(IEEE Std 952-1997 Annex C: white rate noise N gives σ(τ) = N/√τ, flicker B an Allan floor
√(2 ln2/π)·B ≈ 0.664·B, rate random walk K gives K·√(τ/3)), never from the code's output.
"""

from __future__ import annotations

import math

import allantools
import numpy as np
import pytest

from budget.cli.main import main
from budget.errors import InputError
from budget.noise import characterize, read_adev_table

DEG, HOUR = math.pi / 180, 3600.0
FLOOR = math.sqrt(2 * math.log(2) / math.pi)  # 0.664: Allan floor of the flicker term per B


def _curve(tau, N=0.0, B=0.0, K=0.0):
    """IEEE-952 Allan deviation (Annex C closed form) of white, flicker and random-walk rate noise."""
    tau = np.asarray(tau, float)
    return np.sqrt(N ** 2 / tau + FLOOR ** 2 * B ** 2 + K ** 2 * tau / 3)


# a tactical gyro: ARW 0.3 deg/√h, bias instability B = 10 deg/h, RRW 3 deg/h/√h (SI below)
N_GYRO, B_GYRO, K_GYRO = 0.3 * DEG / 60, 10 * DEG / HOUR, 3 * DEG / HOUR / 60
DATASHEET_TAU = np.array([0.01, 0.03, 0.1, 0.3, 1, 3, 10, 30, 100, 300, 1000, 3000])


def _write(path, header, rows):
    path.write_text(header + "\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows) + "\n",
                    encoding="utf-8")
    return path


def test_datasheet_sigma_header_in_deg_h_is_read_and_fitted(tmp_path):
    """A digitised datasheet curve, ``tau (s), sigma (deg/h)``: was refused as a wide table with a
    channel 'sigma (deg/h)'. Read as the ADEV in deg/h; on the exact curve the fit returns the
    coefficients it was made with and the catalog row gives the bias instability as 0.664·B."""
    sigma = _curve(DATASHEET_TAU, N_GYRO, B_GYRO, K_GYRO) / (DEG / HOUR)
    p = _write(tmp_path / "ds.csv", "tau (s),sigma (deg/h)", zip(DATASHEET_TAU, sigma))
    r = read_adev_table(p, 100.0, 10 ** 7, channels=["gyro_z"])["gyro_z"]
    assert np.allclose(r.adev, _curve(DATASHEET_TAU, N_GYRO, B_GYRO, K_GYRO), rtol=1e-12)
    c = characterize({"gyro_z": r})
    assert c.channels["gyro_z"].N == pytest.approx(N_GYRO, rel=0.01)
    assert c.channels["gyro_z"].B == pytest.approx(B_GYRO, rel=0.01)
    assert c.part.gyro_arw_deg_rt_h == pytest.approx(0.3, rel=0.01)
    assert c.part.gyro_bias_instability_deg_h == pytest.approx(FLOOR * 10, rel=0.01)


@pytest.mark.parametrize("name", ["allan_variance [(deg/s)^2]", "AVAR [(deg/s)^2]", "sigma^2 [(deg/s)^2]",
                                  "Allan variance [(deg/s)^2]", "oavar [(deg/s)^2]"])
def test_variance_columns_are_read_as_variances(tmp_path, name):
    """MATLAB's allanvar writes the variance: under any of its usual names it is read as σ²
    (square root taken), never as a deviation (``allan_variance`` was refused as a channel)."""
    tau = np.array([0.01, 0.02, 0.04, 0.08, 0.16, 0.32])
    adev_dps = N_GYRO / np.sqrt(tau) / DEG  # white noise: σ(τ) = N/√τ
    p = _write(tmp_path / "v.csv", f"tau,{name}", zip(tau, adev_dps ** 2))
    r = read_adev_table(p, 100.0, 10 ** 6, channels=["gyro_y"])["gyro_y"]
    assert np.allclose(r.adev, N_GYRO / np.sqrt(tau), rtol=1e-12)


@pytest.mark.parametrize("name", ["Allan deviation (deg/s)", "allan_deviation [deg/s]", "oadev [deg/s]"])
def test_deviation_column_names(tmp_path, name):
    tau = np.array([0.01, 0.02, 0.04, 0.08])
    p = _write(tmp_path / "d.csv", f"tau (s),{name}", zip(tau, N_GYRO / np.sqrt(tau) / DEG))
    r = read_adev_table(p, 100.0, 10 ** 6, channels=["gyro_x"])["gyro_x"]
    assert np.allclose(r.adev, N_GYRO / np.sqrt(tau), rtol=1e-12)


def _allantools_table(tmp_path, n=2 ** 16, rate=100.0, seed=3):
    """White rate noise of ARW N_GYRO → ``allantools.oadev`` → written as pandas writes it
    (its row index first under an empty name; columns taus, adev, adev_err, n)."""
    x = N_GYRO * math.sqrt(rate) * np.random.default_rng(seed).standard_normal(n)
    taus, ad, ade, ns = allantools.oadev(x, rate=rate, data_type="freq", taus="octave")
    rows = [(i, t, a, e, k) for i, (t, a, e, k) in enumerate(zip(taus, ad, ade, ns))]
    return _write(tmp_path / "at.csv", ",taus,adev [rad/s],adev_err,n", rows), taus, ns


def test_allantools_pandas_table_is_read(tmp_path):
    """allantools' oadev saved with pandas was refused (index column, adev_err, n unknown). The
    index is dropped, adev_err is not taken for a confidence interval (it says so), and the
    white-noise N comes back within 3 times IEEE-952 Annex C's relative error of σ(τ),
    1/√(2(K − 1)) with K = n/m clusters, at the middle of the τ range (the fit weighs the curve's
    points about equally: its error is that of a typical point, not of the shortest τ)."""
    n, rate = 2 ** 16, 100.0
    p, taus, ns = _allantools_table(tmp_path, n, rate)
    r = read_adev_table(p, rate, n, channels=["gyro_z"])["gyro_z"]
    assert np.allclose(r.tau_s, taus)
    assert any("adev_err not used" in note for note in r.notes)
    # adev/√n would say EDF = n/2 (~16000 at the longest τ); a few clusters there have a few
    assert r.edf[-1] < 0.01 * ns[-1] / 2
    fit = characterize({"gyro_z": r}).channels["gyro_z"]
    m_mid = math.sqrt(taus[0] * taus[-1]) * rate
    tol = 3 / math.sqrt(2 * (n / m_mid - 1))
    assert fit.N == pytest.approx(N_GYRO, rel=tol)


def test_allantools_n_column_checks_the_record_length(tmp_path):
    """The table's n (differences averaged) fixes the record: n = N + 1 − 2m; a --samples that
    contradicts it would give every row a wrong EDF and is refused, naming the row and the N."""
    n = 2 ** 16
    p, _, ns = _allantools_table(tmp_path, n)
    assert ns[0] == n + 1 - 2  # allantools' own count at m = 1 (the closed form used here)
    with pytest.raises(InputError) as err:
        read_adev_table(p, 100.0, 50_000, channels=["gyro_z"])
    assert err.value.row == 2 and err.value.field == "n" and f"--samples {n}" in str(err.value)


def test_allantools_table_on_the_cli(tmp_path, capsys):
    n = 2 ** 16
    p, _, _ = _allantools_table(tmp_path, n)
    assert main(["noise", "characterize", str(p), "--rate-hz", "100", "--samples", str(n),
                 "--channels", "gyro_z", "--quiet"]) == 0
    out = capsys.readouterr()
    assert "adev_err not used" in out.err and "ARW" in out.out


def test_pandas_index_only_dropped_when_it_is_one(tmp_path):
    """An unnamed first column that is not the row numbers is not dropped silently."""
    tau = np.array([0.01, 0.02, 0.04])
    rows = [(7.0, t, a) for t, a in zip(tau, N_GYRO / np.sqrt(tau))]
    p = _write(tmp_path / "u.csv", ",tau_s,adev [rad/s]", rows)
    with pytest.raises(InputError) as err:
        read_adev_table(p, 100.0, 10 ** 6, channels=["gyro_z"])
    assert "Unnamed" in str(err.value) and err.value.row == 1
