"""Shared fixtures: the location of ../shared (real data), skipping cleanly when it is absent."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """``../shared/data`` beside the repository, or skip with the reason."""
    data = SHARED / "data"
    if not data.is_dir():
        pytest.skip(f"real measured data not found at {data} (clone without ../shared)")
    return data
