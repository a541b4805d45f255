"""The recorder's command-line options.

Shared by ``python -m services.recorder`` and ``armplan record``.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

from services.recorder.duration_floor import warn_if_short
from services.recorder.options import RecorderOptions, default_output
from services.recorder.size_floor import warn_if_small
from shared.bus.topics import topic_paths
from shared.errors import InvalidInputError, RecordingError
from shared.recording.rotation import FLUSH_EVERY, MAX_FLUSH_EVERY, RotationPolicy
from shared.recording.writer import refuse_folder

_SIZE = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*([kKmMgG]?)i?[bB]?\s*$")
_UNITS = {"": 1, "k": 1024, "m": 1024**2, "g": 1024**3}
_WHOLE = re.compile(r"^\s*\d+\s*$")


def parse_size(text: str) -> int:
    """A size like ``"500000"``, ``"64k"``, ``"100M"`` or ``"1G"`` [bytes].

    Raises:
        InvalidInputError: if ``text`` is not such a size.
    """
    match = _SIZE.match(text)
    if not match:
        raise InvalidInputError(
            f"rotation size {text!r} must read like 500000, 64k, 100M or 1G",
            field="rotate_size",
        )
    return int(float(match.group(1)) * _UNITS[match.group(2).lower()])


def parse_keep_parts(text: str) -> int:
    """The number of parts ``--keep-parts`` keeps, e.g. ``"24"`` -> 24.

    Raises:
        InvalidInputError: if ``text`` is not a whole number of at least 1.
    """
    if not _WHOLE.match(text) or int(text) < 1:
        raise InvalidInputError(
            f"--keep-parts must be a whole number of files, at least 1, got {text!r}",
            field="keep_parts",
        )
    return int(text)


def check_usage(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """Exit with a usage error (code 2) for options that need others.

    ``--keep-parts`` needs ``--rotate-size`` or ``--rotate-duration``.
    """
    rotates = args.rotate_size is not None or args.rotate_duration is not None
    if args.keep_parts is not None and not rotates:
        parser.error(
            "--keep-parts needs --rotate-size or --rotate-duration "
            "(without rotation the recording is one file)"
        )


def add_recorder_arguments(parser: argparse.ArgumentParser) -> None:
    """``-o``, ``--keys``, ``--rotate-size``, ``--rotate-duration``, ..."""
    parser.add_argument(
        "-o",
        "--output",
        metavar="FILE.mcap",
        help="the recording (default: armplan-<date>-<time>-<ms>.mcap here); with "
        "rotation, FILE-0001.mcap, FILE-0002.mcap, ...; an existing one is refused",
    )
    parser.add_argument(
        "--overwrite",
        action="store_true",
        help="replace an existing recording at -o (with rotation: its numbered files)",
    )
    parser.add_argument(
        "--keys",
        nargs="+",
        metavar="KEY",
        help="key expressions under the namespace, e.g. plan/trajectory "
        "'bridge/**' (default: " + " ".join(topic_paths()) + ")",
    )
    parser.add_argument(
        "--rotate-size",
        metavar="SIZE",
        help="start a new file at this size, e.g. 100M (default: never)",
    )
    parser.add_argument(
        "--rotate-duration",
        type=float,
        metavar="S",
        help="start a new file after this many seconds (default: never)",
    )
    parser.add_argument(
        "--keep-parts",
        metavar="N",
        help="with rotation, keep only the newest N files (the one being written "
        "counted, so 1 keeps no finished file): older files of this recording "
        "are removed as new ones start (default: keep all)",
    )
    parser.add_argument(
        "--flush-every",
        type=float,
        default=FLUSH_EVERY,
        metavar="S",
        help=f"longest time between flushes to disk [s] (default {FLUSH_EVERY})",
    )
    parser.add_argument(
        "--no-foxglove",
        action="store_true",
        help="do not write the derived Foxglove channels (/tf/..., /decision, ...)",
    )
    defaults = RecorderOptions()
    for arm, default in (
        ("planned", defaults.planned_prefix),
        ("executed", defaults.executed_prefix),
        ("commanded", defaults.commanded_prefix),
    ):
        parser.add_argument(
            f"--{arm}-prefix",
            default=default,
            metavar="TEXT",
            help=f"frame name prefix of the {arm} arm in /tf/{arm} "
            f"(default {default!r}{', which moves the URDF' if not default else ''})",
        )


def options_from_args(args: argparse.Namespace) -> RecorderOptions:
    """The recorder options the command line asks for.

    A ``--rotate-size`` below what a part weighs on its own is warned about
    (:mod:`services.recorder.size_floor`), not refused; so is a
    ``--rotate-duration`` under a second (:mod:`services.recorder.duration_floor`).

    Raises:
        InvalidInputError: naming the option that is wrong.
        RecordingError: ``-o`` names a folder.
    """
    rotation = RotationPolicy(
        max_bytes=None if args.rotate_size is None else parse_size(args.rotate_size),
        max_seconds=args.rotate_duration,
        keep_parts=None
        if args.keep_parts is None
        else parse_keep_parts(args.keep_parts),
    )
    warn_if_small(args.rotate_size, rotation.max_bytes, not args.no_foxglove)
    warn_if_short(rotation.max_seconds)
    _check_flush_every(args.flush_every)
    if args.output is not None and not args.output:
        raise InvalidInputError(
            "-o is empty: name the recording's file (or leave -o out for "
            "armplan-DATE-TIME.mcap here)",
            field="output",
        )
    if args.output:
        refuse_folder_name(args.output)
    output = Path(args.output) if args.output else default_output()
    refuse_folder(output)  # before connecting: no router fixes this
    return RecorderOptions(
        output=output,
        keys=tuple(args.keys) if args.keys else topic_paths(),
        rotation=rotation,
        flush_every=args.flush_every,
        foxglove=not args.no_foxglove,
        planned_prefix=args.planned_prefix,
        executed_prefix=args.executed_prefix,
        commanded_prefix=args.commanded_prefix,
        overwrite=args.overwrite,
    )


def _check_flush_every(seconds: float) -> None:
    """Refuse a ``--flush-every`` outside (0, :data:`MAX_FLUSH_EVERY`] [s], by name.

    The options' own check names their field (``flush_every``), not the option.
    """
    if not 0.0 < seconds <= MAX_FLUSH_EVERY:
        raise InvalidInputError(
            f"--flush-every must be in (0, {MAX_FLUSH_EVERY:g}] s, got {seconds:g}",
            field="flush_every",
        )


def refuse_folder_name(output: str) -> None:
    """Refuse ``-o DIR/`` where no folder ``DIR`` exists.

    ``Path`` drops the trailing slash: ``-o newdir/`` recorded into a file
    named ``newdir``. (An existing folder is refused by ``refuse_folder``.)

    Raises:
        RecordingError: naming the path and how to give a file in it.
    """
    if output.endswith("/") and not Path(output).is_dir():
        folder = output.rstrip("/") or "/"
        raise RecordingError(
            f"{output} ends with /, as a folder's name, and there is no folder "
            f"{folder}: create it and name the recording's file, e.g. "
            f"{Path(folder) / 'session.mcap'}",
            path=output,
        )
