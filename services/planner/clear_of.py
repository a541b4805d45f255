"""What a plan keeps clear of: NAO's body, and the other arm where a request holds it.

The other arm is ``PlanRequest.other_arm``; without it, the body alone.
"""

from __future__ import annotations

import numpy as np

from shared.messages import PlanRequest
from shared.robot import Side, load_arm
from shared.robot.arm_model import ArmModel
from shared.robot.body import BODY, BodyPart
from shared.robot.other_arm import with_other_arm


def kept_clear_of(arm: ArmModel, request: PlanRequest) -> tuple[BodyPart, ...]:
    """NAO's body, and the other arm at ``request.other_arm`` if given.

    Raises:
        JointLimitError: the other arm's posture is outside its own ranges
            (a right arm's angles given for the left, say), naming the joint.
    """
    if request.other_arm is None:
        return BODY
    other = load_arm(Side.LEFT if arm.side is Side.RIGHT else Side.RIGHT)
    posture = np.array(request.other_arm)
    other.limits.check(posture, where="in the other arm's posture (other_arm)")
    return with_other_arm(arm.side, posture, field="other_arm")
