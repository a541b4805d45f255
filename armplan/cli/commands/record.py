"""``armplan record``: record Zenoh key expressions to MCAP until stopped.

The recorder runs in this process (``services.recorder.Recorder``); Ctrl-C,
SIGTERM, SIGHUP (its terminal closed) or ``--duration`` stop it, and the
file is closed with its summary (exit code 0).
A write the file system refuses (disk full) stops it at once with the
reason and exit code 1.
See ``docs/recording.md`` for the channels and how to open them in Foxglove.
"""

from __future__ import annotations

import argparse
import functools
import math
import sys

from armplan.cli.output import say
from services.recorder.arguments import (
    add_recorder_arguments,
    check_usage,
    options_from_args,
)
from services.recorder.service import NAME, Recorder
from services.recorder.sink import STOP_TIMEOUT, RecordingSink
from shared.bus import Bus
from shared.bus.options import add_config_option, add_connect_options
from shared.bus.process_config import process_config
from shared.errors import InvalidInputError
from shared.stop_signals import stop_on_signals
from shared.text.counted import counted

ORDER = 90
HELP = "record Zenoh key expressions to an MCAP file until Ctrl-C"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``record``."""
    parser = commands.add_parser("record", help=HELP, description=HELP)
    add_recorder_arguments(parser)
    add_config_option(parser)
    add_connect_options(parser)
    parser.add_argument(
        "--duration",
        type=float,
        metavar="S",
        help="stop after this many seconds (default: at Ctrl-C or SIGTERM)",
    )
    parser.set_defaults(run=functools.partial(run, parser=parser))


def run(args: argparse.Namespace, parser: argparse.ArgumentParser | None = None) -> int:
    """Record until stopped; print the files and what they hold.

    ``parser`` reports a usage error (``--keep-parts`` without rotation).
    """
    if parser is not None:
        check_usage(parser, args)
    if args.duration is not None and not (
        math.isfinite(args.duration) and args.duration > 0
    ):
        raise InvalidInputError(
            f"--duration must be a positive number of seconds, got {args.duration} "
            "(leave it out to record until Ctrl-C)",
            field="duration",
        )
    config = process_config(args, NAME)
    options = options_from_args(args)
    stop = stop_on_signals()
    with Bus.connect(config) as bus, Recorder(bus, options) as recorder:
        say(
            f"armplan record: recording {' '.join(recorder.keys)} to "
            f"{recorder.sink.paths[0]}; Ctrl-C stops"
        )
        recorder.wait(stop, args.duration)
        _say_stopping(recorder.sink)
    sink = recorder.sink
    files = sink.files_note()
    extra = f" (and {sink.derived} derived for Foxglove)" if sink.derived else ""
    note = sink.behind_note()
    say(f"armplan record: {counted(sink.written, 'message')}{extra} in {files}{note}")
    return 0


def _say_stopping(sink: RecordingSink) -> None:
    """Say on stderr that a backlog is being written out, if there is one.

    Large trajectories each make thousands of Foxglove messages: six of
    20 000 samples took 6.5 s to write out after Ctrl-C, with no word, and a
    second Ctrl-C (ignored: the file is closed whole) did nothing visible.
    """
    if sink.broken.is_set() or not (queued := sink.queued):
        return
    sys.stderr.write(
        f"armplan record: stopping; writing out {counted(queued, 'message')} "
        f"still queued (at most {STOP_TIMEOUT:.0f} s), then closing the file "
        "whole\n"
    )
    sys.stderr.flush()
