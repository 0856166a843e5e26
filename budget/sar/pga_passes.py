"""PGA's runs beyond the first (:func:`budget.sar.pga.pga`): the capture check and the second pass.

Capture check (module docstring of :mod:`budget.sar.pga`, "Restarts"): after a clutter-limited
first window with fewer usable lines than ``min_lines``, the runs of :data:`_RESTARTS` beside the
first, the one whose corrected image is sharpest kept (:func:`_sharpest`).

Second pass (:mod:`budget.sar.pga`, "Second pass"): after a correction of more than
:data:`SECOND_PASS_ABOVE_RAD` rad rms (:func:`correction_rms_rad`) from a clutter-limited start,
PGA run again on the image it corrected, its estimate added when the image gets sharper
(:func:`_second_pass`).

Both judge by the image alone: Σ|g|⁴/(Σ|g|²)² (:func:`budget.sar.sharpness.image_sharpness`).
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from .pga_lines import _Lines, _corrected, ifft_lines
from .sharpness import image_sharpness

if TYPE_CHECKING:
    from .pga import PgaResult

#: The capture check's other runs (:mod:`budget.sar.pga`, "Restarts"): (label, first window,
#: shrink); ``None``: the default.
_RESTARTS = (("measured start", "measured", None), ("slower shrink (0.7)", None, 0.7))
#: The second pass runs after a correction larger than this (rad rms over the bins with signal;
#: :mod:`budget.sar.pga`, "Second pass").
SECOND_PASS_ABOVE_RAD = float(np.pi)


def correction_rms_rad(res: PgaResult) -> float:
    """The size of PGA's correction: the rms of its estimate over the bins with signal
    (:attr:`PgaResult.estimated_bins`; the estimate has no constant or linear term there), rad."""
    phi = np.asarray(res.phase_error_rad, float)[res.estimated_bins]
    return float(np.sqrt(np.mean(phi * phi))) if phi.size else 0.0


def _second_pass(g: np.ndarray, first: PgaResult, size: float, above: float, again,
                 g1: np.ndarray | None = None, hist: np.ndarray | None = None) -> tuple[PgaResult, np.ndarray]:
    """Second pass (module docstring, "Second pass"): PGA run again, from its own start, on the
    image ``first`` corrected; its estimate is added when the image it gives is sharper
    (:func:`budget.sar.sharpness.image_sharpness`), else ``first`` is kept; ``second_pass``
    records it either way. ``g1``, ``hist``: that corrected image and ``g``'s phase history when
    the capture check has formed them already (``hist`` is then overwritten). Returns the result
    and its corrected image."""
    hist = ifft_lines(g) if hist is None else hist
    g1 = _corrected(hist, first.phase_error_rad) if g1 is None else g1
    second = again(g1)
    phi = first.phase_error_rad + second.phase_error_rad
    g2 = _corrected(hist, phi, overwrite=True) if second.usable_lines else g1
    s1, s2 = image_sharpness(g1), image_sharpness(g2)
    kept = bool(second.usable_lines) and s2 > s1
    record = {"correction_rms_rad": size, "above_rad": above, "kept": kept, "sharpness_before": s1,
              "sharpness_after": s2, "start_window": second.start_window, "iterations": second.iterations,
              "converged": second.converged, "usable_lines": second.usable_lines,
              "final_window": second.final_window}
    verdict = (f"kept: the image is sharper (Σ|g|⁴/(Σ|g|²)² ×{s2 / s1:.4f})" if kept else
               "not kept: " + ("no usable scatterers" if not second.usable_lines else
                               f"the image is not sharper (×{s2 / s1:.4f})"))
    note = (f"; second pass after a correction of {size:.3g} rad rms (> {above:g} rad): "
            f"{second.iterations} more iterations, {verdict}")
    if not kept:
        res = replace(first, second_pass=record, reason=first.reason + note)
        return res, g1
    res = replace(first, phase_error_rad=phi, iterations=first.iterations + second.iterations,
                  converged=second.converged, final_window=second.final_window,
                  history=first.history + second.history, fast_bands=first.fast_bands + second.fast_bands,
                  second_pass=record, usable_lines=second.usable_lines,
                  predicted_noise_rad=second.predicted_noise_rad,
                  reason=second.reason + note)
    return res, g2


def _sharpest(g: np.ndarray, d: _Lines, first: PgaResult, finish) -> tuple[PgaResult, np.ndarray, np.ndarray | None]:
    """Capture check (module docstring, "Restarts"): the run from the clutter-limited start and
    the runs of :data:`_RESTARTS`, the one whose corrected image is sharpest
    (:func:`budget.sar.sharpness.image_sharpness`) kept, with that image and ``g``'s phase
    history (None when no run had usable lines; the second pass reuses both); every run is listed
    in ``restarts``."""
    runs = [("clutter-limited start", first)]
    for label, first_window, shrink in _RESTARTS:
        dd = d
        if shrink is not None:
            dd = replace(d, shrink=shrink)
            dd.unshifted = d.unshifted  # the same lines: the same uncorrected start
        runs.append((label, finish(dd,
                                   "auto" if first_window is None else first_window)))
    table, images, hist = [], [], None
    for label, r in runs:
        if r.usable_lines:
            hist = ifft_lines(g) if hist is None else hist  # every run corrects the same phase history
        images.append(_corrected(hist, r.phase_error_rad) if r.usable_lines else g)
        sharp = image_sharpness(images[-1]) if r.usable_lines else float("nan")
        table.append({"start": label, "start_window": r.start_window, "sharpness": sharp, "converged": r.converged,
                      "iterations": r.iterations, "usable_lines": r.usable_lines, "final_window": r.final_window})
    best = max(range(len(runs)), key=lambda i: table[i]["sharpness"] if runs[i][1].usable_lines else -np.inf)
    for i, row in enumerate(table):
        row["kept"] = i == best
    res = runs[best][1]
    res.restarts = table
    res.reason += (f"; capture check ({first.usable_lines} usable lines after a clutter-limited first window "
                   f"of {first.start_window} samples): the sharpest of {len(runs)} runs kept, "
                   f"the {runs[best][0]}")
    return res, images[best], hist

