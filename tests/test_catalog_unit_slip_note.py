"""A single catalog figure typed in another unit than its column's is named in the row notes.

The slips are written here from the units' definitions (not from the note's thresholds): a
datasheet figure in deg/s typed into a deg/h column is 3600× too small, mg into µg 1000×, % into
ppm 10⁴×, a noise density in µg/√Hz typed as m/s/√h 1699.5× too large (1 m/s/√h = 1/60 m/s²/√Hz
= 1699.5 µg/√Hz). One slipped figure among a row's given ones left the row's median grade, and so
every note, unchanged before.
"""

from __future__ import annotations

import json

import pytest
from pydantic import ValidationError

from budget.catalog.fill import FAR_BETTER, FAR_WORSE, resolve_unspecified, row_warnings
from budget.catalog.io import load_catalog, load_grades, shipped_catalog_dir
from budget.cli.main import main

G0 = 9.80665
UG_RT_HZ_PER_M_S_RT_H = 1.0 / 60.0 / (G0 * 1e-6)  # 1699.5

#: column → factor a figure is multiplied by when typed in the named other unit
SLIPS = {
    "gyro_bias_instability_deg_h": (1.0 / 3600.0, "deg/s typed as deg/h"),
    "accel_bias_instability_ug": (1.0 / 1000.0, "mg typed as µg"),
    "accel_bias_repeatability_ug": (1.0 / 1000.0, "mg typed as µg"),
    "gyro_scale_factor_ppm": (1e-4, "% typed as ppm"),
    "accel_scale_factor_ppm": (1e-4, "% typed as ppm"),
    "accel_vrw_m_s_rt_h": (UG_RT_HZ_PER_M_S_RT_H, "µg/√Hz typed as m/s/√h"),
}

SLIP_WORDS = "often typed in another unit"


def _parts():
    cat = load_catalog()
    return list(cat.values()) if isinstance(cat, dict) else list(getattr(cat, "parts", cat))


def test_no_shipped_part_is_named_as_a_unit_slip():
    # the thresholds leave room for what real rows do: consumer parts beat the printed consumer
    # row by up to 40× (ICM-20948 scale factor), no figure is worse than its grade's worst by > 3.4×
    assert FAR_WORSE >= 5 and FAR_BETTER >= 50
    grades = load_grades()
    flagged = [p.part_id for p in _parts() if any(SLIP_WORDS in n for n in row_warnings(p, grades))]
    assert flagged == []


@pytest.mark.parametrize("column", sorted(SLIPS))
def test_each_shipped_figure_slipped_by_a_large_unit_factor_is_named(column):
    # every shipped figure of the column, slipped, is either refused by the row's schema (its
    # physical range) or named in the row notes; an in-run bias instability (adev_min) may lie
    # far below its grade's turn-on bias, so only total / turn-on figures are slipped downwards
    factor, what = SLIPS[column]
    grades = load_grades()
    named = refused = 0
    for part in _parts():
        value = getattr(part, column)
        if value is None or part.grade is None or value <= 0:
            continue
        if column.endswith("instability_deg_h") or column.endswith("instability_ug"):
            if not part.bias_is_constant:
                continue
        try:
            slipped = type(part).model_validate({**part.model_dump(), column: value * factor})
        except ValidationError:
            refused += 1
            continue
        notes = [n for n in row_warnings(slipped, grades) if SLIP_WORDS in n]
        assert len(notes) == 1 and column in notes[0], (part.part_id, what, row_warnings(slipped, grades))
        # the Monte Carlo's resolution of the same row carries the same words
        assert any(column in w and SLIP_WORDS in w for w in resolve_unspecified(slipped).warnings)
        named += 1
    assert named >= 1, f"no shipped part gives {column} (refused by the schema: {refused})"


def test_an_in_run_figure_far_below_its_grades_turn_on_bias_is_not_named():
    # an in-run instability may undercut a grade's turn-on bias by 10³ (ADIS16465-1: 3.6 µg
    # against the industrial 3000 µg); only its worse side is judged
    grades = load_grades()
    part = next(p for p in _parts() if p.part_id == "ADIS16465-1")
    assert part.accel_bias_instability_ug is not None
    assert not any(SLIP_WORDS in n for n in row_warnings(part, grades))
    worse = part.model_copy(update={"accel_bias_instability_ug": part.accel_bias_instability_ug * 1000 * 1000})
    assert any("accel_bias_instability_ug" in n and SLIP_WORDS in n for n in row_warnings(worse, grades))


def test_check_prints_the_slipped_figure_as_a_row_note(tmp_path, capsys):
    # STIM300's accelerometer bias repeatability 750 µg typed in mg (0.75): before, check said
    # nothing, and the part's airborne X-band verdict rested on a 1000× better bias
    lines = (shipped_catalog_dir() / "parts.csv").read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    row = next(r for r in lines[1:] if r.startswith("STIM300,")).split(",")
    i = header.index("accel_bias_repeatability_ug")
    given = float(row[i])
    row[0], row[i] = "MYSTIM", f"{given / 1000:g}"
    path = tmp_path / "mine.csv"
    path.write_text(lines[0] + "\n" + ",".join(row) + "\n", encoding="utf-8")
    assert main(["check", "--preset", "airborne_xband", "--catalog", str(path), "--part", "MYSTIM"]) == 0
    text = capsys.readouterr().out
    assert "row note, MYSTIM: MYSTIM: accel_bias_repeatability_ug = 0.75 µg" in text and SLIP_WORDS in text
    out = tmp_path / "c.json"
    assert main(["check", "--preset", "airborne_xband", "--catalog", str(path), "--part", "MYSTIM",
                 "--json", str(out)]) == 0
    rec = json.loads(out.read_text(encoding="utf-8"))["parts"][0]
    assert any("accel_bias_repeatability_ug" in n and SLIP_WORDS in n for n in rec["row_notes"])
