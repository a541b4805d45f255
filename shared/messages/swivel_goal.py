"""An elbow swivel goal is radians: a value beyond two turns is not.

``--swivel 90``, meaning the elbow out to the side in degrees, was read as
90 rad, the same as 2.0354 rad (90 less 14 turns): the elbow went to
116.6 degrees and the answer was a success. An angle and its mirror for the
other arm (``2 pi - phi``, ``shared.geometry.swivel``) stay within two turns
either way when the angle is within one, so a goal beyond two turns,
``4 pi`` [rad], is refused, saying its radians when it reads as degrees. A
goal that, read as degrees, is no more than two turns either (``12`` meant
as degrees) cannot be told from radians and is taken as given.
"""

from __future__ import annotations

import math
from typing import Annotated, Final

from pydantic import AfterValidator

#: Farthest a swivel goal may be from 0 either way [rad]: two turns.
MAX_SWIVEL: Final = 4.0 * math.pi
#: Most a swivel in degrees is, either way [deg]: one turn.
MAX_DEGREES: Final = 360.0


def within_two_turns(value: float) -> float:
    """``value`` [rad] if within ``MAX_SWIVEL`` of 0; else ``ValueError``.

    The message says the value's radians when, read as degrees, it is
    within a turn.
    """
    if abs(value) <= MAX_SWIVEL:
        return value
    hint = "give it within -4 pi..4 pi rad (2 pi is the whole circle)"
    if abs(value) <= MAX_DEGREES:
        hint = (
            f"it looks like degrees: angles are in radians, and {value:g} deg "
            f"is {math.radians(value):.4f} rad"
        )
    raise ValueError(
        f"an elbow swivel of {value:g} rad is more than two turns "
        f"(4 pi = {MAX_SWIVEL:.4f} rad) from 0; {hint}"
    )


#: An elbow swivel goal [rad], within two turns of 0 either way.
SwivelGoal = Annotated[float, AfterValidator(within_two_turns)]
