"""`sar-budget sar` judges the sidelobe checks a scene's own noise floor fails against the
error-free image of the same scene and noise: an error-free Taylor image at the command's
default 50 dB SNR failed acceptance (azimuth ISLR −20.4 … −21.8 dB against the window's ideal
−27.13 + 3 dB), since the whole-line ISLR integrates the receiver noise whatever the focus. A
large injected error gets room in the image, as the Monte Carlo's ``defocus_room_cells``.
"""

from __future__ import annotations

import numpy as np

from budget.cli.main import main
from budget.presets import get_preset
from budget.sar import SarGeometry, Scene
from budget.sar.injected import run_injected_phase_trial
from budget.sar.phase import normalised_time, smooth_phase_error


def _geom():
    scen = get_preset("airborne_xband").model_copy(update={"window_broadening": 1.2})
    return SarGeometry.from_scenario(scen, window="taylor")


def test_an_error_free_noisy_image_passes_and_says_what_it_was_judged_against():
    geom = _geom()
    scene = Scene.default(geom, snr_db=50.0)
    trial = run_injected_phase_trial(geom, scene, 0.0, np.random.default_rng(0))
    assert trial.evaluation_before.passed and trial.evaluation_after.passed
    assert "error-free image" in trial.reference_note and "islr_db" in trial.reference_note
    # the checks it moved are the ISLRs the noise lifted above ideal + 3 dB
    moved = trial.evaluation_after.checks
    islr = moved[(moved["check"] == "islr_db") & (moved["axis"] == "azimuth")]
    ideal = trial.after.to_frame()["azimuth_ideal_islr_db"].to_numpy()
    assert np.allclose(ideal, -27.13, atol=0.01)               # Taylor −35 dB, n̄ = 4
    assert (islr["value"].to_numpy() > ideal + 3.0).all()      # what failed before
    assert (islr["limit"].to_numpy() > ideal + 3.0).all()      # now the error-free value + 3 dB


def test_a_noise_free_scene_is_judged_against_the_window_alone():
    geom = _geom()
    trial = run_injected_phase_trial(geom, Scene.default(geom, snr_db=None), 0.0, None)
    assert trial.evaluation_after.passed and trial.reference_note == ""


def test_a_large_error_still_fails_on_the_noisy_scene():
    # 6 rad of quadratic phase: the image before PGA is defocused far beyond any noise floor
    geom = _geom()
    psi = smooth_phase_error(normalised_time(geom), quadratic_rad=6.0)
    trial = run_injected_phase_trial(geom, Scene.default(geom, snr_db=50.0), psi, np.random.default_rng(0))
    assert not trial.evaluation_before.passed
    assert any("broadening" in r or "peak_loss" in r for r in trial.evaluation_before.reasons)


def test_the_cli_prints_pass_for_an_error_free_taylor_image(tmp_path, capsys):
    assert main(["sar", "--preset", "airborne_xband", "--window", "taylor", "--quadratic-rad", "0",
                 "--cubic-rad", "0", "--sinusoid-rad", "0"]) == 0
    out = capsys.readouterr().out
    assert out.count("acceptance: PASS") == 2 and "acceptance: FAIL" not in out


def test_a_large_injected_error_gets_room_in_the_image_instead_of_aliasing(capsys):
    # 60 u² spreads a response over ±120/π ≈ ±38 azimuth cells; the 77 GHz image had 16 cells of
    # margin, the defocus aliased, and PGA "converged" 18 rad rms away from the truth
    assert main(["sar", "--preset", "automotive_77ghz", "--quadratic-rad", "60", "--cubic-rad", "0",
                 "--sinusoid-rad", "0"]) == 0
    out = capsys.readouterr().out
    resid = float(out.split("residual vs truth ")[1].split(" rad")[0])
    assert resid < 0.5
    assert "acceptance: PASS" in out.split("after PGA:")[1]
