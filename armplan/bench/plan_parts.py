"""Where a plan's time goes: its parts, each timed on its own.

The parts of planning one reach with method ``mp`` in this process, as
``services.planner`` runs them (the shipped model compiled once beforehand):

- ``wrist_path``: the human-like wrist path (``reach_wrist_path``);
- ``decide_and_track``: the decide stage: the motion decision at every path
  point, made inside the IK tracker's loop, and the ``Decision`` message;
- ``tracking``: the IK tracking alone: the same path with the decided
  primitives replayed (what the ik service computes);
- ``timing``: Ruckig's time parameterisation (``time_segments``) at the
  reach's human pace, as the plan asks for it;
- ``timing_fastest``: the same with ``--fastest``: the jerk-limited bell
  stretched until it first touches a limit (a shorter time-optimal profile
  under constant limits on u is taken if there is one). Not the problem
  toppra solves: toppra's is time-optimal under the speed and acceleration
  limits alone and rides them, so the two are unlike work, compared as the
  nearest part of ours (with both trajectories' durations beside);
- ``messages``: the ``JointPath`` and ``Trajectory`` messages.

The decision's own cost is ``decide_and_track`` minus ``tracking``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from armplan.bench.timer import Timing, time_rounds
from services.ik.track import track_path
from services.planner.build import arc_length, joint_path_message, trajectory_message
from services.planner.reach_path import reach_wrist_path
from services.planner.stages import decide, default_decider
from services.timing import Segment, reach_duration, time_segments
from shared.messages import DecideRequest, Method, ReachTarget
from shared.primitives import get_primitive
from shared.robot import ArmModel, motion_limits
from shared.robot.postures import rest

#: Parts measured, in pipeline order.
PARTS = (
    "wrist_path",
    "decide_and_track",
    "tracking",
    "timing",
    "timing_fastest",
    "messages",
)


class PlanParts(NamedTuple):
    """Time per call of each part [s], and the path's length.

    Attributes:
        points: Path points of the reach.
        timings: Per part (``PARTS``), the time of each call [s].
    """

    points: int
    timings: dict[str, Timing]

    def median(self, part: str) -> float:
        """The part's median time per call [s]."""
        return self.timings[part].percentile(50)

    @property
    def tracking_per_point(self) -> float:
        """IK tracking per path point [s]."""
        return self.median("tracking") / self.points

    @property
    def decision_per_point(self) -> float:
        """Motion decision per path point (decide stage minus tracking) [s]."""
        extra = self.median("decide_and_track") - self.median("tracking")
        return max(extra, 0.0) / self.points


def time_parts(
    arm: ArmModel,
    target: ReachTarget,
    repeats: int,
    after: Callable[[], object] | None = None,
) -> PlanParts:
    """Time each part of planning a reach from rest to ``target``.

    Args:
        arm: The arm.
        target: The reach's target (position [m] in the torso frame).
        repeats: Calls timed per part.
        after: Called after each timed call, untimed (progress).
    """
    points, calls = part_calls(arm, target)
    return PlanParts(points, time_rounds(calls, repeats, after))


def part_calls(
    arm: ArmModel, target: ReachTarget
) -> tuple[int, dict[str, Callable[[], object]]]:
    """The number of path points, and one call per part (on prepared data)."""
    start = rest(arm.side)
    path = reach_wrist_path(arm, start, target)
    request = DecideRequest(path=path, start=tuple(float(v) for v in start))
    decider = default_decider()
    decision, tracked = decide(decider, request)
    primitives = [get_primitive(name) for name in decision.primitives]
    points = np.array(path.positions)
    joint_path = joint_path_message(arm, path.times, tracked)
    segments = [
        Segment(
            np.array(joint_path.positions),
            reach_duration(arm, start, tracked.q[-1]),
            0.0,
            arc_length(joint_path.wrist),
        )
    ]
    fastest = [segments[0]._replace(duration=None)]
    limits = motion_limits(arm.limits)
    timed = time_segments(segments, limits)

    def messages() -> object:
        made = joint_path_message(arm, path.times, tracked)
        return trajectory_message(arm, [made], timed, Method.MP)

    return len(points), {
        "wrist_path": lambda: reach_wrist_path(arm, start, target),
        "decide_and_track": lambda: decide(decider, request),
        "tracking": lambda: track_path(
            arm, points, start, lambda k, st: primitives[k], method=Method.MP
        ),
        "timing": lambda: time_segments(segments, limits),
        "timing_fastest": lambda: time_segments(fastest, limits),
        "messages": messages,
    }
