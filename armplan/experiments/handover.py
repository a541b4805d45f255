"""The human-robot collaboration experiment (paper Section V.B, Fig. 18) on NAO.

NAO does the demo's handover task (``armplan.demo.task``) from its start
posture, movement after movement to the targets of the human reference
(``human_reference``), once with each method. Each movement is planned as
the planner plans a reach (``services.planner.reach_path`` for the wrist
path, the decide and ik stages for the joint path), movement by movement:
the planner's own loop without its timing stage (timing does not change the
path), which lets ``reference`` start each movement in the person's posture;
``chained`` gives the joint paths of the one-request form (``plan`` with all
targets). A movement starts (``Starts``) either where the method's
previous one ended (``chained``, the paper's protocol), or in the person's
posture at that movement's start (``reference``: every reach judged alone,
as in the similarity experiment). Each movement's joint path is read at the
normalised times of the reference's samples of the same movement
(``normalised_time``), and at every sample the posture similarity S (eq.
22-23, ``posture_similarity``) of NAO's posture to the reference's is
taken. The series run on the person's clock: movement after movement,
without the pauses between them.
"""

from __future__ import annotations

from enum import StrEnum
from typing import NamedTuple

import numpy as np

from armplan.demo.task import Task
from armplan.experiments.human_reference import ReferenceMovement, human_reference
from armplan.experiments.nao_reach import track
from armplan.experiments.normalised_time import at_tau_even
from armplan.experiments.posture_similarity import posture_similarity
from armplan.experiments.similarity import METHODS
from services.planner.reach_path import reach_wrist_path
from services.planner.stages import LocalStages, Stages
from shared.messages import Method
from shared.messages.measure_params import MeasureParams
from shared.robot.arm_model import ArmModel, load_arm


class Starts(StrEnum):
    """Where each movement of the task starts (see the module docstring)."""

    CHAINED = "chained"
    REFERENCE = "reference"


class SimilaritySeries(NamedTuple):
    """S over the task for one method.

    Attributes:
        method: The planning method.
        times: The person's time through the task [s], shape (n,).
        similarity: S at each time [-], shape (n,).
        movement: Index of the movement each sample belongs to, shape (n,).
        primitives: What moved NAO's arm, per movement, in order of use.
    """

    method: Method
    times: np.ndarray
    similarity: np.ndarray
    movement: np.ndarray
    primitives: list[list[str]]


def run_handover(
    task: Task,
    stages: Stages | None = None,
    methods: tuple[Method, ...] = METHODS,
    movements: int | None = None,
    starts: Starts = Starts.CHAINED,
    measures: MeasureParams | None = None,
) -> tuple[list[ReferenceMovement], list[SimilaritySeries]]:
    """The reference and each method's S over the task (or its first movements).

    Args:
        task: The task.
        stages: The planner's stages (default: in this process, shipped model).
        methods: The methods to run.
        movements: Only the first this many movements (all if ``None``).
        starts: Where each movement starts.
        measures: The IK measures' weights; default the shipped ones.
    """
    arm = load_arm(task.arm)
    reference = human_reference(arm, task, movements)
    stages = stages or LocalStages()
    return reference, [
        _series(arm, stages, reference, m, starts, measures) for m in methods
    ]


def _series(
    arm: ArmModel,
    stages: Stages,
    reference: list[ReferenceMovement],
    method: Method,
    starts: Starts,
    measures: MeasureParams | None,
) -> SimilaritySeries:
    """Plan the task with ``method`` and compare it with ``reference``."""
    times, values, index, used = [], [], [], []
    q, clock = reference[0].q[0], 0.0
    for k, move in enumerate(reference):
        if starts is Starts.REFERENCE:
            q = move.q[0]
        wrist = reach_wrist_path(arm, q, move.target)
        path = track(stages, wrist, q, method, measures)
        tau = move.times / move.times[-1]
        nao = at_tau_even(np.array(path.positions), tau)
        values.append(posture_similarity(nao, move.q, arm.limits))
        times.append(clock + move.times)
        index.append(np.full(len(tau), k))
        used.append(_in_order(path.primitives))
        q, clock = np.array(path.positions[-1]), clock + float(move.times[-1])
    return SimilaritySeries(
        method,
        np.concatenate(times),
        np.concatenate(values),
        np.concatenate(index),
        used,
    )


def _in_order(labels: list[str]) -> list[str]:
    """Distinct labels in order of first use."""
    return list(dict.fromkeys(labels))
