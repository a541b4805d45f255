"""The motion decision along a wrist path, made inside the IK tracker's loop.

``track_path`` asks for the primitive of each path point with the arm's
kinematics there; the chooser here decides it (``decide_point``) from that
state, the goal and the decision before, and records it. The result: the
``Decision`` message (per point the primitive, its matrix and every g) and
the tracked joint path. The IK service later recomputes the same joint path
with ``choose=lambda k, kin: BY_NAME[decision.primitives[k]]``: the
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
from services.ik.kernel.chain import ChainState
from services.ik.measures import MeasureParams
from services.ik.track import TrackedPath, track_path
from shared.messages import Decision, WristPath
from shared.primitives import BY_NAME, Primitive
from shared.robot.arm_model import ArmModel
from shared.robot.postures import rest

#: Sample interval of a path given without times [s].
DEFAULT_STEP = 0.01
#: How long a new winner must win before it takes over [s] (see Settling).
SETTLE = 0.05
#: Shortest time a primitive drives the arm before another takes over [s].
HOLD = 0.1
#: Rest of the path within which no new primitive starts [m] (see Settling).
TAIL = 0.005


def decide_path(
    model: MotionModel | Decider,
    arm: ArmModel,
    positions: np.ndarray,
    start_q: np.ndarray,
    goal: np.ndarray | None = None,
    palm: np.ndarray | None = None,
    times: np.ndarray | None = None,
    params: MeasureParams | None = None,
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
        params: The measures' weights; default the motion model's.

    Returns:
        The decision (the winner and every g at each point) and the joint path.
    """
    positions = np.asarray(positions, dtype=float)
    times = (
        np.arange(len(positions)) * DEFAULT_STEP
        if times is None
        else np.asarray(times, dtype=float)
    )
    decider = _decider(model, times)
    params = params or decider.model.measures()
    end = positions[-1] if goal is None else np.asarray(goal, dtype=float)
    target = (float(end[0]), float(end[1]), float(end[2]))
    size = DecidingArm.of(arm)
    wanted = None if palm is None else tuple(float(v) for v in palm)
    made: list[Choice] = []
    settle = Settling(times, positions)

    def choose(k: int, kin: ChainState) -> Primitive:
        previous = made[-1] if made else None
        raw = decide_point(decider, kin, target, size, wanted, previous)
        made.append(settle(k, raw, previous))
        return BY_NAME[made[-1].name]

    tracked = track_path(arm, positions, start_q, choose, palm=palm, params=params)
    for k in range(len(made), len(tracked.q)):  # a joint-space detour
        kin = arm.kinematics(tracked.q[k])
        raw = decide_point(decider, kin, target, size, wanted, made[-1])
        made.append(settle(k, raw, made[-1]))
    return decision_message(arm, times, made, params), tracked


class Settling:
    """Along a path, when one primitive hands over to the next.

    The motion variables are discretised (``services.fit.discretize``); where
    one sits on a state's edge the winner of eq. 10 can flip back and forth
    between neighbouring points, and each flip would start a sub-movement of
    the arm lasting a few milliseconds, which no person makes. So, as in the
    paper's Table 4 where each primitive of a reach occurs once, in order:

        - a challenger takes over only after winning ``SETTLE`` [s] in a row,
          and once the primitive in use has moved the arm ``HOLD`` [s] (a
          person's sub-movements last at least about that long);
        - a primitive that has handed over does not come back;
        - within ``TAIL`` [m] of the goal (along the rest of the path) the
          primitive in use finishes the movement.

    The decision recorded at a point is the primitive in use there, with
    every g as computed at that point, so a reader still sees who led.
    """

    def __init__(self, times: np.ndarray, positions: np.ndarray) -> None:
        self.times: list[float] = np.asarray(times, dtype=float).tolist()
        self.left: list[float] = _length_left(positions).tolist()
        self.challenger: int | None = None
        self.since = 0.0
        self.done: set[int] = set()
        self.began = self.times[0]

    def __call__(self, k: int, raw: Choice, previous: Choice | None) -> Choice:
        if previous is None or raw.candidate == previous.candidate:
            self.challenger = None
            return raw
        if raw.candidate in self.done or self.left[min(k, len(self.left) - 1)] < TAIL:
            self.challenger = None
            return _keep(previous, raw)
        if raw.candidate != self.challenger:
            self.challenger, self.since = raw.candidate, self.times[k]
        now = self.times[k] + _step(self.times, k)
        if now - self.since < SETTLE - 1e-9 or now - self.began < HOLD - 1e-9:
            return _keep(previous, raw)
        self.done.add(previous.candidate)
        self.began = self.times[k]
        self.challenger = None
        return raw


def _keep(previous: Choice, raw: Choice) -> Choice:
    """The primitive in use, with this point's g."""
    return Choice(previous.candidate, previous.state, raw.g)


def _step(times: list[float], k: int) -> float:
    """Interval the decision at point k covers [s]."""
    return times[k] - times[k - 1] if 0 < k < len(times) else 0.0


def _length_left(positions: np.ndarray) -> np.ndarray:
    """Path length from each point to the end [m], shape (n,)."""
    pieces = np.linalg.norm(np.diff(positions, axis=0), axis=1)
    return np.concatenate([np.cumsum(pieces[::-1])[::-1], [0.0]])


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


def decision_message(
    arm: ArmModel,
    times: np.ndarray,
    made: list[Choice],
    measures: MeasureParams | None = None,
) -> Decision:
    """The ``Decision`` message of recorded choices (columns: one entry per point).

    ``measures``: the weights the path was tracked with (default the shipped).
    """
    names = [choice.name for choice in made]
    return Decision.model_validate(
        {
            "arm": arm.side,
            "times": np.asarray(times, dtype=float).tolist(),
            "primitives": names,
            "candidates": list(CANDIDATES),
            "g": [list(choice.g) for choice in made],
            "matrices": {name: BY_NAME[name].matrix for name in dict.fromkeys(names)},
            "measures": measures or MeasureParams(),
        }
    )


def _decider(model: MotionModel | Decider, times: np.ndarray) -> Decider:
    """The compiled model for decisions at the path's sample interval."""
    step = float(np.median(np.diff(times))) if len(times) > 1 else DEFAULT_STEP
    base = model if isinstance(model, Decider) else Decider(model)
    return base if abs(base.step - step) < 1e-12 else base.with_step(step)
