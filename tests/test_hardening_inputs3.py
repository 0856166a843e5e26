"""Bad input, round 3: cases a sweep of the CLI and the library entry points found.

Each test names the input and asserts the words of the one-line error (file, field, what was
expected), not only that something was raised.
"""

from __future__ import annotations

import pytest

import budget
from budget.cli.main import main
from budget.errors import InputError
from budget.mc.runner import MAX_LOCAL_WORKERS


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert err and "Traceback" not in "\n".join(err)
    return err[-1]


# --- local worker processes -------------------------------------------------------------------

def test_run_mc_refuses_more_local_processes_than_the_limit_before_starting_any():
    # 100000 workers forked 100000 processes and hung for minutes on a 2-trial run
    with pytest.raises(InputError) as e:
        budget.run_mc("automotive_77ghz", "STIM300", trials=1, workers=100_000)
    assert e.value.field == "workers" and f"1 … {MAX_LOCAL_WORKERS}" in str(e.value)
    assert "more local worker processes" in str(e.value) and "100000" in str(e.value)
    with pytest.raises(InputError) as e:
        budget.sweep(["STIM300"], "automotive_77ghz", trials=1, workers=MAX_LOCAL_WORKERS + 1)
    assert e.value.field == "workers"


def test_cli_mc_with_too_many_workers_exits_2(capsys):
    assert main(["mc", "--preset", "automotive_77ghz", "--part", "STIM300", "--trials", "1",
                 "--workers", "100000", "-q"]) == 2
    line = _one_line(capsys)
    assert "workers" in line and f"expected 1 … {MAX_LOCAL_WORKERS}" in line


# --- an output file that is a folder, checked before the computation --------------------------

@pytest.mark.parametrize("argv", [
    ["mc", "--preset", "automotive_77ghz", "--part", "STIM300", "--trials", "1", "-q", "--json", "{d}"],
    ["report", "--preset", "automotive_77ghz", "-q", "--out", "{d}"],
    ["sweep", "--preset", "automotive_77ghz", "--part", "STIM300", "--trials", "1", "-q", "--out", "{d}"],
])
def test_an_existing_folder_as_output_file_is_refused_before_the_run(tmp_path, monkeypatch, capsys, argv):
    import budget.cli.mc_cmd as mc_cmd
    import budget.cli.report_cmd as report_cmd

    def never(*a, **k):
        raise AssertionError("the computation started")
    monkeypatch.setattr(mc_cmd, "run_mc", never)
    monkeypatch.setattr(mc_cmd, "sweep", never)
    monkeypatch.setattr(report_cmd, "build_report", never)
    assert main([a.format(d=tmp_path) for a in argv]) == 1
    line = _one_line(capsys)
    assert f"{tmp_path}: is a folder; give a file name" in line and "--" in line


def test_report_figures_that_is_a_file_is_refused_before_the_run(tmp_path, capsys):
    f = tmp_path / "figs"
    f.write_text("x")
    assert main(["report", "--preset", "automotive_77ghz", "-q", "--out", str(tmp_path / "r.html"),
                 "--figures", str(f)]) == 1
    line = _one_line(capsys)
    assert "--figures" in line and f"{f}: exists and is not a folder" in line
    assert not (tmp_path / "r.html").exists()  # refused before the report was written
