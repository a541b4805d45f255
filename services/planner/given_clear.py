"""A given wrist path timed as given, its elbow turned clear if its times allow.

``plan --wrist-path`` keeps the path's times. A joint path that comes near
NAO's body (or the other arm) is turned about the wrist
(``services.planner.clear_swivel``), which leaves the wrist on the path,
and the turned one is taken if its speeds, accelerations and jerks keep
the limits at those times.
"""

from __future__ import annotations

import numpy as np

from services.planner.clear_swivel import REFUSED_TOO_FAST, REFUSED_TRIED, keep_clear
from services.timing import time_given
from services.timing.trajectory import TimedTrajectory
from shared.errors import LimitViolationError
from shared.messages import JointPath, Method, WristPath
from shared.robot.arm_model import ArmModel
from shared.robot.body import BodyPart
from shared.robot.motion_limits import MotionLimits


def timed_clear(
    arm: ArmModel,
    path: WristPath,
    joint_path: JointPath,
    method: Method,
    limits: MotionLimits,
    parts: tuple[BodyPart, ...],
) -> tuple[JointPath, TimedTrajectory, str]:
    """A given path's joint path at its own times, its elbow turned if need be.

    A joint path that comes near ``parts`` is turned about the wrist
    (``clear_swivel.keep_clear``), which leaves the wrist on the path; the
    turned one is taken if its speeds keep the limits at the path's times.

    Returns:
        The joint path, its timing, and the advice for a refusal of it for
        the body ("": the default).

    Raises:
        LimitViolationError: the joint path as tracked is too fast already.
    """
    times = np.array(path.times)
    kept = keep_clear(arm, joint_path, path.palm, method, parts)
    if kept.path is not joint_path:
        try:
            timed = time_given(times, np.array(kept.path.positions), limits)
            return kept.path, timed, REFUSED_TRIED
        except LimitViolationError:  # the turn needs more speed than the times
            timed = time_given(times, np.array(joint_path.positions), limits)
            return joint_path, timed, REFUSED_TOO_FAST
    timed = time_given(times, np.array(joint_path.positions), limits)
    return joint_path, timed, REFUSED_TRIED if kept.tried else ""
