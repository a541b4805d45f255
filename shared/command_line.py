"""The argument parser every armplan command line uses.

``armplan`` and its subcommands (``armplan.cli``) and the processes started
as ``python -m ...`` (the services, the bridge, the sim, the recorder, the
router) read their options alike: numbers may be negative, options only as
spelt in full, a misspelt one named with the option it is closest to.
"""

from __future__ import annotations

import argparse
import difflib
import re
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

from shared.text.plain import plain_text

#: Negative numbers in any float spelling (-1, -.5, -1e-3) are values, not options.
NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|nan)$", re.I)


#: The starts of argparse's errors for a required argument or group missing.
MISSING = ("the following arguments are required", "one of the arguments")
#: The start of argparse's error for arguments no parser took.
UNRECOGNIZED = "unrecognized arguments: "


class ArgumentParser(argparse.ArgumentParser):
    """An argparse parser that reads ``-0.12`` and ``-1e-3`` as numbers.

    Options are taken only as spelt in full (``--dwel`` is no ``--dwell``).
    A misspelt option is reported before a required argument that is
    missing, which it may have been meant to give: ``plan --targt X Y Z``
    said only that one of ``--target --wrist-path --task`` is required.
    Its description and epilog are shown as plain text: a command's module
    docstring given as its description keeps no reST markup in ``--help``
    (``shared.text.plain``).
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER
        self.description = plain_text(self.description)
        self.epilog = plain_text(self.epilog)
        self._given: list[str] = []

    def parse_known_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: Any = None
    ) -> tuple[argparse.Namespace, list[str]]:
        """argparse's, the arguments kept for :meth:`error`."""
        self._given = list(sys.argv[1:] if args is None else args)
        return super().parse_known_args(args, namespace)

    def error(self, message: str) -> NoReturn:
        """argparse's error (exit 2), naming unknown options first if any.

        Arguments left over are reported by the command they were given to
        (its usage, its name: ``armplan fit: error: ...``, not the bare
        ``armplan``'s), with the option each misspelt one is closest to:
        ``unrecognized arguments: --timout (did you mean --timeout?)``.
        """
        unknown = self.unknown_options(self._given)
        if unknown and message.startswith(MISSING):
            message = f"{UNRECOGNIZED}{' '.join(unknown)}"
        if message.startswith(UNRECOGNIZED):
            # one given to this parser, before the subcommand: ours to report
            command = None if unknown else self._command_parser()
            if command is not None:
                command.error(message)
            message += self._did_you_mean(message[len(UNRECOGNIZED) :].split())
        super().error(message)

    def _command_parser(self) -> ArgumentParser | None:
        """The subcommand's parser the given arguments chose, if any."""
        for action in self._actions:
            if isinstance(action, argparse._SubParsersAction):
                for arg in self._given:
                    chosen = action.choices.get(arg)
                    if isinstance(chosen, ArgumentParser):
                        return chosen
                    if arg == "--":
                        break
        return None

    def _did_you_mean(self, args: Sequence[str]) -> str:
        """`` (did you mean --x?)`` for the unknown options close to one of ours.

        Only those before ``--``: what follows it is a value, never an option.
        """
        if "--" in args:
            args = args[: list(args).index("--")]
        ours = [  # not the hidden ones
            option
            for option, action in self._option_string_actions.items()
            if option.startswith("--") and action.help != argparse.SUPPRESS
        ]
        names = [a.split("=", 1)[0] for a in args if self._is_unknown_option(a)]
        close = []
        for name in names:
            found = difflib.get_close_matches(name, ours, n=1, cutoff=0.75)
            if found:
                close.append(f"{found[0]} for {name}" if len(names) > 1 else found[0])
        return f" (did you mean {', '.join(close)}?)" if close else ""

    def unknown_options(self, given: Sequence[str]) -> list[str]:
        """The options in ``given`` this parser does not have.

        Up to ``--`` or a subcommand's name (its options are its own).
        """
        commands = {
            name
            for action in self._actions
            if isinstance(action, argparse._SubParsersAction)
            for name in action.choices
        }
        unknown = []
        for arg in given:
            if arg == "--" or arg in commands:
                break
            if self._is_unknown_option(arg):
                unknown.append(arg)
        return unknown

    def _is_unknown_option(self, arg: str) -> bool:
        """Whether ``arg`` reads as an option this parser does not have."""
        if len(arg) < 2 or arg[0] not in self.prefix_chars:
            return False
        if self._negative_number_matcher.match(arg):
            return False  # a value
        known = self._option_string_actions
        name = arg.split("=", 1)[0]
        if " " in arg and name not in known:
            return False  # a value, as argparse reads it ("-x y.json")
        return name not in known and arg[:2] not in known
