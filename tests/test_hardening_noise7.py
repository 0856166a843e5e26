"""Noise lab on data it was not tuned on: what the log reader finds reaches `noise arma`, raw counts
are caught by their magnitude at rest, and the Allan/Kalman front doors refuse what is not a number.

Series are made here with seeded numpy Generators (white noise, an AR(1) by its recursion);
references are theory (white-noise Allan deviation σ·√τ₀/√τ = N/√τ, the scalar Riccati
equation) or an independent implementation (the overlapping Allan variance written out, a linear
interpolation of a missing sample). Tolerances are stated per test.
"""

import json
import math

import numpy as np
import pytest

from budget.cli.main import main
from budget.errors import InputError
from budget.noise import characterize, read_log
from budget.noise.allan import allan_deviation
from budget.noise.arma import fit_arma, select_arma
from budget.noise.kalman import ArmaKalman
from budget.noise.kalman_response import frequency_response
from budget.units import G0

RATE = 100.0


def _ar1(rng, n, phi, sigma, burn=2000):
    """AR(1) by its recursion x(k) = φ x(k−1) + w(k), w ~ N(0, σ²)."""
    w = rng.normal(0.0, sigma, n + burn)
    x = np.empty(n + burn)
    x[0] = w[0]
    for k in range(1, n + burn):
        x[k] = phi * x[k - 1] + w[k]
    return x[burn:]


def _write(path, header, cols, fmt="%.9g"):
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=header, comments="", fmt=fmt)
    return path


def _oadev(y, m):
    """Overlapping Allan deviation at averaging factor m, written out (NIST SP 1065 eq. 11 on the
    averages of m samples): ½·mean over k of (ȳ_{k+m} − ȳ_k)², ȳ_k = mean of y[k:k+m]."""
    c = np.r_[0.0, np.cumsum(y)]
    avg = (c[m:] - c[:-m]) / m
    d = avg[m:] - avg[:-m]
    return math.sqrt(0.5 * np.mean(d * d))


def test_arma_cli_says_what_the_reader_repaired(tmp_path, capsys):
    """`noise arma --repair` interpolated a missing sample and said nothing (characterize did):
    now a warning names it. The model is fitted to the repaired series: the JSON variance equals
    the variance of the series interpolated here by hand (relative 1e-9, rounding only)."""
    rng = np.random.default_rng(71)
    n, k = 3000, 1234
    g = np.rad2deg(_ar1(rng, n, 0.9, 1e-3))  # deg/s
    t = np.arange(n) / RATE
    path = tmp_path / "hole.csv"
    _write(path, "time_s,gyro_z_dps", [t, g])
    lines = path.read_text().splitlines()
    lines[k + 1] = f"{t[k]:.9g},"  # sample k missing
    path.write_text("\n".join(lines) + "\n")
    args = ["noise", "arma", str(path), "--channel", "gyro_z", "--repair", "--no-outliers",
            "--detrend", "0", "--json", "-", "--quiet"]
    assert main(args) == 0
    cap = capsys.readouterr()
    warned = [ln for ln in cap.err.splitlines() if ln.startswith("sar-budget noise: warning: hole.csv: ")]
    assert any("log repaired" in w and "interpolated 1 missing value" in w for w in warned), cap.err
    own = np.deg2rad(g.copy())
    own[k] = 0.5 * (own[k - 1] + own[k + 1])
    assert json.loads(cap.out)["variance_before"] == pytest.approx(np.var(own), rel=1e-9)


def test_arma_cli_warns_of_jittery_stamps(tmp_path, capsys):
    """Stamps with steps uniform in 6…14 ms (23 % rms jitter): characterize warned, `noise arma`
    assumed uniform sampling silently. Now it warns too; the rate it uses is the stamps' span over
    their n − 1 periods, as written in the file (relative 1e-9)."""
    rng = np.random.default_rng(72)
    n = 3000
    t = np.cumsum(rng.uniform(0.006, 0.014, n))
    path = _write(tmp_path / "jitter.csv", "time_s,gyro_z_dps", [t, rng.normal(0.0, 0.1, n)])
    assert main(["noise", "arma", str(path), "--channel", "gyro_z", "--json", "-", "--quiet"]) == 0
    cap = capsys.readouterr()
    assert any("jitter [time]" in ln for ln in cap.err.splitlines()
               if ln.startswith("sar-budget noise: warning: jitter.csv: ")), cap.err
    ts = np.loadtxt(path, delimiter=",", skiprows=1, usecols=0)  # the stamps as written
    assert json.loads(cap.out)["rate_hz"] == pytest.approx((n - 1) / (ts[-1] - ts[0]), rel=1e-9)


def test_arma_cli_refusal_stays_one_line(tmp_path, capsys):
    """The reader's warning on a constant channel is not printed before the refusal: one line."""
    n = 500
    path = _write(tmp_path / "flat.csv", "time_s,gyro_z_dps", [np.arange(n) / RATE, np.full(n, 0.25)])
    assert main(["noise", "arma", str(path), "--channel", "gyro_z", "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "no noise to model" in err


def _accel_counts_log(tmp_path, rng, n=20_000, sigma_g=0.002, counts_per_g=16384.0):
    """Three accelerometers at rest (gravity tilted over x and z) and one gyro, accelerometers
    written as raw counts of a ±2 g part."""
    grav = np.array([0.17, 0.0, 0.985]) / np.linalg.norm([0.17, 0.0, 0.985])
    acc_g = grav + rng.normal(0.0, sigma_g, (n, 3))
    counts = np.round(acc_g * counts_per_g)
    cols = [np.arange(n) / RATE, rng.normal(0.0, 0.05, n), *counts.T]
    header = "time_s,gyro_z_dps,accel_x_mps2,accel_y_mps2,accel_z_mps2"
    return _write(tmp_path / "counts.csv", header, cols, fmt="%.10g"), counts


def test_three_accelerometers_in_counts_are_refused_not_fitted(tmp_path):
    """Raw counts (16384 per g) labelled m/s²: the three axes read |mean| ≈ 16384 m/s² (1670 g) at
    rest. Only the known slips (g ↔ m/s², mg ↔ g) were refused with three axes: this passed the
    reader and failed later on a catalog bound (VRW ≤ 100 m/s/√h) or not at all (`noise arma`).
    Now refused by the reader naming the three fields; the same counts through the scale the
    error asks for give the VRW of theory, N = σ·√τ₀, within 5 % (20,000 samples: the fitted
    white term's standard error is ~1 %)."""
    rng = np.random.default_rng(73)
    sigma_g = 0.002
    path, counts = _accel_counts_log(tmp_path, rng, sigma_g=sigma_g)
    with pytest.raises(InputError) as err:
        read_log(path)
    assert err.value.field == "accel_x_mps2 … accel_z_mps2"
    assert "more than gravity" in str(err.value) and "scale" in str(err.value)
    mapping = tmp_path / "scale.json"
    mapping.write_text(json.dumps({"columns": {"time_s": "time_s", "gyro_z_dps": "gyro_z_dps",
                                               "accel_x_mps2": "accel_x_g", "accel_y_mps2": "accel_y_g",
                                               "accel_z_mps2": "accel_z_g"},
                                   "scale": {c: 1.0 / 16384 for c in ("accel_x_mps2", "accel_y_mps2",
                                                                      "accel_z_mps2")}}))
    from budget.noise import LogMapping
    log = read_log(path, LogMapping.load(mapping))
    res = characterize(log, grade="tactical")
    n_true = sigma_g * G0 / math.sqrt(RATE)  # m/s²·√s, white: σ per sample × √τ₀ (+ LSB/√12, 0.1 %)
    assert res.part.accel_vrw_m_s_rt_h == pytest.approx(n_true * 60.0, rel=0.05)


def test_accelerometers_without_gravity_still_read(tmp_path):
    """Below gravity nothing is refused: a log whose logger removed gravity (|mean| ≈ 0) reads,
    and its white accelerometer noise is fitted as theory says (N = σ·√τ₀, 5 %)."""
    rng = np.random.default_rng(74)
    n, sigma = 20_000, 0.02
    cols = [np.arange(n) / RATE, rng.normal(0.0, 0.05, n), *rng.normal(0.0, sigma, (3, n))]
    path = _write(tmp_path / "linear.csv", "time_s,gyro_z_dps,accel_x_mps2,accel_y_mps2,accel_z_mps2", cols)
    res = characterize(read_log(path), grade="tactical")
    assert res.part.accel_vrw_m_s_rt_h == pytest.approx(sigma / math.sqrt(RATE) * 60.0, rel=0.05)


def test_gyro_counts_at_rest_are_warned(tmp_path, capsys):
    """A gyro column of raw counts (131 per deg/s, a 1e4-count offset) labelled deg/s read at rest
    as 10⁴ deg/s and was characterised silently: its ARW is 131× the sensor's (within 5 %: the
    white term's standard error is ~1 % on 20,000 samples). Now the reader warns (beyond 200
    deg/s at rest); a 20 deg/s consumer turn-on bias in deg/s is not warned."""
    rng = np.random.default_rng(75)
    n, sd = 20_000, 0.05  # deg/s per sample
    g = rng.normal(0.0, sd, n)
    path = _write(tmp_path / "gcounts.csv", "time_s,gyro_z_dps", [np.arange(n) / RATE, 1e4 + np.round(g * 131)],
                  fmt="%.10g")
    log = read_log(path)
    warned = [i for i in log.issues.issues if i.kind == "gyro_rate_at_rest"]
    assert len(warned) == 1 and warned[0].column == "gyro_z_dps" and warned[0].severity == "warning"
    arw = characterize(log, grade="consumer").part.gyro_arw_deg_rt_h
    assert arw == pytest.approx(131 * sd / math.sqrt(RATE) * 60.0, rel=0.05)  # deg/√h, in counts
    assert main(["noise", "characterize", str(path), "--grade", "consumer", "--json", "-", "--quiet"]) == 0
    assert "gyro_rate_at_rest [gyro_z_dps]" in capsys.readouterr().err
    ok = _write(tmp_path / "biased.csv", "time_s,gyro_z_dps", [np.arange(n) / RATE, 20.0 + g])
    assert not [i for i in read_log(ok).issues.issues if i.kind == "gyro_rate_at_rest"]


@pytest.mark.parametrize("rate", ["100", None, True, float("nan"), 0.0])
def test_allan_rate_not_a_positive_number_is_named(rate):
    """`allan_deviation(x, "100")` or `None` failed as a numpy TypeError, and `True` was read as
    1 Hz; now each is an InputError on the field rate_hz (so is the filter response's rate)."""
    x = np.random.default_rng(76).normal(0.0, 1e-3, 1000)
    with pytest.raises(InputError) as err:
        allan_deviation(x, rate)
    assert err.value.field == "rate_hz"
    kf = ArmaKalman(fit_arma(x, 1, 0))
    with pytest.raises(InputError) as err:
        frequency_response(kf, rate)
    assert err.value.field == "rate_hz"


def test_allan_accepts_numpy_numbers_and_matches_theory():
    """A numpy rate (float32, int64) is a number: the same result as the float, equal to the
    overlapping Allan deviation written out here (relative 1e-12), and on white noise within
    its own 95 % interval of σ·√τ₀/√τ at every τ of the octave list (or at most one τ outside)."""
    rng = np.random.default_rng(77)
    sigma = 2e-3
    y = rng.normal(0.0, sigma, 16_384)
    ref = allan_deviation(y, RATE, ci=0.95)
    for rate in (np.float32(RATE), np.int64(100)):
        np.testing.assert_array_equal(allan_deviation(y, rate, ci=0.95).adev, ref.adev)
    own = np.array([_oadev(y, int(m)) for m in ref.m])
    np.testing.assert_allclose(ref.adev, own, rtol=1e-12)
    theory = sigma / np.sqrt(ref.m)
    assert np.count_nonzero((theory < ref.lo) | (theory > ref.hi)) <= 1
    with pytest.raises(InputError) as err:
        allan_deviation(y, RATE, ci="0.95")
    assert err.value.field == "ci"
    with pytest.raises(InputError) as err:
        allan_deviation(["a", "b", "c"], RATE)
    assert err.value.field == "x"


@pytest.mark.parametrize("p0", [-1.0, 0.0, float("nan"), "1", True])
def test_kalman_initial_covariance_must_be_positive(p0):
    """P₀ = p0·I is a covariance: p0 = −1 was accepted (a wrong transient), NaN failed as an
    SVD LinAlgError; both are InputErrors on p0 now, as is a measurement variance given as text."""
    x = _ar1(np.random.default_rng(78), 2000, 0.8, 1e-3)
    fit = fit_arma(x - x.mean(), 1, 0)
    with pytest.raises(InputError) as err:
        ArmaKalman(fit, p0=p0)
    assert err.value.field == "p0"
    with pytest.raises(InputError) as err:
        ArmaKalman(fit, measurement_variance="1e-6")
    assert err.value.field == "measurement_variance"


def test_kalman_steady_state_independent_of_p0_equals_scalar_riccati():
    """Any valid p0 gives the steady state of the scalar Riccati equation for AR(1) with
    Q = σ² (model form), R given: P⁻ = φ²P + σ², P = P⁻R/(P⁻ + R), iterated to a fixed point here
    (relative 1e-10); the filter and the series-level API refuse non-numbers by name."""
    x = _ar1(np.random.default_rng(79), 4000, 0.95, 1e-3)
    fit = fit_arma(x - x.mean(), 1, 0)
    phi, q, r = float(fit.phi[0]), fit.sigma2, 4e-6
    p = 1.0
    for _ in range(20_000):
        pp = phi * phi * p + q
        p = pp * r / (pp + r)
    for p0 in (1e-6, 1.0, 1e3):
        kf = ArmaKalman(fit, measurement_variance=r, process_noise="model", p0=p0)
        assert kf.P_ss[0, 0] == pytest.approx(p, rel=1e-10)
    with pytest.raises(InputError) as err:
        kf.filter("abc")
    assert err.value.field == "z"
    with pytest.raises(InputError) as err:
        select_arma(["a"] * 200)
    assert err.value.field == "x"


def test_a_complex_series_is_refused_not_cut_to_its_real_part():
    x = np.random.default_rng(3).standard_normal(1000) * (1 + 1j)
    with pytest.raises(InputError) as e:
        allan_deviation(x, 100.0, channel="gyro_z")
    assert e.value.field == "gyro_z" and "real" in e.value.expected
    # the same rule (budget.noise.arguments.float_series) at the ARMA and Kalman front doors
    with pytest.raises(InputError) as e:
        select_arma(x)
    assert "complex" in str(e.value)
    kf = ArmaKalman(fit_arma(x.real, 1, 0))
    with pytest.raises(InputError) as e:
        kf.filter(x)
    assert e.value.field == "z" and "complex" in str(e.value)


@pytest.mark.parametrize("bad", ["ab", (5.0,), (10.0, 1.0), (0.1, math.nan), [1.0, 2.0, 3.0]])
def test_a_bad_tau_range_is_refused_by_field(bad):
    from budget.noise import fit_noise_terms

    r = allan_deviation(np.random.default_rng(4).standard_normal(20_000), 100.0, channel="gyro_z")
    with pytest.raises(InputError) as e:
        fit_noise_terms(r, tau_range_s=bad)
    assert e.value.field == "tau_range_s"
    assert fit_noise_terms(r, tau_range_s=(0.01, 10.0)).values["N"] is not None  # a good range fits


@pytest.mark.parametrize("freq", [["a"], [1.0, math.nan], [-1.0], [[1.0, 2.0]]])
def test_filter_response_frequencies_not_numbers_are_named(freq):
    x = np.random.default_rng(78).normal(0.0, 1e-3, 1000)
    kf = ArmaKalman(fit_arma(x, 1, 0))
    with pytest.raises(InputError) as err:
        frequency_response(kf, 100.0, freq)
    assert err.value.field == "freq_hz"
    assert frequency_response(kf, 100.0, 5.0).magnitude.shape == (1,)  # one frequency is one value
