"""Checks of the numbers a caller passes to the noise functions (one home for each rule).

:func:`check_rate_hz` for a sampling rate, :func:`float_series` for a series of samples: a
value that is not what is asked for is refused with an :class:`~budget.errors.InputError`
naming the field, never a numpy TypeError, a rate of ``True`` read as 1 Hz, or a complex series
cut to its real part.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import InputError


def check_rate_hz(rate_hz) -> float:
    """``rate_hz`` as a float, or :class:`InputError` (field ``rate_hz``) unless it is a finite
    real number > 0 (Hz); ``True``, a string or ``None`` is refused, not read as 1 Hz or failing
    as a TypeError."""
    if isinstance(rate_hz, bool) or not isinstance(rate_hz, numbers.Real) or not (
            math.isfinite(rate_hz) and rate_hz > 0):
        raise InputError("sampling rate must be a positive number", field="rate_hz", value=rate_hz,
                         expected="a sampling rate in Hz, a finite number > 0")
    return float(rate_hz)


def float_series(x, field: str, expected: str) -> np.ndarray:
    """``x`` as a float64 array, or :class:`InputError` on ``field`` (with ``expected``) when it
    is complex (numpy would drop the imaginary part with a warning only) or not numbers. The
    shape and finiteness are the caller's to check (each says them in its own terms)."""
    if np.iscomplexobj(x):
        raise InputError("the series is complex", field=field, expected=expected.replace(
            "array of", "array of real", 1))
    try:
        return np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("the series is not numbers", field=field, value=x, expected=expected) from None
