"""Sampling geometry from a scenario, and clear errors for scenarios and inputs that do not fit."""

import numpy as np
import pytest

from budget.errors import InputError
from budget.presets import PRESETS, get_preset
from budget.sar import PointTarget, SarGeometry, Scene, form_image, measure_targets, simulate_echoes


@pytest.fixture(scope="module")
def geom():
    return SarGeometry.from_scenario(get_preset("airborne_xband"))


def test_airborne_sampling_follows_the_scenario(geom):
    s = get_preset("airborne_xband")
    assert geom.aperture_time_s == pytest.approx(s.tc_s, rel=1e-12)
    # Doppler bandwidth of one target a_w V / δℓ and PRF above it plus the scene's spread
    assert geom.doppler_bandwidth_hz == pytest.approx(s.window_broadening * s.platform_speed_m_s
                                                      / s.azimuth_resolution_m, rel=1e-9)
    assert geom.prf_hz >= 1.25 * geom.doppler_bandwidth_hz
    assert geom.azimuth_cell_m() == pytest.approx(s.azimuth_resolution_m, rel=1e-9)
    # range band c/(2δr) realised with whole DFT bins: within one bin
    assert geom.range_bandwidth_hz == pytest.approx(3e8 / (2 * s.range_resolution_m), rel=0.02)
    assert geom.height_m == pytest.approx(s.slant_range_m * np.sin(np.radians(s.depression_deg)))
    assert geom.n_pulses <= 512 and geom.n_range <= 256


@pytest.mark.parametrize("name", [n for n in PRESETS if n != "airborne_xband_long_range"])
def test_presets_fit_a_small_grid(name):
    g = SarGeometry.from_scenario(get_preset(name))
    assert g.n_pulses <= 512 and g.n_range <= 256
    assert g.n_azimuth * g.speed_m_s / g.prf_hz >= g.scene_extent_m[0]


def test_too_many_pulses_names_field_and_limit():
    with pytest.raises(InputError) as err:
        SarGeometry.from_scenario(get_preset("airborne_xband_long_range"))
    assert err.value.field == "azimuth_resolution_m" and "16384" in str(err.value)
    with pytest.raises(InputError, match="M pixels"):  # within the pulses, beyond the pixel limit
        SarGeometry.from_scenario(get_preset("airborne_xband_long_range"), max_pulses=32768, oversample=1.1)
    g = SarGeometry.from_scenario(get_preset("airborne_xband_long_range"), max_pulses=32768, oversample=1.1,
                                  max_pixels=1 << 25)
    assert g.n_pulses > 16384


def test_bad_scenarios_raise():
    base = get_preset("airborne_xband")
    with pytest.raises(InputError) as err:  # aperture shorter than a few pulses
        SarGeometry.from_scenario(base.model_copy(update={"azimuth_resolution_m": 40.0}))
    assert err.value.field == "azimuth_resolution_m" and "pulses" in str(err.value)
    with pytest.raises(InputError) as err:  # resolution finer than the carrier allows
        SarGeometry.from_scenario(get_preset("sas_100khz").model_copy(update={"range_resolution_m": 0.005}))
    assert err.value.field == "range_resolution_m"
    with pytest.raises(InputError) as err:  # zero speed (bypassing pydantic as a caller could)
        SarGeometry.from_scenario(base.model_construct(**{**base.model_dump(), "platform_speed_m_s": 0.0}))
    assert err.value.field == "platform_speed_m_s"
    with pytest.raises(InputError):
        SarGeometry.from_scenario(base, oversample=1.0)


def test_degenerate_inputs_give_clear_errors(geom):
    with pytest.raises(InputError, match="no targets"):
        simulate_echoes(geom, Scene(), None)
    with pytest.raises(InputError, match="outside") as err:
        simulate_echoes(geom, Scene(targets=[PointTarget(azimuth_m=0, range_m=0),
                                             PointTarget(azimuth_m=0, range_m=500)]), None)
    assert err.value.row == 1
    with pytest.raises(InputError) as err:
        simulate_echoes(geom, Scene(targets=[PointTarget(azimuth_m=0, range_m=0)]), np.zeros((3, 3)))
    assert err.value.field == "true_offset_m"
    bad = np.zeros((geom.n_pulses, 3))
    bad[5, 1] = np.nan
    with pytest.raises(InputError, match="NaN"):
        simulate_echoes(geom, Scene(targets=[PointTarget(azimuth_m=0, range_m=0)]), bad)
    with pytest.raises(InputError) as err:  # noise needs a generator
        simulate_echoes(geom, Scene(targets=[PointTarget(azimuth_m=0, range_m=0)], snr_db=30), None)
    assert err.value.field == "rng"
    data = simulate_echoes(geom, Scene(targets=[PointTarget(azimuth_m=0, range_m=0)]), None)
    data[10, 20] = np.nan
    with pytest.raises(InputError, match="NaN") as err:
        form_image(geom, data)
    assert err.value.field == "data"
    with pytest.raises(InputError):
        form_image(geom, data[:, :10])
    with pytest.raises(InputError, match="method"):
        form_image(geom, np.zeros((geom.n_pulses, geom.n_range)), method="pfa")
    img = form_image(geom, np.zeros((geom.n_pulses, geom.n_range)))
    with pytest.raises(InputError, match="no point targets"):
        measure_targets(img, geom, Scene(clutter_to_target_db=-10))
    with pytest.raises(InputError):
        Scene.build(targets=[{"azimuth_m": 0, "range_m": 0, "amplitude": -1}])


def test_sar_cli_demo(tmp_path, capsys):
    import json

    from budget.cli.main import main
    out = tmp_path / "sar.json"
    assert main(["sar", "--preset", "airborne_xband", "--json", str(out)]) == 0
    rep = json.loads(out.read_text())
    assert rep["pga"]["converged"] and rep["passed_after"] and not rep["passed_before"]
    assert rep["residual_rms_rad"] < 0.05
    assert main(["sar", "--preset", "airborne_xband_long_range"]) == 2
    assert "16384" in capsys.readouterr().err
