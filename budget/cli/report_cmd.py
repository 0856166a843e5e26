"""``sar-budget report``: one self-contained HTML report (opens offline) for a scenario.

    sar-budget report (--preset NAME | --scenario S.json) [--part ID ...] [--mc-part ID ...]
                      [--trials N] [--seed K] [--mode paper|derived|no-autofocus] --out REPORT.html
                      [--json REPORT.json]

The analytic check covers ``--part`` (default: the whole catalog); the Monte Carlo runs for
``--mc-part`` (default: none). The report holds the scenario, bounds in every mode, the check,
P(pass) with 95 % intervals, whether the check and the Monte Carlo agree, figures and the
provenance (version, seed, trials, options).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

from ..catalog.io import load_catalog
from ..mc.options import DEFAULT_SEED, DEFAULT_TRIALS, PREFILTERS, McOptions
from ..report import build_report
from .common import add_catalog_option, add_scenario_options, scenario_from_args
from .mc_cmd import add_platform_motion_options, platform_motion_from_args
from .output import write_json
from .progress import Progress, add_quiet_option


def add_parser(sub) -> None:
    p = sub.add_parser("report", help="HTML report: scenario, bounds, check, Monte Carlo, figures",
                       description="Write one self-contained HTML report (plotly.js embedded: opens "
                                   "offline).")
    add_scenario_options(p, required=True)
    p.add_argument("--part", nargs="+", metavar="ID", help="parts to check (default: the whole catalog)")
    p.add_argument("--mc-part", nargs="+", metavar="ID", default=[],
                   help="parts to run through the Monte Carlo (default: none)")
    add_catalog_option(p)
    p.add_argument("--trials", type=int, default=DEFAULT_TRIALS, help="Monte Carlo trials per part")
    p.add_argument("--seed", type=int, default=DEFAULT_SEED, help="random seed")
    p.add_argument("--prefilter", choices=PREFILTERS, default="none", help="IMU pre-filter of the MC chain")
    add_platform_motion_options(p)
    p.add_argument("--mode", choices=("paper", "derived", "no-autofocus"), default="paper",
                   help="bounds of the analytic check")
    p.add_argument("--out", metavar="REPORT.html", required=True, help="HTML file to write")
    p.add_argument("--json", metavar="FILE", help="also write the report's content as JSON ('-' = stdout)")
    p.add_argument("--figures", metavar="DIR", help="also write each figure to DIR")
    p.add_argument("--figure-format", choices=("html", "png", "svg"), default="html",
                   help="format of --figures (png/svg need kaleido and a Chromium)")
    add_quiet_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    s = scenario_from_args(args)
    cat = load_catalog(args.catalog)  # ids (and unknown ids' messages) of the catalog merged with --catalog
    motion = platform_motion_from_args(args)
    options = McOptions.build(prefilter=args.prefilter, **({"platform_motion": motion} if motion else {}))
    bars: list[Progress] = []

    def progress(pid: str):
        bars.append(Progress(f"mc {pid}", quiet=args.quiet))
        return bars[-1]

    try:
        rep = build_report(s, args.part or None, mc_parts=args.mc_part, trials=args.trials, seed=args.seed,
                           options=options, mode=args.mode, progress=progress, catalog=cat)
    finally:
        for b in bars:
            b.close()
    rep.save(args.out)
    if args.figures:
        _write_figures(rep.figures, Path(args.figures), args.figure_format)
    if args.json:
        write_json(rep.to_dict(), args.json)
    # with --json - stdout carries the JSON alone; the summary then goes to stderr
    text_out = sys.stderr if args.json == "-" else sys.stdout
    print(rep.summary(), file=text_out)
    print(f"wrote {args.out}", file=text_out)
    return 0


def _write_figures(figures: dict, directory: Path, fmt: str) -> None:
    """Each figure as ``<name>.<fmt>`` (HTML with plotly.js beside it, or PNG/SVG via kaleido)."""
    from ..plots.export import write_html, write_image

    for name, fig in figures.items():
        stem = re.sub(r"[^A-Za-z0-9]+", "_", name).strip("_").lower()
        if fmt == "html":
            write_html(fig, directory / f"{stem}.html", plotlyjs="beside")
        else:
            write_image(fig, directory / f"{stem}.{fmt}")
