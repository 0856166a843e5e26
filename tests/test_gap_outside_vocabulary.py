"""Logs with effects the gap vocabulary does not have (``tests/gap_outside.py``, an independent
generator): what the workflow says about them.

* a component common to two or three channels: the cross-channel coherence check
  (:mod:`budget.gap.coherence`) — its null is the closed form for independent Gaussian
  channels, |γ|² ~ Beta(1, K − 1) per bin, checked here against Beta draws; on model-following
  logs of both independent generators it fires on no log; on the common vibration it names the
  two channels, the band around the resonator's centre, in phase;
* random telegraph noise (a Gauss–Markov spectrum, two-valued): the slow part's kurtosis
  (:mod:`budget.gap.two_valued`), against a Gaussian twin of the same spectrum;
* a temperature sensitivity curved in T (:mod:`budget.gap.temperature_curve`).

Expectations come from the generators' parameters and the Beta null, not from the code's output.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats
from scipy.signal import lfilter

import gap_outside as go
import gap_truth as gt
from budget.gap import coherence, log_from_arrays, run_gap, temperature_curve, two_valued
from budget.imu import NoiseModel

BASE = NoiseModel.model_validate(go.base_model_dict())
TEN_MIN = 60_000


def test_band_tail_is_the_beta_null():
    k = coherence.SEGMENTS
    # one bin: P(|γ|² ≥ c) = (1 − c)^(K − 1) for Beta(1, K − 1)
    for c in (0.05, 0.3, 0.8):
        assert coherence.log10_tail(np.array([c]), k) == pytest.approx((k - 1) * math.log10(1 - c), rel=1e-9)
        assert 10 ** coherence.log10_tail(np.array([c]), k) == pytest.approx(stats.beta.sf(c, 1, k - 1), rel=1e-9)
    # n bins: the tail of the sum against 20 000 draws of n independent Beta(1, K − 1)
    rng = np.random.default_rng(0)
    draws = rng.beta(1, k - 1, size=(20_000, 12))
    p = np.array([10 ** coherence.log10_tail(d, k) for d in draws])
    for q in (0.01, 0.05, 0.5):
        assert np.mean(p < q) == pytest.approx(q, abs=4 * math.sqrt(q * (1 - q) / p.size) + 1e-3)


def test_independent_gaussian_channels_have_the_null_coherence():
    # white channels drawn here: every band's p-value is uniform; no finding at α = 0.01
    rng = np.random.default_rng(1)
    n, k = 2 ** 16, coherence.SEGMENTS
    chans = {c: rng.standard_normal(n) for c in ("gyro_x", "gyro_y", "gyro_z")}
    assert coherence.findings(chans, 100.0) == []
    # the statistic's own per-bin mean is 1/K (Beta(1, K − 1))
    seg = n // k
    win = np.hanning(seg + 1)[:-1]
    x, y = (np.fft.rfft(chans[c][:k * seg].reshape(k, seg) * win, axis=1) for c in ("gyro_x", "gyro_y"))
    g2 = np.abs(np.sum(x * np.conj(y), 0)) ** 2 / (np.sum(abs(x) ** 2, 0) * np.sum(abs(y) ** 2, 0))
    g2 = g2[3:seg // 2:2]
    assert np.mean(g2) == pytest.approx(1.0 / k, abs=4 * math.sqrt(stats.beta.var(1, k - 1) / g2.size))


@pytest.mark.parametrize("gen,seed", [(go, 11), (go, 12), (gt, 13), (gt, 14)])
def test_no_finding_on_model_following_logs(gen, seed):
    x, temp, _ = gen.make(None, TEN_MIN, seed)
    assert coherence.findings(x, 100.0, temp) == []


def _resonator_peak_coherence() -> float:
    """|γ|² at the common vibration's centre, from the generator's parameters: the resonator's
    one-sided PSD there (unit variance AR(2)) against the gyro's white density."""
    r, w0 = math.exp(-math.pi * go.COMMON_WIDTH_HZ / go.RATE), 2 * math.pi * go.COMMON_HZ / go.RATE
    a1, a2 = 2 * r * math.cos(w0), -r * r
    var = (1 - a2) / ((1 + a2) * ((1 - a2) ** 2 - a1 * a1))
    z = np.exp(-1j * w0)
    s_c = go.scale("common", TEN_MIN) ** 2 * 2.0 / go.RATE / abs(1 - a1 * z - a2 * z * z) ** 2 / var
    s_w = go.GYRO_N ** 2
    return (s_c / (s_c + s_w)) ** 2


def test_common_vibration_is_found_on_its_channels():
    x, temp, truth = go.make("common", TEN_MIN, 21)
    found = coherence.findings(x, 100.0, temp)
    assert [f["channels"] for f in found] == [list(truth["channels"])]
    f = found[0]
    lo, hi = f["bands_hz"][0][0], f["bands_hz"][-1][1]
    assert lo < go.COMMON_HZ < hi
    assert abs(f["peak_hz"] - go.COMMON_HZ) < go.COMMON_WIDTH_HZ
    assert f["peak_coherence"] > 0.9 * _resonator_peak_coherence()
    assert abs(f["phase_deg"]) < 30.0  # the same series on both: in phase
    assert f["null_mean"] == pytest.approx(1.0 / coherence.SEGMENTS)


def test_component_common_to_three_channels_and_a_common_flicker():
    rng = np.random.default_rng(5)
    x = {c: go.base(c, TEN_MIN, rng) for c in go.CHANNELS}
    shared = go.scale("common", TEN_MIN) * go.resonator(TEN_MIN, rng)
    for c in ("gyro_x", "gyro_y", "gyro_z"):
        x[c] = x[c] + shared
    # a flicker common to two accelerometers, 3× their own ADEV floor, opposite in sign
    b = 3.0 * go.ACCEL_FLOOR / go.FLOOR_PER_B / math.sqrt(math.pi)
    flick = b * go.shaped(TEN_MIN, -1.0, rng)
    x["accel_x"], x["accel_y"] = x["accel_x"] + flick, x["accel_y"] - flick
    found = {tuple(f["channels"]): f for f in coherence.findings(x, 100.0)}
    assert set(found) == {("gyro_x", "gyro_y"), ("gyro_x", "gyro_z"), ("gyro_y", "gyro_z"), ("accel_x", "accel_y")}
    acc = found[("accel_x", "accel_y")]
    assert acc["bands_hz"][0][0] < 0.1  # a flicker: coherent at the low end
    assert abs(acc["phase_deg"]) > 150.0


@pytest.mark.slow  # moved to CI's second step: ≥ 15 s on two busy cores (fast suite under 10 min)
def test_run_gap_reports_the_common_component():
    x, temp, truth = go.make("common", TEN_MIN, 22)
    rep = run_gap(log_from_arrays(x, go.RATE, temp_c=temp), BASE, seed=0, realizations=6)
    d = rep.to_dict()
    assert [c["channels"] for c in d["cross_channel"]] == [list(truth["channels"])]
    text = rep.summary()
    assert "gyro_x and gyro_y share a component" in text
    assert any("per-channel model cannot express" in n for n in d["notes"])


def _gyro_y(n, seed, kind):
    """gyro_y of the base model plus a telegraph (or its Gaussian twin: an AR(1) of the same σ
    and correlation time) at the generator's amplitude."""
    rng = np.random.default_rng(seed)
    a, tau_c = go.scale("telegraph", n), 1.0 / (2.0 * go.TELEGRAPH_RATE)
    x = go.base("gyro_y", n, rng)
    if kind == "telegraph":
        return x + a * go.telegraph(n, rng), a, tau_c
    phi = math.exp(-1.0 / (go.RATE * tau_c))
    w = rng.standard_normal(n) * math.sqrt(1 - phi * phi)
    w[0] = rng.standard_normal()
    return x + a * lfilter([1.0], [1.0, -phi], w), a, tau_c


@pytest.mark.parametrize("kind,seed", [("telegraph", 31), ("telegraph", 32), ("gaussian", 31), ("gaussian", 32)])
def test_two_valued_slow_part(kind, seed):
    n = 180_000  # 30 min: 180 correlation times
    x, a, tau_c = _gyro_y(n, seed, kind)
    model = BASE.with_effect({"name": "gauss_markov", "channel": "gyro_y", "params": {"tau_s": tau_c, "sigma": a}})
    got = two_valued.check(model, "gyro_y", x, go.RATE, tau_c, seed=0)
    if kind == "telegraph":
        # ±a with the block means' white noise s² = N²/block on top: −2·a⁴/(a² + s²)² before
        # the blur of the flips inside a block (≈ 1 block in 5), which moves it towards 0
        s2 = go.GYRO_N ** 2 / got["block_s"]
        assert -2.0 < -2.0 * a ** 4 / (a * a + s2) ** 2 < got["kurtosis"] < -0.5
        assert got["two_valued"] and got["z"] < -two_valued.Z_LIMIT
        assert "random telegraph" in two_valued.note(got)
    else:
        assert not got["two_valued"]
        assert abs(got["z"]) < 3.0


def test_curved_temperature_share():
    # the share of the block means' variance beyond [1, t, T]: a (T − T_turn)² series ≈ 1; a
    # linear one plus white noise has only the noise's, whose expected share is 1/(blocks − 3)
    n = 360_000
    temp = go.temperature(n)
    rng = np.random.default_rng(3)
    assert temperature_curve.curved_share((temp - go.T_TURN) ** 2 + 1e-3 * rng.standard_normal(n), temp) > 0.99
    shares = [temperature_curve.curved_share(2.0 * temp + rng.standard_normal(n), temp) for _ in range(20)]
    assert np.mean(shares) == pytest.approx(1.0 / (temperature_curve.BLOCKS - 3), abs=3.0 / temperature_curve.BLOCKS)


@pytest.mark.slow
def test_coherence_false_positives_on_model_following_logs():
    # 60 ten-minute logs (30 of each independent generator) × 15 pairs: the check is at
    # α = 0.01 per log (Bonferroni over pairs and bands), so ≤ 2 % of logs may fire
    fired = 0
    for s in range(60):
        gen = gt if s % 2 == 0 else go
        x, temp, _ = gen.make(None, TEN_MIN, 6000 + s)
        fired += bool(coherence.findings(x, 100.0, temp))
    assert fired <= 1


@pytest.mark.slow
def test_run_gap_names_gauss_markov_with_the_telegraph_note():
    x, temp, truth = go.make("telegraph", 360_000, 41)
    rep = run_gap(log_from_arrays(x, go.RATE, temp_c=temp), BASE, seed=0)
    assert [(s.name, s.channel) for s in rep.steps][:1] == [("gauss_markov", "gyro_y")]
    assert any("two-valued" in n and "random telegraph" in n for n in rep.notes)
    assert rep.to_dict()["slow_shape"][0]["two_valued"]


def test_no_slow_part_below_eight_samples_per_block():
    """A Gauss–Markov τ_c of 2 samples (a decimation filter, as the real ADIS16405 gyro_z's
    0.021 s at 100 Hz) leaves one-sample blocks: the 'slow part' would be the samples, whose
    lattice (a quantized output) is platykurtic without any telegraph — no check is made."""
    n = 100_000
    rng = np.random.default_rng(5)
    lsb = 0.05 * math.pi / 180.0  # a coarse output lattice
    x = np.round((go.base("gyro_y", n, rng) + 0.5 * lsb * rng.standard_normal(n)) / lsb) * lsb
    tau_c = 2.0 / go.RATE
    model = BASE.with_effect({"name": "gauss_markov", "channel": "gyro_y", "params": {"tau_s": tau_c, "sigma": lsb}})
    assert int(round(0.5 * tau_c * go.RATE)) < two_valued.MIN_BLOCK_SAMPLES
    assert two_valued.check(model, "gyro_y", x, go.RATE, tau_c, seed=0) is None


def test_a_small_two_valued_share_is_not_called_two_valued():
    """Significance alone is not enough on a long record: a telegraph ±a beside a Gaussian slow
    part of variance 3a² (block means' white noise s² ≪ a²) has kurtosis ≈ −2a⁴/(4a²)² = −0.125,
    many standard deviations from 0 over 5·10⁴ blocks but above the −0.5 limit: not called
    two-valued."""
    assert -2.0 / 16.0 > two_valued.KURTOSIS_LIMIT
    n, tau_c = 500_000, 0.2  # 10-sample blocks at 100 Hz
    rng = np.random.default_rng(9)
    block = int(round(0.5 * tau_c * go.RATE))
    s = go.GYRO_N * math.sqrt(go.RATE / block)  # the block means' white noise
    a = 10.0 * s
    phi = math.exp(-1.0 / (go.RATE * tau_c))
    w = rng.standard_normal(n) * math.sqrt(1 - phi * phi)
    x = (go.base("gyro_y", n, rng) + a * go.telegraph(n, rng, rate=1.0 / (2.0 * tau_c))
         + math.sqrt(3.0) * a * lfilter([1.0], [1.0, -phi], w))
    model = BASE.with_effect({"name": "gauss_markov", "channel": "gyro_y",
                              "params": {"tau_s": tau_c, "sigma": 2.0 * a}})
    got = two_valued.check(model, "gyro_y", x, go.RATE, tau_c, seed=0)
    assert got is not None
    assert got["z"] < -two_valued.Z_LIMIT  # significant …
    assert two_valued.KURTOSIS_LIMIT < got["kurtosis"] < 0.0  # … but small
    assert not got["two_valued"]
