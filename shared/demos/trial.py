"""One demonstrated reach as arrays, and a set of them."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shared.demos.anthropometry import Subject
from shared.demos.rotations import FloatArray
from shared.robot.side import Side

#: Fewest samples of a trial: a reach moves from its start to its goal, and
#: one sample shows no movement (no step between samples, no sample rate).
MIN_SAMPLES = 2


class Trial(NamedTuple):
    """One reach of one subject, retargeted to NAO (torso frame).

    Attributes:
        subject: The subject's name.
        trial: Trial number, unique within the subject's reaches of ``arm``.
        point: Grid point number 1..16, or 0 if the reach is not on the grid.
        arm: Which arm.
        times: Sample times from the reach's start [s], shape (n,), increasing.
        shoulder: Shoulder positions [m], shape (n, 3).
        elbow: Elbow positions [m], shape (n, 3).
        wrist: Wrist positions [m], shape (n, 3).
        wrist_frame: Wrist frames (x forearm, y palm normal of a right hand),
            shape (n, 3, 3), or ``None`` if the data do not give the roll.
        target: Where the wrist is going [m], shape (3,).
        labels: The primitive moving the arm at each sample, or ``None``.
        source: The demonstration file it was read from, for messages; ``""``
            if it was made here (synthesised, imported).
        lines: The line of the CSV file each sample was read from (from 1;
            ``None`` for a frame of a missing row), for messages, or ``None``
            (not read from a CSV file; not kept in demonstration files).
    """

    subject: str
    trial: int
    point: int
    arm: Side
    times: FloatArray
    shoulder: FloatArray
    elbow: FloatArray
    wrist: FloatArray
    wrist_frame: FloatArray | None
    target: FloatArray
    labels: list[str] | None
    source: str = ""
    lines: list[int | None] | None = None

    @property
    def palm_goal(self) -> FloatArray | None:
        """Palm normal at the end of the reach, shape (3,), or ``None``."""
        if self.wrist_frame is None:
            return None
        return np.asarray(self.arm.sign * self.wrist_frame[-1][:, 1], dtype=float)


class DemoSet(NamedTuple):
    """Demonstrations: the subjects and their trials.

    Attributes:
        subjects: Each subject's human arm, by name.
        trials: The reaches, in recording order.
    """

    subjects: dict[str, Subject]
    trials: list[Trial]

    @property
    def samples(self) -> int:
        """Number of samples over all trials."""
        return sum(len(t.times) for t in self.trials)

    def only(self, subjects: set[str]) -> DemoSet:
        """The trials of ``subjects`` only."""
        kept = {name: s for name, s in self.subjects.items() if name in subjects}
        return DemoSet(kept, [t for t in self.trials if t.subject in subjects])
