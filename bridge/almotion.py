"""Command frames as ALMotion's ``angleInterpolation`` call.

``angleInterpolation(names, angleLists, timeLists, isAbsolute)`` moves each
named joint through its keys: ``angleLists[i][k]`` [rad] reached at
``timeLists[i][k]`` [s] after the call, absolute angles when ``isAbsolute``.
It blocks until the movement ends. The frames' start posture is not a key:
the robot moves from wherever it is to the first key, so it must be at the
start already (the bridge sees to that).
"""

from __future__ import annotations

from typing import NamedTuple

from shared.messages import CommandFrames


class AngleInterpolationCall(NamedTuple):
    """The arguments of one ``ALMotion.angleInterpolation`` call.

    Attributes:
        names: NAO joint names, shape (n,).
        angle_lists: Keys per joint [rad], shape (n, m).
        time_lists: Time of each key from the call [s], shape (n, m).
        is_absolute: True: the angles are absolute, not offsets.
    """

    names: list[str]
    angle_lists: list[list[float]]
    time_lists: list[list[float]]
    is_absolute: bool = True

    @property
    def duration(self) -> float:
        """Time of the last key [s]."""
        return max(times[-1] for times in self.time_lists)


def angle_interpolation_call(frames: CommandFrames) -> AngleInterpolationCall:
    """The ``angleInterpolation`` call that plays ``frames`` (absolute angles)."""
    columns = [list(column) for column in zip(*frames.positions, strict=True)]
    return AngleInterpolationCall(
        names=list(frames.joint_names),
        angle_lists=[[float(v) for v in column] for column in columns],
        time_lists=[list(frames.times) for _ in frames.joint_names],
        is_absolute=True,
    )
