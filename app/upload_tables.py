"""Uploaded logs and Allan tables: one size limit, and Allan tables read like the CLI reads them.

A table of one curve without a channel column (``tau [s], adev (deg/h)``) is read as the channel
the user picks (:func:`curve_channel`, the choices :data:`budget.units.CHANNELS`), as
``--channels gyro_z`` names it on the command line.

``UPLOAD_LIMIT_MB`` is the limit the server is started with (``sar-budget dashboard`` passes
it as ``--server.maxUploadSize``) and the one every log widget states and enforces. An upload is
written to a private temporary copy (suffix kept, so .gz streams through the same chunked
reader as the CLI) and read by the library; it is never executed or unpickled.
"""

from __future__ import annotations

import dataclasses

import streamlit as st

from budget.cli.dashboard_cmd import MAX_UPLOAD_MB as UPLOAD_LIMIT_MB
from budget.errors import InputError
from budget.noise import AllanResult, read_adev_table
from budget.noise.adev_columns import looks_like_adev_table, needs_channel_name
from budget.units import CHANNELS
from uploads import read_via_temp_copy

LOG_TYPES = ["csv", "gz", "bz2", "xz", "zip"]


def upload_label(what: str) -> str:
    """Widget label stating the real limit, e.g. ``IMU log or Allan table (at most 200 MB)``."""
    return f"{what} (at most {UPLOAD_LIMIT_MB} MB)"


def check_size(data: bytes, name: str) -> None:
    """Refuse an upload above the limit with a message (the widget refuses it first, normally)."""
    if len(data) > UPLOAD_LIMIT_MB * 1024 * 1024:
        raise InputError(f"file is {len(data) / 1e6:.1f} MB", file=name,
                         expected=f"at most {UPLOAD_LIMIT_MB} MB")


def upload_log_or_table(key: str, hint: str) -> tuple[bytes, str] | None:
    """The uploader of a static IMU log or an Allan table (widget ``key``): ``(bytes, file name)``
    of an upload within :data:`UPLOAD_LIMIT_MB`, or ``None`` (``hint`` shown) before one."""
    up = st.file_uploader(upload_label("IMU log or Allan table"), type=LOG_TYPES, key=key,
                          max_upload_size=UPLOAD_LIMIT_MB)
    if up is None:
        st.info(hint)
        return None
    data = up.getvalue()
    check_size(data, up.name)
    return data, up.name


@st.cache_data(show_spinner=False, max_entries=8)
def is_adev_table(data: bytes, name: str) -> bool:
    """True when the upload has the Allan-table columns (``channel, tau_s, adev[, lci, uci]``)."""
    if name.lower().endswith((".gz", ".bz2", ".xz", ".zip")):
        return False  # compressed uploads are logs; Allan tables are small text files
    return read_via_temp_copy(data, name, looks_like_adev_table)


@st.cache_data(show_spinner=False, max_entries=8)
def needs_channel(data: bytes, name: str) -> bool:
    """True when the uploaded Allan table holds one curve and no channel column
    (:func:`budget.noise.adev_table.needs_channel_name`): the user names its channel."""
    return read_via_temp_copy(data, name, needs_channel_name)


def curve_channel(prefix: str, name: str, container=st) -> str | None:
    """The channel the user picks for the one curve of table ``name`` (``None`` until picked, with
    a note saying what is needed). The choices are the library's channels."""
    channel = container.selectbox("channel of this curve", CHANNELS, index=None, key=f"{prefix}_curve_channel",
                                  placeholder="pick the channel",
                                  help="the table has no channel column; its unit goes in the ADEV "
                                       "column's header, e.g. adev (deg/h) for a gyro")
    if channel is None:
        container.info(f"{name} has no channel column: it holds one curve. Pick the channel it belongs to.",
                       icon=":material/info:")
    return channel


@st.cache_data(show_spinner="Reading the Allan table …", max_entries=4)
def read_uploaded_adev(data: bytes, name: str, rate_hz: float | None, samples: int | None,
                       ci_level: float = 0.95, channel: str | None = None) -> dict[str, AllanResult]:
    """The uploaded Allan table as ``{channel: AllanResult}`` (SI), as ``sar-budget noise
    characterize TABLE --rate-hz F --samples N [--channels CH]`` reads it (``channel``: the one
    channel of a table without a channel column, :func:`curve_channel`); ``rate_hz`` and
    ``samples`` both ``None``: a digitised datasheet curve, as the CLI reads a table given neither."""
    channels = None if channel is None else [channel]
    try:
        tables = read_via_temp_copy(data, name, lambda p: read_adev_table(p, rate_hz, samples, ci_level=ci_level,
                                                                          channels=channels))
    except InputError as err:  # its ways out in the dashboard's words: uploads.error_text
        raise err.rename_file(err.file or name) from None
    return {ch: dataclasses.replace(r, source=name) for ch, r in tables.items()}


@dataclasses.dataclass(frozen=True)
class UploadedTable:
    """An uploaded Allan table read with the record's rate and length the page asked for."""

    tables: dict[str, AllanResult]
    rate_hz: float | None  # None (and samples None): a digitised curve, no record behind it
    samples: int | None
    curve_channel: str | None  # the channel picked for a one-curve table, else None

    @property
    def digitised(self) -> bool:
        return self.rate_hz is None and self.samples is None

    @property
    def notes(self) -> list[str]:
        """What reading the table noted (a digitised curve, an unused ``adev_err`` column …), as
        the CLI prints them before its result."""
        return [n for t in self.tables.values() for n in t.notes]


def uploaded_adev(prefix: str, data: bytes, name: str, *, digitised: bool = False) -> UploadedTable | None:
    """Ask for the record's rate and length (:func:`adev_inputs`; with ``digitised``, the choice
    of no record: a digitised datasheet curve) and, for a one-curve table, its channel
    (:func:`curve_channel`), then read the table; ``None`` while the channel is not picked."""
    rate, samples = adev_inputs(prefix, digitised=digitised)
    curve = None
    if needs_channel(data, name):
        curve = curve_channel(prefix, name)
        if curve is None:
            return None
    return UploadedTable(read_uploaded_adev(data, name, rate, samples, channel=curve), rate, samples, curve)


#: The choice of the record behind an uploaded Allan table (the noise lab and the model gap offer
#: it; the library's model gap refuses a digitised curve, and the page shows that refusal rather
#: than reading the curve with a default rate and length).
RECORD_LABEL = "record behind the curve"
RECORD_CHOICES = ("known: its sampling rate and length",
                  "not known: a digitised datasheet curve (τ as given)")


def adev_inputs(prefix: str, container=st, *, digitised: bool = False) -> tuple[float | None, int | None]:
    """Rate and record length behind an Allan table (not in the table itself). With
    ``digitised``, the user may say there is no record (:data:`RECORD_CHOICES`): ``(None, None)``,
    the table is then read as a digitised datasheet curve."""
    if digitised:
        how = container.radio(RECORD_LABEL, RECORD_CHOICES, horizontal=True, key=f"{prefix}_adev_record",
                              help="a curve computed from a record: its rate and length fix the averaging "
                                   "factors and, without lci/uci, the confidence intervals; a curve read off "
                                   "a datasheet figure has no record: τ is taken as given and a term's upper "
                                   "limit is read off the curve's own values")
        if how == RECORD_CHOICES[1]:
            return None, None
    left, right = container.columns(2)
    rate = float(left.number_input("sampling rate of the record (Hz)", min_value=0.001, value=100.0,
                                   format="%g", key=f"{prefix}_adev_rate"))
    samples = int(right.number_input("samples in the record", min_value=16, value=1_000_000, step=1000,
                                     key=f"{prefix}_adev_samples"))
    return rate, samples
