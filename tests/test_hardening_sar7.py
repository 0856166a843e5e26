"""Phase histories from other passes, polarisations and writers: a struct array of several
records, file names of two polarisations or passes forming one aperture, empty optional fields
(``af = []``), a float32 frequency axis finer or higher than Gotcha's, a MATLAB v7.3 or empty
file, and the resolution of the image against its closed forms. Synthetic files are written in
``tmp_path``; the Gotcha checks skip when ../shared is absent."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.io as sio

from budget.cli.main import main
from budget.errors import InputError
from budget.sar.afrl import read_afrl
from budget.sar.focus import FocusOptions, form_ground_image
from budget.sar.phase_history import C_M_S, PhaseHistory

from gotcha_synth import circular_track

F0, DF, NF = 9.288e9, 1.4713e6, 424  # the Gotcha band: Hz, Hz, samples


def _fields(antenna, n_freq=NF, f0=F0, df=DF, target=np.zeros(3)):
    """AFRL fields of a point target at ``target`` seen along ``antenna`` (n, 3), m:
    S(n, f) = exp(−j 4π f / c (|A_n − p| − R0_n)), stored (n_freq, n_pulses)."""
    f = f0 + df * np.arange(n_freq)
    r0 = np.linalg.norm(antenna, axis=1)
    s = np.exp(-4j * np.pi * f[None, :] / C_M_S * (np.linalg.norm(antenna - target, axis=1) - r0)[:, None])
    return {"fp": s.T.astype(np.complex64), "freq": f[:, None], "x": antenna[None, :, 0], "y": antenna[None, :, 1],
            "z": antenna[None, :, 2], "r0": r0[None, :]}


def _write(path, fields):
    sio.savemat(str(path), {"data": fields})
    return path


# --- a struct array: every record but the first was dropped --------------------------------------

def test_struct_array_of_several_records_is_refused(tmp_path):
    ant = circular_track(40)
    a, b = _fields(ant[:20], n_freq=16), _fields(ant[20:], n_freq=16)
    rec = np.empty((1, 2), dtype=[(k, object) for k in a])
    for j, part in enumerate((a, b)):
        for k, v in part.items():
            rec[0, j][k] = v
    path = tmp_path / "two.mat"
    sio.savemat(str(path), {"data": rec})
    with pytest.raises(InputError) as err:
        read_afrl(path)
    msg = str(err.value)
    assert "two.mat" in msg and "field data" in msg and "2 records" in msg and "1 × 2" in msg
    empty = tmp_path / "none.mat"
    sio.savemat(str(empty), {"data": np.empty((0, 0), dtype=[(k, object) for k in a])})
    with pytest.raises(InputError, match=r"none\.mat, field data: is an empty struct array"):
        read_afrl(empty)


# --- names of two polarisations or passes ---------------------------------------------------------

def _two_azimuths(tmp_path, first, second):
    ant = circular_track(60)
    return (_write(tmp_path / first, _fields(ant[:30], n_freq=16)),
            _write(tmp_path / second, _fields(ant[30:], n_freq=16)))


@pytest.mark.parametrize("second, what, tags", [
    ("data_3dsar_pass1_az002_VV.mat", "polarisation", ("VV", "HH")),
    ("data_3dsar_pass2_az002_HH.mat", "pass", ("2", "1")),
])
def test_files_named_for_another_polarisation_or_pass_are_refused(tmp_path, capsys, second, what, tags):
    # the two halves of one track: nothing in the data tells the join apart
    a, b = _two_azimuths(tmp_path, "data_3dsar_pass1_az001_HH.mat", second)
    with pytest.raises(InputError) as err:
        read_afrl([a, b])
    msg = str(err.value)
    assert second in msg and "data_3dsar_pass1_az001_HH.mat" in msg
    assert f"says {what} {tags[0]}" in msg and f"says {tags[1]}" in msg
    assert main(["focus", str(a), str(b), "--range-extent-m", "8", "--azimuth-extent-m", "20"]) == 2
    assert second in capsys.readouterr().err


def test_names_of_one_pass_and_polarisation_or_without_tags_are_read(tmp_path):
    a, b = _two_azimuths(tmp_path, "data_3dsar_pass1_az001_VV.mat", "data_3dsar_pass01_az002_vv.mat")
    assert read_afrl([a, b]).n_pulses == 60
    c, d = _two_azimuths(tmp_path, "first.mat", "second.mat")
    assert read_afrl([c, d]).n_pulses == 60


# --- empty optional fields ------------------------------------------------------------------------

@pytest.mark.parametrize("extra", [
    {"af": np.zeros((0, 0))},
    {"af": {"r_correct": np.zeros((0, 0)), "ph_correct": np.zeros((0, 0))}},
    {"th": np.zeros((0, 0)), "phi": np.zeros((0, 0))},
])
def test_empty_optional_fields_read_as_absent(tmp_path, extra):
    ant = circular_track(30)
    plain = read_afrl(_write(tmp_path / "plain.mat", _fields(ant, n_freq=16)))
    ph = read_afrl(_write(tmp_path / "empty.mat", {**_fields(ant, n_freq=16), **extra}))
    assert not ph.has_recorded_autofocus and ph.azimuth_deg is None and ph.elevation_deg is None
    assert np.array_equal(ph.samples, plain.samples) and np.array_equal(ph.antenna_m, plain.antenna_m)


# --- a float32 frequency axis ---------------------------------------------------------------------

@pytest.mark.parametrize("f0, df, n", [(9.6e9, 0.5e6, 64), (16e9, 0.3e6, 64)])
def test_float32_frequency_axis_is_read_as_the_even_axis_it_rounds(tmp_path, f0, df, n):
    ant = circular_track(30)
    fields = _fields(ant, n_freq=n, f0=f0, df=df)
    stored = (f0 + df * np.arange(n)).astype(np.float32)
    steps = np.diff(stored.astype(float))
    assert np.ptp(steps) > 1e-3 * steps.mean()  # beyond PhaseHistory's tolerance as stored
    ph = read_afrl(_write(tmp_path / "f32.mat", {**fields, "freq": stored[:, None]}))
    assert ph.frequency_hz[0] == float(stored[0]) and ph.frequency_hz[-1] == float(stored[-1])
    assert ph.frequency_step_hz == pytest.approx((float(stored[-1]) - float(stored[0])) / (n - 1), rel=1e-12)
    assert np.max(np.abs(ph.frequency_hz - stored)) <= 2 * np.spacing(np.float32(stored[-1]))
    uneven = stored.astype(float).copy()
    uneven[n // 2] += 0.01 * df  # 1 % of a step off: not rounding
    with pytest.raises(InputError, match="equal steps"):
        read_afrl(_write(tmp_path / "uneven.mat", {**fields, "freq": uneven[:, None]}))


# --- files that are not MATLAB v5/v7 --------------------------------------------------------------

def test_v73_and_empty_files_are_named_as_such(tmp_path, capsys):
    head = b"MATLAB 7.3 MAT-file, Platform: GLNXA64, HDF5 schema 1.00 .".ljust(116, b" ") + b"\0" * 8 + b"\x00\x02IM"
    v73 = tmp_path / "v73.mat"
    v73.write_bytes(head.ljust(512, b"\0") + b"\x89HDF\r\n\x1a\n" + b"\0" * 64)
    with pytest.raises(InputError, match=r"v73\.mat: is a MATLAB v7\.3 \(HDF5\) file.*-v7"):
        read_afrl(v73)
    empty = tmp_path / "empty.mat"
    empty.write_bytes(b"")
    assert main(["focus", str(empty)]) == 2
    assert "empty.mat: file is empty (0 bytes)" in capsys.readouterr().err


# --- the image against its closed forms -----------------------------------------------------------

def test_point_target_lands_where_placed_with_the_closed_form_resolution():
    """3 dB widths of a unit point target (rectangular windows): 0.886 c / (2B) / cos(elevation)
    in ground range, B = N Δf, and 0.886 λ_c / (2 Δθ) in cross range, Δθ the angle between the
    first and last look directions; within 2 %."""
    ant = circular_track(469, span_deg=4.0)
    target = np.array([3.0, -2.0, 0.0])
    f = _fields(ant, target=target)
    ph = PhaseHistory(samples=f["fp"].T, frequency_hz=f["freq"].ravel(), antenna_m=ant,
                      scene_range_m=f["r0"].ravel(), pulse_source=["t"] * 469)
    d = 0.015
    opt = FocusOptions(range_extent_m=1.5, azimuth_extent_m=1.5, spacing_m=d, range_window="rect",
                       azimuth_window="rect", range_centre_m=float(target @ np.array([1.0, 0, 0])),
                       azimuth_centre_m=float(target @ np.array([0, 1.0, 0])), workers=1)
    img = form_ground_image(ph, opt)
    assert np.allclose(img.grid.u_hat, [1, 0, 0], atol=1e-9) and np.allclose(img.grid.v_hat, [0, 1, 0], atol=1e-9)
    mag = np.abs(img.data)
    i, j = np.unravel_index(np.argmax(mag), mag.shape)
    assert abs(img.grid.u_m[j] - 3.0) <= d and abs(img.grid.v_m[i] + 2.0) <= d
    assert mag[i, j] == pytest.approx(1.0, abs=0.02)

    def width(line):
        line = line / line.max()
        k = int(np.argmax(line))
        lo, hi = k, k
        while line[lo - 1] >= 0.5 ** 0.5:
            lo -= 1
        while line[hi + 1] >= 0.5 ** 0.5:
            hi += 1
        h = 0.5 ** 0.5
        return d * ((hi + (line[hi] - h) / (line[hi] - line[hi + 1])) - (lo - (line[lo] - h) / (line[lo] - line[lo - 1])))

    el = np.arctan2(ant[:, 2], np.hypot(ant[:, 0], ant[:, 1])).mean()
    look = ant / np.linalg.norm(ant, axis=1)[:, None]
    dtheta = np.arccos(look[0] @ look[-1])
    lam = C_M_S / (F0 + DF * (NF - 1) / 2)
    assert width(mag[i, :]) == pytest.approx(0.886 * C_M_S / (2 * NF * DF) / np.cos(el), rel=0.02)
    assert width(mag[:, j]) == pytest.approx(0.886 * lam / (2 * dtheta), rel=0.02)


# --- the Gotcha files as other writers store them -------------------------------------------------

def test_gotcha_file_rewritten_reads_and_focuses_the_same(gotcha, tmp_path):
    """One shared file saved again in double precision with the frequencies as a row, the
    positions as columns, an empty autofocus and a name of another pass and polarisation: the
    same arrays (frequency axis to its float32 rounding) and the same image."""
    rec = sio.loadmat(str(gotcha[0]))["data"][0, 0]
    fields = {k: rec[k] for k in ("fp", "freq", "x", "y", "z", "r0", "th", "phi")}
    stored_freq = fields["freq"].ravel()
    out = {"fp": fields["fp"].astype(np.complex128), "freq": stored_freq.astype(float)[None, :],
           **{k: fields[k].astype(float).T for k in ("x", "y", "z", "r0", "th", "phi")}, "af": np.zeros((0, 0))}
    other = _write(tmp_path / "data_3dsar_pass2_az045_VV.mat", out)
    a, b = read_afrl(gotcha[0]), read_afrl(other)
    assert a.notes == [] and b.notes == []
    assert np.array_equal(a.samples, b.samples) and np.allclose(a.antenna_m, b.antenna_m, rtol=0, atol=1e-9)
    assert np.max(np.abs(a.frequency_hz - stored_freq)) <= 2 * np.spacing(np.float32(stored_freq.max()))
    assert a.frequency_hz[0] == stored_freq[0] and a.frequency_hz[-1] == stored_freq[-1]
    assert not b.has_recorded_autofocus
    opt = FocusOptions(range_extent_m=10, azimuth_extent_m=10, spacing_m=0.25, workers=1)
    ia, ib = form_ground_image(a, opt), form_ground_image(b, opt)
    assert np.max(np.abs(ia.data - ib.data)) <= 1e-5 * np.abs(ia.data).max()
