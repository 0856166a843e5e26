"""Compiled loop of the trials' noisy range spectra (:meth:`budget.mc.plan.ChainPlan.form`).

:func:`add_band_noise` computes echoes' spectrum + receiver-noise spectrum
(:func:`budget.mc.receiver_noise.receiver_noise_spectrum`) element by element with the same operations —
each draw times its bin's real scale, the sum with the echoes' bin, every out-of-band bin plus
zero — without the zero-filled (n_pulses, n_range) noise array, its scattered assignment and the
stack of them. Compiled by numba on first use and cached beside this file (``cache=True``).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def add_band_noise(out: np.ndarray, spectrum: np.ndarray, draws: np.ndarray, scale: np.ndarray,
                   band_index: np.ndarray) -> None:
    """out (n_pulses, n_range) = ``spectrum`` + the noise spectrum whose in-band bins
    ``band_index`` hold draws[p, i, 0] + j draws[p, i, 1] times ``scale[i]`` (zero elsewhere)."""
    n_p, n_r = spectrum.shape
    n_band = band_index.size
    for p in range(n_p):
        for k in range(n_r):
            s = spectrum[p, k]
            out[p, k] = complex(s.real + 0.0, s.imag + 0.0)
        for i in range(n_band):
            k = band_index[i]
            s = spectrum[p, k]
            out[p, k] = complex(s.real + draws[p, i, 0] * scale[i], s.imag + draws[p, i, 1] * scale[i])
