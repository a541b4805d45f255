"""Random postures and targets that keep clear of NAO's body, for the tests.

The planner refuses a target in the body and a plan that brings the arm
near it (``shared.robot.body``): tests about something else draw from
what it plans.
"""

from __future__ import annotations

import numpy as np

from shared.robot.arm_model import ArmModel
from shared.robot.body import MARGIN, closest, first_point_near


def clear_posture(
    arm: ArmModel,
    rng: np.random.Generator,
    inset: float = 0.0,
) -> np.ndarray:
    """A random posture [rad], (5,), ``inset`` [rad] inside the ranges, whose
    arm keeps twice the body model's margin and whose wrist any posture may
    reach (the first such draw of ``rng``)."""
    lower, upper = arm.limits.lower + inset, arm.limits.upper - inset
    while True:
        q = rng.uniform(lower, upper)
        if closest(arm, [q]).clearance < 2 * MARGIN:
            continue
        if first_point_near([arm.fk(q).wrist]) is None:
            return q


def clear_target(arm: ArmModel, rng: np.random.Generator) -> np.ndarray:
    """The wrist [m], (3,), of :func:`clear_posture`."""
    return arm.fk(clear_posture(arm, rng)).wrist
