"""``sar-budget catalog validate|list|show``."""

from __future__ import annotations

import sys

from ..catalog.io import count_valid_parts, get_part, load_catalog, part_origins, read_grades, shipped_catalog_dir
from ..catalog.validate import collect_errors
from ..errors import InputError
from ..fileio import open_input, text_encoding
from .common import add_catalog_option
from .output import add_json_option, printable, write_json


#: Bad cells ``catalog validate`` lists at most.
MAX_REPORTED = 200


def add_parser(sub) -> None:
    p = sub.add_parser("catalog", help="validate, list or show catalog parts")
    csub = p.add_subparsers(dest="catalog_command", metavar="ACTION", required=True)
    v = csub.add_parser("validate", help="validate a catalog CSV (default: the shipped one)")
    v.add_argument("csv", nargs="?", help="CSV to validate (default: the shipped catalog)")
    v.set_defaults(func=run_validate)
    lst = csub.add_parser("list", help="list parts (shipped merged with the user catalog)")
    add_catalog_option(lst)
    add_json_option(lst)
    lst.set_defaults(func=run_list)
    sh = csub.add_parser("show", help="show one part")
    sh.add_argument("part_id")
    add_catalog_option(sh)
    add_json_option(sh)
    sh.set_defaults(func=run_show)


def _is_grades_table(path) -> bool:
    """The header names ``grade`` and ``rank`` and no ``part_id``: the grades table (``grades.csv``),
    validated as one, not as a parts file missing ``part_id``."""
    try:
        with open_input(path) as fh:
            raw = fh.read(100_000)
    except (OSError, InputError):
        return False  # the parts reader names the problem
    head = raw.decode(text_encoding(raw[:4]), errors="replace").splitlines()  # the codec drops the mark
    head = head[0] if head else ""
    cols = {c.strip().strip('"').lower() for c in head.split(",")}
    return {"grade", "rank"} <= cols and "part_id" not in cols


def run_validate(args) -> int:
    path = args.csv or shipped_catalog_dir() / "parts.csv"
    if _is_grades_table(path):
        n = len(read_grades(path))
        print(f"{printable(path)}: grades table, {n} grades valid")
        return 0
    try:
        n = count_valid_parts(path)  # vectorised check: a 50 MB catalog in seconds
    except InputError:
        errors = collect_errors(path, limit=MAX_REPORTED)  # every bad cell, not only the first
        for err in errors[:-1]:
            print(f"sar-budget catalog: error: {err}", file=sys.stderr)
        more = f" (the first {MAX_REPORTED} shown)" if len(errors) >= MAX_REPORTED else ""
        raise InputError(f"{errors[-1]} — {len(errors)} bad cell(s) in all{more}") from None
    print(f"{printable(path)}: {n} parts valid")
    return 0


def run_list(args) -> int:
    """One line per part; the last column says where its row comes from (a user row that
    replaces a shipped one is marked, so edited numbers are never mistaken for the datasheet's)."""
    cat = load_catalog(args.catalog)
    origin = part_origins(args.catalog)
    if args.json:
        write_json([{**p.model_dump(), "origin": origin[pid]} for pid, p in cat.items()], args.json)
        return 0
    for pid, p in cat.items():
        print(f"{p.part_id:<22}{p.grade:<14}{printable(p.vendor, 40):<40} {printable(p.model, 40):<40} "
              f"{origin[pid]}")
    return 0


def run_show(args) -> int:
    p = get_part(args.part_id, load_catalog(args.catalog))
    origin = part_origins(args.catalog)[p.part_id]
    if args.json:
        write_json({**p.model_dump(), "origin": origin}, args.json)
        return 0
    for k, v in p.model_dump().items():
        print(f"{k:<32}{'' if v is None else printable(v)}")
    print(f"{'origin':<32}{origin}")
    return 0
