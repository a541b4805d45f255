"""ALMotion's arguments, normalised to one key list per joint and checked.

ALMotion accepts, for ``angleLists`` and ``timeLists`` alike: one number
(every joint gets that one key), a list of numbers (one key per joint, or the
keys of the single joint named), or a list of lists (the keys of each joint).
Every check here refuses the whole command with a
:class:`~bridge.sim.errors.SimCommandError`; nothing is clamped, and nothing
of a refused command runs or books a joint. A key time of 1e300 s used to
be accepted: the blocking call then failed with an ``OverflowError`` (not a
refusal) and its task kept the joint booked for good, every later command
on it ``robot_busy``; a joint named twice was accepted and interrupted
itself.
"""

from __future__ import annotations

import math
from itertools import pairwise
from typing import Any, NamedTuple

from bridge.sim.errors import SimCommandError
from bridge.sim.joints import JointSpec
from shared.messages.sample_times import MAX_SPAN

#: Slack on the limits [rad, or rad/s relative]: float round-off only.
SLACK = 1e-6
#: Latest key time a command may have [s]: a day, the longest span of
#: times any armplan message holds.
MAX_KEY_TIME = MAX_SPAN


class KeyCommand(NamedTuple):
    """The keys one joint is asked to go through.

    Attributes:
        joint: NAO joint name.
        times: Key times from reception [s], shape (m,).
        values: Key values [rad] (hands: open fraction; stiffness: 0..1), (m,).
    """

    joint: str
    times: list[float]
    values: list[float]


def _number(value: Any, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SimCommandError(f"{what} must be a number, got {value!r}")
    if not math.isfinite(value):
        raise SimCommandError(f"{what} must be finite, got {value}")
    return float(value)


def per_joint(value: Any, count: int, what: str) -> list[list[float]]:
    """One list of numbers per joint from ALMotion's accepted forms.

    Args:
        value: A number, a list of numbers, or a list of lists.
        count: Number of joints named.
        what: Argument name for messages, e.g. ``"timeLists"``.
    """
    if not isinstance(value, (list, tuple)):
        return [[_number(value, what)] for _ in range(count)]
    if count == 1 and not any(isinstance(v, (list, tuple)) for v in value):
        return [[_number(v, f"{what}[{i}]") for i, v in enumerate(value)]]
    if len(value) != count:
        raise SimCommandError(f"{what} has {len(value)} entries for {count} joints")
    rows = []
    for i, row in enumerate(value):
        items = row if isinstance(row, (list, tuple)) else [row]
        rows.append([_number(v, f"{what}[{i}]") for v in items])
    return rows


def key_commands(
    joints: list[str], values: Any, times: Any, what: str = "angleLists"
) -> list[KeyCommand]:
    """Pair each joint with its keys.

    Each joint is named once; its key times [s] increase from above 0 to at
    most :data:`MAX_KEY_TIME`.
    """
    seen: set[str] = set()
    for joint in joints:
        if joint in seen:
            raise SimCommandError(
                f"{joint} is named twice (itself, or in a chain such as RArm): "
                "one command gives each joint its keys once"
            )
        seen.add(joint)
    value_rows = per_joint(values, len(joints), what)
    time_rows = per_joint(times, len(joints), "timeLists")
    commands = []
    for joint, v, t in zip(joints, value_rows, time_rows, strict=True):
        if not v or len(v) != len(t):
            raise SimCommandError(
                f"{joint} has {len(v)} values for {len(t)} times (need as many, >= 1)"
            )
        if t[0] <= 0.0 or any(b <= a for a, b in pairwise(t)):
            raise SimCommandError(f"{joint} key times must increase from above 0: {t}")
        if t[-1] > MAX_KEY_TIME:
            raise SimCommandError(
                f"{joint} key {len(t)} at t = {t[-1]:g} s is later than "
                f"{MAX_KEY_TIME:g} s (a day), the latest key time this NAO takes"
            )
        commands.append(KeyCommand(joint, t, v))
    return commands


def check_range(command: KeyCommand, spec: JointSpec) -> None:
    """Every key inside the joint's range, or an error naming the key."""
    unit = "" if spec.name.endswith("Hand") else " rad"
    for k, value in enumerate(command.values):
        if not spec.lower - SLACK <= value <= spec.upper + SLACK:
            raise SimCommandError(
                f"{spec.name} key {k + 1} = {value:.5f}{unit} is outside its range "
                f"[{spec.lower:.5f}, {spec.upper:.5f}]{unit}"
            )


def check_speed(command: KeyCommand, spec: JointSpec, start: float) -> None:
    """Check every key is reachable from the previous one within the speed limit.

    The first key is reached from ``start`` [rad] at time 0; an error names the
    key, its time and the limit.
    """
    previous_time, previous = 0.0, start
    for k, (t, value) in enumerate(zip(command.times, command.values, strict=True)):
        speed = abs(value - previous) / (t - previous_time)
        if speed > spec.velocity * (1.0 + SLACK):
            raise SimCommandError(
                f"{spec.name} key {k + 1} (t = {t:.3f} s) needs {speed:.3f} rad/s "
                "from the previous key, above its speed limit "
                f"{spec.velocity:.3f} rad/s"
            )
        previous_time, previous = t, value
