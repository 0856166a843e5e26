"""The random-stream registry: every stream id of the package in one table, none used twice."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from budget.rng import GAP_CHECK_STREAMS, STREAMS, stream_id, trial_generator

#: The pinned table: changing an id changes every result drawn from it — do it on purpose.
PINNED = {"motion_imu": 11, "motion_disturbance": 12, "motion_initial": 13, "motion_aiding": 14,
          "sar_receiver_noise": 21, "prefilter_calibration": 22, "sar_scene": 23,
          "sar_reference": 24}


#: The model-gap report checks' streams (third spawn-key element), pinned likewise.
PINNED_GAP_CHECKS = {"gap_two_valued": 1, "gap_temperature_curve": 2}


def test_the_table_is_pinned_and_ids_are_unique():
    assert dict(STREAMS) == PINNED
    assert dict(GAP_CHECK_STREAMS) == PINNED_GAP_CHECKS
    assert len(set(GAP_CHECK_STREAMS.values())) == len(GAP_CHECK_STREAMS)
    assert len(set(STREAMS.values())) == len(STREAMS)
    with pytest.raises(TypeError):
        STREAMS["new"] = 99  # read-only
    with pytest.raises(KeyError, match="motion_imu"):
        stream_id("motion_imus")


def test_no_module_defines_a_stream_id_of_its_own():
    """Stream ids come from the registry: no ``…STREAM = <number>`` outside budget/rng.py."""
    root = Path(__file__).resolve().parents[1] / "budget"
    literal = re.compile(r"^\s*[A-Z_]*STREAMS?\b[^=\n]*=\s*\(?\s*\d", re.M)
    offenders = [str(p.relative_to(root)) for p in root.rglob("*.py")
                 if p.name != "rng.py" and literal.search(p.read_text(encoding="utf-8"))]
    assert offenders == []


def test_streams_of_one_trial_are_independent_and_reproducible():
    a = trial_generator(3, 5, STREAMS["motion_imu"]).standard_normal(4)
    b = trial_generator(3, 5, STREAMS["motion_imu"]).standard_normal(4)
    c = trial_generator(3, 5, STREAMS["motion_aiding"]).standard_normal(4)
    assert (a == b).all() and not (a == c).any()
