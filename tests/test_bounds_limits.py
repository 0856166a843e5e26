"""Bounds that stop constraining are said to (seed 004 (6)–(7): 0.2 δr/Tc² ≥ 1 caps the arcsin
of (7) at 90° and makes the scale-factor bounds ≥ 100 %), and a lever arm of the wrong length is
refused by name."""

import json
import math

import pytest

from budget.bounds import compute_bounds
from budget.errors import InputError
from budget.scenario import Scenario


def test_misalignment_cap_is_stated_exactly_where_the_arcsin_saturates():
    dr = 0.3
    tc_cap = math.sqrt(0.2 * dr)  # 0.2 δr / Tc² = 1 (seed 004 (7))
    table = compute_bounds([0.5 * tc_cap, 0.99 * tc_cap, 1.01 * tc_cap, 3.0], dr, "paper")
    notes = table.limit_notes()
    mis = [n for n in notes if n.startswith("misalignment")]
    assert len(mis) == 1
    listed = mis[0].split("Tc = ")[1].split(" s")[0].split(", ")
    assert [float(v) for v in listed] == pytest.approx([0.5 * tc_cap, 0.99 * tc_cap], rel=1e-3)
    # the accel scale-factor bound 0.2 δr/Tc² is ≥ 1 on the same Tc; the gyro's 0.1 δr/Tc² on fewer
    acc = [n for n in notes if n.startswith("accel scale factor")][0]
    assert len(acc.split("Tc = ")[1].split(" s")[0].split(", ")) == 2  # 0.2 δr/Tc² ≥ 1: Tc ≤ tc_cap
    gyro = [n for n in notes if n.startswith("gyro scale factor")][0]
    assert len(gyro.split("Tc = ")[1].split(" s")[0].split(", ")) == 1  # 0.1 δr/Tc² ≥ 1: Tc ≤ tc_cap/√2
    assert all(n in table.to_dict()["notes"] for n in notes)
    assert mis[0] in table.summary()


def test_no_limit_note_when_every_bound_constrains():
    table = compute_bounds([1.0, 3.0, 10.0], 0.3, "paper")
    assert table.limit_notes() == ()
    assert "capped" not in table.summary()


@pytest.mark.parametrize("arm", [[0.5, 0.3], [0.5, 0.3, 0.1, 0.2], [1.0]])
def test_lever_arm_of_the_wrong_length_is_refused_by_name(tmp_path, arm):
    data = {"name": "x", "carrier_frequency_hz": 9.6e9, "slant_range_m": 5000.0,
            "platform_speed_m_s": 100.0, "azimuth_resolution_m": 0.5, "range_resolution_m": 0.5,
            "lever_arm_m": arm}
    path = tmp_path / "s.json"
    path.write_text(json.dumps(data))
    with pytest.raises(InputError) as e:
        Scenario.load(path)
    text = str(e.value)
    assert "lever_arm_m" in text and f"{len(arm)} component" in text and "three numbers" in text
    assert "Field required" not in text
