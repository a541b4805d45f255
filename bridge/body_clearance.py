"""Refuse what would bring the arm into NAO's own body (``shared.robot.body``).

The planner refuses such a plan already; the bridge checks again whatever
it is sent (a trajectory from anyone, a replayed recording, an approach
from where the arm happens to be), on the trajectory's samples and on the
command frames themselves, before anything moves. A refusal is a
:class:`~shared.errors.TrajectoryRefusedError` of quantity
``"clearance"``: its ``joint`` is the arm's part (``"right forearm"``), its
value the distance kept [m] and its limit ``MARGIN``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from shared.errors import (
    BodyCollisionError,
    TrajectoryRefusedError,
    body_words,
)
from shared.messages import CommandFrames, Trajectory
from shared.robot import Side, load_arm
from shared.robot.body import BODY, BodyPart, check_postures_clear


def check_trajectory_clear(
    trajectory: Trajectory, parts: tuple[BodyPart, ...] = BODY
) -> None:
    """Refuse ``trajectory`` if a sample's posture comes near the body.

    ``parts``: what to keep clear of, NAO's body by default (the bridge adds
    the other arm where the robot holds it:
    ``shared.robot.other_arm.with_other_arm``).

    Raises:
        TrajectoryRefusedError: quantity ``"clearance"``, ``frame`` the sample.
    """
    times = np.asarray(trajectory.times, dtype=float)
    _check(
        trajectory.arm,
        list(trajectory.joint_names),
        trajectory.positions,
        times - times[0],  # from the start, as the other refusals count
        "sample",
        parts,
    )


def check_frames_clear(
    frames: CommandFrames, what: str = "frame", parts: tuple[BodyPart, ...] = BODY
) -> None:
    """Refuse ``frames`` if the start or a frame comes near the body.

    Args:
        frames: The command frames (their hand channel, if any, is left out).
        what: What a frame is called in the refusal, e.g. "approach frame".
        parts: What to keep clear of, NAO's body by default.

    Raises:
        TrajectoryRefusedError: quantity ``"clearance"``, ``frame`` the frame
            (0: the start).
    """
    rows = [frames.start, *frames.positions]
    times = [0.0, *frames.times]
    _check(frames.arm, list(frames.joint_names), rows, times, what, parts)


def _check(
    side: Side | str,
    names: list[str],
    rows: npt.ArrayLike,
    times: npt.ArrayLike,
    what: str,
    parts: tuple[BodyPart, ...],
) -> None:
    """Refuse if a posture of ``rows`` [rad], (m, len(names)), is near ``parts``."""
    arm = load_arm(side)
    columns = [names.index(name) for name in arm.side.joint_names]
    postures = np.asarray(rows, dtype=float)[:, columns]
    try:
        check_postures_clear(arm, postures, times, parts=parts)
    except BodyCollisionError as near:
        raise TrajectoryRefusedError(
            f"{near.arm} {near.arm_part}",
            "clearance",
            near.clearance,
            near.margin,
            frame=near.index,
            time=near.time,
            detail=(
                f"comes {body_words(near.clearance, near.margin)} NAO's "
                f"{near.body_part} at {what} {near.index} (t = {near.time:.3f} s): "
                "the arm keeps clear of the torso, pelvis, head and the other "
                "arm where it is (docs/robot.md, 'NAO's own body')"
            ),
        ) from None
