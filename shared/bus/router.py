"""The Zenoh router process: ``python -m shared.bus.router``.

Usage: ``python -m shared.bus.router [--config FILE] [--listen ENDPOINT] [--id HEX]
[--check-certificate-every SECONDS]``.
A Python Zenoh session in ``mode: "router"`` listening on the configured
endpoints only (default ``tcp/127.0.0.1:7447``), multicast scouting off. It
runs until SIGTERM or SIGINT; it exits 1 with the reason if it cannot listen
or its TLS certificate has expired (and warns when it expires within 30 days).
While it runs it checks the certificate's dates again, hourly and at its end:
a warning about once a day in the last 30 days, an ERROR once it has expired
(``certificate_watch.py``).
Zenoh's own log (stdout) shows its warnings and, for a secured router, every
handshake accepted or refused, e.g. a wrong password (``zenoh_log.py``).
"""

from __future__ import annotations

import argparse
import logging
import re
from collections.abc import Sequence
from datetime import UTC, datetime

from shared.bus.certificate_watch import CHECK_EVERY, watch_certificate
from shared.bus.config_file import load_config
from shared.bus.process import (
    add_common_arguments,
    freeze_set_up,
    start_process,
    wait_for,
)
from shared.bus.secured import secured_settings
from shared.bus.session import open_router
from shared.bus.zenoh_log import start_zenoh_log
from shared.command_line import ArgumentParser
from shared.errors import ArmplanError

log = logging.getLogger("armplan.bus")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the router until asked to stop; returns the exit code."""
    args = _parser().parse_args(argv)
    stop = start_process(args.log_level)
    try:
        config = load_config(args.config, tuple(args.listen or ()))
        start_zenoh_log(secured=bool(secured_settings(config)))
        watch = watch_certificate(config, datetime.now(UTC))
        with open_router(config, args.id):
            log.info("router listening on %s", ", ".join(config.endpoints))
            if watch is None:
                wait_for(stop)
            else:
                freeze_set_up()
                watch.wait(stop, args.check_certificate_every)
    except ArmplanError as error:
        log.error("router: %s", error.message)
        return 1
    return 0


def _parser() -> argparse.ArgumentParser:
    parser = ArgumentParser(
        prog="python -m shared.bus.router",
        description="armplan's Zenoh router.",
    )
    add_common_arguments(parser)
    parser.add_argument(
        "--listen",
        action="append",
        metavar="ENDPOINT",
        help="endpoint to listen on, e.g. tcp/127.0.0.1:7447 (default: the config's)",
    )
    parser.add_argument(
        "--id",
        type=_zid,
        help="the router's Zenoh id, 1-32 hex digits, no leading 0 (default: "
        "random); lets "
        "the process that started it tell it from another router on the port",
    )
    parser.add_argument(
        "--check-certificate-every",
        type=_seconds,
        default=CHECK_EVERY,
        metavar="SECONDS",
        help="how often a TLS router checks its certificate's dates while it "
        f"runs (default {CHECK_EVERY:.0f}; it checks at the end date too)",
    )
    return parser


def _seconds(text: str) -> float:
    """``text`` as a finite number of seconds above 0."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds > 0")
    return value


def _zid(text: str) -> str:
    """``text`` if it is a Zenoh id: 1-32 lowercase hex digits, no leading 0."""
    if not re.fullmatch(r"[1-9a-f][0-9a-f]{0,31}", text):
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a Zenoh id (1-32 lowercase hex digits, no leading 0)"
        )
    return text


if __name__ == "__main__":
    raise SystemExit(main())
