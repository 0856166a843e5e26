"""A channel whose log is *quieter* than its model: the model gap cannot close it.

Every candidate effect of the workflow adds noise (its increment is a variance, ≥ 0), so on a
channel whose Allan deviation and PSD lie below the model's the only way down was a filter or a
quantizer fitted to pull the model's short-τ power towards the log's: an artefact (on the real
MPU-6050 accelerometers, 1.8–2.4 dB quieter than the datasheet at every τ, the workflow had named
a 25–30 Hz low-pass filter). Such a channel is reported with a note and not worked on
(:mod:`budget.gap.workflow`).
"""

from __future__ import annotations

import numpy as np

from ..errors import NOISE_ALONE_WAY

#: Median misfit (measured − model, dB, over the Allan-deviation τ, PSD bands and line) below
#: which a channel beyond its null threshold reads as quieter than its model ...
QUIET_DB = -1.0
#: ... with at least this share of the misfits below zero ...
QUIET_SHARE = 0.75
#: ... and none above the model by more than this (dB): a line, a vibration or a slow drift
#: standing out of a quieter floor keeps the channel open for its effect.
QUIET_MAX_DB = 1.0


def median_db(d_db, gap: float, threshold: float) -> float | None:
    """The median misfit (dB, < 0) of a channel whose ``gap`` is beyond its null ``threshold``
    because the log is quieter than the model (the three conditions above on the misfits
    ``d_db``); ``None`` otherwise. The workflow also keeps a channel whose trend statistics are
    open."""
    d = np.asarray(d_db, float)
    d = d[np.isfinite(d)]
    if d.size == 0 or gap <= threshold:
        return None
    med = float(np.median(d))
    quiet = med < QUIET_DB and float(np.mean(d < 0)) >= QUIET_SHARE and float(d.max()) <= QUIET_MAX_DB
    return med if quiet else None


def note(channel: str, median: float) -> str:
    """The report's note for a quieter channel."""
    return (f"{channel}: the log is quieter than the model (Allan deviation and PSD a median "
            f"{-median:.1f} dB below it): every candidate effect adds noise, so none can close this "
            "gap and none is named on this channel (a filter or a quantizer fitted to pull the "
            "model down would be an artefact) — the model's values are conservative for this unit; "
            f"characterise the log on its own ({NOISE_ALONE_WAY.cli}) for a model of it")
