"""``sar-budget noise characterize|arma``: Allan characterisation and ARMA/Kalman modelling."""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import InputError
from ..noise import ImuLog, LogMapping, characterize, read_log
from ..noise.arma import DEFAULT_ORDERS, MAX_ORDER
from ..noise.characterize import log_findings_of
from ..noise.measurement import read_measurement
from ..noise.pipeline import AIC_DEFINITION, ArmaOptions, analyse_arma  # noqa: F401
from ..noise.preprocess import DETREND_ORDERS
from .output import add_json_option, warn, write_json
from .progress import add_quiet_option, working


def _log_options(p) -> None:
    p.add_argument("--mapping", metavar="MAP.json", help="column/unit mapping for other log layouts")
    p.add_argument("--repair", action="store_true",
                   help="repair duplicate/out-of-order rows, missing values and gaps (listed)")
    p.add_argument("--max-rows", type=int, metavar="N", help="read only the first N rows")


def add_parser(sub) -> None:
    p = sub.add_parser("noise", help="noise lab: Allan characterisation, ARMA + Kalman filter")
    nsub = p.add_subparsers(dest="noise_command", metavar="ACTION", required=True)

    c = nsub.add_parser("characterize", help="IMU log or Allan table → IEEE-952 terms → catalog row")
    c.add_argument("input", help="static IMU log CSV (.csv/.csv.gz) or Allan table "
                                 "(channel, tau_s, adev[, lci, uci])")
    c.add_argument("--rate-hz", type=float, help="sampling rate of the record behind an Allan table (with "
                                                 "--samples; leave both out for a digitised datasheet curve), "
                                                 "or of a log without a time column (with one, it must agree "
                                                 "with the stamps within 1 %%)")
    c.add_argument("--samples", type=int, help="record length behind an Allan table (with --rate-hz; "
                                               "neither for a digitised datasheet curve)")
    c.add_argument("--ci-level", type=float, default=0.95, help="confidence level of an Allan table's lci/uci")
    c.add_argument("--channels", metavar="CH,CH",
                   help="characterise only these channels, e.g. gyro_x,gyro_y,gyro_z (a log's other "
                        "columns are then neither read nor checked); for an Allan table without a "
                        "channel column (tau_s, adev [deg/h]), the one channel its curve belongs to")
    c.add_argument("--taus", default="octave", choices=("octave", "decade", "dense"),
                   help="τ list for logs (default octave)")
    c.add_argument("--grade", help="grade of the row (default: inferred from the grades table)")
    c.add_argument("--vendor", default="", help="vendor column of the catalog row")
    c.add_argument("--model", default="", help="model column of the catalog row (the part's model name)")
    c.add_argument("--keep-spikes", action="store_true",
                   help="keep isolated spikes that would decide the short-τ Allan deviation (default: "
                        "replaced before the fit, named in a warning)")
    c.add_argument("--as-part", metavar="ID", help="part_id of the catalog row")
    c.add_argument("--append", metavar="CSV", help="append the row to this user catalog CSV (created if absent; "
                                                   "a missing folder is created, as for every output)")
    c.add_argument("--replace", action="store_true", help="with --append: replace an existing id")
    _log_options(c)
    add_json_option(c)
    add_quiet_option(c)
    c.set_defaults(func=run_characterize)

    a = nsub.add_parser("arma", help="preprocess, check, select an ARMA model, Kalman-filter a channel")
    a.add_argument("log", help="static IMU log CSV")
    a.add_argument("--channel", default="gyro_z", help="channel, e.g. gyro_z (default)")
    a.add_argument("--orders", nargs="+", metavar="P,Q",
                   help=f"candidate orders (default 0,0 1,0 2,0 3,0 1,1 2,1; 0,0 = white; p, q ≤ {MAX_ORDER})")
    a.add_argument("--method", choices=("ls", "mle"), default="ls",
                   help="least squares (paper) or exact maximum likelihood (statsmodels)")
    a.add_argument("--pauta-k", type=float, default=4.0, help="outlier factor k (3–5, default 4)")
    a.add_argument("--no-outliers", action="store_true", help="skip the Pauta outlier step")
    a.add_argument("--replace-with", choices=("mean", "neighbour"), default="mean")
    a.add_argument("--detrend", type=int, choices=DETREND_ORDERS, default=1, help="polynomial order")
    a.add_argument("--process-noise", choices=("paper", "model"), default="paper",
                   help="Q = δ1·I (paper) or δ1·G·Gᵀ (model)")
    a.add_argument("--rate-hz", type=float, help="sampling rate (if the log has no time column; with one, "
                                                 "it must agree with the stamps within 1 %%)")
    _log_options(a)
    add_json_option(a)
    add_quiet_option(a)
    a.set_defaults(func=run_arma)


def _mapping(args) -> LogMapping | None:
    return LogMapping.load(args.mapping) if getattr(args, "mapping", None) else None


def run_characterize(args) -> int:
    path = Path(args.input)
    if args.append and not args.as_part:
        raise InputError("--append needs --as-part ID (the part_id of the new row)", field="--as-part")
    if args.replace and not args.append:  # replace in which catalog? (it was silently ignored)
        raise InputError("--replace needs --append CSV (the user catalog whose row it replaces)",
                         field="--replace", expected="--append CSV --replace, or no --replace")
    chans = [c.strip() for c in args.channels.split(",") if c.strip()] if args.channels else None
    data = read_measurement(path, rate_hz=args.rate_hz, samples=args.samples, mapping=_mapping(args),
                            repair=args.repair, max_rows=args.max_rows, ci_level=args.ci_level,
                            channels=chans, digitised=True)
    if chans and not isinstance(data, ImuLog):  # an Allan table: keep its tables of those channels
        missing = [c for c in chans if c not in data]
        if missing:
            raise InputError(f"channel(s) {', '.join(missing)} missing from the table", file=path,
                             field="--channels", expected=f"channels the table has: {', '.join(data)}")
        data = {c: data[c] for c in chans}
    if not isinstance(data, ImuLog):  # a log's warnings and repairs are in the result (log_findings)
        for option, given in (("--max-rows", args.max_rows is not None), ("--mapping", args.mapping),
                              ("--repair", args.repair)):
            if given:  # options of a log: an Allan table would silently ignore them
                raise InputError(f"{option} applies to an IMU log, not to an Allan table", file=path,
                                 field=option, expected=f"no {option} with an Allan table")
        for note in (n for t in data.values() for n in t.notes):
            print(f"note: {note}", file=sys.stderr)
    with working(f"noise characterize: {path.name}", quiet=args.quiet):
        result = characterize(data, part_id=args.as_part or "measured", grade=args.grade,
                              vendor=args.vendor, model=args.model, taus=args.taus,
                              keep_spikes=args.keep_spikes)
    if args.json:  # the summary printed below lists them itself
        for warning in result.warnings + result.log_findings:  # e.g. not one stationary regime, jitter
            warn(args, f"{path.name}: {warning}")
    if args.append:
        from ..catalog.io import append_part
        from .output import make_output_folder
        make_output_folder(args.append)  # one rule for every output: a missing folder is created, and said
        append_part(args.append, result.part, replace=args.replace)
    if args.json:
        write_json(result.to_dict(), args.json)
    else:
        print(result.summary())
    if args.append:
        print(f"appended {result.part.part_id} to {args.append}", file=sys.stderr)
        if (empty := result.empty_fields_text()) is not None:  # what the row does not state, and why
            warn(args, empty)
    return 0


def _orders(text: list[str] | None):
    if not text:
        return DEFAULT_ORDERS
    out = []
    for t in text:
        try:
            p, q = (int(v) for v in t.split(","))
        except ValueError:
            raise InputError("order must be P,Q", field="--orders", value=t, expected="e.g. 2,1") from None
        out.append((p, q))
    return tuple(out)


def run_arma(args) -> int:
    log = read_log(args.log, _mapping(args), args.repair, rate_hz=args.rate_hz,
                   channels=[args.channel], max_rows=args.max_rows, min_samples=100)
    opts = ArmaOptions(orders=_orders(args.orders), method=args.method,
                       pauta_k=None if args.no_outliers else args.pauta_k, replace=args.replace_with,
                       detrend_order=args.detrend, process_noise=args.process_noise)
    with working(f"noise arma: {args.channel}", quiet=getattr(args, "quiet", False)):
        try:
            res = analyse_arma(log.channels[args.channel], log.rate_hz, channel=args.channel, options=opts)
        except InputError as err:  # about the log's channel: name the log
            raise (err if err.file else err.rename_file(args.log)) from None
    # what the reader found and changed (jitter, rows dropped or values interpolated by
    # --repair) is said, as characterize says it: the model was fitted to that data (after the
    # analysis, so that a refusal stays one line)
    name = Path(args.log).name
    for finding in log_findings_of(log):
        warn(args, f"{name}: {finding}")
    for flag in res.checks.flags():
        warn(args, f"{args.channel}: {flag} — modelled anyway, see 'checks'")
    if args.json:  # the summary lists the notes itself (a short record, a model that does not describe the series)
        for note in res.notes:
            warn(args, f"{args.channel}: {note}")
        write_json(res.to_dict(), args.json)
        return 0
    print(res.summary())
    return 0
