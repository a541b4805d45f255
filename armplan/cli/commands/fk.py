"""``armplan fk``: key points of the arm for given joint angles."""

from __future__ import annotations

import argparse

import numpy as np

from armplan.cli.output import print_json, print_table
from armplan.cli.parsing import add_arm, add_json, finite
from shared.messages import FKResult
from shared.robot import load_arm
from shared.robot.body import MARGIN, Closest, closest

ORDER = 10
HELP = "forward kinematics: shoulder, elbow, wrist and hand positions [m]"


def add_parser(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register ``fk``."""
    parser = commands.add_parser("fk", help=HELP, description=HELP)
    add_arm(parser)
    parser.add_argument(
        "--joints",
        type=float,
        nargs=5,
        required=True,
        metavar="Q",
        help="ShoulderPitch ShoulderRoll ElbowYaw ElbowRoll WristYaw [rad]",
    )
    add_json(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Print the arm's key points in the torso frame."""
    arm = load_arm(args.arm)
    q = np.array(finite(args.joints, "joints"))
    arm.limits.check(q)
    points = arm.fk(q)
    result = FKResult(
        **{k: tuple(float(x) for x in v) for k, v in points._asdict().items()}
    )
    if args.json:
        print_json(result.model_dump())
    else:
        rows = [(name, *getattr(result, name)) for name in FKResult.model_fields]
        print_table(("point", "x [m]", "y [m]", "z [m]"), rows)
        print(body_line(closest(arm, [q])))
    return 0


def body_line(near: Closest) -> str:
    """How near the posture's arm comes to NAO's body, as one line."""
    where = f"{near.arm_part} to {near.body_part}"
    gap = near.clearance * 1000
    if near.clearance < 0:
        return f"in NAO's body: {-gap:.1f} mm deep ({where}); the planner refuses it"
    refused = "; the planner refuses it" if near.clearance < MARGIN else ""
    return (
        f"clear of NAO's body by {gap:.1f} mm ({where}; "
        f"at least {MARGIN * 1000:.1f} mm is kept{refused})"
    )
