"""04: bad requests give typed errors that carry their evidence."""

import numpy as np

from services.ik import solve
from shared.errors import ArmplanError, UnreachableTargetError
from shared.robot import load_arm

arm = load_arm("left")
try:
    solve(arm, np.array([0.4, 0.1, 0.1]))  # far beyond NAO's reach
except UnreachableTargetError as error:
    low, high = error.reach
    print(
        f"{error.kind}: distance {error.distance:.3f} m, reach {low:.3f}..{high:.3f} m"
    )
try:
    solve(arm, np.array([0.12, 0.13, 0.05]), primitive="E_R W_P")  # one joint only
except ArmplanError as error:
    print(f"{error.kind}: {error.message}")
