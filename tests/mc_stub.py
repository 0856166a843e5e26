"""A stand-in for a Monte Carlo result with only what the check-vs-Monte-Carlo comparison reads
(P(pass after PGA), its interval, the failure reasons and the filled datasheet terms)."""

from __future__ import annotations

from types import SimpleNamespace


def stub_mc(p: float, lo: float, hi: float, reasons: dict, filled=(), trials: int = 64):
    """``filled``: (column, value, unit) of each datasheet term the run filled from the grade."""
    agg = SimpleNamespace(failure_reasons=lambda: dict(reasons))
    return SimpleNamespace(p_pass_after=p, ci_after=(lo, hi), agg=agg, trials=trials,
                           extra={"unspecified_terms": {"filled": [
                               {"column": c, "value": v, "unit": u} for c, v, u in filled]}})
