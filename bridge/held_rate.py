"""A lower frame rate for frames refused only as NAOqi holds them (32 bits).

Rounded to 32-bit floats, a time near 4 s moves by up to 2.4e-7 s, which
against frames a millisecond apart is a jerk or an acceleration over the
limit that the 64-bit frames keep (``bridge.checks.check_frames``); frames
further apart suffer less from it. Such a refusal offers the highest rate of
``HELD_RATES`` below the one refused whose frames pass every check, made
and checked as the frames to send are (:func:`held_advice`): the demo's
trajectory, refused at 1000 fps, is offered a rate whose frames passed, not
a guess.
"""

from __future__ import annotations

from collections.abc import Callable

from bridge.fidelity import ATTEMPTS
from shared.errors import InvalidInputError, TrajectoryRefusedError
from shared.messages import CommandFrames

#: Frame rates tried, highest first, below the rate refused [Hz]: whole
#: rates (a behavior's must be), each a whole number of milliseconds apart
#: (Choregraphe's runtime steps a timeline every ``1000 // fps`` ms).
HELD_RATES = (500, 250, 200, 125, 100, 50, 40, 25)


def held_advice(make: Callable[[float], CommandFrames], rate: float) -> str:
    """The highest rate below ``rate`` whose frames pass, or why none is offered.

    At most ``ATTEMPTS`` rates of ``HELD_RATES`` are tried, each made and
    checked by ``make`` (every check, the 32-bit one too), so a rate offered
    is one whose frames passed.

    Args:
        make: Checked frames of the trajectory at a frame rate [Hz]; raises
            ``TrajectoryRefusedError``, or ``InvalidInputError``.
        rate: The frame rate refused [Hz].

    Returns:
        "at R fps it would not", or why no rate is offered.
    """
    lower = [r for r in HELD_RATES if r < rate][:ATTEMPTS]
    for candidate in lower:
        try:
            make(candidate)
        except (TrajectoryRefusedError, InvalidInputError):
            continue
        return f"at {candidate} fps it would not"
    slower = "plan the movement slower (lower accelerations and jerks)"
    if not lower:
        return f"no frame rate is offered: {slower}"
    tried = ", ".join(map(str, lower))
    return f"no frame rate is offered ({tried} fps were refused too): {slower}"
