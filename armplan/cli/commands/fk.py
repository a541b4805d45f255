"""``armplan fk``: key points of the arm for given joint angles."""

from __future__ import annotations

import argparse

import numpy as np

from armplan.cli.output import print_json, print_table
from armplan.cli.parsing import add_arm, add_json, finite
from shared.messages import FKResult
from shared.robot import load_arm

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
    return 0
