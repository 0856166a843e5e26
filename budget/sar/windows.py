"""Amplitude windows (rectangular, Taylor) and their ideal impulse responses.

A window weights the aperture (slow time) in azimuth and the band (range frequency) in range.
It is described on the normalised support u ∈ [−1/2, 1/2]. The Taylor window is written as a
cosine series (Taylor 1955; Carrara, Goodman & Majewski 1995, "Spotlight SAR", app. D):

    w(u) = 1 + 2 Σ_{m=1}^{n̄−1} F_m cos(2π m u),
    F_m  = (−1)^{m+1}/2 · Π_{n=1}^{n̄−1} (1 − m²/(σ²(A² + (n−½)²))) / Π_{n≠m} (1 − m²/n²),
    A    = acosh(10^{|SLL|/20}) / π,   σ² = n̄² / (A² + (n̄−½)²),

so its impulse response is a sum of shifted sincs, h(x) = sinc(x) + Σ F_m [sinc(x−m) + sinc(x+m)]
(x in resolution cells, one cell = 1/bandwidth). :func:`ideal_irf` measures that closed form
numerically (3 dB width, first null, PSLR, ISLR) for the "window-aware" comparison of
:mod:`budget.sar.metrics`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from ..errors import InputError


class Window(BaseModel):
    """An amplitude window: ``kind`` 'rect' or 'taylor' (``sidelobe_db`` < 0, ``nbar`` ≥ 2)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    kind: Literal["rect", "taylor"] = "rect"
    sidelobe_db: float = Field(-35.0, le=-13.5, ge=-80.0, allow_inf_nan=False,
                               description="design peak sidelobe level of the Taylor window (dB)")
    nbar: int = Field(4, ge=2, le=12, description="number of nearly equal sidelobes of the Taylor window")

    @classmethod
    def parse(cls, spec: "Window | str | None") -> "Window":
        """'rect' | 'taylor' | 'taylor-35-4' | Window → Window (None → rect); a window's own
        :attr:`label` ('taylor(-35 dB, n̄=4)', as results record it) reads back too."""
        if spec is None:
            return cls()
        if isinstance(spec, Window):
            return spec
        if isinstance(spec, str):
            m = re.fullmatch(r"\s*taylor\(\s*(-?[0-9.]+)\s*dB,\s*n̄=(\d+)\s*\)\s*", spec)
            if m:
                spec = f"taylor-{-float(m.group(1)):g}-{m.group(2)}"
            parts = spec.lower().split("-")
            try:
                if parts[0] == "rect" and len(parts) == 1:
                    return cls(kind="rect")
                if parts[0] == "taylor" and len(parts) <= 3:
                    sll = -float(parts[1]) if len(parts) > 1 else -35.0
                    nbar = int(parts[2]) if len(parts) > 2 else 4
                    return cls(kind="taylor", sidelobe_db=sll, nbar=nbar)
            except ValidationError as err:  # a Taylor window out of its range (taylor-10-4)
                first = err.errors(include_url=False)[0]
                raise InputError(f"the Taylor window's {first['loc'][0]} is out of range ({first['msg']})",
                                 field="window", value=spec,
                                 expected="taylor-SLL-NBAR with a sidelobe level SLL of 13.5–80 dB below the "
                                          "peak and n̄ of 2–12, e.g. taylor-35-4") from None
            except (ValueError, TypeError):
                pass
        raise InputError("unknown window", field="window", value=spec,
                         expected="'rect', 'taylor', 'taylor-35-4' (sidelobe dB, n̄) or a Window")

    @property
    def label(self) -> str:
        return "rect" if self.kind == "rect" else f"taylor({self.sidelobe_db:g} dB, n̄={self.nbar})"

    def coefficients(self) -> np.ndarray:
        """Cosine-series coefficients [1, F_1, …, F_{n̄−1}] (unnormalised), see module docstring."""
        if self.kind == "rect":
            return np.array([1.0])
        return _taylor_coefficients(self.sidelobe_db, self.nbar)

    def __call__(self, u) -> np.ndarray:
        """w(u) on u ∈ [−1/2, 1/2], normalised to w(0) = 1; 0 outside."""
        u = np.asarray(u, dtype=float)
        c = self.coefficients()
        m = np.arange(1, c.size)
        w = c[0] + 2.0 * np.cos(2 * np.pi * u[..., None] * m) @ c[1:] if c.size > 1 else np.ones_like(u)
        w = w / (c[0] + 2.0 * c[1:].sum())
        return np.where(np.abs(u) <= 0.5 + 1e-12, w, 0.0)

    def samples(self, n: int) -> np.ndarray:
        """``n`` samples at u_k = (k − (n−1)/2)/n (the positions of scipy.signal.windows.taylor)."""
        u = (np.arange(n) - (n - 1) / 2.0) / n
        return self(u)

    def impulse_response(self, x_cells) -> np.ndarray:
        """Amplitude IRF h(x) = ∫ w(u) e^{j2πux} du of the continuous window, normalised h(0) = 1."""
        x = np.asarray(x_cells, dtype=float)
        c = self.coefficients()
        h = c[0] * np.sinc(x)
        for m in range(1, c.size):
            h = h + c[m] * (np.sinc(x - m) + np.sinc(x + m))
        return h / c[0]


@lru_cache(maxsize=64)
def _taylor_coefficients(sidelobe_db: float, nbar: int) -> np.ndarray:
    a = math.acosh(10.0 ** (abs(sidelobe_db) / 20.0)) / math.pi
    sigma2 = nbar ** 2 / (a ** 2 + (nbar - 0.5) ** 2)
    f = [1.0]
    for m in range(1, nbar):
        num = np.prod([1.0 - m ** 2 / (sigma2 * (a ** 2 + (n - 0.5) ** 2)) for n in range(1, nbar)])
        den = np.prod([1.0 - m ** 2 / n ** 2 for n in range(1, nbar) if n != m])
        f.append((-1) ** (m + 1) / 2.0 * num / den)
    out = np.array(f)
    out.setflags(write=False)
    return out


@dataclass(frozen=True)
class IdealIrf:
    """Ideal (unaberrated) impulse response of a window, in resolution cells (1/bandwidth).

    ``islr_db`` uses main lobe ±``first_null_cells`` and sidelobes out to ``islr_extent_cells``
    (``inf``: all the energy, by Parseval ∫w² = ∫|h|²).
    """

    window: str
    width_3db_cells: float
    first_null_cells: float
    pslr_db: float
    islr_db: float
    islr_extent_cells: float
    noise_bandwidth: float  # ∫w² / (∫w)²·1 cell: effective area of |h|² in cells (1 for rect)


def ideal_irf(window: Window, islr_extent_cells: float | None = None) -> IdealIrf:
    """Measure the closed-form IRF of ``window`` (see module docstring) numerically."""
    ext = math.inf if islr_extent_cells is None else float(islr_extent_cells)
    return _ideal_irf_cached(window, ext)


@lru_cache(maxsize=64)
def _ideal_irf_cached(window: Window, extent: float) -> IdealIrf:
    step = 1.0 / 512.0
    span = 12.0 if not math.isfinite(extent) else max(extent, 12.0)
    x = np.arange(-span, span + step / 2, step)
    p = np.abs(window.impulse_response(x)) ** 2
    i0 = x.size // 2
    half = p[i0:]
    # 3 dB width: linear interpolation of the first crossing of 1/2 (peak is 1 at x = 0)
    k = int(np.argmax(half < 0.5))
    x3 = x[i0 + k - 1] + (0.5 - half[k - 1]) / (half[k] - half[k - 1]) * step
    # first null: first local minimum of |h|² beyond the half-power point
    d = np.diff(half)
    kn = k + int(np.argmax(d[k:] > 0))
    null = x[i0 + kn]
    side = np.abs(x) > null
    pslr = 10 * np.log10(p[side].max())
    u = np.linspace(-0.5, 0.5, 8193)
    wu = window(u)
    total = np.trapezoid(wu ** 2, u) / np.trapezoid(wu, u) ** 2  # ∫|h|² dx with h(0) = 1 (Parseval)
    main_mask = np.abs(x) <= null
    e_main = np.trapezoid(p[main_mask], x[main_mask])
    if math.isfinite(extent):
        sl_mask = side & (np.abs(x) <= extent)
        e_side = float(np.sum(p[sl_mask]) * step)
    else:
        e_side = total - e_main
    return IdealIrf(window=window.label, width_3db_cells=float(2 * x3), first_null_cells=float(null),
                    pslr_db=float(pslr), islr_db=float(10 * np.log10(e_side / e_main)),
                    islr_extent_cells=extent, noise_bandwidth=float(total))


def scenario_window(scenario) -> Window:
    """The scenario's own azimuth/range window: rect when its ``window_broadening`` a_w < 1.1
    (an unweighted aperture broadens nothing), else Taylor (−35 dB, n̄ = 4)."""
    return Window() if scenario.window_broadening < 1.1 else Window(kind="taylor")


def verdict_window(scenario, choice: "Window | str" = "auto") -> Window:
    """The window the Monte Carlo verdict images with (``McOptions.window``): "auto" = Taylor
    (−35 dB, n̄ = 4) for radar, what an imaging radar uses, and the scenario's own choice
    (:func:`scenario_window`) for sonar; else ``choice`` itself ('rect', 'taylor', a Window)."""
    if isinstance(choice, str) and choice == "auto":
        return Window(kind="taylor") if scenario.medium == "radar" else scenario_window(scenario)
    return Window.parse(choice)
