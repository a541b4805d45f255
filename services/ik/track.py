"""Follow a wrist path point by point, each point moved by its own primitive.

This is the loop the motion decision, the IK service and the planner share:
``choose(k, kin)`` names the primitive for path point k from the arm's state
there (the motion decision, or a list of decisions already made), and one
step of eq. 14 on that primitive's active joints, with its measure, moves the
arm to the point. Run twice with the same choices it gives the same joint
path, bit for bit, which is what lets the decide and ik services split the
work.

A primitive's measure is built when its phase starts (when the chosen
primitive changes), from the posture there: H_G remembers where its elbow
started and how far the wrist was from the goal (eq. 20-21).

Where a primitive's joints cannot follow the path (a one-joint primitive off
its circle, the shoulder swing off its sphere) the wrist leaves the path; if
it strays more than ``PROMOTE_AFTER`` the point is moved by the full-arm
primitive of the same task instead, and the label says so. At the last point
the tracker converges to the goal exactly.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from services.ik.gpm import gpm_step
from services.ik.iterate import converge
from services.ik.kernel.chain import Chain, ChainState, chain_for
from services.ik.measures import Measure, MeasureParams
from services.ik.measures import factory as measure_factory
from services.ik.task import WristTask, controls_radius
from shared.messages.method import Method
from shared.primitives import FULL_GRASP, FULL_REACH, Primitive
from shared.robot.arm_model import ArmModel

#: Chooses the primitive for path point k from the arm's state there. The
#: state is a ChainState: it reads like shared.robot.Kinematics (numpy
#: attributes shoulder, elbow, wrist, wrist_rotation, ...), and its float
#: fields (origins, rot, qf) are cheaper.
Chooser = Callable[[int, ChainState], Primitive]

#: Null-space gain while following a path [rad^2 per unit of H].
ALPHA = 1.0
#: Largest joint change per path point by the task / null-space part [rad].
MAX_STEP, MAX_NULL_STEP = 0.2, 0.02
#: Newton iterations per path point at most, and their stopping error [m].
ITERATIONS, CLOSE_ENOUGH = 3, 1e-4
#: Distance from the path beyond which a point is moved by the full-arm primitive [m].
PROMOTE_AFTER = 0.005
#: Largest wrist error accepted at the goal before the full arm takes over [m].
ARRIVED = 1e-5
ALL_JOINTS = (0, 1, 2, 3, 4)
POSITION_JOINTS = {0, 1, 2, 3}


class TrackedPath(NamedTuple):
    """A joint path that follows a wrist path.

    Attributes:
        q: Joint angles [rad], shape (n, 5).
        wrist: Wrist positions reached [m], shape (n, 3).
        labels: What moved the arm at each point: a primitive's name, or the
            baseline method's name, shape (n,).
    """

    q: np.ndarray
    wrist: np.ndarray
    labels: list[str]


class _Phase(NamedTuple):
    label: str
    active: tuple[int, ...]
    measure: Measure
    task: WristTask


def track_path(
    arm: ArmModel,
    positions: np.ndarray,
    start: np.ndarray,
    choose: Chooser | None,
    *,
    method: Method = Method.MP,
    palm: np.ndarray | None = None,
    params: MeasureParams | None = None,
) -> TrackedPath:
    """Joint angles that move the wrist along ``positions``.

    Args:
        arm: The arm.
        positions: Wrist path [m], shape (n, 3); the last point is the goal.
        start: Posture at the start [rad], shape (5,), within the limits.
        choose: The primitive for each point (method ``mp``); ignored by the
            baselines, which move all joints.
        method: ``mp``, ``least-norm`` or ``single``.
        palm: Palm direction to reach (unit, shape (3,)) for primitives that
            turn the wrist, or ``None``.
        params: Measure coefficients (defaults if ``None``).

    Returns:
        The tracked path; ``q`` stays within the joint limits.
    """
    params = params or MeasureParams()
    chain = chain_for(arm)
    points = np.asarray(positions, dtype=float).tolist()
    goal = points[-1]
    q = [float(v) for v in start]
    out_q: list[list[float]] = []
    out_wrist: list[tuple[float, float, float]] = []
    labels: list[str] = []
    phase: _Phase | None = None
    st = chain.state(q)
    for k, point in enumerate(points):
        wanted = _wanted(method, choose, k, st)
        if phase is None or phase.label != _label(method, wanted):
            phase = _start_phase(chain, method, wanted, st, goal, palm, params)
        q, st = _follow(chain, phase, point, q, st)
        if wanted is not None and _strays(st, point, wanted):
            phase = _start_phase(chain, method, _full(wanted), st, goal, palm, params)
            q, st = _follow(chain, phase, point, q, st)
        if k == len(points) - 1:
            q, st, phase = _arrive(chain, phase, point, q, wanted, method, palm, params)
        out_q.append(q)
        out_wrist.append(st.p_wrist)
        labels.append(phase.label)
    return TrackedPath(np.array(out_q), np.array(out_wrist), labels)


def _wanted(
    method: Method, choose: Chooser | None, k: int, st: ChainState
) -> Primitive | None:
    if method is not Method.MP:
        return None
    if choose is None:
        raise ValueError("method mp needs a chooser of primitives")
    return choose(k, st)


def _label(method: Method, primitive: Primitive | None) -> str:
    return method.value if primitive is None else primitive.name


def _start_phase(
    chain: Chain,
    method: Method,
    primitive: Primitive | None,
    st: ChainState,
    goal: list[float],
    palm: np.ndarray | None,
    params: MeasureParams,
) -> _Phase:
    """Active joints, measure and task of a new phase, built at ``st``."""
    sign = chain.side.sign
    if primitive is None:
        factory = measure_factory.for_baseline(method, params)
        task = WristTask.make(goal, palm, sign)
        return _Phase(method.value, ALL_JOINTS, factory(st), task)
    factory = measure_factory.for_primitive(primitive, goal, params)
    turn = palm if primitive.orients_wrist else None
    task = WristTask.make(goal, turn, sign, controls_radius(primitive.active))
    return _Phase(primitive.name, primitive.active, factory(st), task)


def _follow(
    chain: Chain, phase: _Phase, point: list[float], q: list[float], st: ChainState
) -> tuple[list[float], ChainState]:
    """Steps of eq. 14 towards ``point``: one, more only while still off it.

    The state after each step is the next step's (and the next point's)
    state, so checking the error costs nothing extra. A primitive that cannot
    reach every point takes one step: iterating would not bring it closer.
    """
    task = phase.task.at(point)
    iterations = ITERATIONS if set(phase.active) >= POSITION_JOINTS else 1
    for _ in range(iterations):
        err, cols = task.residual(st)
        step = gpm_step(
            q, err, cols, phase.measure.gradient(st), phase.active,
            chain.lower, chain.upper, ALPHA, MAX_STEP, MAX_NULL_STEP,
        )  # fmt: skip
        q = [a + b for a, b in zip(q, step.dq, strict=True)]
        st = chain.state(q)
        if task.position_error(st) < CLOSE_ENOUGH:
            break
    return q, st


def _arrive(
    chain: Chain,
    phase: _Phase,
    goal: list[float],
    q: list[float],
    wanted: Primitive | None,
    method: Method,
    palm: np.ndarray | None,
    params: MeasureParams,
) -> tuple[list[float], ChainState, _Phase]:
    """Converge onto the goal; if the phase's joints cannot, the full arm does."""
    task = phase.task.at(goal)
    q, _ = converge(chain, task, phase.active, phase.measure, q)
    st = chain.state(q)
    if wanted is None or task.position_error(st) <= ARRIVED:
        return q, st, phase
    phase = _start_phase(chain, method, _full(wanted), st, goal, palm, params)
    q, _ = converge(chain, phase.task.at(goal), phase.active, phase.measure, q)
    return q, chain.state(q), phase


def _strays(st: ChainState, point: list[float], wanted: Primitive) -> bool:
    """True if a primitive that cannot reach every point left the path too far."""
    if set(wanted.active) >= POSITION_JOINTS:
        return False
    return math.dist(st.p_wrist, point) > PROMOTE_AFTER


def _full(primitive: Primitive) -> Primitive:
    """The full-arm primitive with the same wrist task."""
    return FULL_GRASP if primitive.orients_wrist else FULL_REACH
