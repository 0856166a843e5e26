"""Direct detectors: effects whose presence the measured values show without any fit.

* **Lattice → quantization.** When every first difference of a channel is a whole multiple of
  one step δ (:func:`budget.gap.signatures.lattice_step`), the output is quantized. If the
  integrated output (angle, velocity) is floored to a quantum q, the output rate moves in steps
  of q/dt, so q = δ·dt and the IEEE-952 coefficient is Q = q/√12 = δ·dt/√12 (ADEV √3·Q/τ,
  IEEE Std 952 Annex C). The closed-form signature of quantization assumes an accumulator that
  crosses many quanta per sample; a static sensor whose noise moves it by less than a quantum
  per sample gives a correlated error the closed form does not describe, so the effect is
  proposed at the measured Q and judged by *simulation* (the generator floors the integral the
  same way). A lattice of raw counts far finer than the noise is proposed too; its simulated
  improvement is then negligible and it is rejected, as it should be.
* **The same lattice → rate quantization.** A lattice of differences is also what a part gives
  that outputs its *rate* rounded to δ with no accumulator (its LSBs): the values cannot tell the
  two apart, so ``rate_quantization`` at step δ is proposed after ``quantization`` and judged by
  simulation the same way — the integrated form has ADEV ∝ 1/τ, the rounded rate a white level
  δ²/12 and a uniform error's light tails.
"""

from __future__ import annotations

import math

from ..imu import Effect, NoiseModel
from ..imu.registry import QUANTIZERS
from .signatures import Signature, SignatureGrid


def direct_proposals(model: NoiseModel, channel: str, meas: Signature,
                     grid: SignatureGrid) -> list[Effect]:
    """Effects the values of ``channel`` show directly (see module docstring)."""
    out = []
    have = {f.name for f in model.to_si().channel_effects(channel)}
    if meas.lattice is not None and not have & set(QUANTIZERS):  # a channel has one quantizer
        q_coeff = meas.lattice * grid.dt_s / math.sqrt(12.0)
        out.append(Effect(name="quantization", channel=channel, params={"Q": q_coeff}))
        out.append(Effect(name="rate_quantization", channel=channel, params={"step": meas.lattice}))
    return out
