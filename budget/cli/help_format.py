"""``--help`` that shows every option's default (argparse's ArgumentDefaultsHelpFormatter, tidied).

The parser class is handed to the sub-command parsers by ``main.build_parser``, so every
sub-command (and nested ones such as ``noise arma``) shows its defaults without each module
asking. A help text that already names its default, and flags whose default is "off" or "none",
get no second note.
"""

from __future__ import annotations

import argparse


class DefaultsFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Appends ``(default: X)`` where the default is a real value not yet named in the help."""

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        if "default" in text.lower() or action.default in (None, False, argparse.SUPPRESS):
            return text
        if isinstance(action, (argparse._HelpAction, argparse._VersionAction)):
            return text
        return super()._get_help_string(action)


class DefaultsParser(argparse.ArgumentParser):
    """An :class:`argparse.ArgumentParser` whose help shows defaults (:class:`DefaultsFormatter`)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", DefaultsFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str):
        """A bad option is one line, like every other input error (argparse prints the whole
        usage first), with where to look; exit code 2."""
        self.exit(2, f"{self.prog}: error: {message} (options: {self.prog} --help)\n")
