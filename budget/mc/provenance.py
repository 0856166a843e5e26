"""Which catalog and which part figures a result was computed from.

A user catalog row may carry a shipped ``part_id`` with other numbers (it replaces the shipped row,
README "Python API"), so a part id alone does not say what was judged. Results state:

* ``catalog``: where part ids were looked up (:func:`catalog_source`): the shipped ``parts.csv``,
  the user CSV merged over it (a path, or ``$SAR_BUDGET_CATALOG``), or a caller's mapping;
* per part, its datasheet figures as given (:func:`budget.check.part_figures`: the numeric catalog columns,
  in their datasheet units, and the bias convention; a noise model's own dump), a short digest of
  them (:func:`budget.check.figures_digest`: equal figures, equal digest) and whether the row is the shipped
  one (:func:`budget.check.part_origins`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping

from ..check import figures_digest, part_figures, part_origins

__all__ = ["catalog_source", "figures_digest", "part_figures", "part_origins"]


def catalog_source(catalog=None, *, ids_given: bool = True) -> str:
    """Where part ids were looked up, in words: the ``catalog`` argument of the API (None: the
    shipped ``parts.csv``, with ``$SAR_BUDGET_CATALOG`` merged over it when set; a path: that user
    CSV merged over the shipped parts; a :func:`budget.load_catalog` mapping: its files; another
    mapping: the caller's). ``ids_given`` False: every part was given as an object."""
    from ..catalog.io import ENV_VAR, Catalog, shipped_catalog_dir, user_catalog_path

    if not ids_given and catalog is None:
        return "parts given as objects (no catalog look-up)"
    shipped = str(shipped_catalog_dir() / "parts.csv")
    if isinstance(catalog, Catalog):
        user = catalog.user_file
        return f"shipped {shipped}" + (f" with user catalog {user} merged over it" if user else "")
    if isinstance(catalog, Mapping):
        return f"a mapping of {len(catalog)} parts given by the caller"
    if catalog is not None:
        return f"shipped {shipped} with user catalog {os.fspath(catalog)} merged over it"
    user = user_catalog_path(None)
    return f"shipped {shipped}" + (f" with user catalog {user} (${ENV_VAR}) merged over it" if user else "")
