"""No silent zeros: what a Monte Carlo does with a part's unspecified error terms.

An empty catalog cell means "the datasheet does not say" (never "zero error"). Before a Monte
Carlo the eight checked quantities of :data:`budget.parameters.PARAMETERS` are resolved by a
policy (``McOptions.unspecified``):

* ``fill_grade_typical`` (default): each empty one gets its grade's typical value from
  ``catalog/grades.csv`` (seed 004 Tables 3–4), the geometric mean of the grade's min–max range
  (:func:`budget.parameters.grade_value`); the filled values are recorded in the result;
* ``refuse``: an :class:`~budget.errors.InputError` naming the empty columns;
* ``zero``: the user states that the absent terms are zero (synthetic single-term models);
  recorded as such.

A grade's bias (Tables 3–4) is a total / turn-on figure (STIM300: in-run 50 µg but on/off
750 µg), so for the bias the *turn-on* term is what a grade can fill: the repeatability column
of an ``adev_min`` / ``ieee_b`` row (in-run and turn-on are two terms there; an empty in-run
figure has no grade value and is listed as taken as 0), the bias column of a ``total_1sigma`` /
``turn_on_1sigma`` row. A noise model whose ``effects`` already carry white noise or a bias
process on a triad has that term specified. Rate random walk has no grade value; it stays 0
when empty and is listed under ``not_modelled``. A model without a grade cannot be filled:
``fill_grade_typical`` then records its empty terms as zero (and says so).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..errors import InputError
from ..parameters import PARAMETERS, Parameter, grade_value
from .schema import GradeSpec, PartSpec

POLICIES = ("fill_grade_typical", "refuse", "zero")
DEFAULT_POLICY = "fill_grade_typical"

#: Effects of a noise model that carry a quantity's family on a triad.
_EFFECTS_FOR = {"noise": ("white_noise", "heavy_tailed"),
                "bias": ("bias_instability", "gauss_markov", "rate_random_walk")}
#: Columns without a grade value (left at 0 when empty, and listed).
_NO_GRADE_VALUE = ("gyro_rrw_deg_h_rt_h",)
_REPEATABILITY = {"gyro": "gyro_bias_repeatability_deg_h", "accel": "accel_bias_repeatability_ug"}


@dataclass(frozen=True)
class Fill:
    """One filled value: ``column`` set to ``value`` (datasheet ``unit``) for the empty ``quantity``."""

    quantity: str
    column: str
    value: float
    unit: str
    source: str

    def to_dict(self) -> dict:
        return {"quantity": self.quantity, "column": self.column, "value": self.value,
                "unit": self.unit, "source": self.source}


@dataclass(frozen=True)
class Resolution:
    """What was unspecified in a model and how it was resolved (recorded in the MC result)."""

    model: object
    policy: str
    grade: str | None
    unspecified: tuple[str, ...] = ()
    filled: tuple[Fill, ...] = ()
    zeroed: tuple[str, ...] = ()
    not_modelled: tuple[str, ...] = ()
    notes: tuple[str, ...] = field(default=())
    #: what the user should look at in the row itself (a grade its figures contradict, a figure
    #: written as 0); result summaries state these beside the fills
    warnings: tuple[str, ...] = field(default=())

    def to_dict(self) -> dict:
        return {"policy": self.policy, "grade": self.grade, "unspecified": list(self.unspecified),
                "filled": [f.to_dict() for f in self.filled], "zero": list(self.zeroed),
                "not_modelled": list(self.not_modelled), "notes": list(self.notes),
                "warnings": list(self.warnings)}

    def to_frame(self) -> pd.DataFrame:
        """One row per unspecified column: how it was resolved (``filled``, ``zero``, ``not modelled``),
        with the value (datasheet unit) and its source for a fill."""
        rows = [{"column": f.column, "resolved": "filled", "value": f.value, "unit": f.unit, "source": f.source}
                for f in self.filled]
        rows += [{"column": c, "resolved": "zero", "value": 0.0, "unit": "", "source": self.policy}
                 for c in self.zeroed]
        rows += [{"column": c, "resolved": "not modelled", "value": None, "unit": "", "source": self.policy}
                 for c in self.not_modelled]
        return pd.DataFrame(rows, columns=["column", "resolved", "value", "unit", "source"])

    def summary(self) -> str:
        """One line for result summaries."""
        if not self.unspecified:
            return "; ".join([f"no unspecified datasheet terms ({self.policy})", *self.warnings])
        parts = []
        if self.filled:
            parts.append("filled from the " + (self.grade or "?") + " grade's typical values: "
                         + ", ".join(f"{f.column} = {f.value:.4g} {f.unit}" for f in self.filled))
        if self.zeroed:
            parts.append("taken as 0: " + ", ".join(self.zeroed))
        return f"unspecified datasheet terms ({self.policy}): " + "; ".join(parts + list(self.warnings))


def _effect_triads(model, names: tuple[str, ...]) -> set[str]:
    return {f.channel.split("_")[0] for f in getattr(model, "effects", ()) if f.name in names}


def _has_effect(model, prm: Parameter) -> bool:
    names = _EFFECTS_FOR.get(prm.family)
    return bool(names) and prm.triad in _effect_triads(model, names)


def unspecified_quantities(model) -> tuple[str, ...]:
    """Columns ``model`` leaves unspecified among the eight checked quantities — where, for the
    bias of an ``adev_min`` / ``ieee_b`` row, the in-run column and the turn-on (repeatability)
    column are two separate terms."""
    if not isinstance(model, PartSpec):
        return ()
    out = []
    for prm in PARAMETERS:
        if prm.family == "bias" and not model.bias_is_constant:
            if getattr(model, prm.column) is None and not _has_effect(model, prm):
                out.append(prm.column)
            if getattr(model, _REPEATABILITY[prm.triad]) is None:
                out.append(_REPEATABILITY[prm.triad])
        elif getattr(model, prm.column) is None and not _has_effect(model, prm):
            out.append(prm.column)
    return tuple(out)


#: Grade ranks (seed 004 Tables 3–4) between a part's label and what its own figures place it
#: in that make the label's fills doubtful. The tables are coarse and modern MEMS beat them (an
#: industrial ADIS1646x has a tactical ARW), so one rank apart is common and not noted.
GRADE_MISMATCH_RANKS = 2


def _nearest_rank(value: float, prm: Parameter, grades: Mapping[str, GradeSpec]) -> int:
    """Rank of the grade whose range of ``prm`` (catalog unit) ``value`` lies in, or nearest to
    on a log scale."""
    def distance(g: GradeSpec) -> float:
        lo, hi = grade_value(g, prm, "best"), grade_value(g, prm, "worst")
        return 0.0 if lo <= value <= hi else abs(math.log10(value / (lo if value < lo else hi)))
    return min(grades.values(), key=lambda g: (distance(g), g.rank)).rank


def _grade_mismatch_note(model, grades: Mapping[str, GradeSpec], grade: str, label: str) -> tuple[str, ...]:
    """A note when the part's own figures place it (median over its given figures of the grade
    each lies in or nearest to) :data:`GRADE_MISMATCH_RANKS` or more ranks from its grade
    column: the values filled from that grade then describe another class of sensor than the
    row does (a part labelled consumer with navigation-grade figures, say). A grade's bias is a
    turn-on / total figure, so an in-run bias instability is not compared with it."""
    placed = []
    for prm in PARAMETERS:
        column = prm.column
        if prm.family == "bias":
            column = _REPEATABILITY[prm.triad] if getattr(model, _REPEATABILITY[prm.triad]) is not None else \
                (prm.column if model.bias_is_constant else None)
        v = getattr(model, column, None) if column else None
        if v is None or v <= 0:
            continue
        placed.append((column, v, prm.unit, _nearest_rank(float(v), prm, grades)))
    if not placed:
        return ()
    own = grades[grade].rank
    implied = float(np.median([r for *_, r in placed]))
    if abs(implied - own) < GRADE_MISMATCH_RANKS:
        return ()
    by_rank = {g.rank: name for name, g in grades.items()}
    figures = "; ".join(f"{c} = {v:g} {u} ({by_rank[r]})" for c, v, u, r in placed)
    return (f"{label} is labelled {grade}, but its own figures are those of a "
            f"{by_rank[int(round(implied))]}-grade part ({figures}): the values filled from the "
            f"{grade} grade may not describe it (check its grade column, or give the empty figures)",)


#: How far beyond its own grade's range (seed 004 Tables 3–4) one figure may lie before it is
#: named as a possible unit slip: 10× worse than the grade's worst, 100× better than its best.
#: The shipped catalog's figures lie at most 3.4× worse and 40× better (consumer parts beat the
#: printed consumer row on scale factor and ARW), while the usual slips are larger: deg/s typed
#: as deg/h 3600×, mg as µg 1000×, % as ppm 10⁴×, µg/√Hz as m/s/√h 1700×.
FAR_WORSE, FAR_BETTER = 10.0, 100.0
#: The in-run bias instability columns, judged against the grade's (total) bias range, worse side only.
_IN_RUN = {"gyro": "gyro_bias_instability_deg_h", "accel": "accel_bias_instability_ug"}


def _far_from_grade_note(model, grades: Mapping[str, GradeSpec], grade: str, label: str) -> tuple[str, ...]:
    """A note naming each given figure that lies more than :data:`FAR_WORSE` × beyond the worst
    or :data:`FAR_BETTER` × beyond the best of its own grade's range: the signature of a figure
    typed in another unit than its column's (one slipped figure moves the median of
    :func:`_grade_mismatch_note` by nothing). An in-run bias instability (the ``adev_min``
    convention) is judged on the worse side only: a grade's bias is a turn-on / total figure, which an in-run figure never exceeds
    but may undercut by 10³ (ADIS16465-1: 3.6 µg in-run, industrial grade 3000 µg)."""
    g = grades[grade]
    far = []
    for prm in PARAMETERS:
        columns = [prm.column] if prm.family != "bias" else [_IN_RUN[prm.triad], _REPEATABILITY[prm.triad]]
        for column in dict.fromkeys(columns):
            v = getattr(model, column, None)
            if v is None or v <= 0:
                continue
            lo, hi = grade_value(g, prm, "best"), grade_value(g, prm, "worst")
            if v > FAR_WORSE * hi:
                far.append(f"{column} = {v:g} {prm.unit} is {v / hi:.3g}× the {grade} grade's worst ({hi:g})")
            elif v < lo / FAR_BETTER and (column != _IN_RUN[prm.triad] or model.bias_is_constant):
                far.append(f"{column} = {v:g} {prm.unit} is 1/{lo / v:.3g} of the {grade} grade's best ({lo:g})")
    if not far:
        return ()
    return (f"{label}: " + "; ".join(far) + " — a figure this far from its grade is often typed in "
            "another unit (deg/s for deg/h is 3600×, mg for µg 1000×, % for ppm 10⁴×, deg for mrad "
            "17.5×): check it against the datasheet's unit and the column's",)


def _zero_figures_note(model) -> tuple[str, ...]:
    """A note naming the figures given as 0 (a perfect term: what a datasheet never states; an
    unknown figure is an empty cell, filled from the grade and stated)."""
    zero = [prm.column for prm in PARAMETERS if getattr(model, prm.column, None) == 0]
    if not zero:
        return ()
    return (f"given as 0 (a perfect sensor term, checked and simulated as such): {', '.join(zero)}; leave a cell empty "
            "when the figure is unknown, so that it is filled from the grade and stated",)


def _convention_note(model) -> tuple[str, ...]:
    """A note when the row gives a bias instability figure but no ``bias_instability_convention``:
    the default ``adev_min`` then simulates the figure as flicker noise (an Allan minimum), where a
    total or turn-on 1-sigma bias (Honeywell's "bias, 1 sigma") is one constant per trial: a choice
    the verdict rests on and the row did not make."""
    if "bias_instability_convention" in model.model_fields_set:
        return ()
    given = [f"{c} = {getattr(model, c):g} {unit}" for c, unit in (("gyro_bias_instability_deg_h", "deg/h"),
                                                                   ("accel_bias_instability_ug", "µg"))
             if getattr(model, c, None) is not None]
    if not given:
        return ()
    return (f"bias_instability_convention not given: {', '.join(given)} taken as in-run Allan-deviation "
            "minima (adev_min, the default) and simulated as flicker noise; write total_1sigma or "
            "turn_on_1sigma if the datasheet's figure is a total or turn-on 1σ bias (one constant per trial)",)


def row_warnings(model, grades: Mapping[str, GradeSpec] | None = None) -> tuple[str, ...]:
    """What a reader of any verdict on ``model`` (a catalog ``PartSpec`` or ``NoiseModel``) should
    look at in its row: figures given as 0 (a perfect term), figures that as a whole place the
    part two or more grades from its grade column (:func:`_grade_mismatch_note`), and single
    figures far outside their grade's range (:func:`_far_from_grade_note`); () for an SI model
    or a row without a grade."""
    if not isinstance(model, PartSpec):
        return ()
    zero = _zero_figures_note(model)
    if model.grade is None:
        return zero
    if grades is None:
        from .io import load_grades
        grades = load_grades()
    if model.grade not in grades:
        return zero
    label = model.part_id or "the noise model"
    return (_grade_mismatch_note(model, grades, model.grade, label)
            + _far_from_grade_note(model, grades, model.grade, label) + zero)


def resolve_unspecified(model, policy: str = DEFAULT_POLICY,
                        grades: Mapping[str, GradeSpec] | None = None) -> Resolution:
    """Resolve the unspecified terms of ``model`` (a catalog ``PartSpec`` or a ``NoiseModel``).

    Returns a :class:`Resolution` whose ``model`` is the model to simulate (a validated copy
    with the filled columns, or the model itself). Models in SI (``NoiseModelSI``) are taken
    as given. ``grades`` defaults to the shipped ``catalog/grades.csv``.
    """
    if policy not in POLICIES:
        raise InputError("unknown policy for unspecified terms", field="unspecified", value=policy,
                         expected=", ".join(POLICIES))
    if not isinstance(model, PartSpec):
        return Resolution(model=model, policy=policy, grade=None,
                          notes=("an SI noise model is taken as given",))
    grade = model.grade
    missing = unspecified_quantities(model)
    not_modelled = tuple(c for c in _NO_GRADE_VALUE if getattr(model, c) is None)
    label = model.part_id or "the noise model"
    zero_note = _zero_figures_note(model) + _convention_note(model)
    if grade is not None and grades is None:
        from .io import load_grades
        grades = load_grades()
    far_note = _far_from_grade_note(model, grades, grade, label) if grade is not None and grade in grades else ()
    if not missing:
        return Resolution(model=model, policy=policy, grade=grade, not_modelled=not_modelled,
                          warnings=far_note + zero_note)
    if policy == "refuse":
        raise InputError(f"{label} leaves {', '.join(missing)} unspecified", field="unspecified",
                         value=policy, expected="the datasheet values in the catalog row, or "
                         "unspecified = 'fill_grade_typical' (grade typical values, recorded) or "
                         "'zero' (stated zero)")
    if policy == "zero" or grade is None:
        note = ("stated zero (policy 'zero')" if policy == "zero" else
                "no grade to fill from: taken as 0 (give the model a grade, or use 'refuse')")
        return Resolution(model=model, policy=policy, grade=grade, unspecified=missing,
                          zeroed=missing, not_modelled=not_modelled, notes=(note,), warnings=far_note + zero_note)
    if grade not in grades:
        raise InputError(f"grade {grade!r} is not in the grades table", field="grade", value=grade,
                         expected=", ".join(grades))
    g = grades[grade]
    update: dict[str, float] = {}
    fills, zeroed = [], []
    for prm in PARAMETERS:
        targets = [c for c in missing if c in (prm.column, _REPEATABILITY[prm.triad])] \
            if prm.family == "bias" else [c for c in missing if c == prm.column]
        for column in targets:
            if prm.family == "bias" and not model.bias_is_constant and column == prm.column:
                zeroed.append(column)  # no grade value for an in-run (flicker) figure
                continue
            value = grade_value(g, prm, "typical")
            lo, hi = sorted(float(getattr(g, c)) for c in prm.grade_columns)
            span = f"{lo:g}" if lo == hi else f"geometric mean of {lo:g}–{hi:g}"
            what = " as the turn-on bias" if column != prm.column else ""
            fills.append(Fill(prm.column, column, value, prm.unit,
                              f"{grade} grade{what}, seed 004 Tables 3–4 ({span} {prm.grade_unit})"))
            update[column] = value
    notes = (("in-run bias instability has no grade value (grade biases are turn-on / total "
              "figures): " + ", ".join(zeroed) + " not modelled"),) if zeroed else ()
    warned = ((_grade_mismatch_note(model, grades, grade, label) if fills else ())
              + far_note + zero_note)
    data = model.model_dump()
    data.update(update)
    filled_model = type(model).model_validate(data)
    return Resolution(model=filled_model, policy=policy, grade=grade, unspecified=missing,
                      filled=tuple(fills), zeroed=tuple(zeroed),
                      not_modelled=tuple(c for c in not_modelled if c not in update), notes=notes,
                      warnings=warned)
