"""``sar-budget gap``: where a measured log and its noise model disagree, and what is missing.

Contract (scripts rely on it)::

    sar-budget gap MEASURED.csv (--part ID | --model MODEL.json) --report REPORT.json
                   [--out-model UPDATED.json] [--seed K] [--low-frequency] [--decorrelate] [--no-slow-modes]

MEASURED.csv is an IMU log or a measured Allan-deviation table (``channel,tau_s,adev[,lci,uci]``
with ``--rate-hz`` and ``--samples``). REPORT.json: ``gap_before``, ``gap_after``, ``effects``
(name, channel, params in SI channel units, gap_before, gap_after; in the order added, ``[]``
when nothing is missing), ``channels`` (gap_before, gap_after per channel), plus thresholds,
localisation, notes and ``options`` (``low_frequency``, ``decorrelate``: the opt-in statistics,
off by default; ``slow_modes``: the record's slowest modes, on by default for a log). The summary goes to stdout; bad input exits 2 with one line.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..fileio import atomic_write_text, json_text
from ..gap import cross_validate, run_gap
from ..gap.effect_size import DEFAULT_TOLERANCE_DB
from ..gap.workflow import DEFAULT_MAX_STEPS, DEFAULT_REALIZATIONS
from ..noise import LogMapping
from ..units import CHANNELS
from .common import add_part_or_model_options
from .progress import add_quiet_option, working


def add_parser(sub) -> None:
    p = sub.add_parser("gap", help="model gap: compare a log with its noise model, name missing effects")
    p.add_argument("measured", metavar="MEASURED.csv",
                   help="static IMU log CSV (.csv/.csv.gz) or Allan table (channel, tau_s, adev[, lci, uci])")
    add_part_or_model_options(p, part_help="catalog part the log should follow",
                              model_help="noise model: catalog-row fields (datasheet units, absent = 0) "
                                         "+ optional effects")
    p.add_argument("--report", metavar="REPORT.json", required=True, help="write the JSON report here")
    p.add_argument("--out-model", metavar="UPDATED.json", help="write the updated model (base + effects)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the simulations (default 0)")
    p.add_argument("--realizations", type=int, default=DEFAULT_REALIZATIONS,
                   help=f"simulated logs per channel (default {DEFAULT_REALIZATIONS}, ≥ 4)")
    p.add_argument("--max-steps", type=int, default=DEFAULT_MAX_STEPS,
                   help=f"most effects to add (default {DEFAULT_MAX_STEPS})")
    p.add_argument("--alpha", type=float, default=0.01, help="false-alarm level (default 0.01)")
    p.add_argument("--min-gain", type=float, default=0.05,
                   help="share of its channel's excess gap an effect must remove (default 0.05)")
    p.add_argument("--channels", help=f"comma-separated subset of {','.join(CHANNELS)} (for an Allan "
                                      "table without a channel column, the one channel of its curve)")
    p.add_argument("--rate-hz", type=float, help="sampling rate (Allan tables; logs without time)")
    p.add_argument("--samples", type=int, help="record length behind an Allan table")
    p.add_argument("--ci-level", type=float, default=0.95, help="confidence level of an Allan table's lci/uci")
    p.add_argument("--mapping", metavar="MAP.json", help="column/unit mapping for other log layouts")
    p.add_argument("--repair", action="store_true", help="repair the log (listed in the report notes)")
    p.add_argument("--max-rows", type=int, metavar="N", help="read only the first N rows of the log")
    p.add_argument("--no-tau-check", action="store_true",
                   help="accept a log shorter than the model's bias-instability floor needs")
    p.add_argument("--plots", metavar="DIR", help="write measured-vs-model figures (HTML) to DIR")
    p.add_argument("--tolerance-db", type=float, default=DEFAULT_TOLERANCE_DB,
                   help="smallest misfit beyond the model's spread worth naming an effect for, dB "
                        f"(default {DEFAULT_TOLERANCE_DB})")
    p.add_argument("--test-log", metavar="TEST.csv",
                   help="cross-validate on a second log of the same part: effects that do not "
                        "carry over are not named (--out-model then writes the validated model)")
    p.add_argument("--low-frequency", action="store_true",
                   help="also score the record's low-frequency bands (DCT of the detrended log below "
                        "the first PSD band, periods ≈ 40 s to the record length: where a rate random "
                        "walk parts from bias instability and the long-τ ADEV has 2–5 degrees of "
                        "freedom). Logs only. Off by default: measured on the benchmark with "
                        "--decorrelate, it names a hidden random walk once more but reads 3 of 10 "
                        "hidden ramps as a random walk and names a ramp on 2 of 50 model-following "
                        "logs (README, Model gap)")
    p.add_argument("--decorrelate", action="store_true",
                   help="sum the spectral terms (ADEV octaves, PSD bands, low-frequency bands) "
                        "decorrelated under the model's own leave-one-out covariance, so a misfit "
                        "seen by several correlated Allan octaves counts once (the z reported stay "
                        "as measured). Logs only. Off by default, for the same measured trade-off "
                        "as --low-frequency")
    p.add_argument("--no-slow-modes", action="store_true",
                   help="leave out the record's slowest modes (block sums on the slowest DCT modes, "
                        "judged against the model's exact covariance: where a rate random walk shows "
                        "best over one hour; with them their projection on a start-of-record pattern, "
                        "which tells a turn-on transient from slow noise). On by default: on the benchmark it names a hidden walk "
                        "at 3× 8/10 instead of 6/10, at the cost of one hidden ramp read as a walk at "
                        "2× and at 5× (README, Model gap)")
    add_quiet_option(p)
    p.set_defaults(func=run)


def _channels(text: str | None):
    if not text:
        return None
    chans = [c.strip() for c in text.split(",") if c.strip()]
    bad = [c for c in chans if c not in CHANNELS]
    if bad or not chans:
        raise InputError(f"unknown channel(s) {', '.join(bad) or '(none)'}", field="--channels",
                         expected=f"comma-separated names from {', '.join(CHANNELS)}")
    return chans


def run(args) -> int:
    if args.max_steps < 0:
        raise InputError("--max-steps must be ≥ 0", field="--max-steps", value=args.max_steps)
    mapping = LogMapping.load(args.mapping) if args.mapping else None
    model = args.part if args.part else Path(args.model)
    kw = dict(seed=args.seed, realizations=args.realizations, channels=_channels(args.channels),
              max_steps=args.max_steps, alpha=args.alpha, min_gain=args.min_gain,
              check_tau_range=not args.no_tau_check, catalog_csv=args.catalog, mapping=mapping,
              repair=args.repair, max_rows=args.max_rows, tolerance_db=args.tolerance_db,
              low_frequency=args.low_frequency, decorrelate=args.decorrelate,
              slow_modes=not args.no_slow_modes)
    cv = None
    with working(f"gap: {Path(args.measured).name} vs {args.part or Path(args.model).name}",
                 quiet=args.quiet):
        if args.test_log:
            cv = cross_validate(args.measured, args.test_log, model, **kw)
            report = cv.fit
        else:
            report = run_gap(args.measured, model, rate_hz=args.rate_hz, samples=args.samples,
                             ci_level=args.ci_level, **kw)
    if cv is None:
        report.save(args.report)
    else:
        atomic_write_text(Path(args.report),
                          json_text({**report.to_dict(), "cross_validation": cv.to_dict()}))
    if args.out_model:
        (report.updated_model if cv is None else cv.validated_model).save(args.out_model)
    if args.plots:
        from ..plots.gap import write_figures
        write_figures(report, Path(args.plots))
    print(report.summary())
    if cv is not None:
        print(cv.summary())
    return 0
