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


# --- 2. a part or a preset given twice: refused, naming it, not run twice --------------------

def test_check_parts_refuses_a_repeated_part_naming_it(capsys):
    import budget
    with pytest.raises(InputError) as e:
        budget.check_parts(["STIM300", "HG9900", "STIM300", "ADIS16405", "HG9900"], "automotive_77ghz")
    assert e.value.field == "parts"
    assert "part given more than once: STIM300, HG9900" in str(e.value) and "each part once" in str(e.value)
    assert main(["check", "--preset", "automotive_77ghz", "--part", "STIM300", "STIM300"]) == 2
    line = _one_line(capsys)
    assert "field parts: part given more than once: STIM300" in line


def test_sweep_refuses_a_repeated_part_or_preset_before_any_trial(monkeypatch, tmp_path, capsys):
    import budget
    import budget.mc.sweep as sweep_mod

    def never(*a, **k):
        raise AssertionError("a trial ran")
    monkeypatch.setattr(sweep_mod, "run_mc", never)
    with pytest.raises(InputError) as e:
        budget.sweep(["STIM300", "STIM300"], "automotive_77ghz", trials=1)
    assert e.value.field == "parts" and "part given more than once: STIM300" in str(e.value)
    assert "runs the same trials again" in str(e.value)
    with pytest.raises(InputError) as e:
        budget.sweep(["STIM300"], ["automotive_77ghz", "airborne_xband", "automotive_77ghz"], trials=1)
    assert e.value.field == "presets" and "preset given more than once: automotive_77ghz" in str(e.value)
    out = str(tmp_path / "t.csv")
    assert main(["sweep", "--preset", "automotive_77ghz", "automotive_77ghz", "--part", "STIM300",
                 "--trials", "1", "-q", "--out", out]) == 2
    assert "field presets: preset given more than once: automotive_77ghz" in _one_line(capsys)
    assert main(["sweep", "--preset", "automotive_77ghz", "--part", "HG9900", "HG9900", "--trials", "1",
                 "-q", "--out", out]) == 2
    assert "field parts: part given more than once: HG9900" in _one_line(capsys)


def test_distinct_scenarios_sharing_only_a_name_are_not_repeats():
    from budget.errors import refuse_repeats
    from budget.presets import get_preset
    a = get_preset("automotive_77ghz")
    b = a.model_copy(update={"slant_range_m": a.slant_range_m * 2})
    refuse_repeats([a, b], lambda s: s.name, field="scenarios", what="scenario")  # no error


# --- 3. a wrong argument type at a public entry: InputError, not TypeError/AttributeError ------

def test_load_catalog_refuses_a_non_path():
    import budget
    from budget.catalog.io import load_catalog
    for f in (budget.load_catalog, load_catalog):
        with pytest.raises(InputError) as e:
            f(5)
        assert e.value.field == "user_csv" and "not a path (type int)" in str(e.value)
        assert "expected a parts CSV path (str or pathlib.Path), or None" in str(e.value)
    with pytest.raises(InputError, match="type bool"):  # False was read as "no user catalog"
        load_catalog(False)


def test_cheapest_passing_refuses_what_is_not_a_sweep_table():
    import pandas as pd

    import budget
    from budget.mc.sweep import cheapest_passing
    with pytest.raises(InputError) as e:
        budget.cheapest_passing([1, 2])
    assert e.value.field == "table" and "not a sweep table (type list)" in str(e.value)
    assert "expected the pandas.DataFrame budget.sweep returns" in str(e.value)
    with pytest.raises(InputError) as e:
        cheapest_passing(pd.DataFrame({"x": [1.0]}))
    assert "the table has no column scenario, part_id, grade, price_usd" in str(e.value)
    assert cheapest_passing(pd.DataFrame()).empty  # a sweep cancelled before its first cell


def test_fit_noise_terms_refuses_what_is_not_an_allan_deviation():
    from budget.noise.terms import fit_noise_terms
    with pytest.raises(InputError) as e:
        fit_noise_terms("abc")
    assert e.value.field == "allan" and "not an Allan deviation (type str)" in str(e.value)
    assert "AllanResult" in str(e.value)


def _noise(n=2000):
    import numpy as np
    return np.random.default_rng(4).normal(0.0, 1e-3, n)


def test_analyse_arma_refuses_text_and_values_whose_squares_overflow():
    from budget.noise.pipeline import analyse_arma
    with pytest.raises(InputError) as e:
        analyse_arma("abc", 100.0, channel="gyro_x")
    assert e.value.field == "gyro_x" and "the series is not numbers" in str(e.value)
    assert "expected a 1-D array of numbers (rad/s)" in str(e.value)
    # ~1e300: numpy said "array must not contain infs or NaNs" from an overflow deep inside
    with pytest.raises(InputError) as e:
        analyse_arma(_noise() * 1e303, 100.0, channel="accel_z")
    assert e.value.field == "accel_z" and "2000 sample(s) beyond ±100000 m/s² (in SI)" in str(e.value)
    assert "wrong unit?" in str(e.value)
    with pytest.raises(InputError, match="field rate_hz: the sampling rate is not a number"):
        analyse_arma(_noise(), "100", channel="gyro_x")
    with pytest.raises(InputError, match="field channel: channel is not a name"):
        analyse_arma(_noise(), 100.0, channel=5)


# --- 4. an explicit τ list: negative, repeated or out of order is refused, not fixed silently -

@pytest.mark.parametrize("taus, words", [
    ([-1.0, 0.1, 1.0], "τ must be > 0 s (got -1.0)"),    # was dropped silently
    ([0.0, 1.0], "τ must be > 0 s (got 0.0)"),
    ([0.1, 1.0, 1.0], "τ = 1 s is given twice"),
    ([1.0, 0.1], "τ list is not increasing: 0.1 s follows 1 s"),  # was sorted silently
    ([0.1, float("inf")], "τ list must be finite numbers"),
    (["a"], "τ list must be finite numbers (got ['a'])"),
])
def test_allan_deviation_refuses_a_bad_explicit_tau_list(taus, words):
    from budget.noise import allan_deviation
    with pytest.raises(InputError) as e:
        allan_deviation(_noise(5000), 100.0, taus=taus)
    assert e.value.field == "taus" and words in str(e.value)
    assert "expected an increasing array of τ in seconds" in str(e.value)


def test_allan_deviation_keeps_an_increasing_tau_list():
    from budget.noise import allan_deviation
    assert allan_deviation(_noise(5000), 100.0, taus=[0.1, 1.0, 10.0]).tau_s.tolist() == [0.1, 1.0, 10.0]


# --- 5. ArmaOptions: orders and detrend order refused when built, not later (or never) -------

def test_arma_options_refuse_orders_and_detrend_order_when_built(tmp_path, capsys):
    from budget.noise.arma import MAX_ORDER
    from budget.noise.pipeline import ArmaOptions
    with pytest.raises(InputError) as e:
        ArmaOptions(orders=((5, 5),))
    assert e.value.field == "orders" and f"0 ≤ p, q ≤ {MAX_ORDER} (got (5, 5))" in str(e.value)
    with pytest.raises(InputError) as e:
        ArmaOptions(orders=((2.5, 1),))  # int() read it as 2
    assert e.value.field == "orders" and "pair (p, q) of whole numbers" in str(e.value)
    with pytest.raises(InputError) as e:
        ArmaOptions(orders=5)  # was a TypeError: 'int' object is not iterable
    assert e.value.field == "orders" and "a list of pairs (p, q)" in str(e.value)
    for bad in (5, -1, True, 1.0):
        with pytest.raises(InputError) as e:
            ArmaOptions(detrend_order=bad)
        assert e.value.field == "detrend_order" and "detrend order must be 0, 1 or 2" in str(e.value)
        assert "expected 0 (none), 1 (linear) or 2 (quadratic)" in str(e.value)
    ok = ArmaOptions(orders=[[1, 0], (2, 1)], detrend_order=2)
    assert ok.orders == ((1, 0), (2, 1)) and ok.detrend_order == 2


def test_arma_limits_have_one_home():
    # the pipeline's later checks and the options' checks are the same functions
    import numpy as np

    from budget.noise.arma import select_arma
    from budget.noise.preprocess import detrend
    x = _noise(500)
    with pytest.raises(InputError, match="field orders: orders must have 0 ≤ p, q ≤ 3"):
        select_arma(x, orders=[(4, 0)])
    with pytest.raises(InputError, match="field detrend_order: detrend order must be 0, 1 or 2"):
        detrend(np.asarray(x), 3)
