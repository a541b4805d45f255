"""The timing stage as a function of messages: joint paths to one trajectory.

The timing service's thin Zenoh wrapper calls it, and the planner's
``LocalStages`` in this process, so both run the same code. Apart from
``services.planner.stages``: it loads ``scipy.interpolate`` (about 0.7 s),
which the IK and decide services, importing that module, never use.
"""

from __future__ import annotations

import numpy as np

from services.planner.build import arc_length, trajectory_message
from services.timing.hand import (
    first_opening,
    hand_channel,
    hand_dwells,
    hand_moves,
    hand_rates,
)
from services.timing.point_times import point_times
from services.timing.request_limits import request_limits
from services.timing.sample_cap import check_asked, check_samples
from services.timing.segments import Segment, time_segments_with_rests
from services.timing.time_path import sample_period
from shared.errors import InvalidInputError
from shared.messages import JointPath, TimingRequest, Trajectory
from shared.robot import load_arm
from shared.robot.hand import hand_motion_limits
from shared.robot.motion_limits import MotionLimits

#: A hand whose arc is under this share of the arc its joints' travel would
#: sweep at arm's length turns in place (a palm turn: tens of micrometres of
#: IK wobble against centimetres; a reach: a third or more).
IN_PLACE_SHARE = 0.01


def timing(request: TimingRequest, limits: MotionLimits | None = None) -> Trajectory:
    """The timing stage: the task's joint paths as one trajectory (Ruckig).

    Each movement is timed by the hand's arc length along its IK path, so its
    human bell is the hand's speed profile. A segment's hand action moves
    the gripper during its dwell, lengthened to the gripper's time if
    shorter (``services.timing.hand``); the trajectory then carries the
    gripper's open fraction (``Trajectory.hand``). It also carries when it
    passes each point of each joint path (``Trajectory.point_times``), for
    the planner to place each reach's decision on its clock.

    Raises:
        InvalidInputError: a trajectory over ``MAX_TRAJECTORY_SAMPLES``
            samples (refused before timing when the asked durations and
            dwells alone pass it), or joint names other than the arm's.
    """
    first = request.segments[0].joint_path
    actions = [s.hand for s in request.segments]
    moves = hand_moves(
        actions, hand_motion_limits(first.arm), sample_period(request.rate)
    )
    dwells = hand_dwells([s.dwell for s in request.segments], moves)
    check_asked(_with_dwells(request, dwells))
    _check_joint_names(request)
    arm = load_arm(first.arm)
    limits = limits or request_limits(arm.limits, request.limits)
    reach = arm.upper_arm_length + arm.forearm_length
    segments = [
        Segment(
            np.array(s.joint_path.positions),
            s.duration,
            dwell,
            _hand_parameter(s.joint_path, reach),
        )
        for s, dwell in zip(request.segments, dwells, strict=True)
    ]
    timed, rests = time_segments_with_rests(segments, limits, rate=request.rate)
    check_samples(len(timed.times), request.rate)
    paths = [s.joint_path for s in request.segments]
    trajectory = trajectory_message(arm, paths, timed, request.method)
    passed = point_times(timed, [len(p.times) for p in paths], rests)
    trajectory = trajectory.model_copy(update={"point_times": passed})
    opening = first_opening(actions)
    if opening is None:
        return trajectory
    hand = hand_channel(timed.times, rests, moves, opening)
    speed, acceleration = hand_rates(timed.times, rests, moves)
    return trajectory.model_copy(
        update={
            "hand": hand.tolist(),
            "hand_velocities": speed.tolist(),
            "hand_accelerations": acceleration.tolist(),
        }
    )


def _with_dwells(request: TimingRequest, dwells: list[float]) -> TimingRequest:
    """``request`` with each segment's dwell [s] replaced (lengthened for a hand)."""
    if all(d == s.dwell for d, s in zip(dwells, request.segments, strict=True)):
        return request
    segments = [
        s.model_copy(update={"dwell": d})
        for s, d in zip(request.segments, dwells, strict=True)
    ]
    return request.model_copy(update={"segments": segments})


def _hand_parameter(path: JointPath, reach: float) -> np.ndarray | None:
    """The hand's arc length along a movement [m], or None if it turns in place.

    In place: the hand's arc is under ``IN_PLACE_SHARE`` of the arc the
    joints' own motion would sweep at arm's length (``reach`` [m] times the
    largest joint travel [rad]). It is then the IK's micrometre wobble, and
    knots spaced by it made a 0.4 rad palm turn take 1.9-3.7 s where the
    joints allow 0.4 s; ``None`` times the movement by the joints' chord.
    """
    along = arc_length(path.wrist)
    travel = np.abs(np.diff(np.asarray(path.positions), axis=0)).sum(axis=0).max()
    return None if along[-1] < IN_PLACE_SHARE * reach * travel else along


def _check_joint_names(request: TimingRequest) -> None:
    """Every segment moves the first one's arm, by its joints' names, in order.

    Raises:
        InvalidInputError: naming the segment and the names.
    """
    arm = request.segments[0].joint_path.arm
    names = list(arm.joint_names)
    for k, segment in enumerate(request.segments):
        path = segment.joint_path
        if path.arm is not arm or path.joint_names != names:
            raise InvalidInputError(
                f"segment {k} moves the {path.arm.value} arm's {path.joint_names}; "
                f"a {arm.value} arm's task moves {names}, in that order",
                field="segments",
                index=k,
            )
