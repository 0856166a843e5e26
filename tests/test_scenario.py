"""Scenario model: derived quantities, presets, I/O and bad input."""

import json
import math

import pytest

from budget.errors import InputError
from budget.presets import PRESETS, get_preset
from budget.scenario import Scenario


def test_tc_formula_seed004_eq5():
    s = Scenario(carrier_frequency_hz=24e9, slant_range_m=50, azimuth_resolution_m=0.1,
                 range_resolution_m=0.1, platform_speed_m_s=20)
    lam = 299_792_458 / 24e9
    assert s.wavelength_m == pytest.approx(lam)
    assert s.tc_s == pytest.approx(lam * 50 / (2 * 0.1 * 20))
    assert s.aperture_length_m == pytest.approx(20 * s.tc_s)
    # squint: θ = 90° − squint lengthens Tc by 1/cos(squint); broadening scales it linearly
    sq = s.model_copy(update={"squint_deg": 30.0, "window_broadening": 1.3})
    assert sq.tc_s == pytest.approx(s.tc_s * 1.3 / math.cos(math.radians(30)))


def test_sonar_default_speed():
    s = get_preset("sas_100khz")
    assert s.c_m_s == 1500.0 and s.wavelength_m == pytest.approx(0.015)


def test_automotive_presets_below_one_second():
    # seed 004: automotive SAR (24/77 GHz, R ≤ 50/500 m, V = 15–40 m/s, δℓ = 0.1 m) → Tc < 1 s
    for name in ("automotive_24ghz", "automotive_77ghz"):
        assert get_preset(name).tc_s < 1.0
    assert get_preset("missile_borne").platform_speed_m_s == 200.0


@pytest.mark.parametrize("suffix", [".json", ".yaml"])
def test_roundtrip(tmp_path, suffix):
    for s in PRESETS.values():
        p = tmp_path / f"{s.name}{suffix}"
        s.save(p)
        assert Scenario.load(p) == s


@pytest.mark.parametrize("patch,field", [
    ({"platform_speed_m_s": 0}, "platform_speed_m_s"),
    ({"slant_range_m": float("nan")}, "slant_range_m"),
    ({"medium": "lidar"}, "medium"),
    ({"unknown_key": 1}, "unknown_key"),
    ({"window_broadening": 0.5}, "window_broadening"),
])
def test_bad_scenarios_name_the_field(tmp_path, patch, field):
    data = get_preset("airborne_xband").model_dump(mode="json") | patch
    p = tmp_path / "s.json"
    p.write_text(json.dumps(data).replace("NaN", "NaN"))
    with pytest.raises(InputError) as e:
        Scenario.load(p)
    assert field in str(e.value) and "s.json" in str(e.value)


def test_bad_files(tmp_path):
    empty = tmp_path / "e.json"
    empty.write_text("")
    with pytest.raises(InputError, match="empty"):
        Scenario.load(empty)
    broken = tmp_path / "b.json"
    broken.write_text("{not json")
    with pytest.raises(InputError, match="not valid JSON"):
        Scenario.load(broken)
    with pytest.raises(InputError, match="not found"):
        Scenario.load(tmp_path / "missing.json")
    lst = tmp_path / "l.json"
    lst.write_text("[1, 2]")
    with pytest.raises(InputError, match="mapping"):
        Scenario.load(lst)
    with pytest.raises(InputError, match="unknown preset"):
        get_preset("nope")


@pytest.mark.parametrize("field, value", [("range_resolution_m", 0.005), ("azimuth_resolution_m", 0.005)])
def test_resolutions_no_radar_can_have_are_refused_naming_the_field(field, value):
    """9.6 GHz (λ/4 = 7.8 mm): δr = 5 mm needs a 30 GHz bandwidth (the band's lower edge below
    0 Hz), δℓ = 5 mm is finer than a 180° aperture gives — refused by the scenario itself, not
    only by the simulator, so the analytic check never gives such a case a verdict."""
    base = dict(name="x", carrier_frequency_hz=9.6e9, slant_range_m=1000.0, azimuth_resolution_m=0.5,
                range_resolution_m=0.5, platform_speed_m_s=50.0)
    with pytest.raises(InputError) as err:
        Scenario.from_dict({**base, field: value})
    assert err.value.field == field and "λ/4" in err.value.expected
    Scenario.from_dict({**base, field: 0.01})  # just above λ/4: accepted
