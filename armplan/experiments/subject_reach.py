"""One subject's average reach to one grid point, in normalised time.

The paper averages each subject's five trials at a point (Section V.A:
"the average elbow position of each subject"). Here the trials, already
retargeted to NAO, are read at the same normalised times (``normalised_time``)
and averaged sample by sample: the subject's elbow and wrist path over tau.
"""

from __future__ import annotations

from collections import defaultdict
from typing import NamedTuple

import numpy as np

from armplan.experiments.normalised_time import at_tau
from shared.demos.trial import DemoSet, Trial
from shared.errors import InvalidInputError


class SubjectReach(NamedTuple):
    """A subject's mean reach to a point (NAO's torso frame).

    Attributes:
        subject: The subject's name.
        point: Grid point 1..16.
        trials: How many trials were averaged.
        elbow: Mean elbow path at the tau grid [m], shape (m, 3).
        wrist: Mean wrist path at the tau grid [m], shape (m, 3).
        duration: Mean movement time [s].
        labels: The demonstrations' primitive sequences, one per trial.
        hand_y: Mean direction of the wrist frame's y axis (a right hand's
            palm normal) at the tau grid, unit, shape (m, 3); ``None`` if a
            trial has no wrist frames.
    """

    subject: str
    point: int
    trials: int
    elbow: np.ndarray
    wrist: np.ndarray
    duration: float
    labels: list[list[str]]
    hand_y: np.ndarray | None = None


def subject_reaches(demos: DemoSet, tau: np.ndarray) -> list[SubjectReach]:
    """Every (subject, grid point)'s mean reach, sorted by subject then point.

    Trials off the grid (point 0) are left out.

    Raises:
        InvalidInputError: if no trial is on the grid.
    """
    groups: dict[tuple[str, int], list[Trial]] = defaultdict(list)
    for trial in demos.trials:
        if trial.point:
            groups[(trial.subject, trial.point)].append(trial)
    if not groups:
        raise InvalidInputError(
            "the demonstrations hold no trial on the 16-point grid (every "
            "trial has point 0)",
            field="demos",
        )
    return [_mean(key, groups[key], tau) for key in sorted(groups)]


def _mean(key: tuple[str, int], trials: list[Trial], tau: np.ndarray) -> SubjectReach:
    """The trials' mean reach."""
    elbow = np.mean([at_tau(t.times, t.elbow, tau) for t in trials], axis=0)
    wrist = np.mean([at_tau(t.times, t.wrist, tau) for t in trials], axis=0)
    duration = float(np.mean([t.times[-1] - t.times[0] for t in trials]))
    labels = [list(t.labels) for t in trials if t.labels is not None]
    return SubjectReach(
        key[0], key[1], len(trials), elbow, wrist, duration, labels,
        _mean_hand_y(trials, tau),
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
