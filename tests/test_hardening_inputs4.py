"""Bad input, round 4: gaps a sweep of the CLI and the library entry points left open.

Each test names the input and asserts the words of the one-line error (field, value, what was
expected), not only that something was raised.
"""

from __future__ import annotations

import pytest

from budget.cli.main import main
from budget.errors import InputError

RATE_WORDS = "needs an IMU rate of at least"


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert err and "Traceback" not in "\n".join(err)
    return err[-1]


# --- 1. a manoeuvre the IMU cannot sample: the check refuses what the Monte Carlo refuses -----

def test_check_refuses_a_manoeuvre_period_the_monte_carlo_refuses(capsys):
    # a 1 ns oscillation gave "gyro SF bound × 1.1e+20" in the check while mc refused it
    from budget.catalog.io import load_catalog
    from budget.check import check_parts
    from budget.presets import get_preset
    part = load_catalog()["STIM300"]
    motion = {"kind": "oscillation", "period_s": 1e-9}
    with pytest.raises(InputError) as e:
        check_parts([part], get_preset("automotive_77ghz"), platform_motion=motion)
    assert e.value.field == "imu_rate_hz" and RATE_WORDS in str(e.value)
    assert "1e+09 Hz" in str(e.value) and "1e+10 Hz" in str(e.value) and "got 200.0" in str(e.value)
    lines = []
    for argv in (["check", "--preset", "automotive_77ghz"],
                 ["mc", "--preset", "automotive_77ghz", "--part", "STIM300", "--trials", "1", "-q"]):
        assert main(argv + ["--platform-motion", "oscillation", "--manoeuvre-period", "1e-9"]) == 2
        lines.append(_one_line(capsys).split("error: ", 1)[1])
    assert lines[0] == lines[1] and "field imu_rate_hz" in lines[0]  # the same words from one rule
