"""Measured Allan-deviation tables (published curves) as a second input form.

CSV columns ``channel, tau_s, adev[, lci, uci]``; the unit rides on the channel name like a log
column (``gyro_x_dps``, ``gyro_x_rps``, ``accel_x_mps2``, ``accel_x_g`` …). The record's
sampling rate and length are not in the table and are given (``rate_hz``, ``samples``) for a
curve computed from a record: they fix the averaging factor m = τ·rate of each row and, with no
``lci/uci``, the EDF.

Given neither, the table is read as a *digitised curve* (a datasheet figure: a handful of
log-spaced points, τ multiples of no sample period, no record known): τ is taken as given, the
EDF comes from ``lci``/``uci`` when the table has them and is otherwise unknown (``edf`` = ∞,
``lo``/``hi`` NaN: no sample-count-based confidence bounds, the fit's uncertainty unknown), and
a note says so; ``rate_hz`` is NaN and ``samples`` 0 in the result.

With ``lci``/``uci`` the EDF of each row is recovered by inverting the χ² interval at
``ci_level`` (default 0.95, the level of the published curves the tests use), see
:func:`edf_from_interval` (a non-positive ``lci`` is accepted: symmetric Gaussian intervals
from some tools go below zero at long τ). Without them it comes from
:func:`~budget.noise.allan.edf_simple` with the noise type taken from the slope, and the
interval is computed at ``ci_level``. Values are converted to SI (rad/s, m/s²).

τ taken from measured time stamps is rarely a whole number of samples: within
``TAU_TOLERANCE`` (15 %) of one, τ is set to the nearest whole m/rate and the ADEV (and its
bounds) moved along the curve's local log-log slope, ADEV·(m/(τ·rate))^slope, and the result
carries a note saying so (``AllanResult.notes``); farther off is an error (wrong ``rate_hz``; the
message adds that a digitised curve is read without a rate and record length).

Files other tools write are read as they are: delimited by ``,``, ``;`` or a tab (the one that
splits the header into a τ column), ``#`` comment lines before the header (rows in messages are
the file's lines), quoted header names, trailing delimiters, τ in ms or µs (``tau_ms``,
``tau_us``), compressed under any name (gzip, bzip2, xz, zip found by content), UTF-8 with or
without a byte-order mark or UTF-16/32 with one (:func:`budget.fileio.text_encoding`, as for
logs). A decimal comma is refused with its row and said to be one. The ADEV column may be named
``sigma`` (datasheets: ``tau (s), sigma (deg/h)``), ``oadev`` or ``Allan deviation``; a variance
column (``avar``, ``allan_variance``, ``sigma^2``, MATLAB's ``allanvar`` output) is read as a
variance. allantools' ``oadev`` saved with pandas (``,taus,adev,adev_err,n``) is read: the row
index pandas writes first is dropped, ``adev_err`` (adev/√n) is not used for the interval (a note
says so), and ``n`` must agree with ``samples`` (n = samples + 1 − 2m at the shortest τ).

Units written in brackets after a header name are read through :mod:`budget.units`: ``tau [s]``,
``tau (ms)``; ``adev (deg/h)`` (with ``lci``/``uci`` in the same unit, an ``avar`` as its square,
``avar [(deg/h)^2]``) for channels named without a unit (``gyro_z``); ``gyro_x [deg/s]`` as a
channel of the wide layout. A unit in brackets that disagrees with the channel's own
(``gyro_z_dps`` under ``adev [deg/h]``) is refused, and an unknown one is an error listing the
accepted units. A table of one curve without a channel column (``tau_s, adev``) is read as the
channel the caller names (``channels=["gyro_z"]``, ``--channels gyro_z``), refused with how to
name it otherwise.
"""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import optimize, stats

from .. import units as u
from ..errors import DIGITISED_WAY, TABLE_RATE_WAY, InputError
from ..fileio import read_text, require_file
from .allan import AllanResult, confidence_interval, edf_simple, noise_type_from_slope
from .adev_columns import (canonical, channel_unit, is_row_index, long_layout, table_header, tau_to_seconds,
                           value_column, value_unit)
from .logs import decimal_comma

REQUIRED = ("channel", "tau_s", "adev")
#: Largest relative distance of τ·rate from a whole number of samples that is accepted (tools
#: that take τ from measured time stamps write τ·rate = 0.999999, 1.04, 1.10 …).
TAU_TOLERANCE = 0.15
OPTIONAL = ("lci", "uci")


#: What a table's ``adev_err`` column (allantools: adev/√n) is left for, said once per channel.
ERR_NOTE = ("column adev_err not used: it is adev/√n (n overlapping differences taken as independent, "
            "far too small at long τ); the confidence interval comes from the record length and the "
            "curve's slope (EDF), as for a table without lci/uci")
#: Largest relative difference between ``--samples`` and the record length a table's ``n`` column
#: implies (n = samples + 1 − 2m for the overlapping ADEV of a rate record, at the shortest τ).
PAIRS_TOLERANCE = 0.01


def _pairs_check(n: np.ndarray, m: np.ndarray, samples: int, rows: np.ndarray, path: Path) -> None:
    """Refuse a ``samples`` the table's own ``n`` column contradicts: at the shortest τ (m samples)
    the overlapping ADEV of N rate samples averages n = N + 1 − 2m differences (allantools' ``n``;
    the non-overlapping ADEV's N/m − 1 agrees there within a sample), so N = n + 2m − 1. The EDF
    and the confidence intervals of every row follow from N."""
    bad = np.flatnonzero(~np.isfinite(n) | (n < 1))
    if bad.size:
        i = int(bad[0])
        raise InputError("not a positive count", file=path, row=int(rows[i]) + 2, field="n", value=n[i],
                         expected="the number of differences averaged at this τ (allantools' n)")
    implied = int(round(n[0] + 2 * m[0] - 1))
    if abs(implied - samples) > max(2.0, PAIRS_TOLERANCE * samples):
        raise InputError(f"the table's n = {n[0]:.10g} at m = {int(m[0])} says the record had {implied} "
                         f"samples, not the {samples} given", file=path, row=int(rows[0]) + 2, field="n",
                         value=n[0], expected=f"--samples {implied} (the record the curve came from)")


def edf_from_interval(adev: np.ndarray, lo: np.ndarray, hi: np.ndarray, ci_level: float) -> np.ndarray:
    """Degrees of freedom ν behind an interval at ``ci_level``.

    ``lo > 0``: the ν whose χ² interval has the ratio hi/lo. ``lo ≤ 0`` (a symmetric Gaussian
    interval adev ± z·s, as some published curves give at long τ): ν = z²/(2h²) with
    h = (hi − lo)/(2·adev), since the relative standard deviation of σ̂ is ≈ 1/√(2ν).
    """
    qa, qb = 0.5 + ci_level / 2, 0.5 - ci_level / 2
    z = stats.norm.ppf(qa)
    out = np.empty(lo.size)
    for i, (a, b) in enumerate(zip(lo, hi)):
        if a <= 0:
            out[i] = max(0.2, z ** 2 / (2 * ((b - a) / (2 * adev[i])) ** 2))
            continue
        target = math.log((b / a) ** 2)
        f = lambda nu: math.log(stats.chi2.ppf(qa, nu) / stats.chi2.ppf(qb, nu)) - target
        if f(1e9) >= 0:
            out[i] = 1e9
        elif f(0.2) <= 0:
            out[i] = 0.2
        else:
            out[i] = optimize.brentq(f, 0.2, 1e9, rtol=1e-10)
    return out


def read_adev_table(path: str | Path, rate_hz: float | None = None, samples: int | None = None, *,
                    ci_level: float = 0.95, channels=None) -> dict[str, AllanResult]:
    """Read a measured Allan-deviation table → ``{'gyro_x': AllanResult, …}`` in SI units.

    ``rate_hz`` and ``samples``: the record the curve was computed from; neither → a digitised
    curve (module doc). ``channels``: the channel (one, e.g. ``["gyro_z"]``) whose curve a table
    without a channel column (``tau_s, adev [deg/h]``) holds; a table that names its channels
    keeps them all (the caller picks)."""
    path = Path(path)
    require_file(path)
    digitised = rate_hz is None and samples is None  # no record behind the curve
    if not digitised and not (isinstance(rate_hz, (int, float)) and math.isfinite(rate_hz) and rate_hz > 0):
        raise InputError("sampling rate of the record is required", field="rate_hz", value=rate_hz,
                         expected=f"{TABLE_RATE_WAY.cli} > 0 (the rate of the data the curve came from), "
                                  f"with --samples; neither for a digitised datasheet curve")
    if not digitised and not (isinstance(samples, (int, np.integer)) and samples >= 3):
        raise InputError("record length is required", field="samples", value=samples,
                         expected="--samples N ≥ 3 (number of samples behind the curve), with "
                                  f"{TABLE_RATE_WAY.cli}; neither for a digitised datasheet curve")
    if not 0 < ci_level < 1:
        raise InputError("confidence level must be in (0, 1)", field="ci_level", value=ci_level)
    delim, pre = table_header(path) or (",", 0)
    try:
        df = pd.read_csv(io.StringIO(read_text(path, wide=True)), sep=delim, skiprows=pre, skipinitialspace=True,
                         dtype={"channel": str}, comment="#")
    except pd.errors.ParserError as err:
        raise InputError(f"malformed CSV: {str(err).split('C error: ')[-1]}", file=path) from None
    df.columns = [str(c).strip().strip("\"'") for c in df.columns]
    # trailing delimiters (``1,2,3,``) make unnamed empty columns: they hold nothing
    df = df.drop(columns=[c for c in df.columns if c.startswith("Unnamed:") and df[c].isna().all()])
    if len(df.columns) and is_row_index(df, df.columns[0]):  # pandas' to_csv writes its index first
        df = df.drop(columns=[df.columns[0]])
    tau_factor = tau_to_seconds(df.columns, path, 1 + pre)
    written, written_col = value_unit(df.columns, path, 1 + pre)
    value_col = value_column(df.columns)  # as the file names it, for a refusal
    wanted = None if channels is None else [str(c).strip() for c in channels]
    has_channel_column = any(canonical(c) == "channel" for c in df.columns)
    df, file_rows, wide = long_layout(df, path, header_row=1 + pre, channels=wanted)
    file_rows = file_rows + pre
    has_ci = "lci" in df.columns or "uci" in df.columns
    if has_ci and not ("lci" in df.columns and "uci" in df.columns):
        raise InputError("lci and uci must be given together", file=path, row=1 + pre)
    num_cols = ["tau_s", "adev"] + (["lci", "uci"] if has_ci else [])
    for col in num_cols:
        vals = pd.to_numeric(df[col], errors="coerce")
        v = vals.to_numpy(float)
        bad = np.flatnonzero(~np.isfinite(v) | ((v <= 0) if col != "lci" else False))
        if bad.size:
            i = int(bad[0])
            comma = decimal_comma(df[col].iloc[i])
            raise InputError("not a positive finite number" if col != "lci" else "not a number",
                             file=path, row=int(file_rows[i]) + 2,
                             field=df["channel"].iloc[i] if wide and col == "adev" else col, value=df[col].iloc[i],
                             expected="a number with a decimal point (0.01), not a decimal comma" if comma else None)
        df[col] = vals.astype(float) * (tau_factor if col == "tau_s" else 1.0)
    if df.empty:
        raise InputError("no rows after the header", file=path)
    out: dict[str, AllanResult] = {}
    for name in dict.fromkeys(df["channel"]):
        pos = np.flatnonzero((df["channel"] == name).to_numpy())
        rows = file_rows[pos]
        ch, unit = channel_unit(name, None if wide else written, written_col, path, int(rows[0]) + 2,
                                 1 + pre, named=not has_channel_column, value_col=value_col)
        if ch in out:
            raise InputError(f"channel {ch} appears under two unit tags", file=path,
                             row=int(rows[0]) + 2, field="channel", value=name)
        if digitised:
            out[ch] = _digitised(df.iloc[pos], rows, ch, unit, has_ci, ci_level, path)
        else:
            out[ch] = _channel(df.iloc[pos], rows, ch, unit, rate_hz, samples, has_ci, ci_level, path)
    return out


#: What a digitised curve's result says (no record behind it).
DIGITISED_NOTE = (f"read as a digitised curve ({DIGITISED_WAY.cli}: no record known): τ taken as "
                  "given, no confidence bounds from a sample count")


def _curve(df: pd.DataFrame, rows: np.ndarray, path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(τ, adev) of one channel's rows, τ strictly increasing (else refused naming the row)."""
    tau = df["tau_s"].to_numpy(float)
    adev = df["adev"].to_numpy(float)
    if np.any(np.diff(tau) <= 0):
        i = int(np.flatnonzero(np.diff(tau) <= 0)[0]) + 1
        raise InputError("τ must increase within a channel", file=path, row=int(rows[i]) + 2,
                         field="tau_s", value=tau[i])
    return tau, adev


def _digitised(df: pd.DataFrame, rows: np.ndarray, ch: str, unit: str, has_ci: bool,
               ci_level: float, path: Path) -> AllanResult:
    """A digitised curve's channel: τ as given; EDF from ``lci``/``uci`` or unknown (∞)."""
    tau, adev = _curve(df, rows, path)
    factor = u.CHANNEL_UNIT_TO_SI[unit]
    alpha = noise_type_from_slope(tau, adev)
    if has_ci:
        lo, hi = df["lci"].to_numpy(float), df["uci"].to_numpy(float)
        bad = np.flatnonzero((lo > adev) | (hi < adev) | (lo >= hi))
        if bad.size:
            i = int(bad[0])
            raise InputError("need lci ≤ adev ≤ uci and lci < uci", file=path, row=int(rows[i]) + 2,
                             field="lci", value=(lo[i], adev[i], hi[i]))
        edf = edf_from_interval(adev, lo, hi, ci_level)
        note = f"{ch}: {DIGITISED_NOTE}; the EDF of each point from its lci/uci at {ci_level:.3g}"
        ci = ci_level
    else:
        edf = np.full(tau.shape, np.inf)
        lo = hi = np.full(tau.shape, np.nan)
        note = (f"{ch}: {DIGITISED_NOTE} (nor lci/uci): the fitted values' uncertainty is unknown and "
                "a term's upper limit is read off the curve's own values")
        ci = math.nan
    notes = (note,) + ((f"{ch}: {ERR_NOTE}",) if "adev_err" in df.columns else ())
    return AllanResult(tau, adev * factor, lo * factor, hi * factor, edf, np.zeros(tau.size, np.int64),
                       math.nan, 0, ch, u.channel_si_unit(ch), ci, alpha, f"table {path.name}", notes)


def _channel(df: pd.DataFrame, rows: np.ndarray, ch: str, unit: str, rate_hz: float,
             samples: int, has_ci: bool, ci_level: float, path: Path) -> AllanResult:
    tau, adev = _curve(df, rows, path)
    m_raw = tau * rate_hz
    m = np.maximum(np.rint(m_raw), 1.0)
    rel = np.abs(m_raw - m) / m
    off = np.flatnonzero(rel > TAU_TOLERANCE)
    if off.size:
        i = int(off[0])
        raise InputError(f"τ·rate = {m_raw[i]:.6g} is not a whole number of samples", file=path,
                         row=int(rows[i]) + 2, field="tau_s", value=tau[i],
                         expected=f"τ within {TAU_TOLERANCE:.0%} of a multiple of 1/rate = "
                                  f"{1 / rate_hz:.6g} s (check {TABLE_RATE_WAY.cli}; a digitised "
                                  "datasheet curve is read without a rate and record length)")
    # τ from a clock of another rate: every short-τ row off by the same fraction (measured time
    # stamps scatter row by row instead); at long τ the same error rounds to another whole m
    short = np.flatnonzero(m <= 8)
    signed = (m_raw - m) / m
    if short.size >= 3:
        r = signed[short]
        if np.all(np.abs(r) > 0.02) and np.all(np.sign(r) == np.sign(r[0])) and np.ptp(r) < 0.2 * np.abs(r).mean():
            raise InputError(f"τ·rate is {100 * r.mean():+.1f} % off a whole number of samples on every short-τ row "
                             "alike: the curve's rate is not the one given", file=path, row=int(rows[short[0]]) + 2,
                             field="tau_s", value=tau[short[0]],
                             expected=f"{TABLE_RATE_WAY.cli} the curve came from (about {rate_hz / (1 + r.mean()):.6g} Hz?)")
    same = np.flatnonzero(np.diff(m) <= 0)
    if same.size:
        i = int(same[0]) + 1
        raise InputError(f"two τ rows round to the same number of samples m = {int(m[i])}",
                         file=path, row=int(rows[i]) + 2, field="tau_s", value=tau[i],
                         expected=f"one row per whole multiple of 1/rate = {1 / rate_hz:.6g} s")
    notes: tuple[str, ...] = ()
    if np.any(rel > 1e-6):
        slope = np.gradient(np.log(adev), np.log(tau)) if tau.size > 1 else np.zeros(1)
        shift = (m / m_raw) ** slope
        adev = adev * shift
        if has_ci:
            df = df.assign(lci=df["lci"].to_numpy(float) * shift, uci=df["uci"].to_numpy(float) * shift)
        tau = m / rate_hz
        k = int(np.count_nonzero(rel > 1e-6))
        notes = (f"{ch}: τ·rate is not a whole number of samples on {k} row(s) (up to "
                 f"{rel.max():.2%}, τ from measured time stamps?); τ set to the nearest whole "
                 f"number of samples and the ADEV moved along the curve's local slope (by up to "
                 f"{np.max(np.abs(shift - 1)):.2%})",)
    m = np.rint(m).astype(np.int64)
    if "n" in df.columns:
        _pairs_check(pd.to_numeric(df["n"], errors="coerce").to_numpy(float), m, samples, rows, path)
    if "adev_err" in df.columns:
        notes += (f"{ch}: {ERR_NOTE}",)
    n_phase = samples + 1
    too_long = np.flatnonzero(n_phase - 2 * m < 2)
    if too_long.size:
        i = int(too_long[0])
        raise InputError("τ longer than half the record", file=path, row=int(rows[i]) + 2,
                         field="tau_s", value=tau[i],
                         expected=f"τ ≤ {(n_phase - 2) // 2 / rate_hz:.6g} s for a record of {samples} samples")
    factor = u.CHANNEL_UNIT_TO_SI[unit]
    si_unit = u.channel_si_unit(ch)
    alpha = noise_type_from_slope(tau, adev)
    if has_ci:
        lo, hi = df["lci"].to_numpy(float), df["uci"].to_numpy(float)
        bad = np.flatnonzero((lo > adev) | (hi < adev) | (lo >= hi))  # lo ≤ 0 allowed
        if bad.size:
            i = int(bad[0])
            raise InputError("need lci ≤ adev ≤ uci and lci < uci", file=path, row=int(rows[i]) + 2,
                             field="lci", value=(lo[i], adev[i], hi[i]))
        edf = edf_from_interval(adev, lo, hi, ci_level)
    else:
        edf = edf_simple(n_phase, m, alpha)
        lo, hi = confidence_interval(adev, edf, ci_level)
    return AllanResult(tau, adev * factor, lo * factor, hi * factor, edf,
                       (n_phase - 2 * m).astype(np.int64), float(rate_hz), int(samples), ch,
                       si_unit, ci_level, alpha, f"table {path.name}", notes)
