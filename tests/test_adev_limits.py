"""What an Allan curve cannot constrain: upper limits of terms not resolved, the resolved test
against correlated overlapping-τ points, digitised datasheet curves and header units.

Expectations come from the coefficients the curves are synthesised with (``imu_noise``, the
package's generator) or from the IEEE-952 closed form σ²(τ) = 3Q²/τ² + N²/τ + (2 ln2/π)B² +
K²τ/3 + R²τ²/2.
"""

import json
import math

import numpy as np
import pytest
from scipy import stats

from budget import units as u
from budget.cli.main import main
from budget.errors import InputError
from budget.noise import allan_deviation, characterize, fit_noise_terms, read_adev_table
from budget.noise.measurement import read_measurement
from budget.noise.synth import imu_noise
from budget.noise.terms import FLICKER, TERMS, adev_model, upper_limits

DEG, H = u.DEG, u.HOUR
SEEDS = range(20)
#: 2^20 samples at 100 Hz: a 2.9-h record, octave τ up to 2621 s
N_29H, RATE = 2 ** 20, 100.0


def _curves(truth, n=N_29H, rate=RATE, seeds=SEEDS):
    for s in seeds:
        y = imu_noise(n, rate, np.random.default_rng(5000 + s), **truth)
        r = allan_deviation(y, rate, channel="gyro_z", unit="rad/s")
        yield r, fit_noise_terms(r)


# --- upper limits: closed forms ----------------------------------------------------------------

def test_upper_limits_of_a_white_curve_closed_form():
    """σ² = N²/τ exactly (a digitised curve, no confidence level): each limit is the term's
    form meeting the curve at the τ end its slope favours."""
    N = 1e-4
    tau = np.logspace(-2, 3, 11)
    lim = upper_limits(tau, N ** 2 / tau, np.full(tau.size, np.inf), None)
    assert lim["N"] == pytest.approx(N)
    assert lim["Q"] == pytest.approx(N * math.sqrt(tau[0] / 3))  # 3Q²/τ² ≤ N²/τ at τ_min
    assert lim["B"] == pytest.approx(N / math.sqrt(tau[-1] * FLICKER))  # at τ_max
    assert lim["K"] == pytest.approx(math.sqrt(3) * N / tau[-1])
    assert lim["R"] == pytest.approx(math.sqrt(2) * N / tau[-1] ** 1.5)


def test_upper_limit_uses_the_joint_chi2_bound():
    """One-sided χ² bound of each of n points at (1 − 0.95)/n: σ²·edf/χ²_a(edf)."""
    tau, var, edf = np.array([1.0, 2.0]), np.array([4.0, 1.0]), np.array([10.0, 3.0])
    lim = upper_limits(tau, var, edf, 0.95)
    up = var * edf / stats.chi2.ppf(0.05 / 2, edf)
    assert lim["B"] == pytest.approx(math.sqrt(min(up) / FLICKER))
    assert lim["K"] == pytest.approx(math.sqrt(min(up * 3 / tau)))


# --- white noise: every other term not resolved, with a limit ----------------------------------

def test_white_noise_leaves_every_other_term_unresolved_with_a_limit():
    N = 1e-4
    for r, f in _curves(dict(N=N), n=2 ** 18, seeds=range(5)):
        assert f.resolved["N"] and f.N == pytest.approx(N, rel=0.03)
        assert f.limits["N"] is None  # resolved: a value, no limit
        for t in ("Q", "B", "K", "R"):
            assert not f.resolved[t]
            assert f.limits[t] is not None and 0.0 <= f.limits[t] < math.inf  # ≥ the true 0
        # the limits are what the curve allows: the term at its limit touches the curve's joint
        # upper bound at one τ and stays under it at the others
        up = r.adev ** 2 * r.edf / stats.chi2.ppf(0.05 / r.tau_s.size, r.edf)
        k2 = f.limits["K"] ** 2 * r.tau_s / 3
        assert np.all(k2 <= up * (1 + 1e-9)) and np.isclose(k2 / up, 1.0).any()
        assert "not resolved: ≤" in f.summary()


# --- the resolved test and the false-resolution rate ---------------------------------------------

#: truths of 20 simulated records each; a term absent from the truth must not be resolved
FALSE_CASES = {
    "white": (dict(N=1e-4), 2 ** 18),
    "white+rrw": (dict(N=1e-4, K=2e-6), 2 ** 18),
    "white+flicker": (dict(N=1e-4, B=3e-5), 2 ** 18),
    # FOG-like: bias instability and rate random walk only beyond the longest τ
    "fog": (dict(N=0.002 * DEG / 60, B=0.003 * DEG / H, K=0.01 * DEG / H / 60), N_29H),
}


@pytest.mark.slow
@pytest.mark.parametrize("case", list(FALSE_CASES))
def test_false_resolution_rate(case):
    """Curves (of 20) on which a term the truth lacks is reported resolved — before (the old
    test alone: variance coefficient > 2σ, i.e. value > 4× its ±) and now (also above the
    curve's uncertainty over an octave of τ). Measured on these seeds: white 1 → 0, white+rrw
    0 → 0, white+flicker 0 → 0, fog 0 → 0 (another generator's 20 seeds: 1 → 0, 3 → 0, 1 → 0,
    0 → 0); target ≤ 1/20. On the FOG-like curves the old test resolved B at 1.84–1.87× the truth
    on 3/20 (the review's 2.57×); now no resolved term is more than 1.5× its truth."""
    truth, n = FALSE_CASES[case]
    before = after = 0
    for _, f in _curves(truth, n=n):
        absent = [t for t in TERMS if t not in truth]
        old = {t: f.values[t] is not None and f.values[t] > 4 * f.sigmas[t] for t in TERMS}
        before += any(old[t] for t in absent)
        after += any(f.resolved[t] for t in absent)
        for t in truth:
            if f.resolved[t]:
                assert f.values[t] / truth[t] < 1.5, (t, f.values[t] / truth[t])
            else:
                assert f.limits[t] >= truth[t]  # a term not resolved: its true value is allowed
    assert after <= 1, f"{case}: {after}/20 curves resolve a term the truth lacks (before: {before}/20)"
    assert after <= before


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_rrw_on_a_29h_curve_has_a_limit_above_the_truth():
    """K = 3 deg/h/√h under 0.2 deg/√h of ARW on a 2.9-h record: not resolved, and the limit
    allows the truth on 20/20 records (measured 1.3–2.5× the truth)."""
    truth = dict(N=0.2 * DEG / 60, K=3 * DEG / H / 60)
    ratios = []
    for _, f in _curves(truth):
        if not f.resolved["K"]:
            ratios.append(f.limits["K"] / truth["K"])
    assert len(ratios) >= 18 and min(ratios) >= 1.0 and max(ratios) < 4.0


def test_catalog_row_carries_the_limit_in_notes_not_as_a_value(tmp_path):
    truth = dict(N=0.2 * DEG / 60, K=3 * DEG / H / 60)
    y = imu_noise(N_29H, RATE, np.random.default_rng(5001), **truth)
    res = characterize({"gyro_z": allan_deviation(y, RATE, channel="gyro_z", unit="rad/s")},
                       grade="tactical")
    fit = res.channels["gyro_z"]
    assert not fit.resolved["K"]
    lim = u.rad_s_rt_s_to_deg_h_rt_h(fit.limits["K"])
    assert lim >= 3.0
    text = f"RRW not resolved: ≤ {lim:.3g} deg/h/√h at 95 %"
    assert text in res.part.notes and text in res.notes
    assert f"≤ {lim:.3g} deg/h/√h at 95 %" in res.summary()
    row = res.part.gyro_rrw_deg_h_rt_h  # absent → empty; fitted → the fitted value, never the limit
    assert row is None or (row < lim and "gyro_rrw_deg_h_rt_h: fitted but not resolved" in res.part.notes)
    d = res.to_dict()
    assert d["row_limits"]["gyro_rrw_deg_h_rt_h"] == pytest.approx(lim)
    assert d["limits"]["gyro_z"]["K"] == pytest.approx(fit.limits["K"]) and d["limits"]["gyro_z"]["N"] is None
    assert d["limit_level"]["gyro_z"] == 0.95
    json.dumps(d)


# --- digitised datasheet curves ------------------------------------------------------------------

TRUE_DS = dict(N=0.3 / 60 * DEG, B=10.0 / H * DEG, K=3.0 / H / 60 * DEG)  # ARW 0.3, BI 10, RRW 3
TAU_DS = np.array([0.01, 0.03, 0.1, 0.3, 1, 3, 10, 30, 100, 300, 1000, 3000])


def _datasheet(path, header="tau (s),sigma (deg/h)", factor=DEG / H, tau=TAU_DS):
    a = adev_model(tau, **TRUE_DS) / factor
    path.write_text(header + "\n" + "".join(f"{t:g},{v:.6g}\n" for t, v in zip(tau, a)), encoding="utf-8")
    return path


def test_digitised_curve_is_read_without_a_rate(tmp_path):
    p = _datasheet(tmp_path / "ds.csv")
    r = read_adev_table(p, channels=["gyro_z"])["gyro_z"]
    np.testing.assert_allclose(r.tau_s, TAU_DS)  # τ as given (0.03 s is no multiple of a period)
    assert r.samples == 0 and math.isnan(r.rate_hz) and np.all(np.isinf(r.edf)) and np.all(np.isnan(r.hi))
    assert "digitised curve" in r.notes[0] and "no confidence bounds" in r.notes[0]
    res = characterize({"gyro_z": r})
    f = res.channels["gyro_z"]
    assert not f.uncertainty_known and f.limit_level is None
    assert f.N == pytest.approx(TRUE_DS["N"], rel=0.01) and f.B == pytest.approx(TRUE_DS["B"], rel=0.01)
    assert all(s is None for s in f.sigmas.values())  # unknown, not zero
    assert res.part.rate_hz is None and "rate not known" in res.summary()
    assert "digitised curve" in res.part.notes and "uncertainty is unknown" in res.part.notes
    assert res.part.gyro_arw_deg_rt_h == pytest.approx(0.3, rel=0.01)
    for t in TERMS:
        if f.limits[t] is not None:
            assert "no confidence level" in f.limit_text(t)
            assert f.limits[t] >= TRUE_DS.get(t, 0.0) * (1 - 1e-6)


def test_digitised_curve_with_its_interval_has_a_confidence(tmp_path):
    a = adev_model(TAU_DS, **TRUE_DS) / (DEG / H)
    p = tmp_path / "ci.csv"
    p.write_text("tau (s),adev (deg/h),lci,uci\n" + "".join(
        f"{t:g},{v:.6g},{v * 0.9:.6g},{v * 1.1:.6g}\n" for t, v in zip(TAU_DS, a)))
    r = read_adev_table(p, channels=["gyro_z"])["gyro_z"]
    assert np.all(np.isfinite(r.edf)) and "lci/uci" in r.notes[0]
    assert fit_noise_terms(r).uncertainty_known


def test_digitised_curve_on_the_command_line(tmp_path, capsys):
    p = _datasheet(tmp_path / "ds.csv")
    assert main(["noise", "characterize", str(p), "--channels", "gyro_z", "--grade", "tactical",
                 "--json", "-"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["uncertainty_known"]["gyro_z"] is False and out["part"]["rate_hz"] is None
    assert out["part"]["gyro_arw_deg_rt_h"] == pytest.approx(0.3, rel=0.01)


def test_wrong_rate_still_points_to_rate_hz(tmp_path):
    """A table computed from a 100 Hz record, given 37 Hz: refused, with --rate-hz named."""
    y = imu_noise(100_000, 100.0, np.random.default_rng(1), N=1e-3)
    r = allan_deviation(y, 100.0)
    p = tmp_path / "logged.csv"
    p.write_text("channel,tau_s,adev\n" + "".join(f"gyro_z_rps,{float(t)!r},{float(a)!r}\n" for t, a in zip(r.tau_s, r.adev)))
    with pytest.raises(InputError) as err:
        read_adev_table(p, 37.0, 100_000)
    assert "--rate-hz" in str(err.value) and "digitised" in str(err.value)
    # one of rate and length alone is refused; the model gap (no digitised curves) still needs both
    with pytest.raises(InputError, match="record length is required"):
        read_adev_table(p, 100.0, None)
    with pytest.raises(InputError, match="needs the record's rate and length"):
        read_measurement(p)


# --- header units ----------------------------------------------------------------------------------

@pytest.mark.parametrize("unit, factor", [("deg/hour", DEG / H), ("deg/hr", DEG / H), ("°/hour", DEG / H),
                                          ("degrees/hour", DEG / H), ("mrad/s", 1e-3), ("mrad/sec", 1e-3)])
def test_rate_units_in_a_table_header(tmp_path, unit, factor):
    p = _datasheet(tmp_path / "u.csv", header=f"tau (s),sigma ({unit})", factor=factor)
    r = read_adev_table(p, channels=["gyro_z"])["gyro_z"]
    np.testing.assert_allclose(r.adev, adev_model(TAU_DS, **TRUE_DS), rtol=1e-5)


@pytest.mark.parametrize("unit", ["mrad/s/√Hz", "deg/√h", "deg/s/rtHz"])
def test_a_density_unit_in_an_adev_header_is_refused_as_such(tmp_path, unit):
    p = _datasheet(tmp_path / "d.csv", header=f"tau (s),adev ({unit})")
    with pytest.raises(InputError, match="noise density") as err:
        read_adev_table(p, channels=["gyro_z"])
    assert "Allan deviation is in the channel's rate unit" in str(err.value)


def test_mrad_s_is_one_channel_unit_of_the_one_table():
    assert u.CHANNEL_UNIT_TO_SI["mrps"] == 1e-3 and "mrps" in u.CHANNEL_UNIT_TAGS["gyro"]
    assert u.split_channel_column("gyro_x_mrad_s") == ("gyro_x", "mrps")
    assert u.split_channel_column("gyro_x [mrad/s]") == ("gyro_x", "mrps")
