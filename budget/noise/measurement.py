"""One reader for "a measurement": an IMU log or a measured Allan-deviation table.

The noise lab's ``characterize`` and the model-gap workflow take either; the choice is made
here once, by the file's header (``channel, tau_s, adev`` → table, see
:func:`~budget.noise.adev_table.looks_like_adev_table`), with the same rules for both: a table
needs the record's ``rate_hz`` and ``samples`` (or, where the caller accepts one, neither: a
digitised curve); ``samples`` is refused for a log (a log has its own length).
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..fileio import require_file
from .adev_columns import looks_like_adev_table
from .adev_table import read_adev_table
from .allan import AllanResult
from .log_mapping import LogMapping
from .logs import ImuLog, read_log


def read_measurement(path: str | Path, *, rate_hz: float | None = None, samples: int | None = None,
                     mapping: LogMapping | None = None, repair: bool = False,
                     max_rows: int | None = None, ci_level: float = 0.95,
                     min_samples: int = 16, channels=None,
                     digitised: bool = False) -> ImuLog | dict[str, AllanResult]:
    """An :class:`ImuLog` (SI channels) or ``{channel: AllanResult}`` from ``path``. ``channels``:
    of a log, read and check just those columns, so that a problem in a channel the caller
    does not use (a clipped accelerometer when only the gyros are compared) does not refuse
    the log; of an Allan table without a channel column (``tau_s, adev [deg/h]``), the one
    channel its curve belongs to. ``digitised``: a table given neither ``rate_hz`` nor
    ``samples`` is read as a digitised datasheet curve (τ as given, no record: the Allan fit
    takes it; the model gap, which needs the record, leaves it False)."""
    path = Path(path)
    require_file(path, expected="an IMU log CSV or an Allan table")
    if looks_like_adev_table(path):
        if digitised and rate_hz is None and samples is None:
            return read_adev_table(path, ci_level=ci_level, channels=channels)
        if rate_hz is None or samples is None:
            raise InputError("an Allan table needs the record's rate and length", file=path,
                             expected="--rate-hz F --samples N" + (" (neither for a digitised datasheet curve)"
                                                                   if digitised else ""))
        return read_adev_table(path, rate_hz, samples, ci_level=ci_level, channels=channels)
    if samples is not None:
        raise InputError("--samples is for Allan tables; a log has its own length", field="samples")
    return read_log(path, mapping, repair, rate_hz=rate_hz, max_rows=max_rows,
                    min_samples=min_samples, channels=channels)
