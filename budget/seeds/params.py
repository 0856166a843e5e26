"""JSON-ready form of a seed application's parameters (the ``params`` of every seed result)."""

from __future__ import annotations

import dataclasses

from ..fileio import json_safe


def params_dict(params) -> dict:
    """Fields of a parameters dataclass as JSON-ready values: nested pydantic models through
    ``model_dump(mode="json")``, nested dataclasses recursively, numpy values as Python values,
    non-finite floats as ``None`` (:func:`budget.fileio.json_safe`)."""
    return {f.name: _plain(getattr(params, f.name)) for f in dataclasses.fields(params)}


def _plain(value):
    if hasattr(value, "model_dump"):
        return value.model_dump(mode="json")
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return params_dict(value)
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    return json_safe(value)
