"""Whether an AFRL file's geometry fields agree with each other, and what it likely is when not.

The fields overlap: the azimuth ``th`` and elevation ``phi`` (deg) are the antenna's direction
seen from the scene centre, which the positions x, y, z (m, scene-centred frame) also give,

    th_pos = atan2(y, x),    phi_pos = atan2(z, √(x² + y²)),

and ``r0`` (m) is the antenna's distance to the scene centre, |A|. The Gotcha files agree to
≈ 1e-7° in th, 3e-6° in phi and 0.7 mm in r0. A file that does not agree is read with a note
(:func:`angle_notes`, :func:`range_notes`) that names the likely cause where the numbers identify
it; what cannot be imaged at all is refused later by :func:`budget.sar.focus.check_geometry`.

Tolerance of the angle comparison (:func:`angle_tolerance_deg`): half the angle δθ the antenna
turns between consecutive pulses as seen from the scene centre (median over the file; Gotcha
≈ 0.006°, so 0.003°): an angle error below it cannot put a pulse past its neighbour. It is never
below four float32 steps of the largest angle plus the angle four float32 steps of the largest
position subtend at the shortest ground range (the rounding of the storage; ≈ 3e-5° for Gotcha).

Causes named (first match; each test is the comparison above within the tolerance):

* th in radians: th·180/π matches th_pos (phi likewise);
* x and y swapped: th matches atan2(x, y) — the positions are the mirror image of the track
  across the line x = y, and so is the image formed from them;
* th clockwise or y negated: th matches atan2(−y, x) — one of the two mirrors the image;
* phi from the vertical: 90° − phi matches phi_pos;
* a constant offset (another reference direction): th − th_pos the same for every pulse;
* otherwise the largest difference is stated (placeholder angles, another frame?).

r0 (:func:`range_notes`): a median |A| / r0 within 5 % of 1000 or 1/1000 names the unit
(positions in m, ranges in km, or the converse); an r0 shorter than the unambiguous range
c/(2Δf) the frequency step records (the whole geometry within one range ambiguity: 102 m for
Gotcha's 1.47 MHz step, against its 10.2 km) suggests positions and r0 both in km; otherwise a median | |A| − r0 | beyond half the slant-range resolution c/(4B)
shifts the image in range by it (another frame origin?).
"""

from __future__ import annotations

import numpy as np

from .phase_history import C_M_S


def _wrap(deg: np.ndarray) -> np.ndarray:
    """Angle difference wrapped to [−180°, 180°)."""
    return (np.asarray(deg, dtype=float) + 180.0) % 360.0 - 180.0


def angle_tolerance_deg(antenna_m: np.ndarray, angle_deg: np.ndarray | None = None) -> float:
    """Tolerance of the angle comparison, deg (module docstring)."""
    a = np.asarray(antenna_m, dtype=float)
    look = a / np.linalg.norm(a, axis=1)[:, None]
    step = np.arctan2(np.linalg.norm(np.cross(look[:-1], look[1:]), axis=1), np.einsum("ij,ij->i", look[:-1], look[1:]))
    half_step = 0.5 * float(np.degrees(np.median(step))) if step.size else 0.0
    ground = float(np.hypot(a[:, 0], a[:, 1]).min())
    big = float(np.abs(a).max())
    floor = float(np.degrees(4.0 * np.spacing(np.float32(big)) / ground)) if ground > 0 else 0.0
    if angle_deg is not None and np.size(angle_deg):
        floor += 4.0 * float(np.spacing(np.float32(np.abs(angle_deg).max())))
    return max(half_step, floor)


def _azimuth_cause(th: np.ndarray, a: np.ndarray, tol: float) -> tuple[str, str] | None:
    """None when th agrees with the positions, else (kind of disagreement, the note's text after
    the field name)."""
    x, y = a[:, 0], a[:, 1]
    pos = np.degrees(np.arctan2(y, x))
    off = _wrap(th - pos)
    if np.max(np.abs(off)) <= tol:
        return None
    worst = f"th differs from the positions' azimuth atan2(y, x) by up to {np.max(np.abs(off)):.4g}°"
    rad = np.degrees(th)
    candidates = [
        ("radians", rad, pos, "th is in radians (th·180/π matches the positions' azimuth): read as degrees here, only the "
                   "notes and the file order by azimuth use it"),
        ("swapped", th, np.degrees(np.arctan2(x, y)), "x and y look swapped (th matches atan2(x, y)): the positions are the "
                                          "mirror image of the track across x = y, and so is the image formed "
                                          "from them"),
        ("radians, swapped", rad, np.degrees(np.arctan2(x, y)), "th is in radians and x and y look swapped (th·180/π matches "
                                            "atan2(x, y)): the image formed from these positions is mirrored"),
        ("clockwise", th, np.degrees(np.arctan2(-y, x)), "th runs clockwise or y is negated (th matches atan2(−y, x)): if the "
                                           "positions are the wrong ones the image is mirrored"),
    ]
    for kind, got, want, cause in candidates:
        if np.max(np.abs(_wrap(got - want))) <= tol:
            return kind, f"{worst}: {cause}"
    if np.ptp(np.unwrap(np.radians(off))) <= np.radians(2.0 * tol):
        return "offset", (f"{worst}, the same {float(np.median(off)):+.4g}° for every pulse: th measured from another "
                "reference direction? (the image uses the positions)")
    return "other", f"{worst} and follows no unit or axis convention: placeholder angles, or another frame?"


def _elevation_cause(phi: np.ndarray, a: np.ndarray, tol: float) -> tuple[str, str] | None:
    pos = np.degrees(np.arctan2(a[:, 2], np.hypot(a[:, 0], a[:, 1])))
    off = phi - pos
    if np.max(np.abs(off)) <= tol:
        return None
    worst = f"phi differs from the positions' elevation atan2(z, √(x² + y²)) by up to {np.max(np.abs(off)):.4g}°"
    if np.max(np.abs(np.degrees(phi) - pos)) <= tol:
        return "radians", f"{worst}: phi is in radians (phi·180/π matches)"
    if np.max(np.abs(90.0 - phi - pos)) <= tol:
        return "vertical", f"{worst}: phi is measured from the vertical (90° − phi matches)"
    if np.ptp(off) <= 2.0 * tol:
        return "offset", (f"{worst}, the same {float(np.median(off)):+.4g}° for every pulse: another scene-centre height or "
                "frame? (the image uses the positions)")
    return "other", f"{worst} and follows no unit or convention: placeholder angles, or another frame?"


def angle_notes(antenna_m, azimuth_deg=None, elevation_deg=None) -> list[tuple[str, str]]:
    """(kind, note) where ``th``/``phi`` disagree with the positions beyond
    :func:`angle_tolerance_deg`, naming the likely cause (module docstring; the note without the
    file name, the kind e.g. ``"th: radians"`` to group files alike); [] when they agree or are
    absent."""
    a = np.asarray(antenna_m, dtype=float)
    notes = []
    for field, values, judge in (("th", azimuth_deg, _azimuth_cause), ("phi", elevation_deg, _elevation_cause)):
        if values is None:
            continue
        v = np.asarray(values, dtype=float).ravel()
        tol = angle_tolerance_deg(a, v)
        found = judge(v, a, tol)
        if found:
            notes.append((f"{field}: {found[0]}",
                          f"data.{field}: {found[1]} (tolerance {tol:.2g}°, half the angle step between pulses)"))
    return notes


def range_notes(antenna_m, r0_m, frequency_step_hz: float, bandwidth_hz: float) -> list[tuple[str, str]]:
    """(kind, note) where the positions' distance to the scene centre disagrees
    with ``r0`` (module docstring); [] when they agree."""
    a = np.asarray(antenna_m, dtype=float)
    r0 = np.asarray(r0_m, dtype=float).ravel()
    dist = np.linalg.norm(a, axis=1)
    ratio = float(np.median(dist / r0))
    for factor, unit in ((1e-3, "positions in km, r0 in m"), (1e3, "positions in m, r0 in km")):
        if abs(ratio / factor - 1.0) < 0.05:
            return [(f"r0: {unit}", f"data.x/y/z, data.r0: the antenna's distance to the scene centre is {ratio:.4g} × r0 (median "
                    f"{np.median(dist):.5g} against r0 {np.median(r0):.5g}): {unit}? (positions and r0 must be "
                    "in m; the image cannot be formed)")]
    unambiguous = C_M_S / (2.0 * frequency_step_hz)
    if float(np.median(r0)) < unambiguous:
        return [("r0: short", f"data.r0: the antenna is {np.median(r0):.4g} m from the scene centre (median r0), "
                 f"less than the unambiguous range c/(2Δf) = {unambiguous:.4g} m the frequency step records: "
                 "positions and r0 in km?")]
    off = float(np.median(dist - r0))
    half_res = C_M_S / (4.0 * bandwidth_hz)
    if abs(off) > half_res:
        return [("r0: offset", f"data.x/y/z, data.r0: the antenna's distance to the scene centre differs from r0 by {off:+.4g} m "
                f"(median over the pulses; more than half the slant-range resolution, {half_res:.3g} m): the "
                "data are deramped to another point than the frame origin, and the image is shifted by it in "
                "range (another frame origin?)")]
    return []
