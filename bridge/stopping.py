"""A bridge told to stop: no new command; the request being served ends watched.

Both bridge processes stop this way on SIGTERM, Ctrl-C or SIGHUP: the one on
Zenoh (``python -m bridge.serve``, ``BridgeService.stop``) and the one on
stdin/stdout (``python -m bridge``). A request still in its approach is
refused once the approach ends, its trajectory not sent; a trajectory
playing is watched to its end and answered as usual (cut short, the joints
would stop dead), for at most :data:`STOP_GRACE` past its expected end and
:data:`STOP_LIMIT` in all. Past that the arm is stopped (its motion tasks
killed, ``bridge.cut``: unwatched is worse than abrupt) and the request
answered with "the bridge is stopping; it stopped the arm at about t = X s
of Y s ...", within :data:`CUT_WAIT`.
"""

from __future__ import annotations

import logging
import time

from bridge.playback import HALT_WAIT, LOST_AFTER
from bridge.robot_bridge import RobotBridge
from bridge.serving import Serving, Slot

log = logging.getLogger("armplan.bridge")
#: Longest wait, past the playing movement's end, for the request being
#: served when the bridge stops [s] (the end counted from when its call
#: reached the robot; longer than ``playback.OVERRUN``, after which the
#: bridge gives the movement up itself).
STOP_GRACE = 2.0
#: Longest wait for the request being served when the bridge stops [s];
#: a movement still playing then is stopped (``bridge.cut``).
STOP_LIMIT = 30.0
#: Longest wait for the request once its movement is ordered cut [s]: a
#: reading's wait, then the stop's (``LOST_AFTER`` + ``HALT_WAIT``).
CUT_WAIT = LOST_AFTER + HALT_WAIT


def stop_serving(robot: RobotBridge, slot: Slot, limit: float = STOP_LIMIT) -> bool:
    """Send no new command on ``robot``; wait for ``slot``'s request to end.

    Its approach may end, but its trajectory is not sent: it is answered
    with "the bridge is stopping". A trajectory already playing is watched
    to its end and answered as usual, for at most :data:`STOP_GRACE` past
    its expected end (its duration after its call reached the robot; after
    its approach, once that has started) and ``limit`` [s] in all. Past
    that, the arm is stopped (``RobotBridge.cut_short``) and the request
    answered with "the bridge is stopping; it stopped the arm ...", within
    :data:`CUT_WAIT`.

    Args:
        robot: The robot-facing bridge serving the requests.
        slot: The request it serves, and what that has sent.
        limit: Longest wait for a movement playing [s].

    Returns:
        Whether no request is being served any more.
    """
    robot.stop()
    give_up = time.monotonic() + limit

    def deadline(serving: Serving, now: float) -> float:
        return min(serving.end(now) + STOP_GRACE, give_up)

    serving = slot.wait_free(deadline)
    if serving is None:
        return True
    now = time.monotonic()
    why = (
        f"its movement would end past the {limit:g} s a stopping bridge waits for it"
        if now >= give_up
        else f"its movement did not end {STOP_GRACE:g} s past its expected end"
    )
    if serving.moving:
        log.warning("stop: %s; stopping the arm", why)
    robot.cut_short(why)
    cut_at = time.monotonic()
    serving = slot.wait_free(lambda _s, _now: cut_at + CUT_WAIT)
    if serving is None:
        return True
    if serving.moving:
        log.warning(
            "stop: a request is still being served; leaving it: the arm was "
            "ordered stopped %.1f s ago, but its request has not ended "
            "(its movement ends in about %.1f s)",
            CUT_WAIT,
            max(serving.end(time.monotonic()) - time.monotonic(), 0.0),
        )
    else:
        log.warning(
            "stop: a request is still being served; leaving it: nothing was "
            "sent for it, and nothing will be"
        )
    return False
