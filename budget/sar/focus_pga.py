"""Autofocus of a real ground image: PGA's estimate per pulse, sharpness, and the recorded solution.

:func:`focus` forms the image (:mod:`budget.sar.focus`) and applies one of three policies:

* ``"pga"``: :func:`budget.sar.pga.pga` on the deramped image, exactly as the verdict runs it
  (default settings; its returned image, corrected with its own estimate, is the "after" image);
* ``"recorded"``: the provider's solution applied to the phase history and the image re-formed;
* ``"none"``: the image as formed.

Estimate per pulse. PGA estimates φ(ω) on the image's azimuth-frequency bins; pulse n sits on bin
ω_n (:mod:`budget.sar.focus`, eq. 3), so ψ̂_n = φ(ω_n) by linear interpolation. Constant and linear
terms are removed (least squares over the pulses on bins PGA estimated): a constant phase is
invisible and a linear one only shifts the image. The correction applied is exp(−jψ̂_n).

Comparison with the recorded solution, phase errors in the same sign (the error the data carry:
a correction multiplies by its negative): ψ_rec,n = −(χ_n − 4π f_r ΔR_n / c)
(:mod:`budget.sar.phase_history`). Reported, all beyond a constant + linear term in pulse number:

* ``recorded_af_rms_diff_rad``: rms(ψ̂ − ψ_rec) over the pulses PGA estimated;
* the same against ψ_rec low-passed to PGA's bandwidth: PGA's settled window of W azimuth samples
  passes only components of fewer than W·n_ap / (2 n) cycles over an aperture of n_ap of the n bins
  (Wahl et al. 1994, §III); faster parts of ψ_rec cannot be seen by PGA on this image. What PGA
  sees is ψ_rec less :func:`budget.sar.residual.highpass_phase` (the Monte Carlo's definition:
  Legendre terms to the cubic and DCT-II cosines below that number of cycles, fitted together;
  a DCT truncation alone leaks ≈ 7 % of a 1.4 rad smooth error beyond the cut, from the even
  extension's kinks at the ends, measured): ``rms_diff_slow_rad`` = rms(ψ̂ − slow(ψ_rec)), which
  counts the estimate's own content beyond the bandwidth as error and so can exceed the whole
  difference when ψ̂ follows part of ψ_rec's faster content;
* ``rms_diff_in_band_rad``: the part of the difference ψ̂ − ψ_rec within that bandwidth
  (the same low-pass applied to the difference: a projection, never above ``rms_diff_rad``
  by more than the constant + linear refit).

Injection experiments (:meth:`~budget.sar.phase_history.PhaseHistory.with_phase_error`): the data
then carry ψ_rec + ψ_inj, so the same numbers are also reported against that known error
(``comparison["known"]``, with ``reference`` saying what it holds: "recorded + injected", or
"injected" for files without a recorded solution). Against ψ_rec alone the injected error would
count as a difference.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import InputError
from .acquisition import Acquisition, describe_acquisition
from .focus import FocusOptions, GroundImage, form_ground_image
from .sharpness import image_contrast, image_entropy
from .pga import pga
from .phase import remove_linear
from .phase_history import PhaseHistory
from .residual import highpass_phase

AUTOFOCUS_MODES = ("pga", "none", "recorded")


def pulse_estimate(image: GroundImage, phase_error_bins_rad: np.ndarray,
                   estimated_bins: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """PGA's estimate (centred bins) mapped to pulses: (ψ̂_n beyond linear, rad; mask of the pulses
    whose bin PGA estimated). Pulses outside that mask carry the interpolated value, NaN-free."""
    w = image.bin_rad_m
    psi = np.interp(image.pulse_bin_rad_m, w, np.asarray(phase_error_bins_rad, dtype=float))
    sup = np.asarray(estimated_bins, dtype=bool)
    lo, hi = (w[sup].min(), w[sup].max()) if sup.any() else (w[0], w[-1])
    mask = (image.pulse_bin_rad_m >= lo) & (image.pulse_bin_rad_m <= hi)
    if mask.sum() < 3:
        mask = np.ones_like(mask)
    return _beyond_linear(psi, mask), mask


def _beyond_linear(phi: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """φ minus the least-squares constant + linear term in pulse number fitted over ``mask``,
    evaluated on every pulse."""
    k = np.arange(phi.size, dtype=float)
    coef = np.polyfit(k[mask], phi[mask], 1)
    return phi - np.polyval(coef, k)


def _rms(x: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.asarray(x, dtype=float) ** 2)))


def compare_with_recorded(estimate_rad: np.ndarray, recorded_rad: np.ndarray, mask: np.ndarray,
                          bandwidth_cycles: float | None) -> dict:
    """Numbers of the comparison (module docstring), rad rms beyond constant + linear."""
    rec = _beyond_linear(np.asarray(recorded_rad, dtype=float), mask)
    est = np.asarray(estimate_rad, dtype=float)
    out = {"recorded_beyond_linear_rms_rad": _rms(rec[mask]),
           "estimate_beyond_linear_rms_rad": _rms(_beyond_linear(est, mask)[mask]),
           "rms_diff_rad": _rms(remove_linear(est - rec, mask)[mask])}
    if bandwidth_cycles is not None:
        slow = _beyond_linear(rec - highpass_phase(rec, bandwidth_cycles), mask)
        out.update({"pga_bandwidth_cycles": float(bandwidth_cycles),
                    "recorded_slow_rms_rad": _rms(slow[mask]),
                    "recorded_fast_rms_rad": _rms((rec - slow)[mask]),
                    "rms_diff_slow_rad": _rms(remove_linear(est - slow, mask)[mask])})
        diff = remove_linear(est - rec, mask)
        out["rms_diff_in_band_rad"] = _rms(remove_linear(diff - highpass_phase(diff, bandwidth_cycles), mask)[mask])
    return out


@dataclass
class FocusResult:
    """Image before/after autofocus, the per-pulse phase-error estimate and the comparison."""

    autofocus: str
    before: GroundImage = field(repr=False)
    after: GroundImage = field(repr=False)
    phase_estimate_rad: np.ndarray = field(repr=False)  # per pulse, beyond linear; correction = −this
    estimated_pulses: np.ndarray = field(repr=False)
    recorded_phase_error_rad: np.ndarray | None = field(default=None, repr=False)  # beyond linear
    #: With an injected error: recorded + injected (or injected alone) per pulse, beyond linear.
    known_phase_error_rad: np.ndarray | None = field(default=None, repr=False)
    comparison: dict = field(default_factory=dict)
    pga: dict = field(default_factory=dict)
    timings_s: dict = field(default_factory=dict)
    options: dict = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    #: What the data are (band, aperture, closed-form resolutions) beside the image grid.
    acquisition: Acquisition | None = None

    @property
    def pulses(self) -> int:
        return int(self.phase_estimate_rad.size)

    @property
    def entropy_before(self) -> float:
        return image_entropy(self.before.data)

    @property
    def entropy_after(self) -> float:
        return image_entropy(self.after.data)

    @property
    def recorded_af_rms_diff_rad(self) -> float | None:
        return self.comparison.get("rms_diff_rad")

    def summary(self) -> str:
        """A few lines: what the data are (:meth:`Acquisition.summary`), autofocus, entropy and
        contrast before → after, PGA outcome, difference from the recorded solution."""
        s = self.scalars()
        diff = s["recorded_af_rms_diff_rad"]
        lines = [] if self.acquisition is None else [self.acquisition.summary()]
        lines += [f"autofocus {s['autofocus']} on {s['pulses']} pulses: entropy {s['entropy_before']:.5g} → "
                 f"{s['entropy_after']:.5g}, contrast {s['contrast_before']:.4g} → {s['contrast_after']:.4g}"]
        if self.pga:
            lines.append(f"PGA: {self.pga.get('reason')}; {self.pga.get('usable_lines')} usable lines")
        if diff is not None:
            lines.append(f"rms difference from the recorded solution {diff:.3g} rad")
        known = self.comparison.get("known")
        if known:
            lines.append(f"rms difference from the known error ({known['reference']}) {known['rms_diff_rad']:.3g} rad")
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)

    def scalars(self) -> dict:
        """The scalar outcome: entropy and contrast before/after, PGA, comparison, timings (s)."""
        return {"autofocus": self.autofocus, "pulses": self.pulses,
                "entropy_before": self.entropy_before, "entropy_after": self.entropy_after,
                "contrast_before": image_contrast(self.before.data), "contrast_after": image_contrast(self.after.data),
                "recorded_af_rms_diff_rad": self.recorded_af_rms_diff_rad,
                "phase_estimate_peak_to_peak_rad": float(np.ptp(self.phase_estimate_rad[self.estimated_pulses])),
                "comparison": dict(self.comparison), "pga": dict(self.pga), "timings_s": dict(self.timings_s),
                "notes": list(self.notes)}

    def to_frame(self) -> pd.DataFrame:
        """One row per pulse: azimuth bin ω_n (rad/m), estimate, recorded (rad, beyond linear)."""
        df = pd.DataFrame({"azimuth_frequency_rad_m": self.before.pulse_bin_rad_m,
                           "phase_estimate_rad": self.phase_estimate_rad, "estimated": self.estimated_pulses})
        if self.recorded_phase_error_rad is not None:
            df["recorded_phase_error_rad"] = self.recorded_phase_error_rad
        if self.known_phase_error_rad is not None:
            df["known_phase_error_rad"] = self.known_phase_error_rad
        df.index.name = "pulse"
        return df

    def to_dict(self) -> dict:
        """JSON-ready: :meth:`scalars`, what the data are (``acquisition``, :meth:`Acquisition.to_dict`),
        the estimate per pulse, the image grid and the ``options``."""
        out = self.scalars()
        out["acquisition"] = None if self.acquisition is None else self.acquisition.to_dict()
        out.update({"phase_estimate_rad": self.phase_estimate_rad.tolist(),
                    "estimated_pulses": self.estimated_pulses.tolist(),
                    "recorded_phase_error_rad": (None if self.recorded_phase_error_rad is None
                                                 else self.recorded_phase_error_rad.tolist()),
                    "known_phase_error_rad": (None if self.known_phase_error_rad is None
                                              else self.known_phase_error_rad.tolist()),
                    "image": {"shape": list(self.before.data.shape), "spacing_m": self.before.grid.spacing_m,
                              "range_m": [float(self.before.grid.u_m[0]), float(self.before.grid.u_m[-1])],
                              "azimuth_m": [float(self.before.grid.v_m[0]), float(self.before.grid.v_m[-1])]},
                    "options": dict(self.options), "phase_convention": (
                        "phase_estimate_rad is the error the data carry on each pulse (pulse n multiplied by "
                        "exp(j psi_n)); the correction applied is its negative; constant and linear terms removed")})
        return out


def _pga_on_image(image: GroundImage, kernel: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict, float | None]:
    res = pga(image.data, kernel=kernel)
    est, mask = pulse_estimate(image, res.phase_error_rad, res.estimated_bins)
    if res.usable_lines == 0:
        est = np.zeros_like(est)
    info = {"converged": res.converged, "reason": res.reason, "iterations": res.iterations,
            "usable_lines": int(res.usable_lines), "final_window": res.final_window,
            "phase_error_peak_to_peak_rad": float(np.ptp(res.phase_error_rad[res.estimated_bins]))}
    window = getattr(res, "final_window", 0) or None
    bandwidth = None
    if window:
        w = image.bin_rad_m
        n_ap = np.ptp(image.pulse_bin_rad_m) / (w[1] - w[0])
        bandwidth = window * n_ap / (2.0 * w.size)
    return res.image, est, mask, info, bandwidth


def focus(ph: PhaseHistory, options: FocusOptions | None = None, autofocus: str = "pga", *,
          kernel: str = "ml") -> FocusResult:
    """Form the ground image of ``ph`` and autofocus it with ``autofocus`` (module docstring)."""
    if autofocus not in AUTOFOCUS_MODES:
        raise InputError("unknown autofocus", field="autofocus", value=autofocus,
                         expected="'pga', 'none' or 'recorded'")
    if autofocus == "recorded" and not ph.has_recorded_autofocus:
        raise InputError("the files carry no recorded autofocus solution", field="--autofocus",
                         value="recorded", expected="'pga' or 'none' for these files")
    options = options or FocusOptions()
    notes = list(ph.notes)
    timings = {}
    t0 = time.perf_counter()
    before = form_ground_image(ph, options, label="as recorded")
    timings["image_formation"] = time.perf_counter() - t0
    n = ph.n_pulses
    rec = ph.recorded_phase_error_rad() if ph.has_recorded_autofocus else None
    mask = np.ones(n, dtype=bool)
    pga_info: dict = {}
    bandwidth = None
    if autofocus == "pga":
        t0 = time.perf_counter()
        data, est, mask, pga_info, bandwidth = _pga_on_image(before, kernel)
        timings["pga"] = time.perf_counter() - t0
        after = before.with_data(data, "after PGA")
        if not pga_info.get("converged", False):
            notes.append(f"PGA: {pga_info.get('reason', '')}")
    elif autofocus == "recorded":
        t0 = time.perf_counter()
        after = form_ground_image(ph.with_recorded_autofocus(), options, label="recorded autofocus")
        timings["image_formation_recorded"] = time.perf_counter() - t0
        est = _beyond_linear(rec, mask)
        notes.append("the estimate is the recorded solution itself (rms difference 0 by definition)")
    else:
        after = before.with_data(before.data, "no autofocus")
        est = np.zeros(n)
    comparison = {}
    rec_out = None
    if rec is not None:
        comparison = compare_with_recorded(est, rec, mask, bandwidth)
        if autofocus == "recorded":
            comparison["rms_diff_rad"] = 0.0
        rec_out = _beyond_linear(rec, mask)
    elif ph.injected_phase_rad is None:
        notes.append("no recorded autofocus solution in the files: no comparison")
    known_out = None
    if ph.injected_phase_rad is not None:
        known = ph.known_phase_error_rad()
        comparison["known"] = compare_with_recorded(est, known, mask, bandwidth)
        comparison["known"]["reference"] = "recorded + injected" if rec is not None else "injected"
        known_out = _beyond_linear(known, mask)
    return FocusResult(autofocus=autofocus, before=before, after=after, phase_estimate_rad=est,
                       estimated_pulses=mask, recorded_phase_error_rad=rec_out, known_phase_error_rad=known_out,
                       comparison=comparison,
                       pga=pga_info, timings_s=timings, options=options.model_dump(), notes=notes,
                       acquisition=describe_acquisition(ph, before.grid))
