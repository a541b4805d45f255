"""The similarity experiment (paper Section V.A, Fig. 14-15) on NAO.

For every subject and grid point of a demonstration set (and every reach
off the grid, alone): the subject's mean retargeted reach
(``subject_reach``), NAO's reach from the same start to the same goal with
each method (``nao_reach``), and the elbow error

    e = mean over tau of | elbow_NAO(tau) - elbow_subject(tau) |   [m],

tau the normalised time of the reach (``normalised_time``) on an even grid.
The paper's Fig. 14 is the distribution of e per point over the subjects,
Fig. 15 its mean per point; here for ``mp`` and both baselines.

With ``palm`` each reach also turns the palm: NAO starts in the subject's
mean start posture on NAO, WristYaw included (``posture_from_points`` from
the mean elbow, wrist and palm), and turns its palm on the way to where the
subject's ends (as NAO's joints can face it: the subject's mean end posture
on NAO); every reach then also gets the posture similarity S of eq. 22-23,
NAO's five joints against the subject's, averaged over tau. A reach that a
method cannot plan because of the palm (its wrist is within reach, but no
posture within the limits meets the palm there, as the planner judges it)
is left out for every method and listed; if that leaves no reach, the run
fails. A reach NAO cannot make whatever the palm (a goal out of its reach
after retargeting) fails the run, palm or not, naming its file, subject
and trial (or grid point).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from armplan.experiments.nao_reach import PalmTurn, PathSource, nao_reach
from armplan.experiments.normalised_time import SAMPLES, tau_grid
from armplan.experiments.posture_similarity import posture_similarity
from armplan.experiments.subject_reach import (
    ReachKey,
    SubjectReach,
    point_label,
    reach_key,
    reach_name,
    subject_reaches,
)
from services.decide.grid_table import MIN_POINTS, sequence
from services.planner.stages import LocalStages, Stages
from shared.demos.posture_from_points import joint_path_from_palms
from shared.demos.trial import DemoSet
from shared.errors import InvalidInputError, UnreachableTargetError
from shared.geometry.palm import palm_normal
from shared.messages import Method
from shared.messages.measure_params import MeasureParams
from shared.robot.arm_model import ArmModel, load_arm

#: The methods compared, the paper's first.
METHODS = (Method.MP, Method.LEAST_NORM, Method.SINGLE)


class ReachError(NamedTuple):
    """One subject's reach to one point, planned with one method.

    Attributes:
        subject: The subject's name.
        point: Grid point 1..16, or 0 off the grid.
        method: The planning method.
        elbow_error: Mean elbow distance over normalised time [m].
        wrist_error: Mean wrist distance over normalised time [m].
        primitives: The primitives that moved NAO's arm, in order (runs of
            at least ``MIN_POINTS`` path points; one label for a baseline).
        human_primitives: Primitives of the subject's most common sequence.
        posture_similarity: Mean S against the subject's postures (eq. 22-23)
            for a reach with a palm; ``None`` without.
        arm: The arm.
        trial: The trial of a reach off the grid; ``None`` on the grid.
    """

    subject: str
    point: int
    method: Method
    elbow_error: float
    wrist_error: float
    primitives: list[str]
    human_primitives: list[str]
    posture_similarity: float | None = None
    arm: str = "right"
    trial: int | None = None

    @property
    def reach(self) -> ReachKey:
        """Which reach this row is of: (subject, point, arm, trial or -1)."""
        return reach_key(self.subject, self.point, self.arm, self.trial)


class Skipped(NamedTuple):
    """A reach left out: which, and what the planner said.

    Attributes:
        subject: The subject's name.
        point: Grid point 1..16, or 0 off the grid.
        reason: The planner's error message.
        arm: The arm.
        trial: The trial of a reach off the grid; ``None`` on the grid.
        name: The reach named for a message, with its files
            (``subject_reach.reach_name``).
    """

    subject: str
    point: int
    reason: str
    arm: str = "right"
    trial: int | None = None
    name: str = ""


def run_similarity(
    demos: DemoSet,
    source: PathSource = PathSource.HUMAN,
    samples: int = SAMPLES,
    stages: Stages | None = None,
    methods: tuple[Method, ...] = METHODS,
    progress: Callable[[int, int], None] | None = None,
    measures: MeasureParams | None = None,
    palm: bool = False,
    skipped: list[Skipped] | None = None,
) -> list[ReachError]:
    """The experiment on ``demos`` (see the module docstring).

    Args:
        demos: Demonstrations retargeted to NAO.
        source: Where NAO's wrist path comes from (``nao_reach``).
        samples: Samples of normalised time compared per reach.
        stages: The planner's stages (default: in this process, shipped model).
        methods: The methods to run.
        progress: Called with (reaches done, reaches in all) after each.
        measures: The IK measures' weights; default the shipped ones.
        palm: Turn the palm as the subject did (see the module docstring).
        skipped: Receives the reaches left out (with ``palm`` only).

    Raises:
        InvalidInputError: with ``palm``, if a trial has no wrist frames, or
            every reach was left out (:func:`check_some_left`).
        UnreachableTargetError: a reach NAO cannot make (with ``palm``: not
            for the palm's sake), naming it.
    """
    tau = tau_grid(samples)
    stages = stages or LocalStages()
    out: list[ReachError] = []
    left_out: list[Skipped] = []
    reaches = subject_reaches(demos, tau)
    for done, reach in enumerate(reaches, start=1):
        arm = load_arm(reach.arm)
        try:
            out += _rows(arm, stages, reach, methods, source, tau, measures, palm)
        except UnreachableTargetError as exc:
            if not (palm and missed_palm(exc)):
                raise _naming(exc, reach) from exc
            left_out.append(_skipped(reach, exc))
        if progress is not None:
            progress(done, len(reaches))
    if skipped is not None:
        skipped += left_out
    check_some_left(out, left_out)
    return out


def missed_palm(exc: UnreachableTargetError) -> bool:
    """Whether the palm made the target unreachable: the wrist is within reach.

    The solver tried, with a palm, and stopped short (``residual``); a
    target out of the reach shell has no residual, palm or not.
    """
    return exc.evidence["palm"] is not None and exc.evidence["residual"] is not None


def _skipped(reach: SubjectReach, exc: UnreachableTargetError) -> Skipped:
    arm = reach.arm.value
    return Skipped(
        reach.subject, reach.point, str(exc), arm, reach.trial, reach_name(reach)
    )


def check_some_left(rows: list[ReachError], left_out: list[Skipped]) -> None:
    """Refuse a run whose every reach was left out: there is nothing to compare.

    Raises:
        InvalidInputError: naming how many were left out, and the first and why.
    """
    if rows or not left_out:
        return
    first = left_out[0]
    count = len(left_out)
    raise InvalidInputError(
        f"with --palm no reach is left to compare: the planner met the subject's "
        f"palm in none of the {count} reach{'es' if count != 1 else ''} ("
        f"{first.name or first.subject}: {first.reason}); run without --palm",
        field="palm",
        skipped=[s._asdict() for s in left_out],
    )


def _naming(exc: UnreachableTargetError, reach: SubjectReach) -> UnreachableTargetError:
    """``exc`` naming the reach (file, subject, trial or point) it came from.

    A hand-to-mouth reach, its goal out of NAO's reach after retargeting,
    failed the experiment naming only the target.
    """
    evidence = exc.evidence
    at = reach_name(reach) + (f", {evidence['at']}" if evidence["at"] else "")
    advice = evidence["advice"] or (
        "NAO cannot make this reach (armplan demos import notes a goal out of "
        "NAO's reach); import the demonstrations without it"
    )
    return UnreachableTargetError(
        evidence["target"],
        arm=evidence["arm"],
        distance=evidence["distance"],
        reach=tuple(evidence["reach"]),
        residual=evidence["residual"],
        at=at,
        palm=evidence["palm"],
        advice=advice,
    )


def _rows(
    arm: ArmModel,
    stages: Stages,
    reach: SubjectReach,
    methods: tuple[Method, ...],
    source: PathSource,
    tau: np.ndarray,
    measures: MeasureParams | None,
    palm: bool,
) -> list[ReachError]:
    """One row per method for ``reach``."""
    subject = subject_postures(arm, reach) if palm else None
    turn = None if subject is None else palm_turn(arm, subject)
    rows = []
    for method in methods:
        nao = nao_reach(arm, stages, reach, method, source, tau, measures, turn)
        similarity = None
        if subject is not None:
            similarity = float(np.mean(posture_similarity(nao.q, subject, arm.limits)))
        rows.append(
            ReachError(
                reach.subject,
                reach.point,
                method,
                mean_distance(nao.elbow, reach.elbow),
                mean_distance(nao.wrist, reach.wrist),
                sequence(nao.primitives, MIN_POINTS)[0],
                _human_sequence(reach),
                similarity,
                reach.arm.value,
                reach.trial,
            )
        )
    return rows


def subject_postures(arm: ArmModel, reach: SubjectReach) -> np.ndarray:
    """The subject's mean postures on NAO [rad], shape (m, 5), WristYaw included.

    Raises:
        InvalidInputError: if the subject's trials have no wrist frames.
    """
    if reach.hand_y is None:
        raise InvalidInputError(
            f"subject {reach.subject}'s trials at {point_label(reach.point)} have "
            "no wrist frames, so their palm is unknown: run without --palm",
            field="palm",
        )
    return joint_path_from_palms(arm, reach.elbow, reach.wrist, reach.hand_y)


def palm_turn(arm: ArmModel, subject: np.ndarray) -> PalmTurn:
    """Start in the subject's first posture and face the palm of its last."""
    rotation = arm.kinematics(subject[-1]).wrist_rotation
    return PalmTurn(subject[0], palm_normal(rotation, arm.side.sign))


def mean_distance(a: np.ndarray, b: np.ndarray) -> float:
    """Mean distance between two point paths [m], each shape (m, 3)."""
    return float(np.mean(np.linalg.norm(a - b, axis=1)))


def _human_sequence(reach: SubjectReach) -> list[str]:
    """The most common primitive sequence of the subject's trials (or [])."""
    if not reach.labels:
        return []
    seqs = Counter(tuple(sequence(labels)[0]) for labels in reach.labels)
    return list(seqs.most_common(1)[0][0])
