"""The two inputs of the workflow — a measurement and a model — checked against each other.

Measurement: an IMU log (CSV path or :class:`~budget.noise.ImuLog`, channels in SI) or a
measured Allan-deviation table (CSV ``channel, tau_s, adev[, lci, uci]`` with the record's
``rate_hz`` and ``samples``, or ``{channel: AllanResult}``; a one-curve table ``tau_s, adev [deg/h]``
without a channel column is read as the one channel ``channels`` names). Model: a
:class:`~budget.imu.NoiseModel`, a catalog :class:`~budget.catalog.schema.PartSpec`, a catalog
``part_id`` or a MODEL.json/.yaml path.

Rules (each violation is an :class:`~budget.errors.InputError`):

* every compared channel must be in the measurement (default: the channels the measurement
  has — a single-gyro log is compared on that gyro, with a note);
* the rates must agree within 0.1 %: a model's ``rate_hz`` is the rate it describes. A catalog
  part's ``rate_hz`` is the sensor's output rate, so a log recorded at a *lower* rate (output
  decimated by the logger) is accepted with a note — the noise densities do not depend on the
  rate — and a higher one is an error;
* the log must be long enough: ≥ 4096 samples, and its Allan deviation must reach the τ where
  the model's white noise meets its bias-instability floor, (N/(0.664·B))², on every compared
  channel (else the model's floor cannot be tested); ``check_tau_range=False`` skips the latter;
* a model with a temperature effect needs a log with a temperature channel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..catalog.schema import FLICKER_FLOOR
from ..errors import GAP_CHANNELS_WAY, GAP_RECORD_WAY, GAP_TAU_CHECK_WAY, InputError
from ..imu import NoiseModel
from ..imu.registry import DETERMINISTIC_EFFECTS, TEMPERATURE_EFFECTS
from ..imu.resolve import resolve_noise_model
from .. import units as u
from ..units import channel_si_unit
from ..noise import ImuLog
from ..noise.allan import AllanResult
from ..noise.log_checks import LogReport
from ..noise.measurement import read_measurement
from ..noise.stationarity import check_stationarity
from ..units import CHANNELS
from .signatures import MIN_SAMPLES, SignatureGrid

RATE_TOLERANCE = 1e-3


@dataclass
class Measured:
    """A measurement ready for comparison (SI, channel → series or Allan table)."""

    kind: str                      # "log" or "adev_table"
    source: str
    rate_hz: float
    n_samples: int
    series: dict[str, np.ndarray] = field(default_factory=dict)
    tables: dict[str, AllanResult] = field(default_factory=dict)
    temp_c: np.ndarray | None = None
    notes: list[str] = field(default_factory=list)
    #: channels whose log holds two noise levels (:func:`budget.noise.stationarity.check_stationarity`,
    #: kind ``noise_level_change``) → what was found: no effect of the vocabulary is a change of
    #: regime, so the workflow does not work on them (:mod:`budget.gap.workflow`)
    regimes: dict[str, str] = field(default_factory=dict)

    @property
    def channels(self) -> tuple[str, ...]:
        src = self.series if self.kind == "log" else self.tables
        return tuple(c for c in CHANNELS if c in src)


def log_from_arrays(channels: dict[str, np.ndarray], rate_hz: float, temp_c=None,
                    source: str = "arrays") -> ImuLog:
    """An :class:`ImuLog` from SI arrays (channel → (N,) series), e.g. a simulated log."""
    chans = {c: np.asarray(v, float) for c, v in channels.items()}
    bad = [c for c in chans if c not in CHANNELS]
    if bad:
        raise InputError(f"unknown channel(s) {', '.join(bad)}", field="channels",
                         expected=", ".join(CHANNELS))
    sizes = {v.shape for v in chans.values()}
    if not chans or len(sizes) != 1 or len(next(iter(sizes))) != 1:
        raise InputError("channels must be 1-D series of one common length", field="channels",
                         value=sorted(sizes) or None)
    for c, v in chans.items():
        if not np.all(np.isfinite(v)):
            raise InputError("series contains NaN or infinite values", field=c, expected="finite numbers")
    units = {c: channel_si_unit(c) for c in chans}
    temp = None if temp_c is None else np.asarray(temp_c, float)
    if temp is not None and temp.shape != next(iter(sizes)):
        raise InputError(f"temp_c has shape {temp.shape}", field="temp_c",
                         expected=f"{next(iter(sizes))} like the channels")
    return ImuLog(source, chans, float(rate_hz), None, temp, LogReport(), units)


def load_measured(measured, *, rate_hz: float | None = None, samples: int | None = None,
                  mapping=None, repair: bool = False, max_rows: int | None = None,
                  ci_level: float = 0.95, channels=None) -> Measured:
    """Resolve the measurement argument of :func:`budget.gap.run_gap` (``mapping``: a
    :class:`~budget.noise.log_mapping.LogMapping` or the path of its JSON; ``channels``: read
    only those columns of a log file, :func:`~budget.noise.measurement.read_measurement`)."""
    if isinstance(measured, ImuLog):
        return _from_log(measured)
    if isinstance(measured, dict) and measured and all(isinstance(v, AllanResult) for v in measured.values()):
        return _from_tables(measured, str(next(iter(measured.values())).source))
    if isinstance(measured, (str, Path)):
        if isinstance(mapping, (str, Path)):  # a MAP.json path, as on the command line
            from ..noise.log_mapping import LogMapping
            mapping = LogMapping.load(mapping)
        data = read_measurement(measured, rate_hz=rate_hz, samples=samples, mapping=mapping,
                                repair=repair, max_rows=max_rows, ci_level=ci_level,
                                min_samples=MIN_SAMPLES,
                                channels=None if channels is None else list(channels))
        if isinstance(data, ImuLog):
            return _from_log(data)
        return _from_tables(data, str(measured))
    raise InputError(f"not a measurement: {type(measured).__name__}", field="measured",
                     expected="a log path, an ImuLog or {channel: AllanResult}")


def _from_log(log: ImuLog) -> Measured:
    series = {c: np.asarray(v, float) for c, v in log.channels.items()}
    n = log.n_samples
    if n < MIN_SAMPLES:
        raise InputError(f"log too short: {n} samples", file=log.source, field="samples",
                         expected=f"at least {MIN_SAMPLES} samples")
    flat = [c for c, v in series.items() if np.ptp(v) == 0]
    if flat:  # nothing to compare: its Allan deviation and PSD are zero (a dead or clipped channel)
        raise InputError(f"channel(s) {', '.join(flat)} hold one constant value", file=log.source,
                         field=flat[0], expected="a recorded noise signal (drop dead channels from the "
                         "log or the mapping)")
    notes = ["each channel's mean was removed before comparing (turn-on bias, gravity and "
             "Earth rate are not noise statistics)"]
    notes += [f"log: {i.text()}" for i in log.issues.issues]
    notes += [f"log repair: {r}" for r in log.issues.repairs]
    # the comparison assumes one stationary regime, as the Allan fit does: say where it is not
    regimes: dict[str, str] = {}
    for issue in check_stationarity(series, repaired=bool(log.issues.repairs)):
        if issue.kind == "noise_level_change":
            # no effect of the vocabulary changes the noise level mid-record: whatever it named
            # there (heavy tails, a Gauss–Markov term, a ramp …) fitted the change, not the unit
            regimes.setdefault(issue.column, issue.message)
            notes.append(f"WARNING, not one stationary regime: {issue.column}: {issue.message} — no effect is "
                         f"named on {issue.column} (a noise-level change reads as heavy tails or a level "
                         "misfit); compare each regime's rows on its own")
            continue
        notes.append(f"WARNING, not one stationary regime: {issue.column}: {issue.message} — a bias step "
                     f"reads as a rate random walk; what is named on {issue.column} is doubtful")
    temp = None
    if log.temp_c is not None:
        temp = np.asarray(log.temp_c, float)
        if not np.all(np.isfinite(temp)):
            raise InputError("temperature channel has non-finite values", file=log.source, field="temp_c")
        if np.ptp(temp) == 0:
            notes.append("temperature channel is constant: no temperature statistic")
            temp = None
    return Measured("log", log.source, float(log.rate_hz), n, series, temp_c=temp, notes=notes,
                    regimes=regimes)


def _from_tables(tables: dict[str, AllanResult], source: str) -> Measured:
    first = next(iter(tables.values()))
    if any(not t.samples for t in tables.values()):  # read_adev_table without rate and length
        raise InputError("a digitised Allan curve (no record behind it) cannot be compared: the model "
                         "gap needs the record's rate and length", field="measured",
                         expected=GAP_RECORD_WAY.cli)
    rates = {t.rate_hz for t in tables.values()}
    lens = {t.samples for t in tables.values()}
    if len(rates) > 1 or len(lens) > 1:
        raise InputError("Allan tables of one comparison must share rate and record length",
                         field="measured", value=sorted(rates))
    notes = ["measured Allan-deviation table: only the ADEV signature is available (no PSD, "
             "distribution, trend or temperature statistics; outliers and temperature effects "
             "cannot be named)"]
    notes += [n for t in tables.values() for n in getattr(t, "notes", ())]
    return Measured("adev_table", source, float(first.rate_hz), int(first.samples),
                    tables=dict(tables), notes=notes)


def load_model(model, *, catalog_csv=None) -> tuple[NoiseModel, bool, str]:
    """→ (noise model, came from the catalog?, label): :func:`budget.imu.resolve.resolve_noise_model`."""
    return resolve_noise_model(model, catalog_csv)


def check_compatible(meas: Measured, model: NoiseModel, from_catalog: bool,
                     channels, check_tau_range: bool) -> tuple[tuple[str, ...], list[str]]:
    """Apply the module's rules; → (channels to compare, notes)."""
    notes: list[str] = []
    if channels is None and 0 < len(meas.channels) < len(CHANNELS):
        notes.append(f"the measurement has {', '.join(meas.channels)} only: compared on "
                     f"{'that channel' if len(meas.channels) == 1 else 'those channels'}")
        channels = meas.channels
    wanted = tuple(CHANNELS if channels is None else channels)
    unknown = [c for c in wanted if c not in CHANNELS]
    if unknown:
        raise InputError(f"unknown channel(s) {', '.join(unknown)}", field="channels",
                         expected=", ".join(CHANNELS))
    missing = [c for c in wanted if c not in meas.channels]
    if missing:
        raise InputError(f"channel(s) {', '.join(missing)} missing from the measurement",
                         file=meas.source, field="channels",
                         expected=f"every compared channel present (the model describes all six; compare a "
                                  f"subset of {','.join(meas.channels) or '…'}: {GAP_CHANNELS_WAY.cli})")
    if model.rate_hz is None:  # said: the model is simulated at a rate the user did not write
        notes.append(f"the model gives no rate_hz: it is simulated at the measurement's {meas.rate_hz:g} Hz")
    elif abs(model.rate_hz - meas.rate_hz) > RATE_TOLERANCE * model.rate_hz:
        if from_catalog and meas.rate_hz < model.rate_hz:
            notes.append(f"catalog rate {model.rate_hz:g} Hz is the part's output rate; the log was "
                         f"recorded at {meas.rate_hz:g} Hz and the model is simulated at that rate "
                         "(densities do not depend on the rate)")
        else:
            raise InputError(f"different rates: the measurement is sampled at {meas.rate_hz:g} Hz "
                             f"but the model describes {model.rate_hz:g} Hz", field="rate_hz",
                             expected="a model for the log's rate (set rate_hz in MODEL.json, or "
                                      "resample the log)")
    _check_random_terms(model, wanted, meas.source)
    temp_fx = [f.channel for f in model.effects if f.name in TEMPERATURE_EFFECTS and f.channel in wanted]
    if temp_fx and meas.temp_c is None:
        raise InputError(f"the model has a temperature effect on {', '.join(temp_fx)} but the "
                         "measurement has no temperature channel", field="temp_c",
                         expected="a log with a temp_c column")
    if check_tau_range:
        _check_tau(meas, model, wanted)
    return wanted, notes


def _check_random_terms(model: NoiseModel, wanted, source) -> None:
    """Every compared channel needs a random noise term in the model: the gap is judged against
    the model's own realizations, which a channel without one (an empty model, a catalog part
    with no noise figure for that triad) would make all equal — no spread to judge by."""
    si = model.to_si()
    bare = [ch for ch in wanted
            if not any(f.name not in DETERMINISTIC_EFFECTS and any(v > 0 for v in f.params.values())
                       for f in si.channel_effects(ch))]
    if bare:
        name = model.part_id or "the model"
        raise InputError(f"{name} has no noise term for {', '.join(bare)}: the gap compares the log "
                         "with the spread of the model's own noise, and there is none to compare with",
                         file=source, field="model",
                         expected="a noise figure for every compared channel (gyro_arw_deg_rt_h / "
                                  "gyro_bias_instability_deg_h for gyros, accel_vrw_m_s_rt_h / "
                                  "accel_bias_instability_ug for accelerometers, or a noise effect), "
                                  f"or compare only the channels it describes ({GAP_CHANNELS_WAY.cli})")


def _check_tau(meas: Measured, model: NoiseModel, wanted) -> None:
    si = model.to_si()
    tau_max = (meas.n_samples // 4) / meas.rate_hz
    if meas.kind == "adev_table":
        for c in wanted:  # a table with too few τ says so first (a one-row table read "log too short")
            try:
                SignatureGrid.for_table(meas.tables[c])
            except InputError as err:
                raise InputError(err.reason, file=meas.source, field=c,
                                 expected=err.expected) from None
        tau_max = max(float(meas.tables[c].tau_s[-1]) for c in wanted)
    for ch in wanted:
        effs = si.channel_effects(ch)
        n = math.sqrt(sum(f.param("density") ** 2 for f in effs if f.name == "white_noise"))
        b = math.sqrt(sum(f.param("B") ** 2 for f in effs if f.name == "bias_instability"))
        if n > 0 and b > 0:
            need = (n / (FLICKER_FLOOR * b)) ** 2
            if tau_max < need:
                samples = int(math.ceil(4 * need * meas.rate_hz))
                raise InputError(f"log too short for the τ range needed: its Allan deviation reaches "
                                 f"τ = {tau_max:.4g} s but the model's bias-instability floor on {ch} "
                                 f"starts at τ ≈ {need:.4g} s{_levels_said(model, ch, n, b)}",
                                 file=meas.source, field="samples",
                                 value=meas.n_samples,
                                 expected=f"at least {samples} samples at {meas.rate_hz:g} Hz{GAP_TAU_CHECK_WAY.cli}")


def _levels_said(model: NoiseModel, ch: str, n: float, b: float) -> str:
    """The two levels behind the τ the tau check asks for, τ = (N/(0.664·B))²: the channel's
    white density N (SI unit/√Hz, and deg/√h or m/s/√h) and its flicker floor 0.664·B (SI, and
    deg/h or µg), and the share of N written in the model's ``effects``. Effect parameters are
    SI channel units; a datasheet figure written there (an ARW of 0.3 deg/√h as a density of
    0.3 rad/s/√Hz, 1.0e3 deg/√h) asks for a record of years, which the levels make plain."""
    unit = channel_si_unit(ch)
    floor = FLICKER_FLOOR * b
    if ch.startswith("gyro"):
        ds = f"{u.rad_s_rt_hz_to_deg_rt_h(n):.3g} deg/√h", f"{u.rad_s_to_deg_h(floor):.3g} deg/h"
    else:
        ds = f"{u.m_s2_rt_hz_to_m_s_rt_h(n):.3g} m/s/√h", f"{u.m_s2_to_ug(floor):.3g} µg"
    said = (f" (white noise N = {n:.3g} {unit}/√Hz = {ds[0]}, flicker floor 0.664·B = {floor:.3g} "
            f"{unit} = {ds[1]})")
    n_fx = math.sqrt(sum(f.param("density") ** 2 for f in model.effects
                         if f.channel == ch and f.name == "white_noise"))
    if n_fx > 0.5 * n:
        said += (f"; {n_fx:.3g} {unit}/√Hz of N is the model's white_noise effect, whose density is "
                 f"in SI channel units ({unit}/√Hz), not a datasheet unit")
    return said
