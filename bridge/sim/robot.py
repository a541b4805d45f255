"""The simulated NAO's body: its joints, the commands they follow, the cycle step."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from bridge.sim.commands import KeyCommand, check_range, check_speed, key_commands
from bridge.sim.errors import SimCommandError
from bridge.sim.joint import SimJoint
from bridge.sim.joints import expand_names, joint_specs
from bridge.sim.log import SimLog
from bridge.sim.task import MotionTask
from bridge.sim.timeline import KeyCurve, KeyTimeline

#: The methods whose keys a joint follows on a smooth curve (``KeyCurve``);
#: the others' (a speed fraction's single key) it follows in a straight line.
CURVED = frozenset({"angleInterpolation"})


class SimRobot:
    """All joints of the simulated NAO, guarded by one lock.

    Commands are checked whole before any joint takes them; a joint taken by
    a new command ends (interrupts) the command that drove it before.
    """

    def __init__(
        self,
        log: SimLog,
        posture: dict[str, float],
        clock: Callable[[], float] = time.monotonic,
        *,
        stiffness: float = 0.0,
        killed_returns: bool = False,
        sag: float = 0.0,
        grip: float | None = None,
    ) -> None:
        """Start every joint at ``posture`` [rad] (0 if absent), at ``stiffness``.

        ``killed_returns``: a blocking call whose command is interrupted
        returns normally instead of raising (:class:`MotionTask`). ``sag``
        [s]: how long a joint let go falls toward its ``posture`` angle
        (:class:`~bridge.sim.joint.SimJoint`); 0: it holds still. ``grip``:
        each hand holds an object this wide (open fraction 0..1), so it
        closes no further; None: nothing in the hands.
        """
        self._clock = clock
        self._log = log
        self._lock = threading.Lock()
        self.killed_returns = killed_returns
        now = clock()
        self.joints = {
            name: SimJoint(
                spec,
                posture.get(name, 0.0),
                now,
                stiffness,
                sag,
                grip if name.endswith("Hand") else None,
            )
            for name, spec in joint_specs().items()
        }
        self._owners: dict[str, MotionTask] = {}
        self._tasks: list[MotionTask] = []
        #: Joints a kill stopped while commanded: the next cycle logs them once.
        self._stopped: set[str] = set()
        self.cycles = 0

    def now(self) -> float:
        """The sim clock [s]."""
        return self._clock()

    def angles(self, names: str | list[str], use_sensors: bool) -> list[float]:
        """Measured (``use_sensors``) or commanded angles of ``names`` now [rad]."""
        joints, t = expand_names(names), self.now()
        with self._lock:
            return [
                self.joints[j].measured(t)
                if use_sensors
                else self.joints[j].setpoint(t)
                for j in joints
            ]

    def stiffnesses(self, names: str | list[str]) -> list[float]:
        """Stiffness of ``names`` now (0..1)."""
        joints, t = expand_names(names), self.now()
        with self._lock:
            return [self.joints[j].stiffness(t) for j in joints]

    def resources_available(self, names: str | list[str]) -> bool:
        """Whether no running blocking call's task holds any of ``names``.

        A task holds its joints until its last key, through any dwell
        where they hold still, as NAOqi's ``areResourcesAvailable`` says.
        """
        wanted = set(expand_names(names))
        with self._lock:
            return not any(
                task.books and not task.finished and wanted & set(task.joints)
                for task in self._tasks
            )

    def move(
        self,
        method: str,
        t: float | None,
        names: str | list[str],
        values: object,
        times: object,
        absolute: bool = True,
    ) -> MotionTask:
        """Accept a key command received at sim time ``t``, or refuse it whole.

        The joints of a method in :data:`CURVED` follow the smooth curve
        through their keys (:class:`~bridge.sim.timeline.KeyCurve`), the
        others straight lines.

        Args:
            method: The ALMotion method, for the log and errors.
            t: Reception time [s, sim clock]; ``None``: the moment the command
                takes effect, once its keys are read (44 000 keys took
                0.1 s): they count from there (the task's ``start_time``),
                as a robot's count from when its motion task starts.
            names: Joints or chains.
            values: Keys [rad] in any ALMotion form (offsets if not absolute).
            times: Key times from reception [s] in any ALMotion form.
            absolute: False: each key is an offset from the angle at reception.
        """
        commands = key_commands(expand_names(names), values, times)
        with self._lock:  # no cycle commits a joint between t and the command
            t = self.now() if t is None else t
            starts = self._prepare(commands, t)
            if not absolute:
                commands = [_offset(c, starts[c.joint]) for c in commands]
            for command in commands:
                spec = self.joints[command.joint].spec
                check_range(command, spec)
                check_speed(command, spec, starts[command.joint])
            for command in commands:
                joint = self.joints[command.joint]
                start = starts[command.joint]
                timeline = (
                    KeyCurve(
                        t,
                        start,
                        command.times,
                        command.values,
                        (joint.spec.lower, joint.spec.upper),
                    )
                    if method in CURVED
                    else KeyTimeline(t, start, command.times, command.values)
                )
                joint.command(timeline)
            return self._start_task(method, commands, t)

    def stiffen(
        self,
        method: str,
        t: float,
        names: str | list[str],
        values: object,
        times: object,
    ) -> MotionTask:
        """Ramp stiffnesses (0..1) through timed keys received at sim time ``t``."""
        commands = key_commands(expand_names(names), values, times, "stiffness")
        for c in commands:
            if any(not 0.0 <= v <= 1.0 for v in c.values):
                raise SimCommandError(
                    f"{c.joint} stiffness must be in 0..1: {c.values}"
                )
        with self._lock:
            for c in commands:
                joint = self.joints[c.joint]
                joint.commit(t)
                start = joint.stiffness(t)
                joint.command_stiffness(KeyTimeline(t, start, c.times, c.values))
            return self._start_task(method, commands, t, owns=False)

    def stop_all(self, reason: str) -> None:
        """Hold every joint where it is and interrupt every running command."""
        with self._lock:
            t = self.now()
            for joint in self.joints.values():
                joint.commit(t)
            self._log_stopped([j for j in self.joints.values() if j.moving], t, reason)
            for joint in self.joints.values():
                joint.command(None)
            for task in self._tasks:
                self._interrupt(task, reason, t)
            self._tasks, self._owners = [], {}

    def stop_using(self, names: list[str], reason: str) -> list[MotionTask]:
        """End the commands that drive any of ``names``; their joints hold.

        A command ends whole, all of its joints (as NAOqi's
        ``killTasksUsingResources``); the others go on. Returns those ended.
        """
        wanted = set(names)
        with self._lock:
            t = self.now()
            ended = [task for task in self._tasks if wanted & set(task.joints)]
            stopped = [self.joints[name] for task in ended for name in task.joints]
            for joint in stopped:
                joint.commit(t)
            self._log_stopped([j for j in stopped if j.moving], t, reason)
            for task in ended:
                for name in task.joints:
                    self.joints[name].command(None)
                self._interrupt(task, reason, t)
            self._tasks = [task for task in self._tasks if task not in ended]
            self._owners = {
                j: task for j, task in self._owners.items() if task not in ended
            }
        return ended

    def _log_stopped(self, joints: list[SimJoint], t: float, reason: str) -> None:
        """Log where the commanded ``joints`` stop at a kill at ``t`` (held lock).

        A ``state`` line as a cycle's, stamped with the kill's time, with
        ``stopped``: the reason; the next cycle logs them once more, held.
        The cycles log only joints whose command runs, so the kill's own
        step (the joint at full speed one moment, still the next) left no
        line: the next ``state`` came with the next command, and finite
        differences across the gap made a stop from 3.6 rad/s within one
        5 ms cycle (8.7 times the bridge's net acceleration) read as 0.57
        of it.
        """
        self._stopped.update(j.spec.name for j in joints)
        if joints:
            positions = {j.spec.name: round(j.position, 6) for j in joints}
            self._log.write(
                "state", at=t, cycle=self.cycles, positions=positions, stopped=reason
            )

    def _interrupt(self, task: MotionTask, reason: str, t: float) -> None:
        """End ``task`` before its last key and log it (held lock)."""
        if task.finished:
            return
        try:  # logged, then its call is answered: a caller then finds the line
            self._log.write(
                "interrupted",
                at=t,
                method=task.method,
                joints=task.joints,
                reason=reason,
            )
        finally:  # answered whatever happened to the log
            task.interrupt(reason)

    def step(self) -> None:
        """One control cycle: advance every joint, end finished commands, log."""
        with self._lock:
            t = self.now()  # under the lock: no command commits a later time first
            self.cycles += 1
            moving = [
                j
                for j in self.joints.values()
                if j.moving or j.spec.name in self._stopped
            ]
            self._stopped = set()
            for joint in self.joints.values():
                joint.commit(t)
            positions = {j.spec.name: round(j.position, 6) for j in moving}
            finished = [task for task in self._tasks if t >= task.end_time]
            self._tasks = [task for task in self._tasks if t < task.end_time]
        if positions:
            # Stamped with the time the positions were committed at, not the
            # time the line is written: a cycle preempted between the two
            # would otherwise log a speed the motor never had.
            self._log.write("state", at=t, cycle=self.cycles, positions=positions)
        for task in finished:  # logged, then answered (as in _interrupt)
            try:
                self._log.write("done", at=t, method=task.method, joints=task.joints)
            finally:
                task.finish()

    def _prepare(self, commands: list[KeyCommand], t: float) -> dict[str, float]:
        """Commit the commanded joints to ``t``; their setpoints there [rad].

        A joint with stiffness 0 takes the command too, as a NAO's does ("at
        zero stiffness, you can send any commands to the motors, but he will
        not move"): its setpoint follows the keys, its motor stays.
        """
        starts = {}
        for c in commands:
            joint = self.joints[c.joint]
            joint.commit(t)
            starts[c.joint] = joint.setpoint(t)
        return starts

    def _start_task(
        self, method: str, commands: list[KeyCommand], t: float, owns: bool = True
    ) -> MotionTask:
        joints = [c.joint for c in commands]
        end = t + max(c.times[-1] for c in commands)
        task = MotionTask(method, joints, t, end, self.killed_returns)
        if owns:
            for joint in joints:
                previous = self._owners.get(joint)
                if previous is not None and not previous.finished:
                    self._interrupt(previous, f"{joint} was taken by {method}", t)
                self._owners[joint] = task
        self._tasks = [old for old in self._tasks if not old.finished] + [task]
        return task


def _offset(command: KeyCommand, start: float) -> KeyCommand:
    """``command`` with its keys as offsets from ``start`` made absolute [rad]."""
    return command._replace(values=[start + v for v in command.values])
