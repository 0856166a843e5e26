"""An AFRL file whose own geometry fields contradict each other is read with a note naming the
likely cause (``budget.sar.geometry_check``): th or phi in radians, x and y swapped (the image is
mirrored: measured here), th clockwise, a constant offset, placeholder angles, phi from the
vertical; positions or r0 in km; r0 measured from another origin; a square ``fp`` whose
orientation the shape cannot tell. The notes reach ``sar-budget focus``'s text and JSON. Files
are written in ``tmp_path`` from a small synthetic circular pass, or from the shared Gotcha file
(skipped when ../shared is absent)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.io as sio

from budget.cli.main import main
from budget.errors import InputError
from budget.sar.afrl import read_afrl
from budget.sar.focus import FocusOptions, form_ground_image
from budget.sar.phase_history import C_M_S

# The synthetic pass: N pulses over SPAN_DEG of azimuth at GROUND_M ground range and HEIGHT_M
# height, K frequencies DF apart from F0; a point target at TARGET (m, ground plane).
F0, DF, K = 9.3e9, 9.375e6, 64
N, SPAN_DEG, GROUND_M, HEIGHT_M = 96, 2.0, 7090.0, 7276.0
TARGET = np.array([0.6, -0.4, 0.0])


def _fields(n=N, k=K, target=TARGET) -> dict:
    """AFRL fields, float64: S(n, f) = exp(−j 4π f / c (|A_n − p| − R0_n)), th/phi of the positions."""
    az = np.radians(np.linspace(-SPAN_DEG / 2, SPAN_DEG / 2, n))
    ant = np.stack([GROUND_M * np.cos(az), GROUND_M * np.sin(az), np.full(n, HEIGHT_M)], axis=1)
    f = F0 + DF * np.arange(k)
    r0 = np.linalg.norm(ant, axis=1)
    s = np.exp(-4j * np.pi * f[None, :] / C_M_S * (np.linalg.norm(ant - target, axis=1) - r0)[:, None])
    return {"fp": s.T.astype(np.complex64), "freq": f[:, None], "x": ant[None, :, 0], "y": ant[None, :, 1],
            "z": ant[None, :, 2], "r0": r0[None, :], "th": np.degrees(az)[None, :],
            "phi": np.degrees(np.arctan2(HEIGHT_M, GROUND_M)) * np.ones((1, n))}


def _write(path: Path, fields: dict) -> Path:
    sio.savemat(str(path), {"data": fields})
    return path


def _tolerance_deg(n=N) -> float:
    """Half the angle between consecutive look directions, from the values written: the chord
    between two of them on the cone is 2 GROUND sin(δφ/2) / R."""
    slant = np.hypot(GROUND_M, HEIGHT_M)
    d_phi = np.radians(SPAN_DEG / (n - 1))
    return float(np.degrees(np.arcsin(GROUND_M * np.sin(d_phi / 2) / slant)))


def _wrap(deg):
    return (np.asarray(deg, float) + 180.0) % 360.0 - 180.0


def test_consistent_fields_read_without_a_note(tmp_path):
    assert read_afrl(_write(tmp_path / "ok.mat", _fields())).notes == []


def _variant(name: str, d: dict) -> tuple[dict, str, float]:
    """(fields, the cause the note must name, the largest angle difference it must state)."""
    x, y, z, th, phi = (d[c].ravel() for c in ("x", "y", "z", "th", "phi"))
    el = np.degrees(np.arctan2(z, np.hypot(x, y)))
    if name == "th in radians":
        return {**d, "th": np.radians(d["th"])}, "th is in radians", np.abs(np.radians(th) - th).max()
    if name == "x and y swapped":  # the azimuth of the swapped positions is 90° − th
        return ({**d, "x": d["y"], "y": d["x"]}, "x and y look swapped (th matches atan2(x, y))",
                np.abs(_wrap(th - (90.0 - th))).max())
    if name == "th clockwise":
        return {**d, "th": -d["th"]}, "th runs clockwise or y is negated", np.abs(2 * th).max()
    if name == "th from north":
        return ({**d, "th": d["th"] + 90.0}, "the same +90° for every pulse: th measured from another reference",
                90.0)
    if name == "th placeholder":
        return {**d, "th": np.zeros_like(d["th"])}, "follows no unit or axis convention", np.abs(th).max()
    if name == "phi in radians":
        return {**d, "phi": np.radians(d["phi"])}, "phi is in radians", np.abs(np.radians(phi) - el).max()
    if name == "phi from vertical":
        return {**d, "phi": 90.0 - d["phi"]}, "phi is measured from the vertical", np.abs(90.0 - phi - el).max()
    raise ValueError(name)


@pytest.mark.parametrize("name", ["th in radians", "x and y swapped", "th clockwise", "th from north",
                                  "th placeholder", "phi in radians", "phi from vertical"])
def test_angles_that_contradict_the_positions_are_noted_with_their_cause(tmp_path, name):
    fields, cause, worst = _variant(name, _fields())
    ph = read_afrl(_write(tmp_path / "v.mat", fields))
    assert len(ph.notes) == 1, ph.notes
    note = ph.notes[0]
    assert note.startswith(f"v.mat: data.{'th' if name.startswith(('th', 'x')) else 'phi'}: ")
    assert cause in note and f"by up to {worst:.4g}°" in note
    assert f"tolerance {_tolerance_deg():.2g}°" in note


def test_angle_within_the_tolerance_is_not_noted_and_beyond_it_is(tmp_path):
    """The tolerance is half the angle step between pulses: an error of 0.4 of a step passes, 0.6
    of a step is noted."""
    d = _fields()
    tol = _tolerance_deg()
    assert read_afrl(_write(tmp_path / "in.mat", {**d, "th": d["th"] + 0.8 * tol})).notes == []
    notes = read_afrl(_write(tmp_path / "out.mat", {**d, "th": d["th"] + 1.2 * tol})).notes
    assert len(notes) == 1 and "the same +" in notes[0]


def test_swapped_axes_mirror_the_image_across_x_equals_y(tmp_path):
    """What the swap note says, measured: the target at (0.6, −0.4) focuses at (−0.4, 0.6) from
    the swapped positions."""
    opt = FocusOptions(range_extent_m=3, azimuth_extent_m=3, spacing_m=0.05, range_window="rect",
                       azimuth_window="rect", workers=1)
    d = _fields()
    for fields, want in ((d, TARGET[:2]), ({**d, "x": d["y"], "y": d["x"]}, TARGET[[1, 0]])):
        img = form_ground_image(read_afrl(_write(tmp_path / "m.mat", fields)), opt)
        i, j = np.unravel_index(np.argmax(np.abs(img.data)), img.data.shape)  # (v, u)
        peak = img.grid.v_m[i] * img.grid.v_hat + img.grid.u_m[j] * img.grid.u_hat
        assert peak[:2] == pytest.approx(want, abs=0.1)


def test_files_alike_share_one_note(tmp_path):
    d = _fields(n=2 * N)
    half = lambda s: {k: (v[:, s] if k not in ("fp", "freq") else (v[:, s] if k == "fp" else v))  # noqa: E731
                      for k, v in d.items()}
    a = _write(tmp_path / "a.mat", {**half(slice(0, N)), "th": np.radians(d["th"][:, :N])})
    b = _write(tmp_path / "b.mat", {**half(slice(N, 2 * N)), "th": np.radians(d["th"][:, N:])})
    notes = read_afrl([a, b]).notes
    assert len(notes) == 1 and notes[0].startswith("a.mat: data.th:") and notes[0].endswith("(also in b.mat)")


# --- r0 against the positions --------------------------------------------------------------------

def test_positions_or_ranges_in_km_are_noted_naming_the_unit_and_refused_by_focus(tmp_path, capsys):
    d = _fields()
    dist = np.linalg.norm(np.concatenate([d["x"], d["y"], d["z"]]), axis=0)
    km = {**d, **{c: d[c] / 1000.0 for c in "xyz"}}
    note = read_afrl(_write(tmp_path / "km.mat", km)).notes
    assert len(note) == 1 and "positions in km, r0 in m?" in note[0] and "0.001 × r0" in note[0]
    assert main(["focus", str(tmp_path / "km.mat"), "--range-extent-m", "2", "--azimuth-extent-m", "2",
                 "--spacing-m", "0.1"]) == 2
    assert "positions in km, ranges in m?" in capsys.readouterr().err
    r0_km = read_afrl(_write(tmp_path / "r0km.mat", {**d, "r0": d["r0"] / 1000.0})).notes
    assert len(r0_km) == 1 and "positions in m, r0 in km?" in r0_km[0] and "1000 × r0" in r0_km[0]
    both = read_afrl(_write(tmp_path / "both.mat", {**km, "r0": d["r0"] / 1000.0})).notes
    assert len(both) == 1 and f"{np.median(dist) / 1000:.4g} m from the scene centre" in both[0]
    assert f"c/(2Δf) = {C_M_S / (2 * DF):.4g} m" in both[0] and "positions and r0 in km?" in both[0]


def test_ranges_to_another_origin_are_noted_with_the_offset(tmp_path):
    """r0 measured to a point 2 m from the frame origin (within the ±8 m swath, beyond half the
    0.25 m slant-range resolution): the image is shifted; 0.1 m passes."""
    d = _fields()
    assert read_afrl(_write(tmp_path / "near.mat", {**d, "r0": d["r0"] + 0.1})).notes == []
    notes = read_afrl(_write(tmp_path / "off.mat", {**d, "r0": d["r0"] - 2.0})).notes
    assert len(notes) == 1 and "differs from r0 by +2 m" in notes[0]
    assert f"{C_M_S / (4 * K * DF):.3g} m" in notes[0] and "another frame origin?" in notes[0]


def test_square_fp_is_noted_as_undecidable(tmp_path):
    notes = read_afrl(_write(tmp_path / "sq.mat", _fields(n=K))).notes
    assert len(notes) == 1 and f"data.fp is square ({K} × {K})" in notes[0] and "cannot be told" in notes[0]


# --- the focus command carries the notes ---------------------------------------------------------

def test_focus_text_and_json_carry_the_note(tmp_path, capsys):
    fields, cause, _ = _variant("x and y swapped", _fields())
    path = _write(tmp_path / "swapped.mat", fields)
    out = tmp_path / "f.json"
    args = ["focus", str(path), "--autofocus", "none", "--range-extent-m", "3", "--azimuth-extent-m", "3",
            "--spacing-m", "0.1"]
    assert main(args + ["--json", str(out)]) == 0
    assert any(cause in n for n in json.loads(out.read_text())["notes"])
    capsys.readouterr()
    assert main(args) == 0
    assert cause in capsys.readouterr().out


# --- the shared Gotcha file ----------------------------------------------------------------------

def test_gotcha_fields_agree_far_within_the_tolerance(gotcha):
    """th, phi and r0 of the four files against their positions: 1e-7°, 3e-6° and 0.7 mm (the
    float32 rounding), against a tolerance of ≈ 0.003° and 0.12 m; no note."""
    for path in gotcha:
        d = sio.loadmat(str(path))["data"][0, 0]
        x, y, z, r0, th, phi = (np.asarray(d[c], float).ravel() for c in ("x", "y", "z", "r0", "th", "phi"))
        assert np.abs(_wrap(th - np.degrees(np.arctan2(y, x)))).max() < 1e-5
        assert np.abs(phi - np.degrees(np.arctan2(z, np.hypot(x, y)))).max() < 1e-4
        assert np.abs(np.sqrt(x ** 2 + y ** 2 + z ** 2) - r0).max() < 0.002
    assert read_afrl(gotcha).notes == []


def test_gotcha_variants_are_noted(gotcha, tmp_path):
    d = sio.loadmat(str(gotcha[0]))["data"][0, 0]
    base = {k: d[k] for k in ("fp", "freq", "x", "y", "z", "r0", "th", "phi")}
    th = base["th"].astype(float).ravel()
    cases = {"rad": ({**base, "th": np.radians(base["th"])}, "th is in radians"),
             "swap": ({**base, "x": base["y"], "y": base["x"]}, "x and y look swapped"),
             "phirad": ({**base, "phi": np.radians(base["phi"])}, "phi is in radians"),
             "km": ({**base, **{c: base[c] / 1000.0 for c in "xyz"}}, "positions in km, r0 in m?")}
    for name, (fields, cause) in cases.items():
        notes = read_afrl(_write(tmp_path / f"{name}.mat", fields)).notes
        assert len(notes) == 1 and cause in notes[0], (name, notes)
    notes = read_afrl(tmp_path / "rad.mat").notes
    assert f"by up to {np.abs(np.radians(th) - th).max():.4g}°" in notes[0]
    with pytest.raises(InputError, match=r"positions in km, ranges in m\?"):
        form_ground_image(read_afrl(tmp_path / "km.mat"), FocusOptions(range_extent_m=4, azimuth_extent_m=4))
