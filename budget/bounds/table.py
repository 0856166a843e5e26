"""The bounds result: SI arrays inside, datasheet units in :meth:`BoundsTable.to_frame`."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..parameters import BOUNDS


def _from_si(factor: float):
    """SI value → datasheet unit (divide by the unit's SI factor)."""
    def conv(v):
        return v / factor
    return conv


#: Output keys (datasheet units) in the order of seed 004 Tables 1–2 → (SI attribute, SI → unit),
#: built from the one parameter table :data:`budget.parameters.PARAMETERS`.
BOUND_FIELDS: dict[str, tuple[str, callable]] = {
    p.bound_key: (p.bound, _from_si(p.bound_to_si)) for p in BOUNDS
}


@dataclass(frozen=True)
class BoundsTable:
    """Maximum allowed sensor errors, one value per Tc (arrays broadcast over Tc and δr).

    SI: scale factors as ratios, misalignment rad, accel bias m/s², gyro bias rad/s,
    VRW m/s²/√Hz, ARW rad/s/√Hz.
    """

    mode: str
    tc_s: np.ndarray
    range_resolution_m: np.ndarray
    accel_scale_factor: np.ndarray
    gyro_scale_factor: np.ndarray
    misalignment_rad: np.ndarray
    accel_bias_m_s2: np.ndarray
    gyro_bias_rad_s: np.ndarray
    accel_vrw_m_s2_rt_hz: np.ndarray
    gyro_arw_rad_s_rt_hz: np.ndarray
    notes: tuple[str, ...] = field(default=())
    #: the assumptions the bounds were derived with (``model_dump`` of ``DerivedAssumptions`` …);
    #: None for seed 004's printed equations (``paper``)
    assumptions: dict | None = None
    #: the scenario the bounds were computed for (``model_dump(mode="json")``; set by
    #: :func:`budget.compute_bounds`), None for bare arrays of Tc and δr
    scenario: dict | None = None
    #: the scenario keys these bounds rest on that the scenario did not set, with the value taken
    #: (:meth:`Scenario.defaults_taken` of :func:`budget.bounds.scenario_keys`), and the same in
    #: words (set by :func:`budget.compute_bounds`; None / '' for bare arrays or when every key was set)
    scenario_defaults: dict | None = None
    defaults_note: str = ""
    #: what the scenario holds that these bounds treat otherwise than the file might suggest (e.g. a
    #: ``platform_accel_m_s2`` that seed 004's paper bounds do not use: :func:`budget.bounds.accel_level_note`);
    #: printed by :meth:`summary`, in :meth:`to_dict`'s ``notes``
    scenario_notes: tuple[str, ...] = ()

    def datasheet(self) -> dict[str, np.ndarray]:
        """Bounds in datasheet units keyed as in the CLI JSON (``accel_bias_ug`` …)."""
        return {key: conv(np.asarray(getattr(self, si))) for key, (si, conv) in BOUND_FIELDS.items()}

    def to_frame(self) -> pd.DataFrame:
        data = {"tc_s": np.ravel(self.tc_s), "range_resolution_m": np.ravel(
            np.broadcast_to(self.range_resolution_m, np.shape(self.tc_s)))}
        data.update({k: np.ravel(v) for k, v in self.datasheet().items()})
        frame = pd.DataFrame(data)
        # what the summary's head line says: the mode, its assumptions, the scenario (if any)
        frame.attrs.update({"mode": self.mode, "assumptions": self.assumptions, "scenario": self.scenario,
                            "scenario_defaults": self.scenario_defaults})
        return frame

    def limit_notes(self) -> tuple[str, ...]:
        """Where a bound stops constraining: the misalignment bound's arcsin argument reached 1
        (seed 004 (7), and its derived and no-autofocus forms: the bound is capped at 90°, so any
        misalignment meets it) and scale-factor bounds of 100 % or more (a ratio no sensor
        approaches). Empty when every bound constrains."""
        tc = np.ravel(self.tc_s)
        out = []

        def at(mask) -> str:
            return ", ".join(f"{t:.4g}" for t in tc[np.ravel(mask)])

        capped = np.broadcast_to(np.asarray(self.misalignment_rad) >= np.pi / 2 * (1 - 1e-12), np.shape(self.tc_s))
        if np.any(capped):
            out.append(f"misalignment bound capped at 90° (Tc = {at(capped)} s): its arcsin argument "
                       "reaches 1 there, so any misalignment meets it — the bound does not constrain")
        for name in ("accel_scale_factor", "gyro_scale_factor"):
            big = np.broadcast_to(np.asarray(getattr(self, name)) >= 1.0, np.shape(self.tc_s))
            if np.any(big):
                out.append(f"{name.replace('_', ' ')} bound ≥ 100 % (Tc = {at(big)} s): it does not "
                           "constrain any real sensor")
        return tuple(out)

    def to_dict(self) -> dict:
        """JSON-ready: the ``mode``, its ``assumptions`` and ``notes`` (with :meth:`limit_notes`),
        and under ``rows`` one dict per Tc with ``tc_s`` and the datasheet-unit keys (the CLI JSON
        list); ``scenario`` (in full) when the bounds were computed for one."""
        frame = self.to_frame().drop(columns="range_resolution_m")
        out = {"mode": self.mode, "assumptions": self.assumptions,
               "notes": list(self.notes) + list(self.limit_notes()) + list(self.scenario_notes),
               "range_resolution_m": np.ravel(self.range_resolution_m).tolist(),
               "rows": frame.to_dict(orient="records")}
        if self.scenario is not None:
            out["scenario"] = self.scenario
            out["scenario_defaults"] = self.scenario_defaults
        return out

    def summary(self) -> str:
        head = f"Bounds ({self.mode} mode)"
        if self.scenario is not None:
            head += f" for {self.scenario.get('name')}"
        if self.mode == "lever_arm" and self.assumptions:
            arm = self.assumptions.get("lever_arm_m")
            if arm is not None:
                head += (", lever arm [" + ", ".join(f"{v:.3g}" for v in arm) + "] m, platform rate "
                         f"{self.assumptions.get('platform_rate_deg_s'):g} deg/s")
        text = head + "\n" + self.to_frame().to_string(index=False, na_rep="-", float_format=lambda v: f"{v:.4g}")
        unused = (["range_resolution_m '-': these bounds limit phase (λ), not range cells: δr is not used"]
                  if np.all(np.isnan(np.asarray(self.range_resolution_m, float))) else [])
        return "\n".join([text, *unused, *self.limit_notes(), *self.scenario_notes,
                          *([self.defaults_note] if self.defaults_note else [])])
