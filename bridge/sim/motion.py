"""The simulated NAO's ALMotion: the NAOqi API the bridge calls, served over libqi.

Methods and arguments are NAOqi's (radians, seconds, fractions 0..1):
``angleInterpolation``, ``angleInterpolationWithSpeed``, ``setAngles``,
``getAngles``, ``stiffnessInterpolation``, ``setStiffnesses``,
``getStiffnesses``, ``wakeUp``, ``rest``, ``robotIsWakeUp``, ``getLimits``,
``areResourcesAvailable``, ``killTasksUsingResources``, ``killAll``. A
refused command raises (the caller gets libqi's ``RuntimeError`` with the
reason) and is logged; nothing is clamped.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from bridge.sim.commands import per_joint
from bridge.sim.errors import SimCommandError
from bridge.sim.joints import expand_names
from bridge.sim.log import SimLog
from bridge.sim.robot import SimRobot
from bridge.sim.task import GRACE, MotionTask
from shared.libqi import qi

#: Shortest move ``setAngles`` and ``angleInterpolationWithSpeed`` make [s].
MIN_MOVE_TIME = 0.02


def _accept(
    log: SimLog,
    t: float,
    method: str,
    arguments: dict[str, Any],
    start: Callable[[], MotionTask],
) -> MotionTask:
    """Run ``start`` for a call received at ``t`` [s, sim clock], then log it.

    The call is logged (with its ``arguments``, at its task's start, or at
    ``t`` if refused) after its command is applied, not before: a call of
    44 000 keys took 0.3 s to write, and its keys, counted from ``t``, ran
    on while the joints still held the last command, which they then
    caught up at their speed limit. Then the accepted motion, or the
    refusal (re-raised), is logged.
    """
    try:
        task = start()
    except Exception as error:  # logged whatever went wrong, refused if refused
        log.write("call", at=t, method=method, **arguments)
        if isinstance(error, SimCommandError):
            log.write("refused", method=method, reason=str(error))
        raise
    log.write("call", at=task.start_time, method=method, **arguments)
    duration = round(task.end_time - task.start_time, 6)
    log.write("motion", method=method, joints=task.joints, duration=duration)
    return task


def _answer(task: MotionTask, duration: float) -> qi.Future:
    """The answer of a blocking call, set when ``task`` ends.

    Served as the call's result, it blocks the caller as a NAO's blocking
    call does, but no thread: a thread waiting for the task held one of
    libqi's worker threads, and a call from another client (a stop, a
    reading) waited behind a few blocking calls until libqi added one
    (0.5 s). It returns None, or fails as a raised ``SimCommandError`` did
    (libqi's ``RuntimeError``, "SimCommandError: <reason>"): interrupted
    (:meth:`MotionTask.interrupt`), or not ended within ``duration`` [s]
    plus :data:`~bridge.sim.task.GRACE`, then told by a libqi timer.
    """
    promise = qi.Promise()
    overdue = qi.runAsync(task.expire, delay=round((duration + GRACE) * 1e6))

    def reply(reason: str | None) -> None:
        overdue.cancel()
        if reason is None:
            promise.setValue(None)
        else:
            promise.setError(f"{SimCommandError.__name__}: {reason}")

    task.answer(reply)
    return promise.future()


def _fraction(value: Any, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SimCommandError(f"{what} must be a number, got {value!r}")
    if not 0.0 < value <= 1.0:
        raise SimCommandError(f"{what} must be in (0, 1], got {value}")
    return float(value)


def _speed_move(
    robot: SimRobot, t: float, names: Any, targets: Any, fraction: Any, together: bool
) -> MotionTask:
    """Move to ``targets`` [rad] at ``fraction`` of the speed limits.

    Each joint goes straight to its target at that share of its limit; with
    ``together`` all arrive with the slowest one.
    """
    share = _fraction(fraction, "fractionMaxSpeed")
    joints = expand_names(names)
    current = robot.angles(joints, False)
    wanted = _one_each(per_joint(targets, len(joints), "angles"), joints, together)
    durations = [
        max(MIN_MOVE_TIME, abs(w - c) / (share * robot.joints[j].spec.velocity))
        for j, w, c in zip(joints, wanted, current, strict=True)
    ]
    if together:
        durations = [max(durations)] * len(joints)
    method = "angleInterpolationWithSpeed" if together else "setAngles"
    keys = [[w] for w in wanted]
    return robot.move(method, t, joints, keys, [[d] for d in durations])


def _one_each(
    rows: list[list[float]], joints: list[str], together: bool
) -> list[float]:
    """The one target angle [rad] of each joint; refuse a joint given several.

    NAOqi takes one target per joint here. The last of several used to be
    taken, the others never checked against the joint's range (5.0 rad
    passed before 1.0), so a mistake made on the sim failed on a robot.
    """
    method = "angleInterpolationWithSpeed" if together else "setAngles"
    for joint, row in zip(joints, rows, strict=True):
        if len(row) != 1:
            raise SimCommandError(
                f"{joint} has {len(row)} target angles; {method} takes one per joint"
            )
    return [row[0] for row in rows]


@qi.multiThreaded()
class SimulatedMotion:
    """ALMotion of the simulated NAO (served as the ``ALMotion`` service)."""

    def __init__(self, robot: SimRobot, log: SimLog, awake: bool = True) -> None:
        """ALMotion of ``robot``; ``awake``: what ``robotIsWakeUp`` says first."""
        self._robot = robot
        self._log = log
        self._awake = awake

    def angleInterpolation(
        self, names: Any, angleLists: Any, timeLists: Any, isAbsolute: bool
    ) -> qi.Future:
        """Move joints through timed keys [rad, s]; answered once done.

        The keys count from when the command takes effect, once they are
        read and checked (a long call's take tenths of a second).
        """
        task = _accept(
            self._log,
            self._robot.now(),
            "angleInterpolation",
            {
                "names": names,
                "angles": angleLists,
                "times": timeLists,
                "absolute": bool(isAbsolute),
            },
            lambda: self._robot.move(
                "angleInterpolation",
                None,
                names,
                angleLists,
                timeLists,
                bool(isAbsolute),
            ),
        )
        return _answer(task, task.end_time - task.start_time)

    def angleInterpolationWithSpeed(
        self, names: Any, targetAngles: Any, maxSpeedFraction: float
    ) -> qi.Future:
        """Move joints to targets [rad] together; answered once done.

        The joint that needs longest moves at ``maxSpeedFraction`` of its
        speed limit; the others arrive with it.
        """
        t = self._robot.now()
        task = _accept(
            self._log,
            t,
            "angleInterpolationWithSpeed",
            {"names": names, "angles": targetAngles, "fraction": maxSpeedFraction},
            lambda: _speed_move(
                self._robot, t, names, targetAngles, maxSpeedFraction, True
            ),
        )
        return _answer(task, task.end_time - t)

    def setAngles(self, names: Any, angles: Any, fractionMaxSpeed: float) -> None:
        """Start moving joints to ``angles`` [rad]; returns at once.

        Each joint moves at ``fractionMaxSpeed`` of its speed limit.
        """
        t = self._robot.now()
        _accept(
            self._log,
            t,
            "setAngles",
            {"names": names, "angles": angles, "fraction": fractionMaxSpeed},
            lambda: _speed_move(self._robot, t, names, angles, fractionMaxSpeed, False),
        )

    def getAngles(self, names: Any, useSensors: bool) -> list[float]:
        """Angles now [rad]: measured if ``useSensors``, else commanded."""
        return self._robot.angles(names, bool(useSensors))

    def stiffnessInterpolation(
        self, names: Any, stiffnessLists: Any, timeLists: Any
    ) -> qi.Future:
        """Ramp stiffnesses (0..1) through timed keys [s]; answered once done."""
        t = self._robot.now()
        task = _accept(
            self._log,
            t,
            "stiffnessInterpolation",
            {"names": names, "stiffness": stiffnessLists, "times": timeLists},
            lambda: self._robot.stiffen(
                "stiffnessInterpolation", t, names, stiffnessLists, timeLists
            ),
        )
        return _answer(task, task.end_time - t)

    def setStiffnesses(self, names: Any, stiffnesses: Any) -> None:
        """Set stiffnesses (0..1) within one control cycle."""
        t = self._robot.now()
        _accept(
            self._log,
            t,
            "setStiffnesses",
            {"names": names, "stiffness": stiffnesses},
            lambda: self._robot.stiffen(
                "setStiffnesses", t, names, stiffnesses, MIN_MOVE_TIME
            ),
        )

    def getStiffnesses(self, names: Any) -> list[float]:
        """Stiffnesses now (0..1)."""
        return self._robot.stiffnesses(names)

    def wakeUp(self) -> qi.Future:
        """Stiffen every joint (the simulated NAO has no posture to stand in).

        Answered once stiff; awake from then (not if the ramp failed).
        """

        def awake(_: None) -> None:
            self._awake = True

        return self.stiffnessInterpolation("Body", 1.0, 0.1).andThen(awake)

    def rest(self) -> qi.Future:
        """Stop every command and release every stiffness; answered once limp."""
        self._awake = False
        self.killAll()
        return self.stiffnessInterpolation("Body", 0.0, 0.1)

    def robotIsWakeUp(self) -> bool:
        """True after ``wakeUp`` (and at start), False after ``rest``.

        As on a NAO, it is the robot's state, not its joints' stiffness: an
        arm made limp by ``setStiffnesses`` leaves the robot awake.
        """
        return self._awake

    def getLimits(self, name: str) -> list[list[float]]:
        """[[lower, upper, speed limit, torque limit]] per joint [rad, rad/s, N m]."""
        joints = expand_names(name)
        specs = [self._robot.joints[j].spec for j in joints]
        return [[s.lower, s.upper, s.velocity, s.effort] for s in specs]

    def areResourcesAvailable(self, resourceNames: Any) -> bool:
        """True if no running blocking call's task uses these joints or chains.

        A blocking call (``angleInterpolation``, ``angleInterpolationWithSpeed``,
        ``stiffnessInterpolation``) holds its joints until it ends, dwells
        included; ``setAngles`` holds none (NAOqi 2.x's semantics).
        """
        return self._robot.resources_available(expand_names(resourceNames))

    def killTasksUsingResources(self, resourceNames: Any) -> None:
        """Stop the commands using any of these joints or chains; they hold.

        Logged once it has acted, not on arrival: a stop that waits while a
        long call is being applied ends that call, and its entry then
        follows the call's, as its effect does.
        """
        joints = expand_names(resourceNames)
        self._robot.stop_using(joints, "killTasksUsingResources")
        self._log.write("call", method="killTasksUsingResources", joints=joints)

    def killAll(self) -> None:
        """Stop every command; joints hold where they are (logged once done)."""
        self._robot.stop_all("killAll")
        self._log.write("call", method="killAll")
