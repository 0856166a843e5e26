"""Reader for AFRL Gotcha-format phase-history files (MATLAB ``.mat``, one struct ``data``).

Fields (one file = one degree of azimuth of one pass and polarisation): ``fp`` (n_freq, P)
complex phase history, deramped to the scene centre; ``freq`` (n_freq, 1) Hz; ``x``, ``y``, ``z``
(1, P) antenna phase centre, m, scene-centred frame; ``r0`` (1, P) range to the scene centre, m;
``th``, ``phi`` (1, P) azimuth and elevation, deg (optional here); ``af`` (optional) the provider's
autofocus solution with ``r_correct`` (m) and ``ph_correct`` (rad) per pulse. See
:mod:`budget.sar.phase_history` for the phase convention.

Several files are concatenated along the aperture in the order given; they must share the
frequency axis. Every problem raises :class:`~budget.errors.InputError` naming the file and field.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..fileio import require_file
from .geometry_check import angle_notes, range_notes
from .phase_history import RADAR_FREQUENCY_EXPECTED, PhaseHistory, radar_frequency_problem, track_order

_REQUIRED = ("fp", "freq", "x", "y", "z", "r0")
MAX_FILE_BYTES = 2_000_000_000


def _field(rec, names: tuple[str, ...], name: str, path: Path, required: bool = True):
    """Field ``name`` of the struct; None for an optional field that is absent or empty (``[]``,
    MATLAB's way of saying "none")."""
    if name not in names:
        if required:
            raise InputError("missing field", file=path, field=f"data.{name}",
                             expected=f"an AFRL phase-history struct with fields {', '.join(_REQUIRED)}")
        return None
    if not required and np.asarray(rec[name]).size == 0:
        return None
    return rec[name]


def _row(value, n: int, name: str, path: Path) -> np.ndarray:
    arr = np.asarray(value)
    if arr.dtype == object or arr.size != n or (arr.ndim == 2 and min(arr.shape) != 1) or arr.ndim > 2:
        raise InputError(f"shape {arr.shape} does not match {n} pulses", file=path, field=f"data.{name}",
                         expected=f"(1, {n}) values")
    try:
        out = arr.astype(float).ravel()
    except (TypeError, ValueError):
        raise InputError("not numeric", file=path, field=f"data.{name}") from None
    if not np.all(np.isfinite(out)):
        raise InputError("holds NaN or infinite values", file=path, field=f"data.{name}", expected="finite values")
    return out


def _uniform_axis(freq: np.ndarray, stored: np.dtype) -> np.ndarray:
    """The evenly spaced axis from ``freq[0]`` to ``freq[-1]`` when every stored frequency is on it
    to within the rounding of its storage type (two units in the last place: the Gotcha files keep
    9.9 GHz in float32, 1024 Hz apart, so the steps of an even 1.47 MHz axis differ by up to
    2048 Hz, 0.14 %); otherwise ``freq`` unchanged (an uneven axis is refused by
    :class:`~budget.sar.phase_history.PhaseHistory`). The ends are kept as stored."""
    if freq.size < 3 or not np.issubdtype(stored, np.number) or np.issubdtype(stored, np.complexfloating):
        return freq
    line = np.linspace(freq[0], freq[-1], freq.size)
    ulp = float(np.spacing(np.abs(freq).max().astype(stored))) if np.issubdtype(stored, np.floating) else 1.0
    return line if np.max(np.abs(freq - line)) <= 2.0 * ulp else freq


#: Most bytes a file's variables may hold once decompressed (a MATLAB v7 file compresses each
#: variable with zlib: 1.4 GB of zero samples fit in a 1.3 MB file). 1 GB is ≈ 300,000 pulses of
#: 424 complex64 samples, beyond what :func:`budget.sar.focus.check_cost` lets one image use.
MAX_CONTENT_BYTES = 1_000_000_000


def _content_bytes(path: Path, limit: int) -> int:
    """Bytes of a MATLAB v5/v7 file's variables, decompressed, counted by streaming each
    zlib-compressed element in 1 MB pieces (nothing is kept) and stopping once past ``limit``;
    0 when the file is not a v5/v7 file (its reader then says what it is)."""
    import struct
    import zlib

    total = 0
    with open(path, "rb") as fh:
        head = fh.read(128)
        if len(head) < 128 or head[126:128] not in (b"IM", b"MI"):
            return 0
        order = "<" if head[126:128] == b"IM" else ">"
        while total <= limit:
            tag = fh.read(8)
            if len(tag) < 8:
                break
            kind, size = struct.unpack(order + "II", tag)
            if kind != 15:  # not miCOMPRESSED: stored as is, its size is on disk
                total += size
                fh.seek(size + (-size % 8), 1)
                continue
            inflate, left = zlib.decompressobj(), size
            try:
                while left > 0 and total <= limit:
                    chunk = fh.read(min(left, 1 << 20))
                    if not chunk:
                        break
                    left -= len(chunk)
                    data = inflate.decompress(chunk, 1 << 22)
                    while data:
                        total += len(data)
                        if total > limit:
                            break
                        data = inflate.decompress(inflate.unconsumed_tail, 1 << 22)
            except zlib.error:
                return total  # damaged: the reader names it
    return total


def _load_struct(path: Path):
    import scipy.io as sio

    require_file(path, expected="an AFRL phase-history .mat file")
    if path.stat().st_size > MAX_FILE_BYTES:
        raise InputError(f"file is {path.stat().st_size} bytes", file=path,
                         expected=f"at most {MAX_FILE_BYTES} bytes")
    if path.stat().st_size == 0:
        raise InputError("file is empty (0 bytes)", file=path, expected="a MATLAB v5/v7 .mat file")
    with open(path, "rb") as fh:
        head = fh.read(128)
    if len(head) == 128 and head[124:128] in (b"\x00\x02IM", b"\x02\x00MI"):
        raise InputError("is a MATLAB v7.3 (HDF5) file, which this reader does not read", file=path,
                         expected="a MATLAB v5/v7 .mat file (in MATLAB: save(name, 'data', '-v7'))")
    content = _content_bytes(path, MAX_CONTENT_BYTES)
    if content > MAX_CONTENT_BYTES:
        raise InputError(f"its variables decompress to more than {MAX_CONTENT_BYTES} bytes (a file of "
                         f"{path.stat().st_size} bytes)", file=path,
                         expected=f"at most {MAX_CONTENT_BYTES} bytes of phase history per file (fewer pulses)")
    try:
        mat = sio.loadmat(str(path))
    except Exception as err:  # noqa: BLE001 — any failure to parse an untrusted file is bad input
        raise InputError(f"not a readable MATLAB file ({str(err).splitlines()[0] if str(err) else type(err).__name__})",
                         file=path, expected="a MATLAB v5/v7 .mat file") from None
    if "data" not in mat:
        raise InputError("missing variable", file=path, field="data", expected="a struct named 'data'")
    data = mat["data"]
    if data.dtype.names is None:
        raise InputError("is not a struct", file=path, field="data", expected="a MATLAB struct")
    if data.size != 1:  # records beyond the first would be dropped without a word
        what = "an empty struct array" if data.size == 0 else f"a struct array of {data.size} records"
        raise InputError(f"is {what} ({' × '.join(map(str, data.shape))})", file=path, field="data",
                         expected="one struct (one phase history per file: save each record to a file of its own)")
    return data.flat[0], tuple(data.dtype.names)


def read_afrl_file(path: str | Path) -> dict:
    """One file's arrays: samples (P, n_freq) complex64, frequency_hz, antenna_m (P, 3), r0_m and
    the optional azimuth/elevation and recorded autofocus (``None`` when absent)."""
    path = Path(path)
    rec, names = _load_struct(path)
    fp = np.asarray(_field(rec, names, "fp", path))
    if fp.ndim != 2 or not np.iscomplexobj(fp) or min(fp.shape) < 2:
        raise InputError(f"shape {fp.shape}, dtype {fp.dtype}", file=path, field="data.fp",
                         expected="a complex (n_freq, n_pulses) array")
    k, n = fp.shape
    freq = np.asarray(_field(rec, names, "freq", path))
    if freq.size != k or (freq.ndim == 2 and min(freq.shape) != 1):
        hint = (f" (data.fp looks transposed: its {n} columns match the {freq.size} frequencies; it must be "
                "frequencies × pulses)" if freq.size == n else "")
        raise InputError(f"shape {freq.shape} does not match {k} frequency samples of data.fp{hint}", file=path,
                         field="data.freq", expected=f"({k}, 1) frequencies in Hz")
    stored = freq.dtype
    freq = _row(freq, k, "freq", path)
    freq = _uniform_axis(freq, stored)
    problem = radar_frequency_problem(freq)
    if problem:
        raise InputError(problem, file=path, field="data.freq", expected=RADAR_FREQUENCY_EXPECTED)
    if k > 1 and np.all(np.diff(freq) < 0):  # stored from the top of the band down: same samples, flipped
        freq, fp = freq[::-1].copy(), fp[::-1]
    if not np.all(np.isfinite(fp)):
        bad = np.argwhere(~np.isfinite(fp))[0]
        raise InputError(f"non-finite sample at frequency {bad[0]}, pulse {bad[1]}", file=path, field="data.fp",
                         expected="finite complex samples")
    pos = np.stack([_row(_field(rec, names, c, path), n, c, path) for c in ("x", "y", "z")], axis=1)
    out = {"samples": fp.T.astype(np.complex64), "frequency_hz": freq, "antenna_m": pos,
           "r0_m": _row(_field(rec, names, "r0", path), n, "r0", path)}
    for c, key in (("th", "azimuth_deg"), ("phi", "elevation_deg")):
        v = _field(rec, names, c, path, required=False)
        out[key] = None if v is None else _row(v, n, c, path)
    out["square"] = k == n  # frequencies × pulses or pulses × frequencies: the shape cannot tell
    out["r_correct_m"] = out["ph_correct_rad"] = None
    af = _field(rec, names, "af", path, required=False)
    if af is not None and af.dtype.names and all(np.asarray(af.flat[0][c]).size == 0 for c in af.dtype.names):
        af = None  # a struct of empty fields: no recorded solution
    if af is not None:
        af = np.asarray(af)
        af_names = af.dtype.names or ()
        if af.size != 1 or "r_correct" not in af_names or "ph_correct" not in af_names:
            raise InputError("autofocus struct lacks r_correct/ph_correct", file=path, field="data.af",
                             expected="a struct with r_correct (m) and ph_correct (rad) per pulse")
        a0 = af.flat[0]
        out["r_correct_m"] = _row(a0["r_correct"], n, "af.r_correct", path)
        out["ph_correct_rad"] = _row(a0["ph_correct"], n, "af.ph_correct", path)
    return out


#: What a Gotcha file name says of its data: ``data_3dsar_pass1_az001_HH.mat`` is pass 1,
#: polarisation HH (transmit, receive).
_NAME_TAGS = (("pass", re.compile(r"(?:^|_)pass(\d+)(?=_|$)", re.IGNORECASE)),
              ("polarisation", re.compile(r"_(HH|VV|HV|VH)$", re.IGNORECASE)))


def _refuse_mixed_names(paths: list[Path]) -> dict[str, str]:
    """Refuse files whose names say different passes or polarisations (the Gotcha naming,
    :data:`_NAME_TAGS`): their pulses cannot form one aperture (another polarisation's samples
    from the next azimuth join the track without a gap, so nothing else would tell). Names
    without the tag are not compared. Returns what the names agree on, e.g. ``{"pass": "1",
    "polarisation": "HH"}`` (a tag no name carries is left out)."""
    tags: dict[str, str] = {}
    for what, pattern in _NAME_TAGS:
        first = None
        for p in paths:
            m = pattern.search(p.stem)
            if m is None:
                continue
            tag = m.group(1).upper().lstrip("0") or "0"
            if first is None:
                first = (p, tag)
            elif tag != first[1]:
                raise InputError(f"its name says {what} {tag}, that of {first[0].name} says {first[1]}: the pulses "
                                 f"of one image come from one pass and one polarisation", file=p, field="FILE",
                                 expected="files of one pass and one polarisation, in aperture order")
        if first is not None:
            tags[what] = first[1]
    return tags


def name_order(names):
    """``names`` (paths or strings) in natural order: runs of digits compare as numbers, so
    ``az2`` comes before ``az10`` (a lexical sort puts it after, and :func:`read_afrl` refuses
    files out of aperture order)."""
    def key(name):
        text = Path(name).name if isinstance(name, Path) else str(name)
        return [(0, int(t), "") if t.isdigit() else (1, 0, t) for t in re.split(r"(\d+)", text) if t]
    return sorted(names, key=key)


def _aperture_order(paths: list[Path], parts: list[dict]) -> str:
    """The files sorted along the aperture by their first azimuth ``th`` (in the sense the azimuth
    runs within the files; azimuths taken within ±180° of the first file's, so a pass across 0°
    sorts right), or "" when a file has no azimuth or the sense is mixed."""
    th = [part["azimuth_deg"] for part in parts]
    if any(t is None for t in th):
        return ""
    senses = {float(np.sign(t[-1] - t[0])) for t in th if t.size > 1} - {0.0}
    if len(senses) != 1:
        return ""
    sense = senses.pop()
    start = [(t[0] - th[0][0] + 180.0) % 360.0 - 180.0 for t in th]
    order = sorted(range(len(paths)), key=lambda i: sense * start[i])
    return "; by their azimuth: " + " ".join(paths[i].name for i in order)


def _track_notes(paths: list[Path], parts: list[dict]) -> list[str]:
    """Refuse a track that goes back (files out of aperture order); a note per aperture gap
    (:func:`~budget.sar.phase_history.track_order`)."""
    track = np.concatenate([part["antenna_m"] for part in parts])
    src = [f for f, part in enumerate(parts) for _ in range(part["antenna_m"].shape[0])]  # file of each pulse
    order = track_order(track)
    if order.backward is not None:
        i = order.backward
        a, b = paths[src[i]], paths[src[i + 1]]
        if src[i] == src[i + 1]:
            first = i - sum(part["antenna_m"].shape[0] for part in parts[:src[i]])
            raise InputError(f"the antenna goes back along its track between pulses {first} and {first + 1} of this "
                             "file (pulses out of order)", file=a, field="data.x/y/z",
                             expected="antenna positions in aperture order")
        same = [paths[k].name for k in range(len(paths)) if k != src[i + 1] and _same_aperture(parts, k, src[i + 1])]
        if same:
            raise InputError(f"covers the same aperture as {same[0]} (the same first antenna position): another "
                             "polarisation or pass of the same azimuth, or a copy", file=b, field="FILE",
                             expected="one polarisation and pass, each azimuth once, in aperture order")
        raise InputError(f"the antenna jumps back along its track from the last pulse of {a.name} to the first of "
                         f"{b.name}: the files are not in aperture order", file=b, field="FILE",
                         expected="the files in aperture order" + _aperture_order(paths, parts))
    notes = []
    for i, steps in order.gaps:
        a, b = paths[src[i]].name, paths[src[i + 1]].name
        where = a if src[i] == src[i + 1] else f"{a} → {b}"
        notes.append(f"aperture gap after pulse {i} ({where}): {steps:.1f}× the median pulse spacing "
                     f"{order.median_step_m:.3g} m (≈ {max(1, round(steps) - 1)} pulse(s) missing); the azimuth "
                     "window and PGA treat the pulses as evenly spaced, so the image and the autofocus across "
                     "the gap are approximate")
    if order.repeated:
        notes.append(f"{len(order.repeated)} pulse(s) recorded at the antenna position of the pulse before (first: "
                     f"pulse {order.repeated[0]}; duplicated pulses?): the azimuth window and PGA count each as a "
                     "pulse of its own")
    return notes


def _zero_pulse_notes(paths: list[Path], parts: list[dict]) -> list[str]:
    """Refuse files whose samples are all zero; a note counting the all-zero pulses (dropped
    pulses recorded as zeros: they add nothing, and the azimuth window and PGA treat them as
    pulses)."""
    zero = np.concatenate([~np.any(part["samples"] != 0, axis=1) for part in parts])
    if zero.all():
        raise InputError("every sample is zero", file=paths[0] if len(paths) == 1 else ", ".join(p.name for p in paths),
                         field="data.fp", expected="a recorded phase history")
    if not zero.any():
        return []
    idx = np.flatnonzero(zero)
    return [f"{idx.size} of {zero.size} pulses are all zero (first: pulse {idx[0]}; dropped pulses?): they add no "
            "signal, and the azimuth window and PGA still count them as pulses"]


def _geometry_notes(paths: list[Path], parts: list[dict]) -> list[str]:
    """Notes where a file's own fields contradict each other (:mod:`budget.sar.geometry_check`:
    th/phi against the angles of the positions, r0 against their distance to the scene centre) or
    its ``fp`` is square (which axis holds the pulses cannot be told). Files with the same kind of
    disagreement share one note: the first such file's, naming the others."""
    found: dict[str, list] = {}
    for p, part in zip(paths, parts):
        f = part["frequency_hz"]
        step = float((f[-1] - f[0]) / (f.size - 1))
        items = angle_notes(part["antenna_m"], part["azimuth_deg"], part["elevation_deg"])
        items += range_notes(part["antenna_m"], part["r0_m"], step, step * f.size)
        if part["square"]:
            k = f.size
            items.append(("fp: square", f"data.fp is square ({k} × {k}): whether its rows are frequencies and its "
                          "columns pulses (the AFRL layout, read so here) cannot be told from its shape, and no cheap "
                          "property of the samples tells it either; a smeared image may mean it was stored "
                          "transposed"))
        for kind, text in items:
            found.setdefault(kind, [text, []])[1].append(p.name)
    out = []
    for text, names in found.values():
        also = f" (also in {', '.join(names[1:])})" if len(names) > 1 else ""
        out.append(f"{names[0]}: {text}{also}")
    return out


def _same_aperture(parts: list[dict], i: int, j: int) -> bool:
    """Whether files i and j start at the same antenna position (within a tenth of a pulse step)."""
    a, b = parts[i]["antenna_m"], parts[j]["antenna_m"]
    step = np.median(np.linalg.norm(np.diff(a, axis=0), axis=1)) if a.shape[0] > 1 else 0.0
    return bool(np.linalg.norm(a[0] - b[0]) <= 0.1 * step)


def read_afrl(paths) -> PhaseHistory:
    """Read and concatenate AFRL files along the aperture (order as given) into a :class:`PhaseHistory`.

    The files must share the frequency axis (to 1 Hz), be given once each and in aperture order:
    a track that goes back between two files is refused, naming them (and the order of their
    azimuth ``th`` when they have one); each aperture gap (a step > 1.5 × the median pulse
    spacing: a file or pulses missing) gets a note. Files whose Gotcha names say different passes
    or polarisations are refused (:func:`_refuse_mixed_names`); what they agree on is kept as
    :attr:`~budget.sar.phase_history.PhaseHistory.name_tags`. The recorded autofocus solution is
    kept only when every file has one (a note says when it was dropped)."""
    paths = [Path(p) for p in ([paths] if isinstance(paths, (str, Path)) else list(paths))]
    if not paths:
        raise InputError("no phase-history file given", field="FILE", expected="one or more .mat files")
    seen: dict[Path, Path] = {}
    for p in paths:
        key = p.resolve()
        if key in seen:
            raise InputError(f"given twice (also as {seen[key]})", file=p, field="FILE",
                             expected="each phase-history file once, in aperture order")
        seen[key] = p
    parts, held = [], 0
    for p in paths:
        parts.append(read_afrl_file(p))
        held += parts[-1]["samples"].nbytes
        if held > MAX_CONTENT_BYTES:
            raise InputError(f"the files up to this one hold {held} bytes of samples", file=p, field="FILE",
                             expected=f"at most {MAX_CONTENT_BYTES} bytes of phase history in all (fewer files)")
    f0 = parts[0]["frequency_hz"]
    for p, part in zip(paths[1:], parts[1:]):
        f = part["frequency_hz"]
        if f.size != f0.size or np.max(np.abs(f - f0)) > 1.0:
            raise InputError(f"frequency axis differs from that of {paths[0].name}", file=p, field="data.freq",
                             expected=f"the same {f0.size} frequencies in every file")
    notes = _track_notes(paths, parts)  # first: two files of one azimuth are named as such
    name_tags = _refuse_mixed_names(paths)
    notes += _zero_pulse_notes(paths, parts)
    notes += _geometry_notes(paths, parts)
    has_af = all(part["r_correct_m"] is not None for part in parts)
    if not has_af and any(part["r_correct_m"] is not None for part in parts):
        notes.append("recorded autofocus dropped: not every file has one")

    def cat(key):
        if any(part[key] is None for part in parts):
            return None
        return np.concatenate([part[key] for part in parts])

    try:
        ph = PhaseHistory(
            samples=np.concatenate([part["samples"] for part in parts]), frequency_hz=f0,
            antenna_m=np.concatenate([part["antenna_m"] for part in parts]),
            scene_range_m=np.concatenate([part["r0_m"] for part in parts]),
            pulse_source=np.concatenate([[p.name] * part["samples"].shape[0] for p, part in zip(paths, parts)]),
            recorded_range_correction_m=cat("r_correct_m") if has_af else None,
            recorded_phase_correction_rad=cat("ph_correct_rad") if has_af else None,
            azimuth_deg=cat("azimuth_deg"), elevation_deg=cat("elevation_deg"), name_tags=name_tags, notes=notes)
    except InputError as err:
        raise err.rename_file(paths[0] if len(paths) == 1 else ", ".join(p.name for p in paths)) from None
    return ph
