"""What a user sets for a Monte Carlo verdict (pydantic: validated, JSON-serialisable).

The acceptance spec (what "pass" means) is the user's image-quality requirement. Defaults and
where they come from:

* image (:class:`~budget.sar.acceptance.Acceptance`): 3 dB broadening ≤ 10 %, PSLR and ISLR ≤
  the window's ideal + 3 dB (or absolute ``max_pslr_db`` / ``max_islr_db``), peak loss ≤ 1.5 dB
  — engineering rules stated in :mod:`budget.sar.acceptance`; a peak *shift* is geolocation, not
  focus (constant and linear phase only move the image), so the verdict allows 1000 cells: only
  a response that has left the simulated scene fails it;
* ``max_range_migration_cells`` = 1: seed 004 budgets every error within one range cell δr,
  because PGA (an azimuth-phase correction) cannot undo range-cell migration;
* ``max_residual_phase_rms_deg`` = 1°: seed 004's limit on random phase PGA cannot remove
  (≤ 1° rms; it moves σ² ≈ −35 dB of the main-lobe energy into sidelobes), applied to the PGA
  residual beyond its settled window (:mod:`budget.sar.residual`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from ..catalog.fill import DEFAULT_POLICY as UNSPECIFIED_DEFAULT, POLICIES as UNSPECIFIED_POLICIES
from ..errors import from_validation_error, refuse_bool_numbers
from ..nav.manoeuvre import PlatformMotion
from ..noise.prefilter import KINDS as PREFILTER_KINDS
from ..sar.acceptance import Acceptance
from ..sar.windows import Window, verdict_window

#: Default trials and seed of a verdict: the same in the CLI (``mc``, ``sweep``, ``report``), the
#: dashboard and the top-level API, so one part gives one number everywhere. 64 trials = one
#: chunk; the 95 % Wilson interval of P = 1 is then [0.94, 1].
DEFAULT_TRIALS = 64
DEFAULT_SEED = 1

#: IMU pre-filter choices of the trial chain (``budget.noise.prefilter``).
PREFILTERS = ("none", *PREFILTER_KINDS)

#: Image acceptance for the verdict: as :class:`~budget.sar.acceptance.Acceptance`, except that a
#: peak shift is not a focus failure (constant and linear phase only move the image), so only a
#: shift of 1000 cells — a response that has left any simulated scene — fails it.
VERDICT_ACCEPTANCE = Acceptance(max_peak_shift_cells=1000.0)

#: Keys of a user's acceptance spec that are verdict limits of :class:`McOptions`, not image
#: levels of :class:`~budget.sar.acceptance.Acceptance` (``--acceptance A.json`` holds both).
VERDICT_LIMIT_KEYS = ("max_range_migration_cells", "max_residual_phase_rms_deg")


def verdict_acceptance(spec=None, base: Acceptance | None = None) -> dict:
    """The image acceptance of a Monte Carlo verdict from a user's (possibly partial) spec: the
    keys the spec sets over ``base`` (default :data:`VERDICT_ACCEPTANCE`, the verdict's own
    defaults — a peak shift of up to 1000 cells — not :class:`Acceptance`'s, whose 1 cell suits
    a single image's :func:`~budget.sar.acceptance.evaluate`), as a dict of Acceptance fields.

    ``spec``: a mapping of Acceptance keys, or an :class:`Acceptance` (its explicitly set fields,
    ``model_fields_set``, are the spec: ``Acceptance(max_broadening=0.2)`` loosens the broadening
    only). The one merge of the API (``acceptance=`` of :func:`budget.run_mc` / :func:`budget.sweep`,
    :class:`McOptions` built from a mapping) and of ``sar-budget mc --acceptance`` (which merges
    the same way). Keys of :data:`VERDICT_LIMIT_KEYS` are not Acceptance's: see
    :func:`acceptance_spec_options`."""
    base = VERDICT_ACCEPTANCE if base is None else base
    if spec is None:
        given = {}
    elif isinstance(spec, Acceptance):
        given = spec.model_dump(include=set(spec.model_fields_set))
    else:
        given = dict(spec)
    return {**base.model_dump(), **given}


def acceptance_spec_options(spec: Mapping, base: Acceptance | None = None) -> dict:
    """:class:`McOptions` fields of a user's acceptance spec (the ``--acceptance`` JSON, or the
    ``acceptance=`` mapping of the API): ``acceptance`` merged over the verdict's defaults
    (:func:`verdict_acceptance`) and each key of :data:`VERDICT_LIMIT_KEYS` as its own field."""
    spec = dict(spec)
    out = {k: spec.pop(k) for k in VERDICT_LIMIT_KEYS if k in spec}
    out["acceptance"] = verdict_acceptance(spec, base)
    return out

#: Realistic-scene defaults: clutter 25 dB below the strongest target (CTR 25 dB) and SNR 30 dB
#: per image pixel, the levels PGA was measured against on clutter (``benchmarks/bench_pga.py``).
REALISTIC_CLUTTER_DB = -25.0
REALISTIC_SNR_DB = 30.0


class McOptions(BaseModel):
    """Options of the trial chain and of the run.

    ``chunk_trials`` fixes the unit of work (a multiple of the motion engine's random-stream
    block of 64 trials), so results do not depend on ``workers`` or the backend. Build from user
    input with :meth:`build` (errors become :class:`~budget.errors.InputError`).
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    acceptance: Acceptance = VERDICT_ACCEPTANCE
    max_range_migration_cells: float | None = Field(
        1.0, gt=0, allow_inf_nan=False,
        description="fail when the peak LOS error exceeds this many range cells δr "
                    "(PGA cannot undo range migration); None disables")
    max_residual_phase_rms_deg: float | None = Field(
        1.0, gt=0, allow_inf_nan=False,
        description="fail when what PGA cannot remove — (estimate − truth) beyond its settled "
                    "window, budget.sar.residual — exceeds this rms (seed 004: ≤ 1°); None judges "
                    "by the image alone")
    scene: Literal["auto", "realistic", "points"] = Field(
        "realistic", description="realistic (the default): clutter + receiver noise + many dominant "
                                 "scatterers (PGA runs on it; the metrics on five clutter-free points "
                                 "focused with its estimate), what PGA meets in practice; points: five "
                                 "noise-free points, PGA's best case (there its fast-phase stage also "
                                 "estimates beyond its window, which it cannot on clutter: ADIS16405 on "
                                 "airborne X band passes the points scene and fails the realistic one, "
                                 "README, Monte Carlo section); auto: realistic")
    scene_reference: Literal["perfect_imu", "none"] = Field(
        "perfect_imu", description="on a scene with clutter or receiver noise, judge the image and the "
                                   "PGA residual relative to what a perfect IMU gets on the same scene "
                                   "(PGA's own clutter-limited error; budget.mc.reference) rather than "
                                   "to the ideal response; none: the spec is applied as it is")
    clutter_to_target_db: float = Field(REALISTIC_CLUTTER_DB, ge=-80, le=0, allow_inf_nan=False,
                                        description="realistic scene: clutter pixel power over target peak")
    snr_db: float | None = Field(None, ge=-20, le=150, allow_inf_nan=False,
                                 description="receiver noise; None = 30 dB on the realistic scene, "
                                             "noise-free on the points scene")
    n_scatterers: int | None = Field(None, ge=1, le=200, description="dominant scatterers of the realistic "
                                                                     "scene (None: one per 3 range cells, 16)")
    scene_seed: int = Field(0, ge=0, description="seed of the realistic scene's layout and clutter "
                                                 "(the same scene for every trial)")
    defocus_room_cells: Literal["auto"] | float = Field(
        "auto", description="how far a motion error may move a response in azimuth beyond the "
                            "scene and stay in the simulated image and its PRF, resolution cells "
                            "(0 … 1024; budget.sar.SarGeometry); auto: sized by run_mc from the "
                            "part's errors (budget.mc.defocus; said in the result's judged_on), 0 "
                            "for a setup built without a part")
    window: Literal["auto", "rect", "taylor"] = Field(
        "auto", description="azimuth/range weighting: auto = Taylor −35 dB, n̄ = 4 for radar (what an "
                            "imaging radar uses), the scenario's own choice for sonar")
    platform_motion: PlatformMotion = Field(
        PlatformMotion(), description="what the platform does over the aperture (budget.nav.manoeuvre): "
                                      "straight (default; gyro scale factor and misalignment then have "
                                      "no effect), oscillation, attitude_change or a custom disturbance")
    pga_kernel: Literal["ml", "lumv"] = "ml"
    pga_max_iter: int = Field(30, ge=1, le=200)
    pga_tol_rad: float | None = Field(None, gt=0, le=0.5, allow_inf_nan=False,
                                      description="PGA stop tolerance; None = PGA's own default")
    pga_second_pass: bool = Field(True, description="run PGA again on its own corrected image after a correction "
                                                     "of more than π rad rms from a clutter-limited start, kept "
                                                     "when the image is sharper (budget.sar.pga, 'Second pass'); "
                                                     "False: one pass")
    image_method: Literal["rda", "backprojection"] = "rda"
    prefilter: Literal[PREFILTERS] = Field(
        "none", description="seed 000's ARMA-Kalman filtering of the IMU output before navigation: "
                            "none, the real-time filter (kalman) or the RTS smoother (rts); the ARMA "
                            "models are fitted on a simulated static record of the part")
    prefilter_calibration_samples: int = Field(16_384, ge=1024, le=1 << 20,
                                               description="length of that static record")
    unspecified: Literal[UNSPECIFIED_POLICIES] = Field(
        UNSPECIFIED_DEFAULT, description="what to do with a part's empty datasheet terms "
                                         "(budget.catalog.fill): fill_grade_typical, refuse or zero")
    chunk_trials: int = Field(64, ge=64, le=65536, multiple_of=64)
    keep_worst: int = Field(5, ge=0, le=100)
    keep_trial_metrics: bool = Field(True, description="keep per-trial metric lists (memory grows "
                                                       "with trials; sweeps turn it off)")

    _no_bool_numbers = field_validator("*", mode="before")(refuse_bool_numbers)

    @model_validator(mode="before")
    @classmethod
    def _partial_acceptance(cls, data):
        """A partial ``acceptance`` (a mapping, or an Acceptance with some fields set) is completed
        from the verdict's defaults (:func:`acceptance_spec_options`), never from Acceptance's own
        (a peak shift of 1 cell would fail most trials on geolocation, not focus); verdict limits
        in it (:data:`VERDICT_LIMIT_KEYS`) become their fields, unless also given as fields."""
        if not isinstance(data, Mapping) or "acceptance" not in data:
            return data
        acc = data["acceptance"]
        if isinstance(acc, Acceptance):
            return {**data, "acceptance": Acceptance(**verdict_acceptance(acc))}
        if not isinstance(acc, Mapping):
            return data  # pydantic says what is wrong with it
        merged = acceptance_spec_options(acc)
        both = [k for k in VERDICT_LIMIT_KEYS if k in merged and k in data and data[k] != merged[k]]
        if both:
            raise ValueError(f"{both[0]} given twice, in the acceptance spec and as an option, with different values")
        return {**data, **merged}

    @field_validator("defocus_room_cells")
    @classmethod
    def _room_in_range(cls, v):
        if v != "auto" and not (isinstance(v, float) and 0.0 <= v <= 1024.0):
            raise ValueError("expected 'auto' or a number of resolution cells in 0 … 1024")
        return v

    @classmethod
    def build(cls, **kwargs) -> "McOptions":
        """Validated construction raising :class:`~budget.errors.InputError` naming the field."""
        try:
            return cls(**kwargs)
        except ValidationError as err:
            raise from_validation_error(err) from None

    def window_for(self, scenario) -> Window:
        """The window the verdict images ``scenario`` with (:func:`budget.sar.windows.verdict_window`)."""
        return verdict_window(scenario, self.window)

    @property
    def rotation_for_check(self) -> PlatformMotion | None:
        """The motion the analytic check should judge the gyro scale factor and misalignment on
        beside this Monte Carlo: the one it flies when that rotates the body, else None (the
        check keeps the bounds' own 1-rad attitude change)."""
        return self.platform_motion if self.platform_motion.rotates else None
