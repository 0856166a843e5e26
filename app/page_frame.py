"""What every page runs inside: the shared sidebar, then the page body, errors as messages.

A page module ends with ``run_page(render)``. The sidebar is drawn by each page (not by
``main.py``) so that a page is complete on its own — in the browser and under ``AppTest``, which
re-runs only the page script.
"""

from __future__ import annotations

from collections.abc import Callable

import components
import sidebar


def run_page(render: Callable[[], None]) -> None:
    """Draw the sidebar, then ``render`` the page; errors become messages, never tracebacks."""
    components.guarded(lambda: (sidebar.render(), render()))
