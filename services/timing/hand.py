"""The hand's open fraction over a task: a smooth move in each dwell that asks for one.

A reach target may carry a hand action (``shared.messages.hand``: open or
close). The hand moves during the target's dwell, from the moment the arm
has stopped there (the rest begins) toward the action's goal, on a
minimum-jerk profile (``shared.demos.min_jerk``; at rest at both ends) as
short as the hand's limits allow (:func:`hand_duration`). If the dwell is
shorter, it is lengthened to the hand's time, so the arm leaves only once the
hand has closed or opened (:func:`hand_dwells`).

Before the first action the hand holds that action's other end
(``HandAction.before``): closed before a first ``open`` (it holds what it
is to let go of), open before a first ``close`` (it is about to grasp). The
robot bridge brings the hand there, slowly, with the arm's approach to the
start posture. An action whose goal the hand is already at does not move it.

The trajectory also carries the channel's exact rate and its rate
(:func:`hand_rates`), as it carries the joints' speeds and accelerations:
the bridge's curve between samples goes through them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from shared.demos.min_jerk import minimum_jerk_rates, window_progress
from shared.messages.hand import HandAction
from shared.robot.motion_limits import MotionLimits

#: Peaks of the minimum-jerk blend's speed, acceleration and jerk for a unit
#: move in unit time: 15/8, 10/sqrt(3) and 60.
PEAK_SPEED, PEAK_ACCELERATION, PEAK_JERK = 1.875, 10.0 / math.sqrt(3.0), 60.0
#: Tolerance on a whole number of periods [-] (float round-off only).
WHOLE = 1e-9


class HandMove(NamedTuple):
    """One move of the hand.

    Attributes:
        segment: The index of the segment (target) whose dwell holds it.
        start: Open fraction before it [-].
        goal: Open fraction after it [-].
        duration: Its length [s], a whole number of sample periods.
    """

    segment: int
    start: float
    goal: float
    duration: float


def hand_duration(travel: float, limits: MotionLimits, period: float) -> float:
    """Shortest minimum-jerk move of ``travel`` [-] within ``limits`` [s].

    A move ``h0 + travel * b(t / T)`` peaks at speed ``PEAK_SPEED |travel| /
    T``, acceleration ``PEAK_ACCELERATION |travel| / T^2`` and jerk
    ``PEAK_JERK |travel| / T^3``; the shortest ``T`` keeping the three within
    the hand's limits, rounded up to whole sample periods of ``period`` [s]
    (0 for no travel). A full close at the default limits: 0.45 s.
    """
    size = abs(travel)
    if size == 0.0:
        return 0.0
    shortest = max(
        PEAK_SPEED * size / float(limits.velocity[0]),
        math.sqrt(PEAK_ACCELERATION * size / float(limits.acceleration[0])),
        math.cbrt(PEAK_JERK * size / float(limits.jerk[0])),
    )
    return math.ceil(shortest / period - WHOLE) * period


def hand_moves(
    actions: Sequence[HandAction | None], limits: MotionLimits, period: float
) -> list[HandMove]:
    """The hand's moves for each segment's action (None: none), in order.

    The first action starts from its other end (``HandAction.before``); an
    action whose goal the hand is at already makes no move.
    """
    moves: list[HandMove] = []
    state: float | None = None
    for k, action in enumerate(actions):
        if action is None:
            continue
        start = action.before if state is None else state
        if action.goal != start:
            duration = hand_duration(action.goal - start, limits, period)
            moves.append(HandMove(k, start, action.goal, duration))
        state = action.goal
    return moves


def first_opening(actions: Sequence[HandAction | None]) -> float | None:
    """The open fraction the hand holds from the start [-], or None (no action)."""
    first = next((a for a in actions if a is not None), None)
    return None if first is None else first.before


def hand_dwells(dwells: Sequence[float], moves: Sequence[HandMove]) -> list[float]:
    """Each segment's dwell [s], lengthened to its hand move's duration if shorter."""
    longest = {move.segment: move.duration for move in moves}
    return [max(d, longest.get(k, 0.0)) for k, d in enumerate(dwells)]


def hand_channel(
    times: np.ndarray,
    rests: Sequence[int],
    moves: Sequence[HandMove],
    opening: float,
) -> np.ndarray:
    """The hand's open fraction at each sample [-], shape (m,).

    Args:
        times: Sample times [s], shape (m,).
        rests: For each segment, the sample at which its dwell begins.
        moves: The hand's moves (:func:`hand_moves`).
        opening: The open fraction held before the first move [-].
    """
    hand = np.full(len(times), float(opening))
    for move in moves:
        begin = float(times[rests[move.segment]])
        blend = window_progress(times, begin, begin + move.duration)
        after = times >= begin
        hand[after] = move.start + (move.goal - move.start) * blend[after]
    return hand


def hand_rates(
    times: np.ndarray, rests: Sequence[int], moves: Sequence[HandMove]
) -> tuple[np.ndarray, np.ndarray]:
    """The rate [1/s] and its rate [1/s^2] of :func:`hand_channel`, each (m,).

    Exact, from the minimum-jerk profile (0 at rest): the robot bridge's
    curve between samples follows them, where central differences of the
    samples would make a kink at each move's ends (18 times the planned
    jerk between 100 Hz samples played at 1000 fps).

    Args:
        times: Sample times [s], shape (m,).
        rests: For each segment, the sample at which its dwell begins.
        moves: The hand's moves (:func:`hand_moves`).
    """
    speed, acceleration = np.zeros(len(times)), np.zeros(len(times))
    for move in moves:
        begin = float(times[rests[move.segment]])
        travel, duration = move.goal - move.start, move.duration
        rate, change = minimum_jerk_rates((times - begin) / duration)
        speed += travel / duration * rate
        acceleration += travel / duration**2 * change
    return speed, acceleration


__all__ = [
    "HandMove",
    "first_opening",
    "hand_channel",
    "hand_duration",
    "hand_dwells",
    "hand_moves",
    "hand_rates",
]
