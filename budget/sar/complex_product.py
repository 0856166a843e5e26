"""The complex product as NumPy forms it on this machine, for compiled loops that must give NumPy's
numbers bit for bit.

NumPy's multiply loops for complex128 may fuse each component's second product and the sum into
one rounding (re = fma(a_r, b_r, −a_i b_i), im = fma(a_r, b_i, a_i b_r), on CPUs with FMA) or not
(re = a_r b_r − a_i b_i, im = a_r b_i + a_i b_r). :data:`FUSED` says which, found once at import
by comparing NumPy's products with both forms; :func:`cmul` forms either. A loop that multiplies
as NumPy does then leaves every later step — the FFTs, PGA's iterations — exactly where NumPy
would have: PGA's iterations amplify last-bit differences on a trial that does not converge.
"""

from __future__ import annotations

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic


@intrinsic
def _fma(typingctx, a, b, c):
    """a·b + c with one rounding (LLVM's fma intrinsic)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        d = ir.DoubleType()
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(d, [d, d, d]), "llvm.fma.f64")
        return builder.call(fn, args)

    return sig, codegen


@njit(cache=True, inline="always")
def cmul(a: complex, b: complex, fused: bool) -> complex:
    """a·b, each component's sum rounded once (``fused``) or its two products each (not)."""
    if fused:
        return complex(_fma(a.real, b.real, -(a.imag * b.imag)), _fma(a.real, b.imag, a.imag * b.real))
    return complex(a.real * b.real - a.imag * b.imag, a.real * b.imag + a.imag * b.real)


@njit(cache=True)
def _products(a: np.ndarray, b: np.ndarray, fused: bool) -> np.ndarray:
    out = np.empty_like(a)
    for i in range(a.size):
        out[i] = cmul(a[i], b[i], fused)
    return out


def _numpy_fuses() -> bool:
    """Whether NumPy's complex128 product here is the fused form; False for the plain form, and
    for a NumPy that formed neither (the compiled loops then differ from it in the last bits)."""
    rng = np.random.default_rng(0)
    a = rng.standard_normal(4099) + 1j * rng.standard_normal(4099)
    b = rng.standard_normal(4099) + 1j * rng.standard_normal(4099)
    ref = a * b
    return bool(np.array_equal(_products(a, b, True), ref))


#: NumPy's complex128 product on this machine is the fused form (:func:`cmul`).
FUSED = _numpy_fuses()
