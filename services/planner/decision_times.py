"""Each reach's decision placed on the trajectory's clock, once it is timed.

A decision is made on its wrist path's own clock: each reach's ``times``
start at 0 and run at the path's nominal pace. The timing stage sets the
actual pace and the rests, and says when the trajectory passes each point
(``Trajectory.point_times``). The planner writes those times onto the
decisions (``Decision.trajectory_times``), so that a recording places
every decision point at the moment the trajectory is there, and leaves
them out of the plan's trajectory, whose JSON stays the SPEC's.
"""

from __future__ import annotations

from collections.abc import Sequence

from shared.messages import Decision, Trajectory


def timed_decisions(
    trajectory: Trajectory, decisions: Sequence[Decision]
) -> tuple[Trajectory, list[Decision]]:
    """The trajectory without ``point_times``; the decisions with their times.

    Args:
        trajectory: The timing stage's trajectory of a task of targets.
        decisions: One decision per reach, in order (method ``mp``), or none.

    Returns:
        The trajectory as the plan gives it, and the decisions, each with
        ``trajectory_times``; unchanged if the timing gave no point times
        or not one list per decision with one time per point (a timing
        service of another version): a recording then places them on their
        own clock, as before the times existed.
    """
    passed = trajectory.point_times
    plain = trajectory.model_copy(update={"point_times": None})
    if passed is None or not _fits(passed, decisions):
        return plain, list(decisions)
    timed = [
        d.model_copy(update={"trajectory_times": list(times)})
        for d, times in zip(decisions, passed, strict=True)
    ]
    return plain, timed


def on_path_clock(decisions: Sequence[Decision], start: float) -> list[Decision]:
    """``decisions`` of a trajectory played at its wrist path's own times.

    Args:
        decisions: The decisions, on the path's clock [s].
        start: The path's first time [s], the trajectory's first sample.
    """
    return [
        d.model_copy(update={"trajectory_times": [t - start for t in d.times]})
        for d in decisions
    ]


def _fits(passed: list[list[float]], decisions: Sequence[Decision]) -> bool:
    """Whether ``passed`` has a list per decision, a time per point."""
    return len(passed) == len(decisions) and all(
        len(times) == len(d.times) for times, d in zip(passed, decisions, strict=True)
    )
