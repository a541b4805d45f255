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

Each step is :func:`services.ik.weighted.weighted_step`: the primitive's
active joints move freely and the others are ``LOCKED`` (weighted, not
frozen), so the wrist stays on the path even where the primitive's own
joints cannot follow it all (a shoulder swing cannot change the hand's
distance from the shoulder); a locked joint then moves only in the part of
the task the active ones cannot do. Joints near a limit give way smoothly.
Where the task also turns the palm, the locked joints are less locked
(``LOCKED_TURNING``): the demonstrations say the arm shares a roll the
wrist cannot make (see its comment for the figures).

Smoothness (the joint path is later timed by Ruckig, and a person's joints
start and stop with the hand):
    - The null-space gain at each point is proportional to how far the hand
      moves there, so self-motion follows the hand's bell-shaped speed and
      vanishes where the hand is at rest.
    - Self-motion and a change of primitive are measured along the path,
      not in its samples: a path of more than ``NOMINAL_STEPS`` steps (a
      slow one at the same rate) spreads them over proportionally more
      points, so a path sampled k times as densely passes through nearly
      the same postures (the baselines' within a few mrad) and, slowed
      down, the joints' speeds, accelerations and jerks fall with the
      hand's. (Counted in samples, a 60 s reach at 100 Hz got sixty times
      the self-motion of a 1 s one, at the sample rate: ElbowYaw swung
      0.8 rad in 1.7 s while the hand crept, its largest second difference
      8e-4 to 6e-4 rad whether the reach took 10 s or 300 s.)
    - A new primitive takes over across ``BLEND`` points (150 ms at 100 Hz):
      each step there is the old phase's and the new one's, weighted by a
      smoothstep, as a person's sub-movements overlap (Flash and Henis
      1991). Over fewer points the joints' change of velocity at a switch
      set the pace of the whole reach (measured on the 16 grid reaches:
      5 points, 1.5 times the human duration; 15 points, 1.0 times).
    - Exactly one step per point: the small residual of each step is removed
      by the next one, a smooth recurrence. (Iterating only where the
      residual crossed a threshold made a sawtooth that was invisible in
      position but multiplied the jerk tenfold.)
    - At the goal only the wrist task is converged (no null-space jump),
      with every joint, as the steps before it moved every joint. (With the
      primitive's own joints alone, one of them near a limit met the last
      micrometres by moving 0.5 mrad where the path had brought it to rest,
      a hook the timing paid for over the whole reach: 5.4 times the human
      duration on one random reach of ``armplan experiment pace``, 3.9 now.)
    - A wanted palm turns with the hand: at each point the roll still to
      make is the roll the start posture lacks times the part of the path
      still ahead, so the palm arrives with the hand. (Asked for the final
      palm from the first point on, the arm turned it within the first few
      points, while the hand had hardly moved and, near a straight elbow,
      mostly with ElbowYaw: postures further from the demonstrations', and
      reaches with a palm slowed to several times the human duration.)

If the arm cannot follow the path within its limits (more than
``DETOUR_AFTER`` off and still drifting away), chatters along it (a joint
stepping ``CHATTER`` or more one way and then the other at the next point:
with a joint on its limit the others can meet at a fold, where the step
that does the task flips sign from one point to the next; capped at
``MAX_STEP`` the joint went to and fro across it for dozens of points, a
sawtooth the timing could only follow by stopping at every tooth), ends it
more than ``MISSED`` from the goal, or could meet the goal only by a jump (a
joint moving more than ``JUMP`` at the last point, typically a palm that a
joint on its limit kept from turning, met at the end by swinging another
joint by up to a radian: no timing can make that smooth), the whole
movement goes in joint space from the start to the goal posture solved by
:func:`services.ik.solve`, and ``detour_from`` is 0.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from itertools import pairwise
from typing import Final, NamedTuple

import numpy as np

from services.ik.iterate import converge
from services.ik.kernel.chain import Chain, ChainState, chain_for
from services.ik.measures import Measure, MeasureParams, NoMeasure
from services.ik.measures import factory as measure_factory
from services.ik.solver import solve
from services.ik.task import WristTask
from services.ik.weighted import LOCKED, LOCKED_TURNING, weighted_step
from shared.geometry.palm import roll_error
from shared.messages.method import Method
from shared.primitives import FULL_GRASP, FULL_REACH, Primitive, turning_the_wrist
from shared.robot.arm_model import ArmModel

#: Chooses the primitive for path point k from the arm's state there. The
#: state is a ChainState: it reads like shared.robot.Kinematics (numpy
#: attributes shoulder, elbow, wrist, wrist_rotation, ...), and its float
#: fields (origins, rot, qf) are cheaper.
Chooser = Callable[[int, ChainState], Primitive]

#: Null-space gain at a point where the hand moves its unit step (``_gains``)
#: [rad^2/unit of H].
ALPHA: Final = 1.0
#: Largest joint change per path point by the task part [rad], and by the
#: null-space part at a point where the hand moves its unit step [rad].
MAX_STEP: Final = 0.1
MAX_NULL_STEP: Final = 0.01
#: Joints closer than this to a limit they move towards give way [rad].
MARGIN: Final = 0.2
#: Distance from the path beyond which the full arm gives up the path [m].
DETOUR_AFTER: Final = 0.02
#: Points over which a new phase takes over from the old one (a path of
#: over ``NOMINAL_STEPS`` steps: as large a share of its points).
BLEND: Final = 15
#: Steps of a path the self-motion and the blends are counted in, at most.
#: Up to this many steps, every step is one; a path of more divides the
#: same self-motion and blends among its points (``_gains``, ``_blend``).
#: The planner's reaches (100 points per second of a human reach of at most
#: 1.8 s: up to 177 points) and the paper's experiments (101) have fewer,
#: so their joint paths are unchanged, bit for bit.
NOMINAL_STEPS: Final = 200
#: Largest wrist error at the goal before the full arm takes over there [m].
ARRIVED: Final = 1e-6
#: Wrist error at the goal, after the full arm tried, beyond which the
#: movement goes in joint space instead (a joint limit in the way) [m].
MISSED: Final = 1e-5
#: Largest change of a joint at the goal's convergence [rad]: removing the
#: last step's residual takes far less; more is another posture, a jump.
JUMP: Final = 0.01
#: A joint that steps at least this much one way and then the other, at two
#: consecutive points, chatters [rad]: 5 rad/s reversed within one point.
CHATTER: Final = 0.05
ALL_JOINTS: Final[tuple[int, ...]] = (0, 1, 2, 3, 4)
#: A path shorter than this does not move the hand [m] (a turn in place:
#: its length is rounding noise, which as a scale made the null-space gains
#: noise over noise, and the joint path jumped).
STILL: Final = 1e-12


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


class _Phase:
    """A primitive's phase: its label, active joints, measure and wrist task.

    ``base`` is each joint's weight in the step: 1 if active, else
    ``LOCKED``, or ``LOCKED_TURNING`` where the task turns the palm.

    A plain class, not a NamedTuple: compiled, its fields are read directly
    (the tracker reads them several times per path point).
    """

    def __init__(
        self, label: str, active: tuple[int, ...], measure: Measure, task: WristTask
    ) -> None:
        self.label, self.active, self.measure, self.task = label, active, measure, task
        locked = LOCKED if task.palm is None else LOCKED_TURNING
        self.base = [1.0 if k in active else locked for k in range(5)]


class _Follow:
    """What a path-following run works with.

    Attributes:
        chain: The arm's float kinematics.
        method: ``mp`` or a baseline.
        goal: The path's last point [m], 3 floats.
        palm: Palm direction to reach (unit, (3,)), or None.
        params: Measure coefficients.
        mean_step: Mean distance between path points [m].
    """

    def __init__(
        self,
        chain: Chain,
        method: Method,
        goal: list[float],
        palm: np.ndarray | None,
        params: MeasureParams,
        mean_step: float,
    ) -> None:
        self.chain, self.method, self.goal, self.palm = chain, method, goal, palm
        self.params, self.mean_step = params, mean_step


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
    points: list[list[float]] = np.asarray(positions, dtype=float).tolist()
    gains, mean_step = _gains(points)
    run = _Follow(
        chain_for(arm), method, points[-1], palm, params or MeasureParams(), mean_step
    )
    begin = q = [float(v) for v in start]
    out_q: list[list[float]] = []
    out_wrist: list[tuple[float, float, float]] = []
    labels: list[str] = []
    phases = _Phases(run, _blend(len(points)))
    st = run.chain.state(q)
    roll_left = _roll_left(run, points, st)
    previous = [0.0] * 5
    for k, point in enumerate(points):
        wanted = _wanted(method, choose, k, st)
        phases.update(wanted, st)
        if k > 0 or len(points) == 1:
            # The path starts where the arm is: its first posture is the
            # start, also when the palm is still to turn (the next steps do).
            q, st, step = _follow(
                run.chain, phases, point, roll_left[k], q, st, gains[k]
            )
            if _chatters(previous, step):
                return _detour(arm, run, points, begin, phases.phase)
            previous = step
        if phases.lost(st, point):
            return _detour(arm, run, points, begin, phases.phase)
        if k == len(points) - 1:
            last = q
            q, st = _arrive(run, phases, point, q, wanted)
            if (
                _jumped(last, q)
                or phases.phase.task.at(point).position_error(st) > MISSED
            ):
                return _detour(arm, run, points, begin, phases.phase)
        out_q.append(q)
        out_wrist.append(st.p_wrist)
        labels.append(phases.phase.label)
    return TrackedPath(np.array(out_q), np.array(out_wrist), labels)


class _Phases:
    """The phase in use and the one it is taking over from.

    A new phase takes over over ``points`` points (``_blend``): each
    point's step is the old phase's and the new one's, weighted by a
    smoothstep from 0 to 1, so the joints change velocity smoothly at a
    change of primitive.
    """

    def __init__(self, run: _Follow, points: int) -> None:
        self.run, self.points = run, points
        self.phase: _Phase
        self.started = False
        self.old: _Phase | None = None
        self.left = 0
        self.last_miss = 0.0

    def update(self, wanted: Primitive | None, st: ChainState) -> None:
        """Start the phase of ``wanted`` if it is not the one in use.

        With a wanted palm direction every primitive turns the wrist too
        (``turning_the_wrist``): NAO meets the palm only with WristYaw, and a
        model fitted on reaches without a wanted palm never picks W_R.
        """
        if wanted is not None and self.run.palm is not None:
            wanted = turning_the_wrist(wanted)
        label = _label(self.run.method, wanted)
        if not self.started:
            self.phase, self.started = _start_phase(self.run, wanted, st), True
        elif label != self.phase.label:
            self._switch(_start_phase(self.run, wanted, st))

    def promote(self, wanted: Primitive, st: ChainState) -> None:
        """Hand the rest to the full-arm primitive of ``wanted``'s task.

        With a wanted palm that is the grasping one, whatever ``wanted`` is
        (as in :meth:`update`): the palm must still be met at the goal.
        """
        if self.run.palm is not None:
            wanted = turning_the_wrist(wanted)
        self._switch(_start_phase(self.run, _full(wanted), st))

    def lost(self, st: ChainState, point: list[float]) -> bool:
        """True if the wrist misses ``point`` by over ``DETOUR_AFTER``, growing.

        A shrinking miss is a catch-up under way; during a change of phase the
        blend may let it grow for a few points, which does not count.
        """
        miss = self.phase.task.at(point).position_error(st)
        growing = miss > self.last_miss
        self.last_miss = miss
        return miss > DETOUR_AFTER and growing and not self.left

    def blend(self) -> tuple[_Phase | None, float]:
        """(the phase being taken over from, the new phase's weight) at this point."""
        if not self.left:
            return None, 1.0
        t = (self.points - self.left + 1) / (self.points + 1)
        self.left -= 1
        return self.old, t * t * (3.0 - 2.0 * t)

    def _switch(self, new: _Phase) -> None:
        self.old, self.left, self.phase = self.phase, self.points, new


def _roll_left(run: _Follow, points: list[list[float]], st: ChainState) -> list[float]:
    """The palm's roll still to make at each point [rad]: it turns with the hand.

    The roll the start posture ``st`` lacks, times the part of the path still
    ahead (``_progress``); all zero without a palm.
    """
    if run.palm is None:
        return [0.0] * len(points)
    palm = [float(v) for v in run.palm]
    total = roll_error(st.rot, run.chain.side.sign, palm)
    return [(1.0 - s) * total for s in _progress(points)]


def _progress(points: list[list[float]]) -> list[float]:
    """Each point's share of the path's length, 0 to 1.

    Where the hand does not move at all (a turn in place), the minimum-jerk
    share of the points: the turn starts and ends at rest, as the hand's
    bell-shaped speed would have made it.
    """
    steps = _steps(points)
    length = math.fsum(steps)
    last = max(len(points) - 1, 1)
    if length <= STILL:
        return [_minimum_jerk(k / last) for k in range(len(points))]
    out, done = [], 0.0
    for step in steps:
        done += step
        out.append(done / length)
    return out


def _minimum_jerk(tau: float) -> float:
    """The minimum-jerk blend 10 t^3 - 15 t^4 + 6 t^5 of ``tau`` in [0, 1]."""
    return tau**3 * (10.0 - 15.0 * tau + 6.0 * tau * tau)


def _steps(points: list[list[float]]) -> list[float]:
    """The hand's step to each point from the one before [m] (0 for the first)."""
    return [0.0] + [math.dist(a, b) for a, b in pairwise(points)]


def _gains(points: list[list[float]]) -> tuple[list[float], float]:
    """Gain factor per point (its hand step over the unit step), and the mean [m].

    The unit step is the mean step, or for a path of over ``NOMINAL_STEPS``
    steps its length over ``NOMINAL_STEPS``: the gains then add up to
    ``NOMINAL_STEPS``, not to the number of steps, so a densely sampled
    path gets the self-motion of the same path at ``NOMINAL_STEPS`` steps,
    in smaller steps.
    """
    steps = _steps(points)
    if math.fsum(steps) <= STILL:  # the hand stands still: no self-motion
        return [0.0] * len(steps), 0.0
    mean = math.fsum(steps) / max(len(steps) - 1, 1)
    unit = max(mean, math.fsum(steps) / NOMINAL_STEPS)
    return [s / unit for s in steps], mean


def _blend(points: int) -> int:
    """Points a change of phase is blended over on a path of ``points`` points.

    ``BLEND``, or on a path of over ``NOMINAL_STEPS`` steps as large a share
    of its steps as ``BLEND`` is of ``NOMINAL_STEPS``.
    """
    return max(BLEND, round(BLEND * (points - 1) / NOMINAL_STEPS))


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
        task = WristTask.make(run.goal, turn, sign)
        label, active = primitive.name, primitive.active
    return _Phase(label, active, factory(st), task)


def _follow(
    chain: Chain,
    phases: _Phases,
    point: list[float],
    roll_left: float,
    q: list[float],
    st: ChainState,
    gain: float,
) -> tuple[list[float], ChainState, list[float]]:
    """One step of eq. 14 towards ``point``, null-space gain scaled by ``gain``.

    ``roll_left`` is the palm's roll still to make there [rad] (``_roll_left``).
    During a change of phase the step blends the old phase's and the new
    one's. Returns the posture after the step, its state (the next point's)
    and the step [rad].
    """
    old, weight = phases.blend()
    dq = _step(chain, phases.phase, point, roll_left, q, st, gain)
    if old is not None:
        before = _step(chain, old, point, roll_left, q, st, gain)
        dq = [weight * dq[k] + (1.0 - weight) * before[k] for k in range(len(dq))]
    q = [q[k] + dq[k] for k in range(len(q))]
    return q, chain.state(q), dq


def _step(
    chain: Chain,
    phase: _Phase,
    point: list[float],
    roll_left: float,
    q: list[float],
    st: ChainState,
    gain: float,
) -> list[float]:
    """The weighted step of ``phase`` towards ``point`` [rad], 5 floats."""
    err, cols = phase.task.at(point, roll_left).residual(st)
    return weighted_step(
        q, err, cols, phase.measure.gradient(st), phase.base, chain.lower, chain.upper,
        ALPHA * gain, MAX_STEP, MAX_NULL_STEP * gain, MARGIN,
    )  # fmt: skip


def _arrive(
    run: _Follow,
    phases: _Phases,
    goal: list[float],
    q: list[float],
    wanted: Primitive | None,
) -> tuple[list[float], ChainState]:
    """Converge the wrist task onto the goal with every joint, no null-space motion.

    If the phase's task leaves the wrist more than ``ARRIVED`` from the goal
    (a task of the wrist's direction only leaves its distance), the
    full-arm primitive of the same task converges the position.
    """
    phase = phases.phase
    q, _ = converge(run.chain, phase.task.at(goal), ALL_JOINTS, NoMeasure(), q)
    st = run.chain.state(q)
    if wanted is None or phase.task.at(goal).position_error(st) <= ARRIVED:
        return q, st
    phases.promote(wanted, st)
    phase = phases.phase
    q, _ = converge(run.chain, phase.task.at(goal), phase.active, NoMeasure(), q)
    return q, run.chain.state(q)


def _chatters(before: list[float], step: list[float]) -> bool:
    """True if a joint reverses a step of ``CHATTER`` or more by another [rad]."""
    for a, b in zip(before, step, strict=True):
        if a * b < 0.0 and min(abs(a), abs(b)) >= CHATTER:
            return True
    return False


def _jumped(before: list[float], after: list[float]) -> bool:
    """True if a joint moved by more than ``JUMP`` from ``before`` to ``after``."""
    return any(abs(a - b) > JUMP for a, b in zip(after, before, strict=True))


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
    progress = np.array(_progress(points))
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
