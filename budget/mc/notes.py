"""What a Monte Carlo verdict was judged on, in words: the notes of ``McResult.judged_on``.

Everything the user could not know from their inputs is stated beside the numbers: how the track
was navigated, what image-domain PGA leaves on a wideband radar or sonar, what the single-receiver
simulation leaves out, the IMU rate, the platform motion and the lever arm flown, the scenario
keys taken at their defaults, the acceptance applied, and the Earth model. The setup's own notes
are :meth:`budget.mc.chain.ChainSetup.describe`; :func:`run_notes` adds the run's.
"""

from __future__ import annotations

import math

from ..aiding_spec import AidingPlan
from ..imu.noise_model import as_noise_model_si
from ..motion.flat_earth import earth_model
from ..motion.cost import aperture_samples
from ..motion.notes import FEW_SAMPLES, imu_rate_note, lever_arm_note
from ..nav.manoeuvre import PlatformMotion
from ..sar import SarGeometry
from ..scenario import TC_KEYS, Scenario
from ..units import G0
from .options import McOptions

#: Keys of :meth:`budget.mc.chain.ChainSetup.describe` holding what the simulation itself assumed
#: (a wideband radar or sonar under image-domain PGA, range ambiguity, a squint simulated as its
#: broadside equivalent), present only when they apply: every consumer shows them.
SIMULATION_NOTES = ("wideband_note", "ambiguity_note", "squint_note")


def navigation_note(scenario: Scenario) -> str:
    """How the track the image is formed with was navigated (:mod:`budget.motion.engine`): free
    inertial from an alignment at the aperture start (seed 004's assumption: every bias and
    scale-factor term then grows over Tc unchecked), or aided by the scenario's sensors."""
    plan = AidingPlan.from_scenario(scenario)
    if not plan.aiding:
        return (f"free inertial over the aperture (Tc = {scenario.tc_s:.3g} s), aligned at its start; "
                "no aiding sensor in the scenario (its aiding section bounds the drift)")
    return f"aided: {plan.label()}"


# fractional bandwidth above which the result states what image-domain PGA leaves across the band
WIDEBAND_NOTE_FRACTION = 0.10


def wideband_note(geom: SarGeometry) -> str:
    """What image-domain PGA cannot remove at this fractional bandwidth b = B_r/f0, or '' when
    b ≤ :data:`WIDEBAND_NOTE_FRACTION`. The echoes carry the residual line-of-sight error Δr as
    4π (f0 + f) Δr / c at every range frequency (:mod:`budget.sar.echoes`), while PGA estimates
    one phase per azimuth bin, the band centre's; it leaves (f/f0 − 1)·φ, of rms b/√12 · φ over a
    uniform band, as range-dependent defocus. The verdict after PGA is therefore that of an
    image-domain autofocus; a wavenumber-domain autofocus, estimating Δr itself, would remove it."""
    b = geom.range_bandwidth_hz / geom.carrier_frequency_hz
    if b <= WIDEBAND_NOTE_FRACTION:
        return ""
    return (f"fractional bandwidth {100 * b:.0f} %: PGA corrects one phase per azimuth bin (the band centre's) "
            f"and leaves {100 * b / math.sqrt(12):.1f} % rms of the phase error across the band (range-dependent "
            "defocus), which the verdict after PGA includes; a wavenumber-domain autofocus would remove it")


def range_ambiguity_note(geom: SarGeometry) -> str:
    """What the simulation leaves out when one pulse in flight cannot sample the aperture, or ''.
    The pulses must sample a target's Doppler band, PRF ≥ B_a = 2V²T/(λR) (:mod:`budget.sar.geometry`),
    while an echo from range R returns only after 2R/c, so one pulse in flight allows
    PRF ≤ c/(2R). When B_a > c/(2R) (a synthetic-aperture sonar at 100 m, a radar at very long
    range) a real system flies several pulses in flight or a multi-element receiver; the
    simulation forms the image from every pulse at its own PRF and models neither range
    ambiguities nor the receiver array."""
    limit = geom.c_m_s / (2.0 * geom.ref_range_m)
    if geom.doppler_bandwidth_hz <= limit:
        return ""
    return (f"one pulse in flight cannot sample this aperture: its Doppler band needs a PRF ≥ "
            f"{geom.doppler_bandwidth_hz:.3g} Hz, the range {geom.ref_range_m:.4g} m allows ≤ c/(2R) = "
            f"{limit:.3g} Hz; a real system uses several pulses in flight or a multi-element receiver, "
            f"which the simulation (one receiver at PRF {geom.prf_hz:.3g} Hz) does not model, nor range "
            "ambiguities")


#: The defaulted scenario keys a trial is simulated with that no other note of the verdict states
#: (the IMU rate and the lever arm have their own: :func:`imu_rate_note`, :func:`lever_arm_note`).
SIMULATED_DEFAULT_KEYS = TC_KEYS + ("depression_deg",)


def platform_motion_note(scenario: Scenario, motion: PlatformMotion | None = None) -> str:
    """What the simulated platform does (:meth:`PlatformMotion.describe`; default straight, level,
    unrotated flight, where the IMU's gyro scale factor and misalignment act on a zero rate) and,
    in straight flight, the scenario's manoeuvre levels (``platform_rate_deg_s``,
    ``platform_accel_m_s2``) that the analytic bounds use and the simulation does not fly."""
    motion = motion or PlatformMotion()
    text = motion.describe(scenario)
    if motion.kind != "straight":
        return text
    extra = []
    if scenario.platform_rate_deg_s > 0:
        extra.append(f"platform_rate_deg_s = {scenario.platform_rate_deg_s:g}")
    if abs(scenario.platform_accel_m_s2 - G0) > 1e-6 * G0:
        extra.append(f"platform_accel_m_s2 = {scenario.platform_accel_m_s2:g}")
    if extra:
        verb = "are" if len(extra) > 1 else "is"
        text += (f"; the scenario's {' and '.join(extra)} (used by the analytic bounds) {verb} not simulated "
                 "(McOptions.platform_motion, --platform-motion: oscillation or attitude_change flies a rotation)")
    return text



def acceptance_note(options: McOptions) -> str:
    """The limits a trial is judged against (:class:`McOptions`), in words: what "pass" meant."""
    a = options.acceptance
    pslr = f"PSLR ≤ {a.max_pslr_db:g} dB" if a.max_pslr_db is not None else \
        f"PSLR ≤ the window's ideal + {a.pslr_margin_db:g} dB"
    islr = f"ISLR ≤ {a.max_islr_db:g} dB" if a.max_islr_db is not None else \
        f"ISLR ≤ the window's ideal + {a.islr_margin_db:g} dB"
    parts = [f"3 dB broadening ≤ {100 * a.max_broadening:g} %", pslr, islr,
             f"peak loss ≤ {a.max_peak_loss_db:g} dB ({' and '.join(a.axes)} cuts)"]
    # at the verdict's 1000 cells a shift is geolocation, not focus: only a response that left
    # the simulated scene fails it, which the note must say (a "not judged" counted failures)
    parts.append("peak shift ≤ 1000 cells (geolocation, not focus: only a response that has left the "
                 "simulated scene fails it)" if a.max_peak_shift_cells >= 1000.0 else
                 f"peak shift ≤ {a.max_peak_shift_cells:g} cells")
    cells = options.max_range_migration_cells
    parts.append("range migration not judged" if cells is None else f"range migration ≤ {cells:g} range cell(s)")
    deg = options.max_residual_phase_rms_deg
    parts.append("what PGA cannot remove not judged" if deg is None else
                 f"what PGA cannot remove ≤ {deg:g}° rms")
    return "acceptance: " + ", ".join(parts)


def earth_model_line(scenario: Scenario, model) -> str:
    """The navigation model's note for this run (:func:`budget.motion.flat_earth.earth_model_note`,
    as the motion engine writes it for the trials): flat-earth propagation with the size of what
    it leaves out over Tc, and the latitude and heading — the defaults, which the verdict does not
    let a user set — at which the Earth and transport rate turn an aided run's initial attitude
    error."""
    return earth_model(scenario, AidingPlan.from_scenario(scenario), as_noise_model_si(model), say_frame=True)[1]


def aiding_defaults_note(scenario: Scenario) -> str:
    """The aiding keys the scenario leaves at their defaults, with the value taken ('' without
    aiding sensors, or when every key is written): the section's ``aiding_mode`` and
    ``aiding_warmup_s`` and, per sensor, what its entry leaves out (a GNSS's ``latency_s`` 0,
    ``correlated_sigma_m`` 0 — white position noise only, the optimistic case — its antenna
    ``lever_arm_m`` …). The aided verdict rests on them as it does on the sensor's own figures."""
    if not scenario.aiding:
        return ""
    parts = [f"{k} = {getattr(scenario, k)}" for k in ("aiding_mode", "aiding_warmup_s")
             if k not in scenario.model_fields_set]
    if scenario.aiding_mode == "feedforward" and "aiding_blend_time_s" not in scenario.model_fields_set:
        parts.append(f"aiding_blend_time_s = 5·Tc = {5 * scenario.tc_s:.3g} s")
    for i, sensor in enumerate(scenario.aiding):
        unset = [k for k in type(sensor).model_fields if k != "type" and k not in sensor.model_fields_set]
        if unset:
            values = ", ".join(f"{k} = {list(v) if isinstance(v, tuple) else v}"
                               + (" (white position noise only)" if k == "correlated_sigma_m" and v == 0 else "")
                               for k in unset for v in [getattr(sensor, k)])
            parts.append(f"aiding[{i}] ({sensor.type}): {values}")
    if not parts:
        return ""
    return f"{scenario.name}: aiding keys not in the scenario, taken at their defaults: " + "; ".join(parts)


#: Resolution reached ÷ the scenario's δℓ beyond which the Monte Carlo says its window and the
#: scenario's window_broadening disagree.
WINDOW_MISMATCH_RATIO = 1.05


def resolution_reached(scenario: Scenario, options: McOptions) -> dict[str, float]:
    """The resolution the verdict's image reaches (m) with its window (:meth:`McOptions.window_for`):
    w/a_w · δℓ in azimuth and w/a_w · δr in range, w the window's 3 dB width in cells
    (:func:`budget.sar.windows.ideal_irf`; 0.886 rect, 1.18 Taylor −35 dB, n̄ = 4) and a_w the
    scenario's ``window_broadening`` (:func:`window_resolution_note`); ``ratio`` = w/a_w."""
    from ..sar.windows import ideal_irf

    ratio = ideal_irf(options.window_for(scenario)).width_3db_cells / scenario.window_broadening
    return {"azimuth_m": ratio * scenario.azimuth_resolution_m, "range_m": ratio * scenario.range_resolution_m,
            "ratio": ratio}


def scenario_notes_text(scenario: Scenario) -> str:
    """:meth:`Scenario.notes` (what the scenario's numbers hold that the tool does not model:
    a spaceborne speed at which level flight's specific force is not g, a long lever arm …) in
    one line, '' when there is none: stated in every result, not only as a Python warning."""
    return "; ".join(scenario.notes())


def window_resolution_note(scenario: Scenario, options: McOptions) -> str:
    """What resolution the verdict's image reaches when its window is broader than the scenario's
    ``window_broadening`` a_w sizes the aperture for ('' when within :data:`WINDOW_MISMATCH_RATIO`).

    The aperture (Tc = a_w λ R / (2 δℓ V sin θ), seed 004 (5)) and the range bandwidth a_w c/(2 δr)
    give one resolution cell of δℓ/a_w and δr/a_w; a window whose 3 dB width is w cells (0.886 for
    rect, 1.18 for Taylor −35 dB, n̄ = 4) then resolves w/a_w·δℓ and w/a_w·δr. The image metrics are
    judged against that window's own ideal, so the verdict holds, but for that window the
    scenario's δℓ needs a_w = w (a longer Tc, tighter bounds)."""
    from ..sar.windows import ideal_irf

    window = options.window_for(scenario)
    w = ideal_irf(window).width_3db_cells
    ratio = w / scenario.window_broadening
    if ratio <= WINDOW_MISMATCH_RATIO:
        return ""
    return (f"resolution reached: the {window.label} image's 3 dB width is {w:.3g} cells, and the scenario's "
            f"window_broadening a_w = {scenario.window_broadening:g} sizes a cell as δℓ/a_w: azimuth "
            f"{ratio * scenario.azimuth_resolution_m:.3g} m and range {ratio * scenario.range_resolution_m:.3g} m, "
            f"{ratio:.2f}× the δℓ = {scenario.azimuth_resolution_m:g} m and δr = {scenario.range_resolution_m:g} m "
            f"asked for; window_broadening = {w:.3g} gives them with this window (Tc {ratio:.2f}× longer, "
            f"{scenario.tc_s * ratio:.3g} s, and seed 004's bounds tighter by Tc² … Tc³)")


def run_notes(scenario: Scenario, options: McOptions, model) -> dict[str, str]:
    """The notes of one run beside the setup's (:meth:`~budget.mc.chain.ChainSetup.describe`):
    IMU rate, platform motion, lever arm, scenario and aiding defaults (when any), the scenario's
    own notes (:func:`scenario_notes_text`, when any), acceptance, Earth model."""
    notes = {"imu_rate": imu_rate_note(scenario, getattr(model, "rate_hz", None)),
             "platform_motion": platform_motion_note(scenario, options.platform_motion),
             "lever_arm": lever_arm_note(scenario)}
    if defaults := scenario.defaults_note(SIMULATED_DEFAULT_KEYS):
        notes["scenario_defaults"] = defaults
    if aiding := aiding_defaults_note(scenario):
        notes["aiding_defaults"] = aiding
    if window := window_resolution_note(scenario, options):
        notes["window_resolution"] = window
    if caveats := scenario_notes_text(scenario):
        notes["scenario_notes"] = "scenario: " + caveats
    notes["acceptance"] = acceptance_note(options)
    notes["earth_model"] = earth_model_line(scenario, model)
    if fast := fast_phase_note(scenario, options, model):
        notes["fast_phase_prediction"] = fast
    return notes


def fast_phase_note(scenario: Scenario, options: McOptions, model) -> str:
    """The analytic share of apertures whose phase beyond PGA's window stays within the limit
    for this part (:func:`budget.mc.consistency.fast_phase_share`), for a free-inertial run
    without a pre-filter (the prediction's assumptions); '' otherwise or when the part leaves
    no VRW or ARW."""
    if scenario.aiding or options.prefilter != "none":
        return ""
    from ..bounds import scenario_fast_phase

    try:
        fr = scenario_fast_phase(scenario, model.to_si())
    except (AttributeError, TypeError, ValueError):  # a model in SI without the terms
        return ""
    if not fr.total_deg > 0:
        return ""
    n = aperture_samples(scenario)
    sampled = (f"; continuous-time noise, where the simulation's {n} IMU samples over the aperture carry less "
               "(see the IMU rate)") if n < FEW_SAMPLES else ""
    return (f"analytic: {fr.p_within_limit():.3f} of apertures keep the phase beyond PGA's window within "
            f"{fr.limit_deg:g}° ({fr.total_deg:.3g}° rms from VRW and ARW, free inertial{sampled}) — the most the "
            "fast phase lets pass where PGA keeps no fast-phase band, as on the realistic scene")
