"""Azimuth impulse response of one point target from its slow-time phase error.

After range compression, motion compensation and azimuth matched filtering, a point target's
azimuth response is the Fourier transform of its windowed residual phase history,
h(x) = Σ_n w_n e^{jφ_n} e^{−j2πnx/P} (P pulses; x in resolution cells, 1 cell = 1/bandwidth).
This is the single-target, single-range-cell model of seed 003's point-target comparison (the
residual φ = 4π/λ Δr, seed 003 (12)) and of PGA's phase-error model.

The cut is measured with :func:`budget.sar.irf.measure_cut` (peak, 3 dB width, PSLR, ISLR with
the ideal first null of the window as main-lobe edge), so the numbers use the same definitions as
the point-target simulator of :mod:`budget.sar`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import InputError
from .irf import measure_cut
from .windows import Window, ideal_irf


@dataclass
class IrfMetrics:
    """Per-trial metrics (arrays of shape (T,)): PSLR/ISLR dB, 3 dB width and peak shift in
    resolution cells, peak loss dB relative to the error-free response."""

    pslr_db: np.ndarray
    islr_db: np.ndarray
    width_cells: np.ndarray
    shift_cells: np.ndarray
    peak_loss_db: np.ndarray
    window: str

    def summary(self) -> str:
        """One line: window, trials and the medians of PSLR, ISLR, width and peak loss."""
        d = self.to_dict()
        return (f"{d['window']} window, {d['trials']} trials: median PSLR {d['median_pslr_db']:.2f} dB, ISLR "
                f"{d['median_islr_db']:.2f} dB, width {d['median_width_cells']:.3g} cells, peak loss "
                f"{d['median_peak_loss_db']:.2f} dB")

    def to_dict(self) -> dict:
        """JSON-ready: window, trials and the medians of the metrics (dB, cells)."""
        med = lambda a: float(np.median(a))
        return {"window": self.window, "trials": int(self.pslr_db.size),
                "median_pslr_db": med(self.pslr_db), "median_islr_db": med(self.islr_db),
                "median_width_cells": med(self.width_cells),
                "median_peak_loss_db": med(self.peak_loss_db)}

    def to_frame(self) -> pd.DataFrame:
        return pd.DataFrame({"pslr_db": self.pslr_db, "islr_db": self.islr_db,
                             "width_cells": self.width_cells, "shift_cells": self.shift_cells,
                             "peak_loss_db": self.peak_loss_db})


def azimuth_irf_metrics(phase_error_rad, window: Window | str | None = None, *,
                        upsample: int = 16, search_cells: float | None = None) -> IrfMetrics:
    """Metrics of the azimuth IRF for phase errors (T, P) or (P,) (rad) over P pulses.

    ``search_cells``: the peak is searched within ±this many cells of the centre (default: the
    whole line, so a badly defocused response is measured about its global maximum).
    """
    try:
        phi = np.atleast_2d(np.asarray(phase_error_rad, dtype=float))
    except (TypeError, ValueError):
        phi = None
    if phi is None or phi.ndim != 2:
        raise InputError("not a phase error per pulse", field="phase_error_rad",
                         value=getattr(phi, "shape", phase_error_rad),
                         expected="real numbers (rad), shape (P,) or (trials, P)")
    if not np.all(np.isfinite(phi)):
        raise InputError("phase error holds NaN or infinite values", field="phase_error_rad",
                         expected="finite phases in rad")
    T, P = phi.shape
    if P < 8:
        raise InputError(f"{P} pulses are too few for an impulse response", field="phase_error_rad",
                         value=P, expected="at least 8 pulses")
    win = Window.parse(window)
    w = win.samples(P)
    null = ideal_irf(win).first_null_cells
    n = P * upsample
    half = int((search_cells if search_cells is not None else P / 2) * upsample)
    ref = np.abs(np.fft.fft(w, n)[0])
    out = {k: np.empty(T) for k in ("pslr", "islr", "width", "shift", "loss")}
    for t in range(T):
        cut = np.fft.fftshift(np.fft.fft(w * np.exp(1j * phi[t]), n))
        m = measure_cut(cut, 1.0 / upsample, -(n // 2) / upsample, expected_index=n // 2,
                        search_half=half, null=null)
        out["pslr"][t], out["islr"][t] = m.pslr_db, m.islr_db
        out["width"][t], out["shift"][t] = m.width_3db, m.peak_position
        out["loss"][t] = 20 * np.log10(ref / m.peak_amplitude)
    return IrfMetrics(out["pslr"], out["islr"], out["width"], out["shift"], out["loss"], win.label)
