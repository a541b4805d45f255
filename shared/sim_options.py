"""The simulated NAO's behaviour options (``python -m bridge.sim``, ``armplan sim``).

Both commands take them; ``armplan sim`` checks them, then becomes
``python -m bridge.sim`` with them. They live here, not in ``bridge.sim``,
so that ``armplan``'s parser offers them without importing the bridge.
"""

from __future__ import annotations

import argparse

from shared.errors import InvalidInputError


def add_sim_options(parser: argparse.ArgumentParser) -> None:
    """``--killed-calls-return``, ``--limp-sag SECONDS``, ``--grip OPEN_FRACTION``."""
    parser.add_argument(
        "--killed-calls-return",
        action="store_true",
        help="a blocking call whose motion task is killed (killAll, "
        "killTasksUsingResources) returns normally instead of raising, as "
        "NAOqi's may",
    )
    parser.add_argument(
        "--limp-sag",
        type=float,
        default=0.0,
        metavar="SECONDS",
        help="a joint let go falls toward its rest angle at 1 rad/s for this "
        "long, as a NAO's arm falls for about 0.3 s (default 0: it holds still)",
    )
    parser.add_argument(
        "--grip",
        type=float,
        default=None,
        metavar="OPEN_FRACTION",
        help="each hand holds an object this wide (0..1), so it closes no "
        "further (default: nothing in the hands)",
    )


def check_sim_options(args: argparse.Namespace) -> None:
    """Raise InvalidInputError unless the options are in range.

    ``--limp-sag``: 0..10 s; ``--grip``: an open fraction 0..1, or not given.
    """
    check_sag(args.limp_sag)
    check_grip(args.grip)


def sim_argv(args: argparse.Namespace) -> list[str]:
    """The options as ``python -m bridge.sim`` takes them."""
    argv = ["--limp-sag", str(args.limp_sag)]
    if args.killed_calls_return:
        argv.append("--killed-calls-return")
    if args.grip is not None:
        argv += ["--grip", str(args.grip)]
    return argv


def check_sag(sag: float) -> None:
    """Raise InvalidInputError unless ``sag`` [s] is 0..10."""
    if not 0.0 <= sag <= 10.0:  # NaN too
        raise InvalidInputError(
            f"--limp-sag must be 0..10 s, got {sag}", field="limp_sag"
        )


def check_grip(grip: float | None) -> None:
    """Raise InvalidInputError unless ``grip`` is None or an open fraction 0..1."""
    if grip is not None and not 0.0 <= grip <= 1.0:  # NaN too
        raise InvalidInputError(
            f"--grip must be an open fraction 0..1, got {grip}", field="grip"
        )
