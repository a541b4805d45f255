"""Every sample of a timed wrist path lies within the arm's reach.

A sample out of the shell of shoulder-to-wrist distances the arm can make
(``ArmModel.reach``) cannot be followed: the tracker ends centimetres off
it. ``armplan plan`` and ``armplan decide`` refuse a given path with such
a sample before any work, and so do the decide and ik stages
(``services.planner.stages``), so the services answer a raw
``DecideRequest`` or ``PathIKRequest`` as the command line does: they
used to decide and track a path through the shoulder itself, and gave a
joint path 51 mm off that sample.

The stages allow ``STAGE_SLACK`` out of the shell, not the IK's 0.1 mm:
they also track the even grid the planner draws through a path's samples
(``services.planner.even_path``), which may poke a hair out between two
samples that are within reach (``services.planner.grid_reach``).
"""

from __future__ import annotations

import math

import numpy as np

from services.ik.iterate import TOLERANCE
from services.ik.reach_advice import reach_advice
from shared.errors import UnreachableTargetError
from shared.messages import WristPath
from shared.robot.arm_model import ArmModel
from shared.robot.body import BODY, BodyPart, check_target_clear, first_point_near
from shared.robot.postures import rest

#: How far out of the reach shell a sample of a path given to the decide or
#: ik stage may lie [m]: the planner's default path tolerance, as no
#: posture puts the wrist nearer a sample farther out. (At the IK's 0.1 mm
#: the planner's own grid through a noisy reach from the hanging wrist,
#: 0.11 mm out between its first two samples, was refused.)
STAGE_SLACK = 1e-3


def check_path_within_reach(
    arm: ArmModel, path: WristPath, slack: float = TOLERANCE
) -> None:
    """Raise, naming the sample, if a wrist-path sample is out of the arm's reach.

    Args:
        arm: The arm.
        path: The timed wrist path.
        slack: How far out of the shell of shoulder-to-wrist distances a
            sample may lie [m]; default the IK's position tolerance, as for
            one target (``services.ik.check_reachable``).

    Raises:
        UnreachableTargetError: at the first sample out, naming its index,
            its time, its distance from the shoulder [m] and the reach.
    """
    shoulder = arm.fk(rest(arm.side)).shoulder
    points = np.asarray(path.positions, dtype=float)
    with np.errstate(over="ignore"):  # 1e308 is out, at any distance
        distance = np.linalg.norm(points - shoulder, axis=1)
    low, high = arm.reach
    out = np.flatnonzero((distance < low - slack) | (distance > high + slack))
    if out.size == 0:
        return
    k = int(out[0])
    raise UnreachableTargetError(
        path.positions[k],
        arm=arm.side.value,
        distance=math.dist(path.positions[k], shoulder),  # no overflow for 1e308
        reach=arm.reach,
        at=f"wrist-path sample {k} (t = {path.times[k]:.3f} s)",
        advice=reach_advice(arm, path.positions[k], path.positions),
    )


def check_path_clear(
    arm: ArmModel, path: WristPath, parts: tuple[BodyPart, ...] = BODY
) -> None:
    """Raise, naming the sample, if a sample lies where no wrist may be.

    What a wrist path given to the planner or ``armplan decide`` must pass
    beside :func:`check_path_within_reach`. The decide and ik stages do
    not check it: they compute, and the planner checks every posture of
    what it plans (``shared.robot.body``). ``parts``: what the arm keeps
    clear of, NAO's body by default (and the other arm where a plan request
    holds it).

    Raises:
        TargetInBodyError: at the first sample in NAO's body (or nearer it
            than the hand keeps: ``shared.robot.body``).
    """
    k = first_point_near(path.positions, parts)
    if k is not None:
        check_target_clear(
            arm,
            path.positions[k],
            at=f"wrist-path sample {k} (t = {path.times[k]:.3f} s)",
            parts=parts,
        )


__all__ = ["STAGE_SLACK", "check_path_clear", "check_path_within_reach"]
