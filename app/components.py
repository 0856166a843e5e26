"""Shared widgets and helpers of the dashboard (no science here: every number comes from ``budget``).

* :func:`guarded` — runs a page body and turns errors into messages (never a traceback).
* :func:`model_inputs` — one keyed widget per field of a pydantic model, labelled with its unit;
  :func:`keep` / :func:`keep_model_state` keep their values across runs and pages.
* :func:`shipped_catalog`, :func:`grades`, :func:`session_catalog` — cached catalog access.
* :func:`run_on_demand` — a slow library call run only when its button is pressed, its result
  kept in the session and shown until the next run (with a note once the inputs changed).
"""

from __future__ import annotations

import logging
import os
import types
import typing
from collections.abc import Callable, Hashable, Iterable
from typing import Any, NamedTuple

import streamlit as st
from pydantic import BaseModel, ValidationError

from budget.catalog.io import load_catalog, load_grades, shipped_catalog_dir, user_catalog_path
from budget.catalog.schema import GradeSpec, PartSpec
from budget.errors import InputError, OutputError, from_validation_error

log = logging.getLogger("sar_budget.dashboard")

#: Field-name suffix → unit shown in the label (longest suffix first).
UNIT_SUFFIXES: tuple[tuple[str, str], ...] = (
    ("_m_s2", "m/s²"), ("_m_s", "m/s"), ("_deg_s", "deg/s"), ("_hz", "Hz"), ("_rad", "rad"),
    ("_deg", "deg"), ("_m", "m"), ("_s", "s"),
)
#: Session-state key of the user's validated, merged parts (part_id → PartSpec).
USER_PARTS_KEY = "user_parts"
#: Session-state key of the plain store that keeps widget values across pages (see :func:`keep`).
STORE_KEY = "_kept_widget_values"


def field_label(name: str) -> str:
    """``slant_range_m`` → ``slant range (m)``; names without a unit suffix get no unit."""
    for suffix, unit in UNIT_SUFFIXES:
        if name.endswith(suffix):
            return f"{name[: -len(suffix)].replace('_', ' ')} ({unit})"
    return name.replace("_", " ")


def guarded(render: Callable[[], None]) -> None:
    """Run ``render``; bad input is shown as its one-line message, anything else as a short note."""
    try:
        render()
    except Exception as err:  # noqa: BLE001 — the browser never gets a traceback
        from uploads import show_error  # the CLI's one-line messages (budget.errors.describe_error)
        show_error(err)


def scenario_named(name: str, origin: str | None = None) -> str:
    """A scenario as a refusal names it: its name, and where the sidebar's fields came from."""
    return f"{name} (fields from {origin})" if origin else name


def refused_run(run: str, scenarios: list[str], parts: list[str], text: str) -> str:
    """One line for a run the library refused (Monte Carlo, a sweep): what was run, on which
    scenario(s) (:func:`scenario_named`), for which parts, and the library's message."""
    which = f"scenario{'s' if len(scenarios) > 1 else ''} {', '.join(scenarios)}"
    return f"{run} of {which} for {', '.join(parts)} not run: {text}"


# --- run on demand, keep the last result ------------------------------------------------------

#: What :func:`run_on_demand` shows as a message (the library's refusals: bad input, an output it
#: cannot write); anything else goes on to the page's boundary (:func:`guarded`).
REFUSALS: tuple[type[BaseException], ...] = (InputError, OutputError)


class LastRun(NamedTuple):
    """The result shown by :func:`run_on_demand` and the inputs it was computed from."""

    inputs: Hashable
    result: Any


def stale_note(label: str) -> str:
    """The note above a result computed from other inputs than those on the page now."""
    return f"The inputs changed since the last run; press **{label}** to update. Showing the last run."


def run_on_demand(key: str, inputs: Hashable, label: str, run: Callable[[], Any], *, button_key: str,
                  prompt: str | None = None, refused: Callable[[str], str] | None = None, container=st,
                  **button) -> LastRun | None:
    """Draw the button ``label`` (in ``container``); when it is pressed, call ``run()`` and keep
    ``(inputs, result)`` in ``st.session_state[key]``. → the last run kept (None before the first).

    ``run`` is called only on the button, never on a rerun; a later change of ``inputs`` (any
    comparable value that identifies what ``run`` computes) shows :func:`stale_note` instead of
    re-running. A refusal (:data:`REFUSALS`) is one ``st.error`` line — the library's message, passed
    through ``refused`` if given (e.g. to name the scenario and parts) — and the last run stays.
    Before any run ``prompt`` is shown (``st.info``) if given. ``button`` goes to ``st.button``
    (``type`` defaults to primary; ``help``, ``disabled`` …)."""
    from uploads import error_text  # the CLI's one-line messages (budget.errors.describe_error)

    button.setdefault("type", "primary")
    failed = False
    if container.button(label, key=button_key, **button):
        try:
            st.session_state[key] = (inputs, run())
        except REFUSALS as err:
            text = error_text(err)
            st.error(refused(text) if refused else text, icon=":material/error:")
            failed = True
    last = st.session_state.get(key)
    if last is None:
        if prompt and not failed:
            st.info(prompt)
        return None
    if last[0] != inputs:
        st.info(stale_note(label))
    return LastRun(*last)


# --- pydantic model ↔ widgets ------------------------------------------------------------------

def _kind(annotation) -> tuple[str, tuple]:
    """Widget kind for a field annotation: literal, float, int, str, optional_float, tuple (fixed
    numbers) or other (kept in session state as it is, no widget)."""
    origin = typing.get_origin(annotation)
    args = typing.get_args(annotation)
    if origin is typing.Literal:
        return "literal", args
    if origin in (typing.Union, types.UnionType) and set(args) == {float, type(None)}:
        return "optional_float", ()
    if origin is tuple and Ellipsis not in args and all(a in (float, int) for a in args):
        return "tuple", args
    if origin is tuple:  # e.g. the scenario's aiding list: kept as it is, no sidebar widget
        return "other", args
    if annotation in (float, int, str):
        return annotation.__name__, ()
    raise TypeError(f"no dashboard widget for field type {annotation!r}")


def keep(key: str, default, *, force: bool = False) -> None:
    """Carry a widget's value over every run and page switch (call before drawing the widget).

    Widget state is per page in Streamlit and is dropped when a page does not draw the widget;
    re-writing the value through the Session State API each run keeps it, and a plain store
    (never cleaned) brings it back if Streamlit dropped it. ``force`` writes ``default``.
    """
    store = st.session_state.setdefault(STORE_KEY, {})
    if force:
        value = default
    elif key in st.session_state:
        value = st.session_state[key]
    else:
        value = store.get(key, default)
    st.session_state[key] = value
    store[key] = value


def keep_model_state(prefix: str, model: BaseModel, *, force: bool = False,
                     fallbacks: dict[str, float] | None = None) -> None:
    """:func:`keep` for the widgets of every field of ``model`` (keys ``prefix + field``).

    ``model`` gives the defaults (all of them when ``force``, e.g. a preset was picked). An
    optional field that is ``None`` shows ``fallbacks[name]`` greyed out.
    """
    fallbacks = fallbacks or {}
    for name, info in type(model).model_fields.items():
        key, value = prefix + name, getattr(model, name)
        kind, _ = _kind(info.annotation)
        items: dict[str, object]
        if kind == "optional_float":
            items = {key + "__on": value is not None,
                     key: float(value if value is not None else fallbacks.get(name, 0.0))}
        elif kind == "tuple":
            items = {f"{key}__{i}": float(v) for i, v in enumerate(value)}
        elif kind == "float":
            items = {key: float(value)}
        else:
            items = {key: value}
        for k, v in items.items():
            keep(k, v, force=force)


def model_inputs(model_cls: type[BaseModel], prefix: str, names: Iterable[str], container=st) -> None:
    """Render one keyed widget per field in ``names`` (values live in session state)."""
    fields = model_cls.model_fields
    for name in names:
        info, key = fields[name], prefix + name
        kind, args = _kind(info.annotation)
        label, help_ = field_label(name), info.description
        if kind == "literal":
            container.selectbox(label, options=list(args), key=key, help=help_)
        elif kind == "float":
            container.number_input(label, key=key, format="%g", step=None, help=help_)
        elif kind == "int":
            container.number_input(label, key=key, step=1, help=help_)
        elif kind == "str":
            container.text_input(label, key=key, help=help_)
        elif kind == "optional_float":
            on = container.checkbox(f"set {label}", key=key + "__on", help=help_ or "unset = default")
            container.number_input(label, key=key, format="%g", disabled=not on)
        elif kind == "tuple":
            container.markdown(f"<small>{label}</small>", unsafe_allow_html=True, help=help_)
            cols = container.columns(len(args))
            for i, col in enumerate(cols):
                col.number_input("xyz"[i] if len(args) == 3 else str(i), key=f"{key}__{i}", format="%g")


def model_from_state(model_cls: type[BaseModel], prefix: str):
    """Build ``model_cls`` from its widgets' session state; invalid values raise :class:`InputError`."""
    values: dict[str, object] = {}
    for name, info in model_cls.model_fields.items():
        key = prefix + name
        kind, args = _kind(info.annotation)
        if kind == "optional_float":
            values[name] = st.session_state.get(key) if st.session_state.get(key + "__on") else None
        elif kind == "tuple":
            values[name] = tuple(st.session_state.get(f"{key}__{i}") for i in range(len(args)))
        elif key in st.session_state:
            values[name] = st.session_state[key]
    try:
        return model_cls.model_validate(values)
    except ValidationError as err:
        raise from_validation_error(err) from None


# --- catalog access ----------------------------------------------------------------------------

def catalog_files_key() -> tuple:
    """What the catalog read now depends on: the shipped ``parts.csv`` and the user catalog of
    ``$SAR_BUDGET_CATALOG`` (if set), each as (path, mtime_ns, size) — (path, None, None) for a
    file that cannot be read. A file edited, replaced or appended to gives another key."""
    files = [shipped_catalog_dir() / "parts.csv"]
    user = user_catalog_path(None)
    if user is not None:
        files.append(user)
    key = []
    for f in files:
        try:
            info = os.stat(f)
            key.append((str(f), info.st_mtime_ns, info.st_size))
        except OSError:
            key.append((str(f), None, None))
    return tuple(key)


@st.cache_data(show_spinner=False, max_entries=8)
def _catalog_of(files_key: tuple) -> dict[str, PartSpec]:
    return load_catalog()


def shipped_catalog() -> dict[str, PartSpec]:
    """Shipped parts (merged with ``$SAR_BUDGET_CATALOG`` if set), cached on the files' (path,
    mtime_ns, size) (:func:`catalog_files_key`): an edit of the user catalog while the server runs
    is read on the next run, as :func:`budget.catalog.io.catalog_note` and ``part_origins`` (read
    fresh) see it, so a page never mixes the old parts with the new file's notes."""
    return _catalog_of(catalog_files_key())


@st.cache_data(show_spinner=False)
def grades() -> dict[str, GradeSpec]:
    """Grade table of seed 004 Tables 3–4, cached per server."""
    return load_grades()


def user_parts() -> dict[str, PartSpec]:
    """Parts the user uploaded and merged in this session (validated)."""
    return dict(st.session_state.get(USER_PARTS_KEY, {}))


def session_catalog() -> dict[str, PartSpec]:
    """Shipped catalog with this session's user parts merged over it (same id replaces, as
    :func:`budget.catalog.io.load_catalog` does)."""
    merged = dict(shipped_catalog())
    merged.update(user_parts())
    return merged
