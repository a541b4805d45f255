"""The arm must be within the bridge's range before anything is sent to it.

The bridge holds a limp arm where it hangs (``bridge.limp_arm``) and
stiffens the arm before it builds the approach move from there. An arm
can rest outside the bridge's range while inside the robot's own: a limp
elbow hanging at or past ``RElbowRoll``'s soft stop (0.0349 rad), a
shoulder a narrower range excludes, an arm another client commanded
there. Held and stiffened, such an arm was then refused as the
trajectory's "frame 0 ... outside its range, nothing was sent": after a
hold outside the range had gone out, and the arm was left stiff there.
So the posture is checked first, with the frames' own comparison
(``bridge.checks.outside_range``), and an arm outside the range is left as it is.
"""

from __future__ import annotations

import numpy as np

from bridge.checks import outside_range
from bridge.limits import FrameLimits
from bridge.units import unit, value_name
from shared.errors import RobotStateError, fixed


def check_in_range(
    url: str,
    where: np.ndarray,
    limits: FrameLimits,
    *,
    limp: bool,
    outcome: str,
) -> None:
    """Raise if a joint of the arm, at ``where`` [rad] (n,), is outside ``limits``.

    Args:
        url: The robot's NAOqi address.
        where: Where the arm is (measured if ``limp``, else commanded)
            [rad], in the order of ``limits.names``, shape (n,).
        limits: The joints' limits.
        limp: Whether the arm is limp (it came to rest there by itself).
        outcome: What was sent so far, e.g. ``"nothing was sent"``.

    Raises:
        RobotStateError: naming the first joint outside its range, its
            angle and the range, and what to do.
    """
    where = np.asarray(where, dtype=float)
    outside = outside_range(where, limits) | ~np.isfinite(where)
    if not outside.any():
        return
    j = int(np.argmax(outside))
    name, u = limits.names[j], unit(limits.names[j])
    how = "measured" if limp else "commanded"
    state = "limp" if limp else "stiff"
    by_hand = "by hand, as it is limp" if limp else "by hand once made limp"
    raise RobotStateError(
        url,
        f"{name} is {how} at {value_name(name)} {fixed(where[j], 4)}{u}, outside "
        f"the bridge's range [{fixed(limits.lower[j], 4)}, "
        f"{fixed(limits.upper[j], 4)}]{u}",
        outcome=f"{outcome}; the arm was left as it was ({state}): move "
        f"{name} into its range ({by_hand}, or with another client) and send "
        "again",
    )
