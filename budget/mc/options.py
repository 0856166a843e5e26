"""What a user sets for a Monte Carlo verdict (pydantic: validated, JSON-serialisable)."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from ..noise.prefilter import KINDS as PREFILTER_KINDS
from ..sar.acceptance import Acceptance

#: IMU pre-filter choices of the trial chain (``budget.noise.prefilter``).
PREFILTERS = ("none", *PREFILTER_KINDS)

#: Image acceptance for the verdict: as :class:`~budget.sar.acceptance.Acceptance`, except that a
#: peak shift is not a focus failure (constant and linear phase only move the image, DESIGN.md §4).
VERDICT_ACCEPTANCE = Acceptance(max_peak_shift_cells=1000.0)


class McOptions(BaseModel):
    """Options of the trial chain and of the run.

    ``chunk_trials`` fixes the unit of work (a multiple of the motion engine's random-stream
    block of 64 trials), so results do not depend on ``workers`` or the backend.
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    acceptance: Acceptance = VERDICT_ACCEPTANCE
    max_range_migration_cells: float | None = Field(
        1.0, gt=0, description="fail when the peak LOS error exceeds this many range cells δr "
                               "(PGA cannot undo range migration); None disables")
    max_residual_phase_rms_deg: float | None = Field(
        1.0, gt=0, description="fail when the fast phase error (beyond a smooth order-10 Legendre "
                               "fit, which PGA removes) exceeds this rms (seed 004: ≤ 1°); None "
                               "judges by the image alone")
    pga_kernel: Literal["ml", "lumv"] = "ml"
    pga_max_iter: int = Field(30, ge=1, le=200)
    pga_tol_rad: float = Field(0.005, gt=0, le=0.5, description="PGA stops when the estimate changes "
                               "by less than this rms (tighter than the 1° verdict limit)")
    image_method: Literal["rda", "backprojection"] = "rda"
    prefilter: Literal[PREFILTERS] = Field(
        "none", description="seed 000's ARMA-Kalman filtering of the IMU output before navigation: "
                            "none, the real-time filter (kalman) or the RTS smoother (rts); the ARMA "
                            "models are fitted on a simulated static record of the part")
    prefilter_calibration_samples: int = Field(16_384, ge=1024, le=1 << 20,
                                               description="length of that static record")
    snr_db: float | None = Field(None, description="receiver noise; None = noise-free echoes")
    chunk_trials: int = Field(64, ge=64, le=65536, multiple_of=64)
    keep_worst: int = Field(5, ge=0, le=100)
    keep_trial_metrics: bool = Field(True, description="keep per-trial metric lists (memory grows "
                                                       "with trials; sweeps turn it off)")
