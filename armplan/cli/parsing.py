"""Argument parsing shared by every command."""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING

from shared.errors import InvalidInputError

if TYPE_CHECKING:
    from shared.messages.measure_params import MeasureParams


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
