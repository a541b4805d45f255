"""The human reference of the handover task: the reach model, retargeted to NAO.

The reference is not the planner's measure (TPE, NTPE, H_G): it is the
kinematic model of human reaching that makes the synthetic demonstrations
(``shared.demos.reach_model``: minimum-jerk joint laws, the shoulder leading
and the elbow following, the elbow low and out at the goal), for a person of
average stature with the average habits, without noise. Each movement of
the task (``handover_task``) starts where the one before ended; the first
from the task's start posture of NAO (the arm stretched forward), taken
over by the person: same segment directions, same palm. Every sample
(100 Hz) is retargeted to NAO (``shared.demos.retarget``: segment
directions kept, NAO's lengths) and turned into NAO joint angles
(``posture_from_points``, palm included).

The retargeted wrist at the end of each movement, and for grasps and
releases its palm direction, are NAO's targets: NAO is asked to do what the
person did, in its own way.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from armplan.experiments.handover_task import Task
from armplan.experiments.posture_from_points import joint_path_from_points
from shared.demos.anthropometry import Subject, subject_from_stature
from shared.demos.arm_pose import ArmPose, frame_from_directions
from shared.demos.nao_grid import AVERAGE_STATURE
from shared.demos.reach_model import AVERAGE_STYLE, plan_reach, sample_reach
from shared.demos.retarget import ArmTrack, nao_arm_size, retarget
from shared.demos.wrist_roll import forearm_roll
from shared.messages import ReachTarget
from shared.robot import postures
from shared.robot.arm_model import ArmModel

#: Sample rate of the reference [Hz] (the paper's motion capture: 100 Hz).
RATE = 100.0


class ReferenceMovement(NamedTuple):
    """One movement of the reference, on NAO.

    Attributes:
        name: The movement's name.
        times: Sample times from the movement's start [s], shape (n,).
        q: NAO joint angles [rad], shape (n, 5).
        target: NAO's target for this movement.
    """

    name: str
    times: np.ndarray
    q: np.ndarray
    target: ReachTarget


def average_person() -> Subject:
    """A person of average stature (the mean of men's and women's)."""
    return subject_from_stature("average", AVERAGE_STATURE)


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


def human_reference(arm: ArmModel, task: Task) -> list[ReferenceMovement]:
    """The task done by the average person, on NAO (see the module docstring)."""
    person = average_person()
    size = nao_arm_size(arm.side)
    q = getattr(postures, task.start)(arm.side)
    pose = start_pose(arm, q)
    out = []
    for move in task.movements:
        plan = plan_reach(
            person, AVERAGE_STYLE, move.target * person.arm_length, start=pose
        )
        reach = sample_reach(plan, person, RATE)
        n = len(reach.times)
        track = retarget(ArmTrack(np.zeros((n, 3)), reach.elbow, reach.wrist), size)
        q_path = joint_path_from_points(
            arm, track.elbow, track.wrist, reach.wrist_frame, q
        )
        palm = reach.wrist_frame[-1][:, 1] if move.palm else None
        out.append(
            ReferenceMovement(
                move.name, reach.times, q_path, _target(track.wrist[-1], palm)
            )
        )
        pose, q = plan.goal, q_path[-1]
    return out


def _target(wrist: np.ndarray, palm: np.ndarray | None) -> ReachTarget:
    return ReachTarget(
        position=tuple(float(v) for v in wrist),
        palm=None if palm is None else tuple(float(v) for v in palm),
    )
