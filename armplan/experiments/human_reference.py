"""The human reference of the handover task: the reach model, retargeted to NAO.

The task is the demo's (``armplan/demo/handover_task.json``: NAO's start
posture and wrist targets in the torso frame, phase by phase). A person of
average stature with the average habits does it: each NAO target, seen from
NAO's shoulder as a fraction of NAO's arm length (L_u + L_f), becomes the
same direction and fraction of the person's arm; the person starts in NAO's
start posture (same segment directions, same palm).

The reference is not the planner's measure (TPE, NTPE, H_G): it is the
kinematic model of human reaching that makes the synthetic demonstrations
(``shared.demos.reach_model``: minimum-jerk joint laws, the shoulder leading
and the elbow following, the elbow low and out at the goal), without noise.
Each movement starts where the one before ended. Every sample (100 Hz) is
retargeted to NAO (``shared.demos.retarget``: segment directions kept,
NAO's lengths) and turned into NAO joint angles (``posture_from_points``,
palm included).

The retargeted wrist and palm at the end of each movement are NAO's target
posture there (the paper: "some postures in the movement are regarded as
the target postures"): NAO is asked to do what the person did, its own way.
So a task whose targets give palm directions is refused: the person's palm,
not the task's, would be NAO's.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from armplan.demo.task import Task
from shared.demos.anthropometry import Subject, subject_from_stature
from shared.demos.arm_pose import ArmPose, frame_from_directions
from shared.demos.nao_grid import AVERAGE_STATURE
from shared.demos.posture_from_points import joint_path_from_points
from shared.demos.reach_model import AVERAGE_STYLE, plan_reach, sample_reach
from shared.demos.retarget import ArmTrack, nao_arm_size, retarget
from shared.demos.wrist_roll import forearm_roll
from shared.errors import InvalidInputError
from shared.messages import ReachTarget
from shared.robot.arm_model import ArmModel
from shared.robot.side import Side

#: Sample rate of the reference [Hz] (the paper's motion capture: 100 Hz).
RATE = 100.0


class ReferenceMovement(NamedTuple):
    """One movement of the reference, on NAO.

    Attributes:
        name: The movement's name (its phase's, numbered within the phase).
        times: Sample times from the movement's start [s], shape (n,).
        q: NAO joint angles [rad], shape (n, 5).
        target: NAO's target posture for this movement (wrist and palm).
    """

    name: str
    times: np.ndarray
    q: np.ndarray
    target: ReachTarget


class PersonTarget(NamedTuple):
    """A movement of the task in the person's terms.

    Attributes:
        name: The movement's name.
        target: Wrist target in the person's shoulder frame [m], shape (3,).
    """

    name: str
    target: np.ndarray


def average_person() -> Subject:
    """A person of average stature (the mean of men's and women's)."""
    return subject_from_stature("average", AVERAGE_STATURE)


def person_targets(arm: ArmModel, task: Task, person: Subject) -> list[PersonTarget]:
    """The task's NAO targets as the person's (see the module docstring).

    Raises:
        InvalidInputError: for a left-arm task (the reach model is a right arm's),
            or a target with a palm direction (NAO's palm is the person's).
    """
    if task.arm is not Side.RIGHT:
        raise InvalidInputError(
            "the human reach model moves a right arm; the handover task is for the "
            f"{task.arm.value} arm",
            field="task",
        )
    size = nao_arm_size(arm.side)
    scale = person.arm_length / (size.upper_arm + size.forearm)
    out = []
    for phase in task.phases:
        for k, target in enumerate(phase.targets):
            name = phase.name if len(phase.targets) == 1 else f"{phase.name} {k + 1}"
            _refuse_palm(name, target)
            offset = np.array(target.position) - size.shoulder
            out.append(PersonTarget(name, scale * offset))
    return out


def _refuse_palm(name: str, target: ReachTarget) -> None:
    """Refuse a palm direction, which the experiment would not use.

    Raises:
        InvalidInputError: naming the target, if it gives a palm.
    """
    if target.palm is not None:
        raise InvalidInputError(
            f"the task's target {name!r} gives a palm direction; the handover "
            "experiment takes NAO's palm from the human reference (the person's "
            "palm at each movement's end), so leave the task's palms out",
            field="task",
            target=name,
            palm=list(target.palm),
        )


def start_pose(arm: ArmModel, q: np.ndarray) -> ArmPose:
    """NAO's posture ``q`` [rad] as a person's: segment directions and palm kept."""
    points = arm.fk(q)
    upper, fore = points.elbow - points.shoulder, points.wrist - points.elbow
    cos = float(upper @ fore) / float(np.linalg.norm(upper) * np.linalg.norm(fore))
    roll = forearm_roll(
        points.shoulder[None],
        points.elbow[None],
        points.wrist[None],
        arm.rotation(q, "wrist")[None],
    )
    return ArmPose(
        frame_from_directions(upper, fore),
        math.acos(min(max(cos, -1.0), 1.0)),
        float(roll[0]),
    )


def human_reference(
    arm: ArmModel, task: Task, movements: int | None = None
) -> list[ReferenceMovement]:
    """The task done by the average person, on NAO (see the module docstring).

    Args:
        arm: NAO's arm (the task's).
        task: The task.
        movements: Only the first this many movements (all if ``None``).
    """
    person = average_person()
    size = nao_arm_size(arm.side)
    q = np.array(task.start)
    pose = start_pose(arm, q)
    out = []
    for move in person_targets(arm, task, person)[:movements]:
        plan = plan_reach(person, AVERAGE_STYLE, move.target, start=pose)
        reach = sample_reach(plan, person, RATE)
        n = len(reach.times)
        track = retarget(ArmTrack(np.zeros((n, 3)), reach.elbow, reach.wrist), size)
        q_path = joint_path_from_points(
            arm, track.elbow, track.wrist, reach.wrist_frame, q
        )
        target = _target(track.wrist[-1], reach.wrist_frame[-1][:, 1])
        out.append(ReferenceMovement(move.name, reach.times, q_path, target))
        pose, q = plan.goal, q_path[-1]
    return out


def _target(wrist: np.ndarray, palm: np.ndarray) -> ReachTarget:
    return ReachTarget(
        position=tuple(float(v) for v in wrist),
        palm=tuple(float(v) for v in palm),
    )
