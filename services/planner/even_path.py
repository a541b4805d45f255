"""A timed wrist path tracked on the planner's even grid, read back at its times.

The tracker moves by one step per path point (its null-space motion, the
blend at a change of primitive and the removal of the last step's residual
are all counted in points), so a path sampled unevenly in time turned into
joint accelerations and jerks where the gaps changed: a slow path with 30 %
of its samples dropped was refused (RElbowYaw jerk 716 > 661 rad/s^3) where
the full one used 0.04 of the limit. Here such a path is first resampled
evenly in time (``even_grid``), on the clamped cubic spline through its
samples (at rest at both ends, through every sample), and checked to stay
within the arm's reach between the samples
(:mod:`services.planner.grid_reach`, naming the gap to fill); the tracker
follows that; the joint angles at the path's own
times are read off the cubic spline through the tracked postures and then
moved onto the path's samples (``converge`` of the wrist position with every
joint, no null-space motion: the residual is a fraction of a millimetre, so
the move is as small and smooth).

The grid is the planner's own: a point every 10 ms, the rate the tracker's
per-point steps are made for. A path sampled evenly but at another step is
tracked on it too: on a few waypoints a second the tracker's large steps
left the wrist millimetres off its samples (55 of 60 seeded plans of 8
waypoints over 5 s refused), and on a path sampled every 5 ms its blend
and null-space steps, taken per point, came twice as fast in time (the
planner's 1 s reach refused for RElbowYaw acceleration 38.6 > 33.1 rad/s^2
at 5 ms, accepted at 20 ms). A path sampled evenly every 10 ms is tracked
as given (:func:`tracked_as_given`), so the planner's and the experiments'
joint paths are unchanged, bit for bit.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import CubicSpline  # type: ignore[import-untyped]

from services.ik.iterate import converge
from services.ik.kernel.chain import chain_for
from services.ik.measures import NoMeasure
from services.ik.task import WristTask
from services.planner.reach_path import PATH_RATE
from shared.messages import JointPath, WristPath
from shared.messages.target import MAX_TRAJECTORY_SAMPLES
from shared.robot.arm_model import ArmModel

#: Most steps of the even grid: as many as a trajectory may have samples.
MAX_STEPS = MAX_TRAJECTORY_SAMPLES - 1
#: Gaps within this share of their mean are even (written times such as
#: 0.01 * k differ from it in the last digits only).
EVEN = 1e-6
#: Step of the grid a path is tracked on [s]: the planner's own paths' (100
#: points a second, ``reach_path.PATH_RATE``).
GRID_STEP = 1.0 / PATH_RATE
#: Every joint moves in the final correction onto a sample.
ALL_JOINTS = (0, 1, 2, 3, 4)


def is_even(times: list[float]) -> bool:
    """True if ``times`` [s] are equally spaced (to ``EVEN`` of the mean gap)."""
    if len(times) < 3:
        return True
    gaps = np.diff(np.asarray(times, dtype=float))
    return bool(np.ptp(gaps) <= EVEN * float(np.mean(gaps)))


def tracked_as_given(times: list[float]) -> bool:
    """Whether a path at ``times`` [s] is tracked on its own samples.

    It is if they are ``GRID_STEP`` apart (to ``EVEN`` of it); else it is
    tracked on ``even_grid``.
    """
    if len(times) < 2:
        return True
    step = times[1] - times[0]
    return is_even(times) and abs(step - GRID_STEP) <= EVEN * GRID_STEP


def even_grid(path: WristPath) -> WristPath:
    """``path`` resampled every ``GRID_STEP`` (see the module docstring).

    The step is made a little smaller to end on the path's last time (and
    larger if the path would need more than ``MAX_STEPS`` steps). The
    positions [m] lie on the clamped cubic spline through the path's
    samples (zero velocity at both ends); the grid starts and ends at the
    path's first and last times.
    """
    times = np.asarray(path.times, dtype=float)
    span = times[-1] - times[0]
    gap = max(GRID_STEP, span / MAX_STEPS)
    steps = max(math.ceil(span / gap * (1.0 - EVEN)), 1)
    grid = np.linspace(times[0], times[-1], steps + 1)
    grid[-1] = times[-1]
    curve = CubicSpline(times, np.asarray(path.positions), bc_type="clamped")
    positions = curve(grid)
    positions[0], positions[-1] = path.positions[0], path.positions[-1]
    return path.model_copy(
        update={
            "times": grid.tolist(),
            "positions": [tuple(p) for p in positions.tolist()],
        }
    )


def at_path_times(arm: ArmModel, path: WristPath, tracked: JointPath) -> JointPath:
    """The joint path of ``tracked`` (on ``path``'s even grid) at ``path``'s times.

    Each posture [rad] is the cubic spline through the tracked postures at
    the sample's time, moved so its wrist is on the sample (every joint,
    least change); each sample takes the primitive of the grid point at or
    before it.
    """
    grid = np.asarray(tracked.times, dtype=float)
    times = np.asarray(path.times, dtype=float)
    q = CubicSpline(grid, np.asarray(tracked.positions), bc_type="clamped")(times)
    chain = chain_for(arm)
    sign = arm.side.sign
    postures: list[list[float]] = []
    for posture, point in zip(q.tolist(), path.positions, strict=True):
        moved, _ = converge(
            chain, WristTask.make(point, None, sign), ALL_JOINTS, NoMeasure(), posture
        )
        postures.append(list(np.clip(moved, arm.limits.lower, arm.limits.upper)))
    before = np.clip(np.searchsorted(grid, times, side="right") - 1, 0, len(grid) - 1)
    return tracked.model_copy(
        update={
            "times": times.tolist(),
            "positions": postures,
            "primitives": [tracked.primitives[k] for k in before],
            "wrist": [tuple(chain.state(p).p_wrist) for p in postures],
        }
    )
