"""The library of candidate effects: signature, fit and simulation of each vocabulary effect.

Each candidate knows

* its **signature**: the expected increment of every statistic (:mod:`budget.gap.theory`);
* how to **fit** its parameters θ to the measured channel: a closed-form start from the
  residual between measured and model signatures (white level from the τ⁻¹ part of the Allan
  variance residual, quantization from τ⁻², B from the flat part, K from τ, R from the
  least-squares slope, sinusoid from the largest PSD peak ratio, Gauss–Markov from the hump
  over a grid of correlation times, outliers from isolated spikes in the first differences
  (Pauta-like), temperature from the regression on temp_c), then a bounded search that
  minimises the predicted Σz² of the channel (:func:`budget.gap.metric.gap_terms` on the
  predicted model summary);
* how to be **simulated**: as an :class:`~budget.imu.Effect` handed to the IMU generator.

Parameters are SI channel units (see :mod:`budget.imu.noise_model`); θ is the search space
(logarithms of positive parameters).

One module per family, each candidate class named after its effect:

* :mod:`~budget.gap.candidates.floor` — the Allan-floor terms, linear in one variance: white
  noise, quantization, rate quantization, bias instability, rate random walk;
* :mod:`~budget.gap.candidates.regressors` — deterministic series times a coefficient: rate
  ramp, temperature sensitivity, thermal lag, warm-up transient, bias step;
* :mod:`~budget.gap.candidates.spectral` — shapes in the spectrum: sinusoid, Gauss–Markov, the
  output low-pass, vibration;
* :mod:`~budget.gap.candidates.impulsive` — the distribution's tails: outliers, heavy tails.

A new effect: register it in :mod:`budget.imu.registry`, write its candidate in the family it
belongs to and add an instance to :data:`LIBRARY`.
"""

from ...imu.registry import EFFECT_NAMES
from ..fitting import Candidate
from .floor import BiasInstability, Quantization, RateQuantization, RateRandomWalk, WhiteNoise
from .impulsive import HeavyTailed, Outliers
from .regressors import BiasStep, RateRamp, TemperatureLag, TemperatureSensitivity, WarmupTransient
from .spectral import GaussMarkov, Lowpass, Sinusoid, Vibration

#: Effects the workflow can name: the effect registry, in its order.
VOCABULARY = EFFECT_NAMES

LIBRARY: dict[str, Candidate] = {c.name: c for c in (
    WhiteNoise(), Quantization(), RateQuantization(), BiasInstability(), RateRandomWalk(), RateRamp(),
    WarmupTransient(), BiasStep(), Sinusoid(), GaussMarkov(), TemperatureSensitivity(), TemperatureLag(), Outliers(), Lowpass(),
    Vibration(), HeavyTailed())}
