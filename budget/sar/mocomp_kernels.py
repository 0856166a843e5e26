"""Compiled loops of the batched motion compensation (:class:`budget.sar.mocomp.MotionCompensator`):
the first-order phasors' product with the range spectrum, and the second-order phase applied in
place.

Each loop computes what the NumPy expression in its docstring computes, element by element and
in the same order (products and sums of the same operands, complex products as NumPy forms them
(:mod:`budget.sar.complex_product`), e^{jφ} from cos and sin as
:func:`budget.sar.mocomp.cis` forms it), without the (B, n_pulses, n_range) temporaries the
NumPy form allocates and reads: the outer product of the phasors and its gather, the ranges, the
phases and their cosines and sines. Compiled by numba on first use and cached beside this file
(``cache=True``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .complex_product import cmul


@njit(cache=True)
def first_order_product_into(out: np.ndarray, spectrum: np.ndarray, coarse: np.ndarray, fine: np.ndarray,
                             a_index: np.ndarray, b_index: np.ndarray, fused: bool, phasor_first: bool) -> None:
    """out (B, n_pulses, n_range) = spectrum · (coarse[..., a_index] · fine[..., b_index]) for B
    trajectories: ``spectrum`` (B, n_pulses, n_range) (a broadcast view when the trajectories
    share it), ``coarse`` (B, n_pulses, n_a), ``fine`` (B, n_pulses, n_b). ``fused``: the products
    as NumPy forms them (:data:`budget.sar.complex_product.FUSED`); ``phasor_first``: the operand
    order of the complex product (the fused form is not symmetric in its operands)."""
    n_b, n_p, _ = coarse.shape
    n_r = a_index.size
    for b in range(n_b):
        for p in range(n_p):
            for k in range(n_r):
                phasor = cmul(coarse[b, p, a_index[k]], fine[b, p, b_index[k]], fused)
                if phasor_first:
                    out[b, p, k] = cmul(phasor, spectrum[b, p, k], fused)
                else:
                    out[b, p, k] = cmul(spectrum[b, p, k], phasor, fused)


@njit(cache=True)
def second_order_in_place(data: np.ndarray, apc_m: np.ndarray, ground_y_m: np.ndarray,
                          nominal_range_m: np.ndarray, centre_change_m: np.ndarray, phase_per_m: float,
                          wavelength_m: float, pulse_weight: np.ndarray, fused: bool) -> None:
    """data (G, B, n_pulses, n_range) ·= e^{−jψ}, the same ψ on each of the G data sets of a
    trajectory (its cosine and sine formed once): ψ = phase_per_m · dr / λ, dr = (√((x² + (y − y_r)²) + z²)
    − nominal_range_m[p, r]) − centre_change_m[b, p], (x, y, z) = ``apc_m[b, p]`` and y_r =
    ``ground_y_m[r]`` (the reference points lie on x = 0, z = 0); ``phase_per_m`` = −4π as
    :func:`budget.units.range_to_phase` multiplies; then, when ``pulse_weight`` (n_pulses,) is not
    empty, times each pulse's real weight, as NumPy multiplies a complex by a real (the real taken
    as a complex of zero imaginary part); ``fused`` as in :func:`first_order_product_into`."""
    n_g, n_b, n_p, n_r = data.shape
    weighted = pulse_weight.size > 0
    for b in range(n_b):
        for p in range(n_p):
            w = complex(pulse_weight[p], 0.0) if weighted else complex(1.0, 0.0)
            x = apc_m[b, p, 0]
            y = apc_m[b, p, 1]
            z = apc_m[b, p, 2]
            xx = x * x
            zz = z * z
            dc = centre_change_m[b, p]
            for r in range(n_r):
                dy = y - ground_y_m[r]
                dr = (math.sqrt((xx + dy * dy) + zz) - nominal_range_m[p, r]) - dc
                phase = -(phase_per_m * dr / wavelength_m)
                e = complex(math.cos(phase), math.sin(phase))
                for g in range(n_g):
                    v = cmul(data[g, b, p, r], e, fused)
                    data[g, b, p, r] = cmul(v, w, fused) if weighted else v
