"""Whether NAO can reach a retargeted trial's goal: a note when it cannot.

Retargeting keeps the directions of the human upper arm and forearm, and
so the elbow's bend; NAO's elbow bends less (ElbowRoll 2 to 88.5 deg). A
hand-to-mouth reach (the human elbow bent 145 deg) ends 0.068 m from NAO's
shoulder, where NAO's wrist cannot be (0.114 to 0.162 m): the planner
refuses that goal (``UnreachableTargetError``), and ``armplan experiment
similarity`` with it. The trial still serves ``armplan fit`` (the motion
variables are distances and angles of the retargeted arm, not NAO's
postures), so the import notes it rather than refusing it.

The test is the planner's first: the goal's distance from NAO's shoulder
against the arm's reach (``ArmModel.reach``). A goal within it that no
posture within the joint limits meets is found only by planning (the
experiment's error then names the trial).
"""

from __future__ import annotations

import numpy as np

from shared.demos.retarget import ArmTrack
from shared.robot.arm_model import load_arm
from shared.robot.side import Side

#: Slack [m] on the reach: the planner's own (``services.ik.iterate``).
SLACK = 1e-4
#: Index of ElbowRoll among an arm's joints.
ELBOW_ROLL = 3


def goal_reach_problem(human: ArmTrack, nao: ArmTrack, side: Side) -> str | None:
    """Why NAO cannot reach the trial's goal, or ``None`` if it may.

    Args:
        human: The human arm's positions [m], each shape (n, 3).
        nao: The same retargeted to NAO [m], each shape (n, 3).
        side: The arm.
    """
    arm = load_arm(side)
    low, high = arm.reach
    distance = float(np.linalg.norm(nao.wrist[-1] - nao.shoulder[-1]))
    if low - SLACK <= distance <= high + SLACK:
        return None
    upper = human.elbow[-1] - human.shoulder[-1]
    fore = human.wrist[-1] - human.elbow[-1]
    cosine = upper @ fore / (np.linalg.norm(upper) * np.linalg.norm(fore))
    bend = float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))
    least, most = sorted(
        abs(float(np.degrees(a)))
        for a in (arm.limits.lower[ELBOW_ROLL], arm.limits.upper[ELBOW_ROLL])
    )
    off = 1000 * (low - distance if distance < low else distance - high)
    return (
        f"its goal, retargeted, is {distance:.4f} m from NAO's {side.value} "
        f"shoulder, {off:.1f} mm {'nearer' if distance < low else 'farther'} "
        f"than NAO's wrist reaches ({low:.4f}..{high:.4f} m; the subject's elbow "
        f"is bent {bend:.0f} deg there, NAO's ElbowRoll {least:.1f} to "
        f"{most:.1f} deg): armplan fit can use the trial, but NAO cannot reach "
        "its goal, and armplan experiment similarity refuses it"
    )
