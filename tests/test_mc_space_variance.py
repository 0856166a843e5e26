"""Space variance over the simulated scene's range depth (budget.mc.space_variance) and how the
check-vs-Monte-Carlo comparison names it: the closed form, the mapping it rests on measured on
the formed image, a slow 24 GHz car at 30 m (check passes STIM300, the Monte Carlo does not) and
at 300 m with the same aperture time (both pass), and a part whose filled terms do cause the
disagreement."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
import scipy.fft as sfft

from budget.bounds import paper_bounds
from budget.catalog.io import get_part
from budget.catalog.schema import PartSpec
from budget.check import check_parts
from budget.errors import InputError
from budget.mc import McOptions, run_mc
from budget.mc.space_variance import (range_space_variance, space_variance_of, stretch_residual_deg,
                                      verdict_scene_half_depth_m)
from budget.presets import get_preset
from budget.report.content import FILLED_SHARE_MATERIAL, check_vs_mc, filled_terms_share
from budget.sar import SarGeometry, Scene, form_image, simulate_echoes
from budget.sar.phase import residual_phase_rad
from budget.sar.scene import PointTarget
from budget.scenario import Scenario

#: a 24 GHz car crawling at 2 m/s past a kerb 30 m away (Tc = λR/(2δℓV) = 1.86 s)
AUTO24_SLOW = {"name": "auto24_slow", "medium": "radar", "carrier_frequency_hz": 24.125e9,
               "slant_range_m": 30.0, "azimuth_resolution_m": 0.05, "range_resolution_m": 0.1,
               "platform_speed_m_s": 2.0, "depression_deg": 3.0}
#: the same aperture time, resolution and aperture angle at 300 m (10× the range and the speed)
AUTO24_FAR = {**AUTO24_SLOW, "name": "auto24_far", "slant_range_m": 300.0, "platform_speed_m_s": 20.0}


def test_stretch_residual_is_the_closed_form():
    # ε = 0.1, φ = 10°: quadratic (1.1² − 1)·10 = 2.1°, cubic (1.1³ − 1)·10 = 3.31°; near side
    # ε = −0.1: (1 − 0.9²)·10 = 1.9°
    assert stretch_residual_deg(0.1, 10.0) == pytest.approx(2.1, rel=1e-12)
    assert stretch_residual_deg(0.1, 10.0, order=3) == pytest.approx(3.31, rel=1e-12)
    assert stretch_residual_deg(-0.1, 10.0) == pytest.approx(1.9, rel=1e-12)
    assert stretch_residual_deg(0.0, 10.0) == 0.0
    with pytest.raises(InputError):
        stretch_residual_deg(0.1, 10.0, order=1)


def test_the_figure_for_the_30_m_car_against_a_hand_calculation():
    scen = Scenario(**AUTO24_SLOW)
    # the verdict's five points: 10 cells apart, the outer ones 2 steps = 20 range cells of δr
    assert verdict_scene_half_depth_m(scen) == pytest.approx(20 * 0.1, rel=1e-12)
    sv = range_space_variance(scen, 62.0)
    eps = 2.0 / 30.0
    hand = ((1 + eps) ** 2 - 1) * 62.0  # 8.54°
    assert sv.depth_fraction == pytest.approx(eps, rel=1e-12)
    assert sv.residual_deg == pytest.approx(hand, rel=1e-12)
    lam = 299_792_458.0 / 24.125e9
    assert sv.differential_range_m == pytest.approx(lam / (4 * math.pi) * math.radians(hand), rel=1e-9)
    assert sv.limit_deg == 1.0 and sv.material
    # the limit is the acceptance's on phase PGA cannot remove; seed 004's 1° when none is set
    assert range_space_variance(scen, 62.0, options=McOptions(max_residual_phase_rms_deg=20.0)).material is False
    assert range_space_variance(scen, 62.0, options=McOptions(max_residual_phase_rms_deg=None)).limit_deg == 1.0
    # ten times the range, the same depth and phase: ten times less (0.83°), not material
    far = range_space_variance(Scenario(**AUTO24_FAR), 62.0)
    assert far.residual_deg == pytest.approx(((1 + eps / 10) ** 2 - 1) * 62.0, rel=1e-12)
    assert not far.material


@pytest.mark.parametrize("order", [2, 3])
def test_a_range_line_holds_the_error_stretched_by_its_range_not_shifted_by_azimuth(order):
    """The mapping the figure rests on, measured on the formed image: a line-of-sight error
    a·uⁿ (u = 2t/T), the phase history of one target with and without it. Read with the
    centre line's bin-to-time mapping, a target 2 m nearer or farther keeps |(1 + ε)ⁿ − 1|·φ_rms
    (measured within 10 % of it: 3.5/3.9° against 3.6/3.8° for n = 2, 2.3/2.8° against 2.4/2.7°
    for n = 3); read with its own line's mapping ≤ 0.2° (asserted < 0.5°); a target 1 m off
    centre in azimuth keeps ≤ 0.35° with the centre's (asserted < 0.5°)."""
    scen = Scenario(**AUTO24_SLOW)
    g = SarGeometry.from_scenario(scen, window=McOptions().window_for(scen))
    los = g.scene_centre_m[None] - g.nominal_apc_m()
    los /= np.linalg.norm(los, axis=1, keepdims=True)
    u = 2 * g.pulse_times_s / g.aperture_time_s
    err = (2e-3 * u ** order)[:, None] * los
    psi = residual_phase_rad(g, err, None)

    def residuals(x, d):
        scene = Scene(targets=[PointTarget(azimuth_m=x, range_m=d, amplitude=1.0, phase_rad=0.0)], snr_db=None)
        a = form_image(g, simulate_echoes(g, scene, err), np.zeros((g.n_pulses, 3)))
        b = form_image(g, simulate_echoes(g, scene, None), np.zeros((g.n_pulses, 3)))
        j = int(np.argmin(np.abs(a.slant_range_m - (g.ref_range_m + d))))
        t = np.fft.ifftshift(a.slow_time_of_bins_s())
        ok = np.abs(t) <= 0.45 * g.aperture_time_s
        o = np.argsort(t[ok])
        tt = t[ok][o]
        measured = np.unwrap(np.angle(sfft.ifft(a.data[:, j]) * np.conj(sfft.ifft(b.data[:, j])))[ok][o])
        basis = np.stack([np.ones_like(tt), tt], axis=1)

        def rms_deg(y):
            r = y - basis @ np.linalg.lstsq(basis, y, rcond=None)[0]
            return math.degrees(math.sqrt(float(np.mean(r ** 2))))

        centre = np.interp(tt, g.pulse_times_s, psi)
        own = np.interp(tt * (g.ref_range_m + d) / g.ref_range_m, g.pulse_times_s, psi)
        return rms_deg(measured - centre), rms_deg(measured - own), rms_deg(centre)

    for d in (-2.0, 2.0):
        by_centre, by_own, phi = residuals(0.0, d)
        predicted = stretch_residual_deg(d / g.ref_range_m, phi, order)
        assert by_centre == pytest.approx(predicted, rel=0.10)
        assert by_centre > 2.0 and by_own < 0.5
    assert residuals(1.0, 0.0)[0] < 0.5


def test_30_m_disagreement_names_space_variance_with_its_figure_not_the_filled_term():
    """STIM300 on the slow car at 30 m: the check passes, the Monte Carlo (32 trials, seed 1)
    passes 14 of 32 (0.44 [0.28, 0.61]; 0.39 with 64), failing on PSLR. The comparison names space
    variance with its figure (8.5° measured with 64 trials; asserted 4–15°, against the 1° limit)
    and says the filled gyro turn-on bias (1.7 deg/h; its margin 765 against the binding 5.4) is
    not the cause (measured: with it taken as 0 the Monte Carlo passes 0.33 of 64). On the points
    scene: on the realistic scene (the default) the spec is relative to what a perfect IMU gets
    there, whose clutter-limited PGA error already costs PSLR, and the Monte Carlo passes 0.94
    [0.80, 0.98] (32 trials), in agreement with the check."""
    scen, part = Scenario(**AUTO24_SLOW), get_part("STIM300")
    res = run_mc(scen, part, 32, 1, options=McOptions(scene="points"))
    rec = check_parts([part], scen).to_dict()["scenarios"][0]["parts"][0]
    assert rec["verdict"] == "pass"
    out = check_vs_mc(rec, res)
    assert out["agree"] is False and res.ci_after[1] < 0.9
    reasons = res.agg.failure_reasons()
    assert max(reasons, key=reasons.get) == "pslr"
    sv = out["space_variance"]
    assert sv["material"] and 4.0 < sv["residual_deg"] < 15.0
    assert sv["depth_fraction"] == pytest.approx(2.0 / 30.0, rel=1e-12)
    assert "This is space variance" in out["reason"] and "disagreement is expected" in out["reason"]
    assert f"{sv['residual_deg']:.2g}° rms" in out["reason"] and "D/R = 6.67%" in out["reason"]
    assert out["filled_terms_share"] < FILLED_SHARE_MATERIAL
    assert "gyro_bias_repeatability_deg_h = 1.732 deg/h) are not the cause" in out["reason"]
    assert "unspecified='zero'" not in out["reason"]


@pytest.mark.slow
def test_300_m_with_the_same_aperture_time_agrees_and_its_figure_is_not_material():
    """Same error statistics (same Tc and seed), ten times the range: the Monte Carlo passes all
    64 trials (1.00 [0.94, 1.00]: 32 would leave the interval straddling 0.9), nothing is to
    explain, and the figure is below the 1° limit (0.83°)."""
    scen, part = Scenario(**AUTO24_FAR), get_part("STIM300")
    res = run_mc(scen, part, 64, 1)
    rec = check_parts([part], scen).to_dict()["scenarios"][0]["parts"][0]
    out = check_vs_mc(rec, res)
    assert res.p_pass_after == 1.0 and out["agree"] is True and out["reason"] == ""
    sv = space_variance_of(res)
    assert sv.depth_fraction == pytest.approx(2.0 / 300.0, rel=1e-12)
    assert 0.1 < sv.residual_deg < 1.0 and not sv.material


@pytest.mark.slow
def test_a_disagreement_from_filled_terms_still_names_them():
    """A part whose figures are HG9900's but labelled consumer grade, its accelerometer bias
    left empty: the check passes on what is given; the Monte Carlo fills 125 mg from the consumer
    grade (and misalignments and VRW) and fails every trial of 32 on range migration, and with
    the empty terms taken as 0 it passes every trial. The comparison names the filled terms, with
    their rise of the part's use of the bounds, and does not call it space variance."""
    scen = get_preset("airborne_xband")
    part = PartSpec.model_validate({**get_part("HG9900").model_dump(), "part_id": "HG9900_CONSUMER",
                                    "grade": "consumer", "accel_bias_instability_ug": None})
    rec = check_parts([part], scen).to_dict()["scenarios"][0]["parts"][0]
    assert rec["verdict"] == "pass"
    filled = run_mc(scen, part, 32, 1)
    zero = run_mc(scen, part, 32, 1, options=McOptions(unspecified="zero"))
    assert filled.p_pass_after == 0.0 and zero.p_pass_after == 1.0
    out = check_vs_mc(rec, filled)
    assert out["agree"] is False
    assert out["filled_terms_share"] > 100.0  # measured 1788-fold
    assert "It filled datasheet terms the check leaves out" in out["reason"]
    assert "accel_bias_instability_ug = 1.25e+05 µg" in out["reason"] and "-fold" in out["reason"]
    assert "space variance" not in out["reason"]


def test_filled_terms_share_against_a_hand_calculation():
    """One given term (ARW 0.002 deg/√h) and one filled (accelerometer bias 50 µg, a total 1σ
    bias): share = √((b/B)² + (w/W)²) / (w/W) − 1 with B, W the paper bounds at the scenario's Tc
    and δr (datasheet units)."""
    scen = get_preset("airborne_xband")
    base = {k: None for k in get_part("HG9900").model_dump()
            if k.endswith(("_ppm", "_mrad", "_deg_h", "_rt_h", "_ug", "_rt_hz"))}
    spec = PartSpec.model_validate({**get_part("HG9900").model_dump(), **base, "gyro_arw_deg_rt_h": 0.002,
                                    "accel_bias_instability_ug": 50.0})
    mc = SimpleNamespace(model_spec=spec.model_dump(mode="json"), scenario=scen, options=None,
                         extra={"unspecified_terms": {"filled": [
                             {"column": "accel_bias_instability_ug", "value": 50.0, "unit": "µg"}]}})
    ds = paper_bounds(np.array([scen.tc_s]), scen.range_resolution_m).datasheet()
    b = 50.0 / float(np.ravel(ds["accel_bias_ug"])[0])
    w = 0.002 / float(np.ravel(ds["gyro_arw_deg_rt_h"])[0])
    assert filled_terms_share(mc) == pytest.approx(math.hypot(b, w) / w - 1.0, rel=1e-9)
    # nothing filled, or a result that does not say what it simulated: no share
    assert filled_terms_share(SimpleNamespace(model_spec=None, scenario=scen, extra={})) is None
