"""The motion decision along a wrist path, made inside the IK tracker's loop.

``track_path`` asks for the primitive of each path point with the arm's
kinematics there; the chooser here decides it (``decide_point``) from that
state, the goal and the decision before, and records it. The result: the
``Decision`` message (per point the primitive, its matrix and every g) and
the tracked joint path. The IK service later recomputes the same joint path
with ``choose=lambda k, kin: BY_NAME[decision.points[k].primitive]``: the
chooser returns exactly the recorded primitive, so the two agree bit for bit.

Where the tracker gives the path up for a joint-space detour to the goal
(``TrackedPath.detour_from``) it asks no more primitives; the decisions of
the remaining points are then made, for the record, from the detour's
postures (a replay asks for the same points as the original run).
"""

from __future__ import annotations

import numpy as np

from services.decide.decider import CANDIDATES, Choice, Decider
from services.decide.point import DecidingArm, decide_point
from services.fit.model import MotionModel
from services.ik.track import TrackedPath, track_path
from shared.messages import Decision, PointDecision, WristPath
from shared.primitives import BY_NAME, Primitive
from shared.robot.arm_model import ArmModel, Kinematics
from shared.robot.postures import rest

#: Sample interval of a path given without times [s].
DEFAULT_STEP = 0.01


def decide_path(
    model: MotionModel | Decider,
    arm: ArmModel,
    positions: np.ndarray,
    start_q: np.ndarray,
    goal: np.ndarray | None = None,
    palm: np.ndarray | None = None,
    times: np.ndarray | None = None,
) -> tuple[Decision, TrackedPath]:
    """Decide the primitive of every point of a wrist path while tracking it.

    Args:
        model: The motion model (or one already compiled).
        arm: The arm.
        positions: Wrist path [m], shape (n, 3).
        start_q: Posture at the first point [rad], shape (5,).
        goal: Where the movement ends [m], shape (3,); default the last point.
        palm: Wanted palm direction at the goal (unit, shape (3,)), or ``None``.
        times: Times of the points [s], shape (n,); default 0.01 s apart.

    Returns:
        The decision (one ``PointDecision`` per point) and the joint path.
    """
    positions = np.asarray(positions, dtype=float)
    times = (
        np.arange(len(positions)) * DEFAULT_STEP
        if times is None
        else np.asarray(times, dtype=float)
    )
    decider = _decider(model, times)
    end = positions[-1] if goal is None else np.asarray(goal, dtype=float)
    target = (float(end[0]), float(end[1]), float(end[2]))
    size = DecidingArm.of(arm)
    wanted = None if palm is None else tuple(float(v) for v in palm)
    made: list[Choice] = []

    def choose(k: int, kin: Kinematics) -> Primitive:
        previous = made[-1] if made else None
        made.append(decide_point(decider, kin, target, size, wanted, previous))
        return BY_NAME[made[-1].name]

    tracked = track_path(arm, positions, start_q, choose, palm=palm)
    for q in tracked.q[len(made) :]:  # a joint-space detour: no chooser calls
        made.append(
            decide_point(decider, arm.kinematics(q), target, size, wanted, made[-1])
        )
    return decision_message(arm, times, made), tracked


def decide_wrist_path(
    model: MotionModel | Decider,
    arm: ArmModel,
    path: WristPath,
    start_q: np.ndarray | None = None,
) -> Decision:
    """The decision for a ``WristPath`` message (the decide service's request).

    The start posture defaults to the arm hanging at rest.
    """
    start = rest(arm.side) if start_q is None else np.asarray(start_q, dtype=float)
    palm = None if path.palm is None else np.array(path.palm)
    decision, _ = decide_path(
        model,
        arm,
        np.array(path.positions),
        start,
        palm=palm,
        times=np.array(path.times),
    )
    return decision


def decision_message(arm: ArmModel, times: np.ndarray, made: list[Choice]) -> Decision:
    """The ``Decision`` message of recorded choices."""
    points = [
        PointDecision(
            primitive=choice.name,
            matrix=BY_NAME[choice.name].matrix,
            g=dict(zip(CANDIDATES, choice.g, strict=True)),
        )
        for choice in made
    ]
    return Decision(arm=arm.side, times=[float(t) for t in times], points=points)


def _decider(model: MotionModel | Decider, times: np.ndarray) -> Decider:
    """The compiled model for decisions at the path's sample interval."""
    step = float(np.median(np.diff(times))) if len(times) > 1 else DEFAULT_STEP
    base = model if isinstance(model, Decider) else Decider(model)
    return base if abs(base.step - step) < 1e-12 else base.with_step(step)
