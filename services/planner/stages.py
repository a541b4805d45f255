"""The planner's three stages as functions of messages, run in this process.

The same functions serve as the decide, ik and timing services (their thin
Zenoh wrappers call them), so a plan made here and one made through the
services run the same code on the same inputs and agree exactly. Here the
IK stage reuses the joint path the decision already tracked instead of
tracking it again (the services recompute it: same inputs, same result).
"""

from __future__ import annotations

import threading
import weakref
from functools import cache
from typing import Protocol

import numpy as np

from services.decide import Decider, decide_path
from services.fit.default import default_model
from services.fit.model import MotionModel
from services.fit.model_state import digest
from services.ik.track import TrackedPath, track_path
from services.planner.build import arc_length, joint_path_message, trajectory_message
from services.planner.path_reach import STAGE_SLACK, check_path_within_reach
from services.timing import Segment
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
from services.timing.segments import time_segments_with_rests
from services.timing.time_path import sample_period
from shared.errors import InvalidInputError
from shared.messages import (
    DecideRequest,
    Decision,
    JointPath,
    Method,
    PathIKRequest,
    TimingRequest,
    Trajectory,
)
from shared.primitives import get_primitive
from shared.robot import load_arm
from shared.robot.hand import hand_motion_limits
from shared.robot.motion_limits import MotionLimits
from shared.robot.postures import rest

#: A hand whose arc is under this share of the arc its joints' travel would
#: sweep at arm's length turns in place (a palm turn: tens of micrometres of
#: IK wobble against centimetres; a reach: a third or more).
IN_PLACE_SHARE = 0.01


class Stages(Protocol):
    """Where the planner's stages run: here, or as services over Zenoh."""

    def decide(self, request: DecideRequest) -> Decision:
        """The primitive of every point of a reach's wrist path."""

    def ik(self, request: PathIKRequest) -> JointPath:
        """The joint angles along a reach's wrist path."""

    def timing(self, request: TimingRequest) -> Trajectory:
        """The task's joint paths as one timed trajectory."""


def decide(
    model: MotionModel | Decider, request: DecideRequest
) -> tuple[Decision, TrackedPath]:
    """The decide stage: the decision, and the joint path it tracked.

    The decision carries the digest of the model that decided
    (``Decision.model``), so a plan can tell whether all its decisions
    came from one model.

    Raises:
        UnreachableTargetError: a path sample more than ``STAGE_SLACK`` out
            of the arm's reach, naming it.
    """
    arm = load_arm(request.path.arm)
    check_path_within_reach(arm, request.path, STAGE_SLACK)
    start = rest(arm.side) if request.start is None else np.array(request.start)
    palm = None if request.path.palm is None else np.array(request.path.palm)
    decision, tracked = decide_path(
        model,
        arm,
        np.array(request.path.positions),
        start,
        palm=palm,
        times=np.array(request.path.times),
        params=request.measures,
    )
    motion_model = model.model if isinstance(model, Decider) else model
    return decision.model_copy(update={"model": model_digest(motion_model)}), tracked


#: Digests of the models decided with, by ``id``, with a weak reference
#: telling whether that id is still the model's (dead entries are pruned).
_DIGESTS: dict[int, tuple[weakref.ref[MotionModel], str]] = {}
_DIGESTS_LOCK = threading.Lock()


def model_digest(model: MotionModel) -> str:
    """``digest(model)``, computed once per model object.

    Hashing a model's JSON costs up to about 0.1 s for a fine one (64 bins),
    too much for every decision; a model is not changed once built.
    """
    with _DIGESTS_LOCK:
        ref, known = _DIGESTS.get(id(model), (None, None))
    if ref is not None and ref() is model and known is not None:
        return known
    known = digest(model)
    with _DIGESTS_LOCK:
        for key in [k for k, (r, _) in _DIGESTS.items() if r() is None]:
            del _DIGESTS[key]
        _DIGESTS[id(model)] = (weakref.ref(model), known)
    return known


def path_ik(request: PathIKRequest) -> JointPath:
    """The ik stage: track the wrist path with the decided primitives (or a baseline).

    Raises:
        InvalidInputError: method ``mp`` without a decision. (A decision
            of another arm or other times than the path is refused when the
            request is read: ``PathIKRequest``.)
        UnreachableTargetError: a path sample more than ``STAGE_SLACK`` out
            of the arm's reach, naming it.
    """
    arm = load_arm(request.path.arm)
    path = request.path
    check_path_within_reach(arm, path, STAGE_SLACK)
    start = rest(arm.side) if request.start is None else np.array(request.start)
    palm = None if path.palm is None else np.array(path.palm)
    choose = None
    if request.method is Method.MP:
        names = _decided(request)
        primitives = [get_primitive(name) for name in names]
        choose = lambda k, st: primitives[k]  # noqa: E731
    tracked = track_path(
        arm,
        np.array(path.positions),
        start,
        choose,
        method=request.method,
        palm=palm,
        params=request.weights(),
    )
    return joint_path_message(arm, path.times, tracked)


def _decided(request: PathIKRequest) -> list[str]:
    if request.decision is None:
        raise InvalidInputError(
            "method mp needs the decision of every point", field="decision"
        )
    return request.decision.primitives


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


@cache
def default_decider() -> Decider:
    """The shipped motion model, compiled once per process.

    Compiling the model's tables (``Decider``) costs a large share of
    planning one reach; a ``Decider`` is read-only once built (it only
    caches its variants for other step lengths), so every plan shares it.
    """
    return Decider(default_model())


class LocalStages:
    """The stages in this process, with the decision's joint path reused.

    Args:
        model: The motion model; default: the shipped one (compiled once).
    """

    def __init__(self, model: MotionModel | None = None) -> None:
        self.decider = default_decider() if model is None else Decider(model)
        self._tracked: dict[int, tuple[DecideRequest, TrackedPath]] = {}

    def decide(self, request: DecideRequest) -> Decision:
        decision, tracked = decide(self.decider, request)
        self._tracked = {id(decision): (request, tracked)}
        return decision

    def ik(self, request: PathIKRequest) -> JointPath:
        asked, tracked = (
            self._tracked.pop(id(request.decision), (None, None))
            if request.decision
            else (None, None)
        )
        if tracked is None or not _same_work(asked, request):
            return path_ik(request)
        return joint_path_message(
            load_arm(request.path.arm), request.path.times, tracked
        )

    def timing(self, request: TimingRequest) -> Trajectory:
        return timing(request)


def _same_work(asked: DecideRequest | None, request: PathIKRequest) -> bool:
    """Whether ``request`` tracks what the decision ``asked`` for tracked."""
    return (
        asked is not None
        and request.method is Method.MP
        and (asked.path, asked.start, asked.measures)
        == (request.path, request.start, request.measures)
    )
