"""A :class:`~budget.report.content.Report` as one self-contained HTML file.

plotly.js is embedded once in the page (no CDN, no network: the report opens offline); each
figure is a ``<div>`` drawn by it. Tables are plain HTML with numbers to 4 significant figures
and "–" for an empty cell. Everything user-provided (scenario name, part ids) is escaped.
"""

from __future__ import annotations

import html
import json
import math

import pandas as pd

from ..check_text import rotation_line
from ..mc.notes import SIMULATION_NOTES

CSS = """
body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;margin:2em auto;max-width:1200px;color:#222}
h1{font-size:1.6em}h2{font-size:1.25em;margin-top:1.6em;border-bottom:1px solid #ddd}
table{border-collapse:collapse;margin:.6em 0;font-size:.9em}
th,td{border:1px solid #ccc;padding:3px 8px;text-align:right}th{background:#f3f3f3}
td.txt,th.txt{text-align:left}.pass{background:#c7e9c0}.fail{background:#fcbba1}
.warn{background:#fff3cd;border:1px solid #e0c46c;padding:.6em;margin:.6em 0}
.ok{background:#e7f4e4;border:1px solid #9bc995;padding:.6em;margin:.6em 0}
code,pre{background:#f6f6f6;padding:2px 4px}small{color:#666}
"""


def _cell(v) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "–"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.4g}"
    if isinstance(v, (list, tuple)):
        return ", ".join(_cell(x) for x in v)
    return html.escape(str(v))


def table_html(frame: pd.DataFrame, *, table_id: str | None = None, verdict_col: str | None = None) -> str:
    """An HTML table of ``frame`` (numbers right-aligned, text left; verdict cells coloured)."""
    head = "".join(f"<th class='txt'>{html.escape(str(c))}</th>" for c in frame.columns)
    rows = []
    for _, r in frame.iterrows():
        cells = []
        for c in frame.columns:
            v = r[c]
            cls = "txt" if not isinstance(v, (int, float)) or isinstance(v, bool) else ""
            if c == verdict_col and v in ("pass", "fail"):
                cls += f" {v}"
            cells.append(f"<td class='{cls.strip()}'>{_cell(v)}</td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    tid = f" id='{table_id}'" if table_id else ""
    return f"<table{tid}><thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>"


def _comparisons(rep) -> str:
    if not rep.comparisons:
        return "<p><small>No Monte Carlo run in this report: the check is analytic only.</small></p>"
    out = []
    for c in rep.comparisons:
        pid = html.escape(str(c["part_id"]))
        if c["agree"] is False:
            out.append(f"<div class='warn' data-agree='no'><b>{pid}: the check and the Monte Carlo "
                       f"disagree.</b> {html.escape(c['reason'])}</div>")
        elif c["agree"]:
            out.append(f"<div class='ok' data-agree='yes'>{pid}: the check ({c['check_verdict']}) and the "
                       f"Monte Carlo agree.</div>")
        else:
            out.append(f"<div class='ok' data-agree='n/a'>{pid}: {html.escape(c['reason'])}</div>")
    return "".join(out)


def _set_by(scenario, key: str) -> str:
    """'scenario' for a key the scenario wrote, 'default' for one it left or wrote as null (the
    propagation speed with the medium's value it stands for)."""
    if key in scenario.model_fields_set and getattr(scenario, key, None) is not None:
        return "scenario"
    if key == "propagation_speed_m_s":
        return f"default ({scenario.c_m_s:g} m/s, {scenario.medium})"
    return "default"


def render_html(rep) -> str:
    """The whole report as one HTML document."""
    from ..plots.export import plotly_js

    s = rep.scenario
    title = f"IMU budget report — {s.name}"
    # each key says whether the scenario set it or its default stood in
    dump = s.model_dump(mode="json")
    scen = pd.DataFrame({"key": list(dump), "value":
                         [json.dumps(v) if isinstance(v, (list, dict)) else v for v in dump.values()],
                         "set by": [_set_by(s, k) for k in dump]})
    derived = pd.DataFrame({"quantity": list(s.derived()), "value": list(s.derived().values())})
    bounds = rep.bounds.drop(columns=["key"])
    parts = [f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>{html.escape(title)}</title>",
             f"<style>{CSS}</style><script type='text/javascript'>{plotly_js()}</script></head><body>",
             f"<h1>{html.escape(title)}</h1>",
             f"<p>Tc = <b>{s.tc_s:.4g} s</b> (seed 004 (5)), λ = {s.wavelength_m:.4g} m, aperture "
             f"{s.aperture_length_m:.4g} m; check with <b>{html.escape(rep.mode)}</b> bounds.</p>",
             "<h2>Scenario</h2>", table_html(scen, table_id="scenario"), table_html(derived),
             "<h2>Bounds at this Tc (datasheet units)</h2>", table_html(bounds, table_id="bounds"),
             *(f"<p class='judged' data-key='bounds_refused'><small>{html.escape(m)} bounds not computed: "
               f"{html.escape(why)}</small></p>" for m, why in rep.bounds.attrs.get("refused", {}).items()),
             f"<p><small>derived and no-autofocus bounds at the acceleration level the scale factor and "
             f"misalignment see: the scenario's platform_accel_m_s2 = {s.platform_accel_m_s2:g} m/s² "
             "unless the assumptions give another</small></p>",
             "<h2>Analytic check (margin = bound / datasheet value, ≥ 1 passes)</h2>",
             table_html(rep.check_frame(), table_id="check", verdict_col="verdict")]
    if rep.check.rotation:
        parts.append(f"<p class='judged' data-key='rotation'><small>{html.escape(rotation_line(rep.check.rotation[0]))}"
                     "</small></p>")
    if rep.mc:
        parts += ["<h2>Monte Carlo verdict (P(pass) with 95 % Wilson intervals)</h2>",
                  table_html(rep.mc_frame(), table_id="mc")]
        # what every trial was judged on, which the user could not know otherwise
        judged = next(iter(rep.mc.values())).judged_on or {}
        parts += [f"<p class='judged' data-key='{k}'><small>{html.escape(str(judged[k]))}</small></p>"
                  for k in ("navigation", "aiding_defaults", "platform_motion", "lever_arm", "window_resolution",
                            "acceptance", *SIMULATION_NOTES) if judged.get(k)]
        # per part: the values the Monte Carlo filled or took as 0 for empty datasheet cells, and
        # the rate the IMU was simulated at — inputs the user did not give
        for pid, r in rep.mc.items():
            for key, text in (("unspecified", r.unspecified_summary()),
                              ("imu_rate", (r.judged_on or {}).get("imu_rate"))):
                if text:
                    parts.append(f"<p class='judged' data-key='{key}'><small><b>{html.escape(str(pid))}"
                                 f"</b>: {html.escape(str(text))}</small></p>")
    parts += ["<h2>Check vs. Monte Carlo</h2>", _comparisons(rep), "<h2>Figures</h2>"]
    for name, fig in rep.figures.items():
        parts += [f"<h3>{html.escape(name)}</h3>", fig.to_html(include_plotlyjs=False, full_html=False)]
    prov = pd.DataFrame({"item": list(rep.provenance), "value": [
        json.dumps(v) if isinstance(v, (dict, list)) else v for v in rep.provenance.values()]})
    parts += ["<h2>Provenance</h2>", table_html(prov, table_id="provenance"),
              "<p><small>Same version, seed, trials and options → the same numbers.</small></p>",
              "</body></html>"]
    return "\n".join(parts)
