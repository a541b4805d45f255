"""The line that says how near the palm came to the direction asked."""

from __future__ import annotations

from shared.messages import PalmReached


def palm_line(reached: PalmReached, where: str = "") -> str:
    """One line: the palm normal reached and its angle from the wanted one [deg].

    Args:
        reached: The palm reached.
        where: Where, e.g. ``" at target 2"``; empty for a single posture.
    """
    nx, ny, nz = reached.normal
    wx, wy, wz = reached.wanted
    return (
        f"palm{where} {reached.angle_deg:.1f} deg from the wanted direction "
        f"({wx:.3f}, {wy:.3f}, {wz:.3f}): normal ({nx:.3f}, {ny:.3f}, {nz:.3f}) "
        "(only its roll about the forearm is controlled)"
    )
