"""``--help`` that shows every option's default (argparse's ArgumentDefaultsHelpFormatter, tidied).

The parser class is handed to the sub-command parsers by ``main.build_parser``, so every
sub-command (and nested ones such as ``noise arma``) shows its defaults without each module
asking. A help text that already names its default, and flags whose default is "off" or "none",
get no second note; an option without a help text gets its default as its help (argparse leaves
the help column of such an option empty, and the default with it).
"""

from __future__ import annotations

import argparse
import copy
import re

#: What reads as a negative number, not an option: ``-30``, ``-.5``, ``-1.5e1``, ``-2E-3``.
#: argparse's own pattern (``^-\d+$|^-\d*\.\d+$``) misses the exponent, so
#: ``--manoeuvre-angle -1.5e1`` was "expected one argument" while ``-15`` worked.
NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def _no_default(value) -> bool:
    """``None``, ``False``, ``""`` and ``SUPPRESS`` mean "no default"; ``0`` is a value."""
    return value is None or value is False or value is argparse.SUPPRESS or (isinstance(value, str) and value == "")


class DefaultsFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Appends ``(default: X)`` where the default is a real value not yet named in the help."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        if "default" in text.lower() or _no_default(action.default):
            return text
        if isinstance(action, (argparse._HelpAction, argparse._VersionAction)):
            return text
        return super()._get_help_string(action)

    def _format_action(self, action: argparse.Action) -> str:
        if (action.option_strings and not (action.help or "").strip() and not _no_default(action.default)
                and not isinstance(action, (argparse._HelpAction, argparse._VersionAction))):
            action = copy.copy(action)
            action.help = "(default: %(default)s)"
        return super()._format_action(action)


class DefaultsParser(argparse.ArgumentParser):
    """An :class:`argparse.ArgumentParser` whose help shows defaults (:class:`DefaultsFormatter`)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", DefaultsFormatter)
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER  # scientific notation too (-1.5e1)

    def error(self, message: str):
        """A bad option is one line, like every other input error (argparse prints the whole
        usage first), with where to look; exit code 2."""
        self.exit(2, f"{self.prog}: error: {message} (options: {self.prog} --help)\n")
