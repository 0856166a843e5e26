"""Logs in public layouts: a ROS ``rostopic echo -p`` export and a visual-inertial dataset's
``#timestamp [ns], w_RS_S_x [rad s^-1] …`` header. Neither is read without a mapping (their names
are not canonical), but the refusal suggests the mapping that reads them — with the units the
layout states (REP 103's SI for ROS, the bracketed units otherwise) — instead of a misleading
"preamble lines" hint; the suggested mapping then reads the log to the white-noise level that
generated it."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from budget.errors import InputError
from budget.noise import LogMapping, read_log
from budget.noise.log_mapping import suggest_mapping

RATE_HZ = 200.0
GYRO_SIGMA_RAD_S, ACCEL_SIGMA_M_S2 = 2e-3, 2e-2
T0_NS = 1_403_636_579_758_555_392  # a dataset's epoch stamp: ≈ 1.4e18 ns

EUROC = ["#timestamp [ns]", *(f"w_RS_S_{a} [rad s^-1]" for a in "xyz"), *(f"a_RS_S_{a} [m s^-2]" for a in "xyz")]
ROS = ["%time", "field.header.seq", "field.header.stamp", "field.header.frame_id",
       *(f"field.orientation.{a}" for a in "xyzw"), *(f"field.angular_velocity.{a}" for a in "xyz"),
       *(f"field.linear_acceleration.{a}" for a in "xyz")]


def _write(path, header, n=4000, seed=3):
    rng = np.random.default_rng(seed)
    g = rng.normal(0.0, GYRO_SIGMA_RAD_S, (n, 3))
    a = rng.normal(0.0, ACCEL_SIGMA_M_S2, (n, 3)) + (0.0, 0.0, 9.81)
    t = T0_NS + np.arange(n) * int(1e9 / RATE_HZ)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(",".join(header) + "\n")
        for i in range(n):
            lead = [str(t[i])] if header is EUROC else [str(t[i]), str(i), str(t[i]), "imu_link", "0", "0", "0", "1"]
            fh.write(",".join(lead + [f"{v:.9g}" for v in (*g[i], *a[i])]) + "\n")
    return path


@pytest.mark.parametrize("header,expected", [
    (EUROC, {"#timestamp [ns]": "time_ns", **{f"w_RS_S_{a} [rad s^-1]": f"gyro_{a}_rps" for a in "xyz"},
             **{f"a_RS_S_{a} [m s^-2]": f"accel_{a}_mps2" for a in "xyz"}}),
    (ROS, {"%time": "time_ns", **{f"field.angular_velocity.{a}": f"gyro_{a}_rps" for a in "xyz"},
           **{f"field.linear_acceleration.{a}": f"accel_{a}_mps2" for a in "xyz"}}),
])
def test_public_layouts_get_the_mapping_that_reads_them(tmp_path, header, expected):
    assert suggest_mapping(header) == expected
    path = _write(tmp_path / "imu.csv", header)
    with pytest.raises(InputError) as err:
        read_log(path)
    text = str(err.value)
    assert "looks like sensor columns" in text and "preamble" not in text, text
    assert json.dumps(expected)[1:-1] in text  # the mapping, as JSON a user can paste
    log = read_log(path, LogMapping(columns=expected))
    assert log.rate_hz == pytest.approx(RATE_HZ, rel=1e-9)
    n = log.n_samples
    for ch, sigma in (("gyro_x", GYRO_SIGMA_RAD_S), ("accel_y", ACCEL_SIGMA_M_S2)):
        # sample standard deviation of n Gaussian samples: relative standard error 1/√(2(n−1))
        assert np.std(log.channels[ch]) == pytest.approx(sigma, rel=4 / math.sqrt(2 * (n - 1)))


def test_a_sensor_name_without_axes_of_one_kind_is_not_suggested():
    assert suggest_mapping(["angle_x", "angle_y", "angle_z", "Temp"]) == {}
    assert suggest_mapping(["GyroX", "GyroY", "GyroZ"]) == {f"Gyro{a.upper()}": f"gyro_{a}_dps" for a in "xyz"}


def test_bracketed_exponent_units_are_read_on_canonical_channels(tmp_path):
    path = tmp_path / "exp.csv"
    rng = np.random.default_rng(4)
    rows = "".join(f"{i / 100:.2f},{rng.normal(0, 1e-3):.6g},{9.81 + rng.normal(0, 1e-2):.6g}\n" for i in range(500))
    path.write_text("time [s],gyro_z [rad s^-1],accel_z [m s^-2]\n" + rows, encoding="utf-8")
    log = read_log(path)
    assert log.source_units["gyro_z"] == "rps" and log.source_units["accel_z"] == "mps2"
    assert np.mean(log.channels["accel_z"]) == pytest.approx(9.81, abs=5e-3)


# --- a characterisation carries what the reader found and changed in the record it fitted -----------

def _plain_log(path, n=6000, jitter=0.0, nan_row=None, seed=6):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / 100.0 + rng.uniform(-jitter, jitter, n) / 100.0
    g = rng.normal(0.0, 1e-3, n)
    a = 9.81 + rng.normal(0.0, 1e-2, n)
    lines = [f"{ti:.6f},{'nan' if i == nan_row else f'{gi:.6g}'},{ai:.6g}"
             for i, (ti, gi, ai) in enumerate(zip(t, g, a))]
    path.write_text("time_s,gyro_z_dps,accel_z_mps2\n" + "\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_a_characterisation_carries_the_readers_warnings_and_repairs(tmp_path):
    from budget.noise import characterize

    jittery = read_log(_plain_log(tmp_path / "jitter.csv", jitter=0.3))
    warned = [i.text() for i in jittery.issues.issues if i.severity == "warning"]
    assert warned, "the generator's ±30 % stamp jitter is what the reader warns of"
    res = characterize(jittery)
    assert res.log_findings and all(w.removeprefix("warning: ") in res.log_findings for w in warned)
    assert res.to_dict()["log_findings"] == res.log_findings
    assert "log: " in res.summary()

    repaired = read_log(_plain_log(tmp_path / "gap.csv", nan_row=2500), repair=True)
    assert repaired.issues.repairs
    res = characterize(repaired)
    assert any(f.startswith("log repaired: ") for f in res.log_findings), res.log_findings
    assert "log repaired before the fit" in res.part.notes

    clean = characterize(read_log(_plain_log(tmp_path / "clean.csv")))
    assert clean.log_findings == [] and "repaired" not in clean.part.notes


def test_a_record_too_short_for_the_long_tau_terms_is_said_so(tmp_path):
    from budget.noise import characterize
    from budget.noise.characterize import SHORT_RECORD_TAU_S

    short = characterize(read_log(_plain_log(tmp_path / "short.csv", n=60)))
    said = [w for w in short.warnings if "the record is short" in w]
    assert len(said) == 1 and "bias instability" in said[0], short.warnings
    assert max(float(r.tau_s.max()) for r in short.allan.values()) < SHORT_RECORD_TAU_S
    no_floor = short.part.gyro_bias_instability_deg_h is None and short.part.accel_bias_instability_ug is None
    assert ("inferred from the white-noise terms alone" in said[0]) == no_floor  # nothing else to grade by
    white_only = characterize(read_log(_plain_log(tmp_path / "short.csv", n=60)), terms=("Q", "N"))
    assert any("inferred from the white-noise terms alone" in w for w in white_only.warnings)
    # two minutes at 100 Hz: the Allan deviation reaches past 10 s, no such warning
    enough = characterize(read_log(_plain_log(tmp_path / "two_min.csv", n=12_000)))
    assert max(float(r.tau_s.max()) for r in enough.allan.values()) >= SHORT_RECORD_TAU_S
    assert not any("the record is short" in w for w in enough.warnings)
