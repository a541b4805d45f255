"""One subject's average reach to one grid point, in normalised time.

The paper averages each subject's five trials at a point (Section V.A:
"the average elbow position of each subject"). Here the trials, already
retargeted to NAO, are read at the same normalised times (``normalised_time``)
and averaged sample by sample: the subject's elbow and wrist path over tau.
Trials of the two arms are kept apart. A trial off the grid (point 0, as
recorded reaches are imported) has a goal of its own: it is a reach alone,
not averaged with any other.
"""

from __future__ import annotations

from collections import defaultdict
from typing import NamedTuple

import numpy as np

from armplan.experiments.normalised_time import at_tau
from shared.demos.trial import DemoSet, Trial
from shared.errors import InvalidInputError
from shared.robot.side import Side

#: The point of a reach off the grid.
OFF_GRID = 0


def point_label(point: int) -> str:
    """``"P<n>"`` for grid point n, ``"off-grid"`` for reaches off it."""
    return "off-grid" if point == OFF_GRID else f"P{point}"


class SubjectReach(NamedTuple):
    """A subject's mean reach to a point (NAO's torso frame).

    Attributes:
        subject: The subject's name.
        point: Grid point 1..16, or ``OFF_GRID``.
        trials: How many trials were averaged.
        elbow: Mean elbow path at the tau grid [m], shape (m, 3).
        wrist: Mean wrist path at the tau grid [m], shape (m, 3).
        duration: Mean movement time [s].
        labels: The demonstrations' primitive sequences, one per trial.
        hand_y: Mean direction of the wrist frame's y axis (a right hand's
            palm normal) at the tau grid, unit, shape (m, 3); ``None`` if a
            trial has no wrist frames.
        arm: The arm of the trials.
        trial: The trial's number for a reach off the grid (a trial alone);
            ``None`` for a grid point's average.
        sources: The demonstration files its trials were read from, sorted
            (none for trials made here), for messages.
    """

    subject: str
    point: int
    trials: int
    elbow: np.ndarray
    wrist: np.ndarray
    duration: float
    labels: list[list[str]]
    hand_y: np.ndarray | None = None
    arm: Side = Side.RIGHT
    trial: int | None = None
    sources: tuple[str, ...] = ()


def reach_name(reach: SubjectReach) -> str:
    """The reach named for a message, with its files if it has any.

    ``a.mcap: subject 'P01', trial 3 (off the grid)`` or ``subject 'S01' at
    P5 (mean of 5 trials)``.
    """
    files = f"{', '.join(reach.sources)}: " if reach.sources else ""
    if reach.trial is not None:
        return f"{files}subject {reach.subject!r}, trial {reach.trial} (off the grid)"
    return (
        f"{files}subject {reach.subject!r} at {point_label(reach.point)} (mean of "
        f"{reach.trials} trial{'' if reach.trials == 1 else 's'})"
    )


#: A reach's key: (subject, point, arm, trial or -1).
ReachKey = tuple[str, int, str, int]


def reach_key(subject: str, point: int, arm: str, trial: int | None) -> ReachKey:
    """Which reach: its trial is -1 for a grid point's average (sortable)."""
    return (subject, point, arm, -1 if trial is None else trial)


def subject_reaches(demos: DemoSet, tau: np.ndarray) -> list[SubjectReach]:
    """The reaches of ``demos``, sorted by subject, point, arm and trial.

    Each (subject, grid point, arm)'s mean reach, and every trial off the
    grid alone.

    Raises:
        InvalidInputError: if the demonstrations hold no trial.
    """
    groups: dict[ReachKey, list[Trial]] = defaultdict(list)
    for trial in demos.trials:
        alone = trial.trial if trial.point == OFF_GRID else None
        key = reach_key(trial.subject, trial.point, trial.arm.value, alone)
        groups[key].append(trial)
    if not groups:
        raise InvalidInputError("the demonstrations hold no trial", field="demos")
    return [_mean(key, groups[key], tau) for key in sorted(groups)]


def _mean(key: ReachKey, trials: list[Trial], tau: np.ndarray) -> SubjectReach:
    """The trials' mean reach."""
    elbow = np.mean([at_tau(t.times, t.elbow, tau) for t in trials], axis=0)
    wrist = np.mean([at_tau(t.times, t.wrist, tau) for t in trials], axis=0)
    duration = float(np.mean([t.times[-1] - t.times[0] for t in trials]))
    labels = [list(t.labels) for t in trials if t.labels is not None]
    subject, point, arm, trial = key
    sources = tuple(sorted({t.source for t in trials if t.source}))
    return SubjectReach(
        subject, point, len(trials), elbow, wrist, duration, labels,
        _mean_hand_y(trials, tau), Side(arm), None if trial < 0 else trial,
        sources,
    )  # fmt: skip


def _mean_hand_y(trials: list[Trial], tau: np.ndarray) -> np.ndarray | None:
    """The trials' mean wrist-frame y axis at ``tau``, normalised, shape (m, 3)."""
    if any(t.wrist_frame is None for t in trials):
        return None
    mean = np.mean(
        [at_tau(t.times, np.asarray(t.wrist_frame)[:, :, 1], tau) for t in trials],
        axis=0,
    )
    return np.asarray(mean / np.linalg.norm(mean, axis=1, keepdims=True))
