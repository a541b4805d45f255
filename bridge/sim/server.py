"""Serve the simulated NAO's ALMotion over libqi until told to stop."""

from __future__ import annotations

import sys
import threading
from pathlib import Path

from bridge.address import check_listen_url
from bridge.sim.cycle import PERIOD, ControlCycle, check_period
from bridge.sim.joints import joint_specs
from bridge.sim.listen import listen_failure
from bridge.sim.log import SimLog
from bridge.sim.motion import SimulatedMotion
from bridge.sim.process import READY
from bridge.sim.robot import SimRobot
from shared.libqi import qi
from shared.robot import Side
from shared.robot.postures import rest

#: NAOqi's default address on a robot; the simulated NAO's default too.
DEFAULT_LISTEN = "tcp://127.0.0.1:9559"


def rest_posture() -> dict[str, float]:
    """Both arms hanging at rest, hands closed [rad]."""
    posture: dict[str, float] = {}
    for side in Side:
        posture.update(zip(side.joint_names, rest(side).tolist(), strict=True))
    return posture


def _listen(session: qi.Session, url: str) -> None:
    """Listen at ``url``; InvalidInputError naming it and why if libqi cannot."""
    try:
        session.listenStandalone(url)
    except RuntimeError as error:
        raise listen_failure(url, error) from None


def serve(
    listen: str = DEFAULT_LISTEN,
    log_path: str | Path | None = None,
    period: float = PERIOD,
    stop: threading.Event | None = None,
    killed_returns: bool = False,
    limp_sag: float = 0.0,
    grip: float | None = None,
) -> None:
    """Run the simulated NAO until ``stop`` is set.

    Listens at ``listen`` (a NAOqi URL; port 0 picks a free port), registers
    ``ALMotion``, starts the control cycle, then prints
    ``armplan-sim ready <url>`` on stdout. Everything is closed on the way out.

    Args:
        listen: Where to listen, e.g. ``tcp://127.0.0.1:9559``.
        log_path: JSON-lines log file (see :mod:`bridge.sim.log`), or None.
        period: Control cycle [s].
        stop: Set it to stop; None: run until the process is ended.
        killed_returns: A blocking call whose command is interrupted
            (``killAll``, ``killTasksUsingResources``, a new command on its
            joints) returns normally instead of raising, as NAOqi's may.
        limp_sag: How long a joint let go falls toward its rest angle [s]
            (at ``bridge.sim.joint.SAG_SPEED``); 0: it holds still.
        grip: Each hand holds an object this wide (open fraction), closing
            no further; None: nothing in the hands.

    Raises:
        InvalidInputError: a malformed ``listen`` address or a ``period``
            outside 0.001..1 s, or a log file that cannot be written, before
            anything starts; an address it cannot listen at (in use, not
            local), naming it.
    """
    check_listen_url(listen)
    check_period(period)
    qi.logging.setLevel(qi.logging.WARNING)
    stop = stop or threading.Event()
    log = SimLog(log_path)
    # awake, as a NAO standing after wakeUp: every joint stiff
    robot = SimRobot(
        log,
        rest_posture(),
        stiffness=1.0,
        killed_returns=killed_returns,
        sag=limp_sag,
        grip=grip,
    )
    cycle = ControlCycle(robot, period)
    session = qi.Session()
    try:
        _listen(session, listen)
        session.registerService("ALMotion", SimulatedMotion(robot, log))
        url = session.endpoints()[0]
        limits = {n: [s.lower, s.upper, s.velocity] for n, s in joint_specs().items()}
        log.write("start", url=url, period=period, joints=limits, origin=log.origin)
        cycle.start()
        sys.stdout.write(f"{READY} {url}\n")
        sys.stdout.flush()
        while not stop.wait(0.2):
            pass
    finally:
        log.write("stop")
        cycle.stop()
        session.close()
        log.close()
