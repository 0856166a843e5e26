"""Injection experiments on recorded-format phase histories: the injected error is kept with the
data and ``focus`` scores PGA's estimate against the error the data are known to carry (recorded
solution + injected), not against the recorded solution alone."""

from __future__ import annotations

import numpy as np
import pytest

from budget.errors import InputError
from budget.sar.focus import FocusOptions
from budget.sar.focus_pga import focus
from budget.sar.phase import smooth_phase_error
from budget.sar.phase_history import C_M_S, PhaseHistory


def _points_history(n_pulses=469, n_freq=128, span_deg=4.0, seed=3):
    """Twelve point targets in a 40 m scene seen from a circular pass, S(n, f) evaluated directly
    from the data convention exp(−j 4π f / c (|A_n − p| − |A_n|)) (not through the image former)."""
    rng = np.random.default_rng(seed)
    th = np.radians(np.linspace(-span_deg / 2, span_deg / 2, n_pulses))
    ant = np.stack([7090.0 * np.cos(th), 7090.0 * np.sin(th), np.full(n_pulses, 7276.0)], axis=1)
    f = 9.6e9 + 4.0e6 * np.arange(n_freq)
    r0 = np.linalg.norm(ant, axis=1)
    s = np.zeros((n_pulses, n_freq), complex)
    for _ in range(12):
        p = np.array([rng.uniform(-15, 15), rng.uniform(-15, 15), 0.0])
        d_r = np.linalg.norm(ant - p, axis=1) - r0
        s += rng.uniform(0.5, 1.0) * np.exp(-4j * np.pi * f[None, :] / C_M_S * d_r[:, None])
    return PhaseHistory(samples=s.astype(np.complex64), frequency_hz=f, antenna_m=ant, scene_range_m=r0,
                        pulse_source=np.array(["synthetic"] * n_pulses))


def _beyond_linear_rms(x, mask):
    """rms over ``mask`` of x less its least-squares line fitted over ``mask``."""
    k = np.arange(x.size)
    r = x - np.polyval(np.polyfit(k[mask], x[mask], 1), k)
    return float(np.sqrt(np.mean(r[mask] ** 2)))


def test_injections_accumulate_and_the_known_error_adds_the_recorded_one():
    ph = _points_history(n_pulses=64, n_freq=16)
    assert ph.injected_phase_rad is None and ph.known_phase_error_rad() is None
    a, b = np.linspace(0, 1, 64), np.cos(np.arange(64.0))
    twice = ph.with_phase_error(a).with_phase_error(b)
    assert np.allclose(twice.injected_phase_rad, a + b, atol=1e-15)
    assert np.allclose(np.angle(twice.samples / ph.samples), np.angle(np.exp(1j * (a + b)))[:, None], atol=1e-5)
    assert twice.description()["injected_phase_rms_rad"] == pytest.approx(np.sqrt(np.mean((a + b) ** 2)))
    chi, dr = 0.3 * np.sin(np.arange(64.0) / 5), 1e-3 * np.arange(64.0)
    rec = PhaseHistory(samples=ph.samples, frequency_hz=ph.frequency_hz, antenna_m=ph.antenna_m,
                       scene_range_m=ph.scene_range_m, pulse_source=ph.pulse_source,
                       recorded_range_correction_m=dr, recorded_phase_correction_rad=chi)
    both = rec.with_phase_error(a)
    assert np.allclose(both.known_phase_error_rad(), rec.recorded_phase_error_rad() + a, atol=1e-12)
    assert np.array_equal(rec.known_phase_error_rad(), rec.recorded_phase_error_rad())
    # the provider's solution applied first: the data then carry only what is injected after it
    applied = rec.with_recorded_autofocus()
    assert not applied.has_recorded_autofocus and applied.known_phase_error_rad() is None
    assert np.array_equal(applied.with_phase_error(a).known_phase_error_rad(), a)
    # an injection made before applying the solution is still in the data
    assert np.array_equal(both.with_recorded_autofocus().known_phase_error_rad(), a)


def test_focus_scores_pga_against_the_injected_error():
    """Without a recorded solution the comparison is against the injection alone; PGA on twelve
    clean points recovers a 1.4 rad rms smooth error (beyond linear) to a small fraction of it
    (measured 0.009 rad; asserted < 0.05 rad, 3.6 % of the injection). The injection is a cubic
    plus 0.75 cycles of a sinusoid, well inside PGA's ≈ 3 cycles: its part "above PGA's
    bandwidth" must be ≈ 0 (a DCT truncation alone put 0.10 rad there)."""
    ph = _points_history()
    u = np.linspace(-1.0, 1.0, ph.n_pulses)
    psi = smooth_phase_error(u, quadratic_rad=4.0, cubic_rad=2.0, sinusoid_rad=1.5, sinusoid_cycles=1.5)
    opt = FocusOptions(range_extent_m=40, azimuth_extent_m=40, spacing_m=0.25, workers=1)
    res = focus(ph.with_phase_error(psi), opt, "pga")
    known = res.comparison["known"]
    assert known["reference"] == "injected"
    assert res.estimated_pulses.sum() > 0.9 * ph.n_pulses
    assert known["recorded_beyond_linear_rms_rad"] == pytest.approx(_beyond_linear_rms(psi, res.estimated_pulses),
                                                                    rel=1e-9)
    assert known["recorded_beyond_linear_rms_rad"] > 1.0
    assert known["rms_diff_rad"] < 0.05
    assert known["pga_bandwidth_cycles"] > 1.5
    assert known["recorded_fast_rms_rad"] < 0.01 * known["recorded_beyond_linear_rms_rad"]
    assert known["rms_diff_slow_rad"] < 0.05
    assert "known error (injected)" in res.summary()
    frame = res.to_frame()
    m = res.estimated_pulses
    assert np.allclose(frame["known_phase_error_rad"][m], res.known_phase_error_rad[m])
    resid = frame["phase_estimate_rad"][m] - frame["known_phase_error_rad"][m]
    assert float(np.sqrt(np.mean((resid - resid.mean()) ** 2))) < 0.05  # both beyond linear over the same pulses
    assert res.to_dict()["known_phase_error_rad"] is not None
    assert "no comparison" not in " ".join(res.notes)
    # without the injection there is nothing to compare with, as before
    plain = focus(ph, opt, "pga")
    assert "known" not in plain.comparison and any("no comparison" in n for n in plain.notes)
    assert plain.known_phase_error_rad is None and "known_phase_error_rad" not in plain.to_frame()


def test_injected_phase_of_the_wrong_size_or_nan_is_refused():
    ph = _points_history(n_pulses=32, n_freq=16)
    with pytest.raises(InputError, match="injected_phase_rad"):
        ph._replace(injected_phase_rad=np.full(31, 0.1))
    with pytest.raises(InputError, match="injected_phase_rad"):
        ph._replace(injected_phase_rad=np.r_[np.zeros(31), np.nan])
    with pytest.raises(InputError, match="phase_rad"):
        ph.with_phase_error(np.r_[np.zeros(31), np.inf])


def test_focus_cli_reports_the_known_error_on_real_data(shared_data, capsys):
    from budget.cli.main import main
    f = shared_data / "sar" / "gotcha" / "data_3dsar_pass1_az002_HH.mat"
    if not f.is_file():
        pytest.skip(f"Gotcha phase-history file not found: {f}")
    assert main(["focus", str(f), "--inject", "4,2,1.5,1.5", "--range-extent-m", "40",
                 "--azimuth-extent-m", "40"]) == 0
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if ln.startswith("against the known error (recorded + injected)"))
    assert "difference" in line and "low-passed to PGA's bandwidth" in line
    # the difference's part within the bandwidth is a projection of the whole difference
    whole = float(line.split("difference ")[1].split(" rad")[0])
    in_band = float(line.split("the difference's part within the bandwidth ")[1].split(" rad")[0])
    assert in_band <= whole * 1.05
    # the 3 dB widths of the Taylor-windowed image beside the closed-form resolutions (1.184 cells)
    widths = next(ln for ln in out.splitlines() if ln.startswith("3 dB widths of this image"))
    assert "1.184 / 1.184 of those resolutions" in widths


def test_smooth_injection_matches_the_model_and_refuses_bad_numbers():
    ph = _points_history(n_pulses=40, n_freq=16)
    got = ph.with_smooth_phase_error(4.0, 2.0, 1.5, 1.5)
    u = np.linspace(-1.0, 1.0, 40)
    want = smooth_phase_error(u, quadratic_rad=4.0, cubic_rad=2.0, sinusoid_rad=1.5, sinusoid_cycles=1.5)
    assert np.allclose(got.injected_phase_rad, want, atol=1e-15)
    assert "injected phase error 4 u² + 2 u³ + 1.5 sin(1.5πu)" in got.notes[-1]
    for bad in (float("nan"), float("inf"), True, "2"):
        with pytest.raises(InputError, match="cubic_rad"):
            ph.with_smooth_phase_error(4.0, bad, 1.5, 1.5)


def _write_afrl(path, ph: PhaseHistory):
    """``ph`` in the AFRL Gotcha .mat layout (fp: frequencies × pulses; x, y, z, r0 per pulse)."""
    import scipy.io as sio
    n = ph.n_pulses
    sio.savemat(path, {"data": {"fp": ph.samples.T, "freq": ph.frequency_hz.reshape(-1, 1),
                                "x": ph.antenna_m[:, 0].reshape(1, n), "y": ph.antenna_m[:, 1].reshape(1, n),
                                "z": ph.antenna_m[:, 2].reshape(1, n), "r0": ph.scene_range_m.reshape(1, n),
                                "th": np.zeros((1, n)), "phi": np.full((1, n), 45.0)}})
    return path


def test_dashboard_page_injects_and_shows_the_known_error(tmp_path, monkeypatch):
    """The Real SAR data page with "inject a known phase error" shows the library's comparison
    with the injection (files without a recorded solution: against the injection alone)."""
    from pathlib import Path
    from streamlit.testing.v1 import AppTest
    from budget.sar.afrl import read_afrl
    app_dir = Path(__file__).resolve().parents[1] / "app"
    monkeypatch.syspath_prepend(str(app_dir))
    _write_afrl(tmp_path / "points.mat", _points_history())
    at = AppTest.from_file(str(app_dir / "pages" / "focus.py"), default_timeout=120).run()
    at.number_input(key="focus_range_extent").set_value(40.0).run()
    at.number_input(key="focus_azimuth_extent").set_value(40.0).run()
    at.checkbox(key="focus_inject").check().run()
    at.text_input(key="focus_dir").set_value(str(tmp_path)).run()
    at.button(key="focus_run").click().run()
    assert not at.exception, [e.value for e in at.exception]
    ref = focus(read_afrl([tmp_path / "points.mat"]).with_smooth_phase_error(4.0, 2.0, 1.5, 1.5),
                FocusOptions(range_extent_m=40, azimuth_extent_m=40), "pga")
    shown = {m.label: m.value for m in at.metric}
    assert shown["rms diff. from known (rad)"] == f"{ref.comparison['known']['rms_diff_rad']:.3g}"
    assert shown["known error (injected), rms (rad)"] == \
        f"{ref.comparison['known']['recorded_beyond_linear_rms_rad']:.3g}"
    table = at.dataframe[0].value
    assert any(q.startswith("against injected: ") for q in table["quantity"])


@pytest.mark.parametrize("spec, expected", [("1,2,3", "expected four numbers"), ("nan,1,1,1", "must be finite"),
                                            ("a,b,c,d", "expected four numbers")])
def test_focus_cli_refuses_a_bad_injection(tmp_path, capsys, spec, expected):
    from budget.cli.main import main
    path = _write_afrl(tmp_path / "points.mat", _points_history(n_pulses=40, n_freq=16))
    assert main(["focus", str(path), "--inject", spec]) == 2
    err = capsys.readouterr().err
    assert "--inject" in err and expected in err and "Traceback" not in err
