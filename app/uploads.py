"""Uploaded files (written to a private temporary copy, read by the library, never executed) and
the dashboard's side of the error boundary: :func:`error_text` / :func:`show_error` give a page
the same one-line message the CLI prints (:func:`budget.errors.describe_error`), never a
traceback and never a bare "something went wrong"."""

from __future__ import annotations

import hashlib
import logging
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import streamlit as st

from budget.errors import InputError, describe_error, in_words_of
from budget.safe_text import printable
from budget.noise import ImuLog, LogMapping, read_log

log = logging.getLogger("sar_budget.dashboard")


#: The interface the library's messages are said for here: the ways out they name (repair, a
#: rate, channels, workers …) are the dashboard's inputs, not Python arguments or CLI options
#: (:data:`budget.errors.WAYS`, the one home of those words).
INTERFACE = "dashboard"


def error_text(err: BaseException) -> str:
    """The one-line message for ``err``: the input problem as the CLI states it — its ways out in
    the dashboard's words (:func:`budget.errors.in_words_of`) —, or for an unexpected failure its
    type and a short hint (the traceback goes to the server log)."""
    msg = describe_error(err, interface=INTERFACE)
    if msg.kind == "unexpected":
        log.error("dashboard page failed", exc_info=err)
        text = msg.text.split(" — ")[0]
        return f"{printable(text, 300)} — an unexpected error; the details are in the server log."
    return printable(msg.text, 2000)


def naming_upload(err: InputError, file: str, field: str | None = None) -> InputError:
    """``err`` naming the uploaded ``file`` (and ``field``, e.g. the channel) when the library,
    working on arrays, could not: "field x: 10 samples are too few" becomes
    "log.csv, field gyro_z: 10 samples are too few"."""
    if field is not None and err.field in (None, "x"):
        err.field = field
    return err.rename_file(err.file or file)


def show_error(err: BaseException) -> None:
    """Show ``err`` on the page as :func:`error_text` (``st.error``)."""
    st.error(error_text(err), icon=":material/error:")


#: At most this many of a log's findings are shown one by one above a page's results.
MAX_FINDINGS_SHOWN = 5


def show_log_findings(log_: ImuLog) -> None:
    """The log reader's warnings (``st.warning``: a rate below 1 Hz — ms read as s? —, clipped or
    constant channels, jittery stamps) and notes (``st.info``: an ignored column, an unchecked
    accelerometer unit) on the page itself, each naming the file (its ways out in the dashboard's
    words): a finding that changes every number must not sit in a collapsed report only."""
    shown = [i for i in log_.issues.issues if i.severity in ("warning", "info")]
    for issue in shown[:MAX_FINDINGS_SHOWN]:
        text = f"{log_.source}: {printable(in_words_of(issue.text(), INTERFACE), 600)}"
        if issue.severity == "warning":
            st.warning(text, icon=":material/warning:")
        else:
            st.info(text, icon=":material/info:")
    if len(shown) > MAX_FINDINGS_SHOWN:
        st.caption(f"{len(shown) - MAX_FINDINGS_SHOWN} more finding(s) in the log report.")


#: The tick box of the pages that read logs (noise lab, model gap); the library's message about
#: a log's problems names it (``budget.errors.REPAIR_WAY``).
REPAIR_LABEL = "repair the log (drop duplicate/out-of-order rows, interpolate gaps)"


def repair_box(key: str, container=st) -> bool:
    """The log-repair tick box (:data:`REPAIR_LABEL`) under ``key``."""
    return container.checkbox(REPAIR_LABEL, key=key)


#: The inputs beside a log upload that the library's messages about a log's layout name
#: (``budget.errors.LOG_MAPPING_WAY``, ``LOG_NAMES_WAY``, ``LOG_RATE_WAY``).
MAPPING_LABEL = "column mapping (JSON/YAML, optional)"
RATE_LABEL = "sampling rate (Hz)"


@dataclass(frozen=True)
class LogLayout:
    """How to read an uploaded log when its header is not canonical: a column mapping file
    (:class:`budget.noise.LogMapping`, as the CLI's ``--mapping`` reads it) and a sampling rate
    (Hz) for a log without a time column; None where not given."""

    mapping: tuple[bytes, str] | None = None
    rate_hz: float | None = None

    def key(self) -> str:
        """Part of a cache key: the mapping's content digest and the rate."""
        digest = hashlib.sha256(self.mapping[0]).hexdigest()[:16] if self.mapping else "-"
        return f"{digest}:{self.rate_hz}"


def layout_inputs(prefix: str) -> LogLayout:
    """The mapping upload and the rate input beside a log upload (in an expander: most logs need
    neither), under keys ``{prefix}_mapping`` and ``{prefix}_rate_hz``."""
    with st.expander("column mapping and sampling rate (for logs a logger wrote)"):
        st.caption("A log whose header is not `time_s, gyro_x_dps … accel_z_mps2` is read through a mapping "
                   "file: `{\"columns\": {\"GyrX\": \"gyro_x_dps\"}, \"scale\": …, \"skip_rows\": …, "
                   "\"rate_hz\": …}`. The rate is needed only when the log has no time column.")
        left, right = st.columns(2)
        up = left.file_uploader(MAPPING_LABEL, type=["json", "yaml", "yml"], key=f"{prefix}_mapping")
        rate = right.number_input(RATE_LABEL, min_value=0.0, max_value=1e7, value=0.0, step=1.0,
                                  key=f"{prefix}_rate_hz",
                                  help="0: the rate comes from the log's time column (or the mapping's rate_hz)")
    mapping = (up.getvalue(), Path(up.name).name[:200]) if up is not None else None
    return LogLayout(mapping, float(rate) if rate and rate > 0 else None)


@st.cache_data(show_spinner="Reading the log …", max_entries=4)
def read_uploaded_log(data: bytes, name: str, max_rows: int, repair: bool,
                      layout: LogLayout | None = None) -> ImuLog:
    """Write the upload to a temporary file (keeping its suffix: .csv, .gz, …) and read it, through
    the ``layout``'s mapping and rate if given; errors name the user's files, not the temporary copies."""
    name = Path(name or "upload.csv").name[:200] or "upload.csv"
    layout = layout or LogLayout()
    mapping = None
    if layout.mapping is not None:
        mapping = read_via_temp_copy(layout.mapping[0], layout.mapping[1], LogMapping.load)
    log_ = read_via_temp_copy(data, name, lambda tmp: read_log(tmp, mapping, repair=repair, max_rows=max_rows,
                                                               rate_hz=layout.rate_hz))
    log_.source = name
    return log_


def read_via_temp_copy(data: bytes, name: str, read):
    """``read(path)`` on a private temporary copy of an upload (keeping its suffix: .csv, .gz, …);
    errors name the user's file ``name``, not the temporary copy."""
    suffix = "".join(s for s in Path(name).suffixes[-2:] if s.isascii() and len(s) <= 8) or ".csv"
    fd, tmp = tempfile.mkstemp(suffix=suffix)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        return read(tmp)
    except InputError as err:
        if err.file == tmp:
            err.rename_file(name)
        raise
    finally:
        os.unlink(tmp)
