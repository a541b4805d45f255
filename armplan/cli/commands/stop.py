"""``armplan stop``: stop the arm the bridge is moving, now (``<ns>/bridge/stop``).

Usage::

    armplan stop [--connect ENDPOINT] [--config FILE] [--namespace NS]
                 [--timeout S] [--reason TEXT] [--json]

It asks the running bridge (``python -m bridge.serve``, ``armplan up
--with-sim``) on ``<ns>/bridge/stop``: the movement playing is stopped at
once (``ALMotion.killTasksUsingResources`` on the arm's joints), its
execute caller gets the robot's "stopped" error, ``bridge/outcome`` says
"stopped", and a follower (``--follow``) drops the trajectories waiting.
The bridge orders the stop as the query arrives, whatever the caller's
time left; the reply waits for the stopped execution to end and says
whether the arm is known still. This prints what was stopped (``--json``:
the :class:`~shared.messages.StopReply`) and the bridge's note, if any.
The stop is sent even if the bridge's liveliness token is not seen (a
bridge whose token was lost may still serve it); the token's absence is
reported only if no answer comes.
Exit code 0 once the arm is known still; 1 with no bridge answering (or no
router), no answer within ``--timeout`` (the stop was sent all the same),
or an arm not known still when the bridge answered: look at the robot.
A reason with control characters has them removed, and one longer than
200 characters is cut, with a warning: the stop is never refused for it.
"""

from __future__ import annotations

import argparse
import sys

from armplan.cli.output import print_json, say
from armplan.cli.parsing import add_json
from armplan.cli.remote import check_timeout
from shared.bus import Bus
from shared.bus.options import add_config_option, add_connect_options, bus_config
from shared.bus.robot_routes import STOP
from shared.errors import RequestTimeoutError
from shared.messages import StopReply, StopRequest
from shared.messages.stop import NO_TIME_TO_READ, clean_reason

ORDER = 82
HELP = "stop the arm the bridge is moving, now (<ns>/bridge/stop)"
#: How long ``armplan stop`` waits for the bridge's answer by default [s]:
#: the bridge waits up to about 4.3 s for the stopped execution to end and
#: the arm to settle.
DEFAULT_TIMEOUT = 10.0


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``stop``."""
    parser = commands.add_parser("stop", help=HELP, description=HELP)
    add_config_option(parser)
    add_connect_options(
        parser, "the key namespace of the bridge (default: the config's, armplan)"
    )
    parser.add_argument(
        "--timeout",
        type=float,
        default=DEFAULT_TIMEOUT,
        metavar="S",
        help=f"longest wait for the bridge's answer [s] (default {DEFAULT_TIMEOUT:g})",
    )
    parser.add_argument(
        "--reason",
        metavar="TEXT",
        help="why, logged by the bridge and carried in the execution's outcome",
    )
    add_json(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Ask the bridge to stop; print what it stopped."""
    timeout = float(args.timeout)
    check_timeout(timeout)
    reason = None
    if args.reason is not None:
        reason, problems = clean_reason(args.reason)
        if reason is None:
            problems.append("the reason is empty: none sent")
        for problem in problems:
            sys.stderr.write(f"armplan: warning: {problem}\n")
    request = StopRequest(reason=reason)
    config = bus_config(args)
    url = f"{config.namespace}/{STOP.path}"
    with Bus.connect(config) as bus:
        try:
            # sent even if the bridge's token is not seen: an e-stop
            reply = bus.call(STOP, request, timeout=timeout, unseen=True)
        except RequestTimeoutError:
            sys.stderr.write(
                f"armplan: the stop was sent to {url}; a bridge that got it "
                "stops the arm however short the wait, but no answer came: "
                "look at the robot\n"
            )
            raise
    if args.json:
        print_json(reply.model_dump(mode="json"))
    else:
        say(describe(reply))
    if not reply.still:
        sys.stderr.write(
            f"armplan: error: the bridge ({url}) answered before the arm was "
            f"known still{_too_short(reply, timeout)}: look at the robot\n"
        )
        return 1
    return 0


def _too_short(reply: StopReply, timeout: float) -> str:
    """What to change when ``--timeout`` [s] left the bridge no time to read the arm.

    ``""`` otherwise: then the note says why the arm is not known still.
    """
    if NO_TIME_TO_READ not in (reply.note or ""):
        return ""
    return (
        f" (--timeout {timeout:g} s left it no time to read the arm; give it "
        f"more, e.g. the default {DEFAULT_TIMEOUT:g} s)"
    )


def describe(reply: StopReply) -> str:
    """One line: what the stop stopped, what it dropped, whether the arm is still."""
    if reply.stopped and reply.ended is False:
        what = "movement" if reply.playing else "execution before its movement"
        line = f"ordered the {reply.arm} arm's {what} stopped; not yet confirmed"
    elif reply.stopped and reply.phase is not None:
        what = "trajectory" if reply.phase == "trajectory" else "approach"
        where = (
            f" at t = {reply.played:.2f} s of {reply.phase_duration:.2f} s"
            if reply.played is not None and reply.phase_duration is not None
            else " as it started"
        )
        line = f"stopped the {reply.arm} arm's {what}{where}"
    elif reply.stopped:
        line = f"stopped the {reply.arm} arm's execution before its trajectory was sent"
    elif reply.arm is not None:
        line = f"the {reply.arm} arm's execution ended before the stop took effect"
    else:
        line = "nothing was playing"
    if reply.dropped:
        line += f"; dropped {reply.dropped} waiting trajectories"
    line += "; the arm is still" if reply.still else "; the arm is NOT known still"
    line += f" (answered in {reply.waited:.2f} s)"
    if reply.note:
        line += f"\nnote: {reply.note}"
    return line
