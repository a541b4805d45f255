"""The paper's Table 4 on NAO: which primitives, in which order, per grid point.

For each of the 16 grid points (``shared.demos.nao_grid``) NAO's arm starts
hanging at rest and follows the planner's human-like wrist path
(``services.planner.wrist_path.reach_path``) to the point in the average
subject's movement time; the decision runs along it (``path``). A row lists
the primitives in the order they win. Switches lasting fewer than
``MIN_POINTS`` path points (the IK tracker's corrections show up as one-point
switches) are counted apart and not as primitives of the sequence.

``demo_rows`` gives the same table from labelled demonstrations of one arm:
per point the most common sequence of labels and how many trials follow it.
Reaches of the other arm, without a grid point (point 0: every imported
recording) or without labels cannot enter it; ``left_out`` counts them by
reason, so that a table is never silently thinner than the file.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from services.decide.decider import Decider
from services.decide.path import decide_path
from services.fit.model import MotionModel
from services.planner.wrist_path import reach_path
from shared.demos.nao_grid import nao_grid
from shared.demos.trial import DemoSet, Trial
from shared.robot.arm_model import load_arm
from shared.robot.postures import rest
from shared.robot.side import Side

#: Shortest run of one primitive that counts in a sequence [path points].
MIN_POINTS = 3
#: Sample rate of the wrist paths [Hz].
RATE = 100.0


class GridRow(NamedTuple):
    """One grid point's decision.

    Attributes:
        point: 1..16.
        duration: Movement time [s].
        sequence: Primitives in the order they win (runs >= MIN_POINTS).
        short: Runs shorter than MIN_POINTS.
        error: Distance of the wrist from the point at the end [m].
        wrist: The point, the wrist's target in NAO's torso frame [m],
            (x, y, z).
    """

    point: int
    duration: float
    sequence: list[str]
    short: int
    error: float
    wrist: tuple[float, float, float]


class DemoRow(NamedTuple):
    """One grid point in the demonstrations.

    Attributes:
        point: 1..16.
        duration: Mean movement time [s].
        sequence: The most common sequence of labels.
        share: Fraction of the point's trials with that sequence.
        trials: Trials at the point.
    """

    point: int
    duration: float
    sequence: list[str]
    share: float
    trials: int


class LeftOut(NamedTuple):
    """Demonstrated reaches the grid table leaves out, by reason.

    Attributes:
        no_point: Reaches not on the grid (point 0, as imported recordings are).
        no_labels: Reaches on the grid without primitive labels.
        of: Reaches in the demonstrations, left out or not.
        other_arm: Reaches of the arm the table is not for (counted before
            the other reasons).
    """

    no_point: int
    no_labels: int
    of: int
    other_arm: int = 0

    @property
    def total(self) -> int:
        """Reaches left out, for any reason."""
        return self.other_arm + self.no_point + self.no_labels

    def describe(self) -> str:
        """The counts in words, e.g. "2 have no grid point (point 0, ...)"."""
        parts = []
        if self.other_arm:
            parts.append(f"{self.other_arm} {_be(self.other_arm)} of the other arm")
        if self.no_point:
            parts.append(
                f"{self.no_point} {_have(self.no_point)} no grid point (point 0, "
                "as recorded reaches are imported)"
            )
        if self.no_labels:
            parts.append(
                f"{self.no_labels} {_have(self.no_labels)} no primitive labels"
            )
        return " and ".join(parts) or "none"


def _have(count: int) -> str:
    return "has" if count == 1 else "have"


def _be(count: int) -> str:
    return "is" if count == 1 else "are"


def arms_of(demos: DemoSet) -> list[Side]:
    """The arms ``demos``' reaches are of, right first."""
    return [side for side in Side if any(t.arm is side for t in demos.trials)]


def left_out(demos: DemoSet, side: Side | str) -> LeftOut:
    """How many of ``demos``' reaches ``demo_rows`` leaves out for ``side``, and why."""
    arm = Side.parse(side)
    reasons = Counter(_why_left_out(trial, arm) for trial in demos.trials)
    return LeftOut(
        reasons["no_point"],
        reasons["no_labels"],
        len(demos.trials),
        reasons["other_arm"],
    )


def _why_left_out(trial: Trial, side: Side) -> str | None:
    """Why ``side``'s table cannot use ``trial``, or ``None`` if it can.

    Returns:
        ``"other_arm"``, ``"no_point"``, ``"no_labels"`` or ``None``.
    """
    if trial.arm is not side:
        return "other_arm"
    if not trial.point:
        return "no_point"
    if trial.labels is None:
        return "no_labels"
    return None


def runs(labels: Sequence[str]) -> list[tuple[str, int]]:
    """Consecutive equal labels as (label, count), in order."""
    out: list[tuple[str, int]] = []
    for label in labels:
        if out and out[-1][0] == label:
            out[-1] = (label, out[-1][1] + 1)
        else:
            out.append((label, 1))
    return out


def sequence(labels: Sequence[str], min_points: int = 1) -> tuple[list[str], int]:
    """(primitives in order, runs shorter than ``min_points``) of ``labels``."""
    kept: list[str] = []
    short = 0
    for label, count in runs(labels):
        if count < min_points:
            short += 1
        elif not kept or kept[-1] != label:
            kept.append(label)
    return kept, short


def grid_rows(model: MotionModel, side: Side | str = Side.RIGHT) -> list[GridRow]:
    """The decision's Table 4 on NAO (see the module docstring)."""
    arm = load_arm(side)
    decider = Decider(model, 1.0 / RATE)
    start = rest(arm.side)
    out = []
    for target in nao_grid(arm.side):
        path = reach_path(arm, start, target.wrist, target.duration, RATE)
        decision, tracked = decide_path(
            decider, arm, path.positions, start, times=path.times
        )
        kept, short = sequence(decision.primitives, MIN_POINTS)
        error = float(np.linalg.norm(tracked.wrist[-1] - target.wrist))
        x, y, z = (float(v) for v in target.wrist)
        row = GridRow(target.point, target.duration, kept, short, error, (x, y, z))
        out.append(row)
    return out


def demo_rows(demos: DemoSet, side: Side | str) -> list[DemoRow]:
    """Per grid point, the most common label sequence of ``side``'s demonstrations.

    Reaches of the other arm, off the grid or unlabelled are left out
    (``left_out`` counts them).
    """
    arm = Side.parse(side)
    by_point: dict[int, list[tuple[tuple[str, ...], float]]] = {}
    for trial in demos.trials:
        if _why_left_out(trial, arm) is None and trial.labels is not None:
            kept, _ = sequence(trial.labels)
            by_point.setdefault(trial.point, []).append(
                (tuple(kept), float(trial.times[-1]))
            )
    rows = []
    for point in sorted(by_point):
        seen = by_point[point]
        common, count = Counter(s for s, _ in seen).most_common(1)[0]
        duration = float(np.mean([d for _, d in seen]))
        rows.append(
            DemoRow(point, duration, list(common), count / len(seen), len(seen))
        )
    return rows
