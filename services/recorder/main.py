"""``python -m services.recorder``: the recorder process.

Usage: ``python -m services.recorder [-o FILE.mcap] [--keys KEY ...]
[--rotate-size SIZE] [--rotate-duration S] [--keep-parts N] [--config FILE]
[--connect ENDPOINT] [--namespace NS] [--wait S]``. It connects to the
router, records until SIGTERM, SIGINT or SIGHUP, then closes its file with
its summary and exits 0 (at once, also while it still waits for the router).
Once recording it prints one line, ``recording <keys> to <file>``, on
stdout (what ``services.recorder.control`` waits for). It
exits 1 with the error on stderr if the configuration is wrong, no router
answers, the file cannot be created (or exists, without ``--overwrite``),
or the file system refuses a write (disk full): then at once, since what
it receives could no longer be kept. The error also goes to stdout as one
line, ``failed: <error>``, for the program that started it.
"""

from __future__ import annotations

import argparse
import contextlib
import logging
import sys
from collections.abc import Sequence

from services.recorder.arguments import (
    add_recorder_arguments,
    check_usage,
    options_from_args,
)
from services.recorder.service import NAME, Recorder
from shared.bus import Bus
from shared.bus.options import add_connect_options, add_router_wait_option
from shared.bus.process import add_common_arguments, freeze_set_up, start_process
from shared.bus.process_config import process_config
from shared.command_line import ArgumentParser
from shared.errors import ArmplanError, ServiceUnavailableError

log = logging.getLogger("armplan.recorder")
#: The line the recorder prints on stdout once it records.
READY_PREFIX = "recording "
#: The start of the line it prints on stdout when it exits with an error.
FAILED_PREFIX = "failed: "


def main(argv: Sequence[str] | None = None) -> int:
    """Record until asked to stop; returns the exit code."""
    parser = _parser()
    args = parser.parse_args(argv)
    check_usage(parser, args)
    stop = start_process(args.log_level)
    try:
        config = process_config(args, NAME)
        options = options_from_args(args)
        with (
            Bus.connect(config, wait=args.wait, stop=stop) as bus,
            Recorder(bus, options) as rec,
        ):
            keys = " ".join(rec.keys)
            sys.stdout.write(f"{READY_PREFIX}{keys} to {rec.sink.paths[0]}\n")
            sys.stdout.flush()
            freeze_set_up()
            rec.wait(stop)
    except ArmplanError as error:
        if stop.is_set() and isinstance(error, ServiceUnavailableError):
            log.info("%s: asked to stop before a router answered", NAME)
            return 0
        log.error("%s: %s", NAME, error.message)
        _tell_parent(f"{FAILED_PREFIX}{error.message}")
        return 1
    return 0


def _tell_parent(line: str) -> None:
    """One line on stdout, for the program that started the recorder (if any)."""
    with contextlib.suppress(OSError):  # nobody reads it any more
        sys.stdout.write(line.replace("\n", " ") + "\n")
        sys.stdout.flush()


def _parser() -> argparse.ArgumentParser:
    parser = ArgumentParser(
        prog="python -m services.recorder",
        description="The armplan recorder: Zenoh key expressions to MCAP.",
    )
    add_common_arguments(parser)
    add_recorder_arguments(parser)
    add_connect_options(parser)
    add_router_wait_option(parser)
    return parser
