"""Temperature columns of IMU logs as loggers write them: the name (``temp``, ``temperature``,
``imu_temp``, ``temp_c``, ``temp_k``, ``temp_f``) and a unit in brackets, converted to °C in one
place (``budget.units.temperature_to_c``). The temperature-sensitivity detector of the model gap
regresses on this column, so a column left unread hides the effect and a unit misread scales its
coefficient (°F read as °C: 1.8× too small)."""

from __future__ import annotations

import numpy as np
import pytest

from budget.errors import InputError
from budget.noise import LogMapping, read_log

RATE = 100.0
N = 2_000


def _write(path, header: list[str], temp_columns: list[np.ndarray]):
    rng = np.random.default_rng(7)
    t = np.arange(N) / RATE
    cols = [t, rng.normal(0.0, 0.05, N)] + temp_columns
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=",".join(header), comments="", fmt="%.10g")
    return path


def _warm_up_c() -> np.ndarray:
    return 25.0 + 15.0 * (1.0 - np.exp(-np.arange(N) / (0.3 * N)))  # 25 → ≈ 39 °C


def _notes(log) -> list[str]:
    return [i.text() for i in log.issues.issues if i.kind.endswith("temperature") or i.kind == "temperature_column"]


@pytest.mark.parametrize("name, to_file", [
    ("temp_c", lambda c: c),
    ("temperature [°C]", lambda c: c),
    ("Temp (C)", lambda c: c),
    ("imu_temp [degC]", lambda c: c),
    ("temperature [K]", lambda c: c + 273.15),
    ("temp_k", lambda c: c + 273.15),
    ("Temperature (°F)", lambda c: 32.0 + 1.8 * c),
    ("temp_f", lambda c: 32.0 + 1.8 * c),
])
def test_temperature_columns_are_read_in_degrees_celsius(tmp_path, name, to_file):
    truth = _warm_up_c()
    log = read_log(_write(tmp_path / "log.csv", ["time_s", "gyro_x_dps", name], [to_file(truth)]))
    assert log.temp_c is not None
    np.testing.assert_allclose(log.temp_c, truth, atol=1e-6)  # the file holds 10 digits
    assert _notes(log) == []


def test_a_temperature_without_unit_is_read_as_celsius_and_said(tmp_path):
    log = read_log(_write(tmp_path / "log.csv", ["time_s", "gyro_x_dps", "temperature"], [_warm_up_c()]))
    np.testing.assert_allclose(log.temp_c, _warm_up_c(), atol=1e-6)
    assert any("no unit: read as °C" in t for t in _notes(log))


def test_of_two_temperature_columns_the_first_is_read_and_the_other_named(tmp_path):
    a, b = _warm_up_c(), _warm_up_c() + 5.0
    path = _write(tmp_path / "log.csv", ["time_s", "gyro_x_dps", "gyro_temp [C]", "accel_temp [C]"], [a, b])
    log = read_log(path)
    np.testing.assert_allclose(log.temp_c, a, atol=1e-6)
    assert any("'accel_temp [C]'" in t and "not read" in t for t in _notes(log))
    chosen = read_log(path, LogMapping(columns={"accel_temp [C]": "temp_c"}))  # a mapping chooses
    np.testing.assert_allclose(chosen.temp_c, b, atol=1e-6)


@pytest.mark.parametrize("name, said", [
    ("temp_c [K]", "names two temperature units"),
    ("temp [bananas]", "temperature unit 'bananas' not understood; accepted: °C"),
])
def test_a_contradicting_or_unknown_temperature_unit_is_refused_naming_the_column(tmp_path, name, said):
    path = _write(tmp_path / "log.csv", ["time_s", "gyro_x_dps", name], [_warm_up_c()])
    with pytest.raises(InputError) as err:
        read_log(path)
    text = str(err.value)
    assert said in text and "log.csv" in text and "row 1" in text and name in text


def test_a_temperature_far_outside_what_an_imu_sees_is_warned_of(tmp_path):
    """Kelvin written without a unit (298 read as °C) gets a warning naming the column."""
    log = read_log(_write(tmp_path / "log.csv", ["time_s", "gyro_x_dps", "temperature"],
                          [_warm_up_c() + 273.15]))
    warned = [i for i in log.issues.issues if i.kind == "implausible_temperature"]
    assert len(warned) == 1 and warned[0].severity == "warning" and warned[0].column == "temperature"
    assert "is its unit right" in warned[0].message


def test_columns_that_only_contain_the_word_are_not_temperatures(tmp_path):
    log = read_log(_write(tmp_path / "log.csv", ["time_s", "gyro_x_dps", "temp_x", "template"],
                          [_warm_up_c(), _warm_up_c()]))
    assert log.temp_c is None
    assert {i.column for i in log.issues.issues if i.kind == "ignored_column"} == {"temp_x", "template"}


def test_a_header_of_logger_names_gets_a_mapping_to_start_from(tmp_path):
    """GyroX … AccZ are not read without a mapping (their unit is not in the name); the error
    writes out the mapping a user would start from, with the units left to them."""
    path = tmp_path / "logger.csv"
    path.write_text("Time,GyroX,GyroY,GyroZ,AccX,AccY,AccZ\n" + "".join(
        f"{k / 100:.2f},0.1,0.2,0.3,0.0,0.0,9.8\n" for k in range(50)))
    with pytest.raises(InputError) as err:
        read_log(path)
    text = str(err.value)
    assert '"Time": "time_s"' in text and '"GyroX": "gyro_x_dps"' in text and '"AccZ": "accel_z_mps2"' in text
    assert "write the unit each holds" in text
    path.write_text("t,foo,bar\n0,1,2\n0.01,1,2\n")  # nothing sensor-like: no suggestion
    with pytest.raises(InputError) as err:
        read_log(path)
    assert "mapping such as" not in str(err.value)
