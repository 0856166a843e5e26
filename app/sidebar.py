"""The sidebar every page shares: scenario (preset + editable fields), bounds mode, assumptions.

Every page draws it first (through :func:`page_frame.run_page`); :func:`components.keep` carries
its values across runs and pages. The result is a :class:`Context` in ``st.session_state["ctx"]``
that pages read with :func:`context`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import streamlit as st

from budget.bounds import DerivedAssumptions, NoAutofocusAssumptions, scenario_assumptions
from budget.errors import InputError
from budget.structured import parse_structured
from budget.presets import PRESETS, get_preset
from budget.scenario import Scenario

from components import STORE_KEY, field_label, keep, keep_model_state, model_from_state, model_inputs
from uploads import error_text

DEFAULT_PRESET = "airborne_xband"
MAX_SCENARIO_BYTES = 1_000_000
SCENARIO_PREFIX = "scn_"
DERIVED_PREFIX = "da_"
NOAF_PREFIX = "na_"
MODES = ("paper", "derived", "no-autofocus")
MODE_HELP = {
    "paper": "seed 004 (6)–(11) as printed",
    "derived": "same bounds from physics; assumptions editable below",
    "no-autofocus": "without PGA the phase error itself must stay small",
}
#: Assumption fields the scenario sets (assumption field → scenario field): the acceleration level
#: the scale factor and misalignment see is the scenario's ``platform_accel_m_s2``, as
#: ``sar-budget bounds``/``check`` take it (:func:`budget.bounds.scenario_assumptions`) — one
#: input for one quantity, so the assumptions' expanders do not offer it.
FROM_SCENARIO = {"accel_level_m_s2": "platform_accel_m_s2"}
#: Scenario fields shown at the top of the sidebar; the rest go in an expander.
MAIN_FIELDS = ("medium", "carrier_frequency_hz", "slant_range_m", "platform_speed_m_s",
               "azimuth_resolution_m", "range_resolution_m", "squint_deg", "window_broadening")
MORE_FIELDS = tuple(f for f in Scenario.model_fields if f not in MAIN_FIELDS)


@dataclass(frozen=True)
class Context:
    """What the pages work from: the current scenario, bounds mode and the user's edits of the
    derived and no-autofocus assumptions (only the fields changed from their defaults; None when
    none is: the library then takes every assumption from the scenario, as the CLI does)."""

    scenario: Scenario | None
    mode: str
    derived_edits: dict | None
    no_autofocus_edits: dict | None
    errors: tuple[str, ...] = field(default=())
    #: The scenario's warnings (e.g. an echo delay longer than Tc: stop-and-go does not hold),
    #: shown beside every result drawn from it.
    notes: tuple[str, ...] = field(default=())

    def edits(self, mode: str | None = None) -> dict | None:
        """The sidebar's edits of ``mode``'s assumptions (default: the selected mode), to be passed
        to the library as a partial dict — it completes them from the scenario
        (:func:`budget.bounds.scenario_assumptions`); None where there are none (and for the modes
        without sidebar assumptions: paper, lever-arm)."""
        mode = mode or self.mode
        return {"derived": self.derived_edits, "no-autofocus": self.no_autofocus_edits}.get(mode)

    def assumptions(self, mode: str | None = None, scenario: Scenario | None = None):
        """The assumptions the library computes ``mode`` with for this scenario and these edits
        (:func:`budget.bounds.scenario_assumptions`: the scenario's ``platform_accel_m_s2`` for
        derived and no-autofocus, its lever arm and turn rate for lever-arm); None for paper.
        ``scenario``: another than the sidebar's (default: the sidebar's). Raises the library's
        :class:`InputError` where it refuses (``platform_accel_m_s2`` = 0 for the derived and
        no-autofocus bounds, as ``sar-budget bounds --mode derived`` does)."""
        mode = mode or self.mode
        if mode == "paper":
            return None
        return scenario_assumptions(mode, scenario or self.scenario, self.edits(mode))

    def assumptions_words(self, mode: str | None = None, scenario: Scenario | None = None) -> str:
        """One line for the page: which values ``mode`` was computed with — the scenario's
        acceleration level (or lever arm and turn rate) and the sidebar's edits. ``scenario``:
        another than the sidebar's (e.g. the one a kept Monte Carlo run used). Raises as
        :meth:`assumptions` does."""
        mode = mode or self.mode
        a = self.assumptions(mode, scenario)
        if a is None:
            return f"{mode}: seed 004 (6)–(11) as printed (no assumption to set)"
        if mode == "lever-arm":
            share = ("rms over apertures" if a.fast_residual_share is None
                     else f"on {a.fast_residual_share:g} of apertures")
            arm = ", ".join(f"{v:g}" for v in a.lever_arm_m)
            return (f"lever-arm: lever arm [{arm}] m and platform rate {a.platform_rate_deg_s:g} deg/s from the "
                    f"scenario, {a.aperture_window} window (the Monte Carlo's), what PGA cannot remove ≤ "
                    f"{a.fast_residual_limit_deg:g}° {share}")
        edits = self.edits(mode)
        edited = (", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}" for k, v in edits.items())
                  if edits else "none (defaults)")
        return (f"{mode}: acceleration level {a.accel_level_m_s2:g} m/s² — the scenario's platform_accel_m_s2, "
                f"as `sar-budget bounds`/`check` take it; assumptions edited in the sidebar: {edited}")

    @property
    def ok(self) -> bool:
        return self.scenario is not None and not self.errors


#: Session-state keys: the scenario the fields started from (a preset or an uploaded file), as
#: JSON, and where it came from; an edit of any field renames the scenario (see :func:`_named`).
BASE_KEY, BASE_ORIGIN_KEY, UPLOAD_ERROR_KEY = "scn_base_json", "scn_base_origin", "scn_upload_error"
#: Session-state key: the keys the scenario the fields started from left out (taken at their
#: defaults, :meth:`budget.scenario.Scenario.defaults_taken`) — stated beside the results that
#: use them, as the CLI states them, while their fields still hold those defaults.
BASE_DEFAULTS_KEY = "scn_base_defaults"


def _keep_base(s: Scenario, origin: str) -> None:
    keep(BASE_KEY, s.model_dump_json(), force=True)
    keep(BASE_ORIGIN_KEY, origin, force=True)
    keep(BASE_DEFAULTS_KEY, list(s.defaults_taken()), force=True)


def _keep_scenario(preset: str, force: bool) -> None:
    s = get_preset(preset)
    keep_model_state(SCENARIO_PREFIX, s, force=force, fallbacks={"propagation_speed_m_s": s.c_m_s})
    if force or BASE_KEY not in st.session_state.get(STORE_KEY, {}):
        _keep_base(s, f"preset {preset}")


def _apply_preset() -> None:
    keep("scn_preset", st.session_state["scn_preset"], force=True)
    _keep_scenario(st.session_state["scn_preset"], force=True)


def _apply_upload() -> None:
    """A scenario file was uploaded: validate it (every error listed) and load its fields."""
    up = st.session_state.get("scn_upload")
    keep(UPLOAD_ERROR_KEY, "", force=True)
    if up is None:
        return
    try:
        s = scenario_from_upload(up.getvalue(), up.name)
    except InputError as err:
        keep(UPLOAD_ERROR_KEY, error_text(err), force=True)
        return
    keep_model_state(SCENARIO_PREFIX, s, force=True, fallbacks={"propagation_speed_m_s": s.c_m_s})
    _keep_base(s, f"file {up.name}")


def scenario_from_upload(data: bytes, name: str) -> Scenario:
    """A scenario from uploaded JSON/YAML bytes (parsed as data, never executed), read with the
    limits and rules of the CLI's reader (:func:`budget.structured.parse_structured`)."""
    if len(data) > MAX_SCENARIO_BYTES:
        raise InputError(f"file is {len(data)} bytes", file=name, expected=f"at most {MAX_SCENARIO_BYTES} bytes")
    hint = "a scenario file as written by `sar-budget scenario write`"
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError("not valid JSON/YAML (not UTF-8 text)", file=name, expected=hint) from None
    try:
        data_ = parse_structured(text, yaml_syntax=True, path=name)  # JSON is YAML too
    except InputError as err:
        if err.reason.startswith("not valid YAML"):  # the upload may be either
            raise InputError(f"not valid JSON/YAML{err.reason[len('not valid YAML'):]}", file=name,
                             expected=hint) from None
        raise
    return Scenario.from_dict(data_, source=name)


def _named(s: Scenario) -> Scenario:
    """An edited scenario does not keep its preset's (or file's) name: ``<name>_edited``."""
    base_json = st.session_state.get(BASE_KEY)
    if not base_json:
        return s
    base = Scenario.model_validate_json(base_json)
    if s.name != base.name or s.model_dump(exclude={"name"}) == base.model_dump(exclude={"name"}):
        return s  # the user named it, or nothing changed
    return s.model_copy(update={"name": f"{base.name}_edited"})


def _defaults_kept(s: Scenario) -> Scenario:
    """``s`` with the keys its starting scenario left out (:data:`BASE_DEFAULTS_KEY`) unset again
    while their fields still hold the defaults, so that ``s.defaults_note(keys)`` states them as
    the CLI does for the same file; a field the user set (to another value) is the user's."""
    left_out = st.session_state.get(BASE_DEFAULTS_KEY) or []
    default = Scenario.model_fields
    untouched = {k for k in left_out if k in default and getattr(s, k) == default[k].get_default(
        call_default_factory=True)}
    if not untouched:
        return s
    return Scenario.model_validate(s.model_dump(exclude=untouched))


def _reset_assumptions(prefix: str, model) -> None:
    keep_model_state(prefix, model, force=True)


def _build(model_cls, prefix: str, what: str, errors: list[str]):
    try:
        return model_from_state(model_cls, prefix)
    except InputError as err:
        errors.append(f"{what}: {error_text(err)}")
        return None


def _edits(model) -> dict | None:
    """The fields of an assumptions model the user changed from their defaults (without those the
    scenario sets, :data:`FROM_SCENARIO`); None when none is."""
    if model is None:
        return None
    defaults = type(model)().model_dump(mode="json")
    edits = {k: v for k, v in model.model_dump(mode="json").items()
             if k not in FROM_SCENARIO and v != defaults[k]}
    return edits or None


def _assumption_inputs(model_cls, prefix: str) -> None:
    """The assumptions' widgets, without the fields the scenario sets (stated instead)."""
    model_inputs(model_cls, prefix, [f for f in model_cls.model_fields if f not in FROM_SCENARIO], st)
    for name, scenario_field in FROM_SCENARIO.items():
        if name in model_cls.model_fields:
            value = st.session_state.get(SCENARIO_PREFIX + scenario_field)
            shown = f"{value:g}" if isinstance(value, (int, float)) else "its value"
            st.caption(f"{field_label(name)}: the scenario's {scenario_field} = {shown} m/s² (under "
                       "*More scenario fields*), as `sar-budget bounds`/`check` take it")


def render() -> Context:
    """Draw the sidebar and store the resulting :class:`Context` in session state."""
    keep("scn_preset", DEFAULT_PRESET)
    keep("bounds_mode", MODES[0])
    _keep_scenario(st.session_state["scn_preset"], force=False)
    keep_model_state(DERIVED_PREFIX, DerivedAssumptions())
    keep_model_state(NOAF_PREFIX, NoAutofocusAssumptions())

    sb = st.sidebar
    sb.header("Scenario")
    sb.selectbox("preset", options=sorted(PRESETS), key="scn_preset", on_change=_apply_preset,
                 help="picking a preset overwrites the fields below")
    sb.file_uploader("or load a scenario file (JSON/YAML)", type=["json", "yaml", "yml"], key="scn_upload",
                     on_change=_apply_upload, max_upload_size=1,
                     help="e.g. from examples/scenarios or `sar-budget scenario write`; loading it "
                          "overwrites the fields below")
    if st.session_state.get(UPLOAD_ERROR_KEY) and st.session_state.get("scn_upload") is None:
        keep(UPLOAD_ERROR_KEY, "", force=True)  # the refused file is gone (removed, or another page)
    if st.session_state.get(UPLOAD_ERROR_KEY):
        sb.error(st.session_state[UPLOAD_ERROR_KEY], icon=":material/error:")
    sb.caption(f"fields from {st.session_state.get(BASE_ORIGIN_KEY, 'preset ' + DEFAULT_PRESET)}")
    model_inputs(Scenario, SCENARIO_PREFIX, MAIN_FIELDS, sb)
    with sb.expander("More scenario fields"):
        model_inputs(Scenario, SCENARIO_PREFIX, MORE_FIELDS, st)

    sb.header("Bounds")
    sb.radio("bounds mode", MODES, key="bounds_mode", format_func=lambda m: f"{m} — {MODE_HELP[m]}",
             help="used by the check matrix and highlighted in the plots")
    with sb.expander("Derived-mode assumptions"):
        _assumption_inputs(DerivedAssumptions, DERIVED_PREFIX)
        st.button("reset to defaults", key="da_reset", on_click=_reset_assumptions,
                  args=(DERIVED_PREFIX, DerivedAssumptions()))
    with sb.expander("No-autofocus assumptions"):
        _assumption_inputs(NoAutofocusAssumptions, NOAF_PREFIX)
        st.button("reset to defaults", key="na_reset", on_click=_reset_assumptions,
                  args=(NOAF_PREFIX, NoAutofocusAssumptions()))

    errors: list[str] = []
    scenario = _build(Scenario, SCENARIO_PREFIX, "scenario", errors)
    scenario = _defaults_kept(_named(scenario)) if scenario is not None else None
    # the scenario's notes from the scenario itself (with its edited name), not from the
    # process-wide warnings filter (another user's session may be building a scenario at the same
    # time); shown once, beside the results drawn from it (:func:`require_context`)
    notes = tuple(scenario.notes()) if scenario is not None else ()
    derived = _build(DerivedAssumptions, DERIVED_PREFIX, "derived assumptions", errors)
    noaf = _build(NoAutofocusAssumptions, NOAF_PREFIX, "no-autofocus assumptions", errors)
    for e in errors:
        sb.error(e, icon=":material/error:")
    ctx = Context(scenario, st.session_state["bounds_mode"], _edits(derived), _edits(noaf), tuple(errors), notes)
    st.session_state["ctx"] = ctx
    return ctx


def context() -> Context:
    """The context drawn by :func:`render` in this run."""
    return st.session_state["ctx"]


def require_context() -> Context | None:
    """The context, or None after telling the user to fix the sidebar first."""
    ctx = context()
    if not ctx.ok:
        st.warning("Fix the inputs in the sidebar first: " + "; ".join(ctx.errors), icon=":material/warning:")
        return None
    for note in ctx.notes:
        st.warning(note, icon=":material/warning:")
    return ctx
