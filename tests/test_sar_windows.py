"""Windows and their ideal impulse responses against closed forms and scipy's Taylor window."""

import math

import numpy as np
import pytest
from scipy import integrate
from scipy.signal import windows as sw

from budget.errors import InputError
from budget.sar.irf import measure_cut, upsample_periodic
from budget.sar.windows import Window, ideal_irf


@pytest.mark.parametrize("n", [64, 101, 462])
@pytest.mark.parametrize("nbar", [4, 5])
def test_taylor_samples_match_scipy(n, nbar):
    ours = Window(kind="taylor", sidelobe_db=-35, nbar=nbar).samples(n)
    assert np.allclose(ours, sw.taylor(n, nbar=nbar, sll=35, norm=True), atol=1e-12)


def test_rect_ideal_matches_sinc_theory():
    ideal = ideal_irf(Window())
    assert ideal.pslr_db == pytest.approx(-13.26, abs=0.01)
    assert ideal.width_3db_cells == pytest.approx(0.886, abs=0.001)
    assert ideal.first_null_cells == pytest.approx(1.0, abs=1e-3)
    # infinite extent: main lobe ±1 null holds 90.28 % of the energy → −9.68 dB
    main, _ = integrate.quad(lambda x: np.sinc(x) ** 2, -1, 1, limit=200)
    assert ideal.islr_db == pytest.approx(10 * math.log10((1 - main) / main), abs=0.01)
    assert ideal.islr_db == pytest.approx(-9.68, abs=0.02)
    # finite extent ±10 cells: closed-form integral of sinc²
    side, _ = integrate.quad(lambda x: np.sinc(x) ** 2, 1, 10, limit=400)
    assert ideal_irf(Window(), 10).islr_db == pytest.approx(10 * math.log10(2 * side / main), abs=0.02)


@pytest.mark.parametrize("nbar", [4, 5])
def test_taylor_ideal_matches_sampled_window(nbar):
    """Independent route: DFT of scipy's sampled Taylor window, measured on a long line."""
    w = Window(kind="taylor", sidelobe_db=-35, nbar=nbar)
    ideal = ideal_irf(w)
    m, n = 257, 257 * 8
    spec = np.zeros(n, complex)
    spec[np.mod(np.arange(m) - (m - 1) // 2, n)] = sw.taylor(m, nbar=nbar, sll=35)
    line = np.fft.ifft(spec)
    cell = n / m  # samples per resolution cell
    up = upsample_periodic(line, 8)
    meas = measure_cut(up, 1 / 8, 0.0, expected_index=0, search_half=8, null=ideal.first_null_cells * cell)
    assert meas.width_3db / cell == pytest.approx(ideal.width_3db_cells, rel=2e-3)
    assert meas.pslr_db == pytest.approx(ideal.pslr_db, abs=0.1)
    assert meas.islr_db == pytest.approx(ideal.islr_db, abs=0.1)
    # Taylor −35 dB: sidelobes at −35 dB, main lobe broadened ≈ 1.18–1.19× the rect one (0.886)
    assert -35.5 < ideal.pslr_db < -34.8
    assert 1.15 < ideal.width_3db_cells / 0.886 < 1.36


def test_rect_line_measurement_reproduces_theory():
    """Unweighted periodic line (Dirichlet kernel) measured by measure_cut: −13.26 dB, 0.886, −9.7."""
    m, n = 313, 313 * 6
    spec = np.zeros(n, complex)
    spec[np.mod(np.arange(m) - (m - 1) // 2, n)] = 1.0
    up = upsample_periodic(np.fft.ifft(spec), 16)
    cell = n / m
    meas = measure_cut(up, 1 / 16, 0.0, expected_index=0, search_half=16, null=cell)
    assert meas.pslr_db == pytest.approx(-13.26, abs=0.03)
    assert meas.width_3db / cell == pytest.approx(0.886, abs=0.002)
    assert meas.islr_db == pytest.approx(-9.68, abs=0.05)


def test_window_parse():
    assert Window.parse("rect").kind == "rect"
    t = Window.parse("taylor-40-5")
    assert (t.kind, t.sidelobe_db, t.nbar) == ("taylor", -40.0, 5)
    for bad in ("hann", "taylor-x", 3):
        with pytest.raises(InputError):
            Window.parse(bad)
