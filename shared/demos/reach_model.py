"""A human reach from the hanging arm to a point: which joints move, and when.

The model is kinematic and built from published regularities of human
reaching, not from the planner's performance measures (TPE, NTPE, H_G):

- Each degree of freedom follows the minimum-jerk time law over its own
  window (Flash and Hogan 1985): the shoulder (one rotation of the upper-arm
  frame along the geodesic, swing and humeral rotation together), the elbow
  flexion and the forearm roll.
- The shoulder leads and the elbow follows (Dounskaia 2005, the leading
  joint hypothesis): the shoulder starts at once and swings the arm, elbow
  angle held, towards the target; the elbow joins when the arm's pointing
  error (the angle, seen from the shoulder, between the target and the
  wrist of the arm bent as at the end) has fallen to ``coordination`` times
  the elbow's whole change. If it starts below that, both start together.
- A large elbow excursion ends alone: the shoulder stops a fraction
  ``FINAL_ELBOW_GAIN * (elbow change - FINAL_ELBOW_FROM)`` (at most
  ``FINAL_ELBOW_MAX``) of the movement before the end and the elbow
  finishes the last radial part.
- The forearm turns (pronation) for targets near and above shoulder height,
  by more for higher ones, during the phase in which shoulder and elbow move
  together; turns under ``ROLL_MIN`` are not made (the forearm keeps its
  roll).
- The final posture puts the wrist on the target with the elbow low and
  turned outwards, more for higher targets (the elbow stays below the
  shoulder-wrist line in natural reaching: Soechting et al. 1995).
- The duration grows with the hand's distance to the target, scaled so the
  paper's 16 points take 0.55-1.0 s, as in its Table 4.
- Variation: per subject a coordination constant, speed, swivel and roll
  habit; per trial the start posture, the end point (about 6 mm), timing;
  per sample 1 mm of marker noise.

Each sample is labelled with the primitive whose joints move at that time
(``shared.demos.labels``): a joint counts as moving once it has left its
start, and until it is within its end, by more than ``SETTLED``. So the
phases read S_R E_P W_P -> S_R E_PR W_P (or S_R E_PR W_PR while the forearm
turns) -> E_R W_P.

Sources:
    Flash T., Hogan N. (1985). J. Neurosci. 5(7), 1688-1703.
    Dounskaia N. (2005). The internal model and the leading joint
        hypothesis: implications for control of multi-joint movements.
        Exp. Brain Res. 166(1), 1-16.
    Soechting J. F., Buneo C. A., Herrmann U., Flanders M. (1995). Moving
        effortlessly in three dimensions: does Donders' law apply to arm
        movement? J. Neurosci. 15(9), 6271-6280.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from shared.demos.anthropometry import Subject
from shared.demos.arm_pose import (
    ArmPose,
    chain_points,
    frame_from_directions,
    pose_for_target,
)
from shared.demos.labels import labels_from_motion
from shared.demos.min_jerk import time_at_progress, window_progress
from shared.demos.rotations import (
    FloatArray,
    interpolate_frames,
    matrix_from_rotation_vector,
    rotation_angle,
    rotation_vector_from_matrix,
)

#: Upper-arm direction of the hanging right arm (slightly forward, abducted).
REST_UPPER_ARM = (0.04, -0.08, -1.0)
#: Elbow flexion of the hanging arm [rad] (about 14 degrees).
REST_FLEXION = 0.25
#: Trial-to-trial spread of the hanging posture [rad].
REST_SPREAD = 0.03
#: Movement time T = DURATION_PER_LENGTH * (hand-to-target distance / arm length) [s].
DURATION_PER_LENGTH = 0.80
#: The elbow joins when the arm's pointing error is this times the elbow's change.
COORDINATION = 0.45
#: Spread of the coordination constant between subjects.
COORDINATION_SPREAD = 0.07
#: Elbow-only final phase: fraction of T per radian of elbow change above FROM.
FINAL_ELBOW_GAIN, FINAL_ELBOW_FROM, FINAL_ELBOW_MAX = 0.45, 0.35, 0.30
#: Shortest overlap of shoulder and elbow, as a fraction of T.
MIN_OVERLAP = 0.15
#: Elbow turned outwards from straight down at the target [rad]:
#: SWIVEL_OUT + SWIVEL_PER_HEIGHT * (target height / arm length).
SWIVEL_OUT, SWIVEL_PER_HEIGHT = 0.35, 0.50
#: Final pronation [rad]: ROLL_PER_HEIGHT * (target height / arm length - ROLL_FROM),
#: none below ROLL_FROM.
ROLL_FROM, ROLL_PER_HEIGHT = -0.04, 5.0
#: Forearm turns smaller than this are not made [rad].
ROLL_MIN = 0.35
#: Spreads: subject habits [rad or relative], trial end point [m], markers [m].
HABIT_SPREAD, SPEED_SPREAD, TIMING_SPREAD = 0.08, 0.07, 0.03
ENDPOINT_SCATTER, MARKER_NOISE = 0.006, 0.001
#: A joint counts as moving when off both its start and its end by this [rad].
SETTLED = 0.025


class Style(NamedTuple):
    """A subject's habits.

    Attributes:
        coordination: When the elbow joins (see ``COORDINATION``).
        speed: Movement-time factor (1 = average).
        swivel: Elbow swivel habit, added to the model's [rad].
        roll: Pronation habit, added to the model's [rad].
    """

    coordination: float
    speed: float
    swivel: float
    roll: float


class ReachPlan(NamedTuple):
    """One reach: start and goal postures, duration and each joint's window.

    Attributes:
        start: Posture at t = 0.
        goal: Posture at t = duration.
        duration: Movement time T [s].
        elbow_start: When the elbow starts [s].
        shoulder_end: When the shoulder stops [s].
        roll_window: When the forearm turns (start, end) [s]; empty if equal.
    """

    start: ArmPose
    goal: ArmPose
    duration: float
    elbow_start: float
    shoulder_end: float
    roll_window: tuple[float, float]


class ReachSamples(NamedTuple):
    """A sampled reach in the subject's shoulder frame.

    Attributes:
        times: Sample times from the start [s], shape (n,).
        elbow: Elbow positions [m], shape (n, 3).
        wrist: Wrist positions [m], shape (n, 3).
        wrist_frame: Wrist frames, shape (n, 3, 3).
        labels: The primitive whose attributes change at each sample, (n,).
    """

    times: FloatArray
    elbow: FloatArray
    wrist: FloatArray
    wrist_frame: FloatArray
    labels: list[str]


#: The average subject's habits.
AVERAGE_STYLE = Style(COORDINATION, 1.0, 0.0, 0.0)


def draw_style(rng: np.random.Generator) -> Style:
    """A subject's habits, drawn from ``rng``."""
    return Style(
        float(rng.normal(COORDINATION, COORDINATION_SPREAD)),
        float(rng.normal(1.0, SPEED_SPREAD)),
        float(rng.normal(0.0, HABIT_SPREAD)),
        float(rng.normal(0.0, HABIT_SPREAD)),
    )


def rest_pose(rng: np.random.Generator | None = None) -> ArmPose:
    """The right arm hanging; with ``rng``, with trial-to-trial variation."""
    upper = np.array(REST_UPPER_ARM) / np.linalg.norm(REST_UPPER_ARM)
    flexion = REST_FLEXION
    if rng is not None:
        tilt = matrix_from_rotation_vector(rng.normal(0.0, REST_SPREAD, size=3))
        upper = tilt @ upper
        flexion += float(rng.normal(0.0, REST_SPREAD))
    forward = np.array([1.0, 0.0, 0.0])
    bend = forward - float(forward @ upper) * upper
    return ArmPose(frame_from_directions(upper, bend), flexion, 0.0)


def plan_reach(
    subject: Subject,
    style: Style,
    target: FloatArray,
    rng: np.random.Generator | None = None,
    start: ArmPose | None = None,
) -> ReachPlan:
    """Plan one trial's reach to ``target`` (shoulder frame [m], shape (3,)).

    With ``rng`` the trial varies (start posture, end point, timing); without,
    it is the model's noise-free reach. ``start`` replaces the hanging arm as
    the start posture (for a reach that follows another one).
    """
    length = subject.arm_length
    start = rest_pose(rng) if start is None else start
    end = target if rng is None else target + rng.normal(0.0, ENDPOINT_SCATTER, 3)
    height = float(end[2]) / length
    out = SWIVEL_OUT + SWIVEL_PER_HEIGHT * height + style.swivel
    # The final roll is the hanging arm's (0) plus the pronation for the
    # target; a start with another roll (a reach after a reach) turns to it.
    roll = -(ROLL_PER_HEIGHT * max(height - ROLL_FROM, 0.0) + style.roll)
    if abs(roll - start.roll) < ROLL_MIN:
        roll = start.roll
    goal = pose_for_target(end, subject.upper_arm, subject.forearm, math.pi - out, roll)
    hand = chain_points(
        start.frame[None],
        np.array([start.flexion]),
        np.array([start.roll]),
        subject.upper_arm,
        subject.forearm,
    ).wrist[0]
    distance = float(np.linalg.norm(end - hand)) / length
    duration = DURATION_PER_LENGTH * distance * style.speed
    if rng is not None:
        duration *= float(rng.normal(1.0, TIMING_SPREAD))
    return _windows(start, goal, duration, style.coordination, subject)


def _windows(
    start: ArmPose,
    goal: ArmPose,
    duration: float,
    coordination: float,
    subject: Subject,
) -> ReachPlan:
    """Each joint's window from the two postures (see the module docstring)."""
    elbow = abs(goal.flexion - start.flexion)
    final = min(
        max(FINAL_ELBOW_GAIN * (elbow - FINAL_ELBOW_FROM), 0.0), FINAL_ELBOW_MAX
    )
    shoulder_end = duration * (1.0 - final)
    joins = _swing_left_at(start, goal, coordination * elbow, subject)
    elbow_start = shoulder_end * time_at_progress(joins)
    elbow_start = min(elbow_start, shoulder_end - MIN_OVERLAP * duration)
    turning = goal.roll != start.roll
    roll_window = (elbow_start, shoulder_end) if turning else (0.0, 0.0)
    return ReachPlan(start, goal, duration, elbow_start, shoulder_end, roll_window)


def pointing_error(
    start: ArmPose, goal: ArmPose, progress: float, subject: Subject
) -> float:
    """How far the arm, bent as at the goal, points from the target [rad].

    The angle, seen from the shoulder, between the goal's wrist and where the
    wrist would be with the upper-arm frame ``progress`` of the way from
    ``start`` to ``goal`` and the elbow already at its final flexion.
    """
    return _Pointing(start, goal, subject).error(progress)


class _Pointing:
    """:func:`pointing_error` along one reach, its fixed parts computed once.

    The search for the elbow's start asks it 31 times a trial; building the
    two frames of ``interpolate_frames`` each time was two thirds of the
    synthetic set's making.
    """

    def __init__(self, start: ArmPose, goal: ArmPose, subject: Subject) -> None:
        bend = goal.flexion
        self._shape = np.array(  # the final arm's wrist in the upper-arm frame
            (
                subject.upper_arm + subject.forearm * math.cos(bend),
                0.0,
                -subject.forearm * math.sin(bend),
            )
        )
        self._start = start.frame
        self._step = rotation_vector_from_matrix(start.frame.T @ goal.frame)
        self._end = self._wrist(1.0)
        self._end_norm = float(np.linalg.norm(self._end))

    def _wrist(self, progress: float) -> np.ndarray:
        """The bent arm's wrist with the frame ``progress`` of the way [m], (3,)."""
        turn = matrix_from_rotation_vector(progress * self._step)
        return np.asarray((self._start @ turn) @ self._shape)

    def error(self, progress: float) -> float:
        """The pointing error at ``progress`` of the shoulder's way [rad]."""
        now = self._wrist(progress)
        cos = float(now @ self._end) / float(np.linalg.norm(now) * self._end_norm)
        return math.acos(min(max(cos, -1.0), 1.0))


def _swing_left_at(
    start: ArmPose, goal: ArmPose, swing: float, subject: Subject
) -> float:
    """Shoulder progress at which the pointing error falls to ``swing`` [rad]."""
    pointing = _Pointing(start, goal, subject)
    if pointing.error(0.0) <= swing:
        return 0.0
    low, high = 0.0, 1.0
    for _ in range(30):  # the error falls steadily along the geodesic
        mid = 0.5 * (low + high)
        if pointing.error(mid) > swing:
            low = mid
        else:
            high = mid
    return high


def sample_reach(plan: ReachPlan, subject: Subject, rate: float) -> ReachSamples:
    """The reach sampled at ``rate`` [Hz] from t = 0 to t = T, with labels."""
    n = max(2, round(plan.duration * rate) + 1)
    times = np.arange(n) / rate
    times[-1] = plan.duration
    shoulder = window_progress(times, 0.0, plan.shoulder_end)
    elbow = window_progress(times, plan.elbow_start, plan.duration)
    roll = window_progress(times, *plan.roll_window)
    frames = interpolate_frames(plan.start.frame, plan.goal.frame, shoulder)
    bend = plan.goal.flexion - plan.start.flexion
    turn = plan.goal.roll - plan.start.roll
    flexion = plan.start.flexion + elbow * bend
    rolls = plan.start.roll + roll * turn
    points = chain_points(frames, flexion, rolls, subject.upper_arm, subject.forearm)
    swing = rotation_angle(plan.start.frame, plan.goal.frame)
    labels = labels_from_motion(
        moving(shoulder, swing), moving(elbow, abs(bend)), moving(roll, abs(turn))
    )
    return ReachSamples(times, points.elbow, points.wrist, points.wrist_frame, labels)


def moving(progress: FloatArray, change: float) -> npt.NDArray[np.bool_]:
    """Whether a joint counts as moving: off its start and its end by > SETTLED.

    Args:
        progress: The joint's progress from start (0) to end (1), shape (n,).
        change: Its whole change [rad].
    """
    return (progress * change > SETTLED) & ((1.0 - progress) * change > SETTLED)
