"""The effect registry: every error effect of a channel declared once.

Each :class:`EffectSpec` gives the effect's parameters (unit suffix after the channel unit,
lower bound), the **stage** where the generator applies it, and — for the additive effects —
its sample generator. The noise model's validation (:mod:`budget.imu.noise_model`), the
generator (:mod:`budget.imu.generator`, which walks the registry stage by stage) and the
model-gap vocabulary (:mod:`budget.gap.candidates`, one candidate per registered effect with
its closed-form signature in :mod:`budget.gap.theory`) all derive from this table; a test ties
them. Adding an effect: one entry here (plus its generator in :mod:`budget.imu.effects` if it
is additive) and one candidate in the gap library.

Stages, in the generator's order:

1. ``gaussian`` — the stationary Gaussian part drawn jointly and exactly (white noise, the
   flicker bank of bias instability, Gauss–Markov terms; then the rate random walk);
2. ``additive`` — independent additive terms, each drawn by its ``simulate``;
3. ``filter`` — the sensor's output filter on the sum of the additive terms;
4. ``output`` — quantization of the integrated output, then rounding of the output rate to its
   lattice (both see the true signal too);
5. ``glitch`` — data glitches (outliers), last.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from . import effects as fx

STAGES = ("gaussian", "additive", "filter", "output", "glitch")


@dataclass(frozen=True)
class ParamSpec:
    """One parameter: unit suffix (after the channel unit unless ``channel_free``), lower
    bound (``None``: signed, any finite number) and whether the bound is allowed."""

    suffix: str
    low: float | None = 0.0
    inclusive: bool = True
    channel_free: bool = False
    #: largest magnitude accepted (channel units, s or Hz): far beyond any sensor, it keeps
    #: absurd values (1e300) out of the simulation and the fits
    high: float | None = 1e6


@dataclass(frozen=True)
class EffectSpec:
    """An effect: parameters, stage, one-line signature, and (additive stage) its generator
    ``simulate(params, n_trials, time_s, dt_s, rng, temp) -> (T, N)``."""

    name: str
    params: dict[str, ParamSpec]
    stage: str
    signature: str
    simulate: Callable | None = field(default=None, compare=False)


def _deterministic(name: str) -> Callable:
    """The generator of a deterministic effect: its series (:func:`budget.imu.effects.mean_series`,
    the one the model gap's statistics read their means from) in every trial."""

    def simulate(p, n_trials, time_s, dt_s, rng, temp):
        return np.broadcast_to(fx.mean_series(name, p, time_s.size, dt_s, temp), (n_trials, time_s.size))

    return simulate


def _sinusoid(p, n_trials, time_s, dt_s, rng, temp):
    return fx.sinusoid(n_trials, time_s, p["frequency_hz"], p["amplitude"], rng)


def _vibration(p, n_trials, time_s, dt_s, rng, temp):
    return fx.vibration(n_trials, time_s.size, p["center_hz"], p["width_hz"], p["sigma"], dt_s, rng)


def _heavy(p, n_trials, time_s, dt_s, rng, temp):
    return fx.student_t_noise(n_trials, time_s.size, p["density"], p["dof"], dt_s, rng)


_HZ = ParamSpec("Hz", 1e-6, True, True)  # below a µHz a "frequency" is a trend

REGISTRY: dict[str, EffectSpec] = {s.name: s for s in (
    EffectSpec("white_noise", {"density": ParamSpec("/√Hz")}, "gaussian", "ADEV N/√τ"),
    EffectSpec("quantization", {"Q": ParamSpec("·s")}, "output",
               "ADEV √3·Q/τ (IEEE-952); output values on a lattice of step √12·Q/dt"),
    EffectSpec("rate_quantization", {"step": ParamSpec("")}, "output",
               "output rate itself rounded to a lattice of step δ (not its integral): about white, "
               "variance δ²/12, when the noise spans several steps"),
    EffectSpec("bias_instability", {"B": ParamSpec("")}, "gaussian", "flat ADEV 0.664·B"),
    EffectSpec("rate_random_walk", {"K": ParamSpec("/√s")}, "gaussian", "ADEV K·√(τ/3)"),
    EffectSpec("rate_ramp", {"R": ParamSpec("/s", None)}, "additive", "ADEV R·τ/√2; slope R",
               _deterministic("rate_ramp")),
    EffectSpec("warmup_transient", {"amplitude": ParamSpec("", None), "tau_s": ParamSpec("s", 0.0, False, True)},
               "additive", "turn-on transient A·e^(−t/τ) from the first sample: a slope and a slow-mode "
               "pattern concentrated at the start, no variance of its own", _deterministic("warmup_transient")),
    EffectSpec("bias_step", {"amplitude": ParamSpec("", None), "time_s": ParamSpec("s", 0.0, False, True)},
               "additive", "the bias jumps once by A at t₀ after the first sample: a slope, a slow-mode "
               "pattern located at t₀, Allan variance growing as τ at long τ like a walk's, no variance "
               "of its own", _deterministic("bias_step")),
    EffectSpec("sinusoid", {"frequency_hz": _HZ, "amplitude": ParamSpec("")}, "additive",
               "PSD line A²/2 at f; ADEV A·sin²(πfτ)/(πfτ)", _sinusoid),
    EffectSpec("gauss_markov", {"tau_s": ParamSpec("s", 0.0, False, True), "sigma": ParamSpec("")},
               "gaussian", "ADEV hump near τ ≈ 1.9·τc"),
    EffectSpec("temperature_sensitivity", {"coefficient": ParamSpec("/°C", None)}, "additive",
               "regression on the temperature column", _deterministic("temperature_sensitivity")),
    EffectSpec("temperature_lag", {"coefficient": ParamSpec("/°C", None),
                                   "tau_s": ParamSpec("s", 0.0, False, True)}, "additive",
               "regression on the temperature column lagged by τ: a slow drift beside it that "
               "follows the temperature's rate of change", _deterministic("temperature_lag")),
    EffectSpec("outliers", {"rate": ParamSpec("fraction of samples", 0.0, True, True, 1.0),
                            "magnitude": ParamSpec("")}, "glitch",
               "isolated spikes of one magnitude in the first differences"),
    EffectSpec("lowpass", {"cutoff_hz": _HZ}, "filter",
               "PSD falls towards Nyquist; ADEV at the shortest τ below the white line"),
    EffectSpec("vibration", {"center_hz": _HZ, "width_hz": _HZ, "sigma": ParamSpec("")},
               "additive", "PSD peak of −3 dB width w at f0 (a resonance driven by noise)",
               _vibration),
    EffectSpec("heavy_tailed", {"density": ParamSpec("/√Hz"),
                                "dof": ParamSpec("", 2.0, False, True, 1000.0)},
               "additive", "white ADEV; many large first differences of all sizes (Student t)",
               _heavy),
)}

EFFECT_NAMES = tuple(REGISTRY)
#: Effects driven by the log's temperature column.
TEMPERATURE_EFFECTS = ("temperature_sensitivity", "temperature_lag")
#: Deterministic additive series (the same in every realization): they move the mean of the
#: slope, temperature and slow-mode statistics and add no variance to them.
DETERMINISTIC_EFFECTS = ("rate_ramp", "warmup_transient", "bias_step", *TEMPERATURE_EFFECTS)
#: The output quantizers (stage ``output``): a channel has at most one of them.
QUANTIZERS = tuple(n for n, s in REGISTRY.items() if s.stage == "output")
