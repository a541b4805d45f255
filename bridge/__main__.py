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
anything is read).

It runs until stdin ends, or until SIGTERM, SIGINT (Ctrl-C) or SIGHUP. Told
to stop, it stops as ``python -m bridge.serve`` does (:mod:`bridge.stopping`):
it sends no new command, and the request being answered ends watched: one in
its approach is answered ``service_unavailable`` ("the bridge is stopping;
...") once the approach ends, its trajectory not sent; a trajectory playing
is watched to its end and answered, for up to 30 s, past which its arm is
stopped and the request answered ``service_unavailable`` ("... it stopped
the arm at about t = ..."). Its line written, it reads no more lines and
exits 0. (A signal used to end it at once, with a traceback and no reply,
the arm left playing unwatched.) Either way it exits once a robot it gave
up on is no longer being stopped (``NaoqiClient.shut``, at most 30 s).
Importing ``bridge`` first loads libqi before pinocchio (see
shared/libqi.py).
"""

from __future__ import annotations

import json
import logging
import os
import sys
import threading
import time
from collections.abc import Sequence
from typing import TextIO

from bridge.address import ROBOT_ENV, robot_url
from bridge.awake import ALLOW_NOT_AWAKE
from bridge.frames import check_rate
from bridge.naoqi_client import NaoqiClient
from bridge.robot_bridge import RobotBridge
from bridge.serving import Slot
from bridge.stopping import STOP_LIMIT, stop_serving
from shared.bus.process import POLL, start_process
from shared.command_line import ArgumentParser
from shared.errors import ArmplanError, InternalServiceError, InvalidInputError
from shared.messages import ExecuteRequest, parse
from shared.text.plain import plain_text

log = logging.getLogger("armplan.bridge")
#: Longest wait, once a stop finds no request served, for the line being
#: answered [s]: its request sends nothing (the bridge is stopping), but a
#: long trajectory's frames take a while to check.
LINE_WAIT = 30.0


def answer(bridge: RobotBridge, line: str, slot: Slot | None = None) -> str:
    """The reply line for one request line.

    ``slot`` is taken while the request is served, and says what it has
    sent (for a stop, :func:`~bridge.stopping.stop_serving`). An unexpected
    failure is logged with its traceback and answered as ``internal_error``;
    the bridge serves the next line.
    """
    serving = Slot() if slot is None else slot
    try:
        request = parse(ExecuteRequest, line)
        frames = bridge.frames(request.trajectory, request.rate)
        serving.take(frames.duration, wait=True)
        try:
            reply = bridge.handle(
                request,
                on_play=lambda _frames: serving.sending(),
                on_approach=serving.approaching,
                on_arrival=serving.arrived,
                frames=frames,
            )
        finally:
            serving.give_back()
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


def serve(
    bridge: RobotBridge,
    source: TextIO,
    sink: TextIO,
    stop: threading.Event | None = None,
    limit: float = STOP_LIMIT,
) -> None:
    """Answer every non-empty line of ``source`` on ``sink``, until its end or ``stop``.

    The lines are read and answered on a thread; this one waits for their
    end or for ``stop``. Once ``stop`` is set, no new command is sent
    (:func:`~bridge.stopping.stop_serving`): the request being answered
    ends watched (a movement playing, for at most ``limit`` [s], then its
    arm is stopped), its line is written, and no further line is answered.

    Raises:
        Whatever reading ``source`` or writing ``sink`` raised.
    """
    slot = Slot()
    gate = threading.Lock()  # held while a line is answered and written
    closed = threading.Event()  # set under the gate: answer no more lines
    ended = threading.Event()
    failed: list[BaseException] = []

    def answer_lines() -> None:
        try:
            for line in source:
                if not line.strip():
                    continue
                with gate:
                    if closed.is_set():
                        return
                    sink.write(answer(bridge, line, slot) + "\n")
                    sink.flush()
        except BaseException as error:  # raised again by the waiting thread
            failed.append(error)
        finally:
            ended.set()

    threading.Thread(target=answer_lines, name="bridge-lines", daemon=True).start()
    while not ended.wait(POLL):
        if stop is not None and stop.is_set():
            _stop(bridge, slot, gate, closed, limit)
            break
    if failed:
        raise failed[0]


def _stop(
    bridge: RobotBridge,
    slot: Slot,
    gate: threading.Lock,
    closed: threading.Event,
    limit: float,
) -> None:
    """Stop serving: the request being answered ends watched, its line written.

    Once no request is served (:func:`~bridge.stopping.stop_serving`), a
    line still being answered sends nothing: its reply is waited for, at
    most :data:`LINE_WAIT`.
    """
    log.info("stopping: no new command; the request being answered ends watched")
    free = stop_serving(bridge, slot, limit)
    if gate.acquire(timeout=LINE_WAIT if free else 0.0):
        closed.set()
        gate.release()
    else:
        log.warning("python -m bridge: exiting with a request unanswered")


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; 0 at the end of stdin or after a stop signal, 1 on a bad address."""
    parser = ArgumentParser(
        prog="python -m bridge",
        description=plain_text(__doc__),
    )
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
    stop = start_process()  # SIGTERM, Ctrl-C, SIGHUP: stop as bridge.serve does
    replies = replies_stream()
    try:
        with NaoqiClient(url) as client:  # at its end, waits for the stops
            bridge = RobotBridge(
                client, rate=args.rate, require_awake=not args.allow_not_awake
            )
            serve(bridge, sys.stdin, replies, stop)
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
