"""Argument parsing shared by every command."""

from __future__ import annotations

import argparse
import math
import re
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NoReturn

from shared.errors import InvalidInputError
from shared.text.plain import plain_text

if TYPE_CHECKING:
    from shared.messages.measure_params import MeasureParams

#: Negative numbers in any float spelling (-1, -.5, -1e-3) are values, not options.
NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|nan)$", re.I)


#: The starts of argparse's errors for a required argument or group missing.
MISSING = ("the following arguments are required", "one of the arguments")


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
        """argparse's error (exit 2), naming unknown options first if any."""
        unknown = self.unknown_options(self._given)
        if unknown and message.startswith(MISSING):
            message = f"unrecognized arguments: {' '.join(unknown)}"
        super().error(message)

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


def finite(values: list[float] | None, name: str) -> list[float] | None:
    """``values`` if all are finite; else ``InvalidInputError`` naming ``name``."""
    if values is None:
        return None
    for i, value in enumerate(values):
        if not math.isfinite(value):
            raise InvalidInputError(
                f"{name}[{i}] must be a finite number, got {value}", field=name
            )
    return values


def add_arm(
    parser: argparse.ArgumentParser, help: str = "right or left (default: right)"
) -> None:
    """``--arm right|left`` (default right), in any case.

    Read as given: ``Side.parse`` (or ``load_arm``) turns it into an arm,
    refusing any other name with ``UnknownArmError``.
    """
    parser.add_argument("--arm", default="right", help=help)


def add_json(parser: argparse.ArgumentParser) -> None:
    """``--json``: machine-readable output."""
    parser.add_argument(
        "--json",
        action="store_true",
        help="print JSON (machine-readable) instead of text",
    )


def add_measure_options(parser: argparse.ArgumentParser) -> None:
    """``--mu K`` and ``--omega W``: the IK measures' two weights the paper names."""
    parser.add_argument(
        "--mu",
        type=float,
        metavar="K",
        help="elbow swivel stiffness of TPE [J/rad^2] (eq. 17; default: the "
        "motion model's, fitted by armplan fit)",
    )
    parser.add_argument(
        "--omega",
        type=float,
        metavar="W",
        help="wrist discomfort weight of NTPE [J/rad^2] (eq. 19; default: the "
        "motion model's, fitted by armplan fit)",
    )


def measure_fields(args: argparse.Namespace) -> dict[str, float]:
    """The ``MeasureParams`` fields given by ``--mu`` and ``--omega``."""
    return {
        name: getattr(args, name)
        for name in ("mu", "omega")
        if getattr(args, name, None) is not None
    }


def measures_from_args(
    args: argparse.Namespace, base: MeasureParams | None = None
) -> MeasureParams:
    """The measures' weights: ``base`` (default the shipped) with ``--mu``/``--omega``.

    Raises:
        InvalidInputError: naming the option, if a weight is out of its range.
    """
    from shared.messages import parse
    from shared.messages.measure_params import MeasureParams

    given = {} if base is None else base.model_dump()
    return parse(MeasureParams, given | measure_fields(args))
