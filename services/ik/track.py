"""Follow a wrist path point by point, each point moved by its own primitive.

This is the loop the motion decision, the IK service and the planner share:
``choose(k, kin)`` names the primitive for path point k from the arm's state
there (the motion decision, or a list of decisions already made), and a step
of eq. 14 on that primitive's active joints, with its measure, moves the arm
to the point. Run twice with the same choices it gives the same joint path,
bit for bit, which is what lets the decide and ik services split the work.

A primitive's measure is built when its phase starts (when the chosen
primitive changes), from the posture there: H_G remembers where its elbow
started and how far the wrist was from the goal (eq. 20-21).

Smoothness (the joint path is later timed by Ruckig, and a person's joints
start and stop with the hand):
    - The null-space gain at each point is proportional to how far the hand
      moves there, so self-motion follows the hand's bell-shaped speed and
      vanishes where the hand is at rest.
    - Within ``MARGIN`` of a limit a joint's null-space motion slows down
      smoothly, so it does not stop dead on the limit (see gpm.py). (A
      limit-avoidance gradient in the null space was tried and made paths
      rougher: it switches on and off at its band's edges.)
    - Exactly one step per point: the small residual of each step is removed
      by the next one, a smooth recurrence. (Iterating only where the
      residual crossed a threshold made a sawtooth that was invisible in
      position but multiplied the jerk tenfold.)
    - At the goal only the wrist task is converged (no null-space jump).

Where a primitive's joints cannot follow the path (a one-joint primitive off
its circle, the shoulder swing off its sphere) the wrist leaves the path; if
it strays more than ``PROMOTE_AFTER`` the point is moved by the full-arm
primitive of the same task instead, and the label says so. If even the full
arm cannot follow within its limits (more than ``DETOUR_AFTER`` off), the
whole movement goes in joint space from the start to the goal posture solved
by :func:`services.ik.solve`, and ``detour_from`` is 0.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from itertools import pairwise
from typing import NamedTuple

import numpy as np

from services.ik.gpm import gpm_step
from services.ik.iterate import converge
from services.ik.kernel.chain import Chain, ChainState, chain_for
from services.ik.measures import Measure, MeasureParams, NoMeasure
from services.ik.measures import factory as measure_factory
from services.ik.solver import solve
from services.ik.task import WristTask, controls_radius
from shared.messages.method import Method
from shared.primitives import FULL_GRASP, FULL_REACH, Primitive
from shared.robot.arm_model import ArmModel

#: Chooses the primitive for path point k from the arm's state there. The
#: state is a ChainState: it reads like shared.robot.Kinematics (numpy
#: attributes shoulder, elbow, wrist, wrist_rotation, ...), and its float
#: fields (origins, rot, qf) are cheaper.
Chooser = Callable[[int, ChainState], Primitive]

#: Null-space gain at a point where the hand moves its mean step [rad^2/unit of H].
ALPHA = 1.0
#: Largest joint change per path point by the task part [rad], and by the
#: null-space part at a point where the hand moves its mean step [rad].
MAX_STEP, MAX_NULL_STEP = 0.1, 0.01
#: Joints moving towards a limit closer than this slow their null-space
#: motion down smoothly [rad].
MARGIN = 0.2
#: Distance from the path beyond which a point is moved by the full-arm primitive [m].
PROMOTE_AFTER = 0.005
#: Distance from the path beyond which the full arm gives up the path [m].
DETOUR_AFTER = 0.01
#: Largest wrist error at the goal before the full arm takes over there [m].
ARRIVED = 1e-6
ALL_JOINTS = (0, 1, 2, 3, 4)
POSITION_JOINTS = {0, 1, 2, 3}


class TrackedPath(NamedTuple):
    """A joint path that follows a wrist path.

    Attributes:
        q: Joint angles [rad], shape (n, 5).
        wrist: Wrist positions reached [m], shape (n, 3).
        labels: What moved the arm at each point: a primitive's name, or the
            baseline method's name, shape (n,).
        detour_from: 0 if the movement went in joint space to the goal
            because the wrist path could not be followed within the joint
            limits; None if the path was followed.
    """

    q: np.ndarray
    wrist: np.ndarray
    labels: list[str]
    detour_from: int | None = None


class _Phase(NamedTuple):
    label: str
    active: tuple[int, ...]
    measure: Measure
    task: WristTask


class _Follow(NamedTuple):
    """Where the path-following loop stands."""

    chain: Chain
    method: Method
    goal: list[float]
    palm: np.ndarray | None
    params: MeasureParams


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

    Raises:
        UnreachableTargetError: if the path cannot be followed and no posture
            within the limits reaches its end.
    """
    points = np.asarray(positions, dtype=float).tolist()
    run = _Follow(chain_for(arm), method, points[-1], palm, params or MeasureParams())
    gains = _gains(points)
    q = [float(v) for v in start]
    out_q: list[list[float]] = []
    labels: list[str] = []
    phase: _Phase | None = None
    st = run.chain.state(q)
    for k, point in enumerate(points):
        wanted = _wanted(method, choose, k, st)
        if phase is None or phase.label != _label(method, wanted):
            phase = _start_phase(run, wanted, st)
        q, st = _follow(run.chain, phase, point, q, st, gains[k])
        if wanted is not None and _strays(st, point, wanted, PROMOTE_AFTER):
            phase = _start_phase(run, _full(wanted), st)
            q, st = _follow(run.chain, phase, point, q, st, gains[k])
        if math.dist(st.p_wrist, point) > DETOUR_AFTER:
            return _detour(arm, run, points, [float(v) for v in start], phase)
        if k == len(points) - 1:
            q, st, phase = _arrive(run, phase, point, q, wanted)
        out_q.append(q)
        labels.append(phase.label)
    return TrackedPath(np.array(out_q), _wrists(run.chain, out_q), labels)


def _gains(points: list[list[float]]) -> list[float]:
    """Null-space gain factor per point: its hand step over the mean step."""
    steps = [0.0] + [math.dist(a, b) for a, b in pairwise(points)]
    mean = sum(steps) / max(len(steps) - 1, 1)
    return [s / mean if mean > 0.0 else 0.0 for s in steps]


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


def _start_phase(run: _Follow, primitive: Primitive | None, st: ChainState) -> _Phase:
    """Active joints, measure and task of a new phase, built at ``st``."""
    sign = run.chain.side.sign
    if primitive is None:
        factory = measure_factory.for_baseline(run.method, run.params)
        task = WristTask.make(run.goal, run.palm, sign)
        label, active = run.method.value, ALL_JOINTS
    else:
        factory = measure_factory.for_primitive(primitive, run.goal, run.params)
        turn = run.palm if primitive.orients_wrist else None
        task = WristTask.make(run.goal, turn, sign, controls_radius(primitive.active))
        label, active = primitive.name, primitive.active
    return _Phase(label, active, factory(st), task)


def _follow(
    chain: Chain,
    phase: _Phase,
    point: list[float],
    q: list[float],
    st: ChainState,
    gain: float,
) -> tuple[list[float], ChainState]:
    """One step of eq. 14 towards ``point``, null-space gain scaled by ``gain``.

    The state after the step is the next point's state.
    """
    err, cols = phase.task.at(point).residual(st)
    step = gpm_step(
        q, err, cols, phase.measure.gradient(st), phase.active, chain.lower,
        chain.upper, ALPHA * gain, MAX_STEP, MAX_NULL_STEP * gain, MARGIN,
    )  # fmt: skip
    q = [a + b for a, b in zip(q, step.dq, strict=True)]
    return q, chain.state(q)


def _arrive(
    run: _Follow,
    phase: _Phase,
    goal: list[float],
    q: list[float],
    wanted: Primitive | None,
) -> tuple[list[float], ChainState, _Phase]:
    """Converge the wrist task onto the goal, without null-space motion.

    If the phase's joints cannot bring the wrist within ``ARRIVED`` of the
    goal, the full-arm primitive of the same task does.
    """
    q, _ = converge(run.chain, phase.task.at(goal), phase.active, NoMeasure(), q)
    st = run.chain.state(q)
    if wanted is None or phase.task.at(goal).position_error(st) <= ARRIVED:
        return q, st, phase
    phase = _start_phase(run, _full(wanted), st)
    q, _ = converge(run.chain, phase.task.at(goal), phase.active, NoMeasure(), q)
    return q, run.chain.state(q), phase


def _strays(
    st: ChainState, point: list[float], wanted: Primitive, limit: float
) -> bool:
    """True if a primitive that cannot reach every point left the path too far."""
    if set(wanted.active) >= POSITION_JOINTS:
        return False
    return math.dist(st.p_wrist, point) > limit


def _full(primitive: Primitive) -> Primitive:
    """The full-arm primitive with the same wrist task."""
    return FULL_GRASP if primitive.orients_wrist else FULL_REACH


def _detour(
    arm: ArmModel,
    run: _Follow,
    points: list[list[float]],
    start: list[float],
    phase: _Phase,
) -> TrackedPath:
    """The whole movement in joint space, from ``start`` to the goal's posture.

    The goal posture is solved by :func:`services.ik.solve` (with restarts if
    needed) from the start posture; the joints blend to it with the planned
    wrist path's progress (its arc-length fraction), so the timing keeps the
    hand's speed profile while the wrist leaves the path it could not follow.
    Starting over from the start, rather than from where following failed,
    keeps the joint path smooth.
    """
    primitive = None if run.method is not Method.MP else _full_for(phase)
    base = np.array(start)
    goal = solve(
        arm,
        np.array(run.goal),
        method=run.method,
        primitive=None if primitive is None else primitive.name,
        palm=run.palm if primitive is None or primitive.orients_wrist else None,
        start=base,
        params=run.params,
    ).q
    steps = np.concatenate(([0.0], np.linalg.norm(np.diff(points, axis=0), axis=1)))
    progress = np.cumsum(steps) / max(float(steps.sum()), 1e-12)
    joints = base + progress[:, None] * (goal - base)
    label = run.method.value if primitive is None else primitive.name
    return TrackedPath(
        joints, _wrists(run.chain, joints.tolist()), [label] * len(points), 0
    )


def _full_for(phase: _Phase) -> Primitive:
    return FULL_GRASP if phase.task.palm is not None else FULL_REACH


def _wrists(chain: Chain, postures: list[list[float]]) -> np.ndarray:
    """Wrist positions of ``postures`` [m], shape (n, 3)."""
    return np.array([chain.state(q).p_wrist for q in postures])
