"""Fuzz/property suite: every generated input to the catalog CSV, IMU log,
scenario and noise-model readers ends in success or a clear InputError — never another
exception. Each reader runs a 100-case version in the main test command and a 1,000-case
version under ``@pytest.mark.slow`` (CI's second step); hypothesis is derandomized, so every
run tries the same cases."""

from __future__ import annotations

import csv
import gzip
import io
import json
import tempfile
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from budget.catalog.io import read_parts
from budget.catalog.validate import ALT_UNIT_COLUMNS, _read_text, _table_fast, _table_row_by_row
from budget.catalog.schema import PART_COLUMNS
from budget.errors import InputError
from budget.imu import NoiseModel
from budget.noise import read_log
from budget.scenario import Scenario

FAST = settings(max_examples=100, derandomize=True, deadline=None, database=None,
                suppress_health_check=list(HealthCheck))
SLOW = settings(FAST, max_examples=1000)

# --- generators (independent of the readers: plain text/number grammars) -------------------

numbers = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr),
                    st.integers(-10 ** 6, 10 ** 40).map(str),
                    st.sampled_from(["", "0", "-0", "1e-3", "-2.5", "1e400", "nan", "inf", "1_000",
                                     "0x10", " 3 ", "1,5", "٣", "9" * 5000]))
texts = st.one_of(st.text(max_size=30),
                  st.sampled_from(["=1+HYPERLINK(\"x\")", "-2+3+cmd|x", "@SUM(1)", "+1", "\t=x",
                                   "\r=x", "\x1b[31mred", "a\"b", "a,b", "line\nbreak", "tactical",
                                   "industrial", "adev_min", "ieee_b", "total_1sigma", "datasheet",
                                   "P-1", "", " ", "\x00"]))
cells = st.one_of(numbers, texts)
columns = st.sampled_from(list(PART_COLUMNS) + list(ALT_UNIT_COLUMNS) + ["colour", "", "part_id"])


@st.composite
def catalog_texts(draw) -> str:
    header = draw(st.lists(columns, min_size=1, max_size=8))
    if draw(st.booleans()):  # often a usable header, so that the cell checks are reached
        header = ["part_id", "grade", "source"] + [c for c in header if c not in
                                                   ("part_id", "grade", "source")]
    n = draw(st.integers(0, 6))
    rows = []
    for i in range(n):
        width = len(header) if draw(st.integers(0, 5)) else draw(st.integers(0, len(header) + 2))
        row = [draw(cells) for _ in range(width)]
        if header[:3] == ["part_id", "grade", "source"] and width >= 3 and draw(st.booleans()):
            row[:3] = [f"P{i}", draw(st.sampled_from(["tactical", "navigation", "x"])), "ds"]
        rows.append(row)
    buf = io.StringIO()
    quoting = draw(st.sampled_from([csv.QUOTE_MINIMAL, csv.QUOTE_ALL, csv.QUOTE_NONNUMERIC]))
    w = csv.writer(buf, lineterminator=draw(st.sampled_from(["\n", "\r\n"])), quoting=quoting)
    w.writerow(header)
    w.writerows(rows)
    text = buf.getvalue()
    if draw(st.integers(0, 9)) == 0:  # broken quoting / truncation / stray bytes
        text = text[: draw(st.integers(0, len(text)))] + draw(st.sampled_from(['"', "\x00", ",,,\n"]))
    return text


@st.composite
def mostly_valid_catalogs(draw) -> str:
    """Valid rows in a random column set, then 0–2 cells replaced by anything: reaches the
    per-cell checks, where the pandas path and the exact path must agree cell for cell."""
    optional = [c for c in PART_COLUMNS if c not in ("part_id", "grade", "source")]
    extra = draw(st.lists(st.sampled_from(optional + list(ALT_UNIT_COLUMNS)), unique=True, max_size=6))
    # one column per quantity: drop a canonical column whose alternative unit is also drawn
    alt_of = {ALT_UNIT_COLUMNS[a][0] for a in extra if a in ALT_UNIT_COLUMNS}
    extra = [c for c in extra if c in ALT_UNIT_COLUMNS or c not in alt_of]
    header = draw(st.permutations(["part_id", "grade", "source"] + extra))
    rows = []
    for i in range(draw(st.integers(1, 8))):
        row = []
        for col in header:
            if col == "part_id":
                row.append(f"P{i}")
            elif col == "grade":
                row.append(draw(st.sampled_from(["tactical", "navigation", "consumer"])))
            elif col in ("source", "vendor", "model", "notes"):
                row.append(draw(st.sampled_from(["ds rev A", "", "x, y", "-1.5", "ok"])) or
                           ("ds" if col == "source" else ""))
            elif col == "bias_instability_convention":
                row.append(draw(st.sampled_from(["", "adev_min", "ieee_b"])))
            elif col == "verified":
                row.append(draw(st.sampled_from(["", "datasheet", "partial"])))
            else:
                row.append(draw(st.sampled_from(["", "0", "0.5", "12", "1e-3", "3.25"])))
        rows.append(row)
    for _ in range(draw(st.integers(0, 2))):
        r = draw(st.integers(0, len(rows) - 1))
        c = draw(st.integers(0, len(header) - 1))
        rows[r][c] = draw(cells)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    w.writerows(rows)
    return buf.getvalue()


def _outcome(fn, p):
    try:
        result = fn(p, _read_text(p))
    except InputError as err:
        return ("error", err.row, err.field)
    if result is None:  # the fast path declined (irregular file): nothing to compare
        return None
    table, rows = result
    return ("ok", rows, {c: [repr(v) for v in vals] for c, vals in table.items()})


def check_paths_agree(text: str) -> None:
    p = _write(text, ".csv")
    try:
        if _only_input_errors(_read_text, p) is None:
            return  # file-level problem (NUL bytes …): no path is involved
        fast = _outcome(_table_fast, p)
        slow = _outcome(_table_row_by_row, p)
        if fast is not None:
            assert fast == slow
        if slow[0] == "ok":  # pydantic accepts every row the vectorised checks accept
            assert len(read_parts(p)) == len(slow[1])
    finally:
        p.unlink()
        p.parent.rmdir()


LOG_COLS = ["time_s", "time_ms", "time_ns", "gyro_x_dps", "gyro_y_rps", "gyro_z_dph", "accel_x_mps2",
            "accel_y_g", "accel_z_ug", "temp_c", "gyro_x_dps", "junk", "gyro_q_dps", ""]


@st.composite
def log_texts(draw) -> tuple[bytes, str]:
    header = draw(st.lists(st.sampled_from(LOG_COLS), min_size=1, max_size=6))
    n = draw(st.integers(0, 60))
    regular = draw(st.booleans())
    lines = [",".join(header)]
    for i in range(n):
        if regular and draw(st.integers(0, 7)):
            vals = [f"{i * 0.01:.2f}" if h.startswith("time") else f"{(i * 7919 % 13) * 1e-3:.4g}"
                    for h in header]
        else:
            vals = [draw(numbers) if draw(st.integers(0, 3)) else draw(texts)
                    for _ in range(len(header) + draw(st.integers(-1, 1)))]
        lines.append(",".join(vals))
    data = ("\n".join(lines) + "\n").encode("utf-8", "surrogatepass")
    suffix = draw(st.sampled_from([".csv", ".csv", ".csv.gz", ".txt"]))
    if suffix == ".csv.gz":
        data = gzip.compress(data)
        if draw(st.booleans()):
            data = data[: draw(st.integers(0, len(data)))]
    return data, suffix


VALID_SCENARIO = dict(name="s", medium="radar", carrier_frequency_hz=9.6e9, slant_range_m=5000.0,
                      azimuth_resolution_m=0.5, range_resolution_m=0.5, platform_speed_m_s=50.0)
json_values = st.recursive(
    st.one_of(st.none(), st.booleans(), st.floats(), st.integers(-10 ** 50, 10 ** 50), st.text(max_size=20)),
    lambda kids: st.one_of(st.lists(kids, max_size=4), st.dictionaries(st.text(max_size=8), kids, max_size=4)),
    max_leaves=12)


@st.composite
def scenario_docs(draw) -> tuple[str, str]:
    data = dict(VALID_SCENARIO)
    keys = list(data) + ["squint_deg", "depression_deg", "window_broadening", "lever_arm_m",
                         "propagation_speed_m_s", "imu_rate_hz", "aiding", "aiding_mode", "extra"]
    for _ in range(draw(st.integers(0, 3))):
        data[draw(st.sampled_from(keys))] = draw(json_values)
    if draw(st.integers(0, 4)) == 0:
        data = draw(json_values)
    return _dump(draw, data)


def _dump(draw, data) -> tuple[str, str]:
    if draw(st.booleans()):
        return json.dumps(data, allow_nan=True), ".json"
    try:
        return yaml.safe_dump(data), ".yaml"
    except yaml.YAMLError:
        return json.dumps(data), ".json"


@st.composite
def model_docs(draw) -> tuple[str, str]:
    data = {"part_id": "M1", "grade": "tactical", "source": "s", "gyro_arw_deg_rt_h": 0.1}
    keys = list(data) + ["rate_hz", "accel_vrw_m_s_rt_h", "effects", "gyro_bias_instability_deg_h"]
    for _ in range(draw(st.integers(0, 3))):
        data[draw(st.sampled_from(keys))] = draw(json_values)
    if draw(st.booleans()):
        data["effects"] = [{"name": draw(st.sampled_from(["sinusoid", "rate_ramp", "lowpass", "x"])),
                            "channel": draw(st.sampled_from(["gyro_x", "accel_z", "q"])),
                            "params": draw(st.dictionaries(st.sampled_from(
                                ["amplitude", "frequency_hz", "R", "cutoff_hz", "phase_rad"]),
                                st.floats(), max_size=3))}]
    return _dump(draw, data)


# --- the property: success or InputError ------------------------------------------------------

def _write(data: bytes | str, suffix: str) -> Path:
    d = Path(tempfile.mkdtemp(prefix="sar_budget_fuzz_"))
    p = d / f"input{suffix}"
    p.write_bytes(data.encode("utf-8", "surrogatepass") if isinstance(data, str) else data)
    return p


def _only_input_errors(fn, *args, **kw):
    try:
        return fn(*args, **kw)
    except InputError:
        return None  # clear, one-line error: fine


def check_catalog(text: str) -> None:
    p = _write(text, ".csv")
    try:
        parts = _only_input_errors(read_parts, p)
        try:
            fast = _table_fast(p, _read_text(p))
        except InputError:
            fast = "error"
        if fast not in (None, "error"):
            # the pandas path and the exact path accept the same regular files, same values
            slow = _table_row_by_row(p, _read_text(p))
            assert fast[1] == slow[1] and set(fast[0]) == set(slow[0])
            for col, vals in fast[0].items():
                assert len(vals) == len(slow[0][col])
            # … and the per-row pydantic models agree with the vectorised checks
            assert parts is not None and len(parts) == len(fast[1])
        elif fast == "error":
            assert parts is None  # a file the fast path refuses is refused by read_parts too
    finally:
        p.unlink()
        p.parent.rmdir()


def check_log(case: tuple[bytes, str], repair: bool) -> None:
    data, suffix = case
    p = _write(data, suffix)
    try:
        _only_input_errors(read_log, p, repair=repair, rate_hz=100.0 if repair else None)
    finally:
        p.unlink()
        p.parent.rmdir()


def check_structured(loader, case: tuple[str, str]) -> None:
    text, suffix = case
    p = _write(text, suffix)
    try:
        _only_input_errors(loader, p)
    finally:
        p.unlink()
        p.parent.rmdir()


@FAST
@given(catalog_texts())
def test_fuzz_catalog_csv(text):
    check_catalog(text)


@FAST
@given(mostly_valid_catalogs())
def test_fuzz_catalog_fast_and_exact_paths_agree(text):
    check_paths_agree(text)


@FAST
@given(log_texts(), st.booleans())
def test_fuzz_log_csv(case, repair):
    check_log(case, repair)


@FAST
@given(scenario_docs())
def test_fuzz_scenario(case):
    check_structured(Scenario.load, case)


@FAST
@given(model_docs())
def test_fuzz_noise_model(case):
    check_structured(NoiseModel.load, case)


@FAST
@given(st.binary(max_size=300), st.sampled_from([".json", ".yaml", ".csv", ".csv.gz"]))
def test_fuzz_raw_bytes_every_reader(data, suffix):
    p = _write(data, suffix)
    try:
        for fn in (read_parts, read_log) if ".csv" in suffix else (Scenario.load, NoiseModel.load):
            _only_input_errors(fn, p)
    finally:
        p.unlink()
        p.parent.rmdir()


@pytest.mark.slow
@SLOW
@given(catalog_texts())
def test_fuzz_catalog_csv_1000(text):
    check_catalog(text)


@pytest.mark.slow
@SLOW
@given(mostly_valid_catalogs())
def test_fuzz_catalog_fast_and_exact_paths_agree_1000(text):
    check_paths_agree(text)


@pytest.mark.slow
@SLOW
@given(log_texts(), st.booleans())
def test_fuzz_log_csv_1000(case, repair):
    check_log(case, repair)


@pytest.mark.slow
@SLOW
@given(scenario_docs())
def test_fuzz_scenario_1000(case):
    check_structured(Scenario.load, case)


@pytest.mark.slow
@SLOW
@given(model_docs())
def test_fuzz_noise_model_1000(case):
    check_structured(NoiseModel.load, case)
