"""A trial is one reach: one mostly still, stopping, longer or shorter is not.

``armplan fit`` takes every sample of a trial as part of a reach from its
start to its goal (its last sample). A recording of one reach and then
minutes of stillness, taken as one trial, gave a model of the stillness: a
W_P rate of 13,594 and one primitive for a whole reach. Two reaches with a
0.8 s hold between, taken as one, made the W_R rate 2.80 /rad instead of
about 5.7: a wrist that stops on its way (``reach_pause``) is two reaches.
``armplan demos import`` refuses such trials (``long_trial_problem``)
unless told to keep them.

A trial that is no reach at all (``not_a_reach_problem``) is refused by
``armplan demos import`` and ``armplan fit`` alike, with no way round: a
wrist that ends where it started (8 static calibration takes beside 16
reaches doubled every rate, and labelled the still samples S_R E_P W_P),
or one that moves far more briefly than a person reaches (16 two-frame,
10 ms "reaches" passed the fit's count of 16 trials and gave a
one-primitive model).

The wrist moves from when it first leaves its start, by more than
``LEFT_FRACTION`` of the distance from start to goal (at least
``LEFT_AT_LEAST``), until it last comes that near its goal; before and
after, it is still.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from shared.demos.reach_pause import PAUSE_LIMIT, mid_pause
from shared.demos.retarget import nao_arm_size
from shared.demos.rotations import FloatArray
from shared.demos.sample_lines import lines_of, sample_line, trial_span
from shared.demos.trial import Trial
from shared.robot.side import Side

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
#: Shortest time [s] the wrist may move (``moving_span``) in a reach. The
#: paper's subjects took 0.55 to 1.01 s per point on average (Table 4); by
#: ``moving_span`` a minimum-jerk reach moves for about 3/4 of its time (13 %
#: at each end is within 2 % of the way), so the quickest of those moves for
#: about 0.4 s. A quarter of that leaves room for a quick subject and a short
#: reach, and still refuses a fragment of one (10 samples at the paper's
#: 100 Hz).
SHORTEST_MOVE = 0.1
#: Shortest distance from a reach's start to its goal, in lengths of the arm
#: it is retargeted to (L_u + L_f; about 16 mm of NAO's, 6 cm of an adult's).
#: The paper's reaches go from the hanging arm to a board in front of the
#: shoulder (the synthetic set's at least 0.67 arm lengths); less is a still
#: take (a calibration take's retargeted wrist stays within about 1 mm: marker
#: jitter) or a hand shifting, whose motion variables (in arm lengths, moving
#: above 0.025) would be hardly more than their noise.
SHORTEST_TRAVEL = 0.1


def still_spread(wrist: FloatArray) -> float:
    """How far [m] a still wrist may move, its positions shape (n, 3) [m].

    ``LEFT_FRACTION`` of the way from its first to its last position, at
    least ``LEFT_AT_LEAST``.
    """
    way = float(np.linalg.norm(wrist[-1] - wrist[0]))
    return max(LEFT_FRACTION * way, LEFT_AT_LEAST)


def moving_span(times: FloatArray, wrist: FloatArray) -> tuple[float, float]:
    """When the wrist moves: (from, to) [s], times shape (n,), wrist (n, 3) [m]."""
    start, goal = wrist[0], wrist[-1]
    near = still_spread(wrist)
    left = np.flatnonzero(np.linalg.norm(wrist - start, axis=1) > near)
    away = np.flatnonzero(np.linalg.norm(wrist - goal, axis=1) > near)
    if not left.size or not away.size:
        return float(times[0]), float(times[0])
    last = min(int(away[-1]) + 1, len(times) - 1)
    return float(times[left[0]]), float(times[last])


def not_a_reach_problem(trial: Trial) -> str | None:
    """What makes ``trial`` no reach at all, or ``None`` if it may be one.

    Its wrist ends less than ``SHORTEST_TRAVEL`` arm lengths from where it
    starts, or moves (``moving_span``) for less than ``SHORTEST_MOVE``.
    Times [s] and positions [m] are the retargeted trial's.
    """
    duration = float(trial.times[-1] - trial.times[0])
    named = f"{_trial_named(trial)} lasts {duration:.2f} s"
    travel = float(np.linalg.norm(trial.wrist[-1] - trial.wrist[0]))
    least = SHORTEST_TRAVEL * _arm_length(trial.arm)
    if travel < least:
        return (
            f"{named}, and its wrist ends {1000 * travel:.1f} mm from where it "
            f"starts (a reach goes at least {1000 * least:.1f} mm, "
            f"{SHORTEST_TRAVEL:g} of NAO's arm): a still take (e.g. a "
            "calibration) or a hand shifting, not a reach"
        )
    start, end = moving_span(trial.times, trial.wrist)
    if end - start < SHORTEST_MOVE:
        return (
            f"{named}, and its wrist moves for {end - start:.2f} s (from "
            f"{_at(trial, start)} to {_at(trial, end)}), far more briefly than a "
            "person "
            f"reaches (at least {SHORTEST_MOVE:g} s; the paper's subjects took "
            "0.55 to 1.01 s): a fragment of a reach, or no reach"
        )
    return None


@cache
def _arm_length(side: Side) -> float:
    """L_u + L_f [m] of NAO's arm on ``side``."""
    size = nao_arm_size(side)
    return size.upper_arm + size.forearm


def long_trial_problem(trial: Trial) -> str | None:
    """What makes ``trial`` more than one reach, or ``None`` if nothing does.

    Still (``moving_span``) for more than ``STILL_LIMIT`` before the wrist
    moves or after it arrives, stopped on its way for ``PAUSE_LIMIT`` or more
    (``mid_pause``: within ``still_spread``, at least ``SHORTEST_TRAVEL`` arm
    lengths from its start and its goal), or longer than ``LONGEST_REACH``.
    """
    duration = float(trial.times[-1] - trial.times[0])
    start, end = moving_span(trial.times, trial.wrist)
    named = f"{_trial_named(trial)} lasts {duration:.1f} s"
    moves = f"the wrist moves from {_at(trial, start)} to {_at(trial, end)}"
    ends = (
        (start - float(trial.times[0]), "before it moves", (trial.times[0], start)),
        (float(trial.times[-1]) - end, "at its goal", (end, trial.times[-1])),
    )
    for still, where, (first, last) in ends:
        if still > STILL_LIMIT:
            where += _between(trial, float(first), float(last))
            return (
                f"{named}, its wrist still for {still:.1f} s {where} (at most "
                f"{STILL_LIMIT:g} s; {moves}): a trial must be one reach, from its "
                "start to its goal, and armplan fit would count the stillness as "
                "reaching"
            )
    problem = _pause_problem(trial, named)
    if problem is not None:
        return problem
    if duration > LONGEST_REACH:
        return (
            f"{named}, far longer than a reach (at most {LONGEST_REACH:g} s; "
            f"{moves}): a trial must be one reach, from its start to its goal"
        )
    return None


def _pause_problem(trial: Trial, named: str) -> str | None:
    """What makes ``trial`` two reaches with a stop between, or ``None``."""
    away = SHORTEST_TRAVEL * _arm_length(trial.arm)
    pause = mid_pause(trial.times, trial.wrist, still_spread(trial.wrist), away)
    if pause is None:
        return None
    start = float(np.linalg.norm(pause.place - trial.wrist[0]))
    goal = float(np.linalg.norm(pause.place - trial.wrist[-1]))
    return (
        f"{named}, and its wrist stops on its way for "
        f"{pause.restarts - pause.stops:.2f} s, from {_at(trial, pause.stops)} to "
        f"{_at(trial, pause.restarts)}, {1000 * start:.1f} mm from its start and "
        f"{1000 * goal:.1f} mm from its goal (a reach stops for under "
        f"{PAUSE_LIMIT:g} s on its way): two reaches, not one; split the trial "
        f"where the wrist stops ({_when(trial, pause.stops)}) and restarts "
        f"({_when(trial, pause.restarts)})"
    )


def _trial_named(trial: Trial) -> str:
    """``trial`` for a message: ``"trial 3 of subject 'P01' (lines 2-31)"``.

    Its lines for a trial read from a CSV file (``sample_lines``).
    """
    return f"trial {trial.trial} of subject {trial.subject!r}{trial_span(trial.lines)}"


def _at(trial: Trial, seconds: float) -> str:
    """The sample of ``trial`` at ``seconds`` [s]: ``"0.50 s (line 52)"``.

    ``"0.50 s"`` for a trial without lines.
    """
    line = _line(trial, seconds)
    return f"{seconds:.2f} s ({line[2:]})" if line else f"{seconds:.2f} s"


def _when(trial: Trial, seconds: float) -> str:
    """The sample of ``trial`` at ``seconds`` [s]: ``"0.50 s, line 52"``."""
    return f"{seconds:.2f} s{_line(trial, seconds)}"


def _line(trial: Trial, seconds: float) -> str:
    """The line of ``trial``'s sample at ``seconds`` [s], ``", line 52"``."""
    k = int(np.argmin(np.abs(trial.times - seconds)))
    return sample_line(trial.lines, k)


def _between(trial: Trial, first: float, last: float) -> str:
    """The lines of ``trial``'s samples from ``first`` to ``last`` [s].

    For a message, ``", lines 2-402"``; ``""`` for a trial without lines.
    """
    if not trial.lines:
        return ""
    low, high = np.searchsorted(trial.times, (first, last))
    return f", {lines_of(trial.lines, int(low), int(high))}"
