"""The perfect-IMU reference of a cluttered scene (budget.mc.reference): limits as documented."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from budget.mc import McOptions
from budget.mc.chain import ChainSetup, scene_reference
from budget.mc.reference import REFERENCE_DRAWS, REFERENCE_QUANTILE, reference_from_outcomes
from budget.presets import get_preset
from budget.sar.acceptance import Acceptance

_KEYS = ("pslr_db", "islr_db", "azimuth_broadening", "range_broadening", "peak_loss_db", "residual_phase_rms_deg")


def _outcomes(rng, n=16):
    """Zero-error outcomes written here: ideal Taylor-like image before PGA, PGA-degraded after."""
    out = []
    for _ in range(n):
        before = {"pslr_db": -35.2, "islr_db": -27.1, "azimuth_broadening": 0.0, "range_broadening": 0.0,
                  "peak_loss_db": 0.0, "residual_phase_rms_deg": 3.0}
        after = {"pslr_db": rng.uniform(-30, -24), "islr_db": rng.uniform(-25, -21),
                 "azimuth_broadening": rng.uniform(0, 0.05), "range_broadening": 0.0,
                 "peak_loss_db": rng.uniform(0, 0.3), "residual_phase_rms_deg": rng.uniform(0.5, 2.0)}
        out.append(SimpleNamespace(before=before, after=after, passed_after=False))
    return out


def test_limits_follow_the_documented_rules():
    rng = np.random.default_rng(3)
    outs = _outcomes(rng)
    acc = Acceptance(max_peak_shift_cells=1000.0)
    ref = reference_from_outcomes(outs, acc, 1.0)
    q = {k: np.quantile([o.after[k] for o in outs], REFERENCE_QUANTILE) for k in _KEYS}
    eff = ref.effective()
    assert eff["pslr_db"] == pytest.approx(max(-35.2 + 3.0, q["pslr_db"] + 3.0))
    assert eff["islr_db"] == pytest.approx(max(-27.1 + 3.0, q["islr_db"] + 3.0))
    assert eff["broadening"] == pytest.approx((1 + q["azimuth_broadening"]) * 1.1 - 1)
    assert eff["peak_loss_db"] == pytest.approx(q["peak_loss_db"] + 1.5)
    assert eff["residual_phase_rms_deg"] == pytest.approx(math.hypot(1.0, q["residual_phase_rms_deg"]))
    assert any("PSLR" in f for f in ref.scene_fails_spec)  # PSLR quantile > −32.2 dB: the scene alone fails
    assert "perfect-IMU reference" in ref.summary() and len(ref.to_frame()) == len(_KEYS)


def test_absolute_user_limits_stay_absolute():
    outs = _outcomes(np.random.default_rng(4))
    ref = reference_from_outcomes(outs, Acceptance(max_pslr_db=-20.0, max_islr_db=-15.0), None)
    assert ref.effective()["pslr_db"] == -20.0 and ref.effective()["islr_db"] == -15.0
    assert ref.max_residual_phase_rms_deg is None


def test_a_clean_points_scene_has_no_reference_and_a_cluttered_one_has():
    scen = get_preset("automotive_24ghz")
    assert scene_reference(ChainSetup.build(scen, McOptions(scene="points"))) is None
    setup = ChainSetup.build(scen, McOptions(scene="realistic"))
    ref = scene_reference(setup)
    assert ref is not None and ref.draws == REFERENCE_DRAWS
    assert scene_reference(setup) is ref  # computed once per setup
    assert setup.describe()["reference"]["limits"] == ref.effective()
    assert scene_reference(ChainSetup.build(scen, McOptions(scene="realistic", scene_reference="none"))) is None


@pytest.mark.slow
def test_a_perfect_imu_passes_on_noise_draws_the_reference_never_saw():
    """The reference's purpose, checked out of sample: zero-motion-error trials on the realistic
    airborne X-band scene at −20 dB clutter (the worst case of the verdict's tests), with receiver
    noise from the ordinary trial stream (not ``sar_reference``), must all pass — the reference
    and, for the few draws beyond its 99 % quantile, the perfect-IMU twin. At the former 95 %
    quantile of 16 draws (no twin) a perfect IMU was capped near 0.94."""
    from budget.mc.chain import FORMATION_BATCH, run_trials
    from budget.mc.stats import wilson_interval
    scen = get_preset("airborne_xband").model_copy(update={"lever_arm_m": (0.0, 0.0, 0.0)})
    setup = ChainSetup.build(scen, McOptions(scene="realistic", clutter_to_target_db=-20.0, snr_db=30.0))
    zero = np.zeros((FORMATION_BATCH, setup.geom.n_pulses, 3))
    outcomes = []
    for lo in range(0, 64, FORMATION_BATCH):
        outcomes += run_trials(setup, zero, range(lo, lo + FORMATION_BATCH), 7, np.zeros(FORMATION_BATCH))
    # the reference's limits alone (trials passed by their twin did exceed them): a new draw
    # exceeds the 99 % quantile of 64 with probability ≈ 1/65 per metric, so a few of 64 may
    # (measured: 2); six or more would mean the reference no longer describes the scene …
    beyond = sum(o.twin_pass for o in outcomes)
    assert beyond <= 5, beyond
    # … and with the twin rule a perfect IMU never fails (each trial is its own twin)
    assert all(o.passed_after for o in outcomes), [o.reasons for o in outcomes if not o.passed_after]
    assert wilson_interval(len(outcomes), len(outcomes))[0] >= 0.9


def _realistic_24ghz(**kw):
    return ChainSetup.build(get_preset("automotive_24ghz"), McOptions(scene="realistic", **kw))


def test_the_twin_clears_what_the_scene_alone_does_to_a_perfect_imu(monkeypatch):
    """Zero motion error on the realistic 24 GHz scene, judged with a reference of only 8 draws,
    no PSLR/ISLR margin and an IMU allowance of 0.1° on the PGA residual, so that the image limits
    are essentially the reference's 99 % quantile, which a new draw exceeds with probability
    ≈ 1/9 (with the default 64 draws ≈ 1/65: a perfect IMU once failed 2 of 64 trials this way,
    every catalog part the same two). The trials beyond the reference's limits are the scene's
    autofocus error, not an IMU's: against their own perfect-IMU twin every trial passes
    (measured: 3 of 32, on their PSLR or ISLR). The PGA residual of a perfect IMU is zero: the
    chain gives PGA the aperture, whose cut-back then leaves nothing above its window there
    (before it, the residual was the draw that exceeded the reference: 6 of 32 with the 3 dB
    margins)."""
    import budget.mc.chain as chain
    from budget.mc.chain import FORMATION_BATCH, run_trials
    from budget.mc.options import VERDICT_ACCEPTANCE
    monkeypatch.setattr(chain, "REFERENCE_DRAWS", 8)
    acc = VERDICT_ACCEPTANCE.model_copy(update={"pslr_margin_db": 0.0, "islr_margin_db": 0.0})
    setup = _realistic_24ghz(max_residual_phase_rms_deg=0.1, acceptance=acc)
    ref = scene_reference(setup)
    assert ref.draws == 8
    zero = np.zeros((FORMATION_BATCH, setup.geom.n_pulses, 3))
    outcomes = []
    for lo in range(0, 32, FORMATION_BATCH):
        outcomes += run_trials(setup, zero, range(lo, lo + FORMATION_BATCH), 1, np.zeros(FORMATION_BATCH))
    a = ref.acceptance
    over = [o.trial for o in outcomes if o.after["pslr_db"] > a.max_pslr_db or o.after["islr_db"] > a.max_islr_db
            or o.after["residual_phase_rms_deg"] > ref.max_residual_phase_rms_deg]
    assert over, "no draw exceeded the reference: the case no longer exercises the twin"
    assert all(o.after["residual_phase_rms_deg"] < 1e-6 for o in outcomes)  # degrees
    assert all(o.passed_after for o in outcomes)
    assert set(over) <= {o.trial for o in outcomes if o.twin_pass}


def test_the_twin_does_not_clear_an_error_the_imu_adds():
    """A fast phase error written here — 0.08 rad at 20 cycles per aperture, ≈ 3.2° rms, far
    beyond PGA's window — fails for its residual, against the reference and against the twin."""
    from budget.mc.chain import run_trial_errors
    from budget.sar.phase import los_offset_for_phase
    setup = _realistic_24ghz()
    u = 2.0 * setup.geom.pulse_times_s / setup.geom.aperture_time_s
    err = los_offset_for_phase(setup.geom, 0.08 * np.sin(2 * np.pi * 20.0 * u))
    o = run_trial_errors(setup, err, 1, 1, 0.0)
    assert not o.passed_after and "residual_phase_noise" in o.reasons and not o.twin_pass
    assert o.after["residual_phase_rms_deg"] > 2.0
