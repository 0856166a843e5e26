"""examples/check_vs_monte_carlo.py: the PGA-limited verdict beside the Monte Carlo's decision,
run with 2 trials on one cheap preset (the README's figures use 64 on every preset)."""

from __future__ import annotations

import numpy as np
import pytest
from example_loader import load_example

from budget.mc.stats import wilson_interval


def _example():
    return load_example("check_vs_monte_carlo")


@pytest.mark.slow
def test_check_beside_the_monte_carlo_decision(tmp_path, capsys):
    both = _example().main(["--trials", "2", "--presets", "automotive_24ghz", "--out", str(tmp_path / "t.csv")])
    assert len(both) > 10 and set(both["scenario"]) == {"automotive_24ghz"}
    assert (tmp_path / "t.csv").exists()
    # 2 trials cannot decide a 0.9 target: even 2 of 2 has a lower Wilson bound far below it
    assert wilson_interval(2, 2)[0] < 0.5
    assert (both["mc_decision"] == "fail").all()
    passed = both["pga_limited_verdict"] == "pass"
    assert (both.loc[passed, "agreement"].str.startswith("Monte Carlo stricter")).all()
    full = both["p_pass_after"] == 1.0
    assert both.loc[passed & full, "agreement"].str.contains("more trials would decide").all()
    # filling the empty terms from the grade adds terms to check: never a larger margin
    m, s = both["pga_limited_min_margin"].to_numpy(), both["margin_as_simulated"].to_numpy()
    assert np.all(s <= m * (1 + 1e-9))
    assert not ((both["verdict_as_simulated"] == "pass") & (both["pga_limited_verdict"] == "fail")).any()
    out = capsys.readouterr().out
    assert f"of {len(both)} part × preset pairs agree (2 trials, seed 1)" in out
    assert "checked as simulated" in out


@pytest.mark.parametrize("argv", [["--trials", "0"], ["--presets", "no_such_preset"]])
def test_bad_arguments_are_clear_errors(argv, capsys):
    from budget.errors import InputError
    with pytest.raises((SystemExit, InputError, ValueError)):
        _example().main(argv)
