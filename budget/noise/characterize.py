"""From a static IMU log or measured Allan tables to a catalog row (``PartSpec``).

Per channel: overlapping Allan deviation (or the measured table) → IEEE-952 fit
(:func:`~budget.noise.terms.fit_noise_terms`). Catalog row, datasheet units:

* ``gyro_arw_deg_rt_h`` = N·60 in deg/√h; ``gyro_rrw_deg_h_rt_h`` = K in deg/h/√h;
  ``gyro_bias_instability_deg_h`` = √(2 ln2/π)·B in deg/h — the Allan floor of the flicker term,
  i.e. convention ``adev_min`` (what vendors quote);
* ``accel_vrw_m_s_rt_h`` = N·60 in m/s/√h; ``accel_bias_instability_ug`` = √(2 ln2/π)·B in µg.

Axes are combined by the **worst axis** rule: each column takes the largest value over the
axes where the term was *resolved* (:func:`~budget.noise.terms.fit_noise_terms`). A term no axis
resolves leaves its column **empty** — the catalog's "not specified", which a Monte Carlo fills
from the grade or takes as 0 and says so (:mod:`budget.catalog.fill`) — whether the fit found
nothing or a value it cannot pin down: an unresolved RRW written as a figure (fitted 60.7
deg/h/√h, ± 29 %, on a record whose truth was 20) was simulated as if a datasheet gave it. What
was left empty, the value fitted and why are in :attr:`Characterization.left_empty`, the summary,
the JSON (``left_empty``) and the row's notes. A term not resolved gets its upper limit from the
curve (:func:`~budget.noise.terms.upper_limits`), in the column's unit, in the summary, the JSON
(``row_limits``, per channel ``limits``) and the row's notes ("RRW not resolved: ≤ X deg/h/√h at
95 %"); never as the column's value. Q and R have no catalog column; they are kept per channel.
Grade, unless given: the best grade of the catalog's grades table whose upper gyro bias and gyro
ARW limits both hold the row's values (gyros decide when present, otherwise the accelerometer
bias and noise limits).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
from pydantic import ValidationError
from scipy import stats

from .. import units as u
from ..catalog.schema import GRADES, PartSpec
from ..errors import GRADE_WAY, InputError, from_validation_error
from .allan import AllanResult, allan_deviation
from .logs import ImuLog
from .spikes import find_spikes
from .stationarity import check_stationarity, record_rows
from .terms import FLICKER, FLOOR_NAME, TERMS, NoiseTerms, fit_noise_terms

COMBINE_RULE = ("worst axis: each catalog column is the largest value over the axes where the "
                "term was resolved (none: left empty); bias instability as the Allan floor 0.664·B "
                "(adev_min)")
#: What an empty column of the row means downstream (:mod:`budget.catalog.fill`), said with the
#: columns :func:`characterize` leaves empty.
EMPTY_MEANING = ("an empty cell is the catalog's 'not specified': a Monte Carlo fills an empty ARW "
                 "or VRW from the grade's typical value and takes an empty in-run bias instability or "
                 "RRW as 0, and lists each")


@dataclass
class Characterization:
    """Result of :func:`characterize`: the catalog row and the per-channel fits (SI)."""

    part: PartSpec
    channels: dict[str, NoiseTerms]
    allan: dict[str, AllanResult]
    combine_rule: str = COMBINE_RULE
    notes: list[str] = field(default_factory=list)
    #: the fit options of :func:`characterize` (``taus``, ``terms``, ``model_error``, the given ``grade``)
    options: dict = field(default_factory=dict)
    #: findings that make the fit doubtful, one line each naming the channel (e.g. a log that is
    #: not one stationary regime: :func:`budget.noise.stationarity.check_stationarity`)
    warnings: list[str] = field(default_factory=list)
    #: what the log reader found and changed in the record fitted (timing jitter, a channel's
    #: implausible mean, rows dropped or values interpolated on request), one line each; empty
    #: for Allan tables
    log_findings: list[str] = field(default_factory=list)
    #: {catalog column: why it is empty} for each column some axis fitted a value for but no axis
    #: resolved: the value fitted (column unit), the axis, the limit (module doc)
    left_empty: dict[str, str] = field(default_factory=dict)

    def to_dict(self) -> dict:
        """``{"part": row fields, "channels": {ch: {Q, N, B, K, R}}, ..., "options": {...}}`` (SI
        channel units)."""
        return {"part": self.part.model_dump(mode="json"), "combine_rule": self.combine_rule,
                "channels": {ch: dict(t.values) for ch, t in self.channels.items()},
                "channel_units": {ch: t.unit for ch, t in self.channels.items()},
                "uncertainty": {ch: t.sigmas for ch, t in self.channels.items()},
                "resolved": {ch: t.resolved for ch, t in self.channels.items()},
                "limits": {ch: dict(t.limits or {}) for ch, t in self.channels.items()},
                "limit_level": {ch: t.limit_level for ch, t in self.channels.items()},
                "uncertainty_known": {ch: t.uncertainty_known for ch, t in self.channels.items()},
                "row_limits": {col: lim for col, (lim, _) in _column_limits(self.part, self.channels).items()},
                "left_empty": dict(self.left_empty),
                "notes": list(self.notes), "warnings": list(self.warnings),
                "log_findings": list(self.log_findings), "options": dict(self.options)}

    def to_frame(self) -> pd.DataFrame:
        rows = []
        for ch, t in self.channels.items():
            f = t.to_frame()
            f.insert(0, "channel", ch)
            rows.append(f)
        return pd.concat(rows, ignore_index=True) if rows else pd.DataFrame()

    def empty_fields_text(self) -> str | None:
        """One line naming the row's columns left empty because no axis resolved their term, the
        value fitted and what an empty cell means downstream; None when none was left empty."""
        if not self.left_empty:
            return None
        return ("left empty in the catalog row (not resolved): "
                + "; ".join(f"{col} — {why}" for col, why in self.left_empty.items())
                + f" — {EMPTY_MEANING}")

    def summary(self) -> str:
        p = self.part
        limits = _column_limits(p, self.channels)
        fitted = _fitted_unresolved(self.channels)

        def v(col, unit):  # 4 significant digits; a term not found or not resolved is said so,
            x = getattr(p, col)  # with the largest value the curve allows
            lim = f"≤ {limits[col][0]:.3g} {unit} {limits[col][1]}" if col in limits else ""
            if x is None and col in fitted:
                return (f"left empty (fitted {fitted[col][0]:.3g} {unit} on {fitted[col][1]}, not resolved"
                        + (f"; {lim}" if lim else "") + ")")
            if x is None:
                return f"not resolved ({lim})" if lim else "not found"
            return f"{x:.4g} {unit}" + (f", {lim}" if lim else "")

        rate = "rate not known" if p.rate_hz is None else f"rate {p.rate_hz:g} Hz"
        lines = [f"part {p.part_id} ({p.grade}), {rate}",
                 f"  gyro  ARW {v('gyro_arw_deg_rt_h', 'deg/√h')}, {FLOOR_NAME} "
                 f"{v('gyro_bias_instability_deg_h', 'deg/h')}, RRW {v('gyro_rrw_deg_h_rt_h', 'deg/h/√h')}",
                 f"  accel VRW {v('accel_vrw_m_s_rt_h', 'm/s/√h')}, {FLOOR_NAME} "
                 f"{v('accel_bias_instability_ug', 'µg')}",
                 f"  axes combined: {self.combine_rule}"]
        lines += [t.summary() for t in self.channels.values()]
        lines += [f"note: {n}" for n in self.notes]
        lines += [f"warning: {w}" for w in self.warnings]
        lines += [f"log: {f}" for f in self.log_findings]
        return "\n".join(lines)


#: A resolved bias instability whose flicker floor is at most this share of the fitted Allan
#: variance at every τ is "not shown as a floor" (:func:`_floor_not_shown_note`).
FLOOR_SHARE = 0.5


def _floor_not_shown_note(ch: str, t: NoiseTerms, r: AllanResult) -> str | None:
    """A note when B is resolved beside a rate random walk K but its floor 0.664·B carries less
    than :data:`FLOOR_SHARE` of the fitted Allan variance at every τ of the fit: the curve then
    never flattens to it, and B is read off its rounding between the white-noise and
    random-walk slopes, where B and a lower K trade against each other. Measured on records
    with white noise and a random walk only (ARW 0.15 deg/√h, RRW 10 deg/h/√h, 2 h at 50 Hz,
    40 seeds): B resolved on 4, each with a share of 0.29–0.42 and K 20–45 % low; a true floor
    of 1 deg/h (below that curve's 1.32 deg/h minimum) was resolved on 36/40, most with shares
    of 0.3–0.5 too: the note is a caution, not a verdict."""
    if not (t.resolved["B"] and t.values["K"] is not None and t.values["B"] is not None):
        return None
    lo, hi = t.tau_range_s
    tau = r.tau_s[(r.tau_s >= lo * (1 - 1e-9)) & (r.tau_s <= hi * (1 + 1e-9))]
    share = float(np.max(FLICKER * t.values["B"] ** 2 / t.model_adev(tau) ** 2))
    if share > FLOOR_SHARE:
        return None
    return (f"{ch}: the bias instability's floor is at most {share:.0%} of the fitted Allan variance "
            "at any τ: the curve never flattens to it, and B is read off its rounding between the "
            "white-noise and random-walk slopes, where B and a lower K trade against each other "
            "(a record without flicker noise can show this; K may be low)")


def _worst(values: list[float | None]) -> float | None:
    vals = [v for v in values if v is not None]
    return float(max(vals)) if vals else None


#: catalog column ← (sensor, IEEE-952 term) of :func:`_row_values`
_COLUMN_TERMS = {"gyro_arw_deg_rt_h": ("gyro", "N"), "gyro_bias_instability_deg_h": ("gyro", "B"),
                 "gyro_rrw_deg_h_rt_h": ("gyro", "K"), "accel_vrw_m_s_rt_h": ("accel", "N"),
                 "accel_bias_instability_ug": ("accel", "B")}


def _fitted_unresolved(fits: Mapping[str, NoiseTerms]) -> dict[str, tuple[float, str]]:
    """{catalog column: (largest value fitted, in the column's unit; its axis)} for each column
    whose term some axis fitted but no axis resolved: a number the record cannot pin down, left
    out of the row (module doc)."""
    out = {}
    for col, (sensor, term) in _COLUMN_TERMS.items():
        axes = {c: t for c, t in fits.items() if c.startswith(sensor) and t.values[term] is not None}
        if axes and not any(t.resolved[term] for t in axes.values()):
            ch = max(axes, key=lambda c: axes[c].values[term])
            out[col] = (float(_COLUMN_LIMITS[col][2](axes[ch].values[term])), ch)
    return out


def _unresolved_axes(fits: Mapping[str, NoiseTerms], row: Mapping[str, float | None]) -> list[str]:
    """Notes for the columns whose value comes from the axes that resolve the term while another
    axis fitted a larger value it does not resolve: that larger value is not the row's (the worst
    axis is taken over resolved terms); how large it may be is the limit of :func:`_limit_notes`."""
    out = []
    for col, (sensor, term) in _COLUMN_TERMS.items():
        value = row.get(col)
        if value is None:
            continue
        conv = _COLUMN_LIMITS[col][2]
        larger = [f"{c} ({float(conv(t.values[term])):.3g} {_COLUMN_LIMITS[col][1]})" for c, t in fits.items()
                  if c.startswith(sensor) and t.values[term] is not None and not t.resolved[term]
                  and float(conv(t.values[term])) > value]
        if larger:
            out.append(f"{col}: the worst axis that resolves it; a larger value fitted but not resolved on "
                       + ", ".join(larger) + " is not the row's")
    return out


#: catalog column → (its words in a note, the conversion of the term's SI limit to the column's unit)
_COLUMN_LIMITS = {
    "gyro_arw_deg_rt_h": ("ARW", "deg/√h", u.rad_s_rt_hz_to_deg_rt_h),
    "gyro_bias_instability_deg_h": (f"gyro {FLOOR_NAME}", "deg/h",
                                    lambda b: u.rad_s_to_deg_h(math.sqrt(FLICKER) * b)),
    "gyro_rrw_deg_h_rt_h": ("RRW", "deg/h/√h", u.rad_s_rt_s_to_deg_h_rt_h),
    "accel_vrw_m_s_rt_h": ("VRW", "m/s/√h", u.m_s2_rt_hz_to_m_s_rt_h),
    "accel_bias_instability_ug": (f"accel {FLOOR_NAME}", "µg",
                                  lambda b: u.m_s2_to_ug(math.sqrt(FLICKER) * b)),
}


def _column_limits(part: PartSpec, fits: Mapping[str, NoiseTerms]) -> dict[str, tuple[float, str]]:
    """{catalog column: (upper limit in the column's unit, its level in words)} for each column
    whose term some axis does not resolve and whose row value (resolved terms only) does not
    already exceed that axis's limit: the largest limit over those axes (the worst axis can be no
    larger). Levels differ only when a digitised curve is mixed with others (the loosest wording
    is kept)."""
    out = {}
    for col, (sensor, term) in _COLUMN_TERMS.items():
        axes = [t for c, t in fits.items() if c.startswith(sensor) and (t.limits or {}).get(term) is not None]
        if not axes:
            continue
        conv = _COLUMN_LIMITS[col][2]
        lim = max(float(conv(t.limits[term])) for t in axes)
        value = getattr(part, col)
        if value is not None and value >= lim:
            continue
        levels = {t.limit_level for t in axes}
        level = ("from the digitised curve's values, no confidence level" if None in levels
                 else f"at {100 * min(levels):.3g} %")
        out[col] = (lim, level)
    return out


def _limit_notes(part: PartSpec, fits: Mapping[str, NoiseTerms]) -> list[str]:
    """'RRW not resolved: ≤ 3.2 deg/h/√h at 95 %' for each column of :func:`_column_limits`."""
    return [f"{_COLUMN_LIMITS[col][0]} not resolved: ≤ {lim:.3g} {_COLUMN_LIMITS[col][1]} {level}"
            for col, (lim, level) in _column_limits(part, fits).items()]


def _row_values(fits: Mapping[str, NoiseTerms]) -> dict[str, float | None]:
    """{catalog column: the worst axis's value in the column's unit} over the axes that resolve
    the term (ARW/VRW = N, bias instability = its Allan floor 0.664·B, RRW = K); None when none
    does (module doc)."""
    out = {}
    for col, (sensor, term) in _COLUMN_TERMS.items():
        worst = _worst([t.values[term] for c, t in fits.items()
                        if c.startswith(sensor) and t.resolved[term]])
        out[col] = None if worst is None else float(_COLUMN_LIMITS[col][2](worst))
    return out


def infer_grade(row: Mapping[str, float | None]) -> str:
    """Best grade whose upper limits hold the measured values (rule in the module doc)."""
    from ..catalog.io import load_grades  # shipped grades table (seed 004 Tables 3–4)
    grades = sorted(load_grades().values(), key=lambda g: g.rank)
    gyro = row.get("gyro_bias_instability_deg_h"), row.get("gyro_arw_deg_rt_h")
    accel = row.get("accel_bias_instability_ug"), row.get("accel_vrw_m_s_rt_h")
    for g in grades:
        if any(v is not None for v in gyro):
            ok = ((gyro[0] is None or gyro[0] <= g.gyro_bias_deg_h_max)
                  and (gyro[1] is None or gyro[1] <= g.gyro_arw_deg_rt_h_max))
        else:
            ok = ((accel[0] is None or accel[0] <= g.accel_bias_ug_max)
                  and (accel[1] is None or u.m_s_rt_h_to_ug_rt_hz(accel[1]) <= g.accel_noise_ug_rt_hz_max))
        if ok:
            return g.grade
    return GRADES[-1]


#: Longest averaging time (s) below which a record is too short to show a bias-instability floor:
#: IEEE-952's flat Allan floor sits at τ ≈ 10–1000 s for tactical to navigation grades.
SHORT_RECORD_TAU_S = 10.0


def _short_record_warning(allan: Mapping[str, AllanResult], fits: Mapping[str, NoiseTerms]) -> str | None:
    """The warning for a record whose Allan deviation stops before :data:`SHORT_RECORD_TAU_S`
    (a log under about a minute): the terms whose signature lies beyond it — bias instability,
    rate random walk, rate ramp — are not measured by it."""
    tau_max = max(float(np.max(allan[ch].tau_s)) for ch in fits)
    if tau_max >= SHORT_RECORD_TAU_S:
        return None
    return (f"the record is short: its Allan deviation reaches τ = {tau_max:.3g} s only (below "
            f"{SHORT_RECORD_TAU_S:g} s): bias instability, rate random walk and rate ramp lie beyond what "
            "it measures (a value the row gives for them rests on the short τ alone); a static log of "
            "≥ 1 h measures them")


#: blocks whose means give the drift span named in a rate-ramp warning (~56 s on an hour)
DRIFT_BLOCKS = 64


def _drift_warning(ch: str, t: NoiseTerms, x: np.ndarray | None, rate_hz: float | None) -> str:
    """The warning for a channel whose Allan fit resolves a rate ramp R (IEEE-952 σ² = R²τ²/2).

    A resolved ramp is a deterministic drift over the record — a warm-up, a temperature change,
    a record that was not static — not a sensor noise term: R has no catalog column and it
    takes the long-τ Allan points that would otherwise fix K and B, so those are doubtful on this
    channel. The warning gives R in datasheet units per hour and, for a log, the span of the
    means of :data:`DRIFT_BLOCKS` blocks (what the drift did over the record, whatever its shape).
    """
    gyro = ch.startswith("gyro")
    conv, unit = (u.rad_s_to_deg_h, "deg/h") if gyro else (u.m_s2_to_ug, "µg")
    sigma = t.sigmas.get("R")  # None for a digitised curve: no record, no uncertainty to quote
    text = (f"rate ramp resolved: R = {conv(t.values['R'] * u.HOUR):.3g} {unit} per hour "
            + (f"(± {conv(sigma * u.HOUR):.2g})" if sigma is not None and math.isfinite(sigma)
               else "(uncertainty unknown: digitised curve)" if not t.uncertainty_known
               else "(uncertainty not computed)"))
    if x is not None and rate_hz and x.size >= 2 * DRIFT_BLOCKS:
        m = x[: x.size // DRIFT_BLOCKS * DRIFT_BLOCKS].reshape(DRIFT_BLOCKS, -1).mean(axis=1)
        text += (f"; the {x.size / rate_hz / DRIFT_BLOCKS:.3g}-s block means span "
                 f"{conv(np.ptp(m)):.3g} {unit} over the record")
    return (f"{ch}: {text} — a drift (warm-up, temperature, motion), not a noise term; no catalog "
            "column holds it, and this channel's long-τ terms (K, B) are doubtful")


#: A fit whose χ² has a p-value below this does not describe its Allan curve (a warning).
MISFIT_P = 1e-6


def _misfit_warning(ch: str, t: NoiseTerms, a: AllanResult, model_error: float) -> str | None:
    """The warning for a channel whose IEEE-952 fit the Allan curve rejects: χ² (the fit's own,
    weights 1/var(σ̂²) = 1/(σ⁴(2/edf + ε²))) beyond its χ²_dof quantile at p = :data:`MISFIT_P`.
    Names the τ of the largest standardised residual and the measured/fitted Allan deviation
    there: a tone, vibration, output filter or other effect outside Q, N, B, K, R that the
    fitted terms absorb (a 1.7× VRW from a tone, a bias instability from a slow cycle)."""
    if t.dof <= 0 or not stats.chi2.sf(t.chi2, t.dof) < MISFIT_P:
        return None
    tau, lo, hi = np.asarray(a.tau_s), t.tau_range_s[0] * (1 - 1e-9), t.tau_range_s[1] * (1 + 1e-9)
    sel = (tau >= lo) & (tau <= hi) & np.isfinite(a.adev) & (a.adev > 0) & (a.edf > 0)
    m2 = t.model_adev(tau[sel]) ** 2
    z = (a.adev[sel] ** 2 - m2) / (m2 * np.sqrt(2.0 / a.edf[sel] + model_error ** 2))
    k = int(np.argmax(np.abs(z)))
    ratio = a.adev[sel][k] / math.sqrt(m2[k])
    return (f"{ch}: the IEEE-952 terms do not describe its Allan curve (χ²/dof = {t.chi2:.3g}/{t.dof}): "
            f"measured {ratio:.3g}× the fit at τ = {tau[sel][k]:.3g} s (z = {z[k]:+.1f}) — a tone, "
            "vibration, output filter or other effect outside Q, N, B, K, R, which the fitted terms "
            "absorb; the model-gap workflow (sar-budget gap) can name it")


def characterize(data: ImuLog | Mapping[str, AllanResult], *, part_id: str = "measured",
                 grade: str | None = None, vendor: str = "", model: str = "",
                 source: str | None = None, taus="octave", terms=TERMS,
                 model_error: float = 0.05, keep_spikes: bool = False) -> Characterization:
    """Characterise a static log (:class:`ImuLog`) or Allan tables (``{channel: AllanResult}``).

    Constant channels and channels whose fit fails are skipped with a note. ``grade`` defaults
    to :func:`infer_grade`; ``source`` to a description of the input. Isolated spikes of a log
    that would decide its short-τ Allan deviation are replaced before the fit unless
    ``keep_spikes`` (:mod:`budget.noise.spikes`); every spike found is named in ``warnings``.
    """
    notes: list[str] = []
    regimes = []  # findings of the stationarity check (a log only)
    spike_warnings: list[str] = []
    replaced: list[str] = []  # channels whose spikes were replaced
    series: dict[str, np.ndarray] = {}  # the (spike-repaired) record of each channel fitted
    if isinstance(data, ImuLog):
        allan = {}
        repaired = bool(data.issues.repairs)
        regimes = check_stationarity(data.channels, repaired=repaired)
        for ch, x in data.channels.items():
            if np.ptp(x) == 0:
                notes.append(f"{ch}: constant channel skipped")
                continue
            unit = u.channel_si_unit(ch)
            x, spikes = find_spikes(x, ch, replace=not keep_spikes)
            if spikes is not None:
                if spikes.replaced:
                    replaced.append(ch)
                spike_warnings.append(f"{ch}: " + spikes.message(record_rows(repaired), unit))
            allan[ch] = allan_deviation(x, data.rate_hz, taus, channel=ch, unit=unit)
            series[ch] = x
        rate, origin = data.rate_hz, f"log {Path(data.source).name}"
        notes += [f"log repaired: {r}" for r in data.issues.repairs]
        notes += [f"log: {i.text()}" for i in data.issues.issues if i.severity == "info"]  # e.g. columns not read
    elif isinstance(data, Mapping) and all(isinstance(v, AllanResult) for v in data.values()):
        allan = dict(data)
        rates = {r.rate_hz for r in allan.values() if r.samples}  # a digitised curve has none
        rate = rates.pop() if len(rates) == 1 else None
        origin = ", ".join(sorted({r.source for r in allan.values()}))
    else:
        raise InputError("characterize() needs an ImuLog or a {channel: AllanResult} mapping",
                         value=type(data).__name__)
    if isinstance(data, ImuLog):
        src = data.source
    else:  # the Allan table(s) the curves came from
        src = ", ".join(sorted({str(r.source).removeprefix("table ") for r in allan.values()
                                if str(r.source).startswith("table ")})) or None
    if not allan:
        raise InputError("no channel with noise to characterise: every channel is constant (stuck "
                         "or unused sensor)" if isinstance(data, ImuLog) else
                         "no channel with noise to characterise", file=src,
                         expected="a static IMU log with noise on at least one channel")
    fits: dict[str, NoiseTerms] = {}
    for ch, r in allan.items():
        try:
            fits[ch] = fit_noise_terms(r, terms, model_error=model_error)
        except InputError as err:
            notes.append(f"{ch}: not fitted ({err})")
    if not fits:
        raise InputError("no channel could be fitted: " + "; ".join(notes), file=src)
    for ch, t in fits.items():
        if not t.uncertainty_known:
            notes.append(f"{ch}: digitised curve (no record behind it): the fitted values' uncertainty "
                         f"is unknown; a term is resolved when it stands out of the {model_error:.0%} model-error "
                         "floor over an octave of τ, and limits are read off the curve's values")
        weak = [k for k in TERMS if t.values[k] is not None and not t.resolved[k]]
        if weak:
            notes.append(f"{ch}: {', '.join(weak)} fitted but not resolved (its variance "
                         "coefficient, the value squared, within 2σ of 0, or above the curve's "
                         "uncertainty over less than an octave of τ)")
        if (floor := _floor_not_shown_note(ch, t, allan[ch])):
            notes.append(floor)
        lims = [f"{k} {t.limit_text(k)}" for k in TERMS if (t.limits or {}).get(k) is not None]
        if lims:
            notes.append(f"{ch}: not resolved, largest values the curve allows: " + "; ".join(lims))
        extra = [f"{k}={t.values[k]:.3g} {ch_unit}" for k, ch_unit in
                 (("Q", t.unit + "·s"), ("R", t.unit + "/s")) if t.values[k] is not None]
        if extra:
            notes.append(f"{ch}: {', '.join(extra)} (no catalog column)")
    drifting = [ch for ch, t in fits.items() if t.values["R"] is not None and t.resolved["R"]]
    drift_warnings = [_drift_warning(ch, fits[ch], series.get(ch), rate) for ch in drifting]
    misfit_warnings = [w for ch, t in fits.items() if (w := _misfit_warning(ch, t, allan[ch], model_error))]
    values = _row_values(fits)
    given_grade = grade
    short = _short_record_warning(allan, fits)
    if grade is None:
        try:
            grade = infer_grade(values)
        except InputError as err:
            raise InputError(f"cannot infer the grade ({err})", field="grade",
                             expected=GRADE_WAY.cli) from None
        notes.append(f"grade {grade} inferred from the grades table")
        if short and values.get("gyro_bias_instability_deg_h") is None \
                and values.get("accel_bias_instability_ug") is None:
            short += f"; the grade ({grade}) is inferred from the white-noise terms alone"
    misfit_warnings += [short] if short else []
    text = source or f"measured: {origin}, IEEE-952 Allan-variance fit"
    row_notes = f"axes combined by {COMBINE_RULE}"
    left_empty = {col: (f"fitted {v:.3g} {_COLUMN_LIMITS[col][1]} on {ch} but not resolved (variance "
                        "coefficient within 2σ of 0, or above the curve's uncertainty over less than an "
                        "octave of τ): the record cannot pin it down")
                  for col, (v, ch) in _fitted_unresolved(fits).items()}
    for col, why in left_empty.items():
        notes.append(f"{col} left empty: {why}")
        row_notes += f"; {col} left empty: {why}"
    for partial in _unresolved_axes(fits, values):
        notes.append(partial)
        row_notes += f"; {partial}"
    probe = PartSpec.model_construct(**values)  # the row's values, for the limits to compare with
    limit_notes = _limit_notes(probe, fits)
    notes += limit_notes
    row_notes += "".join(f"; {n}" for n in limit_notes)
    digitised = [ch for ch, t in fits.items() if not t.uncertainty_known]
    if digitised:
        row_notes += ("; fitted to a digitised curve (" + ", ".join(digitised)
                      + "): no record behind it, the values' uncertainty is unknown")
    if regimes:
        row_notes += ("; measured on a log that may not be one stationary regime: "
                      + ", ".join(f"{i.column} {i.kind.replace('_', ' ')}" for i in regimes))
    if drifting:
        row_notes += ("; a rate ramp (drift, not noise) resolved on " + ", ".join(drifting)
                      + ": its long-τ terms are doubtful")
    if replaced:
        row_notes += "; isolated spikes replaced before the fit on " + ", ".join(replaced)
    log_findings = log_findings_of(data) if isinstance(data, ImuLog) else []
    if isinstance(data, ImuLog) and data.issues.repairs:
        row_notes += f"; log repaired before the fit ({len(data.issues.repairs)} repair(s))"
    try:
        part = PartSpec(part_id=part_id, vendor=vendor, model=model, grade=grade, rate_hz=rate,
                        source=text, bias_instability_convention="adev_min",
                        notes=row_notes, **values)
    except ValidationError as err:
        e = from_validation_error(err)
        raise InputError(f"the values fitted to {origin} do not make a catalog row: {e.reason}",
                         field=e.field, value=e.value, expected=e.expected) from None
    options = {"taus": taus if isinstance(taus, str) else np.asarray(taus, float).tolist(),
               "terms": list(terms), "model_error": float(model_error), "grade": given_grade,
               "keep_spikes": bool(keep_spikes)}
    return Characterization(part, fits, allan, COMBINE_RULE, notes, options,
                            spike_warnings + [f"{i.column}: {i.message}" for i in regimes]
                            + drift_warnings + misfit_warnings, log_findings, left_empty)


def log_findings_of(log: ImuLog) -> list[str]:
    """The reader's warnings about ``log`` and the repairs it made, one line each — what a
    result fitted to the log must carry (errors were refused or repaired; notes are not findings)."""
    return ([i.text().removeprefix("warning: ") for i in log.issues.issues if i.severity == "warning"]
            + [f"log repaired: {r}" for r in log.issues.repairs])
