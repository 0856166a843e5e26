"""A channel whose log sits a unit factor away from its model at every τ and band: a unit slip.

A gyro column in deg/s read as rad/s (or the reverse) puts every Allan deviation and PSD band
20·log10(180/π) = 35.2 dB off the model; deg/h read as deg/s, 71.1 dB. The workflow then fitted
a dozen effects (quantization, heavy tails, Gauss–Markov terms) to a log read 57× too loud, or
called it "quieter than the model". A misfit that is that factor, give or take the unit's own
scatter about its datasheet, at nearly every τ and band is reported as a likely unit error and
the channel is not worked on (:mod:`budget.gap.workflow`).
"""

from __future__ import annotations

import math

import numpy as np

#: Unit factors a rate column is read wrong by: (factor, what it is).
FACTORS = ((180.0 / math.pi, "deg/s ↔ rad/s"), (3600.0, "deg/h ↔ deg/s (or per hour ↔ per second)"),
           (3600.0 * 180.0 / math.pi, "deg/h ↔ rad/s"))
#: How far (dB) the median misfit may lie from a factor's 20·log10 ...
TOLERANCE_DB = 4.0
#: ... with at least this share of the misfits within ``SPREAD_DB`` of the median (a real unit
#: scatters about its datasheet by a few dB; an effect the model lacks shows at some τ only).
SHARE = 0.8
SPREAD_DB = 6.0


def slip(d_db) -> tuple[float, float, str] | None:
    """(median misfit dB, factor, what it is) when the misfits ``d_db`` (measured − model, dB, over
    the Allan-deviation τ, PSD bands and lines) read as a unit slip (module docstring); None
    otherwise."""
    d = np.asarray(d_db, float)
    d = d[np.isfinite(d)]
    if d.size < 4:
        return None
    med = float(np.median(d))
    if float(np.mean(np.abs(d - med) <= SPREAD_DB)) < SHARE:
        return None
    for factor, what in FACTORS:
        if abs(abs(med) - 20.0 * math.log10(factor)) <= TOLERANCE_DB:
            return med, factor, what
    return None


def note(channel: str, found: tuple[float, float, str]) -> str:
    """The report's note for a channel read with a unit slip."""
    med, factor, what = found
    way = "above" if med > 0 else "below"
    return (f"{channel}: LIKELY UNIT ERROR — the log's Allan deviation and PSD lie a median {abs(med):.1f} dB "
            f"{way} the model at nearly every τ and band, the factor {factor:.4g} "
            f"({20 * math.log10(factor):.1f} dB) of {what}: check the column's unit (its header's suffix); "
            "no effect is named on this channel")
