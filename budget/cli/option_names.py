"""Where a library error names one of its fields, the command line names the option typed.

The library's refusals name their own fields (``McOptions``' ``clutter_to_target_db``, a platform
motion's ``period_s``, the gap's ``realizations``, a catalog row's ``part_id``); the user typed
``--clutter-db``, ``--manoeuvre-period``, ``--realizations``, ``--as-part``. One place maps them:
a field is the option whose argparse ``dest`` it is (``--realizations``: ``realizations``;
``--clutter-db``: ``dest="clutter_to_target_db"``), or the one :data:`FIELD_DESTS` names where
the two differ. The CLI's error boundary (:func:`budget.cli.main.main`) renames the error with
:func:`name_option`, so the line reads ``option --manoeuvre-period: …`` as the command's own
checks (``--trials``, ``--seed``, ``--workers``) already say it. An error read from a file
(``--acceptance A.json``, a scenario file) names that file and its field, and is left as it is.
"""

from __future__ import annotations

import argparse

from ..errors import InputError

#: Library field → argparse ``dest`` of the option that sets it, where the names differ.
FIELD_DESTS: dict[str, str] = {
    "peak_rate_deg_s": "manoeuvre_rate",      # --manoeuvre-rate (platform motion)
    "period_s": "manoeuvre_period",           # --manoeuvre-period
    "angle_deg": "manoeuvre_angle",           # --manoeuvre-angle
    "part_id": "as_part",                     # noise characterize --as-part
}

#: What an option expects in the command line's words, where the library's text names a Python
#: type the command line cannot give (``sar --window``: "… or a Window").
OPTION_EXPECTED: dict[str, str] = {
    "--window": "rect, taylor, or taylor-SLL-NBAR (sidelobe level in dB, n̄; e.g. taylor-35-4)",
}


def command_parser(parser: argparse.ArgumentParser, args) -> argparse.ArgumentParser:
    """The parser of the (sub-)sub-command ``args`` were parsed for (``noise characterize``'s,
    ``check``'s …); ``parser`` itself without one."""
    while True:
        subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
        chosen = getattr(args, subs[0].dest, None) if subs else None
        if not subs or chosen not in subs[0].choices:
            return parser
        parser = subs[0].choices[chosen]


def option_of(field: str | None, parser: argparse.ArgumentParser, args) -> str | None:
    """The option (``--clutter-db``) of the command's ``parser`` that set the library field
    ``field``, if the user gave it; None otherwise."""
    if not field or field.startswith("-"):
        return None
    dest = FIELD_DESTS.get(field, field)
    for action in parser._actions:
        if action.dest == dest and action.option_strings:
            given = getattr(args, dest, None)
            if given is None or given is False:  # (0 is a value given: `is`, not ==)
                return None  # not given: the field is not the option's
            return max(action.option_strings, key=len)
    return None


def name_option(err: BaseException, parser: argparse.ArgumentParser, args) -> BaseException:
    """``err`` naming the option the user typed instead of the library field (:data:`FIELD_DESTS`,
    :data:`OPTION_EXPECTED`); any other error, or one read from a file, as it is."""
    if not isinstance(err, InputError) or err.file:
        return err
    option = option_of(err.field, command_parser(parser, args), args)
    if option is None:
        return err
    err.field = option
    if option in OPTION_EXPECTED:
        err.expected = OPTION_EXPECTED[option]
    err.args = (err._format(),)
    return err
