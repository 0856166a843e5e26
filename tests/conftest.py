"""Shared fixtures: the location of ../shared (real data) and the Gotcha files in it, skipping
cleanly when they are absent."""

from __future__ import annotations

from pathlib import Path

import pytest
from gotcha_synth import GOTCHA_FILES

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """``../shared/data`` beside the repository, or skip with the reason."""
    data = SHARED / "data"
    if not data.is_dir():
        pytest.skip(f"real measured data not found at {data} (clone without ../shared)")
    return data


@pytest.fixture(scope="module")
def gotcha(shared_data) -> list[Path]:
    """The Gotcha pass-1 HH files in aperture order, or skip with the reason."""
    d = shared_data / "sar" / "gotcha"
    files = [d / f for f in GOTCHA_FILES]
    if not all(f.is_file() for f in files):
        pytest.skip(f"Gotcha phase-history files not found in {d}")
    return files
