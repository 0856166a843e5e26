"""The unit in a numeric column's name, and what to suggest for a header the catalog does not read.

A numeric column of ``parts.csv`` is a *quantity* followed by its *unit*: ``gyro_arw`` +
``deg_rt_h``, ``gyro_arw`` + ``deg_s_rt_hz``. The accepted columns are the catalog's own table
(:data:`~budget.catalog.schema.PART_NUMERIC_COLUMNS` and the alternative-unit columns of
:mod:`budget.catalog.validate`): :func:`quantity_table` splits each into quantity and unit from
the unit label the table already holds (``deg/s/√Hz`` → ``deg_s_rt_hz``), so no column list is
kept here.

What is kept here is the vocabulary to *read* the unit of a header the catalog does not accept
(:data:`UNIT_WORDS`, :data:`UNIT_SHORTHAND`): ``dps``, ``deg_s``, ``deg_per_s``, ``mdeg_s``,
``dph``, ``deg_h``, ``rad_s``, ``mg``, ``ug``/``µg``, ``ppm``, ``pct``, ``rt_hz``/``sqrt_hz``/``rthz``
… A unit is read left to right: the first word is the numerator, every later word divides
(``deg_s_rt_hz`` = deg/s/√Hz; ``per`` may stand between), ``rt`` takes the square root of the
next word, a trailing ``2`` squares it (``m_s2``). Each reading carries its factor to SI and its
dimension, so a header is compared with the accepted columns of its quantity *by unit*:

* the same unit under another spelling (``gyro_arw_dps_rt_hz``): that column is suggested;
* a unit of the right dimension the catalog has no column for (``gyro_arw_mdeg_s_rt_hz``): the
  message says so and gives, for every accepted column of the quantity, the factor to apply
  ("divide by 1000 and use gyro_arw_deg_s_rt_hz");
* a unit of another dimension (``gyro_arw_deg_rt_hz``), or one not understood: the accepted
  columns are listed, none picked — a suggestion never changes the unit silently.
"""

from __future__ import annotations

import difflib
import itertools
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction

from .. import units as u

#: Dimension exponents: (angle, length, time, mass, money).
Dims = tuple[Fraction, Fraction, Fraction, Fraction, Fraction]


def _dims(angle=0, length=0, time=0, mass=0, money=0) -> Dims:
    return tuple(Fraction(x) for x in (angle, length, time, mass, money))  # type: ignore[return-value]


_ANGLE, _TIME, _FREQ, _LENGTH = _dims(angle=1), _dims(time=1), _dims(time=-1), _dims(length=1)
_ACCEL, _MASS, _RATIO = _dims(length=1, time=-2), _dims(mass=1), _dims()

#: Words a unit in a header is made of → its readings (factor to SI, dimension, label). ``g``,
#: ``mg``, ``ug`` are an acceleration (g₀ = 9.80665 m/s²) except in the ``mass`` quantity.
UNIT_WORDS: dict[str, tuple[tuple[float, Dims, str], ...]] = {
    "rad": ((1.0, _ANGLE, "rad"),), "radian": ((1.0, _ANGLE, "rad"),), "radians": ((1.0, _ANGLE, "rad"),),
    "mrad": ((1e-3, _ANGLE, "mrad"),), "milliradian": ((1e-3, _ANGLE, "mrad"),),
    "milliradians": ((1e-3, _ANGLE, "mrad"),), "urad": ((1e-6, _ANGLE, "µrad"),),
    "deg": ((u.DEG, _ANGLE, "deg"),), "degree": ((u.DEG, _ANGLE, "deg"),),
    "degrees": ((u.DEG, _ANGLE, "deg"),), "mdeg": ((1e-3 * u.DEG, _ANGLE, "mdeg"),),
    "arcmin": ((u.DEG / 60.0, _ANGLE, "arcmin"),), "arcsec": ((u.DEG / 3600.0, _ANGLE, "arcsec"),),
    "s": ((1.0, _TIME, "s"),), "sec": ((1.0, _TIME, "s"),), "second": ((1.0, _TIME, "s"),),
    "ms": ((1e-3, _TIME, "ms"),), "min": ((60.0, _TIME, "min"),), "h": ((u.HOUR, _TIME, "h"),),
    "hr": ((u.HOUR, _TIME, "h"),), "hour": ((u.HOUR, _TIME, "h"),),
    "hz": ((1.0, _FREQ, "Hz"),), "khz": ((1e3, _FREQ, "kHz"),),
    "m": ((1.0, _LENGTH, "m"),), "mm": ((1e-3, _LENGTH, "mm"),), "cm": ((1e-2, _LENGTH, "cm"),),
    "km": ((1e3, _LENGTH, "km"),), "ft": ((u.FOOT, _LENGTH, "ft"),),
    "g": ((u.G0, _ACCEL, "g"), (1e-3, _MASS, "g")),
    "mg": ((1e-3 * u.G0, _ACCEL, "mg"), (1e-6, _MASS, "mg")),
    "ug": ((1e-6 * u.G0, _ACCEL, "µg"), (1e-9, _MASS, "µg")),
    "ng": ((1e-9 * u.G0, _ACCEL, "ng"),),
    "kg": ((1.0, _MASS, "kg"),),
    "ppm": ((1e-6, _RATIO, "ppm"),), "ppb": ((1e-9, _RATIO, "ppb"),),
    "pct": ((1e-2, _RATIO, "%"),), "percent": ((1e-2, _RATIO, "%"),),
    "usd": ((1.0, _dims(money=1), "USD"),),
}
#: Words standing for two (``dps`` = ``deg_s``): the log reader's channel tags
#: (:data:`budget.units.CHANNEL_UNIT_ALIASES`, read backwards) and a few more.
UNIT_SHORTHAND: dict[str, str] = {**{tag: spelled for spelled, tag in u.CHANNEL_UNIT_ALIASES.items()},
                                  "mdps": "mdeg_s", "degps": "deg_s", "degph": "deg_h", "sps": "hz"}
#: Quantities whose ``g``/``mg``/``ug`` are a mass, not an acceleration.
_MASS_QUANTITIES = ("mass",)

#: How datasheet-minded headers are respelt before they are compared with the column names: the
#: micro sign, "sqrt"/"√", "hr", a degree sign, "%" and "²", brackets around a unit.
HEADER_SPELLINGS = (("µ", "u"), ("μ", "u"), ("√", "rt_"), ("sqrt", "rt"), ("_hr", "_h"), ("°", "deg_"),
                    ("%", "pct"), ("²", "2"), ("^", ""), ("[", "_"), ("]", ""), ("(", "_"), (")", ""),
                    ("/", "_"), (" ", "_"), ("-", "_"))


def respell(header: str) -> str:
    """``header`` lower-cased and respelt (:data:`HEADER_SPELLINGS`): ``Gyro ARW [°/√h]`` →
    ``gyro_arw_deg_rt_h``."""
    key = header.strip().lower()
    for a, b in HEADER_SPELLINGS:
        key = key.replace(a, b)
    return re.sub("_+", "_", key).strip("_")


@dataclass(frozen=True)
class Reading:
    """One reading of a unit text: factor to SI, dimension and the unit as messages write it."""

    si: float
    dims: Dims
    label: str


def _words(text: str) -> list[str]:
    """The words of a unit text, shorthands expanded (``dps`` → deg s) and a joined root split
    (``rthz`` → rt hz)."""
    out: list[str] = []
    for w in text.split("_"):
        if w and w not in UNIT_WORDS and w.startswith("rt") and len(w) > 2:
            out.append("rt")
            w = w[2:]
        out += [x for x in UNIT_SHORTHAND.get(w, w).split("_") if x]
    return out


def unit_words(name: str) -> list[str]:
    """The unit words in a (respelt) column name, shorthands expanded: ``gyro_bias_dph_min`` →
    ['deg', 'h', 'min']. Two names with different unit words are never offered for each other."""
    return [w for w in _words(name) if w in UNIT_WORDS]


def read_unit(text: str) -> list[Reading]:
    """Every reading of a unit written the catalog's way (``deg_s_rt_hz``, ``dps_rt_hz``,
    ``mdeg_per_s_rthz``, ``m_s2_rt_hz``); [] when it is not understood."""
    items: list[tuple[str, Fraction]] = []
    root = False
    for w in _words(text):
        if w == "per" and items:
            continue
        if w == "rt":
            if root:
                return []
            root = True
            continue
        power = 1
        if w not in UNIT_WORDS and w[-1:] in ("2", "3") and w[:-1] in UNIT_WORDS:
            w, power = w[:-1], int(w[-1])
        if w not in UNIT_WORDS:
            return []
        items.append((w, Fraction(power, 2 if root else 1) * (1 if not items else -1)))
        root = False
    if root or not items:
        return []
    out = []
    for choice in itertools.product(*(UNIT_WORDS[w] for w, _ in items)):
        si = 1.0
        dims = [Fraction(0)] * 5
        label = ""
        for (w, e), (factor, d, lab) in zip(items, choice):
            si *= factor ** float(e)
            dims = [a + e * b for a, b in zip(dims, d)]
            part = ("√" if e.denominator == 2 else "") + lab + {2: "²", 3: "³"}.get(abs(e.numerator), "")
            label += part if not label else "/" + part
        out.append(Reading(si, tuple(dims), label))  # type: ignore[arg-type]
    return out


def unit_token(label: str) -> str:
    """The unit label of the catalog's column table as its column names write it:
    ``deg/s/√Hz`` → ``deg_s_rt_hz``, ``µg`` → ``ug``, ``%`` → ``pct``, ``m/s²/√Hz`` → ``m_s2_rt_hz``."""
    return respell(label)


@dataclass(frozen=True)
class Column:
    """An accepted numeric column: its name, unit label and factor to the quantity's canonical unit."""

    name: str
    label: str
    to_canonical: float


def quantity_table(canonical: Mapping[str, tuple[str, float]],
                   alternatives: Mapping[str, tuple[str, object]],
                   alt_labels: Mapping[str, str]) -> dict[str, tuple[Column, ...]]:
    """Quantity → its accepted columns (canonical first), from the catalog's column table: the
    canonical columns with their unit (``PART_NUMERIC_COLUMNS``) and the alternative-unit columns
    with their conversion and label. A column name must end in its unit's token."""
    table: dict[str, list[Column]] = {}
    stem_of: dict[str, str] = {}
    for name, (label, _) in canonical.items():
        stem = _stem(name, label)
        stem_of[name] = stem
        table.setdefault(stem, []).append(Column(name, label, 1.0))
    for name, (canon, conv) in alternatives.items():
        stem = _stem(name, alt_labels[name])
        if stem != stem_of[canon]:
            raise ValueError(f"alternative column {name} is not a unit of {canon}'s quantity")
        table[stem].append(Column(name, alt_labels[name], float(conv(1.0))))
    return {k: tuple(v) for k, v in table.items()}


def _stem(name: str, label: str) -> str:
    token = unit_token(label)
    if not name.endswith("_" + token):
        raise ValueError(f"column {name} does not end in the token of its unit {label!r} ({token})")
    return name[: -len(token) - 1]


def _reading_of(stem: str, readings: list[Reading]) -> Reading | None:
    """The reading of a column's own unit meant for ``stem`` (a mass for ``mass_g``)."""
    mass = stem in _MASS_QUANTITIES
    return next((r for r in readings if (r.dims[3] != 0) == mass), readings[0] if readings else None)


@dataclass(frozen=True)
class Suggestion:
    """What an unknown header most likely meant. ``column``: a column to use as it stands (same
    unit, other spelling), None when none can be named without changing the unit; ``note``: text
    for the message (why none, or the factor to apply); ``expected``: the accepted columns."""

    column: str | None
    note: str = ""
    expected: str | None = None


def _split(key: str, stems) -> tuple[str, str] | None:
    """(quantity, unit text) of a respelt header: the longest quantity it starts with, else the
    quantity its first words are closest to (difflib ratio ≥ 0.85: ``gyro_arv`` → ``gyro_arw``)."""
    exact = [s for s in stems if key == s or key.startswith(s + "_")]
    if exact:
        s = max(exact, key=len)
        return s, key[len(s) + 1:]
    words = key.split("_")
    best, best_ratio = None, 0.0
    for n in range(1, len(words) + 1):
        head = "_".join(words[:n])
        for s in stems:
            r = difflib.SequenceMatcher(None, head, s).ratio()
            if r >= 0.85 and r >= best_ratio:  # a tie goes to the longer head
                best, best_ratio = (s, "_".join(words[n:])), r
    return best


def _factor_phrase(r: float) -> str:
    """How to turn a value into another unit: "divide by 1000", "multiply by 0.06"."""
    if r < 1.0:
        inv = 1.0 / r
        if abs(inv - round(inv)) <= 1e-9 * inv:
            return f"divide by {round(inv)}" if inv < 1e5 else f"divide by {inv:.4g}"
    return f"multiply by {r:.4g}"


def _columns_text(stem: str, cols: tuple[Column, ...]) -> str:
    return f"{stem} in a catalog unit: " + ", ".join(f"{c.name} ({c.label})" for c in cols)


def suggest(header: str, quantities: Mapping[str, tuple[Column, ...]]) -> Suggestion | None:
    """What a numeric header the catalog does not accept most likely meant, by unit (module
    docstring); None when its name is no quantity of the catalog (the caller may then guess among
    the text columns)."""
    key = respell(header)
    split = _split(key, quantities)
    if split is None:
        return None
    stem, unit_text = split
    cols = quantities[stem]
    expected = _columns_text(stem, cols)
    canon = cols[0]
    if not unit_text:
        return Suggestion(None, f"the name gives no unit: write {stem}_<unit>, the unit the figures "
                                f"are in ({', '.join(c.name for c in cols)})", expected)
    canon_reading = _reading_of(stem, read_unit(unit_token(canon.label)))
    readings = [r for r in read_unit(unit_text) if r.dims == canon_reading.dims]
    extra = ""
    if not readings and not read_unit(unit_text):
        # extra words after a unit (gyro_arw_deg_rt_h_typ): drop trailing words that are no unit
        words = unit_text.split("_")
        while words and words[-1] not in UNIT_WORDS and words[-1] not in UNIT_SHORTHAND:
            words.pop()
            if words:
                readings = [r for r in read_unit("_".join(words)) if r.dims == canon_reading.dims]
                if readings:
                    extra = unit_text[len("_".join(words)) + 1:]
                    break
    if not readings:
        seen = read_unit(unit_text)
        if seen:
            return Suggestion(None, f"{seen[0].label} is not a unit of {stem} (given in {canon.label} "
                                    "or an equivalent unit): check which unit the figures are in",
                              expected)
        close = difflib.get_close_matches(unit_text, [unit_token(c.label) for c in cols], n=1, cutoff=0.75)
        if close:
            col = next(c for c in cols if unit_token(c.label) == close[0])
            return Suggestion(None, f"unit {unit_text!r} not understood; if it is {col.label}, "
                                    f"use {col.name}", expected)
        return Suggestion(None, f"unit {unit_text!r} not understood", expected)
    factor = readings[0].si / canon_reading.si  # user unit → canonical unit
    label = readings[0].label
    dropped = f" ('{extra}' dropped)" if extra else ""
    for c in cols:
        if math.isclose(factor, c.to_canonical, rel_tol=1e-9):
            return Suggestion(c.name, f"the same unit, {label}{dropped}", expected)
    # no column in this unit: every accepted one with its factor, the roundest first
    ratios = [(c, factor / c.to_canonical) for c in cols]
    ratios.sort(key=lambda cr: (abs(math.log10(cr[1]) - round(math.log10(cr[1]))) > 1e-9,
                                abs(math.log10(cr[1]))))
    (first, r0), rest = ratios[0], ratios[1:]
    text = f"{label} is not a catalog unit: {_factor_phrase(r0)} and use {first.name}"
    if rest:
        text += " (or " + ", ".join(f"{_factor_phrase(r)} for {c.name}" for c, r in rest) + ")"
    return Suggestion(None, text + dropped, expected)
