"""What a perfect IMU gets on a cluttered scene: the autofocus floor the verdict is judged against.

On a scene with clutter or receiver noise, PGA's estimate carries its own clutter-limited error
whatever the IMU (per bin ≈ 1/√(2 Σ_r SCR_r) rad, Jakowatz & Wahl, JOSA A 10(12), 1993), and that
error degrades the corrected image: on the realistic scene at −20 dB clutter it leaves a few degrees
rms inside PGA's window, enough to break a Taylor PSLR spec of ideal + 3 dB with NO motion error.
An IMU cannot be blamed for it, and a verdict that fails a perfect IMU says nothing about IMUs.

So, for such scenes, the trial chain is first run with zero motion error on ``n`` receiver-noise
draws of their own (random stream ``sar_reference``), and the user's acceptance is applied
relative to that reference instead of to the window's ideal response:

* PSLR, ISLR (when the spec is "ideal + margin"): limit = max(ideal + margin, q + margin);
* broadening: limit = max(b, (1 + q)(1 + b) − 1)  (b relative to the reference width);
* peak loss: limit = max(L, q + L);
* PGA residual beyond its window: limit = √(r² + q²)  (the IMU may add r rms in quadrature);

q the 99 % quantile of the metric over the reference draws (worst target, worst axis). Absolute
limits the user sets (``max_pslr_db`` / ``max_islr_db``) stay absolute. The reference, the
effective limits and whether the scene alone already fails the user's spec are reported with
every result (:meth:`SceneReference.to_dict`), so the user sees what the verdict was judged on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..sar.acceptance import Acceptance

#: Receiver-noise draws of the perfect-IMU reference.
REFERENCE_DRAWS = 64
#: Quantile of the reference metrics the acceptance is relative to. A limit at the q-quantile of
#: the perfect IMU fails a perfect IMU in a fraction 1 − q of the trials by construction, which
#: caps every part's P(pass) at ≈ q. The decisions use the lower 95 % Wilson bound against a
#: target of 0.9 (:mod:`budget.mc.sweep`); at the default 64 trials a part that passes with
#: p = 0.95 expects 61 of 64, lower bound 0.87: a q = 0.95 limit fails the perfect IMU's own
#: decision more often than not. q = 0.99 expects 63–64 of 64 (lower bound 0.92–0.94), and 64
#: draws put its sample quantile between their two largest values (16 draws could not resolve
#: even q = 0.95: that was their largest-but-one).
REFERENCE_QUANTILE = 0.99

_METRICS = ("pslr_db", "islr_db", "azimuth_broadening", "range_broadening", "peak_loss_db",
            "residual_phase_rms_deg")


@dataclass(frozen=True)
class SceneReference:
    """The perfect-IMU reference of one scene and the acceptance derived from it.

    ``quantiles``: the :data:`REFERENCE_QUANTILE` quantile of each after-PGA metric over ``draws`` zero-error trials
    (dB, ratios, degrees); ``ideal``: the same metrics of the image with no error and no PGA;
    ``acceptance`` / ``max_residual_phase_rms_deg``: the effective limits; ``scene_fails_spec``:
    the user's spec limits a perfect IMU already exceeds on this scene (the scene, not the IMU,
    limits the image there).
    """

    draws: int
    quantiles: dict
    ideal: dict
    acceptance: Acceptance
    max_residual_phase_rms_deg: float | None
    spec: dict
    scene_fails_spec: tuple[str, ...]
    perfect_imu_pass_fraction: float
    #: pulses of the image the reference was formed on (the part's own image, widened for its
    #: defocus: :func:`budget.mc.chain.scene_reference`); None when not recorded
    n_pulses: int | None = None

    def summary(self) -> str:
        q = self.quantiles
        on = f" on this part's {self.n_pulses}-pulse image" if self.n_pulses else ""
        text = (f"perfect-IMU reference ({self.draws} noise draws{on}, {100 * REFERENCE_QUANTILE:g} % quantile after PGA): PSLR "
                f"{q['pslr_db']:.1f} dB, ISLR {q['islr_db']:.1f} dB, residual {q['residual_phase_rms_deg']:.2f}°; "
                f"acceptance relative to it: PSLR ≤ {self.effective()['pslr_db']:.1f} dB, ISLR ≤ "
                f"{self.effective()['islr_db']:.1f} dB, residual ≤ {self.effective()['residual_phase_rms_deg']:.2f}°")
        if self.scene_fails_spec:
            text += ("; the scene alone exceeds the spec (" + ", ".join(self.scene_fails_spec)
                     + "): PGA's clutter-limited estimate, not the IMU, limits the image there")
        return text

    def effective(self) -> dict:
        """The limits applied (absolute values), per metric."""
        a = self.acceptance
        pslr = a.max_pslr_db if a.max_pslr_db is not None else self.ideal["pslr_db"] + a.pslr_margin_db
        islr = a.max_islr_db if a.max_islr_db is not None else self.ideal["islr_db"] + a.islr_margin_db
        res = self.max_residual_phase_rms_deg
        return {"pslr_db": pslr, "islr_db": islr, "broadening": a.max_broadening,
                "peak_loss_db": a.max_peak_loss_db, "residual_phase_rms_deg": math.nan if res is None else res}

    def to_frame(self) -> pd.DataFrame:
        eff = self.effective()
        return pd.DataFrame([{"metric": m, "ideal": self.ideal.get(m, math.nan), "perfect_imu_quantile": self.quantiles[m],
                              "limit": eff.get("broadening" if m.endswith("broadening") else m, math.nan),
                              "spec": self.spec.get("broadening" if m.endswith("broadening") else m, math.nan)}
                             for m in _METRICS])

    def to_dict(self) -> dict:
        return {"draws": self.draws, "quantile": REFERENCE_QUANTILE, "perfect_imu_after_pga": dict(self.quantiles),
                "ideal": dict(self.ideal), "spec": dict(self.spec), "limits": self.effective(),
                "scene_fails_spec": list(self.scene_fails_spec),
                "perfect_imu_pass_fraction": self.perfect_imu_pass_fraction, "n_pulses": self.n_pulses}


def reference_from_outcomes(outcomes, acceptance: Acceptance,
                            max_residual_phase_rms_deg: float | None) -> SceneReference:
    """:class:`SceneReference` from zero-error trial outcomes (``TrialOutcome`` of
    :mod:`budget.mc.chain`: ``before`` = the error-free image without PGA, ``after`` = PGA's)."""
    after = {m: np.array([o.after[m] for o in outcomes], dtype=float) for m in _METRICS}
    q = {m: float(np.quantile(np.where(np.isfinite(v), v, np.inf), REFERENCE_QUANTILE)) for m, v in after.items()}
    ideal = {m: float(np.median([o.before[m] for o in outcomes])) for m in _METRICS if m != "residual_phase_rms_deg"}
    a = acceptance
    spec = {"pslr_db": a.max_pslr_db if a.max_pslr_db is not None else ideal["pslr_db"] + a.pslr_margin_db,
            "islr_db": a.max_islr_db if a.max_islr_db is not None else ideal["islr_db"] + a.islr_margin_db,
            "broadening": a.max_broadening, "peak_loss_db": a.max_peak_loss_db,
            "residual_phase_rms_deg": math.nan if max_residual_phase_rms_deg is None else max_residual_phase_rms_deg}
    update = {}
    if a.max_pslr_db is None and q["pslr_db"] + a.pslr_margin_db > spec["pslr_db"]:
        update["max_pslr_db"] = min(q["pslr_db"] + a.pslr_margin_db, -1e-6)
    if a.max_islr_db is None and q["islr_db"] + a.islr_margin_db > spec["islr_db"]:
        update["max_islr_db"] = min(q["islr_db"] + a.islr_margin_db, -1e-6)
    b_ref = max(q["azimuth_broadening"], q["range_broadening"], 0.0)
    update["max_broadening"] = max(a.max_broadening, (1.0 + b_ref) * (1.0 + a.max_broadening) - 1.0)
    update["max_peak_loss_db"] = max(a.max_peak_loss_db, max(q["peak_loss_db"], 0.0) + a.max_peak_loss_db)
    effective = a.model_copy(update=update)
    res = None
    if max_residual_phase_rms_deg is not None:
        res = math.hypot(max_residual_phase_rms_deg, q["residual_phase_rms_deg"])
    fails = []
    if q["pslr_db"] > spec["pslr_db"]:
        fails.append(f"PSLR {q['pslr_db']:.1f} > {spec['pslr_db']:.1f} dB")
    if q["islr_db"] > spec["islr_db"]:
        fails.append(f"ISLR {q['islr_db']:.1f} > {spec['islr_db']:.1f} dB")
    if b_ref > a.max_broadening:
        fails.append(f"broadening {b_ref:.3f} > {a.max_broadening:.3f}")
    if q["peak_loss_db"] > a.max_peak_loss_db:
        fails.append(f"peak loss {q['peak_loss_db']:.2f} > {a.max_peak_loss_db:.2f} dB")
    if max_residual_phase_rms_deg is not None and q["residual_phase_rms_deg"] > max_residual_phase_rms_deg:
        fails.append(f"PGA residual {q['residual_phase_rms_deg']:.2f}° > {max_residual_phase_rms_deg:.2f}°")
    passed = float(np.mean([o.passed_after for o in outcomes])) if outcomes else math.nan
    return SceneReference(draws=len(outcomes), quantiles=q, ideal=ideal, acceptance=effective,
                          max_residual_phase_rms_deg=res, spec=spec, scene_fails_spec=tuple(fails),
                          perfect_imu_pass_fraction=passed)
