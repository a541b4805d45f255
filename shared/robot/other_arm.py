"""NAO's body and its other arm, as one set of parts for an arm to keep clear of.

The robot bridge reads where the robot holds the other arm before it sends
a movement; a plan request may say where it will be (``PlanRequest.
other_arm``). Either way the moving arm keeps clear of that arm's three
capsules as of the torso, pelvis and head (``shared.robot.body``).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shared.errors import InvalidInputError
from shared.robot.arm_model import load_arm
from shared.robot.body import BODY, BodyPart, other_arm
from shared.robot.side import Side


def with_other_arm(
    side: Side | str, other: npt.ArrayLike, field: str = "other"
) -> tuple[BodyPart, ...]:
    """NAO's body and its other arm, held at ``other`` [rad], (5,), to keep clear of.

    ``side`` is the arm that moves; ``other`` the other arm's posture (its
    five joints in their order), where it is held.

    Raises:
        InvalidInputError: ``other`` is not 5 finite angles (a NaN would
            make every distance NaN, and NaN is never "too near"), naming
            ``field``.
    """
    moving = Side.parse(side)
    still = Side.LEFT if moving is Side.RIGHT else Side.RIGHT
    posture = np.asarray(other, dtype=float)
    if posture.shape != (5,) or not np.all(np.isfinite(posture)):
        raise InvalidInputError(
            f"the {still.value} arm's posture must be 5 finite angles [rad], "
            f"got {posture.tolist()}",
            field=field,
        )
    return BODY + other_arm(load_arm(still), posture)
