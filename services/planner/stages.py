"""The planner's three stages as functions of messages, run in this process.

The same functions serve as the decide, ik and timing services (their thin
Zenoh wrappers call them; the timing stage is apart, in
:mod:`services.planner.timing_stage`), so a plan made here and one made
through the services run the same code on the same inputs and agree exactly.
Here the IK stage reuses the joint path the decision already tracked instead
of tracking it again (the services recompute it: same inputs, same result).
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
from services.planner.build import joint_path_message
from services.planner.path_reach import STAGE_SLACK, check_path_within_reach
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
from shared.robot.postures import rest


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
        # Imported here: the timing loads scipy.interpolate (about 0.7 s),
        # which the IK and decide services, importing this module, never use.
        from services.planner.timing_stage import timing

        return timing(request)


def _same_work(asked: DecideRequest | None, request: PathIKRequest) -> bool:
    """Whether ``request`` tracks what the decision ``asked`` for tracked."""
    return (
        asked is not None
        and request.method is Method.MP
        and (asked.path, asked.start, asked.measures)
        == (request.path, request.start, request.measures)
    )
