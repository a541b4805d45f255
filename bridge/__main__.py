"""``python -m bridge [--robot URL]``: the robot bridge over standard input/output.

Reads one :class:`~shared.messages.ExecuteRequest` per line (JSON) on stdin,
plays it on the robot, and writes one line per request on stdout: the
:class:`~shared.messages.ExecuteReply` as JSON, or ``{"error": {"kind",
"message", "evidence"}, "at": T}`` with the monotonic time ``T`` [s] when
the error was raised. The same bridge serves every line, so after a robot
went away the next request connects again. The Zenoh bridge process wraps
the same :class:`~bridge.robot_bridge.RobotBridge`; this is its stand-alone
form, for a real NAO at ``tcp://IP:9559`` or the simulated one: ``--robot``,
else ``$ARMPLAN_ROBOT``, else the simulated NAO at ``tcp://127.0.0.1:9559``
(:mod:`bridge.address`; an address not ``tcp://HOST:PORT`` exits 1 before
anything is read). At the end
of stdin it exits once a robot it gave up on is no longer being stopped
(``NaoqiClient.shut``, at most 30 s). Importing
``bridge`` first loads libqi before pinocchio (see shared/libqi.py).
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import sys
import time
from collections.abc import Sequence
from typing import TextIO

from bridge.address import ROBOT_ENV, robot_url
from bridge.awake import ALLOW_NOT_AWAKE
from bridge.frames import check_rate
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from shared.errors import ArmplanError, InternalServiceError, InvalidInputError
from shared.messages import ExecuteRequest, parse

log = logging.getLogger("armplan.bridge")


def answer(bridge: RobotBridge, line: str) -> str:
    """The reply line for one request line.

    An unexpected failure is logged with its traceback and answered as
    ``internal_error``; the bridge serves the next line.
    """
    try:
        reply = bridge.handle(parse(ExecuteRequest, line))
    except ArmplanError as error:
        return _error_line(error)
    except Exception as error:  # the next request must still be served
        log.exception("execute failed unexpectedly")
        return _error_line(
            InternalServiceError(
                "bridge",
                key="stdin",
                error_type=type(error).__name__,
                detail=str(error).splitlines()[0] if str(error) else "",
            )
        )
    return reply.to_json()


def _error_line(error: ArmplanError) -> str:
    return json.dumps({"error": error.to_wire(), "at": time.monotonic()})


def serve(bridge: RobotBridge, source: TextIO, sink: TextIO) -> None:
    """Answer every non-empty line of ``source`` on ``sink``, until its end."""
    for line in source:
        if line.strip():
            sink.write(answer(bridge, line) + "\n")
            sink.flush()


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point."""
    parser = argparse.ArgumentParser(prog="python -m bridge", description=__doc__)
    parser.add_argument(
        "--robot",
        metavar="URL",
        help=f"the robot's NAOqi address, e.g. tcp://IP:9559 for a real NAO "
        f"(default: ${ROBOT_ENV}, else the simulated NAO on tcp://127.0.0.1:9559)",
    )
    parser.add_argument("--rate", type=float, default=25.0, help="frame rate [Hz]")
    parser.add_argument(
        ALLOW_NOT_AWAKE,
        action="store_true",
        help="play even on a robot that is not awake (ALMotion.robotIsWakeUp() "
        "false: resting, crouched or fallen); only for a robot held up by other "
        "means",
    )
    args = parser.parse_args(argv)
    try:
        check_rate(args.rate)
    except InvalidInputError as error:
        parser.error(error.message)
    try:
        url = robot_url(args.robot)
    except InvalidInputError as error:  # --robot or $ARMPLAN_ROBOT
        parser.exit(1, f"{parser.prog}: error: {error.message}\n")
    replies = replies_stream()
    try:
        with NaoqiClient(url) as client:  # at its end, waits for the stops
            bridge = RobotBridge(
                client, rate=args.rate, require_awake=not args.allow_not_awake
            )
            serve(bridge, sys.stdin, replies)
    finally:
        replies.flush()
    return 0


def replies_stream() -> TextIO:
    """The process's stdout, for the replies alone; anything else goes to stderr.

    libqi's native log lines (``[W] ... qi.path.sdklayout: ...``) are written
    to file descriptor 1 by C++, past Python: the reply stream keeps a copy of
    the original stdout, and descriptor 1 becomes stderr's, so a reader of
    stdout gets JSON lines only.
    """
    sys.stdout.flush()
    replies = os.fdopen(os.dup(1), "w", encoding="utf-8", buffering=1)
    os.dup2(2, 1)
    return replies


if __name__ == "__main__":
    raise SystemExit(main())
