"""The even grid a wrist path is tracked on stays within the arm's reach.

A path not sampled every 10 ms is tracked on the planner's even grid
(:func:`services.planner.even_path.even_grid`), the clamped cubic spline
through its samples. Every sample may be within reach while the curve
between two of them is not: a chord between two points near the edge of
the reach shell cuts inside its inner sphere (the hanging wrist and a
point at 0.97 of the reach, one second apart, passed 0.103 m from the
shoulder, which the wrist cannot come nearer than 0.114 m), and the spline
swings past the samples where the times are uneven. The tracker then left
the path and the user read that the wrist was 176 mm off at a sample,
nothing saying the planner's own curve had left the reachable space.
Shape-preserving interpolants (PCHIP, Akima) cut the same chord, so when
the tracking ends off the path and the tracked wrist left the curve where
it leaves the reach, the gap is named, to be filled with samples (a path
over a limit keeps its own error). It is not checked before: a path
leaving its start on the reach shell (the hanging wrist is 0.8 mm inside
it) may poke a fraction of a millimetre out, and the tracker
follows it within the path's tolerance all the same. Only a grid point
more than ``STAGE_SLACK`` (1 mm) out is refused before tracking, by the
decide and ik stages (``services.planner.path_reach``); the planner then
names the gap here too.
"""

from __future__ import annotations

import numpy as np

from services.ik.iterate import TOLERANCE
from shared.errors import UnreachableTargetError
from shared.messages import WristPath
from shared.robot.arm_model import ArmModel
from shared.robot.postures import rest


def check_grid_within_reach(
    arm: ArmModel,
    path: WristPath,
    grid: WristPath,
    tolerance: float = TOLERANCE,
    tracked: np.ndarray | None = None,
) -> None:
    """Raise, naming the gap between ``path``'s samples, if ``grid`` leaves reach.

    Args:
        arm: The arm.
        path: The timed wrist path as given (its samples within reach).
        grid: ``path`` resampled on the even grid.
        tolerance: How far out of the reach shell a grid point may be [m].
        tracked: The joint angles the tracker found on the grid [rad],
            shape (len(grid.times), 5), if it got that far: the grid is then
            blamed only if the tracked wrist left it where it leaves the
            reach (a path too fast elsewhere keeps its own error).

    Raises:
        UnreachableTargetError: at the grid point farthest out of the reach
            shell (distance from the shoulder [m]), saying between which of
            the path's samples it lies and to add samples there.
    """
    shoulder = arm.fk(rest(arm.side)).shoulder
    points = np.asarray(grid.positions, dtype=float)
    distance = np.linalg.norm(points - shoulder, axis=1)
    low, high = arm.reach
    outside = np.maximum(low - distance, distance - high)
    k = int(np.argmax(outside))
    if outside[k] <= tolerance:
        return
    times = np.asarray(path.times, dtype=float)
    t = grid.times[k]
    after = int(np.clip(np.searchsorted(times, t, side="right"), 1, len(times) - 1))
    before = after - 1
    if tracked is not None:
        wrist = arm.fk(np.asarray(tracked[k], dtype=float)).wrist
        if np.linalg.norm(wrist - points[k]) <= tolerance:
            return  # followed there: the curve's reach is not why it failed
    raise UnreachableTargetError(
        points[k],
        arm=arm.side.value,
        distance=float(distance[k]),
        reach=arm.reach,
        at=(
            f"the wrist path between samples {before} (t = {times[before]:.3f} s) "
            f"and {after} (t = {times[after]:.3f} s), at t = {t:.3f} s on the "
            "curve the planner draws through the samples (a clamped cubic "
            "spline, tracked every 10 ms)"
        ),
        advice="add samples between them to keep the path within reach",
    )


__all__ = ["check_grid_within_reach"]
