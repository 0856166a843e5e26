"""The focus result states what the data are (``budget.sar.acquisition``): band, aperture and the
closed-form resolutions and unambiguous extents, against the numbers a synthetic AFRL file was
written with; a point target's 3 dB widths against the stated resolutions; the CLI's JSON and
text; the dashboard page's table; the shared Gotcha file against its own ``freq`` field (skipped
when ../shared is absent)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.io as sio

from budget.cli.main import main
from budget.errors import InputError
from budget.sar.acquisition import describe_acquisition
from budget.sar.afrl import read_afrl
from budget.sar.focus import FocusOptions, ground_grid
from budget.sar.focus_pga import focus
from budget.sar.phase_history import C_M_S

# What the synthetic file is written with: a circular pass of N pulses over SPAN_DEG of azimuth at
# GROUND_M ground range and HEIGHT_M height, K frequencies DF apart from F0 (B = K DF = 600 MHz).
F0, DF, K = 9.3e9, 9.375e6, 64
N, SPAN_DEG, GROUND_M, HEIGHT_M = 128, 2.0, 7090.0, 7276.0
TARGET = np.array([0.6, -0.4, 0.0])
NAME = "data_3dsar_pass3_az001_VV.mat"


def _track() -> np.ndarray:
    th = np.radians(np.linspace(-SPAN_DEG / 2, SPAN_DEG / 2, N))
    return np.stack([GROUND_M * np.cos(th), GROUND_M * np.sin(th), np.full(N, HEIGHT_M)], axis=1)


def _write(path: Path) -> Path:
    """A point target at TARGET in the AFRL layout: S(n, f) = exp(−j 4π f / c (|A_n − p| − R0_n)),
    fp (K, N), freq (K, 1), x/y/z/r0 (1, N)."""
    ant = _track()
    f = F0 + DF * np.arange(K)
    r0 = np.linalg.norm(ant, axis=1)
    s = np.exp(-4j * np.pi * f[None, :] / C_M_S * (np.linalg.norm(ant - TARGET, axis=1) - r0)[:, None])
    sio.savemat(str(path), {"data": {"fp": s.T.astype(np.complex64), "freq": f[:, None], "x": ant[None, :, 0],
                                     "y": ant[None, :, 1], "z": ant[None, :, 2], "r0": r0[None, :]}})
    return path


def _closed_forms() -> dict:
    """The expected numbers, from the values written (not from the library)."""
    slant = np.hypot(GROUND_M, HEIGHT_M)
    d_phi = np.radians(SPAN_DEG)
    # look directions from the scene centre: the chord between two of them on the cone is
    # 2 GROUND sin(Δφ/2) / R, so the angle between them is 2 asin(GROUND sin(Δφ/2) / R)
    d_theta = 2.0 * np.arcsin(GROUND_M * np.sin(d_phi / 2) / slant)
    step = 2.0 * np.arcsin(GROUND_M * np.sin(d_phi / (2 * (N - 1))) / slant)
    psi = np.arctan2(HEIGHT_M, GROUND_M)
    f_c = F0 + DF * (K - 1) / 2
    lam = C_M_S / f_c
    b = K * DF
    return {"centre_frequency_hz": f_c, "bandwidth_hz": b, "frequency_step_hz": DF, "wavelength_m": lam,
            "aperture_angle_rad": d_theta, "angle_step_rad": step, "grazing_angle_rad": psi,
            "aperture_length_m": (N - 1) * 2.0 * GROUND_M * np.sin(d_phi / (2 * (N - 1))),
            "mean_slant_range_m": slant,
            "slant_range_resolution_m": C_M_S / (2 * b), "ground_range_resolution_m": C_M_S / (2 * b * np.cos(psi)),
            "cross_range_resolution_m": lam / (2 * d_theta), "unambiguous_slant_range_m": C_M_S / (2 * DF),
            "unambiguous_ground_range_m": C_M_S / (2 * DF * np.cos(psi)),
            "unambiguous_cross_range_m": lam / (2 * step)}


@pytest.fixture(scope="module")
def synth(tmp_path_factory) -> Path:
    return _write(tmp_path_factory.mktemp("afrl") / NAME)


@pytest.fixture(scope="module")
def focused(synth):
    """Rectangular windows, 2 m × 2 m about the target at 0.02 m: the impulse response itself."""
    ph = read_afrl(synth)
    g = ground_grid(ph, FocusOptions(range_extent_m=2, azimuth_extent_m=2, spacing_m=0.02))
    opt = FocusOptions(range_extent_m=2.0, azimuth_extent_m=2.0, spacing_m=0.02, range_window="rect",
                       azimuth_window="rect", range_centre_m=float(TARGET @ g.u_hat),
                       azimuth_centre_m=float(TARGET @ g.v_hat), workers=1)
    return focus(ph, opt, "none")


def test_reported_values_equal_the_closed_forms_of_the_written_numbers(focused):
    a = focused.acquisition
    want = _closed_forms()
    assert want["slant_range_resolution_m"] == pytest.approx(0.24983, abs=1e-5)  # B = 600 MHz
    got = a.to_dict()
    for key, value in want.items():
        assert got[key] == pytest.approx(value, rel=1e-9), key
    assert (a.pulses, a.frequency_samples) == (N, K)
    assert a.files == (NAME,) and a.pass_name == "3" and a.polarisation == "VV"
    assert a.platform_speed_m_s is None and "no pulse times" in a.summary()
    assert a.pixel_spacing_m == pytest.approx(0.02) and a.image_ground_range_extent_m == pytest.approx(2.0)
    assert a.notes == ()  # 0.02 m pixels, 2 m window: sampled and unambiguous


def _width_3db(line: np.ndarray, d: float) -> float:
    """Width of |line| at 1/√2 of its peak, m, the crossings interpolated linearly."""
    line = line / line.max()
    k = int(np.argmax(line))
    h = 0.5 ** 0.5
    lo, hi = k, k
    while line[lo - 1] >= h:
        lo -= 1
    while line[hi + 1] >= h:
        hi += 1
    left = lo - (line[lo] - h) / (line[lo] - line[lo - 1])
    right = hi + (line[hi] - h) / (line[hi] - line[hi + 1])
    return d * (right - left)


def test_point_target_width_is_0886_of_the_stated_resolution(focused):
    a = focused.acquisition
    mag = np.abs(focused.before.data)
    i, j = np.unravel_index(np.argmax(mag), mag.shape)
    d = a.pixel_spacing_m
    assert _width_3db(mag[i, :], d) == pytest.approx(0.886 * a.ground_range_resolution_m, rel=0.03)
    assert _width_3db(mag[:, j], d) == pytest.approx(0.886 * a.cross_range_resolution_m, rel=0.03)


def test_undersampled_grid_and_extent_beyond_the_unambiguous_one_are_noted(synth):
    ph = read_afrl(synth)
    want = _closed_forms()
    coarse = describe_acquisition(ph, ground_grid(ph, FocusOptions(range_extent_m=10, azimuth_extent_m=20,
                                                                   spacing_m=0.5)))
    assert want["ground_range_resolution_m"] < 0.5 < want["cross_range_resolution_m"]
    assert len(coarse.notes) == 1 and "exceeds the ground-range resolution" in coarse.notes[0]
    wide = describe_acquisition(ph, ground_grid(ph, FocusOptions(range_extent_m=30, azimuth_extent_m=100,
                                                                 spacing_m=0.25)))
    assert want["unambiguous_ground_range_m"] < 30 and want["unambiguous_cross_range_m"] < 100
    assert any("ground-range extent 30 m exceeds the unambiguous" in n for n in wide.notes)
    assert any("cross-range extent 100 m exceeds the unambiguous" in n for n in wide.notes)


def test_platform_speed_from_pulse_times_and_tags_kept_through_copies(synth):
    ph = read_afrl(synth)
    assert ph.name_tags == {"pass": "3", "polarisation": "VV"}
    assert ph.with_phase_error(np.zeros(N)).name_tags == ph.name_tags
    t = np.arange(N) / 200.0  # 200 Hz PRF
    timed = ph._replace(pulse_time_s=t)
    a = describe_acquisition(timed)
    assert a.platform_speed_m_s == pytest.approx(_closed_forms()["aperture_length_m"] / t[-1], rel=1e-12)
    assert a.pixel_spacing_m is None and "m/s" in a.summary()
    with pytest.raises(InputError, match="pulse times must increase"):
        ph._replace(pulse_time_s=t[::-1])


def test_cli_json_and_text_carry_the_fields_with_units(synth, tmp_path, capsys):
    out = tmp_path / "f.json"
    args = ["focus", str(synth), "--autofocus", "none", "--range-extent-m", "4", "--azimuth-extent-m", "4",
            "--spacing-m", "0.1"]
    assert main(args + ["--json", str(out)]) == 0
    d = json.loads(out.read_text())["acquisition"]
    want = _closed_forms()
    for key in ("centre_frequency_hz", "bandwidth_hz", "wavelength_m", "aperture_angle_rad", "angle_step_rad",
                "aperture_length_m", "mean_slant_range_m", "grazing_angle_rad", "slant_range_resolution_m",
                "ground_range_resolution_m", "cross_range_resolution_m", "unambiguous_slant_range_m",
                "unambiguous_ground_range_m", "unambiguous_cross_range_m"):
        assert d[key] == pytest.approx(want[key], rel=1e-9), key
    assert d["platform_speed_m_s"] is None and "no pulse times" in d["platform_speed_source"]
    assert d["pixel_spacing_m"] == pytest.approx(0.1) and d["files"] == [NAME]
    assert (d["pulses"], d["frequency_samples"], d["pass_name"], d["polarisation"]) == (N, K, "3", "VV")
    assert "first and last look directions" in d["methods"]["aperture_angle_rad"]
    capsys.readouterr()
    assert main(args) == 0
    text = capsys.readouterr().out
    assert f"(pass 3, VV): centre {want['centre_frequency_hz'] / 1e9:.4f} GHz, bandwidth 600 MHz" in text
    assert f"slant range c/(2B) {want['slant_range_resolution_m']:.4g} m" in text


def test_dashboard_page_shows_the_library_table(synth, monkeypatch):
    from streamlit.testing.v1 import AppTest
    app_dir = Path(__file__).resolve().parents[1] / "app"
    monkeypatch.syspath_prepend(str(app_dir))
    at = AppTest.from_file(str(app_dir / "pages" / "focus.py"), default_timeout=60).run()
    at.radio(key="focus_mode").set_value("none").run()
    at.number_input(key="focus_range_extent").set_value(5.0).run()
    at.number_input(key="focus_azimuth_extent").set_value(5.0).run()
    at.text_input(key="focus_dir").set_value(str(synth.parent)).run()
    at.button(key="focus_run").click().run()
    assert not at.exception, [e.value for e in at.exception]
    ref = focus(read_afrl(synth), FocusOptions(range_extent_m=5, azimuth_extent_m=5), "none").acquisition
    table = next(t.value for t in at.dataframe if list(t.value.columns) == ["quantity", "shown"])
    assert table.to_dict(orient="list") == ref.to_frame()[["quantity", "shown"]].to_dict(orient="list")


def test_gotcha_band_against_its_own_freq_field(gotcha):
    """One shared file: centre ≈ 9.6 GHz and bandwidth ≈ 640 MHz (as often quoted for Gotcha; the
    file's 424 samples 1.47 MHz apart occupy 623.8 MHz), each equal to what its ``freq`` field gives."""
    freq = sio.loadmat(str(gotcha[0]))["data"][0, 0]["freq"].ravel().astype(float)
    a = describe_acquisition(read_afrl(gotcha[0]))
    k = freq.size
    assert a.centre_frequency_hz == pytest.approx((freq[0] + freq[-1]) / 2, rel=1e-9)
    assert a.bandwidth_hz == pytest.approx(k * (freq[-1] - freq[0]) / (k - 1), rel=1e-9)
    assert a.frequency_samples == k
    assert a.centre_frequency_hz == pytest.approx(9.6e9, rel=0.01)
    assert a.bandwidth_hz == pytest.approx(640e6, rel=0.05)
    assert a.wavelength_m == pytest.approx(C_M_S / a.centre_frequency_hz, rel=1e-12)
    assert (a.pass_name, a.polarisation) == ("1", "HH")
    phi = sio.loadmat(str(gotcha[0]))["data"][0, 0]["phi"].ravel().astype(float)
    assert np.degrees(a.grazing_angle_rad) == pytest.approx(phi.mean(), abs=0.01)
    assert a.notes == ()
