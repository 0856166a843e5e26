"""``sar-budget scenario show|write|validate``: a scenario file to start from, and a check of one.

* ``show --preset NAME`` (or ``--scenario FILE``): every key with its value and the derived
  quantities (λ, Tc, aperture length); ``--json -`` for the scenario JSON itself.
* ``write --preset NAME OUT.json|OUT.yaml``: write the preset as a file to edit (atomically;
  an existing file is kept unless ``--force``).
* ``validate FILE``: read a scenario file and report every error in it (exit 2), or its Tc.
"""

from __future__ import annotations

import json
from pathlib import Path

from ..errors import InputError
from ..presets import PRESETS, get_preset
from ..scenario import Scenario
from .common import add_scenario_options, scenario_from_args
from .output import add_json_option, write_json


def add_parser(sub) -> None:
    p = sub.add_parser("scenario", help="show, write or validate a scenario (JSON/YAML)",
                       description="Scenario files: show a preset or file, write a preset to edit, "
                                   "validate a file (every error listed).")
    ssub = p.add_subparsers(dest="scenario_command", metavar="ACTION", required=True)
    s = ssub.add_parser("show", help="print a preset's or file's keys and derived quantities")
    add_scenario_options(s, required=True)
    add_json_option(s)
    s.set_defaults(func=run_show)
    w = ssub.add_parser("write", help="write a preset as a JSON/YAML file to start from")
    w.add_argument("--preset", choices=sorted(PRESETS), required=True, help="preset to write")
    w.add_argument("out", metavar="OUT.json|OUT.yaml", help="file to write (format from the suffix)")
    w.add_argument("--name", help="scenario name in the file (default: the preset's name)")
    w.add_argument("--force", action="store_true", help="overwrite an existing file")
    w.set_defaults(func=run_write)
    v = ssub.add_parser("validate", help="check a scenario file; every error is listed")
    v.add_argument("file", metavar="S.json|S.yaml")
    v.set_defaults(func=run_validate)


def describe(s: Scenario) -> str:
    """Keys and derived quantities of ``s``, one per line (SI; the unit is in the key); a key the
    scenario did not set is marked ``(default)`` beside the value taken."""
    lines = [f"scenario {s.name}"]
    for k, v in s.model_dump(mode="json").items():
        if k != "name":
            text = "(default)" if v is None else f"{v}" if k in s.model_fields_set else f"{v}  (default)"
            lines.append(f"  {k:<28}{text}")
    lines.append("derived:")
    lines += [f"  {k:<28}{v:.6g}" for k, v in s.derived().items()]
    return "\n".join(lines)


def run_show(args) -> int:
    s = scenario_from_args(args)
    if args.json:
        write_json(s.model_dump(mode="json"), args.json)
    else:
        print(describe(s))
    return 0


def run_write(args) -> int:
    out = Path(args.out)
    if out.suffix.lower() not in (".json", ".yaml", ".yml"):
        raise InputError("unknown scenario file type", file=out, expected="a .json, .yaml or .yml file")
    if out.exists() and not args.force:
        raise InputError("file exists", file=out, expected="a new file name, or --force to overwrite")
    s = get_preset(args.preset)
    if args.name is not None:  # "" is refused by name, not ignored
        s = Scenario.from_dict({**s.model_dump(), "name": args.name}, source="--name")
    s.save(out)
    print(f"wrote {out} (preset {args.preset}; Tc = {s.tc_s:.4g} s)")
    return 0


def run_validate(args) -> int:
    s = Scenario.load(args.file)  # InputError lists every error (exit 2)
    print(f"{args.file}: valid scenario {s.name!r}, Tc = {s.tc_s:.4g} s")
    return 0


def dumps(s: Scenario) -> str:
    """Scenario as the JSON text ``write`` produces (the dashboard's download uses it too)."""
    return json.dumps(s.model_dump(mode="json"), indent=2) + "\n"
