"""What every page runs inside: the shared sidebar (where the page uses it), then the page body,
errors as messages.

A page module ends with ``run_page(render)``. The sidebar is drawn by each page (not by
``main.py``) so that a page is complete on its own — in the browser and under ``AppTest``, which
re-runs only the page script. Pages that do not use the scenario (noise lab, model gap) pass
``sidebar=False``: the scenario fields are then not shown where they would change nothing, and
their values are kept for the pages that use them (:func:`components.keep`).
"""

from __future__ import annotations

from collections.abc import Callable

import components
import sidebar as scenario_sidebar


def run_page(render: Callable[[], None], *, sidebar: bool = True) -> None:
    """Draw the sidebar (unless ``sidebar=False``), then ``render`` the page; errors become
    messages, never tracebacks."""
    if sidebar:
        components.guarded(lambda: (scenario_sidebar.render(), render()))
    else:
        components.guarded(render)
