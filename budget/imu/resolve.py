"""The IMU a user names: a catalog part id, a noise-model file, or an object — resolved in one place
for the API, the CLI, the dashboard and the model-gap workflow."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from ..catalog.io import as_catalog, get_part
from ..catalog.schema import PartSpec
from ..errors import InputError
from .noise_model import NoiseModel

#: Suffixes that make a string a noise-model file rather than a catalog ``part_id``.
MODEL_FILE_SUFFIXES = (".json", ".yaml", ".yml")


def resolve_part(part, catalog: Mapping | str | Path | None = None):
    """A :class:`PartSpec` or :class:`NoiseModel` (returned as is), a catalog ``part_id``
    (→ :class:`PartSpec`) or a noise-model file (→ :class:`NoiseModel`: a :class:`~pathlib.Path`,
    or a string that is not a part id of the catalog and ends in .json/.yaml/.yml or names a file).

    ``catalog``: the catalog mapping, or a user CSV merged over the shipped one, or ``None``
    (shipped catalog, ``$SAR_BUDGET_CATALOG``) — :func:`budget.catalog.io.as_catalog`; read only
    for a ``part_id``. An unknown part id is an :class:`InputError` naming the catalog file(s)
    searched and listing the closest ids; a model file that is missing, not valid
    JSON/YAML or has a bad field is an :class:`InputError` naming the file and the field.
    """
    if isinstance(part, Path):
        return NoiseModel.load(part)
    if isinstance(part, str):
        cat = as_catalog(catalog)
        if part not in cat and (Path(part).suffix.lower() in MODEL_FILE_SUFFIXES or Path(part).is_file()):
            return NoiseModel.load(Path(part))
        return get_part(part, cat)
    if isinstance(part, (PartSpec, NoiseModel)) or hasattr(part, "part_id") or hasattr(part, "gyro_arw_deg_rt_h"):
        return part
    raise InputError(f"cannot use a {type(part).__name__} as a part", field="part",
                     expected="a PartSpec, a NoiseModel, a catalog part_id or a noise-model .json/.yaml path")


def resolve_noise_model(model, catalog: Mapping | str | Path | None = None) -> tuple[NoiseModel, bool, str]:
    """:func:`resolve_part` as a noise model: → (model, came from the catalog?, label)."""
    got = resolve_part(model, catalog)
    if isinstance(got, NoiseModel):
        label = Path(model).name if isinstance(model, (str, Path)) else (got.part_id or "model")
        return got, False, label
    if isinstance(got, PartSpec):
        return NoiseModel.from_part(got), True, got.part_id
    raise InputError(f"not a noise model: {type(model).__name__}", field="model",
                     expected="a NoiseModel, a PartSpec, a part_id or a MODEL.json path")
