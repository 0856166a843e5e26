"""Uploaded files: written to a private temporary copy, read by the library, never executed."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import streamlit as st

from budget.errors import InputError
from budget.noise import ImuLog, read_log


@st.cache_data(show_spinner="Reading the log …", max_entries=4)
def read_uploaded_log(data: bytes, name: str, max_rows: int, repair: bool) -> ImuLog:
    """Write the upload to a temporary file (keeping its suffix: .csv, .gz, …) and read it;
    errors name the user's file, not the temporary copy."""
    suffix = "".join(Path(name).suffixes[-2:]) or ".csv"
    fd, tmp = tempfile.mkstemp(suffix=suffix)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        log = read_log(tmp, repair=repair, max_rows=max_rows)
    except InputError as err:
        if err.file == tmp:
            err.rename_file(name)
        raise
    finally:
        os.unlink(tmp)
    log.source = name
    return log
