"""A trial is one reach: one mostly still, or far longer, is not.

``armplan fit`` takes every sample of a trial as part of a reach from its
start to its goal (its last sample). A recording of one reach and then
minutes of stillness, taken as one trial, gave a model of the stillness: a
W_P rate of 13,594 and one primitive for a whole reach. ``armplan demos
import`` refuses such a trial (``long_trial_problem``) unless told to keep
it.

The wrist moves from when it first leaves its start, by more than
``LEFT_FRACTION`` of the distance from start to goal (at least
``LEFT_AT_LEAST``), until it last comes that near its goal; before and
after, it is still.
"""

from __future__ import annotations

import numpy as np

from shared.demos.rotations import FloatArray
from shared.demos.trial import Trial

#: How far the wrist must leave its start, or be from its goal, to move,
#: relative to the start-goal distance (a minimum-jerk reach spends 13 % of
#: its time at each end within 2 % of the way).
LEFT_FRACTION = 0.02
#: ... and at least this far [m] (NAO's arm: about 8 mm of a human's, above
#: the markers' jitter).
LEFT_AT_LEAST = 0.003
#: Longest stillness [s] before the wrist moves, and again after it arrives:
#: a capture's rest before the reach and its hold at the goal, each judged
#: alone (judged together, 1 s of each around a 1 s reach was refused, since
#: a minimum-jerk reach itself spends about a quarter of its time within 2 %
#: of its ends).
STILL_LIMIT = 3.0
#: Longest trial [s]: a reach takes a second or two.
LONGEST_REACH = 10.0


def moving_span(times: FloatArray, wrist: FloatArray) -> tuple[float, float]:
    """When the wrist moves: (from, to) [s], times shape (n,), wrist (n, 3) [m]."""
    start, goal = wrist[0], wrist[-1]
    near = max(LEFT_FRACTION * float(np.linalg.norm(goal - start)), LEFT_AT_LEAST)
    left = np.flatnonzero(np.linalg.norm(wrist - start, axis=1) > near)
    away = np.flatnonzero(np.linalg.norm(wrist - goal, axis=1) > near)
    if not left.size or not away.size:
        return float(times[0]), float(times[0])
    last = min(int(away[-1]) + 1, len(times) - 1)
    return float(times[left[0]]), float(times[last])


def long_trial_problem(trial: Trial) -> str | None:
    """What makes ``trial`` more than one reach, or ``None`` if nothing does.

    Still (``moving_span``) for more than ``STILL_LIMIT`` before the wrist
    moves or after it arrives, or longer than ``LONGEST_REACH``.
    """
    duration = float(trial.times[-1] - trial.times[0])
    start, end = moving_span(trial.times, trial.wrist)
    named = f"trial {trial.trial} of subject {trial.subject!r} lasts {duration:.1f} s"
    moves = f"the wrist moves from {start:.2f} s to {end:.2f} s"
    ends = (
        (start - float(trial.times[0]), "before it moves"),
        (float(trial.times[-1]) - end, "at its goal"),
    )
    for still, where in ends:
        if still > STILL_LIMIT:
            return (
                f"{named}, its wrist still for {still:.1f} s {where} (at most "
                f"{STILL_LIMIT:g} s; {moves}): a trial must be one reach, from its "
                "start to its goal, and armplan fit would count the stillness as "
                "reaching"
            )
    if duration > LONGEST_REACH:
        return (
            f"{named}, far longer than a reach (at most {LONGEST_REACH:g} s; "
            f"{moves}): a trial must be one reach, from its start to its goal"
        )
    return None
