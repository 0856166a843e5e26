"""Recorded phase histories the authors never saw: frequencies in GHz, a track in km or in a frame
not centred on the scene, every other pulse dropped (aliased azimuth), a window beyond the
recorded range swath, a standing antenna, all-zero pulses, two polarisations of one azimuth, a
transposed or descending frequency axis, a compressed file that decompresses to gigabytes and
more pulses than the image formation may hold. Synthetic files are written in ``tmp_path``; the
Gotcha checks skip when ../shared is absent."""

from __future__ import annotations

import zlib

import numpy as np
import pytest
import scipy.io as sio

from budget.cli.main import main
from budget.errors import InputError
from budget.sar import afrl, focus as focus_mod
from budget.sar.afrl import read_afrl
from budget.sar.focus import FocusOptions, backproject, form_ground_image, ground_grid
from budget.sar.phase_history import C_M_S, PhaseHistory

from gotcha_synth import circular_track

F0, DF, NF = 9.288e9, 1.4713e6, 424  # the Gotcha band: Hz, Hz, samples


_track = circular_track


def _samples(antenna, targets=(np.zeros(3),), r0=None, n_freq=NF):
    """S(n, f) = Σ exp(−j 4π f / c (|A_n − p| − R0_n)), (n_freq, n_pulses) as the files store it."""
    f = F0 + DF * np.arange(n_freq)
    r0 = np.linalg.norm(antenna, axis=1) if r0 is None else r0
    s = np.zeros((antenna.shape[0], n_freq), complex)
    for p in targets:
        s += np.exp(-4j * np.pi * f[None, :] / C_M_S * (np.linalg.norm(antenna - p, axis=1) - r0)[:, None])
    return s.T.astype(np.complex64), f


def _write(path, antenna, fp=None, freq=None, r0=None, **kw):
    """An AFRL-format .mat file (struct ``data``) of ``antenna`` (n, 3) m."""
    if fp is None:
        fp, freq = _samples(antenna, r0=r0)
    r0 = np.linalg.norm(antenna, axis=1) if r0 is None else r0
    data = {"fp": fp, "freq": np.asarray(freq, float)[:, None], "x": antenna[None, :, 0],
            "y": antenna[None, :, 1], "z": antenna[None, :, 2], "r0": np.asarray(r0, float)[None, :]}
    sio.savemat(str(path), {"data": data}, **kw)
    return path


def _small(**kw) -> FocusOptions:
    base = dict(range_extent_m=8, azimuth_extent_m=20, spacing_m=0.25, range_window="rect",
                azimuth_window="rect", workers=1)
    return FocusOptions(**{**base, **kw})


# --- units ------------------------------------------------------------------------------------

@pytest.mark.parametrize("factor, unit", [(1e-9, "GHz"), (1e-6, "MHz")])
def test_frequencies_in_ghz_or_mhz_are_refused_naming_the_unit(tmp_path, factor, unit):
    ant = _track(40)
    fp, f = _samples(ant)
    path = _write(tmp_path / "ph.mat", ant, fp=fp, freq=f * factor)
    with pytest.raises(InputError) as err:
        read_afrl(path)
    msg = str(err.value)
    assert "ph.mat" in msg and "data.freq" in msg and f"in {unit}?" in msg
    assert f"{F0 * factor:.4g}" in msg  # the band as read, and what it would be in Hz
    assert f"{F0:.4g}" in msg
    with pytest.raises(InputError, match="not radar frequencies"):  # the library object refuses it too
        PhaseHistory(samples=fp.T, frequency_hz=f * factor, antenna_m=ant, scene_range_m=np.linalg.norm(ant, axis=1),
                     pulse_source=["x"] * 40)


def test_positions_in_km_are_refused_before_any_image(tmp_path, capsys):
    ant = _track(60)
    fp, f = _samples(ant)
    # positions in km, ranges in m: the antenna is 10 "m" from the scene centre, inside the window
    path = _write(tmp_path / "km.mat", ant / 1000.0, fp=fp, freq=f, r0=np.linalg.norm(ant, axis=1))
    assert main(["focus", str(path), "--range-extent-m", "8", "--azimuth-extent-m", "20"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "km.mat" in err and "in km?" in err
    assert f"{np.linalg.norm(ant[:, :2], axis=1).min() / 1000:.4g} m" in err
    # a window smaller than 7 m still cannot be imaged: |A| − r0 names the unit
    ph = read_afrl(path)
    with pytest.raises(InputError, match=r"positions in km, ranges in m\?"):
        form_ground_image(ph, _small(range_extent_m=4, azimuth_extent_m=5))


def test_track_in_a_frame_not_centred_on_the_scene_is_refused_with_the_offset(tmp_path, capsys):
    ant = _track(60)
    fp, f = _samples(ant)
    shift = np.array([500.0, 300.0, 0.0])  # positions in a local frame 583 m from the scene centre
    path = _write(tmp_path / "local.mat", ant + shift, fp=fp, freq=f, r0=np.linalg.norm(ant, axis=1))
    assert main(["focus", str(path), "--range-extent-m", "8", "--azimuth-extent-m", "20"]) == 2
    err = capsys.readouterr().err.strip()
    offset = np.median(np.linalg.norm(ant + shift, axis=1) - np.linalg.norm(ant, axis=1))  # independent
    assert "local.mat" in err and "antenna_m, scene_range_m" in err and f"{offset:.4g} m" in err
    assert f"±{C_M_S / (4 * DF):.4g} m" in err  # the recorded swath c / 4Δf


def test_window_beyond_the_recorded_range_swath_is_refused(tmp_path):
    ant = _track(60, span_deg=0.5)  # the Gotcha pulse spacing: 146 m cross-range period
    ph = read_afrl(_write(tmp_path / "ph.mat", ant))
    half = C_M_S / (4 * DF)  # 50.9 m slant: ≈ 73 m ground range at 45.7° elevation
    with pytest.raises(InputError) as err:
        form_ground_image(ph, _small(range_extent_m=200, spacing_m=0.5, azimuth_extent_m=20))
    assert err.value.field == "range_extent_m" and f"±{half:.4g} m" in str(err.value)
    form_ground_image(ph, _small(range_extent_m=100, spacing_m=0.3, azimuth_extent_m=20))  # ±35 m slant: fine


def test_antenna_that_does_not_move_is_refused(tmp_path):
    ant = np.repeat(_track(3)[1:2], 50, axis=0)
    ph = read_afrl(_write(tmp_path / "still.mat", ant))
    with pytest.raises(InputError, match="does not move"):
        form_ground_image(ph, _small())


# --- aliased azimuth ----------------------------------------------------------------------------

def test_every_other_pulse_dropped_refuses_a_window_that_would_hold_its_own_ghosts(tmp_path):
    ant = _track(469)[::2]  # every other pulse of a 469-pulse, 4° pass
    target = np.array([0.0, 30.0, 0.0])
    ph = read_afrl(_write(tmp_path / "half.mat", ant, fp=_samples(ant, [target])[0], freq=_samples(ant[:2])[1]))
    # independent period: λ_min / (2 × the cross-range direction-cosine step between pulses)
    unit = ant / np.linalg.norm(ant, axis=1, keepdims=True)
    step = np.median(np.abs(np.diff(unit[:, 1])))  # cross range is y at azimuth 0
    period = C_M_S / (F0 + DF * (NF - 1)) / (2 * step)
    assert 70 < period < 76
    with pytest.raises(InputError) as err:
        form_ground_image(ph, _small(azimuth_extent_m=100, range_extent_m=4))
    assert err.value.field == "azimuth_extent_m" and f"every {period:.4g} m" in str(err.value)
    # the refusal is warranted: without the check the 100 m window shows the target again near
    # 30 − period (spread over the band's periods, 72.8–75.5 m): most of the target's energy again, none at full rate
    opt = _small(azimuth_extent_m=100, range_extent_m=4)
    full_ant = _track(469)
    full = read_afrl(_write(tmp_path / "full.mat", full_ant, fp=_samples(full_ant, [target])[0],
                            freq=_samples(ant[:2])[1]))
    energy = {}
    for name, data in (("half", ph), ("full", full)):
        grid = ground_grid(data, opt)
        mag2 = (np.abs(backproject(data, grid, opt)) ** 2).sum(axis=1)
        v_target = 30.0 if grid.v_hat[1] > 0 else -30.0
        ghost = v_target - np.sign(v_target) * (period + 1.5)
        energy[name] = mag2[np.abs(grid.v_m - ghost) < 3.0].sum() / mag2[np.abs(grid.v_m - v_target) < 3.0].sum()
    assert energy["half"] > 0.3 and energy["half"] > 1000 * energy["full"]  # measured 0.76 and 1.6e-6
    form_ground_image(ph, _small(azimuth_extent_m=0.9 * period, range_extent_m=4))  # within the period: fine


def test_gotcha_with_every_other_pulse_dropped(gotcha, tmp_path, capsys):
    cols = {}
    for f in gotcha:
        r = sio.loadmat(str(f))["data"][0, 0]
        for k in ("fp", "x", "y", "z", "r0"):
            cols.setdefault(k, []).append(np.asarray(r[k]))
        freq = np.asarray(r["freq"], float)
    d = {k: np.concatenate(v, axis=1)[:, ::2] for k, v in cols.items()}
    path = tmp_path / "gotcha_every_other.mat"
    sio.savemat(str(path), {"data": {**d, "freq": freq}})
    ant = np.stack([d["x"][0], d["y"][0], d["z"][0]], axis=1).astype(float)
    unit = ant / np.linalg.norm(ant, axis=1, keepdims=True)
    a_c = ant[ant.shape[0] // 2]
    v_hat = np.cross([0, 0, 1.0], np.array([a_c[0], a_c[1], 0]) / np.hypot(a_c[0], a_c[1]))
    period = C_M_S / freq.max() / (2 * np.median(np.abs(np.diff(unit @ v_hat))))  # ≈ 72.8 m
    assert main(["focus", str(path), "--json", str(tmp_path / "o.json")]) == 2  # default 100 m window
    err = capsys.readouterr().err
    assert "azimuth_extent_m" in err and f"{period:.4g} m" in err and "ghosts" in err


# --- samples and files --------------------------------------------------------------------------

def test_all_zero_files_are_refused_and_zero_pulses_counted(tmp_path):
    ant = _track(60)
    fp, f = _samples(ant)
    with pytest.raises(InputError, match="every sample is zero") as err:
        read_afrl(_write(tmp_path / "zero.mat", ant, fp=np.zeros_like(fp), freq=f))
    assert "zero.mat" in str(err.value) and err.value.field == "data.fp"
    fp[:, 20:27] = 0
    ph = read_afrl(_write(tmp_path / "some.mat", ant, fp=fp, freq=f))
    assert any(n.startswith("7 of 60 pulses are all zero (first: pulse 20") for n in ph.notes)


def test_descending_frequency_axis_reads_as_the_same_samples(tmp_path):
    ant = _track(40)
    fp, f = _samples(ant)
    up = read_afrl(_write(tmp_path / "up.mat", ant, fp=fp, freq=f))
    down = read_afrl(_write(tmp_path / "down.mat", ant, fp=fp[::-1], freq=f[::-1]))
    np.testing.assert_array_equal(down.frequency_hz, up.frequency_hz)
    np.testing.assert_array_equal(down.samples, up.samples)


def test_transposed_samples_are_named_as_such(tmp_path):
    ant = _track(40)
    fp, f = _samples(ant)
    with pytest.raises(InputError, match="data.fp looks transposed") as err:
        read_afrl(_write(tmp_path / "t.mat", ant, fp=fp.T.copy(), freq=f))
    assert "t.mat" in str(err.value)


def test_two_polarisations_of_one_azimuth_are_named_not_called_out_of_order(tmp_path):
    ant = _track(80)
    a = _write(tmp_path / "pass1_az001_HH.mat", ant[:40])
    b = _write(tmp_path / "pass1_az001_VV.mat", ant[:40])
    c = _write(tmp_path / "pass1_az002_HH.mat", ant[40:])
    with pytest.raises(InputError) as err:
        read_afrl([a, b, c])
    msg = str(err.value)
    assert "pass1_az001_VV.mat" in msg and "same aperture as pass1_az001_HH.mat" in msg
    assert "polarisation" in msg and "not in aperture order" not in msg
    read_afrl([a, c])  # one polarisation: read


# --- sizes --------------------------------------------------------------------------------------

def test_compressed_file_that_decompresses_too_far_is_refused_before_loading(tmp_path, monkeypatch):
    ant = _track(2000)
    fp = np.zeros((NF, 2000), np.complex64)
    fp[0, 0] = 1
    path = _write(tmp_path / "bomb.mat", ant, fp=fp, freq=F0 + DF * np.arange(NF), do_compression=True)
    plain = _write(tmp_path / "plain.mat", ant, fp=fp, freq=F0 + DF * np.arange(NF))
    assert path.stat().st_size < plain.stat().st_size / 20
    # counted size: the same as the uncompressed file's variables (its size less the 128-byte header)
    assert abs(afrl._content_bytes(path, 10 ** 9) - (plain.stat().st_size - 128)) < 64
    monkeypatch.setattr(afrl, "MAX_CONTENT_BYTES", 1_000_000)

    def no_load(*a, **k):
        raise AssertionError("loadmat must not run")

    monkeypatch.setattr("scipy.io.loadmat", no_load)
    with pytest.raises(InputError, match="decompress to more than 1000000 bytes") as err:
        read_afrl(path)
    assert "bomb.mat" in str(err.value)


def test_more_pulses_than_the_range_profiles_may_hold_are_refused_up_front(monkeypatch):
    n = 17000  # × 4096 range samples × 8 bytes = 557 MB of profiles > 512 MiB
    ant = _track(n, span_deg=0.2)
    f = F0 + DF * np.arange(NF)
    ph = PhaseHistory(samples=np.ones((n, NF), np.complex64), frequency_hz=f, antenna_m=ant,
                      scene_range_m=np.linalg.norm(ant, axis=1), pulse_source=["big"] * n)

    def no_profiles(*a, **k):
        raise AssertionError("range profiles must not be built")

    monkeypatch.setattr(focus_mod, "range_profiles", no_profiles)
    with pytest.raises(InputError) as err:
        form_ground_image(ph, FocusOptions())
    limit = focus_mod.MAX_PROFILE_BYTES // (8 * 4096)
    assert err.value.field == "pulses" and f"at most {limit} pulses" in str(err.value) and limit == 16384
    # cost: 401 × 401 pixels × 16000 pulses = 2.6e9 pixel-pulses passes; a 4× larger window does not
    with pytest.raises(InputError, match="pixel-pulses"):
        focus_mod.check_cost(ph._replace(samples=ph.samples[:16000], frequency_hz=f, antenna_m=ant[:16000],
                                         scene_range_m=ph.scene_range_m[:16000], pulse_source=["big"] * 16000),
                             FocusOptions(range_extent_m=200, azimuth_extent_m=200))


def test_content_counter_stops_at_the_limit_without_inflating_everything(tmp_path):
    raw = zlib.compress(b"\0" * 50_000_000, 9)
    path = tmp_path / "one.mat"
    header = b"MATLAB 5.0 MAT-file".ljust(116, b" ") + b"\0" * 8 + b"\x00\x01IM"
    path.write_bytes(header + np.array([15, len(raw)], "<u4").tobytes() + raw)
    got = afrl._content_bytes(path, 1_000_000)
    assert 1_000_000 < got <= 1_000_000 + (1 << 22)
    assert afrl._content_bytes(path, 10 ** 9) == 50_000_000


def test_an_aperture_of_a_few_pulses_is_refused_not_scored(tmp_path):
    """Five pulses: with a constant and a linear term removed their phase has nothing left to
    differ in, so a comparison with any solution would read as perfect agreement."""
    ant = _track(5, span_deg=0.05)
    ph = read_afrl(_write(tmp_path / "five.mat", ant))
    with pytest.raises(InputError) as err:
        form_ground_image(ph, _small())
    assert err.value.field == "pulses" and "5 pulses" in str(err.value)
    assert f"at least {focus_mod.MIN_FOCUS_PULSES} pulses" in str(err.value)


def test_a_duplicated_pulse_is_noted(tmp_path):
    ant = _track(40)
    ant = np.insert(ant, 11, ant[10], axis=0)  # pulse 11 recorded at pulse 10's position
    ph = read_afrl(_write(tmp_path / "dup.mat", ant))
    notes = [n for n in ph.notes if "duplicated pulses" in n]
    assert len(notes) == 1 and "1 pulse(s)" in notes[0] and "first: pulse 11" in notes[0]
