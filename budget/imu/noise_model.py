"""IMU noise model: a catalog row (datasheet units) plus a list of per-channel error effects.

A catalog part *is* a noise model: :class:`NoiseModel` reuses every numeric field of
:class:`~budget.catalog.schema.PartSpec` (same names, units and limits; absent = 0) and converts
them through :meth:`PartSpec.to_si`, so no conversion factor lives here. On top of the row it
holds ``effects``: extra error terms from the effect registry (:mod:`budget.imu.registry`),
each on one channel with parameters in SI channel units:

==========================  ===========================================================
effect                      parameters (gyro: rad/s-based; accelerometer: m/s²-based)
==========================  ===========================================================
white_noise                 ``density`` (channel unit/√Hz)
quantization                ``Q`` (IEEE-952 coefficient, channel unit × s; ADEV √3·Q/τ)
rate_quantization           ``step`` (channel unit): the output rate rounded to a lattice
bias_instability            ``B`` (IEEE-952 flicker coefficient; ADEV floor 0.664·B)
rate_random_walk            ``K`` (channel unit/√s; ADEV K·√(τ/3))
rate_ramp                   ``R`` (channel unit/s; ADEV R·τ/√2), signed
warmup_transient            ``amplitude`` (channel unit, signed: the bias at the first sample
                            above its settled value), ``tau_s``: A·e^(−t/τ), t from the first
                            sample of the log (of the aperture in a Monte Carlo: the IMU
                            switched on with it, the worst case)
bias_step                   ``amplitude`` (channel unit, signed), ``time_s``: the bias jumps
                            by A at t₀ = ``time_s`` after the first sample of the log (of the
                            simulation in a Monte Carlo) and stays there
sinusoid                    ``frequency_hz``, ``amplitude`` (peak, channel unit)
gauss_markov                ``tau_s`` (correlation time), ``sigma`` (steady-state 1σ)
temperature_sensitivity     ``coefficient`` (channel unit/°C), signed
temperature_lag             ``coefficient`` (channel unit/°C), signed; ``tau_s``: time
                            constant of the first-order lag between the logged temperature
                            and the sensing element's
outliers                    ``rate`` (fraction of samples, 0–1), ``magnitude`` (channel unit)
lowpass                     ``cutoff_hz``: first-order output filter (1 − a)·y + a·x,
                            a = 1 − exp(−2π·f_c·dt), on the channel's additive noise
vibration                   ``center_hz``, ``width_hz`` (−3 dB width), ``sigma`` (rms):
                            band-limited random vibration (a noise-driven resonance)
heavy_tailed                ``density`` (unit/√Hz), ``dof`` (Student-t ν > 2): white noise
                            with heavy tails (distinct from sparse ``outliers``)
==========================  ===========================================================

``lowpass`` extends the shared vocabulary: real MEMS parts average or filter internally before
they output a sample, which white noise alone cannot describe (the ADIS16405 logs show it).

The JSON form (MODEL.json) is the catalog row's keys in datasheet units plus
``"effects": [{"name": ..., "channel": ..., "params": {...}}]``; it is what the Monte Carlo and
the model-gap workflow read and write.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from ..catalog.schema import ImuErrorsSI, PartSpec
from ..errors import InputError, from_validation_error, refuse_bool_numbers
from ..fileio import atomic_write_text
from ..structured import read_structured
from ..units import ACCEL_CHANNELS, CHANNELS, GYRO_CHANNELS, channel_si_unit
from .registry import QUANTIZERS, REGISTRY

#: Effect name → {parameter: (unit suffix for messages, lower bound, lower bound inclusive?)},
#: derived from the effect registry. ``None`` as bound means any finite number (signed).
EFFECT_PARAMS: dict[str, dict[str, tuple[str, float | None, bool]]] = {
    name: {p: (ps.suffix, ps.low, ps.inclusive) for p, ps in spec.params.items()}
    for name, spec in REGISTRY.items()}
EFFECT_NAMES = tuple(EFFECT_PARAMS)


def param_unit(name: str, param: str, channel: str) -> str:
    """Unit of one effect parameter on one channel (for messages, tables and docs)."""
    spec = REGISTRY[name].params[param]
    if spec.channel_free:
        return spec.suffix
    if name == "quantization":
        return "rad" if channel.startswith("gyro") else "m/s"
    return channel_si_unit(channel) + spec.suffix


class Effect(BaseModel):
    """One error effect on one channel, parameters in SI channel units (see module table)."""

    model_config = ConfigDict(extra="forbid", frozen=True)
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    name: str
    channel: str
    params: dict[str, float] = Field(default_factory=dict)

    @field_validator("name")
    @classmethod
    def _known_name(cls, v: str) -> str:
        if v not in EFFECT_PARAMS:
            raise ValueError(f"unknown effect {v!r}; expected one of {', '.join(EFFECT_NAMES)}")
        return v

    @field_validator("channel")
    @classmethod
    def _known_channel(cls, v: str) -> str:
        if v not in CHANNELS:
            raise ValueError(f"unknown channel {v!r}; expected one of {', '.join(CHANNELS)}")
        return v

    @model_validator(mode="after")
    def _check_params(self) -> "Effect":
        spec = EFFECT_PARAMS[self.name]
        unknown = sorted(set(self.params) - set(spec))
        if unknown:
            raise ValueError(f"effect {self.name!r} has unknown parameter(s) {', '.join(unknown)}; "
                             f"expected {', '.join(spec)}")
        missing = [p for p in spec if p not in self.params]
        if missing:
            raise ValueError(f"effect {self.name!r} needs parameter(s) {', '.join(missing)}")
        for p, (_, low, inclusive) in spec.items():
            v = self.params[p]
            unit = param_unit(self.name, p, self.channel)
            if not math.isfinite(v):
                raise ValueError(f"{self.name}.{p} must be a finite number in {unit} (got {v})")
            if low is not None and (v < low or (v == low and not inclusive)):
                rel = "≥" if inclusive else ">"
                raise ValueError(f"{self.name}.{p} must be {rel} {low:g} {unit} (got {v:g})")
            high = REGISTRY[self.name].params[p].high
            if high is not None and abs(v) > high:
                bound = f"within ±{high:g}" if low is None else f"at most {high:g}"
                raise ValueError(f"{self.name}.{p} must be {bound} {unit} (got {v:g})")
        return self

    def param(self, key: str) -> float:
        return float(self.params[key])


@dataclass(frozen=True)
class NoiseModelSI:
    """A noise model in SI: catalog terms (``errors``) and the explicit effects.

    ``channel_effects(ch)`` lists every additive term of one channel, the catalog-implied ones
    first (white noise from ARW/VRW, flicker from the bias instability B, rate random walk),
    then the explicit ones; terms of the same kind add as independent processes.
    ``turn_on_bias``, ``scale_factor`` and ``misalignment`` give the 1σ of the per-trial random
    constants of a triad (``"gyro"`` or ``"accel"``).
    """

    errors: ImuErrorsSI
    effects: tuple[Effect, ...]

    def catalog_effects(self, channel: str) -> list[Effect]:
        e = self.errors
        if channel in GYRO_CHANNELS:
            terms = (("white_noise", "density", e.gyro_arw_rad_s_rt_hz),
                     ("bias_instability", "B", e.gyro_bias_instability_b_rad_s),
                     ("rate_random_walk", "K", e.gyro_rrw_rad_s_rt_s))
        elif channel in ACCEL_CHANNELS:
            terms = (("white_noise", "density", e.accel_vrw_m_s2_rt_hz),
                     ("bias_instability", "B", e.accel_bias_instability_b_m_s2))
        else:
            raise ValueError(f"unknown channel {channel!r}")
        return [Effect(name=n, channel=channel, params={p: v}) for n, p, v in terms if v > 0.0]

    def channel_effects(self, channel: str) -> list[Effect]:
        return self.catalog_effects(channel) + [f for f in self.effects if f.channel == channel]

    def turn_on_bias(self, triad: str) -> float:
        return self.errors.gyro_turn_on_bias_rad_s if triad == "gyro" else self.errors.accel_turn_on_bias_m_s2

    def scale_factor(self, triad: str) -> float:
        return self.errors.gyro_scale_factor if triad == "gyro" else self.errors.accel_scale_factor

    def misalignment(self, triad: str) -> float:
        return self.errors.gyro_misalignment_rad if triad == "gyro" else self.errors.accel_misalignment_rad


_GRADE = Literal["strategic", "navigation", "stabilization", "tactical", "industrial", "consumer"]


class NoiseModel(PartSpec):
    """A catalog row (all :class:`PartSpec` numeric fields, datasheet units) plus ``effects``.

    ``part_id``, ``grade`` and ``source`` are optional here. Use :meth:`from_part`,
    :meth:`load` / :meth:`save` (JSON or YAML), :meth:`with_effect` and :meth:`to_si`.
    """

    # a file's true/false is no number (a catalog CSV, read as text, has no booleans)
    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    part_id: str | None = Field(None, pattern=r"^[A-Za-z0-9][A-Za-z0-9._\-]{0,63}$")
    grade: _GRADE | None = None
    source: str = ""
    effects: tuple[Effect, ...] = ()

    @model_validator(mode="after")
    def _check_model(self) -> "NoiseModel":
        quant = [f.channel for f in self.effects if f.name in QUANTIZERS]
        dup = sorted({c for c in quant if quant.count(c) > 1})
        if dup:
            raise ValueError(f"more than one quantizer ({', '.join(QUANTIZERS)}) on {', '.join(dup)}; "
                             "a channel has one quantizer")
        if self.rate_hz is not None:
            check_rate(self.rate_hz, self.effects)
        return self

    # --- construction ----------------------------------------------------------------
    @classmethod
    def from_part(cls, part: PartSpec) -> "NoiseModel":
        """The noise model of a catalog part (no extra effects)."""
        data = part.model_dump()
        data.setdefault("effects", ())
        return cls.model_validate(data)

    @classmethod
    def from_dict(cls, data: dict, *, source: str | Path | None = None) -> "NoiseModel":
        if not isinstance(data, dict):
            raise InputError("a noise model must be a mapping of keys to values", file=source,
                             expected="a JSON object with catalog-row keys and optional 'effects'")
        try:
            return cls.model_validate(data)
        except ValidationError as err:
            raise from_validation_error(err, file=source) from None

    @classmethod
    def load(cls, path: str | Path) -> "NoiseModel":
        """Read MODEL.json (or .yaml/.yml); every problem names the file and the field."""
        data = read_structured(path, "a noise model")
        return cls.from_dict(data, source=path)

    def to_dict(self) -> dict:
        """JSON-ready dict: set fields only (absent datasheet values stay absent = 0)."""
        data = self.model_dump(mode="json", exclude_none=True)
        for key in ("vendor", "model", "source", "notes"):
            if data.get(key) == "":
                data.pop(key)
        data["effects"] = [f.model_dump(mode="json") for f in self.effects]
        return data

    def save(self, path: str | Path) -> None:
        """Write as JSON (or YAML by suffix), atomically."""
        path = Path(path)
        data = self.to_dict()
        if path.suffix.lower() in (".yaml", ".yml"):
            text = yaml.safe_dump(data, sort_keys=False, allow_unicode=True)
        else:
            text = json.dumps(data, indent=2, ensure_ascii=False) + "\n"
        atomic_write_text(path, text)

    def with_effect(self, effect: Effect | dict) -> "NoiseModel":
        """A new model with one more effect (validated, the original is unchanged)."""
        if isinstance(effect, dict):
            try:
                effect = Effect.model_validate(effect)
            except ValidationError as err:
                raise from_validation_error(err) from None
        data = self.model_dump()
        data["effects"] = (*self.effects, effect)
        try:
            return type(self).model_validate(data)
        except ValidationError as err:
            raise from_validation_error(err) from None

    def to_si(self) -> NoiseModelSI:  # type: ignore[override]
        """SI parameters: the catalog row through :meth:`PartSpec.to_si` plus the effects."""
        return NoiseModelSI(errors=PartSpec.to_si(self), effects=tuple(self.effects))


def check_rate(rate_hz: float, effects) -> None:
    """Raise ``ValueError`` if a sinusoid is at or above the Nyquist frequency rate/2."""
    for f in effects:
        if f.name == "sinusoid" and f.param("frequency_hz") * 2.0 >= rate_hz:
            raise ValueError(f"sampling rate {rate_hz:g} Hz is below twice the {f.param('frequency_hz'):g} Hz "
                             f"sinusoid on {f.channel}; expected rate_hz > 2 × frequency_hz")


def as_noise_model_si(model) -> NoiseModelSI:
    """Accept a :class:`NoiseModel`, a catalog :class:`PartSpec` or a :class:`NoiseModelSI`."""
    if isinstance(model, NoiseModelSI):
        return model
    if isinstance(model, NoiseModel):
        return model.to_si()
    if isinstance(model, PartSpec):
        return NoiseModel.from_part(model).to_si()
    raise InputError(f"not a noise model: {type(model).__name__}", field="model",
                     expected="a NoiseModel, a catalog PartSpec or a NoiseModelSI")
