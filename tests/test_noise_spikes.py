"""Isolated spikes before the Allan fit (budget.noise.spikes): found with their rows, replaced
only where they would decide the short-τ Allan deviation, never on noise the tool fits."""

import numpy as np
import pytest

from budget import units as u
from budget.noise import characterize, read_log
from budget.noise.spikes import DOMINANT_FRACTION, find_spikes

RATE = 100.0
ARW = 0.5  # deg/√h


def _white(n, rng, arw=ARW):
    """Rate samples (rad/s) of white noise with the given ARW: σ = N·√rate (IEEE 952)."""
    return rng.standard_normal(n) * u.deg_rt_h_to_rad_s_rt_hz(arw) * np.sqrt(RATE)


def _log(path, gyro):
    t = np.arange(gyro.shape[0]) / RATE
    rng = np.random.default_rng(1)
    acc = rng.standard_normal((gyro.shape[0], 3)) * 1e-3
    cols = np.column_stack([t, gyro / u.DEG, acc])
    header = "time_s,gyro_x_dps,gyro_y_dps,gyro_z_dps,accel_x_mps2,accel_y_mps2,accel_z_mps2"
    np.savetxt(path, cols, delimiter=",", header=header, comments="", fmt="%.10g")
    return path


def test_one_spike_would_decide_the_arw_and_is_replaced_with_its_row(tmp_path):
    """One sample of 5000 deg/s in 10 min of a 0.5 deg/√h gyro: kept, the ARW comes out > 100×
    too large; by default it is replaced and the ARW is within 3 % of the clean record's."""
    rng = np.random.default_rng(5)
    g = np.column_stack([_white(60_000, rng) for _ in range(3)])
    clean = characterize(read_log(_log(tmp_path / "clean.csv", g))).part.gyro_arw_deg_rt_h
    g[1000, 0] = 5000 * u.DEG
    log = read_log(_log(tmp_path / "spike.csv", g))
    fixed = characterize(log)
    assert fixed.part.gyro_arw_deg_rt_h == pytest.approx(clean, rel=0.03)
    (w,) = [w for w in fixed.warnings if "spike" in w]
    assert w.startswith("gyro_x: 1 isolated spike") and "row 1,002" in w and "replaced" in w
    assert "spikes replaced before the fit on gyro_x" in fixed.part.notes
    kept = characterize(log, keep_spikes=True)
    assert kept.part.gyro_arw_deg_rt_h > 100 * clean and "kept on request" in " ".join(kept.warnings)
    assert kept.options["keep_spikes"] is True


def test_burst_of_adjacent_spikes_is_found_sample_by_sample():
    rng = np.random.default_rng(6)
    x = _white(20_000, rng)
    x[500:503] = [2.0, -1.5, 3.0]
    x[0], x[-1] = 4.0, -4.0  # at the ends too (a window padded with the end value would hide them)
    y, sp = find_spikes(x, "gyro_x")
    assert sorted(sp.index.tolist()) == [0, 500, 501, 502, x.size - 1] and sp.replaced
    assert np.max(np.abs(y[495:508])) < 10 * np.std(x[1000:-1])
    assert abs(y[0]) < 10 * np.std(x[1000:-1]) and abs(y[-1]) < 10 * np.std(x[1000:-1])


@pytest.mark.parametrize("kind", ["gaussian", "student_t4", "quantized", "random_walk"])
def test_noise_the_tool_fits_is_never_replaced(kind):
    """10⁶ samples of Gaussian, Student-t (ν = 4), one-LSB quantized and random-walk-plus-white
    noise (independent draws): nothing replaced; at most a few samples of the t noise named."""
    rng = np.random.default_rng(11)
    n = 1_000_000
    x = {"gaussian": lambda: rng.standard_normal(n),
         "student_t4": lambda: rng.standard_t(4, n),
         "quantized": lambda: np.round(0.6 * rng.standard_normal(n)),
         "random_walk": lambda: np.cumsum(0.05 * rng.standard_normal(n)) + rng.standard_normal(n)}[kind]()
    y, sp = find_spikes(x, "gyro_x")
    assert y is x or np.array_equal(y, x)
    assert sp is None or (not sp.replaced and sp.index.size <= 5 and sp.share < DOMINANT_FRACTION)


def test_small_spikes_are_named_but_kept():
    """Ten samples at 60 robust σ in 10⁶: named, but at a few % of the squared differences they do
    not decide the fit and are kept; the same ten in 10⁵ samples carry a third and are replaced."""
    rng = np.random.default_rng(8)
    for n, replaced in ((1_000_000, False), (100_000, True)):
        x = rng.standard_normal(n)
        idx = rng.choice(np.arange(10, n - 10), 10, replace=False)
        x[idx] += 60 * np.sign(rng.standard_normal(10))
        y, sp = find_spikes(x, "accel_z")
        assert set(sp.index.tolist()) == set(idx.tolist()) and sp.replaced is replaced
        if replaced:
            assert sp.share > DOMINANT_FRACTION and np.max(np.abs(y)) < 6
        else:
            assert 0.01 < sp.share < DOMINANT_FRACTION and y is x and "kept (below 10 %" in sp.message()


@pytest.mark.shared_data
def test_real_logs_have_no_spikes(shared_data):
    for name in ("adis16405_static_1.csv.gz", "adis16405_static_2.csv.gz"):
        log = read_log(shared_data / "logs" / name, max_rows=300_000)
        assert all(find_spikes(x, ch)[1] is None for ch, x in log.channels.items()), name
