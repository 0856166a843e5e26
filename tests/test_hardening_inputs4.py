"""Bad input, round 4: cases a new user's session with odd scenarios and huge runs found.

Each test names the input and asserts the words of the one-line error (field, what was
expected), not only that something was raised.
"""

from __future__ import annotations

import pytest

import budget
from budget.cli.main import main
from budget.errors import InputError
from budget.mc.runner import MAX_TRIALS


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert err and "Traceback" not in "\n".join(err)
    return err[-1]


# --- a trial count no run can finish ----------------------------------------------------------

def test_run_mc_and_sweep_refuse_more_trials_than_one_run_takes_before_starting():
    # 10¹² trials built a task list of 1.6·10¹⁰ entries and filled 22 GB before the first trial
    with pytest.raises(InputError) as e:
        budget.run_mc("automotive_24ghz", "STIM300", trials=10 ** 12)
    assert e.value.field == "trials" and f"1 … {MAX_TRIALS:,}" in str(e.value)
    assert "1000000000000" in str(e.value)
    with pytest.raises(InputError) as e:
        budget.sweep(["STIM300"], "automotive_24ghz", trials=MAX_TRIALS + 1)
    assert e.value.field == "trials"


def test_cli_mc_with_a_huge_trial_count_exits_2(capsys):
    assert main(["mc", "--preset", "automotive_24ghz", "--part", "STIM300", "--trials", str(10 ** 12),
                 "-q"]) == 2
    line = _one_line(capsys)
    assert "trials" in line and f"expected 1 … {MAX_TRIALS:,}" in line and "other seeds" in line
